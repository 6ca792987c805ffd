"""One dynamic case: the solver settings, the initial state, ``run_case``."""
