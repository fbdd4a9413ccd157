"""Annotations to SDF elements (sdf.md decisions 9, 11-13; the paper's §5.3).

An annotation ``Ray { update_rate = 1  ray = RayDetails { … } }`` becomes one element per
parameter of its template, in the template's declaration order (the parameters of the
templates it extends first), named after the parameter without a leading ``_``; a nested
template becomes a nested element. Parameters the annotation leaves out take the template's
default (the paper: defaults are emitted); a nested template with no default is written only
when the annotation sets it. A few parameters are XML attributes in SDF rather than elements
(``ATTRIBUTES``). Values naming a model element (``gearbox_reference_body = B``,
``collision = Link::body``) are turned into that element's SDF name by the caller's resolver.
"""

from __future__ import annotations

from typing import Callable, Iterator

from cyphy import expr as ex
from cyphy.lang import ast
from cyphy.lang.workspace import Workspace
from cyphy.model.elements import AnnotationValue
from cyphy.model.evaluate import EvalError, evaluate
from cyphy.semantics.sdf.tree import Node

#: (template, parameter) → attribute name: where SDF 1.6 has an attribute, not an element.
ATTRIBUTES = {
    ("Light", "_type"): "type",
    ("Save", "enabled"): "enabled",
    ("SensorNoise", "_type"): "type",
}

#: Resolves an element path (``('Rod', 'my_body')``) to an SDF name, or None.
Resolver = Callable[[tuple[str, ...]], "str | None"]


class Templates:
    """The annotation templates of a workspace by simple name, the user's before the
    library's (an elaborated annotation keeps only its template's simple name)."""

    def __init__(self, ws: Workspace) -> None:
        self._by_name: dict[str, ast.AnnotationTemplate] = {}
        user = list(ws.user_files())
        users = {f.path for f in user}
        for f in [*user, *(f for p, f in ws.files.items() if p not in users)]:
            for item in f.items:
                if isinstance(item, ast.AnnotationTemplate):
                    self._by_name.setdefault(item.name, item)
        self._defaults: dict[int, object] = {}

    def get(self, name: str) -> ast.AnnotationTemplate | None:
        return self._by_name.get(name)

    def chain(self, name: str) -> list[ast.AnnotationTemplate]:
        """The template and those it extends, the most general first."""
        out: list[ast.AnnotationTemplate] = []
        t = self.get(name)
        while t is not None and t not in out:
            out.insert(0, t)
            t = self.get(t.extends[-1]) if t.extends else None
        return out

    def is_a(self, name: str, general: str) -> bool:
        return any(t.name == general for t in self.chain(name))

    def params(self, name: str) -> Iterator[tuple[ast.AnnotationTemplate, ast.TemplateParam]]:
        seen: set[str] = set()
        for t in self.chain(name):
            for p in t.params:
                if p.name not in seen:
                    seen.add(p.name)
                    yield t, p

    def default(self, param: ast.TemplateParam) -> object:
        """The value of a parameter's default (literals only in the library), or None."""
        key = id(param)
        if key not in self._defaults:
            self._defaults[key] = self._evaluate(param.default)
        return self._defaults[key]

    def _evaluate(self, value: object) -> object:
        if value is None:
            return None
        if isinstance(value, ast.TemplateInstance):
            args = tuple((a.name, self._evaluate(a.value)) for a in value.args)
            return AnnotationValue((value.template[-1],), args, value.span)
        try:
            return evaluate(value, {})  # type: ignore[arg-type]
        except EvalError:
            if isinstance(value, ex.Name):
                return value.parts
            return None


def fill(node: Node, value: AnnotationValue, templates: Templates, resolve: Resolver,
         skip: frozenset[str] = frozenset()) -> None:
    """Add to ``node`` the elements (and attributes) of ``value``, defaults included, except
    the parameters named in ``skip`` (which the caller writes itself)."""
    name = value.template[-1]
    given = dict(value.args)
    declared = False
    for owner, param in templates.params(name):
        declared = True
        if param.name in skip:
            continue
        v = given[param.name] if param.name in given else templates.default(param)
        if v is None:
            continue
        attribute = ATTRIBUTES.get((owner.name, param.name))
        if attribute is not None:
            node.attrs[attribute] = _attribute_text(v)
            continue
        write(node, param.name, v, templates, resolve)
    if not declared:  # a template we do not know (AN1 reports it): what was given
        for pname, v in value.args:
            if pname not in skip and v is not None:
                write(node, pname, v, templates, resolve)


def write(node: Node, pname: str, v: object, templates: Templates, resolve: Resolver) -> None:
    """One parameter as a child element of ``node``."""
    tag = pname.lstrip("_")
    if isinstance(v, AnnotationValue):
        fill(node.add(tag), v, templates, resolve)
    elif isinstance(v, tuple):
        node.add(tag, resolve(v) or "::".join(v))
    else:
        node.add(tag, v)  # type: ignore[arg-type]


def _attribute_text(v: object) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    return str(v)
