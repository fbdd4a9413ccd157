"""What a ``cyphy gen`` target is: how it runs, its flag's help, and the options it adds."""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING, Callable, NamedTuple

if TYPE_CHECKING:
    from cyphy.api import Generated


class Target(NamedTuple):
    """One ``cyphy gen --<flag>``: ``run`` takes the parsed arguments and returns what was
    generated; ``add_options`` adds the target's own options to the ``gen`` parser (each
    option is refused with the other targets)."""

    run: Callable[[argparse.Namespace], "Generated"]
    help: str
    add_options: Callable[[argparse.ArgumentParser], None]
