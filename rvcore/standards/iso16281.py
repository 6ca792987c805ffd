"""Rating life of the ball bearing: ISO 281 basic rating life and ISO/TS 16281 reference
rating life from the load distribution, static and over a duty cycle. SI in and out,
except where a standard's formula is written in its own units (N, mm), said there.

What is computed
----------------
- the basic dynamic load rating ``C_r`` of the bearing from its geometry (ISO 281), or
  the catalogue value given in the bearing file (``dynamic_load_rating``);
- the ISO 281 dynamic equivalent load ``P_r = X·F_r + Y·F_a`` and the basic rating life
  ``L10 = (C_r/P_r)^3`` [10^6 rev];
- the ISO/TS 16281 basic reference rating life ``L10r`` from the per-contact loads of the
  quasi-static equilibrium (:func:`rvcore.statics.equilibrium.solve_statics`);
- the same reference rating life over a duty cycle, from the equivalent contact loads
  that the integrator accumulates at every step (Palmgren–Miner).

No life modification factor (``a_1``, ``a_ISO`` of ISO 281 clause 9 / ISO/TS 16281's
modified reference rating life: lubrication, contamination, fatigue limit) is applied:
every life here is the 90 %-reliability basic (reference) rating life of a bearing of
conventional steel and quality, in revolutions of the inner ring relative to the outer.

Standards and their numbering
-----------------------------
- ISO 281:2007, *Rolling bearings — Dynamic load ratings and rating life*, clause 5
  (radial ball bearings): 5.1.1 eq. (1) and (2) (``C_r``), Tables 1 and 2 (``b_m``,
  ``f_c``), 5.1.2 (bearing combinations), 5.2 eq. (3) and Table 3 (``X``, ``Y``, ``e``),
  5.3 eq. (4) (``L10``).
- ISO/TS 16281:2008, *Rolling bearings — Methods for calculating the modified reference
  rating life for universally loaded bearings*: eq. (19) and (20) (``Q_ci``, ``Q_ce`` of
  radial ball bearings), eq. (25) to (28) (``Q_ei``, ``Q_ee``), eq. (29) (``L10r``).

The clause and equation numbers above were written from the standards' structure as we
know it and cross-checked against the equation labels of an open implementation of
ISO/TS 16281 (github.com/minzhun/ISO16281); the standards' texts were not at hand.
Check them against your copy before citing.

Units: the standards' formulas take ``D_w`` in mm and give newtons; every function here
takes metres and converts inside.
"""
from __future__ import annotations

import math

import numpy as np

from .iso281 import (LIFE_EXPONENT, WEIBULL_E, LifeError, basic_dynamic_load_rating, basic_rating_life,
                     FC_TABLE_F_INNER, FC_TABLE_F_OUTER, fc_osculation_problem,
                     equivalent_dynamic_load, rating_geometry)
from .iso76 import static_rating_basis

def contact_load_ratings(load_rating: float, contact_angle: float, gamma: float, f_inner: float,
                         f_outer: float, ball_count: int, rows: int = 1):
    """ISO/TS 16281 basic dynamic load ratings of the inner and outer raceway contacts.

    Parameters
    ----------
    load_rating : float
        The bearing's basic dynamic radial load rating ``C_r`` [N] (ISO 281 from the
        geometry, or the catalogue value: the contact ratings scale with it).
    contact_angle : float
        Nominal contact angle ``α`` [rad].
    gamma : float
        ``D_w·cos α / D_pw`` [-].
    f_inner, f_outer : float
        Groove curvature ratios ``f_i = r_i/D_w``, ``f_e = r_e/D_w`` [-].
    ball_count : int
        ``Z``, balls per row.
    rows : int
        ``i`` [-].

    Returns
    -------
    Q_ci, Q_ce : float
        Ball load for which one row's inner (outer) raceway has a basic rating life of
        10^6 revolutions [N].

    Notes
    -----
    ISO/TS 16281:2008 eq. (19) and (20), radial ball bearings:

    .. math:: Q_{ci} = \\frac{C_r}{0.407\\, Z\\, (i \\cos α)^{0.7}}
              \\left[1 + \\left(1.044 \\left(\\frac{1-γ}{1+γ}\\right)^{1.72}
              \\left(\\frac{f_i (2 f_e - 1)}{f_e (2 f_i - 1)}\\right)^{0.41}\\right)^{10/3}\\right]^{0.3}
    .. math:: Q_{ce} = \\frac{C_r}{0.389\\, Z\\, (i \\cos α)^{0.7}}
              \\left[1 + \\left(1.044 \\left(\\frac{1-γ}{1+γ}\\right)^{1.72}
              \\left(\\frac{f_i (2 f_e - 1)}{f_e (2 f_i - 1)}\\right)^{0.41}\\right)^{-10/3}\\right]^{0.3}

    The bracket splits the bearing's rating between its two rings by the
    Lundberg–Palmgren ratio ``Q_ci/Q_ce``; 0.407 and 0.389 are the ratios of the
    equivalent ring loads to ``F_r/(Z cos α)`` of a radial bearing at zero clearance
    under pure radial load, so that eq. (29) reproduces ISO 281's L10 there.
    """
    k = 1.044 * ((1.0 - gamma) / (1.0 + gamma)) ** 1.72 * \
        (f_inner * (2.0 * f_outer - 1.0) / (f_outer * (2.0 * f_inner - 1.0))) ** 0.41
    base = load_rating / (ball_count * (rows * math.cos(contact_angle)) ** 0.7)
    q_ci = base / 0.407 * (1.0 + k ** (10.0 / 3.0)) ** 0.3
    q_ce = base / 0.389 * (1.0 + k ** (-10.0 / 3.0)) ** 0.3
    return q_ci, q_ce


def equivalent_ring_loads(inner_loads, outer_loads, ball_count: int):
    """ISO/TS 16281 dynamic equivalent ball loads of the rotating inner and stationary outer ring.

    Parameters
    ----------
    inner_loads, outer_loads : array_like
        Normal load of each ball of one row on the inner (outer) raceway [N].
    ball_count : int
        ``Z`` [-].

    Returns
    -------
    Q_ei, Q_ee : float
        [N]

    Notes
    -----
    ISO/TS 16281:2008 eq. (25) and (26), the inner ring rotating relative to the load:

    .. math:: Q_{ei} = \\left(\\frac{1}{Z}\\sum_j Q_{ij}^3\\right)^{1/3}, \\qquad
              Q_{ee} = \\left(\\frac{1}{Z}\\sum_j Q_{ej}^{10/3}\\right)^{3/10}

    A point of the rotating ring meets every load of the distribution in turn, so its
    damage averages the loads with the life equation's exponent 3; a point of the
    stationary ring always meets the same ball load, and the ring survives only if each
    of its loaded sectors does: with Weibull slope ``e = 10/9`` and sector lives
    ``∝ Q_j^(−3)``, ``ln S = Σ_j ln S_j ∝ Σ_j Q_j^(3e)``, the exponent ``3e = 10/3`` (Harris & Kotzalas, *Rolling Bearing Analysis: Advanced
    Concepts of Bearing Technology*, the chapter on fatigue life: equivalent rolling
    element load of the rotating ring with exponent 3, of the stationary ring with 10/3,
    ball bearings). The same exponents appear in eq. (25)–(28) as an open ISO/TS 16281
    implementation (github.com/minzhun/ISO16281) codes them: (25)/(26) inner ring
    rotating, (27)/(28) outer ring rotating with the roles exchanged. The standard's text
    itself was not at hand to confirm.
    """
    qi = np.maximum(np.asarray(inner_loads, dtype=float), 0.0)
    qo = np.maximum(np.asarray(outer_loads, dtype=float), 0.0)
    q_ei = (np.sum(qi ** 3) / ball_count) ** (1.0 / 3.0)
    q_ee = (np.sum(qo ** (10.0 / 3.0)) / ball_count) ** 0.3
    return float(q_ei), float(q_ee)


def combine_lives(lives) -> float:
    """Life of a system of parts in series, Lundberg–Palmgren: ``(Σ L_k^(−10/9))^(−9/10)``.

    Parameters
    ----------
    lives : array_like
        Lives of the parts (rings, rows) [any unit, the same for all]; inf for an
        unloaded part.

    Returns
    -------
    float
        In the unit of ``lives``; inf when every part is unloaded.

    Notes
    -----
    ISO/TS 16281:2008 eq. (29) written with ring lives (see :data:`WEIBULL_E`); the same
    rule (ISO 281 5.1.2's ``i^0.7 ≈ i^(7/9)``) combines the rows of a bearing.
    """
    lives = np.asarray(lives, dtype=float)
    if np.any(lives <= 0.0):
        return 0.0
    s = float(np.sum(lives ** (-WEIBULL_E)))
    return math.inf if s == 0.0 else s ** (-1.0 / WEIBULL_E)


def reference_rating_life(q_ci: float, q_ce: float, q_ei, q_ee) -> float:
    """ISO/TS 16281 basic reference rating life ``L10r`` [10^6 rev].

    Parameters
    ----------
    q_ci, q_ce : float
        Contact load ratings of one row (:func:`contact_load_ratings`) [N].
    q_ei, q_ee : float or array_like
        Equivalent ball loads of each row's inner and outer ring [N].

    Returns
    -------
    float
        ``L10r`` [10^6 rev]; inf when no ball is loaded.

    Notes
    -----
    Ring lives ``L_i = (Q_ci/Q_ei)^3``, ``L_e = (Q_ce/Q_ee)^3`` and, ISO/TS 16281:2008
    eq. (29), ``L10r = (L_i^(−10/9) + L_e^(−10/9))^(−9/10)`` per row; the rows combine
    the same way (:func:`combine_lives`).
    """
    q_ei, q_ee = np.atleast_1d(np.asarray(q_ei, float)), np.atleast_1d(np.asarray(q_ee, float))
    with np.errstate(divide="ignore"):
        lives = np.concatenate([(q_ci / q_ei) ** LIFE_EXPONENT, (q_ce / q_ee) ** LIFE_EXPONENT])
    return combine_lives(lives)


# --------------------------------------------------------------------------- the bearing


def geometry_load_rating(bearing) -> float:
    """ISO 281 ``C_r`` of the bearing from its geometry [N] (:func:`basic_dynamic_load_rating`).

    Raises :class:`LifeError` (one line, :func:`rvcore.standards.iso281.fc_osculation_problem`)
    where the groove radii exceed 0.52/0.53·D_w: Table 2's ``f_c`` does not hold there."""
    g = rating_geometry(bearing)
    problem = fc_osculation_problem(g["f_inner"], g["f_outer"])
    if problem:
        raise LifeError(problem)
    return basic_dynamic_load_rating(g["ball_diameter"], g["pitch_diameter"], g["contact_angle"],
                                     g["ball_count"], g["rows"],
                                     double_row_deep_groove=g["rows"] > 1 and g["contact_angle"] == 0.0)


def dynamic_load_rating(bearing) -> float:
    """The bearing's ``C_r`` [N]: the catalogue value when the bearing file gives one
    (``Bearing.dynamic_load_rating > 0``), else ISO 281 from the geometry."""
    c = float(getattr(bearing, "dynamic_load_rating", 0.0) or 0.0)
    return c if c > 0.0 else geometry_load_rating(bearing)


def dynamic_rating_basis(bearing) -> str:
    """One line: which ``C_r`` the lives take (the maker's, ISO 281 Table 2's, or none and
    why), for every output to repeat."""
    if float(getattr(bearing, "dynamic_load_rating", 0.0) or 0.0) > 0.0:
        return "C_r from the bearing file (the maker's catalogue value)"
    try:
        g = rating_geometry(bearing)
    except LifeError as exc:
        return str(exc)
    return fc_osculation_problem(g["f_inner"], g["f_outer"]) or \
        "ISO 281 C_r from the geometry, Table 2 f_c (groove radii within 0.52/0.53 Dw)"


def rating_caveats(bearing) -> list:
    """The caveats every output must repeat about the catalogue ratings of this bearing:
    a line each where ISO 76's ``f_0`` is reduced or ISO 281's ``C_r`` refused (groove radii
    above 0.52/0.53·D_w); empty otherwise."""
    try:
        g = rating_geometry(bearing)
    except LifeError:
        return []
    out = []
    if g["f_inner"] > FC_TABLE_F_INNER or g["f_outer"] > FC_TABLE_F_OUTER:   # ISO 76's limits are the same
        out.append(static_rating_basis(g["f_inner"], g["f_outer"]))
        if not float(getattr(bearing, "dynamic_load_rating", 0.0) or 0.0) > 0.0:
            out.append(fc_osculation_problem(g["f_inner"], g["f_outer"]))
    return out


def bearing_contact_ratings(bearing):
    """``(Q_ci, Q_ce)`` of one row of the bearing [N], from :func:`dynamic_load_rating`.

    A catalogue ``C_r`` scales both by ``C_catalogue/C_r(geometry)``: eq. (19)/(20) are
    proportional to ``C_r``.
    """
    g = rating_geometry(bearing)
    return contact_load_ratings(dynamic_load_rating(bearing), g["contact_angle"], g["gamma"], g["f_inner"],
                                g["f_outer"], g["ball_count"], g["rows"])


def ring_ball_loads(bearing, static_result):
    """Each ball's normal load on the inner and on the outer raceway, per row [N].

    Returns
    -------
    inner, outer : ndarray
        Shape (n_rows, Z); a ring's several arcs (four-point) are summed, as the
        integrator's accumulation does (``bdiag[:, B_QI]``, ``bdiag[:, B_QO]``).
    """
    q = np.asarray(static_result.ball_loads, dtype=float)
    inner_cols = np.asarray(static_result.arc_rings) == 0
    q_in = np.where(inner_cols[None, :], q, 0.0).sum(axis=1)
    q_out = np.where(~inner_cols[None, :], q, 0.0).sum(axis=1)
    n_rows = len(bearing.rows)
    rob = np.asarray(static_result.row_of_ball)
    inner = np.array([q_in[rob == r] for r in range(n_rows)])
    outer = np.array([q_out[rob == r] for r in range(n_rows)])
    return inner, outer


def static_life(bearing, static_result, radial_load: float | None = None,
                axial_load: float | None = None) -> dict:
    """Rating lives of the bearing at one quasi-static equilibrium.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    static_result : rvcore.statics.equilibrium.StaticResult
        The equilibrium: ``ball_loads[j, k]``, ``arc_rings``, ``row_of_ball``.
    radial_load, axial_load : float, optional
        ``F_r``, ``F_a`` [N] for ISO 281's ``P_r``; by default the resultant the
        equilibrium carries (``static_result.applied``, the ring's weight included).
        ISO 281 has no term for a tilting moment; ISO/TS 16281's L10r includes it
        through the load distribution.

    Returns
    -------
    dict
        ``reference_rating_life_L10r_Mrev`` (ISO/TS 16281, from the load distribution),
        ``basic_rating_life_L10_Mrev`` (ISO 281, NaN where Table 3 has no factors for
        this bearing), ``dynamic_load_rating_N`` (catalogue or geometry),
        ``equivalent_load_N`` (ISO 281 ``P_r``; NaN as L10), ``contact_load_rating_inner_N``,
        ``contact_load_rating_outer_N`` (``Q_ci``, ``Q_ce`` of a row) and
        ``equivalent_ring_loads_N`` ((n_rows, 2): ``Q_ei``, ``Q_ee`` of each row).
        Lives are inf where nothing loads the bearing. No life modification factor.
    """
    g = rating_geometry(bearing)
    c = dynamic_load_rating(bearing)
    q_ci, q_ce = bearing_contact_ratings(bearing)
    inner, outer = ring_ball_loads(bearing, static_result)
    eq = np.array([equivalent_ring_loads(qi, qo, g["ball_count"]) for qi, qo in zip(inner, outer)])
    l10r = reference_rating_life(q_ci, q_ce, eq[:, 0], eq[:, 1])
    applied = np.asarray(static_result.applied, dtype=float)
    fr = float(np.hypot(applied[0], applied[1])) if radial_load is None else float(radial_load)
    fa = float(applied[2]) if axial_load is None else float(axial_load)
    try:
        p = equivalent_dynamic_load(fr, fa, g["contact_angle"], g["ball_count"], g["ball_diameter"],
                                    g["double_row"], g["rows"])
        l10 = basic_rating_life(c, p)
    except LifeError:
        p = l10 = math.nan
    return {"reference_rating_life_L10r_Mrev": l10r, "basic_rating_life_L10_Mrev": l10,
            "dynamic_load_rating_N": c, "equivalent_load_N": p,
            "contact_load_rating_inner_N": q_ci, "contact_load_rating_outer_N": q_ce,
            "equivalent_ring_loads_N": eq}


# --------------------------------------------------------------------------- duty cycle


def duty_cycle_life(bearing, life_sums: dict) -> dict:
    """ISO/TS 16281 reference rating life over a duty cycle, Palmgren–Miner.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    life_sums : dict
        The integrator's accumulation (:attr:`rvcore.recording.results.CaseResult.life_sums`):
        ``"inner"``, ``"outer"``: arrays (n_phases + 1, n_rows) of ``Σ dN·Q_ei^3`` and
        ``Σ dN·Q_ee^3`` [N^3 rev] per phase and (last row) over the whole simulated cycle,
        where ``dN = |ω_i − ω_o|·dt/2π`` and ``Q_ei^3 = (1/Z)Σ_j Q_ij^3``,
        ``Q_ee^3 = ((1/Z)Σ_j Q_ej^(10/3))^(9/10)`` of the step (:func:`equivalent_ring_loads`);
        ``"revolutions"``: (n_phases + 1,) [rev].

    Returns
    -------
    dict
        ``rating_life_L10r`` [rev of the inner ring relative to the outer],
        ``rating_life_L10r_Mrev`` [10^6 rev], ``rating_life_cycles`` [cycles of the
        profile], ``fatigue_damage`` ((n_phases,) [1] per cycle), ``fatigue_damage_cycle``
        [1], ``revolutions_per_cycle`` [rev]. Lives are inf and damages 0 when nothing
        loads the rotating bearing; lives and damages are NaN where ``C_r`` is not rated
        (:func:`geometry_load_rating` raises: groove radii above 0.52/0.53·D_w).

    Notes
    -----
    A ring under equivalent load ``Q_e`` has the life ``(Q_c/Q_e)^3`` 10^6 rev; over ``dN``
    revolutions it takes the damage ``dN·Q_e^3/(10^6·Q_c^3)`` (Palmgren–Miner, linear in
    revolutions at each load). Over the cycle each ring k of each row takes

    .. math:: D_k = A_k / (10^6\\, Q_{c,k}^3)

    (``A_k`` the accumulated sum), i.e. its life is ``1/D_k`` cycles. The bearing's life
    combines the ring lives as ISO/TS 16281 eq. (29) does (:func:`combine_lives`):

    .. math:: L_{cycles} = \\left(\\sum_k D_k^{10/9}\\right)^{-9/10}, \\quad
              L_{10r} = L_{cycles}\\, N_{cycle}, \\quad D_{cycle} = 1/L_{cycles}

    which, at a constant operating point, is the static L10r exactly. ``D_cycle`` is
    homogeneous of degree 1 in the ``D_k``, so Euler's theorem splits it exactly over the
    phases p: ``D_p = Σ_k (∂D_cycle/∂D_k)·D_{k,p}`` with
    ``∂D_cycle/∂D_k = (D_k/D_cycle)^(1/9)``; the phases' shares sum to ``D_cycle`` when the
    phases cover the cycle. No life modification factor is applied.
    """
    inner = np.asarray(life_sums["inner"], dtype=float)
    outer = np.asarray(life_sums["outer"], dtype=float)
    revs = np.asarray(life_sums["revolutions"], dtype=float)
    if inner.ndim != 2 or inner.shape != outer.shape or revs.shape != (inner.shape[0],):
        raise ValueError(f"life_sums: 'inner' {inner.shape} and 'outer' {outer.shape} must both be "
                         f"(n_phases + 1, n_rows) and 'revolutions' {revs.shape} (n_phases + 1,)")
    if inner.shape[1] != len(bearing.rows):
        raise ValueError(f"life_sums has {inner.shape[1]} rows, the bearing {len(bearing.rows)}")
    if np.any(inner < 0) or np.any(outer < 0) or np.any(revs < 0):
        raise ValueError("life_sums must not be negative")
    try:
        q_ci, q_ce = bearing_contact_ratings(bearing)
    except LifeError:
        # not rated (rvcore.standards.iso281.fc_osculation_problem): NaN, never a number from a
        # table that does not hold; the caveat goes with the bearing (rating_caveats)
        nan = math.nan
        return {"rating_life_L10r": nan, "rating_life_L10r_Mrev": nan, "rating_life_cycles": nan,
                "fatigue_damage": np.full(inner.shape[0] - 1, nan), "fatigue_damage_cycle": nan,
                "revolutions_per_cycle": float(revs[-1])}
    scale = np.array([1e6 * q_ci ** LIFE_EXPONENT, 1e6 * q_ce ** LIFE_EXPONENT])
    damage = np.stack([inner, outer], axis=-1) / scale        # (n_phases + 1, n_rows, 2) [1]
    ring_cycle = damage[-1].ravel()
    d_cycle = float(np.sum(ring_cycle ** WEIBULL_E)) ** (1.0 / WEIBULL_E)
    n_cycle = float(revs[-1])
    if d_cycle > 0.0:
        weights = (ring_cycle / d_cycle) ** (WEIBULL_E - 1.0)
        phase = damage[:-1].reshape(damage.shape[0] - 1, -1) @ weights
        cycles = 1.0 / d_cycle
    else:
        phase = np.zeros(damage.shape[0] - 1)
        cycles = math.inf
    l10r = cycles * n_cycle if n_cycle > 0 else (math.inf if d_cycle == 0.0 else 0.0)
    return {"rating_life_L10r": l10r, "rating_life_L10r_Mrev": l10r / 1e6, "rating_life_cycles": cycles,
            "fatigue_damage": phase, "fatigue_damage_cycle": d_cycle, "revolutions_per_cycle": n_cycle}


def life_sums_at(bearing, static_result, revolutions) -> dict:
    """The integrator's ``life_sums`` of a cycle held at one equilibrium, per phase.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    static_result : rvcore.statics.equilibrium.StaticResult
    revolutions : array_like
        Revolutions of the inner ring in each phase [rev]; the cycle is their sum.

    Returns
    -------
    dict
        As :func:`duty_cycle_life` takes it, with ``dN·Q_e^3`` from the equilibrium's ball
        loads (the integrator's accumulation contract, done by hand).
    """
    revs = np.asarray(revolutions, dtype=float)
    g = rating_geometry(bearing)
    inner, outer = ring_ball_loads(bearing, static_result)
    eq = np.array([equivalent_ring_loads(qi, qo, g["ball_count"]) for qi, qo in zip(inner, outer)])
    per_rev = eq ** LIFE_EXPONENT                               # (n_rows, 2) [N^3]
    revs_all = np.append(revs, revs.sum())
    return {"inner": revs_all[:, None] * per_rev[None, :, 0], "outer": revs_all[:, None] * per_rev[None, :, 1],
            "revolutions": revs_all}
