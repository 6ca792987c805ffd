"""Reference fit files (``sweeps/reference/*.toml``): the published (or a rig's) linear fits.

The report compares the sweep's fits against them. The study's Tables 3 and 4 ship as
``sweeps/reference/study-fits.toml`` (:func:`default_reference_path`), each fit naming
its source. :func:`load_reference_fits` reads and validates such a file: unknown or
missing keys, bad values and units that do not convert are errors that name the file
and the key.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

from rvcore.profile import PHASES

from ..errors import ConfigError, UserError
from .units import parse_quantity, registry

#: The sweep axes a line is fitted against, in this order (the fits of fits.nc and of the
#: reference files alike).
AXES = ("speed", "radial_load")

#: Units a reference fit's slope must convert to, per axis (pint expressions).
_SLOPE_DIMENSION = {"speed": "m/(rad/s)", "radial_load": "m/N"}
#: pint expression of our coordinate units, per axis.
AXIS_PINT_UNITS = {"speed": "degree/s", "radial_load": "N"}
_FIXED_KIND = {"speed": "angular_speed", "radial_load": "force"}

_TOP_KEYS = {"title", "source", "description", "fits"}
_FIT_KEYS = {"table", "row", "label", "phase", "displacement", "metric", "axis", "fixed_axis",
             "fixed_value", "slope", "slope_units", "intercept", "intercept_units", "remarks",
             "source"}
_REQUIRED = ("table", "row", "phase", "displacement", "metric", "axis", "fixed_axis",
             "fixed_value", "slope", "slope_units", "intercept", "intercept_units")


@dataclass(frozen=True)
class ReferenceFit:
    """One published (or user-supplied) linear fit ``y = intercept + slope·x``.

    Parameters
    ----------
    table : str
        The table it comes from (e.g. ``"Table 3"``).
    row : int
        Row number in that table, from 1.
    label : str
        Human-readable origin, e.g. ``"Table 3, row 1: Start-up, Radial Variation Range"``.
    phase : str
        One of :data:`rvcore.profile.PHASES`.
    displacement : str
        ``"radial"`` or ``"axial"``.
    metric : str
        ``"range"``, ``"mean"`` or ``"std"``.
    axis, fixed_axis : str
        The fitted axis and the axis held fixed (``"speed"`` / ``"radial_load"``).
    fixed_value : float
        Value of the fixed axis [rad s^-1 for speed, N for load].
    fixed_text : str
        The fixed value as written in the file.
    slope, intercept : float
        In ``slope_units`` and ``intercept_units`` (pint expressions).
    remarks, source : str
    """

    table: str
    row: int
    label: str
    phase: str
    displacement: str
    metric: str
    axis: str
    fixed_axis: str
    fixed_value: float
    fixed_text: str
    slope: float
    slope_units: str
    intercept: float
    intercept_units: str
    remarks: str = ""
    source: str = ""

    @property
    def variable(self) -> str:
        """The metric variable of ``metrics.nc`` this fit describes."""
        return f"{self.displacement}_displacement_{self.metric}"

    @property
    def fixed_coordinate(self) -> float:
        """The fixed value in our coordinate units [degree s-1 or N]."""
        return math.degrees(self.fixed_value) if self.fixed_axis == "speed" else self.fixed_value

    def slope_in_coordinate_units(self) -> float:
        """The slope in m per coordinate unit [m (degree s-1)-1 or m N-1]."""
        q = registry().Quantity(self.slope, self.slope_units)
        return float(q.to(f"m/({AXIS_PINT_UNITS[self.axis]})").magnitude)

    def intercept_si(self) -> float:
        """The intercept [m]."""
        return float(registry().Quantity(self.intercept, self.intercept_units).to("m").magnitude)

    def to_reference_units(self, slope_coord: float, intercept_m: float):
        """Our slope [m per coordinate unit] and intercept [m] in this fit's units."""
        ureg = registry()
        s = ureg.Quantity(slope_coord, f"m/({AXIS_PINT_UNITS[self.axis]})").to(self.slope_units).magnitude
        i = ureg.Quantity(intercept_m, "m").to(self.intercept_units).magnitude
        return float(s), float(i)


def default_reference_path() -> Path:
    """The study's published fits, ``sweeps/reference/study-fits.toml``, as shipped."""
    from .shipped import REFERENCE_FITS, shipped_file

    return shipped_file(REFERENCE_FITS)


def load_reference_fits(path=None) -> list:
    """Read and validate a reference-fit file.

    Parameters
    ----------
    path : path-like, optional
        The TOML file; default :func:`default_reference_path`.

    Returns
    -------
    list of ReferenceFit

    Raises
    ------
    ConfigError
        On an unknown key, a missing key, a bad value or unconvertible units, naming the
        file, the key, the value and the reason.
    """
    path = Path(path) if path is not None else default_reference_path()
    try:
        with open(path, "rb") as fh:
            doc = tomllib.load(fh)
    except FileNotFoundError:
        raise UserError(f"{path}: reference-fit file not found") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(path, None, None, f"not valid TOML ({exc})") from None
    for key in doc:
        if key not in _TOP_KEYS:
            raise ConfigError(path, key, doc[key], f"unknown key (expected one of {', '.join(sorted(_TOP_KEYS))})")
    fits = doc.get("fits")
    if not isinstance(fits, list) or not fits:
        raise ConfigError(path, "fits", fits, "needs at least one [[fits]] table")
    ureg = registry()
    out = []
    for i, f in enumerate(fits):
        where = f"fits[{i}]"
        if not isinstance(f, dict):
            raise ConfigError(path, where, f, "must be a table")
        for key in f:
            if key not in _FIT_KEYS:
                raise ConfigError(path, f"{where}.{key}", f[key],
                                  f"unknown key (expected one of {', '.join(sorted(_FIT_KEYS))})")
        for key in _REQUIRED:
            if key not in f:
                raise ConfigError(path, f"{where}.{key}", None, "missing")

        def choice(key, allowed):
            v = f[key]
            if v not in allowed:
                raise ConfigError(path, f"{where}.{key}", v, f"must be one of {', '.join(allowed)}")
            return v

        phase = choice("phase", PHASES)
        displacement = choice("displacement", ("radial", "axial"))
        metric = choice("metric", ("range", "mean", "std"))
        axis = choice("axis", AXES)
        fixed_axis = choice("fixed_axis", AXES)
        if fixed_axis == axis:
            raise ConfigError(path, f"{where}.fixed_axis", fixed_axis, f"must differ from axis ({axis!r})")
        fixed = parse_quantity(f["fixed_value"], _FIXED_KIND[fixed_axis], file=path, key=f"{where}.fixed_value")
        for key in ("slope", "intercept"):
            if isinstance(f[key], bool) or not isinstance(f[key], (int, float)) or not math.isfinite(f[key]):
                raise ConfigError(path, f"{where}.{key}", f[key], "must be a finite number")
        row = f["row"]
        if isinstance(row, bool) or not isinstance(row, int) or row < 1:
            raise ConfigError(path, f"{where}.row", row, "must be a positive integer")
        for key, target in (("slope_units", _SLOPE_DIMENSION[axis]), ("intercept_units", "m")):
            try:
                ureg.Quantity(1.0, str(f[key])).to(target)
            except Exception as exc:  # pint raises several types
                raise ConfigError(path, f"{where}.{key}", f[key],
                                  f"must convert to {target} ({exc.__class__.__name__})") from None
        out.append(ReferenceFit(
            table=str(f["table"]), row=row,
            label=str(f.get("label", f"{f['table']}, row {row}")),
            phase=phase, displacement=displacement, metric=metric, axis=axis,
            fixed_axis=fixed_axis, fixed_value=fixed, fixed_text=str(f["fixed_value"]),
            slope=float(f["slope"]), slope_units=str(f["slope_units"]),
            intercept=float(f["intercept"]), intercept_units=str(f["intercept_units"]),
            remarks=str(f.get("remarks", "")), source=str(f.get("source", doc.get("source", ""))),
        ))
    return out
