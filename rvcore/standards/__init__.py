"""The ISO standards and catalogue methods the model cites: tables and formulas, no dynamics. Imports nothing of rvcore but ``_numba``."""
