"""The one check of a formula's input: a finite number above zero, else the caller's error."""
from __future__ import annotations

import math


def finite_positive(name: str, value, unit: str, error: type = ValueError) -> float:
    """``value`` as a float, refused unless it is a finite number > 0.

    Parameters
    ----------
    name : str
        What the value is, for the message [-].
    value :
        The input, in ``unit``.
    unit : str
        Its unit, for the message ("" for none) [-].
    error : type
        The exception raised (a ``ValueError``; a module's own, e.g. ``LubricantError``) [-].

    Returns
    -------
    float
        The value [unit].
    """
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise error(f"{name} must be a number, got {value!r}") from None
    if not (math.isfinite(x) and x > 0.0):
        raise error(f"{name} must be a finite number > 0 {unit}, got {value!r}")
    return x
