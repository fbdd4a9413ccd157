"""N independent PI-controlled DC motors on one bench, under one controller: the model files
and a Flow* scenario, for ``bench_reach.py`` and the decomposition tests.

Each motor is the motor of ``examples/dcmotor`` (its own shaft and flywheel); ``drive(w)``
sets every motor's desired speed, ``stop()`` sets them to 0 once the range finder reads at
most 1 m. The unsafe set is that some motor over-speeds (a disjunction: one Flow* run per
motor) or, with ``every=True``, that all of them do at once (a conjunction: one part per
motor, any of which proves it).
"""

from __future__ import annotations

from pathlib import Path

def speed_control_motor(motor: str, joint: str) -> str:
    """An ``aref`` of the library's SpeedControlMotor with ``examples/dcmotor``'s constants,
    whose torque drives ``joint``: the motor every synthetic bench model uses."""
    return f"""
			aref {motor} = SpeedControlMotor {{
				instantiation R = 1.0
				instantiation L = 0.1
				instantiation Kt = 0.05
				instantiation Ke = 0.05
				instantiation b = 0.01
				instantiation J = 0.01
				instantiation Kp = 2.0
				instantiation Ki = 5.0
				instantiation Kd = 0.0
				relation {motor}.T == {joint}.tau
			}}"""


def _motor(k: int) -> str:
    return f"""
		jref Shaft{k} = Revolute {{
			pose {{ x = 0 y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }}
			annotation Revolute {{
				axis = Axis {{ xyz = (|0,0,1|) }}
			}}
			instantiation AXIS = (|0,0,1|)
			flexibly connected to Flywheel{k}{speed_control_motor(f"Motor{k}", f"Shaft{k}")}
		}}"""


_FLYWHEEL = """
	local link Flywheel{k} {{
		pose {{ x = 0 y = 0 z = {z}m roll = 0 pitch = 0 yaw = 0 }}
		def {{
			inertial information {{
				mass 0.2kg
				inertia matrix {{ ixx 0.0005 ixy 0 ixz 0 iyy 0.0005 iyz 0 izz 0.001 }}
			}}
		}}
		local body Disc{k} {{
			def {{ cylinder(radius = 0.1m, length = 0.02m) }}
		}}
	}}"""

_BASE = """package motorsBase

import physmod::math::*
import physmod::joints::Revolute
import physmod::actuators::SpeedControlMotor
import physmod::sensors::Sonar

pmodel MotorsBase {{
	local link Bench {{
		def {{
			inertial information {{
				mass 1.0kg
				inertia matrix {{ ixx 0.002 ixy 0 ixz 0 iyy 0.002 iyz 0 izz 0.002 }}
			}}
		}}
		local body Frame {{
			def {{ box(length = 0.1m, width = 0.1m, height = 0.1m) }}
		}}
		sref Range = Sonar {{
			pose {{ x = 0.05m y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }}
		}}{motors}
	}}{flywheels}
}}
"""

_MAPPING = """package motorsMapping

import motorsBase::*
import dcMotorSoftware::*

map MotorsMapping dmodel DCMotorSoftware to pmodel MotorsBase {{
	operation drive {{{drive}
	}}
	operation stop {{{stop}
	}}
	input event near {{
		predicate Bench::Range.range <= 1.0
	}}
}}
"""

#: ``examples/dcmotor``'s machine ``SSpeed`` written by hand as a scenario ``[controller]``
#: table (what ``sampled_stop.toml`` held before the machine drove it): the motors' controller
#: here, and what the tests compare the machine with.
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

_SCENARIO = """model = "MotorsBase"
elements = [{elements}, "MotorsBase::Bench::Range"]
horizon = {horizon}
tscale = 0.1

[init]
{init}Range_distance = [3, 3.1]

[environment]
Range_distance = "-2"

{controller}
[unsafe]
constraints = [{unsafe}]
"""


def write_motors(folder: Path, n: int, horizon: float = 1.5, every: bool = False) -> Path:
    """The model files of ``n`` motors in ``folder`` (with the d-model of
    ``examples/dcmotor``), and the scenario; returns the scenario's path."""
    folder.mkdir(parents=True, exist_ok=True)
    ks = range(1, n + 1)
    (folder / "MotorsBase.rsm").write_text(_BASE.format(
        motors="".join(_motor(k) for k in ks),
        flywheels="".join(_FLYWHEEL.format(k=k, z=0.06 * k) for k in ks)))
    (folder / "Mapping.rsm").write_text(_MAPPING.format(
        drive="".join(f"\n\t\tequation Bench::Shaft{k}::Motor{k}.das == w" for k in ks),
        stop="".join(f"\n\t\tequation Bench::Shaft{k}::Motor{k}.das == 0" for k in ks)))
    software = Path(__file__).resolve().parent.parent / "examples" / "dcmotor" / \
        "DCMotorSoftware.rsm"
    (folder / "DCMotorSoftware.rsm").write_text(software.read_text())
    # the reduction numbers the PI integrators it introduces: Motor1_int1, Motor2_int2, …
    init = "".join(f"Motor{k}_{v} = 0\n" for k in ks for v in ("av", "i", f"int{k}", "theta"))
    over = [f"Motor{k}_av >= 20" for k in ks]
    either = " \\\\/ ".join(over)  # the notation's "\\/", escaped in a TOML string
    unsafe = ", ".join(f'"{c}"' for c in over) if every else f'"{either}"'
    path = folder / f"motors{n}.toml"
    path.write_text(_SCENARIO.format(
        elements=", ".join(f'"MotorsBase::Bench::Shaft{k}::Motor{k}"' for k in ks),
        horizon=horizon, init=init, unsafe=unsafe, controller=SSPEED_TABLE.lstrip()))
    return path
