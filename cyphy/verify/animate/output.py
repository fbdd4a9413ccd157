"""An animation written out: CSV (one row per sample, the events since the previous sample
in the last column), JSON (trajectories and the events with their times), or a PNG plot."""

from __future__ import annotations

import csv
import io
import json
from typing import Any, Sequence

from cyphy.verify.animate.animation import Animation
from cyphy.verify.animate.errors import AnimateError


def _event(channel: str, value: Any) -> str:
    if value is None:
        return channel
    if isinstance(value, tuple):
        return f"{channel}.({','.join(_scalar(v) for v in value)})"
    return f"{channel}.{_scalar(value)}"


def _scalar(v: Any) -> str:
    return ("true" if v else "false") if isinstance(v, bool) else repr(v)


def _json_value(v: Any) -> Any:
    return list(v) if isinstance(v, tuple) else v


def to_csv(animation: Animation) -> str:
    """``t,<state>...,events``: each row's events are those of (previous sample, t]."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(animation.columns + ["events"])
    events = list(animation.events)
    k = 0
    for i, row in enumerate(animation.rows):
        here = []
        last = i == len(animation.rows) - 1
        while k < len(events) and (events[k][0] <= row[0] + 1e-12 or last):
            here.append(_event(events[k][1], events[k][2]))
            k += 1
        writer.writerow([repr(float(v)) for v in row] + [" ".join(here)])
    return buffer.getvalue()


def to_json(animation: Animation) -> str:
    doc = {
        "composition": animation.composition,
        "columns": animation.columns,
        "rows": animation.rows,
        "events": [{"t": t, "channel": c, "value": _json_value(v)}
                   for t, c, v in animation.events],
        "undetermined": animation.undetermined,
    }
    return json.dumps(doc, indent=1) + "\n"


def plot(animation: Animation, names: Sequence[str] = (), title: str = "") -> bytes:
    """A PNG of the chosen columns over time (default: the integrated states but the timer,
    at most 8) as bytes, for the caller to write atomically."""
    from cyphy.backends.plotting import line_plot  # lazy: matplotlib behind it

    chosen = list(names) or [x for x in animation.differential if x != "timer"][:8]
    missing = [n for n in chosen if n not in animation.columns]
    if missing:
        raise AnimateError("E-ANIMATE-OPTION", f"--plot-var {missing[0]}: not a column of the "
                           "animation", hint="choose among: " + ", ".join(animation.columns[1:]),
                           status=2)
    times = [r[0] for r in animation.rows]
    return line_plot(times, [(name, [r[animation.columns.index(name)] for r in animation.rows])
                             for name in chosen], title)
