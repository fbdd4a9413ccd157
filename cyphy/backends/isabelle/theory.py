"""An Isabelle session for a CyPhyCircus program: ``ROOT``, the prelude, the theory, a README.

The theory lays the program out in define-before-use order (``../shared/spec/isabelle.md``
section 2.3): the ``cycle``/``tscale`` axiomatization, the constants (``definition`` when they
have a value, ``consts`` when open), the uninterpreted functions, the channels as one
datatype, the state as two ``alphabet``s (visible fields, then the private ones on top), and
one ``definition`` per action, each followed by its ``[closure]`` lemma. The Jinja2 templates
in ``cyphy/backends/isabelle/templates/`` hold the layout; every term comes from
:class:`cyphy.backends.isabelle.terms.IsabellePrinter`.
"""

from __future__ import annotations

import re

from dataclasses import replace
from functools import lru_cache
from importlib.resources import files
from typing import Any

from cyphy import codes
from cyphy.backends.isabelle.names import RESERVED, IsabelleNames, is_identifier
from cyphy.backends.isabelle.terms import (HOL_FUNCTIONS, IsabellePrinter, Symbols, UnsupportedNode,
                                     bound_identifier)
from cyphy.records import record
from cyphy.semantics.circus import ast as c
from cyphy.semantics.circus.dmodel_cycle import is_cycle_process
from cyphy.semantics.circus.names import NameTable, identifier
from cyphy.semantics.circus.rules import DEVIATIONS, REGISTER_CHANNELS, functions
from cyphy.semantics.circus.walk import action_nodes
from cyphy.semantics.scalarise.process import scalar_process
from cyphy.semantics.scalarise.shapes import ScalariseError

UNTRANSLATABLE = codes.code("E-ISABELLE", codes.E,
                            "the CyPhyCircus program has no Isabelle/UTP counterpart")

PRELUDE = "CyPhyCircus_Prelude"


@record(frozen=False, slots=False)
class Definition:
    """One action definition as the template writes it."""

    name: str
    params: list[str]
    type: str
    body: str
    lemma: str
    simp_extra: str
    caveat: str = ""


@record(frozen=False, slots=False)
class IsabelleSession:
    """The session's files (relative path → text) and what the reader of the theory needs:
    the printed action ASTs by definition name, the identifier table and the caveats."""

    files: dict[str, str]
    theory_name: str
    actions: dict[str, c.ActionDef]
    names: IsabelleNames
    symbols: Symbols


class IsabelleError(Exception):
    """The program cannot be written as Isabelle/UTP; the message says what, ``span``
    where when it is known (else the mapping)."""

    def __init__(self, message: str, span: Any = None, shapes: bool = False) -> None:
        super().__init__(message)
        self.span = span
        self.shapes = shapes  # vector and matrix sizes that do not fit: an S3 error


@lru_cache(maxsize=1)
def _environment() -> Any:
    # lazy: Jinja is needed only when a theory is rendered, not to import the printer
    from jinja2 import Environment, PackageLoader, StrictUndefined

    # lazy: imports Jinja2 too
    from cyphy.backends.isabelle.bytecode_cache import bytecode_cache

    # The options below decide the compiled code: the cache's folder is named for this module.
    return Environment(loader=PackageLoader("cyphy.backends.isabelle", "templates"),
                       undefined=StrictUndefined, keep_trailing_newline=True,
                       trim_blocks=True, lstrip_blocks=True, autoescape=False,
                       bytecode_cache=bytecode_cache("backends/isabelle/theory.py"))


@lru_cache(maxsize=1)
def _prelude() -> str:
    """The prelude theory: fixed text, shipped as is (no template)."""

    return (files("cyphy.backends.isabelle") / "templates" / f"{PRELUDE}.thy").read_text("utf-8")


def definition_order(actions: tuple[c.ActionDef, ...]) -> list[c.ActionDef]:
    """The actions in define-before-use order: the given order where it already is one (the
    rules build bottom-up), otherwise each moved after what it calls; a cycle is an error
    (2020 ``definition`` is not recursive: recursion goes through ``MuC``)."""
    by_name = {d.name: d for d in actions}
    if len(by_name) < len(actions):  # the rules name actions apart: one would be lost here
        twice = sorted({d.name for d in actions if sum(e.name == d.name for e in actions) > 1})
        raise IsabelleError(f"actions named twice: {', '.join(twice)}")
    done: dict[str, c.ActionDef] = {}
    visiting: set[str] = set()

    def visit(d: c.ActionDef) -> None:
        if d.name in done:
            return
        if d.name in visiting:
            raise IsabelleError(f"action {d.name} calls itself through named actions")
        visiting.add(d.name)
        for callee in calls(d.body):
            if callee in by_name:
                visit(by_name[callee])
        visiting.discard(d.name)
        done[d.name] = d

    for d in actions:
        visit(d)
    return list(done.values())


def calls(action: object) -> list[str]:
    """The named actions ``action`` calls, in order of appearance, each once."""
    out: dict[str, None] = {}
    for node in action_nodes(action):  # type: ignore[arg-type]
        if isinstance(node, c.Call):
            out.setdefault(node.name, None)
    return list(out)


def _constant_order(constants: tuple[c.Constant, ...]) -> list[c.Constant]:
    by_name = {k.name: k for k in constants}
    done: dict[str, c.Constant] = {}

    def visit(k: c.Constant, depth: int = 0) -> None:
        if k.name in done or depth > len(by_name):
            return
        for n in (c.names_in(k.value) if k.value is not None else ()):
            if n in by_name and n != k.name:
                visit(by_name[n], depth + 1)
        done[k.name] = k

    for k in constants:
        visit(k)
    return list(done.values())


def _given_sets(program: c.Program) -> list[str]:
    """The named types that are not HOL's (``typedecl``s), from every declaration."""
    pm = program.pmodel
    types: list[c.Type] = [b.type for b in program.globals.constants]
    types += [k.type for k in c.program_constants(program)]
    types += [t for ch in program.channels for v in ch.variants for t in v.types]
    types += [f.type for f in (*pm.state.fields, *pm.local.fields)]
    for d in pm.actions:
        types += [p.type for p in d.params]
        for node in action_nodes(d.body):
            if isinstance(node, c.IndexedExtChoice):
                types.append(node.var.type)
            if isinstance(node, c.VarBlock):
                types.append(node.var.type)
    found: dict[str, None] = {}
    while types:
        t = types.pop(0)
        if isinstance(t, c.TBasic) and t.name not in ("real", "nat", "int", "bool"):
            found.setdefault(t.name, None)
        elif isinstance(t, c.TSeq):
            types.append(t.of)
        elif isinstance(t, c.TProduct):
            types.extend(t.items)
    return list(found)


def symbols_of(program: c.Program, taken: frozenset[str] = frozenset()) -> Symbols:
    """Every global name of the program with its Isabelle identifier, registered in a
    fixed order (types, constants, functions, channels, state, actions) so that the
    identifiers, and the ``_v`` suffixes where a reserved word is hit, are deterministic;
    ``taken``: identifiers the dialect reserves besides the common ones."""
    pm = program.pmodel
    names = IsabelleNames(taken)
    prefix = identifier(pm.name)
    for t in (f"{prefix}_chan", f"{prefix}_action", f"{prefix}Visible", pm.state.name):
        names.add(t)
    given = _given_sets(program)
    for g in given:
        names.add(g)
    nat = {b.name for b in program.globals.constants if b.type == c.NAT}
    nat |= {k.name for k in c.program_constants(program) if k.type == c.NAT}
    ints = {b.name for b in program.globals.constants if b.type == c.INT}
    ints |= {k.name for k in c.program_constants(program) if k.type == c.INT}
    for b in program.globals.constants:
        names.add(b.name)
    for k in c.program_constants(program):
        names.add(k.name)
    functions = {}
    for f in program.functions:
        functions[f.name] = HOL_FUNCTIONS.get(f.name) or names.add(f.name)
    constructors: dict[tuple[str, str | None], str] = {}
    for ch in program.channels:
        if not ch.variants:
            constructors[(ch.name, None)] = names.add(ch.name)
        for v in ch.variants:
            constructors[(ch.name, v.tag)] = names.add(f"{ch.name}_{v.tag}"
                                                       if v.tag else ch.name)
    for f in pm.state.fields:
        names.add(f.name)
    for d in pm.actions:
        names.add(d.name)
    names.add("MainAction")
    dm = program.dmodel if isinstance(program.dmodel, c.BasicProcess) else None
    d_state: list[str] = []
    d_actions: list[str] = []
    if dm is not None:  # D: its state, action type, actions and main; N and its channels
        d_state = [f.name for f in dm.state.fields]
        d_actions = [d.name for d in dm.actions]
        for n in (dm.state.name, f"{identifier(dm.name)}_action", *d_state, *d_actions,
                  f"{identifier(dm.name)}Main", program.system.name,
                  f"{program.system.name}_channels"):
            names.add(n)
    return Symbols(
        names=names,
        state=frozenset(f.name for f in pm.state.fields) | frozenset(d_state),
        constants=frozenset({b.name for b in program.globals.constants}
                            | {k.name for k in c.program_constants(program)}),
        nat=frozenset(nat),
        ints=frozenset(ints),
        actions=frozenset(d.name for d in pm.actions) | frozenset(d_actions),
        functions=functions,
        constructors=constructors,
        given_sets=tuple(given),
        locals=tuple(c.Binding(f.name, f.type) for f in pm.local.fields),
    )


@record(frozen=True, slots=False)
class ScalarProgram:
    """The program with the p-model's state made scalar (:mod:`cyphy.semantics.scalarise`),
    and what that pass promoted to state and holds during evolutions."""

    program: c.Program
    promoted: tuple[str, ...]
    held: tuple[str, ...]


def scalar_program(program: c.Program, evolving_as_state: bool = True) -> ScalarProgram:
    """Vectors and matrices as components, evolving locals as state (both dialects print
    this, never ``real list`` arithmetic); raises :class:`IsabelleError` with the node's span
    where the shapes do not fit."""
    try:
        scalar = scalar_process(program.pmodel, evolving_as_state)
    except ScalariseError as err:
        raise IsabelleError(str(err), getattr(err.node, "span", None), shapes=True) from None
    # transpose and the like are gone once written per component: declare only what is used,
    # by P and by D (a machine's guards and calls may apply abs, sqrt…)
    dm = program.dmodel
    used = {f.name: f for f in (*functions(scalar.process),
                                *(functions(dm) if isinstance(dm, c.BasicProcess) else ()))}
    return ScalarProgram(replace(program, pmodel=scalar.process,
                                 functions=tuple(used[n] for n in sorted(used))),
                         scalar.promoted, scalar.held)


def evolution_note(scalar: ScalarProgram, names: IsabelleNames) -> str:
    """What the theory's state and Evolve hold, for its header comment."""
    text = ("The state is scalar: a vector or matrix X of the model is the fields X_1, X_2, "
            "... (row by row, as cyphy solve names them); vector constants stay lists, read "
            "with nth (A ! k, from 0). ")
    if scalar.promoted:
        text += ("Locals whose derivative appears, and one variable per running integral, "
                 f"are state too ({', '.join(names[n] for n in scalar.promoted)}), so that "
                 "EvolveC constrains their rates; the other locals are quantified at each "
                 "instant. ")
    text += ("State that no equation of Evolve determines: the numeric variables that "
             "discrete actions write and no derivative governs (actuator set-points)")
    if scalar.held:
        text += f" are held: {', '.join(names[n] for n in scalar.held)}' = 0 in Evolve"
    else:
        text += " are held (x' = 0 in Evolve); there are none here"
    return text + ("; all other state is free, constrained only by the equations (the "
                   "world's inputs: sensor readings, joint outputs; Boolean set-points, which "
                   "have no rate to hold).")


def generate_session(program: c.Program, table: NameTable,
                     system_name: str | None = None) -> IsabelleSession:
    """The session folder's files for ``program``; raises :class:`IsabelleError` when a
    construct has no Isabelle/UTP counterpart."""
    if system_name is not None and (not is_identifier(system_name) or system_name in RESERVED):
        raise IsabelleError(f"the system name '{system_name}' is not an identifier, or is a "
                            "word of Isabelle/UTP's grammar")
    scalar = scalar_program(program)
    program = scalar.program
    pm = program.pmodel
    symbols = symbols_of(program)
    printer = IsabellePrinter(symbols)
    names = symbols.names
    theory = f"{identifier(pm.name)}_CyPhyCircus"
    prefix = identifier(pm.name)
    try:
        context = _theory_context(program, pm, printer)
    except UnsupportedNode as err:
        raise IsabelleError(str(err)) from None
    context.update(evolution_note=evolution_note(scalar, names),
                   theory=theory, prelude=PRELUDE, prefix=prefix, mapping=program.system.name,
                   dmodel=program.dmodel.name,
                   # the mapping's name, renamed like every other (``M`` is a UTP word)
                   system=system_name or names.get(program.system.name) or program.system.name,
                   pmodel=pm.name, chan_type=names[f"{prefix}_chan"],
                   action_type=names[f"{prefix}_action"])
    env = _environment()
    files = {
        "ROOT": env.get_template("ROOT.j2").render(session=f"{prefix}_CyPhy", theory=theory,
                                                    prelude=PRELUDE),
        f"{PRELUDE}.thy": _prelude(),
        f"{theory}.thy": env.get_template("theory.thy.j2").render(**context),
        "README": env.get_template("README.j2").render(
            session=f"{prefix}_CyPhy", theory=theory, prelude=PRELUDE,
            mapping=program.system.name, pmodel=pm.name),
    }
    files["names.tsv"] = _names_table(table, names, symbols, c.dmodel_constants(program))
    defs = {d.name: d for d in pm.actions}
    defs["MainAction"] = c.ActionDef("MainAction", (), pm.main)
    defs.update(_dprocess_actions(program))
    return IsabelleSession(files, theory, defs, names, symbols)


def _dprocess_actions(program: c.Program) -> dict[str, c.ActionDef]:
    """D's action definitions (its main action ``<D>Main`` last), as the theory prints them
    after P's; none when D is opaque."""
    dm = program.dmodel
    if not isinstance(dm, c.BasicProcess):
        return {}
    main = c.ActionDef(f"{identifier(dm.name)}Main", (), dm.main)
    return {d.name: d for d in [*definition_order(dm.actions), main]}


def _theory_context(program: c.Program, pm: c.BasicProcess, printer: IsabellePrinter,
                    action_type: str | None = None) -> dict[str, Any]:
    """What the theory templates lay out; ``action_type`` is the type of an action
    (default: the session's type synonym)."""
    names = printer.symbols.names
    globals_ = program.globals
    axioms = [printer.doprint(w, "hol") for w in globals_.where]
    constants = []
    for k in _constant_order(c.program_constants(program)):
        value = None if k.value is None else printer.doprint(k.value, "hol")
        constants.append({"name": names[k.name], "type": _quoted(printer.type(k.type)),
                          "value": value, "origin": k.origin})
    functions = []
    for f in program.functions:
        ident = printer.symbols.functions[f.name]
        if f.name in HOL_FUNCTIONS:
            continue
        tvars = [f"'a{i}" for i in range(1, f.arity + 1)] + ["'r"]
        functions.append({"name": ident, "type": " \\<Rightarrow> ".join(tvars)})
    constructors, channels = [], []
    for ch in program.channels:
        variants = ch.variants or (c.ChannelVariant(None, ()),)
        for v in variants:
            ident = printer.symbols.constructors[(ch.name, v.tag)]
            payload = ""
            if v.types:
                payload = " \\<times> ".join(printer.type(t) for t in v.types)
            channels.append({"name": ident, "type": _quoted(payload or "unit")})
            constructors.append(ident + (f' "{payload}"' if payload else ""))
    visible = [{"name": names[f.name], "type": _quoted(printer.type(f.type))}
               for f in pm.state.fields if f.visible]
    private = [{"name": names[f.name], "type": _quoted(printer.type(f.type))}
               for f in pm.state.fields if not f.visible]
    definitions = []
    utp = action_type is None
    action_type = action_type or names[f"{identifier(pm.name)}_action"]
    for d in [*definition_order(pm.actions), c.ActionDef("MainAction", (), pm.main)]:
        definitions.append(_definition(printer, d, action_type))
    dprocess = None
    if isinstance(program.dmodel, c.BasicProcess):
        dm = program.dmodel
        # the axiomatic dialect types D's actions over the system's one state, as P's
        d_type = names[f"{identifier(dm.name)}_action"] if utp else action_type
        dprocess = _dprocess_context(program, dm, printer, d_type)
    return {
        "dprocess": dprocess,
        "cycle_constants": [{"name": names[b.name], "type": printer.type(b.type)}
                            for b in globals_.constants],
        "axioms": axioms, "constants": constants, "functions": functions,
        "given_sets": [names[g] for g in printer.symbols.given_sets],
        "constructors": constructors, "channels": channels, "visible": visible,
        "private": private,
        "visible_name": names[f"{identifier(pm.name)}Visible"], "state_name": names[pm.state.name],
        "definitions": definitions,
        "deviations": DEVIATIONS,
    }


def _definition(printer: IsabellePrinter, d: c.ActionDef, action_type: str) -> Definition:
    """One action's definition and closure lemma as the template writes them."""
    names = printer.symbols.names
    whole = {p.name: p.type.name for p in d.params if p.type in (c.INT, c.NAT)}
    with printer.binding([p.name for p in d.params]) as params, printer.whole_params(whole):
        body = printer.action(d.body)
    ptypes = [printer.type(p.type) for p in d.params]
    multi_input = any(isinstance(n, c.Comm) and sum(isinstance(f, c.In) for f in n.fields)
                      > 1 for n in action_nodes(d.body))
    return Definition(name=names[d.name], params=params,
                      type=" \\<Rightarrow> ".join([*ptypes, action_type]), body=body,
                      lemma=f"{names[d.name]}_NCSP",
                      simp_extra=" prod.case_eq_if" if multi_input else "")


def _dprocess_context(program: c.Program, dm: c.BasicProcess, printer: IsabellePrinter,
                      action_type: str) -> dict[str, Any]:
    """D's alphabet, action type and definitions (its main action ``<D>Main``) and, in the
    utp dialect, the composition ``N = (D [| cs |] P) \\ cs`` over the channel set ``cs``
    (spec Structure): each process's state hidden by utp-main's ``state 'a \\<bullet> P``
    (state_srea, rea_designs/utp_rdes_prog.thy:424-432; NCSP by NCSP_state_srea,
    sf_rdes/utp_sfrd_prog.thy:407), synchronised by ``P \\<lbrakk>cs\\<rbrakk>\\<^sub>C Q``
    (circus/utp_circus_parallel.thy:838, parallel_is_NCSP :947) and hidden by ``HideCSP``
    (circus/utp_circus_hiding.thy:167, HideCSP_NCSP_closed :184)."""
    names = printer.symbols.names
    definitions = [_definition(printer, d, action_type)
                   for d in _dprocess_actions(program).values()]
    ctors = printer.symbols.constructors
    singles, ranges = [], []
    for ch in program.channels:
        if ch.name not in REGISTER_CHANNELS:
            continue
        for v in ch.variants or (c.ChannelVariant(None, ()),):
            (ranges if v.types else singles).append(ctors[(ch.name, v.tag)])
    parts = ([f"{{{', '.join(singles)}}}"] if singles else []) + \
        [f"range {r}" for r in ranges]
    channels = parts[0]
    for part in parts[1:]:
        channels = f"({channels} \\<union> {part})"
    return {
        "state_name": names[dm.state.name], "action_type": action_type,
        "fields": [{"name": names[f.name], "type": _quoted(printer.type(f.type))}
                   for f in dm.state.fields],
        "definitions": definitions, "main": definitions[-1].name,
        "cycle": is_cycle_process(dm),  # one cycle written out (typed events), not modes
        "channels_name": names[f"{program.system.name}_channels"], "channels": channels,
    }


def _quoted(t: str) -> str:
    return t if t.replace("_", "").isalnum() else f'"{t}"'


def _names_table(table: NameTable, names: IsabelleNames, symbols: Symbols,
                 dconstants: tuple[c.Constant, ...]) -> str:
    """qualified RoboSim name, CyPhyCircus name, Isabelle identifier (locals are bound), and
    for a device's constant its definition-qualified name (``SpeedControlMotor::R``), which
    ``--const`` and a scenario's ``[consts]`` may use (empty otherwise)."""
    rows = ["qualified\tcyphycircus\tisabelle\tdefinition"]
    globals_ = names.identifiers()
    by_mangled = {mangled: qualified for qualified, mangled in table.items()}
    split = {m.group(1) for n, _ in names.items()
             if (m := re.fullmatch(r"(.+?)(?:_\d+)+", n)) and m.group(1) in by_mangled
             and names.get(m.group(1)) is None}
    for qualified, mangled in table.items():
        if mangled in split:
            continue  # the theory has its components (below), not the vector itself
        ident = names.get(mangled) or bound_identifier(mangled, globals_)
        rows.append(f"{qualified}\t{mangled}\t{ident}\t{table.definition(qualified)}")
    # What the theory has in their place: the components of a vector or matrix (the state is
    # scalar: LHinge_F is LHinge_F_1 .. LHinge_F_6) and the integrator states of integrals.
    for mangled, ident in sorted(names.items()):
        if mangled in by_mangled:
            continue
        m = re.fullmatch(r"(.+?)((?:_\d+)+)", mangled)
        if m and m.group(1) in split:
            index = "".join(f"[{k}]" for k in m.group(2).split("_")[1:])
            rows.append(f"{by_mangled[m.group(1)]}{index}\t{mangled}\t{ident}\t")
            continue
        m = re.fullmatch(r"(.+)_int\d*", mangled)
        if m and m.group(1) in by_mangled:
            rows.append(f"integral of {by_mangled[m.group(1)]}\t{mangled}\t{ident}\t")
    # The d-model process's own state (its machine's mode, the events it read): no RoboSim
    # element has these names, so the first column says whose they are.
    listed = {row.split("\t")[2] for row in rows[1:]}
    for field in sorted(symbols.state):
        ident = names.get(field) or field
        if ident not in listed:
            rows.append(f"state of the d-model process\t{field}\t{ident}\t")
    for k in dconstants:  # a machine's open constants, named as D names its variables
        rows.append(f"{k.origin}\t{k.name}\t{names.get(k.name) or k.name}\t")
    return "\n".join(rows) + "\n"

