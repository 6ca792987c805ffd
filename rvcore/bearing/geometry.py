"""Bearing geometry and materials, SI in and SI out.

A bearing is one or more rows sharing one inner ring and one fixed outer ring. Each row
has its own balls, cage, pitch diameter, axial position and groove arcs (docs/model.md §2).

Groove arcs
-----------
Each groove cross-section is a list of circular arcs of radius ``f·D``. An arc is given by
its curvature ratio ``f`` and its *contact angle* ``α``: the direction, in the row's
cross-section plane (radial r, axial z), of the line through the centred ball along
which that arc touches it.

- outer-ring arc at ``α`` touches the centred ball in the direction ``u = (cos α, sin α)``
- inner-ring arc at ``α`` touches it in the direction ``−u``

so an (inner ``α``, outer ``α``) pair is one load line, and a positive ``α`` carries an
axial load that pushes the inner ring towards ``+z``. The arc centre sits on that line,

    C = P₀ − ((f − ½)·D − g)·u_contact ,    g = P_d / 4 ,

where ``P₀ = (d_m/2, z_row)`` is the centred ball and ``P_d`` the radial internal
clearance (free radial play of one ring against the other), so that each arc is ``g``
away from touching the centred ball. The penetration of a ball whose centre is ``P`` is

    δ = |P − C| − (f − ½)·D

for inner and outer arcs alike, with the normal along C→P.

- one arc per ring, α = 0: deep-groove raceway;
- one arc per ring, α ≠ 0: angular-contact raceway;
- two arcs per ring at ±α: four-point (gothic-arch) raceway. Each arc of a multi-arc
  ring is only real on its own side of the groove's mid-plane, recorded as ``side``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..hertz import INNER, OUTER  # noqa: F401 (the ring labels live with Hertz theory)
from .imperfections import PERFECT, Imperfections
from .laws import DRY_LAW
from .lubricant import (BALL_ROUGHNESS_DEFAULT, DENSITY_DEFAULT, PRESSURE_VISCOSITY_DEFAULT,
                        RACEWAY_ROUGHNESS_DEFAULT)

#: Standard acceleration of gravity [m s^-2] (CGPM 1901).
STANDARD_GRAVITY = 9.80665

#: Gravity vectors of the named mountings, in the bearing frame (z along the axis) [m s^-2].
#: A horizontal axis has gravity along −y; a vertical one along −z.
MOUNTINGS = {"horizontal": (0.0, -STANDARD_GRAVITY, 0.0),
             "vertical": (0.0, 0.0, -STANDARD_GRAVITY)}


@dataclass(frozen=True)
class Material:
    """An isotropic elastic solid.

    Parameters
    ----------
    density : float
        [kg m^-3]
    youngs_modulus : float
        [Pa]
    poisson_ratio : float
        [-]
    thermal_expansion : float
        Linear thermal expansion coefficient α_T [K^-1]; default 11.5e-6 K^-1, bearing
        steel (:data:`rvcore.bearing.thermal.STEEL_THERMAL_EXPANSION`). It enters only the
        operating clearance (:mod:`rvcore.bearing.thermal`).
    """

    density: float
    youngs_modulus: float
    poisson_ratio: float
    thermal_expansion: float = 11.5e-6


@dataclass(frozen=True)
class Arc:
    """One circular arc of a groove cross-section.

    Parameters
    ----------
    curvature_ratio : float
        ``f``: arc radius divided by ball diameter [-], > 0.5.
    contact_angle : float
        Direction of the arc's contact line with the centred ball [rad] (see module doc).
    """

    curvature_ratio: float
    contact_angle: float


@dataclass(frozen=True)
class Cage:
    """A rigid cage ring with cylindrical radial pockets at 2πj/Z.

    Parameters
    ----------
    inner_diameter, outer_diameter, width : float
        Envelope of the cage ring [m].
    pocket_clearance : float
        Pocket diameter minus ball diameter [m].
    land_clearance : float
        Radial gap between the cage and its guiding land at the centred cage [m].
    guidance : str
        ``"outer-land"`` (guided by the outer-ring land; cylindrical pockets with a radial
        axis) or ``"ball"`` (no land contact: spherical pockets on the pitch circle centre
        the cage on its balls, :func:`rvcore.contact.laws.spherical_pocket_penetration`).
    material : Material
    land_stiffness : float
        Cage–land normal stiffness in ``Q = K·δ^1.5`` [N m^-1.5]. The land contact is a
        line contact, so Hertz point theory does not give it; it is a stated assumption.
    """

    inner_diameter: float
    outer_diameter: float
    width: float
    pocket_clearance: float
    land_clearance: float
    guidance: str
    material: Material
    land_stiffness: float


@dataclass(frozen=True)
class Row:
    """One row of balls with its grooves and cage.

    Parameters
    ----------
    ball_count : int
    ball_diameter : float
        [m]
    pitch_diameter : float
        [m]
    axial_position : float
        Axial coordinate of the row's centre plane [m].
    inner_arcs, outer_arcs : tuple of Arc
    cage : Cage
    radial_clearance : float
        Radial internal clearance P_d (free radial play) [m]; negative for an
        interference (a radially preloaded row).
    inner_offset : float
        Axial shift of the row's inner raceway from its nominal place [m]: a pair's share
        of the preload offset (:mod:`rvcore.statics.preload`), 0 for a free row.
    imperfections : rvcore.bearing.imperfections.Imperfections or RealizedImperfections
        Raceway eccentricity and waviness, ball size variation (docs/model.md §12); perfect
        by default.
    """

    ball_count: int
    ball_diameter: float
    pitch_diameter: float
    axial_position: float
    inner_arcs: tuple[Arc, ...]
    outer_arcs: tuple[Arc, ...]
    cage: Cage
    radial_clearance: float = 0.0
    inner_offset: float = 0.0
    imperfections: Imperfections = PERFECT

    @property
    def nominal_contact_angle(self) -> float:
        """Contact angle of the first outer arc [rad] (the row's nominal angle)."""
        return self.outer_arcs[0].contact_angle


#: How the inner ring may tilt (:attr:`InnerRing.tilt`).
TILT_CONDITIONS = ("free", "held")


@dataclass(frozen=True)
class InnerRing:
    """Mass properties of the inner ring.

    Parameters
    ----------
    shoulder_diameter : float
        Outer diameter of the inner ring's shoulders [m]; with the bore and width it sets
        the ring's mass (the groove is neglected).
    attached_mass : float
        Mass of reducer parts bolted to the inner ring [kg].
    attached_inertia : float
        Their transverse moment of inertia about the bearing centre [kg m^2].
    tilt : str
        How the ring is held about its two tilt axes (docs/model.md §11): ``"free"`` (zero
        moment: a single row under a radial load tilts and loads fewer balls harder) or
        ``"held"`` (kept square, as a shaft on a second support holds it; the statics,
        the stiffness and the dynamics fix both tilts at 0 and report the reaction
        moment that holds them).
    """

    shoulder_diameter: float
    attached_mass: float = 0.0
    attached_inertia: float = 0.0
    tilt: str = "free"

    def __post_init__(self):
        if self.tilt not in TILT_CONDITIONS:
            raise ValueError(f"inner ring tilt {self.tilt!r} is not one of {', '.join(TILT_CONDITIONS)}")


@dataclass(frozen=True)
class ContactLaw:
    """Normal-contact damping (IMPACT type) and the friction law of docs/model.md §3–4.

    Parameters
    ----------
    damping : float
        ``c_max`` of ball–race contacts [N s m^-1].
    damping_depth : float
        ``d_max``: penetration over which the damping ramps in [m].
    pocket_damping, land_damping : float
        ``c_max`` of ball–pocket and cage–land contacts [N s m^-1].
    mu_static, mu_dynamic : float
        Friction coefficients [-].
    v_static, v_dynamic : float
        Slip speeds of the static and dynamic regimes [m s^-1].
    law : str
        The friction law by name, one of :data:`rvcore.bearing.laws.FRICTION_LAWS`:
        ``coulomb_step`` (the study's, the default) or ``ehl_bair_winer`` (lubricated,
        from the film; its boundary friction is ``mu_static`` rising over ``v_static``).
    """

    damping: float
    damping_depth: float
    pocket_damping: float
    land_damping: float
    mu_static: float = 0.1
    v_static: float = 0.1
    mu_dynamic: float = 0.02
    v_dynamic: float = 1.0
    law: str = DRY_LAW


@dataclass(frozen=True)
class Lubricant:
    """The lubricant (of a grease: its base oil), :mod:`rvcore.bearing.lubricant` resolves it.

    Parameters
    ----------
    kinematic_viscosity : float or None
        An override: the kinematic viscosity at the operating temperature [m^2 s^-1]. None
        (the default): it follows from the base oil and the operating temperature
        (ASTM D341 / Walther, :func:`rvcore.bearing.lubricant.operating_viscosity`).
    method : str
        How the bearing is lubricated: ``"grease"`` (the default, an assumption),
        ``"oil-mist"``, ``"oil-bath"`` or ``"oil-jet"`` (Palmgren's ``f_0`` table).
    grade : int or None
        ISO VG grade of the base oil (ISO 3448: its ν40 midpoint in mm^2/s) [-]; None with
        no ``viscosity_40``: ISO VG 68, an assumption (the study names no lubricant).
    viscosity_40, viscosity_100 : float or None
        Kinematic viscosities of the base oil at 40 °C and 100 °C [m^2 s^-1]; None: from
        ``grade`` (ν40) and :data:`rvcore.bearing.lubricant.VG68_VISCOSITY_100` (ν100 of
        the default VG 68, VI 94).
    density : float
        Density of the base oil [kg m^-3] (:data:`rvcore.bearing.lubricant.DENSITY_DEFAULT`).
    pressure_viscosity : float
        Pressure–viscosity coefficient α [Pa^-1]
        (:data:`rvcore.bearing.lubricant.PRESSURE_VISCOSITY_DEFAULT`).
    ep_additives : bool
        EP additives proven effective (ISO 281's EP rule).
    contamination : float or None
        Contamination factor e_C [-] in [0, 1]; None: ISO 281 Table 13's "normal
        cleanliness", lower bound (:func:`rvcore.bearing.lubricant.contamination_of`).
    ball_roughness, raceway_roughness : float
        rms roughnesses [m] (:data:`rvcore.bearing.lubricant.BALL_ROUGHNESS_DEFAULT`,
        :data:`~rvcore.bearing.lubricant.RACEWAY_ROUGHNESS_DEFAULT`).
    """

    kinematic_viscosity: float | None = None
    method: str = "grease"
    grade: int | None = None
    viscosity_40: float | None = None
    viscosity_100: float | None = None
    density: float = DENSITY_DEFAULT
    pressure_viscosity: float = PRESSURE_VISCOSITY_DEFAULT
    ep_additives: bool = False
    contamination: float | None = None
    ball_roughness: float = BALL_ROUGHNESS_DEFAULT
    raceway_roughness: float = RACEWAY_ROUGHNESS_DEFAULT


#: Modal damping ratio of a flexible ring's modes when none is given [-]. An assumption: 2 %,
#: the middle of the 1–5 % usually measured on steel rings bolted or fitted into a housing.
DEFAULT_DAMPING_RATIO = 0.02

#: Highest Fourier order of a flexible ring's modes when none is given [-]: the static
#: deflection's truncation error falls as ``max_order⁻³`` (:mod:`rvcore.rings.deflection`).
DEFAULT_RING_MAX_ORDER = 60

#: The kinds of a flexible ring's support (:class:`RingSupport`).
RING_SUPPORTS = ("foundation", "housing", "fe_file")


@dataclass(frozen=True)
class RingSupport:
    """A flexible ring and what holds it, as plain data (docs/model.md §16); the modes are
    built from it by :func:`rvcore.rings.flexible.bearing_rings`.

    Parameters
    ----------
    kind : str
        One of :data:`RING_SUPPORTS`: ``"foundation"`` (a seat of radial and axial stiffness
        per unit circumference, ``seat_*``), ``"housing"`` (a second ring of section
        ``housing_section`` holding it through the seat ``seat_*``, itself on ``ground_*``),
        ``"fe_file"`` (the support's stiffness per Fourier order, ``orders``,
        ``radial_stiffness``, ``axial_stiffness``, as reduced from an FE model).
    max_order : int
        Highest Fourier order kept [-].
    damping_ratio : float
        Modal damping ratio ``ζ`` of the ring's modes [-].
    section : tuple
        The ring's own section given: (area [m²], centroid radius [m], ``I_in`` [m⁴],
        ``I_out`` [m⁴], torsion constant [m⁴]); empty: from the envelope and grooves.
    shoulder_diameter : float
        The outer ring's bore at its shoulders [m] (its section from the envelope); 0 for
        the inner ring (``inner_ring.shoulder_diameter``) or a given section.
    seat_radial, seat_axial : float
        The seat's stiffness per unit circumference of the ring [N m⁻²]; ``inf``: bonded.
    housing_section : tuple
        The housing's (carrier's) section, as ``section``.
    housing_material : Material or None
        The housing's material; None: the ring's.
    ground_radial, ground_axial : float
        What holds the housing, per unit circumference of the housing [N m⁻²]; 0: free.
    orders : tuple of int
        ``fe_file``: the orders ``k = 0 … N`` of the table [-].
    radial_stiffness, axial_stiffness : tuple of float
        ``fe_file``: the support's stiffness per unit modal amplitude at each order,
        radial and axial [N m⁻¹] (:class:`rvcore.rings.support.OrderStiffness`).
    """

    kind: str
    max_order: int = DEFAULT_RING_MAX_ORDER
    damping_ratio: float = DEFAULT_DAMPING_RATIO
    section: tuple = ()
    shoulder_diameter: float = 0.0
    seat_radial: float = math.inf
    seat_axial: float = math.inf
    housing_section: tuple = ()
    housing_material: Material | None = None
    ground_radial: float = 0.0
    ground_axial: float = 0.0
    orders: tuple = ()
    radial_stiffness: tuple = ()
    axial_stiffness: tuple = ()

    def __post_init__(self):
        if self.kind not in RING_SUPPORTS:
            raise ValueError(f"ring support {self.kind!r} is not one of {', '.join(RING_SUPPORTS)}")


@dataclass(frozen=True)
class Bearing:
    """A whole bearing: envelope, rows, rings, materials and contact law.

    ``arrangement`` names how a pair's rows are mirrored (``"back-to-back"``,
    ``"face-to-face"``, ``"tandem"``; ``""`` for a single row or rows given one by one),
    ``preload`` the axial preload force asked for [N] (0 when none or when the pair is
    preloaded by an offset) and ``preload_offset`` the total axial offset of the rows'
    inner raceways that sets it [m] (see :mod:`rvcore.statics.preload`).

    ``gravity`` is the gravitational acceleration in the bearing frame [m s^-2], set by
    the mounting (:data:`MOUNTINGS`; horizontal axis by default).
    ``dynamic_load_rating`` is the catalogue basic dynamic radial load rating C_r [N]
    (ISO 281); 0 means "from the geometry" (:mod:`rvcore.standards.iso16281`). ``lubricant`` is what
    the friction-moment estimate, ISO 281's κ and the film take (:class:`Lubricant`).
    ``inner_ring_temperature`` and ``outer_ring_temperature`` are the rings' operating
    temperatures [K] (default 40 °C both), ``reference_temperature`` the one the rows'
    ``radial_clearance`` is given at [K] (20 °C); the loader
    (:func:`rvcore.bearing.thermal.operating_bearing`) has already turned each row's
    clearance into its operating value, ``nominal_radial_clearances`` keeping the given
    ones (empty where nothing moved). ``inner_ring_support`` and ``outer_ring_support`` make a ring flexible in its
    support (:class:`RingSupport`; None, the default: rigid). ``warnings`` carries caveats that every output of a run must repeat (for example a
    ball overlap accepted through ``allow_ball_overlap``). ``assumptions`` lists the
    dotted keys whose values the source does not give.
    """

    name: str
    bore: float
    outer_diameter: float
    width: float
    rows: tuple[Row, ...]
    ring_material: Material
    ball_material: Material
    inner_ring: InnerRing
    contact: ContactLaw
    allow_ball_overlap: bool = False
    gravity: tuple = (0.0, -STANDARD_GRAVITY, 0.0)
    warnings: tuple = ()
    assumptions: tuple = ()
    arrangement: str = ""
    preload: float = 0.0
    preload_offset: float = 0.0
    dynamic_load_rating: float = 0.0
    lubricant: Lubricant = Lubricant()
    inner_ring_temperature: float = 313.15
    outer_ring_temperature: float = 313.15
    reference_temperature: float = 293.15
    nominal_radial_clearances: tuple = ()
    source: str = ""
    description: str = ""
    inner_ring_support: RingSupport | None = None
    outer_ring_support: RingSupport | None = None

    @property
    def operating_viscosity(self) -> float:
        """Kinematic viscosity of the lubricant at the operating temperature [m^2 s^-1]
        (:func:`rvcore.bearing.lubricant.operating_viscosity`)."""
        from .lubricant import operating_viscosity

        return operating_viscosity(self)


# --------------------------------------------------------------------------- derived


def ball_mass(row: Row, material: Material) -> float:
    """Mass of one ball [kg]: ``ρ·π·D³/6``."""
    return material.density * math.pi * row.ball_diameter**3 / 6.0


def ball_inertia(row: Row, material: Material) -> float:
    """Moment of inertia of one homogeneous ball about its centre [kg m^2]: ``m·D²/10``."""
    return ball_mass(row, material) * row.ball_diameter**2 / 10.0


def min_pitch_diameter(ball_count: int, ball_diameter: float) -> float:
    """Smallest pitch diameter on which ``ball_count`` balls fit without overlap [m].

    Neighbouring centres are ``d_m·sin(π/Z)`` apart, so ``d_m ≥ D / sin(π/Z)``.
    """
    return ball_diameter / math.sin(math.pi / ball_count)


def max_ball_count(pitch_diameter: float, ball_diameter: float, web: float = 0.0) -> int:
    """Largest Z whose balls, plus a cage web of ``web`` [m] between them, fit on the pitch circle."""
    z = int(math.pi / math.asin(min(1.0, (ball_diameter + web) / pitch_diameter)))
    while z > 1 and pitch_diameter * math.sin(math.pi / z) < ball_diameter + web:
        z -= 1
    return z


def arc_geometry(row: Row, arc: Arc, ring: int):
    """Centre and size of one groove arc in the row's cross-section.

    Returns
    -------
    centre_radial : float
        Distance of the arc centre from the bearing axis [m].
    centre_axial : float
        Axial coordinate of the arc centre, relative to the row plane [m]; an inner arc
        is moved by the row's ``inner_offset``.
    radius_minus_half : float
        ``(f − ½)·D`` [m]; the penetration is ``|P − C| − radius_minus_half``.
    side : int
        +1 or −1 when the arc is one of several on its ring (it exists only where its
        contact point lies on that side of the groove mid-plane), else 0.
    """
    d = row.ball_diameter
    g = row.radial_clearance / 4.0
    ux, uz = math.cos(arc.contact_angle), math.sin(arc.contact_angle)
    if ring == INNER:
        ux, uz = -ux, -uz
    reach = (arc.curvature_ratio - 0.5) * d - g
    cr = row.pitch_diameter / 2.0 - reach * ux
    cz = -reach * uz + (row.inner_offset if ring == INNER else 0.0)
    arcs = row.inner_arcs if ring == INNER else row.outer_arcs
    side = 0
    if len(arcs) > 1 and abs(uz) > 1e-12:
        side = 1 if uz > 0 else -1
    return cr, cz, (arc.curvature_ratio - 0.5) * d, side


def inner_ring_mass_properties(bearing: Bearing):
    """Mass [kg], polar and transverse inertia [kg m^2] of the inner ring with attachments.

    The ring is an annulus from the bore to the shoulder diameter over the width:
    ``m = ρ·π/4·(d_s² − d_b²)·B``, ``I_p = m·(r_s² + r_b²)/2``,
    ``I_t = m·(3·(r_s² + r_b²) + B²)/12``.
    """
    rs, rb, b = bearing.inner_ring.shoulder_diameter / 2, bearing.bore / 2, bearing.width
    m = bearing.ring_material.density * math.pi * (rs**2 - rb**2) * b
    ip = m * (rs**2 + rb**2) / 2.0
    it = m * (3.0 * (rs**2 + rb**2) + b**2) / 12.0
    return (m + bearing.inner_ring.attached_mass, ip, it + bearing.inner_ring.attached_inertia)


def cage_mass_properties(row: Row):
    """Mass [kg] and polar inertia [kg m^2] of a cage ring with Z cylindrical pockets.

    The pockets (diameter ``D + c_p`` through the radial wall) are subtracted from the
    annulus; the polar inertia is that of the remaining annulus, ``m·(r_o² + r_i²)/2``.
    """
    c = row.cage
    ro, ri = c.outer_diameter / 2, c.inner_diameter / 2
    pocket = math.pi / 4 * (row.ball_diameter + c.pocket_clearance) ** 2 * (ro - ri)
    volume = math.pi * (ro**2 - ri**2) * c.width - row.ball_count * pocket
    m = c.material.density * max(volume, 0.0)
    return m, m * (ro**2 + ri**2) / 2.0


def epicyclic_cage_ratio(row: Row, contact_angle: float | None = None) -> float:
    """Cage speed over inner-ring speed for rolling without slip, outer ring fixed.

    ``ω_c/ω_i = ½·(1 − D·cos α / d_m)``.
    """
    a = row.nominal_contact_angle if contact_angle is None else contact_angle
    return 0.5 * (1.0 - row.ball_diameter * math.cos(a) / row.pitch_diameter)


def centrifugal_ball_load(ball_mass, pitch_radius, orbit_speed):
    """The centrifugal force of a ball on its orbit, pressing it on the outer race [N].

    Parameters
    ----------
    ball_mass : float or ndarray
        Mass of the ball [kg].
    pitch_radius : float or ndarray
        Radius of the ball centres' orbit [m].
    orbit_speed : float or ndarray
        Angular speed of the orbit, the cage's [rad s^-1]: ``ω·epicyclic_cage_ratio(row)``
        for rolling without slip at the inner ring's ω (:func:`epicyclic_cage_ratio`).

    Notes
    -----
    ``F_c = m_b·(d_m/2)·ω_c²``: the one place it is written.
    """
    return ball_mass * pitch_radius * orbit_speed ** 2
