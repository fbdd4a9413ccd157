"""The rules of platform mappings and d-models: statements, interfaces, platforms, modules,
controllers, state machines and transitions."""

from __future__ import annotations

from typing import Any

from lark import Token

from cyphy import codes
from cyphy import expr as ex
from cyphy.diagnostics import Diagnostic
from cyphy.lang import ast
from cyphy.lang.builder.base import BuilderBase, Tagged, name_of


class DModelRules(BuilderBase):
    """Methods of the mapping, d-model and state-machine rules."""

    def platform_mapping(self, meta: Any, c: list[Any]) -> ast.PlatformMapping:
        name, dmodel, pmodel, *members = c
        return ast.PlatformMapping(
            name_of(name), dmodel.parts, pmodel.parts, self._flat(members),
            span=self._span(meta), dmodel_span=dmodel.span, pmodel_span=pmodel.span,
        )

    def operation_mapping(self, meta: Any, c: list[Any]) -> ast.OperationMapping:
        return ast.OperationMapping(name_of(c[0]), self._flat(c[1:]), span=self._span(meta))

    def _event_mapping(self, direction: str, meta: Any, c: list[Any]) -> ast.EventMapping:
        name, param, *members = c
        return ast.EventMapping(
            direction, name_of(name), param.value if param else None, self._flat(members),
            span=self._span(meta), param_span=param.span if param else None,
        )

    def input_event_mapping(self, meta: Any, c: list[Any]) -> ast.EventMapping:
        return self._event_mapping("input", meta, c)

    def output_event_mapping(self, meta: Any, c: list[Any]) -> ast.EventMapping:
        return self._event_mapping("output", meta, c)

    def variable_mapping(self, meta: Any, c: list[Any]) -> ast.VariableMapping:
        return ast.VariableMapping(name_of(c[0]), self._flat(c[1:]), span=self._span(meta))

    def event_param(self, meta: Any, c: list[Token]) -> Tagged:
        return Tagged("param", name_of(c[0]), self._span(meta))

    def predicate(self, meta: Any, c: list[Any]) -> ast.Predicate:
        return ast.Predicate(c[0], span=self._span(meta))

    def action(self, meta: Any, c: list[Any]) -> ast.Action:
        return ast.Action(c[0], span=self._span(meta))

    def statement(self, meta: Any, c: list[Any]) -> tuple[ast.Statement, ...]:
        return tuple(c)

    def assignment(self, meta: Any, c: list[Any]) -> ast.Assign:
        return ast.Assign(c[0], c[1], span=self._span(meta))

    def call_statement(self, meta: Any, c: list[Any]) -> ast.Statement:
        call, span = c[0], self._span(meta)
        if (isinstance(call, ex.Call) and isinstance(call.func, ex.Name)
                and call.func.parts == ("wait",) and len(call.args) == 1):
            return ast.WaitStatement(call.args[0], span=span)
        return ast.CallStatement(call, span=span)

    def skip_statement(self, meta: Any, c: list[Any]) -> ast.SkipStatement:
        return ast.SkipStatement(span=self._span(meta))

    # ----- d-models
    def interface(self, meta: Any, c: list[Any]) -> ast.Interface:
        return ast.Interface(name_of(c[0]), self._flat(c[1:]), span=self._span(meta))

    def event_decl(self, meta: Any, c: list[Any]) -> ast.EventDecl:
        return ast.EventDecl(name_of(c[0]), c[1], span=self._span(meta))

    def operation_sig(self, meta: Any, c: list[Any]) -> ast.OperationSig:
        return ast.OperationSig(name_of(c[0]), self._flat(c[1:]), span=self._span(meta))

    def clock_decl(self, meta: Any, c: list[Token]) -> ast.ClockDecl:
        return ast.ClockDecl(name_of(c[0]), span=self._span(meta))

    def robotic_platform(self, meta: Any, c: list[Any]) -> ast.RoboticPlatform:
        return ast.RoboticPlatform(name_of(c[0]), self._flat(c[1:]), span=self._span(meta))

    def uses(self, meta: Any, c: list[Any]) -> ast.InterfaceUse:
        return ast.InterfaceUse("uses", c[0].parts, span=self._span(meta))

    def provides(self, meta: Any, c: list[Any]) -> ast.InterfaceUse:
        return ast.InterfaceUse("provides", c[0].parts, span=self._span(meta))

    def requires(self, meta: Any, c: list[Any]) -> ast.InterfaceUse:
        return ast.InterfaceUse("requires", c[0].parts, span=self._span(meta))

    def module(self, meta: Any, c: list[Any]) -> ast.Module:
        return ast.Module(name_of(c[0]), self._flat(c[1:]), span=self._span(meta))

    def cycle_def(self, meta: Any, c: list[Any]) -> ast.CycleDef:
        return ast.CycleDef(c[0], span=self._span(meta))

    def node_ref_kind(self, meta: Any, c: list[Token]) -> str:
        return str(c[0])

    def node_ref(self, meta: Any, c: list[Any]) -> ast.NodeRef:
        return ast.NodeRef(c[0], name_of(c[1]), c[2].parts, span=self._span(meta))

    def connection(self, meta: Any, c: list[Any]) -> ast.Connection:
        a, ae, b, be, flag = c
        return ast.Connection(name_of(a), name_of(ae), name_of(b), name_of(be), flag,
                              span=self._span(meta))

    def connection_flag(self, meta: Any, c: list[Token]) -> str:
        return name_of(c[0])

    # ----- behaviour: controllers, state machines, operation definitions
    def controller(self, meta: Any, c: list[Any]) -> ast.Controller:
        return ast.Controller(name_of(c[0]), self._flat(c[1:]), span=self._span(meta))

    def machine_ref_kind(self, meta: Any, c: list[Token]) -> str:
        return str(c[0])

    def machine_ref(self, meta: Any, c: list[Any]) -> ast.MachineRef:
        return ast.MachineRef(c[0], name_of(c[1]), c[2].parts, span=self._span(meta))

    def state_machine(self, meta: Any, c: list[Any]) -> ast.StateMachine:
        return ast.StateMachine(name_of(c[0]), self._flat(c[1:]), span=self._span(meta))

    def operation_def(self, meta: Any, c: list[Any]) -> ast.StateMachine:
        name, *rest = c
        params = tuple(x for x in rest if isinstance(x, ast.Param))
        members = self._flat(x for x in rest if not isinstance(x, ast.Param))
        return ast.StateMachine(name_of(name), members, "operation", params,
                                span=self._span(meta))

    def terminates(self, meta: Any, c: list[Any]) -> ast.Terminates:
        return ast.Terminates(span=self._span(meta))

    def context_kind(self, meta: Any, c: list[Token]) -> str:
        return str(c[0])

    def context(self, meta: Any, c: list[Any]) -> ast.Context:
        return ast.Context(c[0], tuple(c[1:]), span=self._span(meta))

    def _machine_node(self, kind: str, meta: Any, c: list[Token]) -> ast.MachineNode:
        return ast.MachineNode(kind, name_of(c[0]), span=self._span(meta))

    def initial_node(self, meta: Any, c: list[Token]) -> ast.MachineNode:
        return self._machine_node("initial", meta, c)

    def junction_node(self, meta: Any, c: list[Token]) -> ast.MachineNode:
        return self._machine_node("junction", meta, c)

    def final_node(self, meta: Any, c: list[Token]) -> ast.MachineNode:
        return self._machine_node("final", meta, c)

    def state(self, meta: Any, c: list[Any]) -> ast.State:
        return ast.State(name_of(c[0]), self._flat(c[1:]), span=self._span(meta))

    def action_kind(self, meta: Any, c: list[Token]) -> str:
        return str(c[0])

    def state_action(self, meta: Any, c: list[Any]) -> ast.StateAction:
        return ast.StateAction(c[0], c[1], span=self._span(meta))

    def transition_from(self, meta: Any, c: list[Token]) -> Tagged:
        return Tagged("from", name_of(c[0]), self._tok_span(c[0]))

    def transition_to(self, meta: Any, c: list[Token]) -> Tagged:
        return Tagged("to", name_of(c[0]), self._tok_span(c[0]))

    def exec_trigger(self, meta: Any, c: list[Any]) -> Tagged:
        return Tagged("exec", True, self._span(meta))

    def transition_trigger(self, meta: Any, c: list[Any]) -> Tagged:
        return Tagged("trigger", c[0], self._span(meta))

    def transition_condition(self, meta: Any, c: list[Any]) -> Tagged:
        return Tagged("condition", c[0], self._span(meta))

    def transition(self, meta: Any, c: list[Any]) -> ast.Transition:
        name, *members = c
        span = self._span(meta)
        where = f"transition {name_of(name)}"
        parts: dict[str, Any] = {}
        for m in members:
            tag, value, mspan = ((m.tag, m.value, m.span) if isinstance(m, Tagged)
                                 else ("action", m.statements, m.span))
            if tag in parts:
                self._duplicate(tag, where, mspan)
                continue
            parts[tag] = (value, mspan)
        value = {k: v for k, (v, _) in parts.items()}
        return ast.Transition(
            name_of(name), value.get("from"), value.get("to"), bool(value.get("exec")),
            value.get("trigger"), value.get("condition"), value.get("action"), span=span,
            source_span=parts["from"][1] if "from" in parts else None,
            target_span=parts["to"][1] if "to" in parts else None)

    def send_statement(self, meta: Any, c: list[Any]) -> ast.SendStatement:
        span = self._span(meta)
        if not isinstance(c[0], ex.PlatformRef):
            self.diagnostics.append(Diagnostic(
                codes.SYNTAX, "only an output event of the platform can be sent with '!'", span,
                "write $event!value"))
        return ast.SendStatement(c[0], c[1], span=span)

    def clock_reset(self, meta: Any, c: list[Token]) -> ast.ClockReset:
        return ast.ClockReset(name_of(c[0]), span=self._span(meta))

    def exec_statement(self, meta: Any, c: list[Any]) -> ast.ExecStatement:
        return ast.ExecStatement(span=self._span(meta))
