"""ISO 281:2007 clause 9: the modified rating life ``L_nm = a_1·a_ISO·L10`` of a ball
bearing, and its Palmgren–Miner accumulation over a duty cycle. Pure functions, SI in and
out, except where the standard writes its formula in its own units (r/min, mm, mm² s⁻¹),
said there; the conversion is inside.

Used by :mod:`rvcore.statics.lubrication` (the statics' and the steady point's L_nm) and,
through the kernels :func:`reference_viscosity_of` and :func:`a_iso_of` (the one place of
ν1's and a_ISO's formulas; the checked functions call them), by the dynamics' per-step κ and
a_ISO (:func:`rvcore.recording.plan.fill_state_signals`). Lives here are in revolutions of the inner ring
relative to the outer, as in :mod:`rvcore.standards.iso16281` (whose basic lives are in 10^6 rev: a
caller multiplies by 1e6).

Notes
-----
Reference viscosity ν1 (ISO 281:2007 9.3.3, the standard's two speed branches; ``n`` in
r/min, ``d_m`` in mm, ν1 in mm² s⁻¹)::

    ν1 = 45000·n^−0.83·d_m^−0.5        n < 1000 r/min
    ν1 =  4500·n^−0.5 ·d_m^−0.5        n ≥ 1000 r/min

Viscosity ratio ``κ = ν/ν1`` (ν the operating viscosity). The standard covers
``0.1 ≤ κ ≤ 4``: above 4, κ = 4 is used; below 0.1 the standard does not apply (boundary
lubrication) and gives no reduction of its own. Here a κ below 0.1 is flagged (the
statics' ``kappa_outside_iso281``, the duty cycle's ``kappa_below_scope_fraction``: the
share of its revolutions run there) and a_ISO is taken at κ = 0.1, where the
formula gives a_ISO ≈ 0.1 for every load (its floor: ``2.2649·0.1^−0.054381 = 2.5671`` to
the constants' rounding, so the bracket is ≈ 1; within 0.6 % up to e_C·C_u/P = 3).

Life modification factor for radial ball bearings (ISO 281:2007 9.3.3.x, eq. for ball
bearings; ``e_C`` the contamination factor, ``C_u`` the fatigue load limit, ``P`` the
dynamic equivalent load)::

    a_ISO = 0.1·[1 − (2.5671 − c/κ^e)^0.83·(e_C·C_u/P)^(1/3)]^−9.3
        0.1 ≤ κ < 0.4 :  c = 2.2649, e = 0.054381
        0.4 ≤ κ < 1   :  c = 1.9987, e = 0.190870
        1   ≤ κ ≤ 4   :  c = 1.9987, e = 0.071739

limited to ``a_ISO ≤ 50`` (also where the bracket reaches 0). The three branches meet at
κ = 0.4 and κ = 1 to the constants' rounding (tests/core/test_lubrication.py).

The EP rule (ISO 281:2007 9.3.3.x, as open implementations of the standard state it; the
text was not at hand): if κ < 1 and ``e_C ≥ 0.2``, a lubricant with EP additives proven
effective may be rated with κ = 1, ``a_ISO`` then limited to 3. The rule is an
allowance ("may"): here it is applied only where it raises a_ISO, i.e.
``a_ISO = max(a_ISO(κ), min(a_ISO(1), 3))``.

Fatigue load limit of a ball bearing, the standard's simplified method (ISO 281:2007
Annex B, B.3.2.x, ``C_0`` the basic static load rating of ISO 76, ``d_m`` in mm)::

    C_u = C_0/22                       d_m ≤ 100 mm
    C_u = C_0/22·(100/d_m)^0.5         d_m > 100 mm

(:func:`rvcore.standards.iso76.static_load_rating` gives ``C_0``.) The standard prefers
its detailed method (Annex B's contact-stress route) where the two differ.

Duty cycle, Palmgren–Miner: step ``k`` runs ``N_k`` revolutions at ``P_k`` and ``κ_k``;
its modified L10 is ``a_ISO,k·L10,k`` with ``L10,k = (C/P_k)^3·10^6`` rev (ISO 281 5.3
eq. (4)). The damage of a cycle is ``D = Σ_k N_k/(a_ISO,k·L10,k)``; the cycle's modified
life ``L_nm = a_1·ΣN_k/D`` [rev]. At one constant step it is ``a_1·a_ISO·L10`` exactly.
a_1 scales the whole life (it shifts the Weibull line, not a step's damage).

Sources
-------
ISO 281:2007, *Rolling bearings — Dynamic load ratings and rating life*, clause 9 and
Annex B. The standard's text was not at hand. The a_ISO constants, ν1's branches, C_u's
simplified form and the EP rule were checked against two independent open
implementations found by content (a Rust bearing solver that cites the standard's
equation numbers, and a Python ISO 281 module that lists its constants as confirmed);
one of them carried 0.019087 for the middle branch's exponent, a typing slip: only
0.190870 makes the branches meet at κ = 0.4 (tested). Table 13's e_C guide values are
those MESYS's manual and FVA's documentation reproduce from ISO 281:2007; Table 12's a_1
were checked against the Weibull relation they come from (ISO/TR 1281-2:
``a_1 = 0.95·(ln(100/R)/ln(100/90))^(2/3) + 0.05``, tested).
"""
from __future__ import annotations

import math

import numpy as np

from .._numba import kernel
from .inputs import finite_positive

__all__ = [
    "KAPPA_MIN", "KAPPA_MAX", "A_ISO_MAX", "A_ISO_EP_MAX", "EP_MIN_CONTAMINATION",
    "CONTAMINATION_GUIDE", "CONTAMINATION_DEFAULT_LEVEL", "RELIABILITY_FACTORS",
    "reference_viscosity", "viscosity_ratio", "fatigue_load_limit_ball", "a_iso_ball",
    "contamination_factor", "reliability_factor", "modified_rating_life",
    "duty_cycle_modified_life", "reference_viscosity_of", "a_iso_of",
]

#: The κ range ISO 281's a_ISO covers; above 4, 4 is used [-].
KAPPA_MIN, KAPPA_MAX = 0.1, 4.0
#: Upper limit of a_ISO (ISO 281:2007 9.3.x) [-].
A_ISO_MAX = 50.0
#: The EP rule: a_ISO limited to 3 when κ = 1 is used for κ < 1, allowed where e_C ≥ 0.2.
A_ISO_EP_MAX = 3.0
EP_MIN_CONTAMINATION = 0.2
#: a_ISO's ball-bearing branches: (κ from, κ below, c, e) [-].
_BRANCHES = ((0.1, 0.4, 2.2649, 0.054381), (0.4, 1.0, 1.9987, 0.190870), (1.0, math.inf, 1.9987, 0.071739))

#: ISO 281:2007 Table 13, guide values of the contamination factor e_C: level →
#: ((high, low) for d_m < 100 mm, (high, low) for d_m ≥ 100 mm) [-]. As MESYS's manual
#: ("Contamination factor", citing ISO 281:2007) and FVA-Workbench's documentation
#: reproduce it.
CONTAMINATION_GUIDE = {
    "extreme cleanliness": ((1.0, 1.0), (1.0, 1.0)),
    "high cleanliness": ((0.8, 0.6), (0.9, 0.8)),
    "normal cleanliness": ((0.6, 0.5), (0.8, 0.6)),
    "slight contamination": ((0.5, 0.3), (0.6, 0.4)),
    "typical contamination": ((0.3, 0.1), (0.4, 0.2)),
    "severe contamination": ((0.1, 0.0), (0.1, 0.0)),
    "very severe contamination": ((0.0, 0.0), (0.0, 0.0)),
}
#: Default level: "normal cleanliness" (Table 13: oil through a fine filter; bearings
#: greased for life and shielded), taken at its lower bound. A choice, not a standard's
#: default: the RV main bearing runs in the reducer's grease behind its seals.
CONTAMINATION_DEFAULT_LEVEL = "normal cleanliness"

#: ISO 281:2007 Table 12, life modification factor for reliability: reliability [%] → a_1.
RELIABILITY_FACTORS = {90.0: 1.0, 95.0: 0.64, 96.0: 0.55, 97.0: 0.47, 98.0: 0.37, 99.0: 0.25,
                       99.2: 0.22, 99.4: 0.19, 99.6: 0.16, 99.8: 0.12, 99.9: 0.093,
                       99.92: 0.087, 99.94: 0.080, 99.95: 0.077}


class ModifiedLifeError(ValueError):
    """An input the standard's clause 9 does not cover (said why)."""


def _positive(name, value, unit):
    return finite_positive(name, value, unit, ModifiedLifeError)


def reference_viscosity(speed, pitch_diameter) -> float:
    """ISO 281 reference kinematic viscosity ν1 [m² s⁻¹] (module Notes).

    Parameters
    ----------
    speed : float
        Relative speed of the rings ``|ω_i − ω_o|`` [rad s⁻¹], > 0.
    pitch_diameter : float
        ``d_m`` [m].

    Returns
    -------
    float
        ν1 [m² s⁻¹]; the standard's formula takes n in r/min and d_m in mm.
    """
    return reference_viscosity_of(_positive("speed", abs(float(speed)), "rad/s"),
                                  _positive("pitch_diameter", pitch_diameter, "m"))


@kernel(inline=True)
def reference_viscosity_of(speed, pitch_diameter):
    """ν1 [m² s⁻¹] of :func:`reference_viscosity` without its checks, for the kernels (the
    one place of the formula); ``speed`` ``|ω|`` [rad s⁻¹] (0 gives inf), ``pitch_diameter``
    [m]."""
    n = speed * 60.0 / (2.0 * math.pi)
    dm = pitch_diameter * 1e3
    if n <= 0.0:
        return math.inf
    if n < 1000.0:
        nu1 = 45000.0 * n ** -0.83 * dm ** -0.5
    else:
        nu1 = 4500.0 * n ** -0.5 * dm ** -0.5
    return nu1 * 1e-6


def viscosity_ratio(viscosity, speed, pitch_diameter) -> float:
    """``κ = ν/ν1`` [-], not limited (:func:`a_iso_ball` limits it).

    Parameters
    ----------
    viscosity : float
        Operating kinematic viscosity ν [m² s⁻¹].
    speed, pitch_diameter : float
        As :func:`reference_viscosity`.
    """
    return _positive("viscosity", viscosity, "m^2/s") / reference_viscosity(speed, pitch_diameter)


def fatigue_load_limit_ball(static_load_rating, pitch_diameter) -> float:
    """Fatigue load limit ``C_u`` of a ball bearing, ISO 281 Annex B's simplified form [N].

    Parameters
    ----------
    static_load_rating : float
        ``C_0`` [N] (ISO 76; :func:`rvcore.standards.iso76.static_load_rating`).
    pitch_diameter : float
        ``d_m`` [m].
    """
    c0 = _positive("static_load_rating", static_load_rating, "N")
    dm = _positive("pitch_diameter", pitch_diameter, "m") * 1e3
    cu = c0 / 22.0
    return cu if dm <= 100.0 else cu * (100.0 / dm) ** 0.5


@kernel(inline=True)
def _a_iso_raw(kappa, x):
    """a_ISO of the branch κ (already in [0.1, 4]) falls in, ``x = e_C·C_u/P`` ≥ 0
    (:data:`_BRANCHES`)."""
    if kappa < _BRANCHES[1][0]:
        c, e = _BRANCHES[0][2], _BRANCHES[0][3]
    elif kappa < _BRANCHES[2][0]:
        c, e = _BRANCHES[1][2], _BRANCHES[1][3]
    else:
        c, e = _BRANCHES[2][2], _BRANCHES[2][3]
    base = 2.5671 - c / kappa ** e
    bracket = 1.0 - max(base, 0.0) ** 0.83 * x ** (1.0 / 3.0)
    if bracket <= 0.0:
        return A_ISO_MAX
    return min(0.1 * bracket ** -9.3, A_ISO_MAX)


def a_iso_ball(kappa, ec_cu_over_p, ep_additives: bool = False, contamination=None) -> dict:
    """ISO 281 life modification factor a_ISO of a ball bearing (module Notes).

    Parameters
    ----------
    kappa : float
        Viscosity ratio κ [-], > 0.
    ec_cu_over_p : float
        ``e_C·C_u/P`` [-], ≥ 0.
    ep_additives : bool
        The lubricant has EP additives proven effective (the EP rule).
    contamination : float, optional
        ``e_C`` [-]; needed when ``ep_additives`` (the rule asks ``e_C ≥ 0.2``).

    Returns
    -------
    dict
        ``a_iso`` [-]; ``kappa_used`` [-] (κ as the formula took it); ``outside_scope``
        (κ < 0.1: the standard does not apply; a_ISO is taken at κ = 0.1, i.e. ≈ 0.1);
        ``ep_rule`` (the EP rule raised a_ISO).
    """
    k = _positive("kappa", kappa, "")
    x = float(ec_cu_over_p)
    if not (math.isfinite(x) and x >= 0.0):
        raise ModifiedLifeError(f"e_C*C_u/P must be a finite number >= 0, got {ec_cu_over_p!r}")
    if ep_additives and contamination is None:
        raise ModifiedLifeError("the EP rule needs the contamination factor e_C")
    ec = float(contamination) if contamination is not None else 0.0
    a, k_used, ep = a_iso_of(k, x, bool(ep_additives), ec)
    return {"a_iso": a, "kappa_used": k_used, "outside_scope": k < KAPPA_MIN, "ep_rule": ep}


@kernel(inline=True)
def a_iso_of(kappa, x, ep_additives, contamination):
    """:func:`a_iso_ball` without its checks, for the kernels (the one place of the rule):
    ``(a_ISO, κ used, EP rule applied)`` for κ > 0 [-], ``x = e_C·C_u/P`` ≥ 0 [-], the EP flag
    and ``e_C`` [-]. κ below 0.1 is taken at 0.1 (module Notes), above 4 at 4."""
    k_used = min(max(kappa, KAPPA_MIN), KAPPA_MAX)
    a = _a_iso_raw(k_used, x)
    ep = False
    if ep_additives and k_used < 1.0 and contamination >= EP_MIN_CONTAMINATION:
        a_ep = min(_a_iso_raw(1.0, x), A_ISO_EP_MAX)
        if a_ep > a:
            a, k_used, ep = a_ep, 1.0, True
    return a, k_used, ep


def contamination_factor(level: str = CONTAMINATION_DEFAULT_LEVEL, pitch_diameter=0.1,
                         bound: str = "low") -> float:
    """A guide value of the contamination factor e_C, ISO 281:2007 Table 13 [-].

    Parameters
    ----------
    level : str
        A key of :data:`CONTAMINATION_GUIDE`.
    pitch_diameter : float
        ``d_m`` [m]: the column (d_m < 100 mm, or ≥ 100 mm).
    bound : {"low", "high"}
        Which end of the table's range.
    """
    key = str(level).strip().lower()
    if key not in CONTAMINATION_GUIDE:
        raise ModifiedLifeError(f"contamination level must be one of {sorted(CONTAMINATION_GUIDE)}, "
                                f"got {level!r}")
    if bound not in ("low", "high"):
        raise ModifiedLifeError(f"bound must be 'low' or 'high', got {bound!r}")
    dm = _positive("pitch_diameter", pitch_diameter, "m")
    hi, lo = CONTAMINATION_GUIDE[key][0 if dm < 0.1 else 1]
    return lo if bound == "low" else hi


def reliability_factor(reliability=90.0) -> float:
    """a_1 of ISO 281:2007 Table 12 [-].

    Parameters
    ----------
    reliability : float
        Reliability [%], one of the table's rows (:data:`RELIABILITY_FACTORS`): the
        standard tabulates them; other values are refused, not interpolated.
    """
    r = float(reliability)
    for key, a1 in RELIABILITY_FACTORS.items():
        if abs(r - key) < 1e-9:
            return a1
    raise ModifiedLifeError(f"reliability {reliability!r} % is not a row of ISO 281 Table 12 "
                            f"({', '.join(f'{k:g}' for k in RELIABILITY_FACTORS)})")


def modified_rating_life(basic_life, a_iso, a1=1.0) -> float:
    """``L_nm = a_1·a_ISO·L10`` [the unit of ``basic_life``].

    Parameters
    ----------
    basic_life : float
        L10 (ISO 281) or L10r (ISO/TS 16281) [rev or 10^6 rev], ≥ 0 or inf.
    a_iso, a1 : float
        Life modification factors [-], > 0.
    """
    life = float(basic_life)
    if not life >= 0.0:
        raise ModifiedLifeError(f"basic life must be >= 0, got {basic_life!r}")
    return _positive("a1", a1, "") * _positive("a_iso", a_iso, "") * life


def duty_cycle_modified_life(loads, kappas, revolutions, load_rating, fatigue_load_limit,
                             contamination, a1=1.0, ep_additives=False) -> dict:
    """Modified rating life of a duty cycle, Palmgren–Miner (module Notes).

    Parameters
    ----------
    loads : array_like
        Dynamic equivalent load of each step ``P_k`` [N], ≥ 0 (0: no damage).
    kappas : array_like
        Viscosity ratio of each step ``κ_k`` [-], > 0.
    revolutions : array_like
        Revolutions of each step ``N_k`` [rev], ≥ 0.
    load_rating : float
        ``C`` (``C_r``) [N].
    fatigue_load_limit : float
        ``C_u`` [N].
    contamination : float
        ``e_C`` [-], in [0, 1].
    a1 : float
        Reliability factor [-] (:func:`reliability_factor`).
    ep_additives : bool
        Apply the EP rule at each step (:func:`a_iso_ball`).

    Returns
    -------
    dict
        ``modified_life`` [rev]; ``a_iso`` (per step) [-]; ``damage`` (per step, of one
        cycle) [1]; ``damage_cycle`` [1]; ``revolutions_cycle`` [rev];
        ``outside_scope`` (per step: κ < 0.1); ``outside_scope_revolutions`` [rev], the
        revolutions run below κ = 0.1. The life is inf when no step is loaded.
    """
    p = np.atleast_1d(np.asarray(loads, dtype=float))
    k = np.atleast_1d(np.asarray(kappas, dtype=float))
    n = np.atleast_1d(np.asarray(revolutions, dtype=float))
    if not (p.shape == k.shape == n.shape and p.ndim == 1):
        raise ModifiedLifeError(f"loads {p.shape}, kappas {k.shape} and revolutions {n.shape} must "
                                "be 1-D arrays of one length")
    if not (np.all(np.isfinite(p)) and np.all(p >= 0.0)):
        raise ModifiedLifeError("loads must be finite and >= 0 N")
    if not (np.all(np.isfinite(n)) and np.all(n >= 0.0)):
        raise ModifiedLifeError("revolutions must be finite and >= 0")
    c = _positive("load_rating", load_rating, "N")
    cu = _positive("fatigue_load_limit", fatigue_load_limit, "N")
    ec = float(contamination)
    if not 0.0 <= ec <= 1.0:
        raise ModifiedLifeError(f"contamination factor e_C must lie in [0, 1], got {contamination!r}")
    a = np.ones_like(p)
    outside = np.zeros(p.shape, dtype=bool)
    damage = np.zeros_like(p)
    for j in range(p.size):
        if p[j] <= 0.0 or n[j] <= 0.0:
            continue
        r = a_iso_ball(k[j], ec * cu / p[j], ep_additives, ec)
        a[j], outside[j] = r["a_iso"], r["outside_scope"]
        damage[j] = n[j] / (a[j] * 1e6 * (c / p[j]) ** 3)
    d = float(damage.sum())
    total = float(n.sum())
    life = math.inf if d == 0.0 else _positive("a1", a1, "") * total / d
    return {"modified_life": life, "a_iso": a, "damage": damage, "damage_cycle": d,
            "revolutions_cycle": total, "outside_scope": outside,
            "outside_scope_revolutions": float(n[outside].sum())}
