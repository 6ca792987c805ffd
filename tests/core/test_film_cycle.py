"""The film and the modified life along the duty cycle (issue 40): the dynamics' per-step
Hamrock–Dowson film against the formula evaluated here from rolling kinematics, and the
Palmgren–Miner accumulation of ISO 281's a_ISO over a two-level cycle computed by hand.

The film case: a pure axial load on an angular-contact row loads every ball alike, at the
contact angle the geometry gives (tests/core/test_designer_outputs.py, whose textbook
relations are reused), so every inner contact carries the same load ``Q`` and, in rolling
at steady speed ω, the entrainment speed ``u = ω·d_m·(1 − γ²)/4``, ``γ = D·cos α/d_m``
(Harris & Kotzalas; the inner and the outer contact alike). The film formula itself is
checked against Hamrock & Dowson's published numbers in tests/core/test_lubrication.py.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit

from rvcore.bearing.layout import A_LOG_HC1, A_LOG_LAM1, compile_bearing
from rvcore.bearing.lubricant import contact_lubricant, contamination_of, operating_viscosity
from rvcore.contact.film import HC_EXP_U, HC_EXP_W, HM_EXP_U, HM_EXP_W, hamrock_dowson_contact
from rvcore.dynamics import races as R
from rvcore.dynamics.rhs import new_diagnostics
from rvcore.hertz import effective_modulus, race_contact
from rvcore.output_table import SLOT
from rvcore.profile import OperatingPoint
from rvcore.recording.plan import build_plan, fill_state_signals, new_accumulators, reduce_step
from rvcore.recording.results import modified_cycle_outputs, read_life_sums
from rvcore.simulation.run import run_case
from rvcore.simulation.settings import SolverSettings
from rvcore.standards.iso16281 import bearing_contact_ratings, dynamic_load_rating
from rvcore.standards.iso281_modified import a_iso_ball, fatigue_load_limit_ball
from rvcore.standards.iso76 import bearing_static_load_rating

from .physics_cases import axial_point, constant_profile, section_bearing
from .test_designer_outputs import ISO76


def _films(bearing, q, omega, alpha):
    """(central, minimum) Hamrock–Dowson film [m] of the inner and the outer contact at load
    ``q`` [N] in rolling at ``omega`` [rad/s], contact angle ``alpha`` [rad]: each a
    FilmThickness."""
    row = bearing.rows[0]
    ring, ball = bearing.ring_material, bearing.ball_material
    e_eff = effective_modulus(ring.youngs_modulus, ring.poisson_ratio, ball.youngs_modulus, ball.poisson_ratio)
    eta0, alpha_p, _ = contact_lubricant(bearing)
    gamma = row.ball_diameter * math.cos(alpha) / row.pitch_diameter
    u = omega * row.pitch_diameter * (1.0 - gamma * gamma) / 4.0
    out = []
    for side, arc in (("inner", row.inner_arcs[0]), ("outer", row.outer_arcs[0])):
        # the model's contact law takes each arc's Hertz ellipse at the arc's nominal angle
        hc = race_contact(row.ball_diameter, row.pitch_diameter, arc.curvature_ratio, arc.contact_angle, side,
                          e_eff)
        out.append(hamrock_dowson_contact(hc, q, u, eta0, alpha_p))
    return out


def test_film_along_the_cycle_is_hamrock_dowson_of_the_rolling_contacts():
    """Steady 240 °/s, every ball under the same axial-load share: the smallest film over
    the loaded contacts, its λ and their phase means and minima are Hamrock–Dowson's at
    the inner contact (the thinner: its R_x is the smaller) with the load and the rolling
    entrainment speed computed here, within 1 % (the film goes as u^0.67: a ball's slip
    against pure rolling of 1 % moves it 0.7 %; the load as Q^−0.067)."""
    bearing = section_bearing(8, alpha=math.radians(25.0))
    f_a, q, alpha = axial_point(bearing, ISO76 / 2.0)
    omega = math.radians(240.0)
    res = run_case(bearing, constant_profile(0.0, 0.006), OperatingPoint(omega, 0.0, f_a),
                   SolverSettings(output_rate=1e4, gravity=False))
    inner, outer = _films(bearing, q, omega, alpha)
    assert inner.central < outer.central and inner.minimum < outer.minimum
    sigma = contact_lubricant(bearing)[2]
    steady = 1     # the phase [t_end/3, 2 t_end/3): rolling settled
    m = res.phase_metrics
    for name, want in (("film_thickness_central", inner.central), ("film_thickness_minimum", inner.minimum),
                       ("film_parameter", inner.minimum / sigma)):
        assert m[f"{name}_mean"][steady] == pytest.approx(want, rel=0.01), name
        assert m[f"{name}_min"][steady] == pytest.approx(want, rel=0.01), name
        assert m[f"{name}_min"][steady] <= m[f"{name}_mean"][steady]
    lam = res.series["film_parameter"]
    t = res.time
    window = (t >= 0.002) & (t < 0.004)
    np.testing.assert_allclose(lam[window], inner.minimum / sigma, rtol=0.01)
    # κ at the prescribed speed, ISO 281's ν1 (n < 1000 r/min branch) computed here
    n = omega * 60.0 / (2.0 * math.pi)
    nu1 = 45000.0 * n ** -0.83 * (bearing.rows[0].pitch_diameter * 1e3) ** -0.5 * 1e-6
    np.testing.assert_allclose(res.series["kappa"], operating_viscosity(bearing) / nu1, rtol=1e-12)
    assert m["kappa_mean"][steady] == pytest.approx(operating_viscosity(bearing) / nu1, rel=1e-12)


def test_no_loaded_contact_no_film():
    """No load and no gravity: no race contact is loaded, so no film (NaN), and its
    phase mean and minimum are NaN, not 0."""
    bearing = section_bearing(6, alpha=math.radians(25.0), clearance=20e-6)
    res = run_case(bearing, constant_profile(0.0, 0.0015), OperatingPoint(math.radians(120.0), 0.0, 0.0),
                   SolverSettings(output_rate=1e4, gravity=False))
    assert np.all(np.isnan(res.series["film_parameter"]))
    for name in ("film_parameter_mean", "film_parameter_min", "film_thickness_minimum_mean"):
        assert np.all(np.isnan(res.phase_metrics[name])), name


# ---- Palmgren-Miner of a_ISO over a two-level cycle ----------------------------------


def _accumulate(bearing, levels):
    """Drive the integrator's per-step kernels by hand: for each ``(ω [rad/s], Q [N], dt
    [s])`` one step with every ball carrying ``Q`` on both races, reduced into one
    accumulator line; returns the life sums as the case reads them."""
    model = compile_bearing(bearing, gravity=False)
    plan = build_plan(1, 0)
    acc = new_accumulators(plan, 1)       # one phase and the whole cycle, the same steps
    diag, bdiag = new_diagnostics(1, model.n_balls, 0)
    cos_nominal = np.array([math.cos(bearing.rows[0].nominal_contact_angle)])
    for omega, q, dt in levels:
        table, meta = constant_profile(0.0, 1.0).resolve(OperatingPoint(omega, 0.0, 1.0)).arrays()
        bdiag[:, 0] = q     # B_QI
        bdiag[:, 1] = q     # B_QO
        fill_state_signals(diag, np.zeros(model.n_states), 0.5, dt, table, meta, model.rows, bdiag,
                           np.zeros((0, 6)), cos_nominal, model.params)
        for line in acc:
            reduce_step(line, plan.reductions, diag, 0.5, 0, 0.5 * dt)
    return read_life_sums(acc, plan), diag


def test_miner_sum_of_a_iso_over_a_two_level_cycle():
    """Two levels, by hand: N_k = ω_k·dt_k/2π revolutions at ball load Q_k; the step's
    reference life 1/D_k (D_k = ((Q_k/Q_ci)^(30/9) + (Q_k/Q_ce)^(30/9))^(9/10) per 10^6 rev,
    ISO/TS 16281's ring lives combined as its eq. (29)), its equivalent load
    P_k = C_r·D_k^(1/3); a_ISO,k from κ_k = ν/ν1(ω_k) and e_C·C_u/P_k (ISO 281 9.3); the
    rings' damages Σ_k N_k·Q_k³/(a_k·10^6·Q_c³) combined as eq. (29) give L_nm. One level
    below κ = 0.1 is counted in the flag."""
    bearing = section_bearing(8, alpha=math.radians(25.0))
    q_ci, q_ce = bearing_contact_ratings(bearing)
    c = dynamic_load_rating(bearing)
    dm = bearing.rows[0].pitch_diameter
    ec = contamination_of(bearing)
    cu = fatigue_load_limit_ball(bearing_static_load_rating(bearing), dm)
    nu = operating_viscosity(bearing)
    levels = ((math.radians(600.0), 2000.0, 0.5), (math.radians(0.5), 4000.0, 20.0))
    sums, diag = _accumulate(bearing, levels)

    d_i = d_o = n_total = n_low = 0.0
    for omega, q, dt in levels:
        n = omega * dt / (2.0 * math.pi)
        rpm = omega * 60.0 / (2.0 * math.pi)
        kappa = nu / (45000.0 * rpm ** -0.83 * (dm * 1e3) ** -0.5 * 1e-6)
        d_step = ((q / q_ci) ** (30.0 / 9.0) + (q / q_ce) ** (30.0 / 9.0)) ** 0.9
        p = c * d_step ** (1.0 / 3.0)
        a = a_iso_ball(kappa, ec * cu / p)["a_iso"]
        d_i += n * q ** 3 / (a * 1e6 * q_ci ** 3)
        d_o += n * q ** 3 / (a * 1e6 * q_ce ** 3)
        n_total += n
        n_low += n if kappa < 0.1 else 0.0
    assert 0.0 < n_low < n_total          # the second level is below ISO 281's κ range
    want = n_total / (d_i ** (10.0 / 9.0) + d_o ** (10.0 / 9.0)) ** 0.9
    out = modified_cycle_outputs(bearing, sums, math.nan)
    assert out["rating_life_L_nm"] == pytest.approx(want, rel=1e-9)
    assert out["kappa_below_scope_fraction"] == pytest.approx(n_low / n_total, rel=1e-9)
    assert diag[SLOT["a_iso"]] == pytest.approx(a, rel=1e-12)     # the last level's


def test_one_level_cycle_is_a_iso_times_l10r():
    """At one constant level the cycle's L_nm is a_ISO·L10r exactly (the unmodified sums
    give L10r), and a_iso_cycle reads that a_ISO back."""
    from rvcore.standards.iso16281 import duty_cycle_life

    bearing = section_bearing(8, alpha=math.radians(25.0))
    sums, diag = _accumulate(bearing, ((math.radians(120.0), 3000.0, 1.0),))
    l10r = duty_cycle_life(bearing, sums)["rating_life_L10r"]
    out = modified_cycle_outputs(bearing, sums, l10r)
    a = diag[SLOT["a_iso"]]
    assert 0.1 < a < 50.0
    assert out["rating_life_L_nm"] == pytest.approx(a * l10r, rel=1e-12)
    assert out["a_iso_cycle"] == pytest.approx(a, rel=1e-12)
    assert out["kappa_below_scope_fraction"] == 0.0


# --------------------------------------------------------------------------- the smallest film
def _arc_scratch(ue, q, delta):
    """A row's scratch (rvcore.dynamics.races) whose first arc has contacts of entrainment
    speeds ``ue`` [m/s], loads ``q`` [N] and penetrations ``delta`` [m]: balls at rest on
    the axis, normal x̂, slip −2·u_e along ŷ, so that the mean surface speed is u_e."""
    buf = np.zeros(R.SCRATCH_SIZE)
    out = buf[R.arc(0):R.arc(1)]
    n = len(q)
    buf[R.G_INV_RHO_B * R.W:R.G_INV_RHO_B * R.W + n] = 1.0
    for field, values in ((R.C_NX, 1.0), (R.C_UY, -2.0 * np.asarray(ue)), (R.C_Q, q), (R.C_DELTA, delta)):
        out[field * R.W:field * R.W + n] = values
    return buf, out


@njit
def _every_contact(buf, out, nz, arcs, h):
    """The film of every loaded contact of the scratch's first arc (``_arc_scratch``), its
    minimum taken over all of them: (log h_c, log λ)."""
    lh_min, ll_min = math.inf, math.inf
    for j in range(nz):
        delta, q = out[R.C_DELTA * R.W + j], out[R.C_Q * R.W + j]
        if delta <= 0.0 or q <= 0.0:
            continue
        ue = R.entrainment_speed(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, h, 0.0, 0.0, 1.0, 0.0,
                                 out[R.C_UY * R.W + j], 0.0, 0.0, 1.0, 0.0, 0.0)
        lu = math.log(ue) if ue > 0.0 else -math.inf
        lq = math.log(q)
        lh = arcs[0, A_LOG_HC1] + HC_EXP_U * lu + HC_EXP_W * lq
        ll = arcs[0, A_LOG_LAM1] + HM_EXP_U * lu + HM_EXP_W * lq
        if lh < lh_min:
            lh_min = lh
        if ll < ll_min:
            ll_min = ll
    return lh_min, ll_min


@njit
def _pruned(buf, out, nz, arcs, h):
    return R.smallest_film(buf, out, nz, arcs, 0, h)


@settings(max_examples=150, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 51), u_spread=st.sampled_from([0.0, 1e-12, 1e-6, 1e-3, 0.3]),
       q_spread=st.sampled_from([0.0, 1e-12, 1e-6, 1e-2, 0.9]), open_share=st.sampled_from([0.0, 0.3, 1.0]),
       stopped=st.booleans())
def test_the_smallest_film_is_the_minimum_over_every_loaded_contact_bit_for_bit(seed, n, u_spread, q_spread,
                                                                                open_share, stopped):
    """`races.smallest_film` takes the logarithms only of the contacts that can hold the
    smallest film (module Notes there); its result must be, bit for bit, the minimum of
    Hamrock–Dowson's log h_c and log λ over every loaded contact, computed here contact by
    contact: near ties in speed and load, open contacts, a contact at rest (no film)."""
    rng = np.random.default_rng(seed)
    ue = 2.0 * (1.0 + u_spread * rng.uniform(-1.0, 1.0, n))
    q = 3000.0 * (1.0 - q_spread * rng.uniform(0.0, 1.0, n))
    delta = np.where(rng.uniform(size=n) < open_share, -1e-6, 1e-5)
    if stopped:
        ue[rng.integers(n)] = 0.0
    buf, out = _arc_scratch(ue, q, delta)
    arcs = np.zeros((1, 12))
    arcs[0, A_LOG_HC1], arcs[0, A_LOG_LAM1] = -16.2, 2.3
    got = _pruned(buf, out, n, arcs, 0.0115)
    want = _every_contact(buf, out, n, arcs, 0.0115)
    assert np.array([got]).tobytes() == np.array([want]).tobytes(), (got, want)
