"""Registry of diagnostic codes of the front end (parse, I/O, scope and typing).

Later stages register their own codes (well-formedness ids, SDF, consistency) the same way:
``code(...)`` adds the code to ``REGISTRY`` so that the CLI can list them.
"""

from __future__ import annotations

from cyphy.diagnostics import Code, Severity

REGISTRY: dict[str, Code] = {}


def code(id: str, severity: Severity, summary: str) -> Code:
    if id in REGISTRY:
        raise ValueError(f"diagnostic code {id} registered twice")
    c = Code(id, severity, summary)
    REGISTRY[id] = c
    return c


E, W = Severity.ERROR, Severity.WARNING

# The command line's values (exit status 2, as argparse's usage errors).
OPTION = code("E-OPTION", E, "a command-line value does not fit the model")
CONST_REPLACED = code("W-CONST-REPLACED", W, "a given constant value (--const, --consts, a "
                      "scenario's [consts]) replaces a different declared value")
CONST_INSTANTIATED = code("W-CONST-INSTANTIATED", W, "a given constant value does not reach "
                          "a constant that an instantiation sets (the instantiation wins)")

# Reading files.
IO = code("E-IO", E, "a file or folder cannot be read")
NO_FILES = code("E-NO-FILES", E, "no model files (.pm, .rst, .rsm) were found")
ENCODING = code("E-ENCODING", E, "a file is not valid UTF-8")
SYNTAX = code("E-SYNTAX", E, "the text does not follow the notation")
LEX = code("E-LEX", E, "a character or token that the notation does not have")
MEMBER = code("E-MEMBER", E, "a member that this kind of block cannot hold")
DUPLICATE_MEMBER = code("E-DUPLICATE", E, "a member given twice where one is allowed")
ORDER = code("W-ORDER", W, "members out of the order RoboTool writes and expects")

# Scope and typing (wellformedness.md, S1-S5).
S1 = code("S1", E, "every name used resolves")
S2 = code("S2", E, "names declared in one scope are unique")
S3 = code("S3", E, "expressions are well-typed")
S4 = code("S4", E, "equations mention only the declarations of their block")
S5 = code("S5", E, "imports resolve to a package; no part contains its own p-model")
