"""The headline's quantities and the targets a user sets for them (``--target-…`` of
``rvsweep report`` and ``rvsweep sweep --report``): the table and the parsing of the
options, without the report's numerical packages, so that ``--help`` stays light.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import ConfigError


@dataclass(frozen=True)
class Target:
    """One headline quantity and its optional target.

    Parameters
    ----------
    key : str
        Its key in :data:`.summary.COLUMNS` (values in that column's unit).
    name : str
        What the headline calls it.
    worst : str
        ``"min"``: the smallest value over the sweep is the worst, the target is a lower
        bound; ``"max"``: the largest, the target an upper bound.
    flag : str
        The ``rvsweep report`` option that sets the target.
    kind : str
        Unit kind of the option's value (:data:`pipeline.schema.units.SI_UNITS`).
    scale : float
        Multiplies the option's SI value into the column's unit [column unit / SI unit].
    unit : str
        The column's unit as the headline writes it ('' for a ratio).
    example : str
        An example value for ``--help``.
    where : str
        When in the cycle the value is taken ('' for s₀: its phase is read per point).
    """

    key: str
    name: str
    worst: str
    flag: str
    kind: str
    scale: float
    unit: str
    example: str
    where: str


#: The headline's quantities in their order, each with its ``rvsweep report`` target option.
TARGETS = (
    Target("safety", "smallest static safety factor s₀", "min", "--target-s0", "dimensionless", 1.0, "",
           "2", ""),
    Target("life_mrev", "shortest rating life L10r of the duty cycle", "min", "--target-life", "dimensionless",
           1.0, "Mrev", "50 (million revolutions)", "over the whole cycle"),
    Target("modified_life_mrev", "shortest modified rating life L_nm of the duty cycle (ISO 281 a_ISO)", "min",
           "--target-modified-life", "dimensionless", 1.0, "Mrev", "50 (million revolutions)",
           "over the whole cycle"),
    Target("startup_torque", "largest start-up drive torque", "max", "--target-torque", "moment", 1.0, "N m",
           '"20 N m"', "start-up phase"),
    Target("radial_stiffness", "smallest radial stiffness k_r", "min", "--target-radial-stiffness", "stiffness",
           1e-6, "N/µm", '"500 N/um"', "steady point"),
    Target("axial_stiffness", "smallest axial stiffness k_a", "min", "--target-axial-stiffness", "stiffness",
           1e-6, "N/µm", '"150 N/um"', "steady point"),
    Target("tilting_stiffness", "smallest tilting stiffness k_θ", "min", "--target-tilting-stiffness", "moment",
           1e-3, "N m/mrad", '"2000 N*m/mrad"', "steady point"),
)

_BY_KEY = {t.key: t for t in TARGETS}


def parse_targets(values: dict) -> dict:
    """The targets of the command line in their columns' units.

    Parameters
    ----------
    values : dict
        Target key (:attr:`Target.key`) -> the option's text as typed (None: not set).
        ``--target-life`` is a number of million revolutions; ``--target-s0`` a number;
        the torque and stiffness targets quantities with units (``"20 N m"``,
        ``"500 N/um"``, ``"2000 N*m/mrad"``).

    Returns
    -------
    dict
        Target key -> value in the column's unit (s₀ [1], L10r [Mrev], torque [N m],
        k_r and k_a [N/µm], k_θ [N m/mrad]), for the options set.

    Raises
    ------
    ConfigError
        Naming the option, the value as typed and why: not a number or quantity of the
        right kind, not finite, or not positive.
    """
    from ..schema.units import parse_quantity

    out = {}
    for key, text in values.items():
        if text is None:
            continue
        t = _BY_KEY[key]
        if t.kind == "dimensionless":
            try:
                v = float(text)
            except ValueError:
                raise ConfigError("command line", t.flag, text, "not a number") from None
        else:
            v = parse_quantity(text, t.kind, file="command line", key=t.flag)
        if not math.isfinite(v) or v <= 0.0:
            raise ConfigError("command line", t.flag, text, "a target must be a positive finite number")
        out[key] = v * (t.scale if t.kind != "dimensionless" else 1.0)
    return out
