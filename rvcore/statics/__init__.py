"""Statics on rigid rings (or flexible ones, rvcore.rings.flexible): equilibrium, its stiffness, preloaded pairs, the operating point, runout."""
