"""What the models mean, built from the elaborated model: ``sdf/`` (the paper's SDF rules as a
tree), ``circus/`` (the CyPhyCircus semantics: its AST, rules, names, name sets), ``dynamics/``
(the kinematic tree, rigid-body algorithms, equations and their reduction), ``machines/``
(RoboSim's cycle semantics of state machines), ``consistency/`` (mapping checks with Z3), and
``scalarise`` (vector equations per component). Printers live in :mod:`cyphy.backends`."""
