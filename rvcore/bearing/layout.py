"""A Bearing compiled into flat float arrays for the numba kernels.

The kernels take no Python objects, so everything they need is packed here once per
case: global scalars in ``params``, one line per row in ``rows``, one line per groove arc
in ``arcs``, and the pocket angles in ``pockets``. Index constants name the columns.

State vector layout (all SI)::

    [0:10]   inner ring  x, y, z, tilt_x, tilt_y, vx, vy, vz, tilt_rate_x, tilt_rate_y
    per row, at rows[r, R_CAGE0]:
    [+0:8]   cage        x, y, z, angle, vx, vy, vz, angular speed
    per ball, at rows[r, R_BALL0] + 9·j:
    [+0:9]   ball        x, y, z, vx, vy, vz, wx, wy, wz
    after the rows, a flexible ring's modal amplitudes and rates (rvcore.dynamics.ring_modes)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import hertz
from .laws import FRICTION_LAW_SIZE, LUBRICATED_LAW, pack_ehl_traction_law, pack_friction_law
from .lubricant import contact_lubricant, contamination_of, operating_viscosity
from .imperfections import MAX_WAVINESS_TERMS, realize
from .geometry import (INNER, OUTER, Bearing, arc_geometry, ball_inertia, ball_mass,
                       cage_mass_properties, inner_ring_mass_properties)

RING_STATES = 10
CAGE_STATES = 8
BALL_STATES = 9

# params columns
# (the applied loads, the tilting moment and the load's direction are not here: they are
# channels of the resolved profile, rvcore.profile.CH_*, read by the kernels at each t)
P_RING_M, P_RING_IP, P_RING_IT = 0, 1, 2
P_DAMP_C, P_DAMP_D = 3, 4
P_POCKET_C, P_LAND_C = 5, 6
P_DAMPING = 7                      # 1: contact damping on
P_GX, P_GY, P_GZ = 8, 9, 10        # gravitational acceleration in the bearing frame [m s^-2]
P_TILT_HELD = 11                   # 1: the inner ring's tilts are held at 0 (InnerRing.tilt "held")
#: The friction law's record (rvcore.bearing.laws.pack_friction_law) from this column on.
P_LAW = 12
#: The lubricant and the ratings the per-step film and modified life need, after the law's
#: record (rvcore.recording.plan.fill_state_signals; every bearing has a lubricant): the
#: operating kinematic viscosity ν [m² s⁻¹] (rvcore.bearing.lubricant.operating_viscosity),
#: the first row's pitch diameter d_m [m], e_C·C_u [N] (ISO 281 clause 9; NaN: not rated),
#: the EP flag and e_C [-], C_r [N], and a row's contact load ratings Q_ci, Q_ce [N]
#: (ISO/TS 16281; NaN: not rated), and the composite roughness σ [m].
(P_LUB_NU, P_LUB_DM, P_LUB_ECCU, P_LUB_EP, P_LUB_EC, P_LUB_C, P_LUB_QCI, P_LUB_QCE, P_LUB_SIGMA) = range(
    P_LAW + FRICTION_LAW_SIZE, P_LAW + FRICTION_LAW_SIZE + 9)
N_PARAMS = P_LAW + FRICTION_LAW_SIZE + 9

# rows columns
(R_Z, R_BALL0, R_CAGE0, R_PITCH_R, R_ZROW, R_HALF_D, R_MB, R_IB, R_POCKET_R, R_POCKET_K,
 R_POCKET_PC, R_CAGE_M, R_CAGE_I, R_CAGE_RI, R_CAGE_RO, R_LAND_CLEAR, R_LAND_K, R_GUIDE,
 R_ARC0, R_NARC, R_POCKET0) = range(21)
# the row's imperfections (rvcore.bearing.imperfections, realized): a flag (0: perfect, every
# term below skipped), each raceway's eccentricity as a vector in its ring's frame (e·cos
# φ_e, e·sin φ_e: no trigonometry in the right-hand side), its waviness terms (order,
# amplitude, phase; MAX_WAVINESS_TERMS a raceway, inner then outer from R_WAVE0)
(R_IMPERFECT, R_ECC_I_X, R_ECC_I_Y, R_ECC_O_X, R_ECC_O_Y, R_NWAVE_I, R_NWAVE_O, R_WAVE0) = range(21, 29)
# then the axial runout: each raceway's tilted plane as a vector (a·cos φ_a, a·sin φ_a) and
# its axial harmonics (order, amplitude, phase; inner then outer from R_AXWAVE0)
(R_AX_I_X, R_AX_I_Y, R_AX_O_X, R_AX_O_Y, R_NAXWAVE_I, R_NAXWAVE_O) = range(
    R_WAVE0 + 2 * 3 * MAX_WAVINESS_TERMS, R_WAVE0 + 2 * 3 * MAX_WAVINESS_TERMS + 6)
R_AXWAVE0 = R_NAXWAVE_O + 1
N_ROWCOLS = R_AXWAVE0 + 2 * 3 * MAX_WAVINESS_TERMS

# pockets columns (one line a ball): the pocket's azimuth, the ball's diameter deviation [m]
PK_COS, PK_SIN, PK_BALL_DD = 0, 1, 2
N_PKCOLS = 3

# arcs columns; A_RX, A_EEFF, A_ELL are the arc's Hertz contact as the film needs it (the
# effective radius in the rolling direction R_x [m], the effective modulus E' [Pa] and the
# ellipticity k [-]; rvcore.contact.laws.contact_film); A_LOG_HC1 and A_LOG_LAM1 the logarithms
# of the bearing's lubricant's Hamrock-Dowson central film [m] and λ = h_min/σ [-] at that
# contact at 1 N and 1 m/s, for the per-step film signals: NaN here, filled by
# rvcore.contact.film.with_film_columns (the formula's layer is above this one)
A_RING, A_CR, A_CZ, A_RMH, A_K, A_PC3, A_SIDE, A_RX, A_EEFF, A_ELL, A_LOG_HC1, A_LOG_LAM1 = range(12)
N_ARCCOLS = 12
#: Raceway arcs a row may have, inner and outer together (a four-point row has four): the
#: right-hand side keeps every arc's contacts of a row at once (:mod:`rvcore.dynamics.races`).
MAX_ROW_ARCS = 4
#: Balls a row may have: the right-hand side keeps a row's ball contacts in a scratch of
#: this width (:mod:`rvcore.dynamics.races`).
MAX_ROW_BALLS = 256

GUIDE_BALL, GUIDE_OUTER_LAND = 0, 1


@dataclass(frozen=True)
class CompiledBearing:
    """Arrays for the kernels plus the Hertz contacts they were built from."""

    params: np.ndarray
    rows: np.ndarray
    arcs: np.ndarray
    pockets: np.ndarray  # (n_balls_total, 2): cos, sin of 2πj/Z
    n_states: int
    n_balls: int
    hertz_contacts: tuple  # ((row, ring, arc index, HertzContact), ...)

    def stiffest_arc(self, r: int):
        """K [N m^-1.5] of row ``r``'s stiffest race arc: the contact the integrators' steps,
        the IMEX tolerances and the modes' explicit rates are sized on."""
        row = self.rows[r]
        a0, na = int(row[R_ARC0]), int(row[R_NARC])
        return self.arcs[a0:a0 + na, A_K].max()


def compile_bearing(bearing: Bearing, *, friction: bool = True, damping: bool = True,
                    gravity: bool = True) -> CompiledBearing:
    """Pack ``bearing`` for the kernels; Hertz constants are solved here, once.

    ``gravity`` False zeroes the bearing's gravity vector (docs/model.md §9 conservation checks).
    The loads, the tilting moment and the load's direction are not compiled in: they are
    the profile's channels (:meth:`rvcore.profile.Profile.resolve`).
    """
    bearing = realize(bearing)   # rows realized already keep their draw (rvcore.simulation.run.run_case)
    m_ring, ip_ring, it_ring = inner_ring_mass_properties(bearing)
    c = bearing.contact
    params = np.zeros(N_PARAMS)
    params[[P_RING_M, P_RING_IP, P_RING_IT]] = m_ring, ip_ring, it_ring
    params[P_DAMP_C], params[P_DAMP_D] = c.damping, c.damping_depth
    params[P_POCKET_C], params[P_LAND_C] = c.pocket_damping, c.land_damping
    params[P_LAW:P_LAW + FRICTION_LAW_SIZE] = pack_friction_law(c.mu_static, c.v_static, c.mu_dynamic,
                                                                c.v_dynamic, on=friction, kind=c.law,
                                                                ehl=_ehl_record(bearing))
    params[P_DAMPING] = 1.0 if damping else 0.0
    if gravity:
        params[[P_GX, P_GY, P_GZ]] = bearing.gravity
    params[P_TILT_HELD] = 1.0 if bearing.inner_ring.tilt == "held" else 0.0
    params[P_LUB_NU:P_LUB_SIGMA + 1] = _lubrication_record(bearing)

    e_race = hertz.effective_modulus(bearing.ring_material.youngs_modulus, bearing.ring_material.poisson_ratio,
                                     bearing.ball_material.youngs_modulus, bearing.ball_material.poisson_ratio)
    rows = np.zeros((len(bearing.rows), N_ROWCOLS))
    arcs, contacts, pockets = [], [], []
    offset = RING_STATES
    n_balls = 0
    for r, row in enumerate(bearing.rows):
        cage = row.cage
        e_pocket = hertz.effective_modulus(bearing.ball_material.youngs_modulus, bearing.ball_material.poisson_ratio,
                                           cage.material.youngs_modulus, cage.material.poisson_ratio)
        # a ball-guided cage has spherical pockets (rvcore.contact.laws.spherical_pocket_penetration)
        pocket = (hertz.pocket_contact if cage.guidance == "outer-land" else hertz.spherical_pocket_contact)(
            row.ball_diameter, row.ball_diameter + cage.pocket_clearance, e_pocket)
        m_cage, i_cage = cage_mass_properties(row)
        rows[r, R_Z] = row.ball_count
        rows[r, R_CAGE0] = offset
        rows[r, R_BALL0] = offset + CAGE_STATES
        offset += CAGE_STATES + BALL_STATES * row.ball_count
        rows[r, R_PITCH_R] = row.pitch_diameter / 2
        rows[r, R_ZROW] = row.axial_position
        rows[r, R_HALF_D] = row.ball_diameter / 2
        rows[r, R_MB] = ball_mass(row, bearing.ball_material)
        rows[r, R_IB] = ball_inertia(row, bearing.ball_material)
        rows[r, R_POCKET_R] = (row.ball_diameter + cage.pocket_clearance) / 2
        rows[r, R_POCKET_K] = pocket.stiffness
        rows[r, R_POCKET_PC] = pocket.pressure_coefficient**3
        rows[r, R_CAGE_M], rows[r, R_CAGE_I] = m_cage, i_cage
        rows[r, R_CAGE_RI], rows[r, R_CAGE_RO] = cage.inner_diameter / 2, cage.outer_diameter / 2
        rows[r, R_LAND_CLEAR] = cage.land_clearance
        rows[r, R_LAND_K] = cage.land_stiffness
        rows[r, R_GUIDE] = GUIDE_OUTER_LAND if cage.guidance == "outer-land" else GUIDE_BALL
        if row.ball_count > MAX_ROW_BALLS:
            raise ValueError(f"row {r}: {row.ball_count} balls; at most {MAX_ROW_BALLS}")
        if len(row.inner_arcs) + len(row.outer_arcs) > MAX_ROW_ARCS:
            raise ValueError(f"row {r}: {len(row.inner_arcs) + len(row.outer_arcs)} raceway arcs; "
                             f"at most {MAX_ROW_ARCS} (two a groove)")
        rows[r, R_ARC0] = len(arcs)
        rows[r, R_POCKET0] = n_balls
        for ring, ring_arcs in ((INNER, row.inner_arcs), (OUTER, row.outer_arcs)):
            for k, arc in enumerate(ring_arcs):
                cr, cz, rmh, side = arc_geometry(row, arc, ring)
                hc = hertz.race_contact(row.ball_diameter, row.pitch_diameter, arc.curvature_ratio,
                                        arc.contact_angle, "inner" if ring == INNER else "outer", e_race)
                r_x, _ = hertz.effective_radii(hc)
                arcs.append((ring, cr, cz, rmh, hc.stiffness, hc.pressure_coefficient**3, side, r_x,
                             hc.effective_modulus, hc.ellipticity, math.nan, math.nan))
                contacts.append((r, ring, k, hc))
        rows[r, R_NARC] = len(arcs) - rows[r, R_ARC0]
        imp = row.imperfections
        _pack_imperfections(rows[r], imp)
        dd = imp.ball_diameter_deviation or (0.0,) * row.ball_count
        for j in range(row.ball_count):
            a = 2 * math.pi * j / row.ball_count
            pockets.append((math.cos(a), math.sin(a), dd[j]))
        n_balls += row.ball_count
    return CompiledBearing(params, rows, np.array(arcs, dtype=float), np.array(pockets, dtype=float),
                           offset, n_balls, tuple(contacts))


def _lubrication_record(bearing: Bearing):
    """``params[P_LUB_NU:P_LUB_SIGMA + 1]`` of ``bearing`` (their comment above); a rating the
    standards do not give for this bearing is NaN, and so are the modified lives from it."""
    from ..standards.iso16281 import LifeError, bearing_contact_ratings, dynamic_load_rating
    from ..standards.iso281_modified import fatigue_load_limit_ball
    from ..standards.iso76 import StaticRatingError, bearing_static_load_rating

    dm = bearing.rows[0].pitch_diameter
    ec = contamination_of(bearing)
    try:
        c = dynamic_load_rating(bearing)
        q_ci, q_ce = bearing_contact_ratings(bearing)
    except LifeError:
        c = q_ci = q_ce = math.nan
    try:
        cu = fatigue_load_limit_ball(bearing_static_load_rating(bearing), dm)
    except (StaticRatingError, ValueError):
        cu = math.nan
    return (operating_viscosity(bearing), dm, ec * cu, 1.0 if bearing.lubricant.ep_additives else 0.0, ec, c,
            q_ci, q_ce, contact_lubricant(bearing)[2])


def _ehl_record(bearing: Bearing):
    """The lubricated law's sub-record of ``bearing`` (None for a law without one).

    Notes
    -----
    The lubricant's ``η0``, ``α`` and σ from :func:`rvcore.bearing.lubricant.contact_lubricant`;
    the boundary friction ``μ_b``, ``v_b`` are the bearing's ``friction.mu_static`` and
    ``friction.v_static`` (the study law's rise, so that a contact without film behaves as
    the study's law below v_s); the slope cap is the study law's slope at zero slip,
    ``1.5·μ_s/v_s``, so that the lubricated case's step equals the dry one's
    (:mod:`rvcore.contact.traction_ehl`, Notes, "Slope cap"). The other parameters take
    their defaults (:func:`rvcore.bearing.laws.pack_ehl_traction_law`).
    """
    c = bearing.contact
    if c.law != LUBRICATED_LAW:
        return None
    eta0, alpha, sigma = contact_lubricant(bearing)
    return pack_ehl_traction_law(eta0, alpha, mu_b=c.mu_static, v_b=c.v_static,
                                 slope_cap=1.5 * c.mu_static / c.v_static, sigma=sigma)


def _pack_imperfections(line, imp) -> None:
    """Write a row's realized imperfections into its ``rows`` line (layout above)."""
    line[R_IMPERFECT] = 0.0 if imp.perfect else 1.0
    for cx, cy, e, a in ((R_ECC_I_X, R_ECC_I_Y, imp.inner_eccentricity, imp.inner_eccentricity_angle),
                         (R_ECC_O_X, R_ECC_O_Y, imp.outer_eccentricity, imp.outer_eccentricity_angle)):
        line[cx], line[cy] = e * math.cos(a), e * math.sin(a)
    for cx, cy, a, phi in ((R_AX_I_X, R_AX_I_Y, imp.inner_axial_amplitude, imp.inner_axial_angle),
                           (R_AX_O_X, R_AX_O_Y, imp.outer_axial_amplitude, imp.outer_axial_angle)):
        line[cx], line[cy] = a * math.cos(phi), a * math.sin(phi)
    for n_i, n_o, c0, inner, outer in (
            (R_NWAVE_I, R_NWAVE_O, R_WAVE0, imp.inner_waviness, imp.outer_waviness),
            (R_NAXWAVE_I, R_NAXWAVE_O, R_AXWAVE0, imp.inner_axial_waviness, imp.outer_axial_waviness)):
        line[n_i], line[n_o] = len(inner), len(outer)
        for ring, terms in enumerate((inner, outer)):
            for k, w in enumerate(terms):
                c = c0 + 3 * (ring * MAX_WAVINESS_TERMS + k)
                line[c], line[c + 1], line[c + 2] = w.order, w.amplitude, w.phase


def nominal_state(model: CompiledBearing) -> np.ndarray:
    """Everything centred and at rest: balls at their pocket centres on the pitch circle."""
    y = np.zeros(model.n_states)
    for r in range(model.rows.shape[0]):
        row = model.rows[r]
        b0, z, p0 = int(row[R_BALL0]), int(row[R_Z]), int(row[R_POCKET0])
        for j in range(z):
            cs, sn = model.pockets[p0 + j, PK_COS], model.pockets[p0 + j, PK_SIN]
            b = b0 + BALL_STATES * j
            y[b:b + 3] = row[R_PITCH_R] * cs, row[R_PITCH_R] * sn, row[R_ZROW]
    return y


def body_name(model: CompiledBearing, state_index: int) -> str:
    """Human name of the body that owns ``state_index`` ("ball 12 of row 0", "cage of row 0", ...)."""
    if state_index < RING_STATES:
        return "inner ring"
    for r in range(model.rows.shape[0]):
        c0, b0, z = int(model.rows[r, R_CAGE0]), int(model.rows[r, R_BALL0]), int(model.rows[r, R_Z])
        if c0 <= state_index < b0:
            return f"cage of row {r}"
        if b0 <= state_index < b0 + BALL_STATES * z:
            return f"ball {(state_index - b0) // BALL_STATES} of row {r}"
    return "unknown body"
