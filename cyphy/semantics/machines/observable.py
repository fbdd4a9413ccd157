"""What of a machine's outputs reaches no input of the p-model: output events and platform
variables the platform mapping gives no effect (observable only: a simulation records
them, the Flow* automaton and the theory's D leave them out)."""

from __future__ import annotations

from typing import Sequence

from cyphy.lang import ast
from cyphy.model.machines import Machine


def observable_events(machines: Sequence[Machine], files: list[ast.SourceFile],
                      pmodel: str) -> frozenset[str]:
    """The output events the machines (a machine and the operations it calls) may send, and the platform
    variables it may write, that the platform mapping of ``pmodel`` gives no effect: no
    mapping (an event of the machine's output context that the robotic platform does not
    use, a variable PMap3 leaves unmapped), or one without equations or actions.
    They reach no input of the p-model: observable only (a simulation records them)."""
    mapped = {e.name for f in files for item in f.items
              if isinstance(item, ast.PlatformMapping) and item.pmodel[-1] == pmodel
              for e in item.events if e.direction == "output" and (e.equations or e.actions)}
    sent = {name for m in machines
            for name in m.platform.output_events}
    # a platform variable without a ``variable`` mapping (PMap3 allows it) is shared memory
    # of the d-model: a write is kept for later reads and recorded, and reaches no input
    mapped |= {v.name for f in files for item in f.items
               if isinstance(item, ast.PlatformMapping) and item.pmodel[-1] == pmodel
               for v in item.variables if v.equations or v.actions}
    sent |= {name for m in machines
             for name in m.platform.written}
    return frozenset(sent - mapped)
