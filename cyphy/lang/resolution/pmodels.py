"""Name resolution inside p-models: blocks, parts and their connections, relations and
equations that must stay inside their block (S4), ports, definitions and annotations."""

from __future__ import annotations

from typing import Any, Iterable

from cyphy import codes, progress
from cyphy import expr as ex
from cyphy.diagnostics import Span, did_you_mean
from cyphy.lang import ast
from cyphy.lang.resolution.checker import CheckerBase
from cyphy.lang.resolution.names import (
    BUILTIN_NAMES, MEMBER_WORD, Scope, all_blocks_of, indices_of, name_hint, names_in,
    path_roots, steps_of,
)
from cyphy.lang.scopes import is_constant, is_definition, is_pmodel, is_template, is_value
from cyphy.lang.workspace import Declaration


class PModelChecks(CheckerBase):
    """The p-model checks of the resolver."""

    # ------------------------------------------------------------------ p-models
    def _pmodel(self, pm: ast.PModel) -> None:
        names: dict[str, object] = {d.name: d for d in pm.declarations}
        self._unique(pm.declarations, "variable", f"p-model {pm.name}")
        self._unique([m for m in pm.members if isinstance(m, (ast.Block, ast.Part))], "block",
                     f"p-model {pm.name}")
        scope = Scope(names)
        blocks = self.all_blocks(pm)
        for d in pm.declarations:
            self._type(d.type)
            self._expr(d.value, scope)
            self.declared(d, scope)
        for i, m in enumerate(pm.members):
            progress.step(f"{pm.name}: {i + 1} of {len(pm.members)} elements")
            if isinstance(m, ast.Part):
                self._part(m, pm, scope)
            elif isinstance(m, ast.Block):
                self._block(m, pm, scope, blocks, ancestors=())
            elif isinstance(m, (ast.Equation, ast.Constraint, ast.Relation)):
                self._expr(m.expr, scope.child({n: bs[0] for n, bs in blocks.items()}))
                if not isinstance(m, ast.Relation):
                    self.predicate(m.expr, scope, f"an equation of p-model {pm.name}")
            elif isinstance(m, ast.Solution):
                self._type(m.type)
            elif isinstance(m, (ast.Pose, ast.IndexDecl)):
                self._members_exprs([m], scope)

    def _members_exprs(self, members: Iterable[object], scope: Scope) -> None:
        for m in members:
            if isinstance(m, ast.Pose):
                for f in m.fields:
                    self._expr(f.value, scope)
                    self.number(f.value, scope, f"pose field '{f.key}'")
            elif isinstance(m, ast.IndexDecl):
                for bound in (m.lower, m.upper):
                    self._expr(bound, scope)
                    self.number(bound, scope, "an index bound")

    def _part(self, part: ast.Part, pm: ast.PModel, scope: Scope) -> None:
        target = self.resolve(part, part.pmodel, is_pmodel, "p-model", part.span)
        inner = scope.child({part.index.var: part.index} if part.index else {})
        self._members_exprs(part.indices, scope)
        for m in part.members:
            if isinstance(m, ast.Pose):
                self._members_exprs([m], inner)
            elif isinstance(m, ast.Instantiation):
                self._expr(m.value, inner)
            elif isinstance(m, (ast.PartFixed, ast.PartFlexible)):
                self._part_connection(m, part, target, pm)

    def _part_connection(self, m: ast.PartFixed | ast.PartFlexible, part: ast.Part,
                         target: Declaration | None, pm: ast.PModel) -> None:
        if isinstance(target, ast.PModel):
            source = m.link if isinstance(m, ast.PartFixed) else m.joint
            kind = ast.BlockKind.LINK if isinstance(m, ast.PartFixed) else ast.BlockKind.JOINT
            found = any(b.kind is kind and b.name == source for b in self.all_blocks(
                target).get(source, []))
            if not found:
                names = [n for n, bs in self.all_blocks(target).items()
                         if any(b.kind is kind for b in bs)]
                self.error(codes.S1, f"p-model {target.name} has no {kind.value} '{source}'",
                           m.span, did_you_mean(source, names) or
                           f"name a {kind.value} of p-model {target.name}")
        self._connection_target(m.target, m.part, pm, m.span)

    def _table(self, key: Any, build: Any) -> Any:
        if key not in self._tables:
            self._tables[key] = build()
        return self._tables[key]

    def _links(self, pm: ast.PModel) -> set[str]:
        return self._table(("links", id(pm)), lambda: {
            b.name for b in pm.blocks if b.kind is ast.BlockKind.LINK})

    def all_blocks(self, pm: ast.PModel) -> dict[str, list[ast.Block]]:
        return self._table(("blocks", id(pm)), lambda: all_blocks_of(pm))

    def _connection_target(self, link: str, part_name: str | None, pm: ast.PModel,
                           span: Span) -> None:
        if part_name is None:
            links = self._links(pm)
            if link not in links:
                self.error(codes.S1, f"p-model {pm.name} has no link '{link}'", span,
                           did_you_mean(link, links) or
                           "name a link of this p-model, or 'L in P' for link L of part P")
            else:
                self._link_use(pm, link, span)
            return
        parts = {p.name: p for p in pm.parts}
        part = parts.get(part_name)
        if part is None:
            self.error(codes.S1, f"p-model {pm.name} has no part '{part_name}'", span,
                       did_you_mean(part_name, parts) or "name a part of this p-model")
            return
        self.resolution.uses.append((span, (part_name,), part))
        target = self.resolution.get(part)
        if isinstance(target, ast.PModel):
            links = self._links(target)
            if link not in links:
                self.error(codes.S1, f"part {part_name} (p-model {target.name}) has no link "
                           f"'{link}'", span, did_you_mean(link, links) or
                           f"name a link of p-model {target.name}")
            else:
                self._link_use(target, link, span)

    def _link_use(self, pm: ast.PModel, link: str, span: Span) -> None:
        """Record that ``span`` names link ``link`` of ``pm`` (for editors)."""
        for b in self.all_blocks(pm).get(link, []):
            if b.kind is ast.BlockKind.LINK:
                self.resolution.uses.append((span, (link,), b))
                return

    def _block(self, block: ast.Block, pm: ast.PModel, scope: Scope,
               blocks: dict[str, list[ast.Block]], ancestors: tuple[ast.Block, ...]) -> None:
        what = f"{block.kind.value} {block.name}"
        definition: ast.Definition | None = None
        if block.ref is not None:
            found = self.resolve(block, block.ref, is_definition(), f"{block.kind.value} "
                                 "definition", block.span, candidates_accept=is_definition(
                                     block.kind))
            definition = found if isinstance(found, ast.Definition) else None
        index_names = {i.var: i for i in block.indices}
        self._members_exprs(block.indices, scope)
        def_members: list[object] = []
        if definition is not None:
            def_members.extend(definition.members)
        for d in block.definitions:
            def_members.extend(d.members)
        own_decls = [m for m in def_members if isinstance(m, ast.VarDecl)]
        own_decls += list(block.declarations)
        own = {d.name: d for d in own_decls}
        inner = scope.child({**index_names, **own})
        self._unique([m for m in block.members if isinstance(m, ast.Block)], "block", what)
        self._unique([d for d in block.declarations]
                     + [m for d in block.definitions for m in d.members
                        if isinstance(m, ast.VarDecl)], "variable", what)
        block_names = self._table(("names", id(pm)), lambda: {n: bs[0] for n, bs in
                                                               blocks.items()})
        # S4: a definition's equations see its own declarations, the index variables of
        # the enclosing blocks and package-level constants and functions, nothing else.
        visible_indices = {**indices_of(ancestors), **index_names}
        for d in block.definitions:
            self._definition_members(d.members, Scope(visible_indices), what,
                                     outer=inner.child(block_names), pm=pm)
        for m in block.members:
            if isinstance(m, ast.Pose):
                self._members_exprs([m], scope.child(index_names).child(own))
            elif isinstance(m, ast.Block):
                self._block(m, pm, inner, blocks, ancestors + (block,))
            elif isinstance(m, ast.FixedConnection):
                self._connection_target(m.target, m.part, pm, m.span)
            elif isinstance(m, ast.FlexibleConnection):
                self._connection_target(m.target, m.part, pm, m.span)
            elif isinstance(m, ast.Relation):
                self._relation(m, inner, blocks)
            elif isinstance(m, ast.Annotation):
                self._template_instance(m.instance, inner, pm)
            elif isinstance(m, ast.Instantiation):
                self._expr(m.value, scope.child(index_names))
                if definition is not None and m.name not in {
                        d.name for d in definition.members if isinstance(d, ast.VarDecl)}:
                    consts = [d.name for d in definition.members if is_constant(d)]
                    self.error(codes.S1, f"{definition.kind.value} definition {definition.name}"
                               f" has no constant '{m.name}' to instantiate", m.span,
                               did_you_mean(m.name, consts) or
                               f"instantiate one of: {', '.join(consts) or '(no constants)'}")
            elif isinstance(m, (ast.Equation, ast.Constraint)):
                self._expr(m.expr, inner.child(block_names))
                self.predicate(m.expr, inner, f"an equation of {what}")
            elif isinstance(m, ast.VarDecl):
                self._type(m.type)
                self._expr(m.value, inner)
                self.declared(m, inner)

    def _relation(self, rel: ast.Relation, scope: Scope, blocks: dict[str, list[ast.Block]]
                  ) -> None:
        """Relations label containment: their names are the block's own variables, or ports
        of blocks of the p-model written ``Block.port``."""
        for e in path_roots(rel.expr):
            steps = steps_of(e)
            if steps is None:
                continue
            first = steps[0][0]
            if scope.find(first) is not None or first in BUILTIN_NAMES:
                continue
            if self.scopes.lookup(self.file, (first,), is_value):
                continue
            if first in blocks:
                if len(steps) >= 2:
                    self._port(blocks[first][0], steps[1][0], steps[1][1])
                continue
            hint = name_hint(first, scope.all_names() | set(blocks)) or \
                "name a variable of this block, or Block.port of a block of the p-model"
            self.error(codes.S1, f"unknown name '{first}' in relation", steps[0][1], hint)

    def ports_of(self, block: ast.Block) -> dict[str, ast.VarDecl] | None:
        """The variables a block declares (through its definition); None when unknown."""
        members: list[object] = list(block.declarations)
        for d in block.definitions:
            members.extend(d.members)
        if block.ref is not None:
            target = self.resolution.get(block)
            if target is None:
                target_list = self.scopes.lookup(self.file, block.ref, is_definition())
                target = target_list[0] if target_list else None
            if not isinstance(target, ast.Definition):
                return None
            members.extend(target.members)
        return {m.name: m for m in members if isinstance(m, ast.VarDecl)}

    def _port(self, block: ast.Block, port: str, span: Span) -> None:
        ports = self.ports_of(block)
        if ports is None or port in ports:
            return
        self.error(codes.S1, f"{block.kind.value} {block.name} has no variable '{port}'", span,
                   did_you_mean(port, ports) or
                   f"its variables are: {', '.join(sorted(ports)) or '(none)'}")

    def _definition_members(self, members: Iterable[object], scope: Scope, what: str,
                            outer: Scope | None, pm: ast.PModel | None = None) -> None:
        members = list(members)
        decls = [m for m in members if isinstance(m, ast.VarDecl)]
        restricted = scope.child({d.name: d for d in decls})
        # Geometry, inertia and annotation values may use the p-model's constants; only
        # equations are confined to the block (S4).
        own = outer.child(restricted.names) if outer is not None else restricted
        for d in decls:
            self._type(d.type)
            self._expr(d.value, own)
            self.declared(d, own)
        for m in members:
            if isinstance(m, (ast.Equation, ast.Constraint)):
                self._expr(m.expr, own, restricted=restricted, where=what)
                self.predicate(m.expr, own, f"an equation of {what}")
            elif isinstance(m, ast.Annotation):
                self._template_instance(m.instance, own, pm)
            elif not isinstance(m, ast.VarDecl):
                for e in ast.expressions_in(m):
                    self._expr(e, own)
                    if isinstance(m, (ast.Shape, ast.Inertial, ast.Bounce, ast.LaserRetro)):
                        self.number(e, own, f"a value of the {MEMBER_WORD[type(m)]} of {what}")
        self._unique(decls, "variable", what)

    def _template_instance(self, inst: ast.TemplateInstance, scope: Scope,
                           pm: ast.PModel | None = None) -> None:
        self.resolve(inst, inst.template, is_template, "annotation template", inst.span)
        self._unique(inst.args, "parameter", f"annotation {'::'.join(inst.template)}")
        for arg in inst.args:
            if isinstance(arg.value, ast.TemplateInstance):
                self._template_instance(arg.value, scope, pm)
            else:
                self._annotation_value(arg.value, scope, pm)

    def _annotation_value(self, value: ex.Expr, scope: Scope, pm: ast.PModel | None) -> None:
        """Values are expressions over the block's constants, or element paths
        (``collision = Rod::my_body``)."""
        blocks = self.all_blocks(pm) if pm is not None else {}
        for node in names_in(value):
            if pm is not None and all(p in blocks for p in node.parts):
                continue
            self._name(node, scope, None, "")
