"""The profile's tilting-moment and load-direction channels (rvcore.profile CH_MOMENT,
CH_DIRECTION) as the dynamics read them.

Checks, each against a reference derived here:

- the moment channel a profile leaves out is M0·F_r(t)/F_r0, evaluated here from the
  radial channel's own breakpoints (relative and absolute radial tables);
- the load's direction read from a channel is the operating point's ``load_angle``
  plus the channel's offset: a constant offset ψ gives the history of load_angle = ψ;
  and turning the load by one ball spacing through the channel alone turns the response
  with it (rotation symmetry, weightless), so the kernels really read the channel;
- the work potential of the channels' moment in ``potential_energy`` is the one whose
  gradient is the moment ``M·(−sin ψ, cos ψ, 0)`` rhs applies to the ring;
- a moment channel (no radial load) tilts the ring about (−sin ψ, cos ψ, 0) in the sense
  of the moment, and the damped response settles on the quasi-static tilt
  (``rvcore.statics.equilibrium.solve_statics(..., moment=M, load_angle=ψ)``).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pipeline.schema import load_bearing
from rvcore.simulation.run import run_case
from rvcore.simulation.initial_state import initial_state
from rvcore.simulation.settings import SolverSettings
from rvcore.dynamics.energy import potential_energy
from rvcore.dynamics.rhs import new_diagnostics, rhs
from rvcore.bearing.layout import compile_bearing
from rvcore.profile import (CH_DIRECTION, CH_MOMENT, CH_RADIAL, N_CHANNELS, Channel, OperatingPoint,
                            Profile, scaled_study_profile, study_profile)
from rvcore.statics.equilibrium import solve_statics
from tests.core.physics_cases import constant_profile, section_bearing

REDUCED = Path(__file__).resolve().parents[2] / "sweeps" / "bearings" / "reduced-test.toml"
SPEED = math.radians(660.0)
PHASES = (("startup", 0.0, 0.01), ("steady", 0.01, 0.02), ("deceleration", 0.02, 0.03))


def _radial_by_hand(ch: Channel, t: float) -> float:
    """Linear interpolation of a breakpoint table, held at its ends (written out here)."""
    times, values = ch.times, ch.values
    if t <= times[0]:
        return values[0]
    for k in range(len(times) - 1):
        if times[k] <= t <= times[k + 1]:
            return values[k] + (values[k + 1] - values[k]) * (t - times[k]) / (times[k + 1] - times[k])
    return values[-1]


# ------------------------------------------------------------------ the defaults


@pytest.mark.parametrize("relative", [True, False])
def test_moment_channel_left_out_follows_the_radial_load(relative):
    """M(t) = M0·F_r(t)/F_r0 at every instant, for a relative and an absolute radial table."""
    f_r0, m0 = 20e3, 750.0
    times = (0.0, 0.3, 1.1, 4.3, 4.6)
    fractions = (0.0, 1.0, 0.4, 1.0, 0.0)
    radial = (Channel(times, fractions) if relative
              else Channel(times, tuple(f * f_r0 for f in fractions), relative=False))
    const = Channel((0.0,), (1.0,))
    prof = Profile("p", radial, const, const, (("startup", 0.0, 1.0), ("steady", 1.0, 2.0),
                                               ("deceleration", 2.0, 4.6)), 4.6)
    res = prof.resolve(OperatingPoint(1.0, f_r0, 1e3, moment=m0))
    for t in np.linspace(-0.1, 4.7, 97):
        f_r = _radial_by_hand(Channel(times, tuple(f * f_r0 for f in fractions)), float(t))
        assert res.value(CH_RADIAL, t) == pytest.approx(f_r, rel=1e-12, abs=1e-9)
        assert res.value(CH_MOMENT, t) == pytest.approx(m0 * f_r / f_r0, rel=1e-12, abs=1e-9)
    # no moment on the operating point: none in the profile
    res0 = prof.resolve(OperatingPoint(1.0, f_r0, 1e3))
    assert np.all(res0.moment[1] == 0.0)


def test_direction_channel_left_out_is_the_load_angle():
    res = study_profile().resolve(OperatingPoint(1.0, 1e3, 1e3, load_angle=0.8))
    for t in (0.0, 1.0, 4.6):
        assert res.value(CH_DIRECTION, t) == 0.8


def test_a_given_moment_channel_is_its_own_and_the_scaled_study_keeps_it():
    own = Channel((0.0, 0.2), (0.0, 3e3), relative=False)
    turn = Channel((0.0, 0.2), (0.0, 0.5), relative=False)
    p = study_profile()
    p = Profile(p.name, p.radial_load, p.axial_load, p.speed, p.phases, p.duration, "", own, turn)
    res = p.resolve(OperatingPoint(1.0, 1e3, 1e3, moment=99.0, load_angle=0.25))
    assert res.value(CH_MOMENT, 0.1) == pytest.approx(1.5e3)
    assert res.value(CH_DIRECTION, 0.1) == pytest.approx(0.25 + 0.25)
    q = scaled_study_profile(0.5)
    assert q.moment is None and q.load_direction is None
    r = Profile(*[getattr(p, f) for f in ("name", "radial_load", "axial_load", "speed", "phases", "duration")])
    assert r.resolve(OperatingPoint(1.0, 1e3, 1e3)).arrays()[0].shape[0] == N_CHANNELS


def test_a_fraction_of_an_angle_is_refused():
    p = study_profile()
    with pytest.raises(ValueError, match="absolute angle"):
        Profile(p.name, p.radial_load, p.axial_load, p.speed, p.phases, p.duration,
                load_direction=Channel((0.0,), (0.5,), relative=True))


# ------------------------------------------------------------------ the direction


def _with_direction(prof: Profile, offset: Channel) -> Profile:
    return Profile(prof.name, prof.radial_load, prof.axial_load, prof.speed, prof.phases, prof.duration,
                   prof.description, None, offset)


def test_constant_direction_channel_is_the_load_angle():
    """The reduced test bearing (in gravity) on a 30 ms cycle: a direction channel of
    constant ψ with load_angle 0 is the same problem as load_angle = ψ, so δ_r (taken
    along ψ) and the ring's path agree to round-off."""
    bearing = load_bearing(REDUCED)
    psi = 0.7
    prof = Profile("short", Channel((0.0, 0.005), (0.0, 1.0)), Channel((0.0, 0.005), (0.0, 1.0)),
                   Channel((0.0,), (1.0,)), PHASES, 0.03)
    settings = SolverSettings(output_rate=1e4)
    a = run_case(bearing, prof, OperatingPoint(SPEED, 20e3, 8e3, load_angle=psi), settings)
    b = run_case(bearing, _with_direction(prof, Channel((0.0,), (psi,), relative=False)),
                 OperatingPoint(SPEED, 20e3, 8e3), settings)
    dr = a.series["radial_displacement"]
    assert np.abs(dr).max() > 1e-5                      # a real radial response
    np.testing.assert_allclose(b.series["radial_displacement"], dr, rtol=0, atol=1e-9 * np.abs(dr).max())
    for name in ("inner_ring_x", "inner_ring_y"):
        np.testing.assert_allclose(b.series[name], a.series[name], rtol=0, atol=1e-9 * np.abs(dr).max())
    assert np.all(b.series["load_direction"] == psi)


def test_direction_channel_turns_the_response():
    """Weightless, turning F_r by one ball spacing through the channel (load_angle 0)
    turns the ring's path by that angle and leaves δ_r (now along the turned load)
    unchanged up to the start's round-off (see test_dynamics' load-angle check; a real
    asymmetry, or a kernel that ignored the channel, differs by order 1)."""
    z = 12
    bearing = section_bearing(z)
    phi = 2 * math.pi / z
    prof = constant_profile(0.005, 0.04)
    settings = SolverSettings(output_rate=1e4, gravity=False)
    op = OperatingPoint(SPEED, 20e3, 10e3)
    a = run_case(bearing, prof, op, settings)
    b = run_case(bearing, _with_direction(prof, Channel((0.0,), (phi,), relative=False)), op, settings)
    xa, ya = a.series["inner_ring_x"], a.series["inner_ring_y"]
    scale = np.hypot(xa, ya).max()
    c, s = math.cos(phi), math.sin(phi)
    tol = 1e-4
    assert np.abs(c * xa - s * ya - b.series["inner_ring_x"]).max() < tol * scale
    assert np.abs(s * xa + c * ya - b.series["inner_ring_y"]).max() < tol * scale
    assert np.abs(a.series["radial_displacement"] - b.series["radial_displacement"]).max() < tol * scale


# ------------------------------------------------------------------ the moment


def test_moment_and_direction_in_rhs_are_minus_the_energy_gradient():
    """At rest, frictionless and undamped, the ring's tilt accelerations in rhs times I_t
    are −∂V/∂θ of potential_energy with the channels' M and ψ: both apply the moment
    M·(−sin ψ, cos ψ, 0), one as a force, one as its work potential."""
    from rvcore.bearing.layout import P_RING_IT

    bearing = section_bearing(8)
    model = compile_bearing(bearing, friction=False, damping=False, gravity=False)
    prof = Profile("m", Channel((0.0,), (1.0,)), Channel((0.0,), (1.0,)), Channel((0.0,), (0.0,)),
                   PHASES, 0.03, "", Channel((0.0,), (800.0,), relative=False),
                   Channel((0.0,), (0.9,), relative=False))
    res = prof.resolve(OperatingPoint(0.0, 5e3, 4e3, load_angle=0.3))
    table, meta = res.arrays()
    y = initial_state(model, res, 0.0)
    y[3] += 2e-5                     # off equilibrium, so both sides are far from zero
    y[4] -= 1e-5
    dy = np.zeros_like(y)
    diag, bdiag = new_diagnostics(model.rows.shape[0], model.n_balls)
    rhs(0.0, y, dy, model.params, model.rows, model.arcs, model.pockets, table, meta, diag, bdiag)

    def energy(yy):
        return potential_energy(0.0, yy, model.params, model.rows, model.arcs, model.pockets, table, meta)

    for k, slot in ((3, 8), (4, 9)):
        e = 1e-9
        yp, ym = y.copy(), y.copy()
        yp[k] += e
        ym[k] -= e
        moment = -(energy(yp) - energy(ym)) / (2 * e)
        assert abs(moment) > 10.0
        assert model.params[P_RING_IT] * dy[slot] == pytest.approx(moment, rel=1e-4, abs=1e-2)
    # and the moment's share of V alone is −M·a·θ with a = (−sin ψ, cos ψ), ψ = 0.3 + 0.9
    psi = 0.3 + 0.9
    a = np.array([-math.sin(psi), math.cos(psi)])
    no_moment = Profile("m0", *[getattr(prof, f) for f in ("radial_load", "axial_load", "speed", "phases",
                                                            "duration", "description")],
                        Channel((0.0,), (0.0,), relative=False), prof.load_direction)
    table0, meta0 = no_moment.resolve(OperatingPoint(0.0, 5e3, 4e3, load_angle=0.3)).arrays()
    share = energy(y) - potential_energy(0.0, y, model.params, model.rows, model.arcs, model.pockets,
                                         table0, meta0)
    assert share == pytest.approx(-800.0 * (a @ y[3:5]), rel=1e-9)


@pytest.mark.parametrize("psi", [0.0, 1.1])
def test_moment_channel_tilts_the_ring_like_the_statics(psi):
    """ω = 0, weightless, 5 kN thrust held; the moment channel ramps 0 → M over 5 ms with
    no radial load, along a direction channel ψ. The ring tilts about (−sin ψ, cos ψ)
    in the sense of M (a stiff support turns the way it is pushed), not about the
    normal axis, and settles on the quasi-static tilt.
    """
    m = 2e3
    bearing = section_bearing(12)
    t_end = 0.06
    prof = Profile("moment", Channel((0.0,), (0.0,)), Channel((0.0,), (1.0,)), Channel((0.0,), (0.0,)),
                   (("startup", 0.0, 0.02), ("steady", 0.02, 0.04), ("deceleration", 0.04, t_end)), t_end, "",
                   Channel((0.0, 0.005), (0.0, m), relative=False), Channel((0.0,), (psi,), relative=False))
    res = run_case(bearing, prof, OperatingPoint(0.0, 0.0, 5e3), SolverSettings(output_rate=1e4, gravity=False))
    st = solve_statics(bearing, 0.0, 5e3, m, psi, gravity=False)
    axis = np.array([-math.sin(psi), math.cos(psi)])
    normal = np.array([math.cos(psi), math.sin(psi)])
    st_tilt = np.asarray(st.displacement[3:5])
    # the statics' own sign: the tilt along the moment's axis, the same sense (12 discrete
    # balls make the tilt stiffness slightly anisotropic off a ball's azimuth: ~1 % across)
    assert st_tilt @ axis > 0 and abs(st_tilt @ normal) < 0.02 * np.linalg.norm(st_tilt)
    tilt = np.column_stack([res.series["inner_ring_tilt_x"], res.series["inner_ring_tilt_y"]])
    late = res.time >= 0.045
    assert np.all(tilt[late] @ axis > 0)
    assert np.abs(tilt[late] @ normal).max() < 0.02 * (st_tilt @ axis)
    # settled on the quasi-static tilt
    assert np.linalg.norm(tilt[late] - st_tilt, axis=1).max() < 0.02 * np.linalg.norm(st_tilt)
    # the moment channel is what was applied
    assert res.series["applied_moment"][-1] == pytest.approx(m)
    assert res.series["applied_moment"][0] == 0.0
