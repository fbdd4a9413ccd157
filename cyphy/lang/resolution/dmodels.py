"""Name resolution inside d-models (interfaces, platforms, controllers, state machines,
modules) and platform mappings, and the parts that contain their own p-model (S5)."""

from __future__ import annotations

from graphlib import CycleError, TopologicalSorter
from cyphy import codes
from cyphy.diagnostics import did_you_mean
from cyphy.lang import ast
from cyphy.lang.resolution.checker import CheckerBase
from cyphy.lang.resolution.mappings import MappingChecker
from cyphy.lang.resolution.names import Scope
from cyphy.lang.scopes import is_interface, is_machine, is_node


class DModelChecks(CheckerBase):
    """The d-model checks of the resolver."""

    def _mapping(self, mapping: ast.PlatformMapping) -> None:
        MappingChecker(self, mapping).run()

    # ------------------------------------------------------------------ d-models
    def _interface(self, i: ast.Interface) -> None:
        self._unique(list(i.events) + list(i.operations) + list(i.variables), "member",
                     f"interface {i.name}")
        for m in i.members:
            if isinstance(m, ast.EventDecl):
                self._type(m.type)
            elif isinstance(m, ast.OperationSig):
                self._unique(m.params, "parameter", f"operation {m.name}")
                for p in m.params:
                    self._type(p.type)
            elif isinstance(m, ast.VarDecl):
                self._type(m.type)

    def _platform(self, p: ast.RoboticPlatform) -> None:
        for use in p.interface_uses:
            self.resolve(use, use.interface, is_interface, "interface", use.span)
        for m in p.members:
            if isinstance(m, ast.EventDecl):
                self._type(m.type)
            elif isinstance(m, ast.OperationSig):
                for prm in m.params:
                    self._type(prm.type)
            elif isinstance(m, ast.VarDecl):
                self._type(m.type)

    def _controller(self, c: ast.Controller) -> None:
        nodes: dict[str, object] = {c.name: c}
        nodes.update({m.name: m for m in c.members
                      if isinstance(m, (ast.MachineRef, ast.StateMachine))})
        for m in c.members:
            if isinstance(m, ast.InterfaceUse):
                self.resolve(m, m.interface, is_interface, "interface", m.span)
            elif isinstance(m, ast.MachineRef):
                self.resolve(m, m.target, is_machine, "state machine or operation", m.span)
            elif isinstance(m, ast.StateMachine):
                self._machine(m)
            elif isinstance(m, ast.VarDecl):
                self._type(m.type)
        for m in c.members:
            if isinstance(m, ast.Connection):
                self._connection_events(m, nodes)

    def _machine(self, stm: ast.StateMachine) -> None:
        """The interfaces and types a machine names; its states, transitions and expressions
        are checked by the machine rules (``cyphy.wellformed.machines``)."""
        for p in stm.params:
            self._type(p.type)
        for use in stm.interface_uses:
            self.resolve(use, use.interface, is_interface, "interface", use.span)
        self._unique_nodes(stm.members, f"{stm.kind if stm.kind == 'operation' else 'machine'} "
                           f"{stm.name}")
        self._unique([m for m in stm.members if isinstance(m, (ast.VarDecl, ast.ClockDecl))],
                     "variable", f"machine {stm.name}")
        stack: list[object] = list(stm.members)
        while stack:
            m = stack.pop()
            if isinstance(m, ast.VarDecl):
                self._type(m.type)
            elif isinstance(m, ast.State):
                self._unique_nodes(m.members, f"state {m.name}")
                stack.extend(m.members)

    def _unique_nodes(self, members: tuple[object, ...], where: str) -> None:
        """S2 in one scope of a machine: two states (or junctions) of one name make every
        transition to that name ambiguous; two transitions of one name, every reference."""
        self._unique([m for m in members if isinstance(m, (ast.State, ast.MachineNode))],
                     "state or junction", where)
        self._unique([m for m in members if isinstance(m, ast.Transition)], "transition", where)

    def _module(self, mod: ast.Module) -> None:
        nodes: dict[str, object] = {}
        for m in mod.members:
            if isinstance(m, ast.RoboticPlatform):
                self._platform(m)
                nodes[m.name] = m
            elif isinstance(m, ast.NodeRef):
                self.resolve(m, m.target, is_node, "controller or platform", m.span)
                nodes[m.name] = m
            elif isinstance(m, (ast.Controller, ast.StateMachine)):
                nodes[m.name] = m
            elif isinstance(m, ast.CycleDef):
                cycle = ast.Param("cycle", ast.PrimitiveType("nat"), span=m.span)
                self._expr(m.expr, Scope({"cycle": cycle}))
                self.predicate(m.expr, Scope({"cycle": cycle}), "cycleDef")
        for m in mod.members:
            if isinstance(m, ast.Connection):
                for node in (m.source, m.target):
                    if node not in nodes:
                        self.error(codes.S1, f"module {mod.name} has no node '{node}'", m.span,
                                   did_you_mean(node, nodes) or
                                   "connect the platform or a controller of this module")
                self._connection_events(m, nodes)

    def _connection_events(self, c: ast.Connection, nodes: dict[str, object]) -> None:
        """S1 for the events a connection names: ``connection P on near to ctrl on near``
        names an event of each end (of its own declarations or of an interface it uses,
        requires or provides). A misspelt one silently connects nothing: the controller
        would never see the event."""
        for node, event in ((c.source, c.source_event), (c.target, c.target_event)):
            events = self._events_of(nodes.get(node))
            if events is not None and event not in events:
                self.error(codes.S1, f"'{node}' has no event '{event}' for connection "
                           f"{c.source} on {c.source_event} to {c.target} on "
                           f"{c.target_event}", c.span,
                           did_you_mean(event, events) or
                           f"its events are: {', '.join(sorted(events)) or '(none)'}")

    def _events_of(self, node: object) -> set[str] | None:
        """The events of a connection's end (a platform, a controller, a machine, or a
        reference to one), or None when it cannot be known (an unresolved reference)."""
        if isinstance(node, (ast.NodeRef, ast.MachineRef)):
            node = self.resolution.get(node)
        if not isinstance(node, (ast.RoboticPlatform, ast.Controller, ast.StateMachine)):
            return None
        events = {e.name for e in node.members if isinstance(e, ast.EventDecl)}
        uses = node.interface_uses if isinstance(node, (ast.RoboticPlatform,
                                                        ast.StateMachine)) else \
            tuple(u for u in node.members if isinstance(u, ast.InterfaceUse))
        for use in uses:
            found = self.scopes.lookup(self.file, use.interface, is_interface)
            if not found:
                return None
            events.update(e.name for i in found if isinstance(i, ast.Interface)
                          for e in i.events)
        return events

    # ------------------------------------------------------------------ S5 part cycles
    def _part_cycles(self) -> None:
        """S5: a part must not (transitively) contain its own p-model. ``graphlib`` finds a
        cycle; its first edge is reported and removed until no cycle is left."""

        edges: dict[tuple[int, int], ast.Part] = {}
        names: dict[int, str] = {}
        for file in self.ws.files.values():
            for item in file.items:
                if isinstance(item, ast.PModel):
                    names[id(item)] = item.name
                    for part in item.parts:
                        target = self.resolution.get(part)
                        if isinstance(target, ast.PModel):
                            edges.setdefault((id(item), id(target)), part)
        while edges:
            graph: dict[int, set[int]] = {}
            for source, target in edges:
                graph.setdefault(source, set()).add(target)
            try:
                TopologicalSorter(graph).prepare()
                return
            except CycleError as err:
                cycle = list(reversed(err.args[1]))  # graphlib lists it against the edges
                part = edges.pop((cycle[0], cycle[1]))
                chain = " → ".join(names[n] for n in cycle)
                self.error(codes.S5, f"part {part.name} makes a p-model contain itself "
                           f"({chain})", part.span,
                           "a part must not (transitively) contain its own p-model")
