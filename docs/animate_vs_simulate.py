"""Draw docs/animate_vs_simulate.png: the generated Isabelle theories run by ``cyphy animate``
beside ``cyphy simulate`` on the same machine, inputs and constants (docs/theories.md).

    python3 docs/animate_vs_simulate.py      # about a minute; rewrites the PNG
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from cyphy import api  # noqa: E402  (after the checkout is on the path)

MOTOR = {"R": 1.0, "L": 0.1, "Kt": 0.05, "Ke": 0.05, "b": 0.01, "J": 0.01, "Kp": 2.0,
         "Ki": 5.0, "Kd": 0.0}
CASES = [  # example, mapping, scenario, t_end, inputs, constants, speeds plotted
    ("dcmotor", "examples/dcmotor", "examples/dcmotor/whole_bench.toml", 2.0,
     {"Range_distance": "3.05 - 2*t"}, {"tscale": 0.1}, ["Motor_av"]),
    ("marXbot", "examples/marxbot/Mapping.rsm", "examples/marxbot/avoid_obstacle.toml", 9.0,
     {"Proximity1_distance": "0.255 - 0.0125125*(LMotor_theta + RMotor_theta)"},
     {**{f"{m}_{k}": v for m in ("LMotor", "RMotor") for k, v in MOTOR.items()},
      "Proximity1_a": 0.3, "Proximity1_b": 0.01, "Proximity1_c": 0.0, "tscale": 0.1},
     ["LMotor_av", "RMotor_av"]),
]


def main() -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(1, 2, figsize=(11, 4), dpi=80)
    for ax, (title, mapping, scenario, t_end, inputs, consts, speeds) in zip(axes, CASES):
        with tempfile.TemporaryDirectory() as folder:
            generated = api.generate_isabelle([ROOT / mapping], api.SemanticsGenOptions())
            for name, text in generated.files.items():
                (Path(folder) / name).write_text(text)
            animation = api.animate(folder, t_end, inputs, consts, samples=181)
        model = str(ROOT / Path(mapping).parent if mapping.endswith(".rsm") else ROOT / mapping)
        done = subprocess.run([sys.executable, "-m", "cyphy", "simulate", model, "--scenario",
                               str(ROOT / scenario), "--t-end", str(t_end), "--format",
                               "json", "-q"], capture_output=True, text=True, check=True,
                              cwd=ROOT, env={"PYTHONPATH": str(ROOT), "PATH": ""})
        simulated = json.loads(done.stdout)
        times = [row[0] for row in animation.rows]
        for name in speeds:
            i = animation.columns.index(name)
            ax.plot(simulated["t"], simulated["columns"][name], lw=3, alpha=0.4,
                    label=f"{name} (simulate)")
            ax.plot(times, [row[i] for row in animation.rows], "--", lw=1.2,
                    label=f"{name} (animate: the theory)")
        ax.set_title(f"{title}: {animation.composition}")
        ax.set_xlabel("t (s)")
        ax.set_ylabel("rad/s")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="small")
    figure.tight_layout()
    figure.savefig(ROOT / "docs" / "animate_vs_simulate.png", metadata={"Software": None})


if __name__ == "__main__":
    main()
