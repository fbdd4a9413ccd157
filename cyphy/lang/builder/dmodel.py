"""The rules of platform mappings and d-models: statements, interfaces, platforms, modules,
controllers, state machines and transitions."""

from __future__ import annotations

from typing import Any

from lark import Token

from cyphy import codes
from cyphy import expr as ex
from cyphy.diagnostics import Diagnostic
from cyphy.lang import ast
from cyphy.lang.builder.base import BuilderBase, Tagged, name_of, text_of
from cyphy.lang.reductions import Pos


class DModelRules(BuilderBase):
    """Methods of the mapping, d-model and state-machine rules."""

    def platform_mapping(self, pos: Pos, c: list[Any]) -> ast.PlatformMapping:
        name, dmodel, pmodel, *members = c
        return ast.PlatformMapping(
            name_of(name), dmodel.parts, pmodel.parts, self._flat(members),
            span=self._span(pos), dmodel_span=dmodel.span, pmodel_span=pmodel.span,
        )

    def operation_mapping(self, pos: Pos, c: list[Any]) -> ast.OperationMapping:
        return ast.OperationMapping(name_of(c[0]), self._flat(c[1:]), span=self._span(pos))

    def _event_mapping(self, direction: str, pos: Pos, c: list[Any]) -> ast.EventMapping:
        name, param, *members = c
        return ast.EventMapping(
            direction, name_of(name), param.value if param else None, self._flat(members),
            span=self._span(pos), param_span=param.span if param else None,
        )

    def input_event_mapping(self, pos: Pos, c: list[Any]) -> ast.EventMapping:
        return self._event_mapping("input", pos, c)

    def output_event_mapping(self, pos: Pos, c: list[Any]) -> ast.EventMapping:
        return self._event_mapping("output", pos, c)

    def variable_mapping(self, pos: Pos, c: list[Any]) -> ast.VariableMapping:
        return ast.VariableMapping(name_of(c[0]), self._flat(c[1:]), span=self._span(pos))

    def event_param(self, pos: Pos, c: list[Token]) -> Tagged:
        return Tagged("param", name_of(c[0]), self._span(pos))

    def predicate(self, pos: Pos, c: list[Any]) -> ast.Predicate:
        return ast.Predicate(c[0], span=self._span(pos))

    def action(self, pos: Pos, c: list[Any]) -> ast.Action:
        return ast.Action(c[0], span=self._span(pos))

    def statement(self, pos: Pos, c: list[Any]) -> tuple[ast.Statement, ...]:
        return tuple(c)

    def assignment(self, pos: Pos, c: list[Any]) -> ast.Assign:
        return ast.Assign(c[0], c[1], span=self._span(pos))

    def call_statement(self, pos: Pos, c: list[Any]) -> ast.Statement:
        call, span = c[0], self._span(pos)
        if (isinstance(call, ex.Call) and isinstance(call.func, ex.Name)
                and call.func.parts == ("wait",) and len(call.args) == 1):
            return ast.WaitStatement(call.args[0], span=span)
        return ast.CallStatement(call, span=span)

    def skip_statement(self, pos: Pos, c: list[Any]) -> ast.SkipStatement:
        return ast.SkipStatement(span=self._span(pos))

    # ----- d-models
    def interface(self, pos: Pos, c: list[Any]) -> ast.Interface:
        return ast.Interface(name_of(c[0]), self._flat(c[1:]), span=self._span(pos))

    def event_decl(self, pos: Pos, c: list[Any]) -> ast.EventDecl:
        return ast.EventDecl(name_of(c[0]), c[1], span=self._span(pos))

    def operation_sig(self, pos: Pos, c: list[Any]) -> ast.OperationSig:
        return ast.OperationSig(name_of(c[0]), self._flat(c[1:]), span=self._span(pos))

    def clock_decl(self, pos: Pos, c: list[Token]) -> ast.ClockDecl:
        return ast.ClockDecl(name_of(c[0]), span=self._span(pos))

    def robotic_platform(self, pos: Pos, c: list[Any]) -> ast.RoboticPlatform:
        return ast.RoboticPlatform(name_of(c[0]), self._flat(c[1:]), span=self._span(pos))

    def uses(self, pos: Pos, c: list[Any]) -> ast.InterfaceUse:
        return ast.InterfaceUse("uses", c[0].parts, span=self._span(pos))

    def provides(self, pos: Pos, c: list[Any]) -> ast.InterfaceUse:
        return ast.InterfaceUse("provides", c[0].parts, span=self._span(pos))

    def requires(self, pos: Pos, c: list[Any]) -> ast.InterfaceUse:
        return ast.InterfaceUse("requires", c[0].parts, span=self._span(pos))

    def module(self, pos: Pos, c: list[Any]) -> ast.Module:
        return ast.Module(name_of(c[0]), self._flat(c[1:]), span=self._span(pos))

    def cycle_def(self, pos: Pos, c: list[Any]) -> ast.CycleDef:
        return ast.CycleDef(c[0], span=self._span(pos))

    def node_ref_kind(self, pos: Pos, c: list[Token]) -> str:
        return text_of(c[0])

    def node_ref(self, pos: Pos, c: list[Any]) -> ast.NodeRef:
        return ast.NodeRef(c[0], name_of(c[1]), c[2].parts, span=self._span(pos))

    def connection(self, pos: Pos, c: list[Any]) -> ast.Connection:
        a, ae, b, be, flag = c
        return ast.Connection(name_of(a), name_of(ae), name_of(b), name_of(be), flag,
                              span=self._span(pos))

    def connection_flag(self, pos: Pos, c: list[Token]) -> str:
        return name_of(c[0])

    # ----- behaviour: controllers, state machines, operation definitions
    def controller(self, pos: Pos, c: list[Any]) -> ast.Controller:
        return ast.Controller(name_of(c[0]), self._flat(c[1:]), span=self._span(pos))

    def machine_ref_kind(self, pos: Pos, c: list[Token]) -> str:
        return text_of(c[0])

    def machine_ref(self, pos: Pos, c: list[Any]) -> ast.MachineRef:
        return ast.MachineRef(c[0], name_of(c[1]), c[2].parts, span=self._span(pos))

    def state_machine(self, pos: Pos, c: list[Any]) -> ast.StateMachine:
        return ast.StateMachine(name_of(c[0]), self._flat(c[1:]), span=self._span(pos))

    def operation_def(self, pos: Pos, c: list[Any]) -> ast.StateMachine:
        name, *rest = c
        params = tuple(x for x in rest if isinstance(x, ast.Param))
        members = self._flat(x for x in rest if not isinstance(x, ast.Param))
        return ast.StateMachine(name_of(name), members, "operation", params,
                                span=self._span(pos))

    def terminates(self, pos: Pos, c: list[Any]) -> ast.Terminates:
        return ast.Terminates(span=self._span(pos))

    def context_kind(self, pos: Pos, c: list[Token]) -> str:
        return text_of(c[0])

    def context(self, pos: Pos, c: list[Any]) -> ast.Context:
        return ast.Context(c[0], tuple(c[1:]), span=self._span(pos))

    def _machine_node(self, kind: str, pos: Pos, c: list[Token]) -> ast.MachineNode:
        return ast.MachineNode(kind, name_of(c[0]), span=self._span(pos))

    def initial_node(self, pos: Pos, c: list[Token]) -> ast.MachineNode:
        return self._machine_node("initial", pos, c)

    def junction_node(self, pos: Pos, c: list[Token]) -> ast.MachineNode:
        return self._machine_node("junction", pos, c)

    def final_node(self, pos: Pos, c: list[Token]) -> ast.MachineNode:
        return self._machine_node("final", pos, c)

    def state(self, pos: Pos, c: list[Any]) -> ast.State:
        return ast.State(name_of(c[0]), self._flat(c[1:]), span=self._span(pos))

    def action_kind(self, pos: Pos, c: list[Token]) -> str:
        return text_of(c[0])

    def state_action(self, pos: Pos, c: list[Any]) -> ast.StateAction:
        return ast.StateAction(c[0], c[1], span=self._span(pos))

    def transition_from(self, pos: Pos, c: list[Token]) -> Tagged:
        return Tagged("from", name_of(c[0]), self._tok_span(c[0]))

    def transition_to(self, pos: Pos, c: list[Token]) -> Tagged:
        return Tagged("to", name_of(c[0]), self._tok_span(c[0]))

    def exec_trigger(self, pos: Pos, c: list[Any]) -> Tagged:
        return Tagged("exec", True, self._span(pos))

    def transition_trigger(self, pos: Pos, c: list[Any]) -> Tagged:
        return Tagged("trigger", c[0], self._span(pos))

    def transition_condition(self, pos: Pos, c: list[Any]) -> Tagged:
        return Tagged("condition", c[0], self._span(pos))

    def transition(self, pos: Pos, c: list[Any]) -> ast.Transition:
        name, *members = c
        span = self._span(pos)
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

    def send_statement(self, pos: Pos, c: list[Any]) -> ast.SendStatement:
        span = self._span(pos)
        if not isinstance(c[0], ex.PlatformRef):
            self.diagnostics.append(Diagnostic(
                codes.SYNTAX, "only an output event of the platform can be sent with '!'", span,
                "write $event!value"))
        return ast.SendStatement(c[0], c[1], span=span)

    def clock_reset(self, pos: Pos, c: list[Token]) -> ast.ClockReset:
        return ast.ClockReset(name_of(c[0]), span=self._span(pos))

    def exec_statement(self, pos: Pos, c: list[Any]) -> ast.ExecStatement:
        return ast.ExecStatement(span=self._span(pos))
