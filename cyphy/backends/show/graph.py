"""The kinematic graph of an elaborated p-model for Graphviz (``cyphy show --format dot``,
``--format svg``).

Links are nodes (labelled with their qualified name below the p-model, the full name as
tooltip); each joint instance is a solid edge from its parent link to its child link,
labelled with the joint's name and its annotation's template (else its definition); each
fixed connection is a dashed edge labelled ``fixed``; a joint with no flexible connection is
a dotted edge to a small point. Parallel edges and cycles are drawn as they are: the graph is
the model's, before any loop is cut for a tree format.
"""

from __future__ import annotations

import shutil
import subprocess

from cyphy.model.elements import ElaboratedModel, Element, Joint


class GraphvizMissing(Exception):
    """``dot`` is not on PATH (the message says how to get it)."""


def _quote(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


def _below_model(element: Element) -> str:
    return "::".join(element.qname[1:]) or element.qname[0]


def _kind(joint: Joint) -> str:
    if joint.annotation is not None:
        return joint.annotation.template[-1]
    if joint.definition:
        return joint.definition.rpartition("::")[2]
    return "joint"


def model_to_dot(model: ElaboratedModel) -> str:
    """The graph in the DOT language: deterministic (declaration order throughout)."""
    ids = {id(link): f"l{i}" for i, link in enumerate(model.links)}
    lines = [f"digraph {_quote(model.name)} {{",
             f"  label={_quote('kinematic graph of ' + model.name)};",
             "  labelloc=t;",
             "  rankdir=TB;",
             '  node [shape=box, style="rounded,filled", fillcolor="#eef3fb", '
             'fontname="Helvetica"];',
             '  edge [fontname="Helvetica", fontsize=10];']
    for link in model.links:
        lines.append(f"  {ids[id(link)]} [label={_quote(_below_model(link))}, "
                     f"tooltip={_quote(link.name)}];")
    for joint in model.joints:
        assert joint.parent is not None and joint.child is not None
        label = f"{joint.simple_name}\n({_kind(joint)})"
        lines.append(f"  {ids[id(joint.parent)]} -> {ids[id(joint.child)]} "
                     f"[label={_quote(label)}, tooltip={_quote(joint.name)}];")
    for fixed in model.fixed:
        assert fixed.parent is not None and fixed.child is not None
        lines.append(f"  {ids[id(fixed.parent)]} -> {ids[id(fixed.child)]} "
                     '[label="fixed", style=dashed, arrowhead=none];')
    for i, joint in enumerate(model.unconnected):
        point = f"u{i}"
        lines.append(f"  {point} [shape=point, label=\"\"];")
        owner = ids.get(id(joint.parent)) if joint.parent is not None else None
        if owner is not None:
            label = f"{joint.simple_name}\n(unconnected)"
            lines.append(f"  {owner} -> {point} [label={_quote(label)}, style=dotted, "
                         f"tooltip={_quote(joint.name)}];")
    lines.append("}")
    return "\n".join(lines) + "\n"


def dot_to_svg(dot: str) -> str:
    """The graph drawn by Graphviz's ``dot`` as SVG."""
    binary = shutil.which("dot")
    if binary is None:
        raise GraphvizMissing("--format svg needs Graphviz's `dot` on PATH (Debian: apt "
                              "install graphviz); --format dot writes the graph without it")
    done = subprocess.run([binary, "-Tsvg"], input=dot, capture_output=True, text=True,
                          check=False)
    if done.returncode != 0:
        raise GraphvizMissing(f"Graphviz's dot failed: {done.stderr.strip()}")
    return done.stdout
