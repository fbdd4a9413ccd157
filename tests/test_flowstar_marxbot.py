"""The marXbot examples (issue 17): the d-model's turn is half a turn at the scenarios'
tscale (checked by `cyphy simulate`), and the verdicts of the scenarios under the machine
SMovement with the real Flow* (obstacle_stop.toml's is in test_flowstar_check.py)."""

from __future__ import annotations

import math
import re
import tomllib

import numpy as np
import pytest

from cyphy.cli import main

from conftest import EXAMPLES, flowstar_binary, needs_flowstar
from test_simulate_machine import _csv

MARXBOT = EXAMPLES / "marxbot"
RADIUS, AXIS = 0.025025, 0.06  # Mapping.rsm: the drive wheels' radius, the track distance


def test_the_machine_s_time_unit_is_the_scenarios_tscale():
    """SMovement's clock counts time units; its constant tu says how long one is, and every
    marXbot scenario runs the machine with that tscale."""
    software = (MARXBOT / "marXbotSoftware.rsm").read_text()
    tu = float(re.search(r"\btu: real = ([0-9.eE+-]+)", software).group(1))
    assert "since(C) >= PI/(av*tu)" in software
    for path in sorted(MARXBOT.glob("*.toml")):
        assert tomllib.loads(path.read_text())["tscale"] == tu, path.name


def test_smovement_turns_the_robot_about_half_a_turn(capsys):
    """`cyphy simulate` under the machine: C is reset at the stop (t = 1.8) and
    since(C) >= PI/(0.5*0.1) = 62.8 first holds 63 cycles of 0.1 s later, so the wheels are
    asked to turn on the spot from t = 1.9 to 8.1 (0.5 rad/s for 6.2 s, 3.1 rad), and the
    robot's heading, the integral of r(wl - wr)/axis, turns by about pi (the motors' lag
    carries it a little past the command's end)."""
    assert main(["simulate", str(MARXBOT), "--scenario", str(MARXBOT / "avoid_obstacle.toml"),
                 "--t-end", "9", "--samples", "901"]) == 0
    c = _csv(capsys.readouterr().out)
    t = c["t"]
    demand_l = c["LMotor_e"] + c["LMotor_av"]
    demand_r = c["RMotor_e"] + c["RMotor_av"]
    turn = 0.5 * AXIS / (2 * RADIUS)  # move(0, av): the wheels' speeds
    turning = np.isclose(demand_l, turn) & np.isclose(demand_r, -turn)
    first = np.nonzero(turning)[0][0]
    last = first + np.argmin(turning[first:]) - 1  # the first turn's last sample
    begin, end = t[first], t[last]
    assert begin == pytest.approx(1.9, abs=0.011)  # the cycle after the stop at t = 1.8
    assert end + 0.01 - begin == pytest.approx(6.2, abs=0.011)
    rate = RADIUS * (c["LMotor_av"] - c["RMotor_av"]) / AXIS
    heading = np.concatenate([[0], np.cumsum(np.diff(t) * (rate[1:] + rate[:-1]) / 2)])
    turned = heading[np.searchsorted(t, end + 0.1)] - heading[np.searchsorted(t, begin)]
    assert turned == pytest.approx(math.pi, abs=0.05)
    # turning on the spot leaves the obstacle's distance as it is
    d = c["Proximity1_distance"]
    assert np.ptp(d[(t >= begin + 0.5) & (t <= end)]) < 2e-3


def _reach(capsys, scenario, tmp_path):
    rc = main(["reach", str(MARXBOT), "--scenario", str(MARXBOT / scenario), "-o",
               str(tmp_path / "out"), "--flowstar-bin", str(flowstar_binary())])
    out = capsys.readouterr()
    return rc, out.out + out.err


@needs_flowstar
def test_real_flowstar_proves_avoid_obstacle(tmp_path, capsys):
    """The robot keeps 5 cm from the obstacle over 2.5 s under SMovement: SAFE, one run
    (about 20 s of Flow* on an idle machine)."""
    rc, out = _reach(capsys, "avoid_obstacle.toml", tmp_path)
    assert rc == 0 and out.startswith("SAFE: Flow* proved the initial set safe in 1 run, "
                                      "every computation completed"), out


@needs_flowstar
def test_real_flowstar_proves_avoid_obstacle_with_the_hinges_dynamics(tmp_path, capsys):
    """The same with the wheels' equations of motion: SAFE, one run (about 20 s)."""
    rc, out = _reach(capsys, "avoid_obstacle_dynamics.toml", tmp_path)
    assert rc == 0 and out.startswith("SAFE: Flow* proved the initial set safe in 1 run, "
                                      "every computation completed"), out
