"""Rigid-ring statics: equilibrium, its stiffness, preloaded pairs, the operating point, runout."""
