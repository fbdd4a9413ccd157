"""The mutation sweep: small faults a user could make in the examples and the held-out models,
each refused with the right diagnostic at the right line, or accepted when the model stays
valid; and for every mutant the commands a user runs next (``gen --isabelle``, ``simulate``)
refuse it without writing anything, or, when it is accepted, run.

The catalogue is :data:`MUTANTS`, one row a mutant: the model folder, the file, the text
replaced and its replacement, and the expected code (``ACCEPTED`` for a valid mutant). The
expected place is the line where the replacement starts, or the line of ``at`` (text of the
mutated file) when the fault is reported elsewhere (an unmapped event at the mapping's header).
Each mutant is checked in process, through :func:`cyphy.cli.main`, on a copy of its folder.
"""

from __future__ import annotations

import json
import shutil
from dataclasses import dataclass
from pathlib import Path

import pytest

from conftest import EXAMPLES, ROOT
from cyphy.cli import main

HELDOUT = ROOT / "tests" / "data" / "heldout"
ACCEPTED = "accepted"
BOTH = ("gen", "simulate")

#: Each model folder, and the short scenario ``simulate`` runs for an accepted mutant.
FOLDERS = {
    "dcmotor": (EXAMPLES / "dcmotor", "sampled_stop.toml"),
    "marxbot": (EXAMPLES / "marxbot", "obstacle_stop.toml"),
    "lift": (HELDOUT / "lift", "cycle.toml"),
    "pendulum": (HELDOUT / "pendulum", "swing.toml"),
    "ranger": (HELDOUT / "ranger", "approach.toml"),
    "rover": (HELDOUT / "rover", "bump.toml"),
    "tracks": (HELDOUT / "tracks", "clear.toml"),
    "pincer": (HELDOUT / "pincer", "squeeze.toml"),
    "pvars": (ROOT / "tests" / "data" / "pvars", "spin.toml"),
}


@dataclass(frozen=True)
class Mutant:
    """One fault: ``old`` replaced by ``new`` in ``folder``/``file`` (and the ``also`` edits,
    each ``(file, old, new)``), refused with ``expect`` at the line of ``at`` (default: where
    ``new`` starts) in ``at_file`` (default: ``file``), or ``ACCEPTED``. ``runs``: the
    commands (``gen``, ``simulate``) that then succeed (default: both when accepted, none
    when refused; a warning's mutant may run). ``shows``: text the generated Isabelle theory
    must hold (what the mutation changed)."""

    name: str
    folder: str
    file: str
    old: str
    new: str
    expect: str
    at: str | None = None
    at_file: str | None = None
    also: tuple[tuple[str, str, str], ...] = ()
    runs: tuple[str, ...] | None = None
    shows: str | None = None


M = Mutant
DC_MAP, DC_SW, DC_BASE = "Mapping.rsm", "DCMotorSoftware.rsm", "DCMotorBase.rsm"
NEAR = "\tinput event near {\n\t\tpredicate Bench::Range.range <= 1.0\n\t}\n"
STOP = "\toperation stop {\n\t\tequation Bench::Shaft::Motor.das == 0\n\t}\n"
HEADER = "map BenchMapping"
T3 = "action $stop() }"
#: Output events for the motor bench, typed (``beep: real``, ``flag: boolean``) and not
#: (``tick``): declared, on the platform, connected, in the machine's output context and
#: mapped; the machine sends them with ``T3`` (a mutant's own text).
BEEPS = (
    (DC_SW, "interface NearI {\n\tevent near\n}",
     "interface NearI {\n\tevent near\n}\n\ninterface BeepI {\n\tevent beep: real\n"
     "\tevent flag: boolean\n\tevent tick\n}"),
    (DC_SW, "\t\tuses NearI\n\t}", "\t\tuses NearI\n\t\tuses BeepI\n\t}"),
    (DC_SW, "connection Bench on near to ctrl on near (_async)",
     "connection Bench on near to ctrl on near (_async)\n"
     + "".join(f"\tconnection ctrl on {e} to Bench on {e} (_async)\n"
               for e in ("beep", "flag", "tick"))),
    (DC_SW, "\tuses NearI\n\trequires SpeedI", "\tuses NearI\n\tuses BeepI\n\trequires SpeedI"),
    (DC_SW, "connection SpeedController on near to sm on near",
     "connection SpeedController on near to sm on near\n"
     + "".join(f"\tconnection sm on {e} to SpeedController on {e}\n"
               for e in ("beep", "flag", "tick"))),
    (DC_SW, "output context { requires SpeedI }", "output context { requires SpeedI uses BeepI }"),
    (DC_MAP, "\tinput event near {",
     "\toutput event beep ? b {\n\t\tequation Bench::Shaft::Motor.das == b\n\t}\n"
     "\toutput event flag ? f {\n\t\tequation Bench::Shaft::Motor.das == 0\n\t}\n"
     "\toutput event tick {\n\t\tequation Bench::Shaft::Motor.das == 0\n\t}\n"
     "\tinput event near {"),
)
SENDS = "$beep!1.0; $flag!true; $tick"
SONAR = "\t\t\tpose { x = 0.2m y = 0 z = 0 roll = 0 pitch = 0 yaw = 0 }\n"
PAD = "\t\t\t\tinertial information { mass 0.02kg }\n\t\t\t}\n\t\t}\n"
PLATE = "\t\t\t\tinertial information { mass 0.3kg }\n\t\t\t}\n\t\t}\n"
#: The marXbot's ring of proximity sensors sized by a constant without a value.
OPEN_NP = (("marXbotBase.rsm", "index j : [0,24)", "index j : [0,NP)"),
           ("marXbotBase.rsm", "pmodel marXbotBase {", "pmodel marXbotBase {\n\tconst NP: nat"))
#: The motor bench's mapping written a second time, in a file of its own.
SECOND_MAPPING = ("package dcMotorMapping2\n\nimport dcMotorBase::*\n"
                  "import dcMotorSoftware::*\n\n"
                  f"{HEADER}2 dmodel DCMotorSoftware to pmodel DCMotorBase {{\n"
                  "\toperation drive {\n\t\tequation Bench::Shaft::Motor.das == w\n\t}\n"
                  f"{STOP}{NEAR}}}\n")
LTREEL = "\t\tinstantiation DEPTH = 0.03m\n\t}\n\tpart RTreel"


#: The theory's D of the motor bench when near reaches no machine: read, and dropped.
DROPPED = r"DCMotorSoftwareRead = (registerRead_near?(near_in) \<^bold>\<rightarrow> Skip)"
#: A vector platform variable beside the wheel's speed.
PAIR = (("WheelSoftware.rsm", "\tvar speed: real\n",
         "\tvar speed: real\n\tvar pair: vector(real, 2)\n"),)
DRIVE = "\t\tequation Bench::Shaft::Motor.das == w"
#: The motor's speed passed through a vector local of the operation's mapping.
VECTOR_LOCAL = ("\t\tvar g: vector(real, 2)\n\t\tequation g == (|w, 0|)\n"
                "\t\tequation Bench::Shaft::Motor.das == g[1]")


def in_ltreel(line: str) -> str:
    """``LTREEL`` with ``line`` added to the left treel's part."""
    return LTREEL.replace("\t}", f"\t\t{line}\n\t}}")


MUTANTS: tuple[Mutant, ...] = (
    # ---- platform mappings (PMap) -----------------------------------------------------------
    M("event-reads-unknown-output", "dcmotor", DC_MAP, "Range.range <= 1.0",
      "Range.rnge <= 1.0", "S1"),
    M("event-predicate-not-boolean", "dcmotor", DC_MAP, "Range.range <= 1.0",
      "Range.range + 1.0", "S3"),
    M("event-reads-actuator-input", "dcmotor", DC_MAP, "Bench::Range.range <= 1.0",
      "Bench::Shaft::Motor.das <= 1.0", "PMap12"),
    M("event-reads-joint", "dcmotor", DC_MAP, "Bench::Range.range <= 1.0",
      "Bench::Shaft.theta <= 1.0", "PMap12"),
    M("event-writes-sensor-output", "dcmotor", DC_MAP, "predicate Bench::Range.range <= 1.0",
      "predicate Bench::Range.range <= 1.0\n\t\tequation Bench::Range.range == 2.0", "PMap7",
      at="equation Bench::Range.range == 2.0"),
    M("event-direction-swapped", "dcmotor", DC_MAP, "input event near", "output event near",
      "PMap4"),
    M("event-unmapped", "dcmotor", DC_MAP, NEAR, "", "PMap3", at=HEADER),
    M("event-mapped-twice", "dcmotor", DC_MAP, NEAR, NEAR + NEAR, "S2",
      at="input event near {\n\t\tpredicate Bench::Range.range <= 1.0\n\t}\n}"),
    M("event-unknown", "dcmotor", DC_MAP, "input event near", "input event nearr", "PMap4"),
    M("event-untyped-with-parameter", "dcmotor", DC_MAP, "input event near {",
      "input event near ? d {", "PMap5"),
    M("event-typed-parameter-wrong-type", "ranger", "RangerSoftware.rsm", "event echo: real",
      "event echo: boolean", "S3", at="equation r == Rail::Carriage::Eye.voltage",
      at_file="Mapping.rsm"),
    M("event-reads-misspelled-port", "ranger", "Mapping.rsm", "r == Rail::Carriage::Eye.voltage",
      "r == Rail::Carriage::Eye.voltag", "S1"),
    M("event-typed-without-parameter", "ranger", "Mapping.rsm", "input event echo ? r {",
      "input event echo {", "PMap5"),
    M("event-threshold-changed", "dcmotor", DC_MAP, "Range.range <= 1.0",
      "Range.range <= 0.5", ACCEPTED,
      shows=r"(&Range_range \<le>\<^sub>u \<guillemotleft>0.5\<guillemotright>)"),
    M("operation-unmapped", "dcmotor", DC_MAP, STOP, "", "PMap3", at=HEADER),
    M("operation-mapped-twice", "dcmotor", DC_MAP, STOP, STOP + STOP, "S2",
      at="\toperation stop {\n\t\tequation Bench::Shaft::Motor.das == 0\n\t}\n\tinput"),
    M("operation-unknown", "dcmotor", DC_MAP, "operation stop {", "operation halt {", "PMap4"),
    M("operation-writes-sensor-output", "dcmotor", DC_MAP,
      "equation Bench::Shaft::Motor.das == 0", "equation Bench::Range.range == 0", "PMap9"),
    M("operation-reads-joint", "dcmotor", DC_MAP, "Bench::Shaft::Motor.das == w",
      "Bench::Shaft::Motor.das == w + Bench::Shaft.theta", "PMap9"),
    M("operation-reads-sensor-output", "dcmotor", DC_MAP, "Bench::Shaft::Motor.das == w",
      "Bench::Shaft::Motor.das == w + Bench::Range.range", "PMap9"),
    M("operation-unknown-parameter", "dcmotor", DC_MAP, "Motor.das == w", "Motor.das == v",
      "S1"),
    M("operation-parameter-wrong-type", "dcmotor", DC_SW, "drive(w: real)",
      "drive(w: boolean)", "S3", at="equation Bench::Shaft::Motor.das == w",
      at_file=DC_MAP),
    M("operation-argument-wrong-type", "dcmotor", DC_SW, "$drive(wref)", "$drive(true)",
      "STM8"),
    M("operation-parameter-added", "dcmotor", DC_SW, "drive(w: real)",
      "drive(w: real, k: real)", "STM3", at="$drive(wref)", at_file=DC_SW),
    M("operation-equations-and-actions", "dcmotor", DC_MAP,
      "equation Bench::Shaft::Motor.das == 0",
      "equation Bench::Shaft::Motor.das == 0\n\t\taction Bench::Shaft::Motor.das = 0", "PMap6",
      at="action Bench::Shaft::Motor.das = 0"),
    M("operation-empty", "dcmotor", DC_MAP, "equation Bench::Shaft::Motor.das == 0", "",
      "PMap6", at="operation stop"),
    M("operation-action-calls-dmodel", "dcmotor", DC_MAP,
      "equation Bench::Shaft::Motor.das == 0", "action $drive(0)", "PMap11"),
    M("operation-reads-stm-constant", "dcmotor", DC_MAP, "Motor.das == w",
      "Motor.das == wref", "S1"),
    M("operation-scaled", "dcmotor", DC_MAP, "Motor.das == w", "Motor.das == 2*w", ACCEPTED,
      shows=r"(&Motor_das =\<^sub>u \<guillemotleft>(2 * w)\<guillemotright>)"),
    M("operation-two-wheels-swapped", "rover", "Mapping.rsm", "LMotor.das == left",
      "LMotor.das == right", ACCEPTED,
      shows=r"(&LMotor_das =\<^sub>u \<guillemotleft>right\<guillemotright>)"),
    M("operation-writes-actuator-output", "dcmotor", DC_MAP,
      "equation Bench::Shaft::Motor.das == 0", "equation Bench::Shaft::Motor.T == 0", "PMap9"),
    # units in a mapping (U2): a value with a unit has the dimension of the port it meets
    M("operation-length-for-angular-speed", "dcmotor", DC_MAP, "Motor.das == w",
      "Motor.das == w * 1m", "U2", at="Bench::Shaft::Motor.das == w * 1m"),
    M("operation-speed-plus-length", "dcmotor", DC_MAP, "Motor.das == 0",
      "Motor.das == 1rad/1s + 1m", "U2", at="1rad/1s + 1m"),
    M("event-time-for-range", "dcmotor", DC_MAP, "Range.range <= 1.0", "Range.range <= 2s",
      "U2", at="Bench::Range.range <= 2s"),
    M("event-threshold-in-centimetres", "dcmotor", DC_MAP, "Range.range <= 1.0",
      "Range.range <= 50cm", ACCEPTED),
    M("operation-speed-with-its-unit", "dcmotor", DC_MAP, "Motor.das == w",
      "Motor.das == w * 1rad/1s", ACCEPTED),
    # a mapping's locals belong to a member (PMap18)
    M("mapping-local-at-top", "dcmotor", DC_MAP,
      "\toperation drive {\n\t\tequation Bench::Shaft::Motor.das == w",
      "\tvar half: real\n\toperation drive {\n\t\tequation Bench::Shaft::Motor.das == half"
      "\n\t\tequation half == w / 2", "PMap18", at="var half: real"),
    M("mapping-local-in-its-member", "dcmotor", DC_MAP,
      "\toperation drive {\n\t\tequation Bench::Shaft::Motor.das == w",
      "\toperation drive {\n\t\tvar half: real\n\t\tequation Bench::Shaft::Motor.das == "
      "half\n\t\tequation half == w / 2", ACCEPTED),
    M("variable-type-mismatch", "dcmotor", DC_MAP, STOP,
      STOP + "\tvariable armed {\n\t\tequation Bench::Shaft::Motor.das == armed\n\t}\n", "S3",
      at="equation Bench::Shaft::Motor.das == armed",
      also=((DC_SW, "provides SpeedI", "provides SpeedI\n\t\tvar armed: boolean"),)),
    M("variable-writes-sensor", "dcmotor", DC_MAP, STOP,
      STOP + "\tvariable level {\n\t\tequation Bench::Range.range == level\n\t}\n", "PMap10",
      at="equation Bench::Range.range == level",
      also=((DC_SW, "provides SpeedI", "provides SpeedI\n\t\tvar level: real"),)),
    M("variable-not-of-platform", "dcmotor", DC_MAP, STOP,
      STOP + "\tvariable level {\n\t\tequation Bench::Shaft::Motor.das == 1\n\t}\n", "PMap4",
      at="variable level"),
    M("event-misspelt-sensor", "lift", "Mapping.rsm", "Slide::Level.height >= 0.3",
      "Slide::Levl.height >= 0.3", "S1"),
    M("event-predicate-reads-actuator", "lift", "Mapping.rsm",
      "Mast::Slide::Level.height <= 0.02", "Mast::Slide::Winch.dls <= 0.02", "PMap12"),
    M("index-out-of-range", "marxbot", "Mapping.rsm", "Proximity[1]", "Proximity[24]",
      "IX5"),
    M("index-count", "marxbot", "Mapping.rsm", "Proximity[1]", "Proximity[1, 0]", "IX5"),
    M("index-past-a-constant-bound", "marxbot", "Mapping.rsm", "Proximity[1]",
      "Proximity[30]", "IX5", also=(("marXbotBase.rsm", "index j : [0,24)", "index j : [0,NP)"),
                                    ("marXbotBase.rsm", "pmodel marXbotBase {",
                                     "pmodel marXbotBase {\n\tconst NP: nat = 24"))),
    # NP has no value: check warns that it cannot decide (gen refuses: the ring's size is
    # open); the scenario gives NP = 24, and simulate refuses the index with IX5
    M("index-past-an-open-bound", "marxbot", "Mapping.rsm", "Proximity[1]", "Proximity[30]",
      "IX5", also=OPEN_NP + (("obstacle_stop.toml", "[consts]\n", "[consts]\nNP = 24\n"),),
      runs=()),
    M("index-within-an-open-bound", "marxbot", "obstacle_stop.toml", "[consts]\n",
      "[consts]\nNP = 24\n", "IX5", at="Proximity[1]", at_file="Mapping.rsm", also=OPEN_NP,
      runs=("simulate",)),
    M("indexed-joint-out-of-range", "tracks", "Mapping.rsm",
      "Chassis::Axle[1].Motor.das == -w", "Chassis::Axle[2].Motor.das == -w", "IX5"),
    M("indexed-part-out-of-range", "pincer", "Mapping.rsm",
      "predicate Fingers[0].Root.Knuckle.Angle.reading >= 0.5",
      "predicate Fingers[2].Root.Knuckle.Angle.reading >= 0.5", "IX5"),
    M("indexed-steer-same-way", "tracks", "Mapping.rsm",
      "Chassis::Axle[1].Motor.das == -w", "Chassis::Axle[1].Motor.das == w", ACCEPTED),
    M("mapping-wrong-pmodel", "dcmotor", DC_MAP, "to pmodel DCMotorBase",
      "to pmodel DCMotorBas", "S1"),
    M("pmap1-joint-unconnected", "dcmotor", DC_BASE, "\t\t\tflexibly connected to Flywheel\n",
      "", "PMap1", at="jref Shaft"),
    # second round: what a mapping's members say, and faults a user plausibly writes
    M("operation-parameter-unused", "dcmotor", DC_MAP, "Motor.das == w", "Motor.das == 10",
      "PMap13", at="operation drive", runs=BOTH),
    M("output-event-value-unused", "dcmotor", DC_SW, T3, f"action $stop(); {SENDS} }}",
      "PMap13", at="b {", at_file=DC_MAP, runs=BOTH,
      also=BEEPS + ((DC_MAP, "Motor.das == b", "Motor.das == 1"),)),
    M("input-event-value-never-given", "ranger", "Mapping.rsm",
      "equation r == Rail::Carriage::Eye.voltage",
      "var v: real\n\t\tequation v == Rail::Carriage::Eye.voltage", "PMap14",
      at="r {"),
    M("mapping-twice-in-two-files", "dcmotor", "Mapping2.rsm", "", SECOND_MAPPING, "PMap15",
      at=HEADER + "2"),
    M("operation-writes-input-twice", "dcmotor", DC_MAP, "Bench::Shaft::Motor.das == w",
      "Bench::Shaft::Motor.das == w\n\t\tequation Bench::Shaft::Motor.das == 2*w", "PMap16",
      at="Bench::Shaft::Motor.das == 2*w"),
    M("operation-assigns-input-twice", "dcmotor", DC_MAP,
      "equation Bench::Shaft::Motor.das == w",
      "action Bench::Shaft::Motor.das = w; Bench::Shaft::Motor.das = 0", "PMap16",
      at="Bench::Shaft::Motor.das = 0"),
    M("event-value-given-twice", "ranger", "Mapping.rsm",
      "r == Rail::Carriage::Eye.voltage", "r == Rail::Carriage::Eye.voltage\n"
      "\t\tequation r == Rail::Carriage::Eye.voltage + 1", "PMap16",
      at="r == Rail::Carriage::Eye.voltage + 1"),
    M("operation-same-equation-twice", "dcmotor", DC_MAP, "Bench::Shaft::Motor.das == w",
      "Bench::Shaft::Motor.das == w\n\t\tequation Bench::Shaft::Motor.das == w", ACCEPTED),
    M("operation-derivative-of-parameter", "dcmotor", DC_MAP, "Motor.das == w",
      "Motor.das == derivative(w)", "PMap17", at="derivative(w)"),
    M("operation-derivative-of-input", "dcmotor", DC_MAP, "Motor.das == w",
      "Motor.das == w\n\t\tequation derivative(Bench::Shaft::Motor.das) == 0", "PMap17",
      at="derivative(Bench"),
    M("platform-requires-instead-of-provides", "dcmotor", DC_SW, "\t\tprovides SpeedI\n",
      "\t\trequires SpeedI\n", "STM3", at="$drive(wref)"),
    M("event-mapped-as-operation", "dcmotor", DC_MAP, "\tinput event near {",
      "\toperation near {", "PMap4"),
    M("event-value-from-actuator-input", "ranger", "Mapping.rsm",
      "r == Rail::Carriage::Eye.voltage", "r == Rail::Carriage::Push.dls", "PMap7",
      at="r == Rail::Carriage::Push.dls"),
    M("event-reads-sensor-input", "ranger", "Mapping.rsm",
      "Rail::Carriage::Eye.voltage >= 0.4", "Rail::Carriage::Eye.distance <= 0.7", "PMap12"),
    M("mapping-names-a-controller", "dcmotor", DC_MAP, "dmodel DCMotorSoftware",
      "dmodel SpeedController", "S1"),
    M("operation-reads-actuator-output", "dcmotor", DC_MAP, "Motor.das == w",
      "Motor.das == w - Bench::Shaft::Motor.av", "PMap9", at="Bench::Shaft::Motor.av"),
    M("stm-calls-an-event", "dcmotor", DC_SW, T3, "action $near() }", "STM3"),
    M("stm-reads-an-operation", "dcmotor", DC_SW, "condition not $near",
      "condition not $stop", "STM4"),
    M("operation-local", "dcmotor", DC_MAP, "\t\tequation Bench::Shaft::Motor.das == w",
      "\t\tvar half: real\n\t\tequation half == w/2\n"
      "\t\tequation Bench::Shaft::Motor.das == 2*half", ACCEPTED),
    M("operation-mapping-constant", "dcmotor", DC_MAP, "\toperation drive {\n"
      "\t\tequation Bench::Shaft::Motor.das == w", "\tconst K: real = 2.0\n\toperation drive {"
      "\n\t\tequation Bench::Shaft::Motor.das == K*w", ACCEPTED),
    M("event-always", "dcmotor", DC_MAP, "predicate Bench::Range.range <= 1.0",
      "predicate true", ACCEPTED),
    # ---- d-models (state machines) ----------------------------------------------------------
    M("pvars-variable-not-required", "pvars", "WheelSoftware.rsm",
      "output context { requires SpeedI }", "output context { }", "STM5",
      at="entry speed = slow"),
    M("pvars-platform-does-not-provide", "pvars", "WheelSoftware.rsm", "\t\tprovides SpeedI\n",
      "\t\tvar level: real\n", "STM5", at="entry speed = slow"),
    M("pvars-value-of-wrong-type", "pvars", "WheelSoftware.rsm", "entry speed = slow",
      "entry speed = true", "STM8"),
    M("pvars-constant-assigned", "pvars", "WheelSoftware.rsm", "var speed: real",
      "const speed: real = 1", "STM5", at="entry speed = slow"),
    M("pvars-unmapped-variable-is-shared", "pvars", "WheelSoftware.rsm",
      "entry speed = 2 * speed", "entry speed = 2 * speed ; count = count + 1", ACCEPTED,
      also=(("WheelSoftware.rsm", "\tvar speed: real\n", "\tvar speed: real\n\tvar count: int\n"),),
      shows="registerWrite_speed"),
    M("stm-unknown-event", "dcmotor", DC_SW, "condition not $near", "condition not $nearr",
      "STM4"),
    M("stm-operation-wrong-arity", "dcmotor", DC_SW, "$drive(wref)", "$drive(wref, 1.0)",
      "STM3"),
    M("stm-operation-too-few", "rover", "RoverSoftware.rsm", "$drive(cruise, cruise)",
      "$drive(cruise)", "STM3"),
    M("stm-unknown-operation", "dcmotor", DC_SW, "$drive(wref)", "$drivee(wref)", "STM3"),
    M("stm-no-initial", "dcmotor", DC_SW, "\tinitial i0\n", "", "STM2", at="stm SSpeed"),
    M("stm-unknown-target", "dcmotor", DC_SW, "from Check to Stopped",
      "from Check to Stoped", "STM1"),
    M("stm-guard-not-boolean", "dcmotor", DC_SW, "condition not $near", "condition wref",
      "STM8"),
    M("stm-wrong-type-assigned", "dcmotor", DC_SW, "entry $drive(wref)",
      "entry $drive(wref); on = 1.0", "STM8",
      also=((DC_SW, "const wref: real = 10.0", "const wref: real = 10.0\n\tvar on: boolean"),)),
    M("stm-during-argument-wrong-type", "lift", "LiftSoftware.rsm", "during $lift(-vdown)",
      "during $lift(not vdown)", "STM8"),
    M("stm-state-twice", "dcmotor", DC_SW, "\tstate Stopped {}\n",
      "\tstate Stopped {}\n\tstate Stopped {}\n", "S2", at="state Stopped {}\n\ttransition"),
    M("connection-unknown-event", "dcmotor", DC_SW, "connection Bench on near to ctrl",
      "connection Bench on nearr to ctrl", "S1"),
    M("connection-unknown-controller", "dcmotor", DC_SW, "connection Bench on near to ctrl",
      "connection Bench on near to ctl", "S1"),
    M("cycle-zero", "dcmotor", DC_SW, "\tcycleDef cycle == 1\n\trobotic",
      "\tcycleDef cycle == 0\n\trobotic", "STM9"),
    M("cycle-constant-zero", "dcmotor", DC_SW, "\tcycleDef cycle == 1\n\trobotic",
      "\tcycleDef cycle == PERIOD\n\trobotic", "STM9",
      also=((DC_SW, "package dcMotorSoftware\n",
             "package dcMotorSoftware\nconst PERIOD: nat = 0\n"),)),
    M("controller-event-unknown", "dcmotor", DC_SW,
      "connection SpeedController on near to sm on near",
      "connection SpeedController on near to sm on nearr", "S1"),
    M("stm-sends-events", "dcmotor", DC_SW, T3, f"action $stop(); {SENDS} }}", ACCEPTED,
      also=BEEPS),
    M("stm-sends-int-on-real-event", "dcmotor", DC_SW, T3,
      "action $stop(); $beep!1; $flag!(wref > 1.0); $tick }", ACCEPTED, also=BEEPS),
    M("stm-sends-boolean-on-real-event", "dcmotor", DC_SW, T3,
      "action $stop(); $beep!true; $flag!true; $tick }", "STM8", also=BEEPS),
    M("stm-sends-number-on-boolean-event", "dcmotor", DC_SW, T3,
      "action $stop(); $beep!1.0; $flag!1.5; $tick }", "STM8", also=BEEPS),
    M("stm-sends-vector-on-real-event", "dcmotor", DC_SW, T3,
      "action $stop(); $beep!(|1.0, 2.0|); $flag!true; $tick }", "STM8", also=BEEPS),
    M("stm-sends-value-on-untyped-event", "dcmotor", DC_SW, T3,
      "action $stop(); $beep!1.0; $flag!true; $tick!1 }", "STM4", also=BEEPS),
    M("stm-sends-typed-event-without-value", "dcmotor", DC_SW, T3,
      "action $stop(); $beep; $flag!true; $tick }", "STM4", also=BEEPS),
    M("stm-binds-untyped-event", "dcmotor", DC_SW, "condition $near action",
      "condition $near?x action", "STM4",
      also=((DC_SW, "const wref: real = 10.0", "const wref: real = 10.0\n\tvar x: real"),)),
    M("stm-binds-into-constant", "ranger", "RangerSoftware.rsm", "$echo?seen",
      "$echo?cruise", "STM4"),
    M("stm-binds-real-into-boolean", "ranger", "RangerSoftware.rsm", "$echo?seen",
      "$echo?armed", "STM8",
      also=(("RangerSoftware.rsm", "var seen: real = 0",
             "var seen: real = 0\n\tvar armed: boolean = false"),)),
    M("stm-reads-typed-event-without-binding", "ranger", "RangerSoftware.rsm",
      "condition $echo?seen", "condition $echo", ACCEPTED),
    M("stm-binds-real-into-int", "ranger", "RangerSoftware.rsm", "var seen: real = 0",
      "var seen: int = 0", "STM8", at="$echo?seen"),
    M("stm-speed-changed", "dcmotor", DC_SW, "wref: real = 10.0", "wref: real = 5.0",
      ACCEPTED, shows=r"registerWrite_drive!(\<guillemotleft>5.0\<guillemotright>)"),
    M("stm-bound-changed", "pendulum", "PendulumSoftware.rsm", "tmax: real = 0.3",
      "tmax: real = 0.2", ACCEPTED,
      shows=r"registerWrite_push!(\<guillemotleft>(- 0.2)\<guillemotright>)"),
    # ---- p-models ---------------------------------------------------------------------------
    M("part-missing-constant", "marxbot", "marXbotBase.rsm",
      "roll = PI pitch = 0 yaw = 0 }\n\t\tinstantiation HEIGHT = 0.05m\n",
      "roll = PI pitch = 0 yaw = 0 }\n", "P1", at="part LTreel",
      # a warning; Evolve's motion needs HEIGHT (E-CONST), the scenario's elements do not
      runs=("simulate",)),
    M("part-unknown-constant", "marxbot", "marXbotBase.rsm",
      "roll = PI pitch = 0 yaw = 0 }\n\t\tinstantiation HEIGHT = 0.05m\n",
      "roll = PI pitch = 0 yaw = 0 }\n\t\tinstantiation HEIGHT = 0.05m\n"
      "\t\tinstantiation SIZE = 0.05m\n", "P3", at="instantiation SIZE"),
    M("part-sets-valued-constant", "marxbot", "marXbotBase.rsm",
      "roll = PI pitch = 0 yaw = 0 }\n", "roll = PI pitch = 0 yaw = 0 }\n"
      "\t\tinstantiation BELT = 0.003m\n", "P2", at="instantiation BELT"),
    M("index-range-reversed", "marxbot", "marXbotBase.rsm", "index j : [0,24)",
      "index j : [24,0)", "IX1"),
    M("pose-field-twice", "dcmotor", DC_BASE, "z = 0.06m roll = 0", "z = 0.06m z = 0 roll = 0",
      "PO1"),
    M("link-fixed-to-itself", "rover", "RoverBase.rsm", "\tlocal link Head {\n",
      "\tlocal link Head {\n\t\tfixed to Head\n", "L6", at="fixed to Head"),
    M("joint-to-missing-link", "dcmotor", DC_BASE, "flexibly connected to Flywheel",
      "flexibly connected to Flywheell", "S1"),
    M("negative-mass", "dcmotor", DC_BASE, "mass 0.2kg", "mass -0.2kg", "V1"),
    M("negative-inertia", "pendulum", "PendulumBase.rsm",
      "ixx 0.001 ixy 0 ixz 0 iyy 0.001", "ixx 0.001 ixy 0 ixz 0 iyy -0.001", "V1"),
    M("zero-axis", "dcmotor", DC_BASE, "instantiation AXIS = (|0,0,1|)",
      "instantiation AXIS = (|0,0,0|)", "V6"),
    M("non-unit-axis", "pendulum", "PendulumBase.rsm", "AXIS = (|0,1,0|)",
      "AXIS = (|0,2,0|)", "V6"),
    M("near-unit-axis", "rover", "RoverBase.rsm", "AXIS = (|0,0,1|)",
      "AXIS = (|0,0,1.000001|)", ACCEPTED),
    M("axis-to-four-digits", "pendulum", "PendulumBase.rsm", "AXIS = (|0,1,0|)",
      "AXIS = (|0,0.9999,0|)", ACCEPTED),
    M("axis-one-percent-long", "pendulum", "PendulumBase.rsm", "AXIS = (|0,1,0|)",
      "AXIS = (|0,1.01,0|)", "V6"),
    M("axes-disagree", "dcmotor", DC_BASE, "instantiation AXIS = (|0,0,1|)",
      "instantiation AXIS = (|0,1,0|)", "V4", runs=BOTH),
    M("fixed-cycle", "rover", "RoverBase.rsm", "\tlocal link Head {\n",
      "\tlocal link Head {\n\t\tfixed to Tail\n", "Fix4", at="fixed to Tail",
      also=(("RoverBase.rsm", "\tlocal link LWheel {",
             "\tlocal link Tail {\n\t\tdef { inertial information { mass 0.1 } }\n"
             "\t\tfixed to Head\n\t}\n\tlocal link LWheel {"),)),
    M("fixed-cycle-through-a-part", "marxbot", "marXbotBase.rsm", LTREEL,
      in_ltreel("link Track fixed to Core"), "Fix4", at="link Track fixed to Core"),
    M("fixed-triangle-through-parts", "marxbot", "marXbotBase.rsm", LTREEL,
      in_ltreel("link Track fixed to Track in RTreel"), "Fix4",
      at="link Track fixed to Track in RTreel"),
    M("fixed-cycle-through-indexed-part-copies", "pincer", "PincerBase.rsm",
      "\t\tlocal body Plate {", "\t\tfixed to Root in Fingers\n\t\tlocal body Plate {", "Fix4",
      at="link Root fixed to Palm"),
    # ---- modules: one cycle (STM10), events carried by connections (STM11) ----------------
    M("machine-cycle-differs", "dcmotor", DC_SW, "stm SSpeed {\n\tcycleDef cycle == 1",
      "stm SSpeed {\n\tcycleDef cycle == 2", "STM10", at="cycleDef cycle == 2"),
    M("controller-cycle-differs", "dcmotor", DC_SW,
      "controller SpeedController {\n\tcycleDef cycle == 1",
      "controller SpeedController {\n\tcycleDef cycle == 0.5", "STM10",
      at="cycleDef cycle == 0.5"),
    M("every-cycle-changed-together", "dcmotor", DC_SW,
      "module DCMotorSoftware {\n\tcycleDef cycle == 1",
      "module DCMotorSoftware {\n\tcycleDef cycle == 2", ACCEPTED,
      also=((DC_SW, "controller SpeedController {\n\tcycleDef cycle == 1",
             "controller SpeedController {\n\tcycleDef cycle == 2"),
            (DC_SW, "stm SSpeed {\n\tcycleDef cycle == 1",
             "stm SSpeed {\n\tcycleDef cycle == 2"))),
    # (the theory's D reads near and drops it: it never occurs for the machine)
    M("event-not-connected-to-controller", "dcmotor", DC_SW,
      "\tconnection Bench on near to ctrl on near (_async)\n", "", "STM11", at="not $near",
      runs=BOTH, shows=DROPPED),
    M("event-not-connected-to-machine", "dcmotor", DC_SW,
      "\tconnection SpeedController on near to sm on near\n", "", "STM11", at="not $near",
      runs=BOTH, shows=DROPPED),
    # ---- third sweep: controllers' interfaces, vector writes, cycles that end -------------
    M("pvars-dollar-entry-of-vector-written", "pvars", "WheelSoftware.rsm",
      "entry speed = slow", "entry speed = slow ; $pair[1] = 1", "STM5", at="$pair[1] = 1",
      also=PAIR),
    M("pvars-dollar-whole-vector-written", "pvars", "WheelSoftware.rsm",
      "entry speed = slow", "entry speed = slow ; $pair = (|1, 2|)", ACCEPTED, also=PAIR),
    M("pvars-controller-does-not-require", "pvars", "WheelSoftware.rsm",
      "\trequires SpeedI\n\tsref", "\tsref", "STM12", at="entry speed = slow"),
    M("controller-does-not-require-operations", "dcmotor", DC_SW,
      "\tuses NearI\n\trequires SpeedI", "\tuses NearI", "STM12", at="$drive(wref)"),
    M("operation-vector-local", "dcmotor", DC_MAP, DRIVE, VECTOR_LOCAL, ACCEPTED),
    M("operation-vector-local-entry-agrees", "dcmotor", DC_MAP, DRIVE,
      VECTOR_LOCAL + "\n\t\tequation g[1] == w", ACCEPTED),
    M("operation-vector-local-entry-written-again", "dcmotor", DC_MAP, DRIVE,
      VECTOR_LOCAL + "\n\t\tequation g[1] == 2*w", "PMap16", at="g[1] == 2*w"),
    M("operation-vector-local-written-twice", "dcmotor", DC_MAP, DRIVE,
      VECTOR_LOCAL + "\n\t\tequation g == (|2*w, 0|)", "PMap16", at="g == (|2*w, 0|)"),
    M("stm-sends-an-input-event", "dcmotor", DC_SW, "entry $drive(wref)",
      "entry $near; $drive(wref)", "STM4", at="$near; $drive"),
    M("stm-sends-an-operation-without-parentheses", "dcmotor", DC_SW, T3, "action $stop }",
      ACCEPTED),
    M("stm-loop-without-exec", "dcmotor", DC_SW, "from Cruise to Check exec",
      "from Cruise to Check", "STM13", at="transition t1"),
    # a loop whose guards contradict each other is never completed in one cycle: valid
    M("stm-loop-without-exec-guards-exclusive", "dcmotor", DC_SW, "from Cruise to Check exec",
      "from Cruise to Check condition $near", ACCEPTED),
    M("stm-loop-through-junction-without-exec", "lift", "LiftSoftware.rsm",
      "from Rising to Top exec", "from Rising to Top", "STM13", at="transition t1"),
    M("stm-wait-negative", "dcmotor", DC_SW, "entry $drive(wref)",
      "entry wait(-1); $drive(wref)", "STM14", at="-1); $drive"),
    M("stm-wait-a-constant-fraction", "dcmotor", DC_SW, "entry $drive(wref)",
      "entry wait(wref / 4); $drive(wref)", "STM14", at="wref / 4"),
    M("stm-wait-two-cycles", "dcmotor", DC_SW, "entry $drive(wref)",
      "entry $drive(wref); wait(2)", ACCEPTED),
    # the first cycle's mode depends on the inputs: reach starts where the initial set
    # decides (tests/test_reach_first_cycle.py), simulate runs the machine itself, the
    # theory writes its cycle out
    M("stm-first-cycle-reads-an-event", "rover", "RoverSoftware.rsm",
      "from Ahead to Turn exec condition", "from Ahead to Turn condition", ACCEPTED),
    # an open constant (the paper's family of models): check warns, gen --isabelle runs (D
    # opaque), simulate (and reach, gen --flowstar: below) refuse it until it has a value
    M("stm-constant-without-value", "rover", "RoverSoftware.rsm", "const cruise: real = 8.0,",
      "const cruise: real,", "STM15", runs=("gen",)),
    M("stm-reads-a-package-constant-without-value", "rover", "RoverSoftware.rsm",
      "const cruise: real = 8.0, spin", "const spin", "STM15", at="const cruise: real\n",
      also=(("RoverSoftware.rsm", "interface WheelsI {",
             "const cruise: real\n\ninterface WheelsI {"),), runs=("gen",)),
    M("event-mapped-without-predicate", "dcmotor", DC_MAP,
      "\t\tpredicate Bench::Range.range <= 1.0\n", "", "PMap12", at="input event near",
      runs=BOTH),
    M("negative-size", "dcmotor", DC_BASE, "radius = 0.1m", "radius = -0.1m", "V2"),
    M("mass-changed", "rover", "RoverBase.rsm", "mass 0.1kg", "mass 0.15kg", ACCEPTED),
    M("relation-names-every-copy", "tracks", "TracksBase.rsm", SONAR,
      SONAR + "\t\t\trelation Range.distance == Axle.theta\n", "E-RELATION",
      at="Axle.theta"),
    M("relation-in-a-part-names-its-copy", "pincer", "PincerBase.rsm", PAD,
      PAD + "\t\tsref Tip = AngleEncoder {\n\t\t\trelation Tip.angle == Knuckle.theta\n"
      "\t\t}\n", ACCEPTED),
    M("relation-outside-a-part-names-its-joint", "pincer", "PincerBase.rsm", PLATE,
      PLATE + "\t\tsref Tip = AngleEncoder {\n\t\t\trelation Tip.angle == Knuckle.theta\n"
      "\t\t}\n", "S1", at="relation Tip.angle"),
)


def mutate(mutant: Mutant, into: Path) -> Path:
    """A copy of the mutant's folder in ``into`` with its edits made (each ``old`` must occur
    in the original exactly once, so a row cannot silently stop applying; an empty ``old``
    adds the file ``new`` holds)."""
    source, _ = FOLDERS[mutant.folder]
    folder = into / mutant.folder
    shutil.copytree(source, folder, ignore=shutil.ignore_patterns("*-gen", "README.md"))
    for file, old, new in ((mutant.file, mutant.old, mutant.new), *mutant.also):
        path = folder / file
        if not old:  # a file of the user's own, added to the folder
            assert not path.exists(), f"{mutant.name}: {file} exists"
            path.write_text(new, encoding="utf-8")
            continue
        text = path.read_text(encoding="utf-8")
        assert text.count(old) == 1, f"{mutant.name}: {old!r} occurs {text.count(old)} times"
        path.write_text(text.replace(old, new), encoding="utf-8")
    return folder


def expected_line(mutant: Mutant, folder: Path) -> int:
    """The line the diagnostic must point at: where ``at`` (or the replacement) starts."""
    text = (folder / (mutant.at_file or mutant.file)).read_text(encoding="utf-8")
    anchor = mutant.at or mutant.new.strip()
    assert anchor and text.count(anchor) == 1, f"{mutant.name}: anchor {anchor!r} not unique"
    return text[:text.index(anchor)].count("\n") + 1


def _run(argv: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    """``cyphy argv`` in process: exit status, stdout, stderr (never a traceback, never 70)."""
    status = main(argv)
    out, err = capsys.readouterr()
    assert status != 70 and "Traceback" not in err, (argv, err)
    return status, out, err


@pytest.mark.parametrize("mutant", MUTANTS, ids=lambda m: m.name)
def test_mutant(mutant: Mutant, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``check`` refuses the mutant with its code at its line (or accepts it); then
    ``gen --isabelle`` and ``simulate`` write nothing for a refused mutant and run for an
    accepted one."""
    folder = mutate(mutant, tmp_path)
    status, out, err = _run(["check", "--format", "json", str(folder)], capsys)
    diags = json.loads(out)
    errors = [d for d in diags if d["severity"] == "ERROR"]
    assert status == (1 if errors else 0), err
    if mutant.expect == ACCEPTED:
        assert errors == [], errors
    else:
        where = (mutant.expect, mutant.at_file or mutant.file, expected_line(mutant, folder))
        found = {(d["code"], Path(d["span"]["file"]).name, d["span"]["line"]) for d in diags}
        assert where in found, diags
        assert all(d["hint"] for d in diags), diags
    runs = mutant.runs if mutant.runs is not None else BOTH if mutant.expect == ACCEPTED else ()
    assert not (runs and errors)

    theories = tmp_path / "theories"
    status, _, err = _run(["gen", str(folder), "--isabelle", "-o", str(theories)], capsys)
    assert (status == 0) == ("gen" in runs), err
    if "gen" in runs:
        theory = next(theories.glob("*_CyPhyCircus.thy")).read_text(encoding="utf-8")
        assert mutant.shows is None or mutant.shows in theory
    else:
        assert not theories.exists() or not any(theories.iterdir())

    trajectories = tmp_path / "trajectories.csv"
    scenario = folder / FOLDERS[mutant.folder][1]
    status, _, err = _run(["simulate", str(folder), "--scenario", str(scenario), "--t-end",
                           "0.2", "-o", str(trajectories)], capsys)
    assert (status == 0) == ("simulate" in runs), err
    assert trajectories.exists() == ("simulate" in runs)


def test_an_index_past_an_open_bound_is_refused_once_the_bound_is_given(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``Proximity[30]`` of ``index j : [0,NP)``, NP without a value: ``check`` cannot tell
    (a warning, exit 0); given NP = 24, by ``--const`` (``check``, ``gen``) or the scenario's
    ``[consts]`` (``simulate``, ``reach``), each refuses the index with IX5 at it."""
    mutant = next(m for m in MUTANTS if m.name == "index-past-an-open-bound")
    folder = mutate(mutant, tmp_path)
    line = expected_line(mutant, folder)
    at = f"Mapping.rsm:{line}:29: "
    status, _, err = _run(["check", str(folder)], capsys)
    assert status == 0 and at + "WARNING IX5:" in err and "NP has no value" in err, err
    scenario = str(folder / "obstacle_stop.toml")
    runs = (["check", str(folder), "--const", "NP=24"],
            ["gen", str(folder), "--sdf", "-o", str(tmp_path / "sdf"), "--const", "NP=24"],
            ["simulate", str(folder), "--scenario", scenario, "-o", str(tmp_path / "t.csv")],
            ["reach", str(folder), "--scenario", scenario])
    for argv in runs:
        status, _, err = _run(argv, capsys)
        assert status in (1, 2) and at + "ERROR IX5: the mapping of input event obstacle " \
            "reads copy 30 of Proximity, whose index j ranges over 0..23" in err, (argv, err)
    assert not (tmp_path / "sdf").exists() and not (tmp_path / "t.csv").exists()


def test_a_machine_constant_without_a_value_is_refused_by_the_commands_that_run_it(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``const cruise: real`` in the rover's drive machine: ``check`` warns (STM15, exit 0)
    unless ``--const`` gives it; ``simulate``, ``gen --flowstar`` and ``reach`` refuse the
    model with an error at the constant, writing nothing (before: ``check`` said nothing);
    given ``--const cruise=8``, simulate runs."""
    from conftest import flowstar_binary

    mutant = next(m for m in MUTANTS if m.name == "stm-constant-without-value")
    folder = mutate(mutant, tmp_path)
    at = f"RoverSoftware.rsm:{expected_line(mutant, folder)}:8: "
    status, _, err = _run(["check", str(folder)], capsys)
    assert status == 0 and at + "WARNING STM15: the constant cruise read by machine " \
        "SDrive has no value" in err, err
    status, _, err = _run(["check", str(folder), "--const", "cruise=8"], capsys)
    assert status == 0 and "STM15" not in err, err
    scenario = str(folder / "bump.toml")
    runs = [["simulate", str(folder), "--scenario", scenario, "--t-end", "0.2", "-o",
             str(tmp_path / "t.csv")],
            ["gen", str(folder), "--flowstar", "--scenario", scenario, "-o",
             str(tmp_path / "flowstar")]]
    if flowstar_binary() is not None:  # reach looks for Flow* first
        runs.append(["reach", str(folder), "--scenario", scenario])
    for argv in runs:
        status, _, err = _run(argv, capsys)
        assert status in (1, 2) and at + "ERROR E-FLOWSTAR: state machine SDrive: the " \
            "constant cruise of SDrive has no value" in err, (argv, err)
    assert not (tmp_path / "t.csv").exists() and not (tmp_path / "flowstar").exists()
    status, _, err = _run(runs[0] + ["--const", "cruise=8"], capsys)
    assert status == 0 and (tmp_path / "t.csv").exists(), err
