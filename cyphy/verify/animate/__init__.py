"""``cyphy animate``: run a generated Isabelle/UTP session from its text alone.

:mod:`reader` reads the session (ROOT and theories) into definitions, constants and state;
:mod:`terms` evaluates its terms; :mod:`evolve` turns ``Evolve``'s equations into an explicit
ODE; :mod:`executor` runs ``D`` and ``P`` synchronised on their channels and integrates
between the cycle's ``tock``s. Nothing here reads cyphy's model: the theory is the only input.
"""
