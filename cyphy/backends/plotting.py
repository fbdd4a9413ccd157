"""One line plot of time series as PNG bytes, shared by ``simulate`` and ``animate`` (the
caller writes the bytes atomically, where it checked it could before the run)."""

from __future__ import annotations

import io
from typing import Sequence


def line_plot(times: Sequence[float], series: Sequence[tuple[str, Sequence[float]]],
              title: str = "") -> bytes:
    """Each named series over ``times``, with a legend, as a PNG."""
    import matplotlib  # lazy: only --plot draws

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # lazy: as above

    figure, axes = plt.subplots(figsize=(7, 4), dpi=80)
    for name, values in series:
        axes.plot(times, values, label=name)
    axes.set_xlabel("t (s)")
    if title:
        axes.set_title(title)
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize="small")
    figure.tight_layout()
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", metadata={"Software": None})
    plt.close(figure)
    return buffer.getvalue()
