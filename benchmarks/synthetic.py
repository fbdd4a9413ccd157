"""Synthetic RoboSim p-models of any size, for benchmarks and scaling tests.

``chain_model(n)`` is a serial chain of ``n`` links ``L0 … L{n-1}``; ``tree_model(n, b)`` is a
tree of ``n`` links where link ``Lk`` (k ≥ 1) hangs from ``L{(k-1)//b}`` (breadth-first
numbering, ``b`` children per inner link). Every link has a pose, a ``def`` with a mass, one box
body and one ``sref`` IR sensor (or, with ``sensors_per_link=k``, one indexed ``sref`` that
expands to ``k`` sensors); every link with children holds, per child ``Lc``, a revolute
``jref J<c-1>`` flexibly connected to ``Lc`` with a ``SpeedControlMotor`` ``aref M<c-1>`` whose
torque drives the joint (``relation Mk.T == Jk.tau``). So a model of ``n`` links has ``n``
bodies, ``n`` sensors and ``n - 1`` joints and actuators, whatever its shape.

Only library elements are used (``physmod::joints::Revolute``,
``physmod::actuators::SpeedControlMotor``, ``physmod::sensors::IR``), so a chain checks with
no diagnostics; so does a tree in the ``lean`` form, at any size. A tree of the default form
places cousins alike (by depth and place among siblings), and from about 40 links some are at
the same place: V5 warns. ``write_model`` puts a model in a folder for the file-based API.
"""

from __future__ import annotations

from pathlib import Path

_HEADER = """\
package synthetic

import physmod::joints::Revolute
import physmod::actuators::SpeedControlMotor
import physmod::sensors::IR
import physmod::sdf::annotations::*
import physmod::math::*

"""


def _num(v: float) -> str:
    return repr(round(v, 6))


#: Joint axes of a bent chain, by joint number: about z, then y, then x, and again.
_BENT_AXES = ("0,0,1", "0,1,0", "1,0,0")


def _link(k: int, children: list[int], x: float, z: float, yaw: float, sensors: int,
          bent: bool = False) -> str:
    joints = "".join(
        f"""
\t\tjref J{c - 1} = Revolute {{
\t\t\tannotation Revolute {{ axis = Axis {{ xyz = (|{_axis(c - 1, bent)}|) }} }}
\t\t\tinstantiation AXIS = (|{_axis(c - 1, bent)}|)
\t\t\tflexibly connected to L{c}
\t\t\taref M{c - 1} = SpeedControlMotor {{
\t\t\t\trelation M{c - 1}.T == J{c - 1}.tau
\t\t\t}}
\t\t}}"""
        for c in children
    )
    index = f"\n\t\t\tindex i : [0,{sensors})" if sensors > 1 else ""
    sensor_y = "0.01*i" if sensors > 1 else "0.0"
    return f"""
\tlocal link L{k} {{
\t\tpose {{ x = {_num(x)} y = 0.0 z = {_num(z)} roll = 0.0 pitch = 0.0 yaw = {_num(yaw)} }}
\t\tdef {{
\t\t\tinertial information {{ mass 1.0 }}
\t\t}}
\t\tlocal body B{k} {{
\t\t\tpose {{ x = 0.0 y = 0.0 z = 0.05 roll = 0.0 pitch = 0.0 yaw = 0.0 }}
\t\t\tdef {{ box(length = 0.1, width = 0.05, height = 0.1) }}
\t\t}}
\t\tsref S{k} = IR {{{index}
\t\t\tpose {{ x = 0.05 y = {sensor_y} z = 0.05 roll = 0.0 pitch = 0.0 yaw = 0.0 }}
\t\t}}{joints}
\t}}
"""


def _lean_link(k: int, children: list[int], x: float, z: float, yaw: float) -> str:
    """A link of :func:`tree_model`'s ``lean`` form: a pose, a mass, a box and a revolute
    joint per child, no sensor, no motor (about 300 bytes a link). Each link is a millimetre
    further along y than the one before, so that no two are at the same place (V5): the
    model checks with no diagnostics at any size."""
    joints = "".join(f"\n\t\tjref J{c - 1} = Revolute {{ instantiation AXIS = (|0,0,1|) "
                     f"flexibly connected to L{c} }}" for c in children)
    y = _num(0.001 * k)
    return f"""\tlocal link L{k} {{
\t\tpose {{ x = {_num(x)} y = {y} z = {_num(z)} roll = 0.0 pitch = 0.0 yaw = {_num(yaw)} }}
\t\tdef {{ inertial information {{ mass 1.0 }} }}
\t\tlocal body B{k} {{ def {{ box(length = 0.1, width = 0.05, height = 0.1) }} }}{joints}
\t}}
"""


def _axis(joint: int, bent: bool) -> str:
    return _BENT_AXES[joint % 3] if bent else "0,0,1"


def _model(name: str, n: int, parent_of: list[int | None], sensors: int,
           bent: bool = False, lean: bool = False) -> str:
    if n < 1:
        raise ValueError("a synthetic model needs at least one link")
    children: list[list[int]] = [[] for _ in range(n)]
    depth = [0] * n
    for k in range(1, n):
        p = parent_of[k]
        assert p is not None and p < k
        children[p].append(k)
        depth[k] = depth[p] + 1
    parts = [_HEADER, f"pmodel {name} {{\n"]
    for k in range(n):
        sibling = children[parent_of[k]].index(k) if parent_of[k] is not None else 0
        x = 0.1 * (sibling + depth[k]) if bent else 0.1 * sibling
        if lean:
            parts.append(_lean_link(k, children[k], x, 0.1 * depth[k], 0.1 * (k % 7)))
        else:
            parts.append(_link(k, children[k], x, 0.1 * depth[k], 0.1 * (k % 7), sensors,
                               bent))
    parts.append("}\n")
    return "".join(parts)


def chain_model(n: int, *, sensors_per_link: int = 1, bent: bool = False) -> str:
    """RoboSim text of a p-model ``Chain<n>``: ``L0 → L1 → … → L{n-1}`` by joints ``J0 … J{n-2}``.

    ``sensors_per_link > 1`` makes each ``sref`` indexed (``index i : [0,k)``, ``y = 0.01*i``),
    to exercise index expansion. By default every joint turns about z and the links are
    stacked along z (coaxial: the mass matrix does not depend on the angles); ``bent`` turns
    the joints about z, y, x in turn and steps each link 0.1 m along x too, a robot arm whose
    equations of motion couple every joint."""
    return _model(f"Chain{n}", n, [None, *range(n - 1)], sensors_per_link, bent)


def tree_model(n: int, branching: int = 3, *, sensors_per_link: int = 1,
               lean: bool = False) -> str:
    """RoboSim text of a p-model ``Tree<n>``: a ``branching``-ary tree of ``n`` links, ``L0`` the
    root and ``L{(k-1)//branching}`` the parent of ``Lk``; the joint to ``Lk`` is ``J{k-1}``.
    ``lean``: links without sensors or motors (:func:`_lean_link`), a model about half the
    size in bytes."""
    if branching < 1:
        raise ValueError("branching must be at least 1")
    return _model(f"Tree{n}", n, [None, *((k - 1) // branching for k in range(1, n))],
                  sensors_per_link, lean=lean)


def write_model(folder: Path, text: str, name: str = "synthetic.pm") -> Path:
    """Write ``text`` to ``folder/name`` (creating the folder) and return the file's path."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


if __name__ == "__main__":  # print a small model, to look at
    import sys

    size = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    print(chain_model(size))
