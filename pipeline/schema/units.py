"""Units, in one place: user quantities in, UDUNITS spellings out.

Everything inside ``rvcore`` is SI. Config files and the command line accept unit strings,
parsed here with pint (:func:`parse_quantity`), or plain numbers which are taken as SI.
The files the pipeline writes name units in UDUNITS spelling (CF ``units`` attributes):
:func:`udunits` spells a pint unit that way, :func:`si_udunits` the SI unit of a kind of
:data:`SI_UNITS`, and :func:`compose_units` combines UDUNITS strings (a fit's slope is the
metric's unit over the axis's).
"""
from __future__ import annotations

import contextlib
import contextvars
import functools
import math
import re
import warnings

import pint
import pint.util

from ..errors import ConfigError, UnitlessNumberWarning

#: The SI unit (pint spelling) each physical kind is converted to. The key is what callers
#: ask for; the files write it as :func:`si_udunits` spells it.
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
    "compliance": "m/N",
    "area": "m**2",
    "second_moment": "m**4",
    "damping": "N*s/m",
    "inertia": "kg*m**2",
    "kinematic_viscosity": "m**2/s",
    "frequency": "Hz",
    "temperature": "K",
    "inverse_pressure": "1/Pa",
    "thermal_expansion": "1/K",
    "dimensionless": "dimensionless",
}

#: A temperature as written: a number and one of these units (pint refuses to multiply a
#: number by an offset unit such as degC, so temperatures are read here, not by pint).
_TEMPERATURE = re.compile(r"^\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*"
                          r"(K|kelvin|degC|°C|degree_Celsius|celsius)\s*\Z")


_TORQUE = re.compile(r"(?<![A-Za-z])([kM]?)Nm\b")


@functools.lru_cache(maxsize=1)
def registry() -> pint.UnitRegistry:
    ureg = pint.UnitRegistry()
    return ureg


#: True while a plain number is read without a warning (:func:`numbers_in_si`).
_NUMBERS_IN_SI = contextvars.ContextVar("numbers_in_si", default=False)


@contextlib.contextmanager
def numbers_in_si():
    """Read plain numbers in SI without a :class:`~pipeline.errors.UnitlessNumberWarning`:
    where the caller refuses them itself (a trace file's duty constant must carry its
    unit) or reads numbers it wrote in SI."""
    token = _NUMBERS_IN_SI.set(True)
    try:
        yield
    finally:
        _NUMBERS_IN_SI.reset(token)


def unit_warnings_on_success(read):
    """``read`` (a reader of a whole file or table) with its
    :class:`~pipeline.errors.UnitlessNumberWarning` held back until it returns: a file that
    is refused says its one error line, not warnings about values it then refused."""
    @functools.wraps(read)
    def reader(*args, **kwargs):
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always", UnitlessNumberWarning)
            result = read(*args, **kwargs)
        for w in said:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        return result
    return reader


def _unitless(value, x: float, kind: str, file, key) -> float:
    """``x``, the SI value of the plain number ``value``; warns where a unit was due
    (a dimensional kind, a value other than 0, text the user wrote). An angle other than 0
    is refused: degrees and radians are both in use, and neither reading is safe
    (``load_angle = 30`` read as 30 rad points the load at 279°)."""
    target = SI_UNITS[kind]
    if x != 0.0 and kind == "angle" and not _NUMBERS_IN_SI.get():
        raise ConfigError(file, key, value, "an angle needs its unit, e.g. '30 deg' or '0.5 rad' "
                                            "(a plain number could be either)")
    if x != 0.0 and target != "dimensionless" and not _NUMBERS_IN_SI.get():
        warnings.warn(UnitlessNumberWarning(file, key, value, f"a number without a unit, read in SI: "
                                                              f"{x:g} {target.replace('**', '^')}"), stacklevel=3)
    return x


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
        return _unitless(value, float(value), kind, file, key)
    if kind == "temperature":
        return _temperature(value, file, key)
    if not isinstance(value, str):
        raise ConfigError(file, key, value, f"expected a number or a string with units of {target}")
    ureg = registry()
    _check_text(value, target, file, key)
    _check_arithmetic(value, file, key)
    # Engineers write torque as "Nm"/"kNm"; pint would not read that as newton·metre.
    text = _TORQUE.sub(lambda m: f"{m.group(1) or ''}N*m", value.strip())
    try:
        q = ureg.Quantity(text)
    except pint.UndefinedUnitError as exc:
        names = ", ".join(repr(n) for n in getattr(exc, "unit_names", ()) or ()) or "a name"
        raise ConfigError(file, key, value, f"not a quantity: {names} is not a unit") from None
    except Exception:  # pint raises several types (some of them internal) for unparsable text
        raise ConfigError(file, key, value, f"not a quantity: expected a number and a unit of "
                                            f"{target}, e.g. {_EXAMPLE.get(target, '1 ' + target)!r}") from None
    magnitude = q if isinstance(q, (int, float)) else q.magnitude
    try:
        magnitude = float(magnitude)
    except (OverflowError, TypeError, ValueError):
        raise ConfigError(file, key, value, "not a finite number") from None
    if not math.isfinite(magnitude):
        raise ConfigError(file, key, value, "not a finite number")
    try:
        if isinstance(q, (int, float)):
            return _unitless(value, float(q), kind, file, key)
        if kind == "angle" and q.units == ureg.dimensionless:   # "30": 30 rad, not 30 deg
            return _unitless(value, float(q.magnitude), kind, file, key)
        if q.dimensionless and kind != "angle" and kind != "dimensionless":
            if q.units == ureg.dimensionless:
                return _unitless(value, float(q.magnitude), kind, file, key)  # a bare number in a string: SI
        return float(q.to(target).magnitude)
    except pint.DimensionalityError:
        raise ConfigError(file, key, value, f"wrong units: expected something convertible to {target}, got {q.units:~}") from None


def is_temperature_text(value) -> bool:
    """Whether ``value`` is written as a temperature (``"40 degC"``, ``"313.15 K"``)."""
    return isinstance(value, str) and _TEMPERATURE.match(value) is not None


def _temperature(value, file, key) -> float:
    """A temperature string (``"40 degC"``, ``"40 °C"``, ``"313.15 K"``) in K."""
    m = _TEMPERATURE.match(value) if isinstance(value, str) else None
    if m is None:
        raise ConfigError(file, key, value, "not a temperature: expected a number and K or degC, "
                                            "e.g. '40 degC' or '313.15 K'")
    x = float(m.group(1))
    if not math.isfinite(x):
        raise ConfigError(file, key, value, "not a finite number")
    return x if m.group(2) in ("K", "kelvin") else x + 273.15


#: What a value is allowed to be made of: ASCII digits and letters, the arithmetic of a
#: unit, and the few non-ASCII unit symbols engineers type. pint reads far more (it drops
#: a "#..." comment and stray symbols, so "30kN💥" was 30 kN) and fails on the rest with
#: its internal errors; this keeps both out.
_ALLOWED = re.compile(r"[0-9A-Za-z .+\-*/^()_°µμΩ%]*")
#: A number at the start (what a quantity must begin with, or a unit alone such as "rpm").
_LEADING_NUMBER = re.compile(r"^\s*[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
#: Exponents inside the unit ("m^2", "m**2", "N/m^1.5", "s^-1"): the only digits a unit holds.
_EXPONENT = re.compile(r"(\^|\*\*)\s*\(?\s*[+-]?\d+(\.\d+)?(/\d+)?\s*\)?")
_EXAMPLE = {"N": "30 kN", "rad/s": "660 deg/s", "m": "0.5 mm", "s": "0.3 s", "N*m": "2 kN*m"}


def _check_text(value: str, target: str, file, key) -> None:
    """Refuse text that is not one number and one unit: a character outside
    :data:`_ALLOWED`, or a number after the unit ("30 kN 2", which pint multiplies)."""
    bad = next((ch for ch in value if not _ALLOWED.fullmatch(ch)), None)
    if bad is not None:
        raise ConfigError(file, key, value, f"not a quantity: {bad!r} is not part of a number or a unit")
    m = _LEADING_NUMBER.match(value)
    unit = value[m.end():] if m else value
    if re.search(r"\d", _EXPONENT.sub("", unit)):
        raise ConfigError(file, key, value, "not a quantity: text after the number and its unit")


#: Longest text a quantity may be: "0.000125 N/m^1.5" is 16 characters; 64 leave room for
#: spaces and long unit names ("kilonewton * meter") and none for a pasted file.
MAX_QUANTITY_LENGTH = 64
#: Largest power a unit may be raised to: the units of the schema go up to m^3 (density)
#: and m^1.5 (Hertz stiffness); 4 leaves room and keeps "m**99999" out.
MAX_UNIT_POWER = 4
#: An exponent ("^" or "**") and what it raises: a number, or a parenthesised one.
_POWER = re.compile(r"(\^|\*\*)\s*(\(\s*[+-]?[\d.]+(?:\s*/\s*\d+)?\s*\)|[+-]?[\d.]+)")


def _unit_group(before: str) -> bool:
    """Whether ``before`` ends in a parenthesised group holding a unit name ("(kN)")."""
    if not before.endswith(")"):
        return False
    depth = 0
    for i in range(len(before) - 1, -1, -1):
        depth += {")": 1, "(": -1}.get(before[i], 0)
        if depth == 0:
            return any(ch.isalpha() for ch in before[i:]) and not _POWER.search(before[i:])
    return False


def _check_arithmetic(value: str, file, key) -> None:
    """Refuse what would make pint compute for ever or overflow, before pint sees it.

    pint evaluates its input as arithmetic: ``"9**9**9 N"`` is a number of 370 million
    digits (the parser hangs) and ``"2**2**20 N"`` one that overflows a float. A quantity
    is a number and a unit, so a power may raise only a unit (``m^2``, ``N/m**1.5``,
    ``s^-1``), by at most :data:`MAX_UNIT_POWER`, and never a power (``m^2^3``). The
    number itself is written as digits with an optional ``e`` exponent (``1e3 N``).
    """
    if len(value) > MAX_QUANTITY_LENGTH:
        raise ConfigError(file, key, value[:MAX_QUANTITY_LENGTH] + "...",
                          f"not a quantity: {len(value)} characters, more than the "
                          f"{MAX_QUANTITY_LENGTH} a number and its unit take")
    for m in _POWER.finditer(value):
        before = value[:m.start()].rstrip()
        if not before or not (before[-1].isalpha() or before[-1] in "°µμΩ" or _unit_group(before)):
            raise ConfigError(file, key, value,
                              f"not a quantity: {m.group(0).strip()!r} raises a number or a power to a power; "
                              "write the number with an e exponent (1e3) and raise only a unit (m^2)")
        rest = value[m.end():].lstrip()
        if rest.startswith(("^", "**")):
            raise ConfigError(file, key, value,
                              "not a quantity: a power of a power (a power tower); raise a unit once (m^2)")
        text = m.group(2).strip("() ").replace(" ", "")
        num, _, den = text.partition("/")
        try:
            power = float(num) / (float(den) if den else 1.0)
        except (ValueError, ZeroDivisionError):
            raise ConfigError(file, key, value, f"not a quantity: {m.group(0).strip()!r} is not a power") from None
        if abs(power) > MAX_UNIT_POWER:
            raise ConfigError(file, key, value,
                              f"not a quantity: the power {power:g} is more than the {MAX_UNIT_POWER} "
                              "a unit of this schema needs")
    if "^" in value.replace("**", "^") and value.replace("**", "^").count("^") != len(_POWER.findall(value)):
        raise ConfigError(file, key, value, "not a quantity: a power without a number after it")


def is_safe_text(value: str) -> bool:
    """Whether pint may be given ``value`` to evaluate: the checks of :func:`parse_quantity`
    (characters, trailing text, power towers, length) pass. For callers that ask pint
    about a text before it is parsed as a quantity (a sweep axis's kind)."""
    try:
        _check_text(value, "", None, None)
        _check_arithmetic(value, None, None)
    except ConfigError:
        return False
    return True


def format_quantity(value_si: float, unit: str, kind: str) -> str:
    """Format an SI float in ``unit`` (e.g. ``format_quantity(30000, 'kN', 'force')``)."""
    ureg = registry()
    q = ureg.Quantity(value_si, SI_UNITS[kind]).to(unit)
    return f"{q.magnitude:.6g} {unit}"


# --------------------------------------------------------------------------- UDUNITS

#: UDUNITS names of the units whose pint symbol UDUNITS does not know (pint writes "deg").
_UDUNITS_SYMBOLS = {"degree": "degree"}


def _format_terms(terms: dict) -> str:
    """``{symbol: exponent}`` as a UDUNITS product: positive powers first, in order, then
    the negative ones (``{"N": 1, "m": -1.5}`` -> ``"N m-1.5"``); ``"1"`` when empty."""
    def power(v):
        return f"{v:g}" if v != 1 else ""
    pos = [f"{k}{power(v)}" for k, v in terms.items() if v > 0]
    neg = [f"{k}{power(v)}" for k, v in terms.items() if v < 0]
    return " ".join(pos + neg) or "1"


def udunits(unit) -> str:
    """The UDUNITS spelling of a pint unit: ``"N*s/m"`` -> ``"N s m-1"``,
    ``"degree/s"`` -> ``"degree s-1"``, ``"dimensionless"`` -> ``"1"``.

    Parameters
    ----------
    unit : str or pint.Unit
        A unit pint reads (the spellings of :data:`SI_UNITS`).
    """
    ureg = registry()
    container = pint.util.to_units_container(ureg.Unit(unit), ureg)
    return _format_terms({_UDUNITS_SYMBOLS.get(name, ureg.get_symbol(name)): exponent
                          for name, exponent in container.items()})


@functools.lru_cache(maxsize=None)
def si_udunits(kind: str) -> str:
    """The UDUNITS spelling of the SI unit of ``kind`` (a key of :data:`SI_UNITS`)."""
    return udunits(SI_UNITS[kind])


def _udunits_terms(units: str) -> dict:
    """A UDUNITS product string (``"degree s-1"``) as ``{symbol: exponent}``."""
    terms: dict = {}
    for tok in str(units).split():
        if tok == "1":
            continue
        m = re.fullmatch(r"([A-Za-z_]+)(-?\d+(?:\.\d+)?)?", tok)
        if not m:
            raise ValueError(f"cannot compose units {units!r}")
        exponent = float(m.group(2)) if m.group(2) and "." in m.group(2) else int(m.group(2) or 1)
        terms[m.group(1)] = terms.get(m.group(1), 0) + exponent
    return terms


def compose_units(numerator: str, *denominators: str, power: int = 1) -> str:
    """``numerator**power / (denominators...)`` of UDUNITS strings, as a UDUNITS string.

    >>> compose_units("m", "degree s-1")
    'm s degree-1'
    """
    terms: dict = {}
    for k, v in _udunits_terms(numerator).items():
        terms[k] = terms.get(k, 0) + power * v
    for d in denominators:
        for k, v in _udunits_terms(d).items():
            terms[k] = terms.get(k, 0) - v
    return _format_terms(terms)
