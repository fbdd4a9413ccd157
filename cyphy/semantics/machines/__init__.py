"""State machines of the d-model: RoboSim's cycle semantics, an interpreter (``cycle``), and
the machine compiled to a finite automaton (``automaton``)."""
