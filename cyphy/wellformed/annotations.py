"""Annotations and templates: AN1-AN4.

An annotation ``annotation Revolute { axis = Axis { xyz = (|0,1,0|) } }`` instantiates an
annotation template; a parameter is a value (``xyz: vector(real, 3)``), an element path
(``collision: ElementPath``) or a nested template (``axis: template Axis``). Templates may extend
one another and inherit their parameters. S1 reports template names that resolve to no
template; these rules check the rest.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

from cyphy import expr as ex
from cyphy.diagnostics import did_you_mean
from cyphy.lang import ast
from cyphy.lang.notation import type_to_notation
from cyphy.lang.scopes import is_template
from cyphy.wellformed.indexing import (
    Lookup, lookup_in, site_names, type_problem,
)
from cyphy.wellformed.registry import WFContext, rule

Template = ast.AnnotationTemplate
ELEMENT_PATH = ("ElementPath",)


# --------------------------------------------------------------------------- templates


def _resolve(ctx: WFContext, owner: Template, name: ast.QName, node: object
             ) -> Template | None:
    """A template named in ``owner`` (its ``extends`` or a parameter's type): recorded by S1
    for the user's templates, looked up from the owner's file for the library's."""
    target = ctx.target(node)
    if isinstance(target, Template):
        return target
    file = ctx.file_of(owner)
    if file is None:
        return None
    found = ctx.scopes.lookup(file, name, is_template)
    return found[0] if found and isinstance(found[0], Template) else None


def _parent(ctx: WFContext, t: Template) -> Template | None:
    return _resolve(ctx, t, t.extends, t) if t.extends is not None else None


def _chain(ctx: WFContext, t: Template) -> list[Template]:
    """``t`` and the templates it extends, nearest first, stopping before a repetition."""
    chain = [t]
    parent = _parent(ctx, t)
    while parent is not None and all(parent is not c for c in chain):
        chain.append(parent)
        parent = _parent(ctx, parent)
    return chain


def _params(ctx: WFContext, t: Template) -> dict[str, tuple[ast.TemplateParam, Template]]:
    """The parameters of ``t``, inherited ones included (the nearest declaration wins).
    Remembered per template for the run: every annotation of a model asks (do not change
    the returned dict)."""
    memo: dict[int, tuple[Template, dict[str, tuple[ast.TemplateParam, Template]]]] = \
        ctx.cache.setdefault("template params", {})
    hit = memo.get(id(t))
    if hit is not None and hit[0] is t:
        return hit[1]
    params: dict[str, tuple[ast.TemplateParam, Template]] = {}
    for c in _chain(ctx, t):
        for p in c.params:
            params.setdefault(p.name, (p, c))
    memo[id(t)] = (t, params)
    return params


def _extends(ctx: WFContext, sub: Template, sup: Template) -> bool:
    return any(c is sup for c in _chain(ctx, sub))


def _all_templates(ctx: WFContext) -> Iterator[Template]:
    for f in ctx.workspace.files.values():
        for item in f.items:
            if isinstance(item, Template):
                yield item


def _nested_only(ctx: WFContext) -> dict[int, tuple[Template, Template, str]]:
    """Templates that are the type of a template parameter (``axis: template Axis``): the
    nested details of an annotation, with one template and parameter that take each."""
    out: dict[int, tuple[Template, Template, str]] = {}
    for t in _all_templates(ctx):
        for p in t.params:
            if p.template is not None:
                target = _resolve(ctx, t, p.template, p)
                if target is not None:
                    out.setdefault(id(target), (target, t, p.name))
    return out


# --------------------------------------------------------------------------- annotations


Annotated = tuple[ast.SourceFile, str, ast.Annotation, Lookup]


def _annotations(ctx: WFContext) -> list[Annotated]:
    """Every annotation of the user's files, with the block it annotates and a lookup for the
    names its values may use (the block's constants, the p-model's, the package's). Found
    once per run, for AN1-AN3."""
    if "annotations" not in ctx.cache:
        ctx.cache["annotations"] = list(_find_annotations(ctx))
    return ctx.cache["annotations"]


def _find_annotations(ctx: WFContext) -> Iterator[Annotated]:
    for site in ctx.blocks():
        block = site.block
        members = list(block.annotations) + [m for d in block.definitions for m in d.members
                                             if isinstance(m, ast.Annotation)]
        if members:
            lookup = lookup_in(ctx, site.file, site_names(ctx, site))
            for a in members:
                yield site.file, f"{block.kind.value} {block.name}", a, lookup
    for file, definition in ctx.definitions():
        names = {m.name: m for m in definition.members if isinstance(m, ast.VarDecl)}
        lookup = lookup_in(ctx, file, names)
        for m in definition.members:
            if isinstance(m, ast.Annotation):
                yield file, f"{definition.kind.value} definition {definition.name}", m, lookup


def _instances(inst: ast.TemplateInstance) -> Iterator[ast.TemplateInstance]:
    """``inst`` and the template instances nested in it."""
    stack = [inst]
    while stack:
        i = stack.pop()
        yield i
        stack.extend(a.value for a in reversed(i.args)
                     if isinstance(a.value, ast.TemplateInstance))


def _template_defaults(ctx: WFContext) -> Iterator[tuple[ast.SourceFile, Template,
                                                         ast.TemplateParam]]:
    for file, t in ctx.items(Template):
        for p in t.params:
            if p.default is not None:
                yield file, t, p


def _name(inst: ast.TemplateInstance) -> str:
    return "::".join(inst.template)


@rule("AN1", "an annotation names an annotation template")
def check_AN1_names_template(ctx: WFContext) -> None:
    """An annotation names an annotation template that exists. S1 reports a name that is no
    template at all; AN1 reports an annotation that names a template which exists only as the
    nested detail of another (``annotation Axis {…}``, where Axis is the type of the ``axis``
    parameter of Revolute): such a template describes part of an SDF element, not one."""
    nested = _nested_only(ctx)
    for _, what, a, _ in _annotations(ctx):
        target = ctx.target(a.instance)
        if not isinstance(target, Template) or id(target) not in nested:
            continue
        _, owner, param = nested[id(target)]
        ctx.error("AN1", a.instance, f"the annotation of {what} names template "
                  f"{target.name}, which is not an annotation template: it is the type of "
                  f"parameter '{param}' of {owner.name}",
                  f"write 'annotation {owner.name} {{ {param} = {target.name} {{ … }} }}'")


@rule("AN2", "an annotation sets only parameters its template declares")
def check_AN2_declared_parameters(ctx: WFContext) -> None:
    """Every parameter set by an annotation (at any nesting depth) is declared by the template
    it instantiates or by a template that one extends."""
    roots = [a.instance for _, _, a, _ in _annotations(ctx)]
    roots += [p.default for _, _, p in _template_defaults(ctx)
              if isinstance(p.default, ast.TemplateInstance)]
    misplaced = {id(inst) for inst in _wrong_nested(ctx, roots)}
    for root in roots:
        for inst in _instances(root):
            template = ctx.target(inst)
            if not isinstance(template, Template) or id(inst) in misplaced:
                continue  # S1, or AN3 reports the instance itself as the wrong template
            params = _params(ctx, template)
            for arg in inst.args:
                if arg.name in params:
                    continue
                chain = " or the templates it extends" if template.extends else ""
                ctx.error("AN2", arg, f"template {template.name}{chain} declares no "
                          f"parameter '{arg.name}'", did_you_mean(arg.name, params) or
                          f"its parameters are: {', '.join(sorted(params)) or '(none)'}")


def _wrong_nested(ctx: WFContext, roots: list[ast.TemplateInstance]
                  ) -> Iterator[ast.TemplateInstance]:
    """Nested instances of a template other than the one their parameter takes
    (``sonar = Sonar { … }`` where ``sonar: template SonarDetails``)."""
    for root in roots:
        for inst in _instances(root):
            template = ctx.target(inst)
            if not isinstance(template, Template):
                continue
            params = _params(ctx, template)
            for arg in inst.args:
                if isinstance(arg.value, ast.TemplateInstance) and arg.name in params:
                    param, owner = params[arg.name]
                    want = (_resolve(ctx, owner, param.template, param)
                            if param.template is not None else None)
                    got = ctx.target(arg.value)
                    if isinstance(got, Template) and want is not None \
                            and not _extends(ctx, got, want):
                        yield arg.value


def _value_problem(ctx: WFContext, param: ast.TemplateParam, owner: Template,
                   value: ex.Expr | ast.TemplateInstance, lookup: Lookup) -> tuple[str, str] | None:
    """(message end, hint) when ``value`` does not fit ``param``; None when it does."""
    if param.template is not None:
        want = _resolve(ctx, owner, param.template, param)
        wanted = want.name if want is not None else "::".join(param.template)
        if not isinstance(value, ast.TemplateInstance):
            return (f"takes a nested {wanted} {{ … }}, not an expression",
                    f"write '{param.name} = {wanted} {{ … }}'")
        got = ctx.target(value)
        if isinstance(got, Template) and want is not None and not _extends(ctx, got, want):
            return (f"takes {wanted} {{ … }} (or a template extending it), not "
                    f"{got.name} {{ … }}", f"write '{param.name} = {wanted} {{ … }}'")
        return None
    if isinstance(value, ast.TemplateInstance):
        return (f"takes a value of type {type_to_notation(param.type)}, not a nested template",
                f"write '{param.name} = <{type_to_notation(param.type)}>'")
    if isinstance(param.type, ast.NamedType) and param.type.name[-1:] == ELEMENT_PATH:
        if isinstance(value, (ex.Name, ex.Member, ex.Index, ex.Str)):
            return None
        return ("takes an element path (a link, or Link::body), not an expression",
                f"write '{param.name} = Link' or '{param.name} = Link::body'")
    problem = type_problem(value, param.type, lookup)
    if problem is not None:
        return (f"is declared {type_to_notation(param.type)}, but its value is {problem}",
                f"give a value of type {type_to_notation(param.type)}")
    return None


@rule("AN3", "annotation parameters get values of their declared types")
def check_AN3_parameter_values(ctx: WFContext) -> None:
    """A template-typed parameter (``axis: template Axis``) gets a nested instantiation of that
    template or of one that extends it; a value parameter gets an expression of its type (an
    element path for ``ElementPath``). Defaults in templates are checked the same way."""
    checks: list[tuple[ast.TemplateInstance, Lookup]] = [
        (a.instance, lookup) for _, _, a, lookup in _annotations(ctx)]
    for file, t, p in _template_defaults(ctx):
        lookup = lookup_in(ctx, file, {})
        problem = _value_problem(ctx, p, t, p.default, lookup)  # type: ignore[arg-type]
        if problem is not None:
            ctx.error("AN3", p.default, f"parameter '{p.name}' of template {t.name} "
                      f"{problem[0]} (in its default)", problem[1])
        if isinstance(p.default, ast.TemplateInstance):
            checks.append((p.default, lookup))
    misplaced = {id(inst) for inst in _wrong_nested(ctx, [root for root, _ in checks])}
    for root, lookup in checks:
        for inst in _instances(root):
            template = ctx.target(inst)
            if not isinstance(template, Template) or id(inst) in misplaced:
                continue  # S1, or the instance is itself the wrong template (reported)
            params = _params(ctx, template)
            for arg in inst.args:
                if arg.name not in params:
                    continue  # AN2
                param, owner = params[arg.name]
                problem = _value_problem(ctx, param, owner, arg.value, lookup)
                if problem is not None:
                    ctx.error("AN3", arg, f"parameter '{arg.name}' of template "
                              f"{template.name} {problem[0]}", problem[1])


@rule("AN4", "template extension is acyclic and declares each parameter once")
def check_AN4_extension(ctx: WFContext) -> None:
    """Template extension (``annotation template Ray extends SensorBase``) is acyclic, and a
    template does not declare a parameter that a template it extends already declares."""
    in_cycle: set[int] = set()
    for _, t in ctx.items(Template):
        if id(t) in in_cycle:
            continue
        chain = _chain(ctx, t)
        last = _parent(ctx, chain[-1])
        if last is not None and any(last is c for c in chain):
            start = next(i for i, c in enumerate(chain) if c is last)
            cycle = chain[start:]
            in_cycle.update(id(c) for c in cycle)
            if any(c is t for c in cycle):
                path = " → ".join(c.name for c in cycle + [cycle[0]])
                ctx.error("AN4", t, f"template {t.name} extends itself ({path})",
                          "remove one 'extends' to break the cycle")
                continue
        for p in t.params:
            for ancestor in chain[1:]:
                again = next((q for q in ancestor.params if q.name == p.name), None)
                if again is not None:
                    where = Path(again.span.file).name
                    ctx.error("AN4", p, f"parameter '{p.name}' of template {t.name} is "
                              f"already declared by {ancestor.name}, which {t.name} extends "
                              f"({where}:{again.span.line})",
                              f"remove '{p.name}' from {t.name} (it is inherited)")
                    break
