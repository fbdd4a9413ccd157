"""An Isabelle session in the axiomatic dialect (isabelle-utp/Ax_CyPhyCircus).

The layout follows ``../shared/spec/isabelle.md`` section 2.5: the theory imports
``Axiomatic_CyPhyCircus.Ax_CyPhyCircus`` (no prelude), declares ``cycle`` and ``tscale`` as
``consts`` with the constraints as axioms, the channels as one ``chantype``, the state as
``alphabet``s, ``WaitT`` by primitive recursion on the number of ``tock`` events, and one
``definition`` of type ``(Chan, State) cyphyaction`` per action, with no closure lemmas (the
dialect has no healthiness conditions). Everything but the notation is shared with the
primary dialect (:mod:`cyphy.backends.isabelle.theory`): names, order, constants, caveats.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

from cyphy import expr as ex
from cyphy.semantics.dynamics.evolve_odes import EvolveOdes
from cyphy.backends.isabelle.terms import HOL_FUNCTIONS, UnsupportedNode
from cyphy.backends.isabelle.ax_terms import AX_RESERVED, AxiomaticPrinter
from cyphy.backends.isabelle.names import is_identifier
from cyphy.backends.isabelle.theory import (IsabelleError, IsabelleSession,
                                            _dprocess_actions, _environment, _names_table, _theory_context,
                                            scalar_program, symbols_of)
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.names import NameTable, identifier
from cyphy.semantics.circus.walk import action_nodes, map_action
from cyphy.semantics.circus.rules import REGISTER_CHANNELS, TIMER
from cyphy.semantics.scalarise.process import initialised

PARENT = "Axiomatic_CyPhyCircus"
PARENT_IMPORT = '"Axiomatic_CyPhyCircus.Ax_CyPhyCircus"'
WAIT = "WaitT"


def generate_ax_session(program: c.Program, table: NameTable, odes: EvolveOdes | None,
                        system_name: str | None = None,
                        elements: tuple[str, ...] = ()) -> IsabelleSession:
    """The session folder's files for ``program``; ``odes`` are Evolve's explicit ODEs
    (None only for a program without an evolution). Raises :class:`IsabelleError` when a
    construct has no counterpart in the dialect."""
    if system_name is not None and not is_identifier(system_name):
        raise IsabelleError(f"the system name '{system_name}' is not an identifier")
    program = scalar_program(program, evolving_as_state=False).program
    if odes is not None:  # the reduction's states start at 0 or their declared values
        states = [o.variable for o in odes.odes if o.kind == "state"]
        pm = program.pmodel
        program = replace(program, pmodel=replace(pm, actions=tuple(
            initialised(d, states, pm.initial, pm.ranges) for d in pm.actions),
            main=_outputs_tied(pm.main, odes)))  # and the world inputs' rates chosen
    pm = program.pmodel
    symbols = symbols_of(program, AX_RESERVED)
    names = symbols.names
    names.add(WAIT)
    added = list(odes.added) + list(odes.rates) if odes is not None else []
    for name in added:
        names.add(name)
    symbols = replace(symbols, state=symbols.state | frozenset(added),
                      functions={**HOL_FUNCTIONS, **symbols.functions})
    printer = AxiomaticPrinter(symbols, odes.odes if odes is not None else None)
    prefix = identifier(pm.name)
    theory = f"{prefix}_AxCyPhyCircus"
    session = f"{prefix}_AxCyPhy"
    dm = program.dmodel if isinstance(program.dmodel, c.BasicProcess) else None
    system_state = names.add(f"{program.system.name}State") if dm is not None else None
    action_type = (f"({names[f'{prefix}_chan']}, "
                   f"{system_state or names[pm.state.name]}) cyphyaction")
    try:
        context = _theory_context(program, pm, printer, action_type)
    except UnsupportedNode as err:
        raise IsabelleError(str(err)) from None
    defs = {d.name: d for d in pm.actions}
    defs["MainAction"] = c.ActionDef("MainAction", (), pm.main)
    defs.update(_dprocess_actions(program))
    uses_wait = any(isinstance(n, c.Wait) for d in defs.values() for n in action_nodes(d.body))
    evolving = {names[d.name] for d in defs.values()
                if any(isinstance(n, c.Evolution) for n in action_nodes(d.body))}
    for d in context["definitions"]:
        if d.name in evolving and odes is not None:
            d.caveat = _evolve_note(odes, elements)
    context.update(
        theory=theory, parent_import=PARENT_IMPORT, prefix=prefix,
        mapping=program.system.name, dmodel=program.dmodel.name,
        system=system_name or program.system.name, pmodel=pm.name,
        chan_type=names[f"{prefix}_chan"], action_type=action_type,
        wait=names[WAIT] if uses_wait else None,
        uses_fmod=any(isinstance(n, ex.BinOp) and n.op == "%" for n in c.walk(pm)),
        tock=symbols.constructors.get(("tock", None), "tock"),
        added=[{"name": names[a], "type": "real"} for a in added],
        added_note=(f"{', '.join(names[a] for a in added)}: evolving variables that no state "
                    "field holds (device locals, integrals); Evolve's explicit ODE needs them "
                    "in the state. The paper quantifies them afresh in every Evolve; here "
                    "they keep their values between cycles, and Init starts them at 0 or "
                    "their declared initial values."
                    + (f" {', '.join(names[r] for r in odes.rates)}: the rates of the world's "
                       "inputs, constant during one evolution and chosen afresh (any value) "
                       "before each, so the inputs vary continuously, piecewise linearly; the "
                       "paper and the utp dialect leave them free." if odes and odes.rates
                       else "")))
    if dm is not None:
        context["dprocess"].update(_composition(program, dm, names, symbols, added),
                                   state_name=system_state, extends=names[pm.state.name])
    env = _environment()
    evolve = ("Ax_CyPhyCircus's evolution takes an explicit ODE. The p-model's equations were "
              "reduced to one as `cyphy solve` does"
              + (f" (restricted to {', '.join(elements)})" if elements else "")
              + ": one derivative per state of the reduction, the chain rule for the state "
              "fields the equations give as functions of the states (they follow the states "
              "from their values, assigned before each evolution), timer` = 1. The world's "
              "inputs (visible fields no equation determines) move at rates u_rate chosen "
              "afresh before each evolution; set-points and other variables no equation "
              "determines stay constant while the state evolves. Evolving variables that are "
              f"no state field (device locals, integrals, the rates) are added to "
              f"{names[pm.state.name]}.")
    files = {
        "ROOT": env.get_template("ax_ROOT.j2").render(session=session, parent=PARENT,
                                                       theory=theory),
        f"{theory}.thy": env.get_template("ax_theory.thy.j2").render(**context),
        "README": env.get_template("ax_README.j2").render(
            session=session, parent=PARENT, theory=theory, mapping=program.system.name,
            pmodel=pm.name, evolve=evolve),
        "names.tsv": _names_table(table, names, symbols, c.dmodel_constants(program)),
    }
    return IsabelleSession(files, theory, defs, names, symbols)


def _composition(program: c.Program, dm: c.BasicProcess, names: Any, symbols: Any,
                 added: list[str]) -> dict[str, Any]:
    """``N = (D ⟦ dvars | cs | pvars ⟧ P) \\ cs`` as Ax_CyPhyCircus can state it. It has no
    state hiding (utp-main's ``state 'a • P``): its operators are over one state type
    (Ax_CyPhyCircus.thy:34-58), and its own example composes two actions over one alphabet
    with a name-set partition (examples/Ranger_CyPhyCircus.thy:57, ``RangerLoop
    ⟦envVars | triggerChan | bufferVars⟧ EventBuffer``). So one alphabet, ``<N>State``,
    extends P's with D's variables, every action is typed over it, and the parallel
    (``_ParallelAct``, Circus_Toolkit IsaCircus_Syntax.thy:80, 100 → ``cParallelAct``,
    Ax_CyPhyCircus.thy:52) gives D its variables and P its own; the channel set is
    Circus_Toolkit's ``\\<lbrace>c, …\\<rbrace>`` (Channels_Events.thy:74-100: every event of
    each channel) and the hiding ``P \\<Zhide> cs`` (IsaCircus_Syntax.thy:81, 101 → ``cHide``,
    Ax_CyPhyCircus.thy:51)."""
    ctors = [symbols.constructors[(ch.name, v.tag)] for ch in program.channels
             if ch.name in REGISTER_CHANNELS for v in ch.variants or (c.ChannelVariant(None, ()),)]
    pm = program.pmodel
    p_vars = [names[f.name] for f in pm.state.fields] + [names[a] for a in added]

    def svid(idents: list[str]) -> str:  # a variable, or a tuple (Variables.thy:212-218)
        return idents[0] if len(idents) == 1 else "(" + ", ".join(idents) + ")"

    return {"channels": "\\<lbrace>" + ", ".join(ctors) + "\\<rbrace>",
            "d_vars": svid([names[f.name] for f in dm.state.fields]), "p_vars": svid(p_vars),
            "system": names[program.system.name]}


def _outputs_tied(main: c.Action, odes: EvolveOdes) -> c.Action:
    """The main action with every output of the reduction set to its value over the states
    where the timer is reset, before each evolution: Evolve's explicit ODE carries an output
    by the chain rule from where it starts, so it must start on its definition (the utp
    dialect states the algebraic equation itself); the discrete actions between evolutions
    (a call setting a set-point) change the value it must start at. Before it, the rates of
    the world inputs are chosen afresh (``cSpec rates True True``): the world may change
    how its inputs move at every cycle."""
    outputs = [(o.variable, o.value) for o in odes.odes
               if o.kind == "output" and o.value is not None]
    if not outputs and not odes.rates:
        return main
    # the world inputs' rates (u' = u_rate in the ODE) take any value for the next evolution
    choose = c.Spec(tuple(odes.rates), ex.Bool(True), ex.Bool(True)) if odes.rates else None

    def tie(a: c.Action) -> c.Action | None:
        if isinstance(a, c.Assign) and a.targets == (TIMER,):
            tied = c.Assign(a.targets + tuple(n for n, _ in outputs),
                            a.values + tuple(v for _, v in outputs))
            return tied if choose is None else c.Seq((choose, tied))
        return None

    return map_action(main, tie)


def _evolve_note(odes: EvolveOdes, elements: tuple[str, ...]) -> str:
    """What the explicit ODE below is, in the theory itself."""
    kinds = [o.kind for o in odes.odes]
    outputs = [o.variable for o in odes.odes if o.kind == "output"]
    text = ("The equations reduced to explicit ODEs (as cyphy solve does"
            + (f", restricted to {', '.join(elements)}" if elements else "")
            + f"): {kinds.count('state')} states")
    if outputs:
        text += (f"; {', '.join(outputs)} follow the states by the chain rule, from their "
                 "values over the states, which the main action assigns where it resets the "
                 "timer")
    inputs = [o.variable for o in odes.odes if o.kind == "input"]
    if inputs:
        text += (f"; the world's inputs {', '.join(inputs)} move at their rates, chosen afresh "
                 "before each evolution")
    return text + ". Set-points and other variables no equation determines stay constant."
