"""The dcmotor example's controller written by hand as a scenario ``[controller]`` table: what
``examples/dcmotor/sampled_stop.toml`` held before the d-model's machine ``SSpeed`` drove it.
The Flow*, machine and simulate tests compare the machine with it."""

SSPEED_TABLE = """
[controller]
initial = "cruise"

[controller.states.cruise]
calls = ["drive(10)"]

[controller.states.stopped]
calls = ["stop()"]

[[controller.transitions]]
from = "cruise"
to = "stopped"
when = "near"
"""
