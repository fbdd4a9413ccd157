"""Flow* 2.1.0: export of a p-model under a controller scenario as a hybrid automaton
(:mod:`export`), the format's grammar (:mod:`syntax`), and running Flow* for a verdict
(:mod:`verdict`)."""
