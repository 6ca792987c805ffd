"""Quantities with units at the edges: parse "30 kN", "660 deg/s", "0.3 s" to SI floats.

Everything inside ``rvcore`` is SI. Config files and the command line accept unit strings,
parsed here with pint, or plain numbers which are taken as SI.
"""
from __future__ import annotations

import functools
import re

import pint

from ..errors import ConfigError

# The SI unit each physical kind is converted to. The key is what callers ask for.
SI_UNITS = {
    "length": "m",
    "mass": "kg",
    "time": "s",
    "force": "N",
    "moment": "N*m",
    "angle": "rad",
    "angular_speed": "rad/s",
    "speed": "m/s",
    "acceleration": "m/s**2",
    "density": "kg/m**3",
    "pressure": "Pa",
    "stiffness_hertz": "N/m**1.5",
    "stiffness": "N/m",
    "damping": "N*s/m",
    "inertia": "kg*m**2",
    "kinematic_viscosity": "m**2/s",
    "frequency": "Hz",
    "dimensionless": "dimensionless",
}


_TORQUE = re.compile(r"(?<![A-Za-z])([kM]?)Nm\b")


@functools.lru_cache(maxsize=1)
def registry() -> pint.UnitRegistry:
    ureg = pint.UnitRegistry()
    return ureg


def parse_quantity(value, kind: str, *, file=None, key: str | None = None) -> float:
    """Convert ``value`` to a float in the SI unit of ``kind``.

    Parameters
    ----------
    value : str, int or float
        A unit string such as ``"30 kN"``, or a plain number taken as already SI.
    kind : str
        One of the keys of :data:`SI_UNITS`.
    file, key :
        Where the value came from, for the error message.

    Raises
    ------
    ConfigError
        Naming file, key, value and why (unknown unit, wrong dimension, not a number).
    """
    target = SI_UNITS[kind]
    if isinstance(value, bool):
        raise ConfigError(file, key, value, f"expected a quantity in {target}, got a boolean")
    if isinstance(value, (int, float)):
        return float(value)
    if not isinstance(value, str):
        raise ConfigError(file, key, value, f"expected a number or a string with units of {target}")
    ureg = registry()
    # Engineers write torque as "Nm"/"kNm"; pint would not read that as newton·metre.
    text = _TORQUE.sub(lambda m: f"{m.group(1) or ''}N*m", value.strip())
    try:
        q = ureg.Quantity(text)
    except Exception as exc:  # pint raises several types for unparsable strings
        raise ConfigError(file, key, value, f"cannot read as a quantity ({exc.__class__.__name__}: {exc})") from None
    try:
        if isinstance(q, (int, float)):
            return float(q)
        if q.dimensionless and kind != "angle" and kind != "dimensionless":
            if q.units == ureg.dimensionless:
                return float(q.magnitude)  # a bare number in a string: SI
        return float(q.to(target).magnitude)
    except pint.DimensionalityError:
        raise ConfigError(file, key, value, f"wrong units: expected something convertible to {target}, got {q.units:~}") from None


def format_quantity(value_si: float, unit: str, kind: str) -> str:
    """Format an SI float in ``unit`` (e.g. ``format_quantity(30000, 'kN', 'force')``)."""
    ureg = registry()
    q = ureg.Quantity(value_si, SI_UNITS[kind]).to(unit)
    return f"{q.magnitude:.6g} {unit}"
