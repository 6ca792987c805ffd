"""The input schema: one entry per input field of the bearing file, the profile file, the
sweep's ``[solver]`` table and the operating point.

Each :class:`Field` gives the key path as the TOML nests it (``rows[].balls.diameter``,
``friction.mu_static``, ``solver.step_safety``; ``[]`` stands for any list index), its
kind, its bounds, its default (or :data:`REQUIRED`), the unit an engineer reads it in,
a one-line doc and where its value sits in the ``rvcore`` dataclass the loader builds.

Readers of this table:

- :mod:`pipeline.schema.reader` / :mod:`.bearingfile` / :mod:`.profilefile`: the keys
  each table allows, each value's kind, bounds and default;
- :func:`pipeline.schema.convert.from_fields`, the loader's one converter: each
  key's value lands at its ``source`` (a new bearing key with a ``source`` needs no other
  loader code; what no one key holds is named in ``bearingfile.SET_ELSEWHERE``);
- :mod:`.profilefile`, through the same converter: a channel's times and interpolation, the
  cycle's duration (its values, fraction or value, and the phases in ``profilefile.SET_ELSEWHERE``);
- the case id (:func:`pipeline.schema.sweepfile.case_configuration`): every attribute of
  the dataclasses but those of the keys marked ``hashed=False`` (free text);
- :mod:`pipeline.schema.sweepaxes`: the kinds of operating-point, solver, bearing and
  profile values on sweep axes and in ``[fixed]`` (there is no second kind table);
- :func:`pipeline.schema.tomlfile.parse_sets` callers (``--set``) through
  :func:`check_set_key`;
- ``rvsweep check`` (display units, ``--fields``) and :mod:`.parameters` (the report's
  parameter table).

Why a plain table of frozen dataclasses and not pydantic: pydantic is not a dependency
and may not be added, and the loaders need more than per-field validation anyway
(cross-field rules such as "two arcs at ±α", "v_dynamic > v_static", and error messages
that name file, key path with indices and the value as written). A flat table keyed by
path is also what ``check --fields`` and the report list, which a nested model would
have to be flattened into first.
"""
from __future__ import annotations

import dataclasses
import functools
import math
import re
import types
import typing
from dataclasses import dataclass

from rvcore.simulation.settings import SolverSettings
from rvcore.bearing.geometry import MOUNTINGS, TILT_CONDITIONS, ContactLaw
from rvcore.bearing.laws import FRICTION_LAWS
from rvcore.bearing.layout import MAX_ROW_BALLS
from rvcore.standards.iso492 import BALL_GRADES, TOLERANCE_CLASSES
from rvcore.statics.preload import ARRANGEMENTS
from rvcore.profile import INTERPOLATIONS, PHASES
from rvcore.standards.palmgren import LUBRICATIONS
from rvcore.bearing.geometry import DEFAULT_DAMPING_RATIO, RING_SUPPORTS, Lubricant
from rvcore.bearing.lubricant import (BALL_ROUGHNESS_DEFAULT, DENSITY_DEFAULT, ISO_VG_GRADES,
                                      PRESSURE_VISCOSITY_DEFAULT, RACEWAY_ROUGHNESS_DEFAULT)
from rvcore.bearing.thermal import OPERATING_TEMPERATURE_DEFAULT, REFERENCE_TEMPERATURE, STEEL_THERMAL_EXPANSION
from rvcore.standards.iso281_modified import CONTAMINATION_DEFAULT_LEVEL, CONTAMINATION_GUIDE

from ..errors import ConfigError

#: Largest seed: the realization axis stores seeds as float coordinates, exact up to 2**53.
MAX_SEED = 2**53 - 1

#: Most lobes of a waviness term: a million lobes on the study's 328 mm inner raceway are a
#: wavelength of 1 µm, roughness rather than waviness. The amplitude bounds the order much
#: further (:mod:`pipeline.schema.physical`: the ball must not bridge the troughs); this
#: bound holds where the amplitude is 0.
MAX_WAVINESS_ORDER = 10**6

#: Highest Fourier order of a flexible ring's modes the inputs allow [-].
MAX_RING_ORDER = 400

#: Temperatures the inputs allow [K]: -50 to 200 degC, about where bearing steels keep their
#: hardness and mineral oils stay liquid; also what keeps a plain number (read as K) such as
#: 40 out.
_TEMPERATURE_BOUNDS = (223.15, 473.15)
_TEMPERATURE_WHY = ("must lie between -50 and 200 degC (a plain number is kelvin: write \"40 degC\" "
                    "or \"313.15 K\")")

#: Default of a field that must be given.
REQUIRED = object()

#: Kinds of field.
KINDS = ("quantity", "integer", "boolean", "choice", "string", "list")

#: Which file a field belongs to (``statistics``: a sweep file's ``[statistics]`` table).
FILES = ("bearing", "profile", "solver", "operating_point", "statistics")


@dataclass(frozen=True)
class Field:
    """One input field.

    Parameters
    ----------
    path : str
        Key path as the TOML nests it, ``[]`` for any list index.
    kind : str
        One of :data:`KINDS`. A ``list`` holds ``length`` items of ``unit_kind``.
    file : str
        One of :data:`FILES`.
    unit_kind : str or None
        A key of :data:`pipeline.schema.units.SI_UNITS` (quantities and lists of them).
    bounds : str, tuple or None
        ``"positive"``, ``"nonnegative"``, ``"fraction"`` (``0 < x ≤ 1``), an open
        interval ``(lo, hi)`` in SI, or None.
    default :
        The value (SI) when the key is left out, or :data:`REQUIRED`.
    unit : str
        The unit shown to engineers (``"mm"``, ``"kN"``, ``"deg/s"``); "" for none.
    doc : str
        One line.
    choices : tuple
        The allowed strings of a ``choice``.
    minimum, maximum : int or None
        Smallest and largest allowed ``integer``.
    why : str
        The reason given when the bounds fail, if the generic one would say too little.
    source : str or None
        Attribute path into the ``rvcore`` dataclass built from the file
        (``rows[].cage.material.density``); None where no single attribute holds it.
    length : int or None
        Number of items of a ``list`` (None: any, at least one).
    hashed : bool
        False for free text that changes no result (a description, a source): left out of
        the case id (:func:`pipeline.schema.sweepfile.case_configuration`) and of the
        parameter table.
    """

    path: str
    kind: str
    file: str
    unit_kind: str | None = None
    bounds: object = None
    default: object = REQUIRED
    unit: str = ""
    doc: str = ""
    choices: tuple = ()
    minimum: int | None = None
    maximum: int | None = None
    why: str = ""
    source: str | None = None
    length: int | None = None
    hashed: bool = True

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    @property
    def text_default(self) -> bool:
        """True where the default is a rule told to the reader (``"from the geometry"``), not a
        value: a key left out keeps the ``rvcore`` dataclass's own default (0, None, "")."""
        if not isinstance(self.default, str):
            return False
        if self.kind == "choice":
            return self.default not in self.choices
        return self.kind != "string"

    @property
    def axis_kind(self) -> str | None:
        """The kind of this field's values on a sweep axis (``SI_UNITS`` key, ``"bool"``,
        or ``"category"`` for a ``choice``: its coordinates are the strings themselves)."""
        if self.kind in ("quantity", "list"):
            return self.unit_kind
        if self.kind == "integer":
            return "dimensionless"
        if self.kind == "boolean":
            return "bool"
        if self.kind == "choice":
            return "category"
        return None

    def bounds_text(self) -> str:
        b = self.bounds
        if b == "positive":
            return "> 0"
        if b == "nonnegative":
            return ">= 0"
        if b == "fraction":
            return "in (0, 1]"
        if isinstance(b, tuple):
            return f"in ({b[0]:g}, {b[1]:g}) SI"
        if self.minimum is not None and self.maximum is not None:
            return f"{self.minimum} to {self.maximum}"
        if self.minimum is not None:
            return f">= {self.minimum}"
        if self.choices:
            return "one of " + ", ".join(self.choices)
        return ""


def _default(cls, name):
    return {f.name: f.default for f in dataclasses.fields(cls)}[name]


def _q(path, unit_kind, unit, doc, file="bearing", bounds="positive", default=REQUIRED, **kw):
    return Field(path, "quantity", file, unit_kind, bounds, default, unit, doc, **kw)


def _material(prefix: str, source: str, whose: str, thermal: bool = True) -> list:
    out = [
        _q(f"{prefix}.density", "density", "kg/m^3", f"density of {whose}", source=f"{source}.density"),
        _q(f"{prefix}.youngs_modulus", "pressure", "GPa", f"Young's modulus of {whose}",
           source=f"{source}.youngs_modulus"),
        _q(f"{prefix}.poisson_ratio", "dimensionless", "", f"Poisson's ratio of {whose}", bounds=(-1.0, 0.5),
           why="must lie between -1 and 0.5 for an isotropic solid", source=f"{source}.poisson_ratio"),
    ]
    if thermal:
        out.append(_q(f"{prefix}.thermal_expansion", "thermal_expansion", "K^-1",
                      f"linear thermal expansion coefficient of {whose} (the operating clearance, "
                      "rvcore.bearing.thermal); default bearing steel 11.5e-6 K^-1", bounds=(0.0, 1e-4),
                      default=STEEL_THERMAL_EXPANSION, source=f"{source}.thermal_expansion",
                      why="must lie in (0, 1e-4) K^-1: metals and ceramics expand 1e-6 to 3e-5 per K "
                          "(write e.g. \"11.5e-6 K^-1\")"))
    return out


def _imperfections(prefix: str, where: str) -> list:
    """The ``[imperfections]`` keys (docs/model.md §12) under ``prefix``: the bearing's, or one
    row's override (``rows[].imperfections``), or a pair's entry (``pair.imperfections[]``). All
    three land in the row's :class:`rvcore.bearing.imperfections.Imperfections`, the pair's entry
    over the row's over the bearing's (:func:`pipeline.schema.bearingfile.layered_imperfections`)."""
    src = "rows[].imperfections"
    out = [Field(f"{prefix}.tolerance_class", "choice", "bearing", default="none",
                 choices=("none",) + TOLERANCE_CLASSES,
                 doc=f"ISO 492 tolerance class of {where}: sets the eccentricities e = K/2 from K_ia, K_ea, "
                     "the axial runout amplitudes a = S/2 from S_ia, S_ea (classes 5, 4) and a default ball "
                     "grade; none: a perfect bearing unless other keys say otherwise",
                 source=f"{src}.tolerance_class")]
    for ring in ("inner", "outer"):
        out += [
            _q(f"{prefix}.{ring}_eccentricity", "length", "um",
               f"{ring} raceway's centre offset from its ring's axis ({where}); 0 none",
               bounds="nonnegative", default="from tolerance_class, else 0", source=f"{src}.{ring}_eccentricity"),
            _q(f"{prefix}.{ring}_eccentricity_angle", "angle", "deg",
               f"direction of the {ring} raceway's offset (its high point) in its ring's frame",
               bounds=None, default="(drawn from the case's seed, else 0)",
               source=f"{src}.{ring}_eccentricity_angle"),
            Field(f"{prefix}.{ring}_waviness[].order", "integer", "bearing", minimum=1,
                  maximum=MAX_WAVINESS_ORDER, default=REQUIRED,
                  doc=f"lobes of one {ring} raceway waviness harmonic; with its amplitude A, "
                      "A·order²/R² − 1/R (inner) or + 1/R (outer) must stay below 2/D_w, or the "
                      "ball bridges the troughs (R the raceway radius)",
                  why="a wavelength of a micrometre is roughness, not waviness",
                  source=f"{src}.{ring}_waviness[].order"),
            _q(f"{prefix}.{ring}_waviness[].amplitude", "length", "um",
               f"amplitude of the {ring} raceway radius harmonic", bounds="nonnegative",
               source=f"{src}.{ring}_waviness[].amplitude"),
            _q(f"{prefix}.{ring}_waviness[].phase", "angle", "deg", "phase of the harmonic at the ring's angle 0",
               bounds=None, default=0.0, source=f"{src}.{ring}_waviness[].phase"),
            _q(f"{prefix}.{ring}_axial_amplitude", "length", "um",
               f"{ring} raceway's axial runout ({where}): amplitude a of a groove plane tilted to its ring's "
               f"axis, half the runout's total indicator reading (ISO 492 S_{ring[0]}a = 2a); 0 none",
               bounds="nonnegative", default="(S/2 from tolerance_class where ISO 492 gives S: classes 5, 4; else 0)",
               source=f"{src}.{ring}_axial_amplitude"),
            _q(f"{prefix}.{ring}_axial_angle", "angle", "deg",
               f"where the {ring} raceway's tilted plane stands furthest along +z (its high point), in its "
               "ring's frame", bounds=None, default="(drawn from the case's seed, else 0)",
               source=f"{src}.{ring}_axial_angle"),
            Field(f"{prefix}.{ring}_axial_waviness[].order", "integer", "bearing", minimum=1,
                  maximum=MAX_WAVINESS_ORDER, default=REQUIRED,
                  doc=f"order of one higher harmonic of the {ring} raceway's axial runout (the groove moves "
                      "along the axis by A·cos(order·φ + phase))",
                  why="a wavelength of a micrometre is roughness, not waviness",
                  source=f"{src}.{ring}_axial_waviness[].order"),
            _q(f"{prefix}.{ring}_axial_waviness[].amplitude", "length", "um",
               f"amplitude of the {ring} raceway's axial harmonic", bounds="nonnegative",
               source=f"{src}.{ring}_axial_waviness[].amplitude"),
            _q(f"{prefix}.{ring}_axial_waviness[].phase", "angle", "deg",
               "phase of the axial harmonic at the ring's angle 0", bounds=None, default=0.0,
               source=f"{src}.{ring}_axial_waviness[].phase"),
        ]
    out += [
        Field(f"{prefix}.ball_diameter_deviation", "list", "bearing", "length", None, default=(), unit="um",
              doc=f"one diameter deviation per ball of {where} (else drawn within the ball grade)",
              source=f"{src}.ball_diameter_deviation"),
        Field(f"{prefix}.ball_grade", "choice", "bearing", default="(from tolerance_class, else none)",
              choices=tuple(BALL_GRADES), doc="ISO 3290 ball grade: ball sizes drawn within its lot variation V_DwL",
              source=f"{src}.ball_grade"),
    ]
    return out


def _section(prefix: str, whose: str, optional: str) -> list:
    """A ring section given by its properties (rvcore.rings.section.given_section), under ``prefix``."""
    return [
        _q(f"{prefix}.area", "area", "mm^2", f"cross-section area of {whose} {optional}", default="(not given)"),
        _q(f"{prefix}.centroid_diameter", "length", "mm", f"diameter of {whose} section's centroid circle",
           default="(not given)"),
        _q(f"{prefix}.i_in_plane", "second_moment", "mm^4",
           f"second moment of {whose} section for bending in the ring's plane (radial), about its centroid",
           default="(not given)"),
        _q(f"{prefix}.i_out_of_plane", "second_moment", "mm^4",
           f"second moment of {whose} section for bending out of the ring's plane (axial)", default="(not given)"),
        _q(f"{prefix}.torsion_constant", "second_moment", "mm^4", f"Saint-Venant torsion constant J of {whose} "
           "section", default="(not given)"),
    ]


def _flexible(ring: str) -> list:
    """``[<ring>_ring.flexible]``: the ring flexible in its support (docs/model.md §16; absent: rigid)."""
    p = f"{ring}_ring.flexible"
    out = [
        Field(f"{p}.support", "choice", "bearing", choices=RING_SUPPORTS,
              doc=f"what holds the flexible {ring} ring: foundation (a seat of stiffness per unit circumference), "
                  "housing (a second ring through the seat), fe_file (per-order stiffness from an FE model, "
                  "docs/inputs.md); leave [" + p + "] out for a rigid ring"),
        Field(f"{p}.max_order", "integer", "bearing", default="60 (fe_file: the file's highest order)",
              minimum=2, maximum=MAX_RING_ORDER,
              doc="highest Fourier order of the ring's modes (the static deflection's error falls as its cube)",
              why="the thin-ring modes are a curved beam's: above a few hundred lobes the wave is shorter than "
                  "the ring is thick"),
        _q(f"{p}.damping_ratio", "dimensionless", "", "modal damping ratio of the ring's modes; default 0.02 "
           "(an assumption: the middle of the 1-5 % measured on fitted steel rings)", bounds=(0.0, 1.0),
           default=DEFAULT_DAMPING_RATIO, why="must lie strictly between 0 and 1: a fraction of critical damping"),
        *_section(f"{p}.section", f"the {ring} ring's", "(give all five, or none: from the envelope and groove)"),
    ]
    if ring == "outer":
        out.append(_q(f"{p}.shoulder_diameter", "length", "mm",
                      "the outer ring's bore at its shoulders: its section from the envelope and groove "
                      "(required unless section.* is given)", default="(required without section)"))
    out += [
        _q(f"{p}.seat_radial_stiffness", "pressure", "N/mm^2",
           "radial stiffness of the ring's seat per unit circumference (foundation: required; housing: the fit "
           "between the rings, default inf = bonded)", bounds="nonnegative", default="(inf: bonded)"),
        _q(f"{p}.seat_axial_stiffness", "pressure", "N/mm^2",
           "axial stiffness of the ring's seat per unit circumference (as seat_radial_stiffness)",
           bounds="nonnegative", default="(inf: bonded)"),
        *_section(f"{p}.housing", "the housing's (carrier's)", "(or inner_diameter, outer_diameter, width)"),
        _q(f"{p}.housing.inner_diameter", "length", "mm", "bore of a rectangular housing (carrier) section",
           default="(or the section's properties)"),
        _q(f"{p}.housing.outer_diameter", "length", "mm", "outside diameter of a rectangular housing section",
           default="(or the section's properties)"),
        _q(f"{p}.housing.width", "length", "mm", "axial width of a rectangular housing section",
           default="(or the section's properties)"),
        # read by pipeline.schema.ringfile (no one attribute of the Bearing holds them: no source)
        *(dataclasses.replace(f, source=None)
          for f in _material(f"{p}.housing.material", "", "the housing", thermal=False)),
        _q(f"{p}.housing.ground_radial_stiffness", "pressure", "N/mm^2",
           "radial stiffness of what holds the housing, per unit circumference of the housing; default 0 (free)",
           bounds="nonnegative", default=0.0),
        _q(f"{p}.housing.ground_axial_stiffness", "pressure", "N/mm^2",
           "axial stiffness of what holds the housing, per unit circumference; default 0 (free)",
           bounds="nonnegative", default=0.0),
        Field(f"{p}.file", "string", "bearing", default="(required with fe_file)",
              doc="fe_file: the support's stiffness (or compliance) per Fourier order, a CSV file with a units "
                  "row (docs/inputs.md), relative to the bearing file"),
    ]
    return out


def _arcs(groove: str, attr: str, ring: str) -> list:
    p = f"rows[].{groove}.arcs[]"
    return [
        _q(f"{p}.curvature_ratio", "dimensionless", "", f"{ring} groove radius over ball diameter, f",
           bounds=(0.5, math.inf), why="must exceed 0.5", source=f"rows[].{attr}[].curvature_ratio"),
        _q(f"{p}.contact_angle", "angle", "deg", f"{ring} arc's contact angle (two arcs: ±α, four-point)",
           bounds=(-math.pi / 2, math.pi / 2), why="a contact angle must lie strictly between -90 and 90 deg",
           source=f"rows[].{attr}[].contact_angle"),
    ]


_BEARING = [
    Field("name", "string", "bearing", default="<file stem>", doc="the bearing's name", source="name"),
    Field("description", "string", "bearing", default="", doc="free text", source="description", hashed=False),
    Field("source", "string", "bearing", default="", doc="where the numbers come from", source="source",
          hashed=False),
    Field("allow_ball_overlap", "boolean", "bearing", default=False, source="allow_ball_overlap",
          doc="true turns balls that do not fit on their pitch circle into a warning (docs/model.md §10)"),
    Field("assumptions", "list", "bearing", default=(), doc="key paths whose values are assumed"),
    Field("mounting", "choice", "bearing", default="horizontal", choices=tuple(MOUNTINGS),
          doc="axis orientation, which sets gravity (or give gravity as a vector)"),
    Field("gravity", "list", "bearing", "acceleration", default="from mounting", unit="m/s^2", length=3,
          doc="gravity in the bearing frame, instead of mounting", source="gravity"),
    _q("dynamic_load_rating", "force", "kN",
       "catalogue basic dynamic load rating C_r of the whole bearing (a pair: of the pair; ISO 281); "
       "left out: computed from the geometry. It scales the ISO/TS 16281 contact ratings", default="from the geometry", source="dynamic_load_rating",
       why="must be positive: a catalogue C_r is a force; leave the key out to compute it from the geometry"),
    _q("envelope.bore", "length", "mm", "bore diameter", source="bore"),
    _q("envelope.outer_diameter", "length", "mm", "outer diameter", source="outer_diameter"),
    _q("envelope.width", "length", "mm", "width", source="width"),
    *_material("material", "ring_material", "rings and balls"),
    *_material("ring_material", "ring_material", "the rings"),
    *_material("ball_material", "ball_material", "the balls"),
    _q("inner_ring.shoulder_diameter", "length", "mm", "inner ring's shoulder diameter",
       source="inner_ring.shoulder_diameter"),
    _q("inner_ring.attached_mass", "mass", "kg", "mass moving with the inner ring", bounds="nonnegative",
       default=0.0, source="inner_ring.attached_mass"),
    _q("inner_ring.attached_inertia", "inertia", "kg m^2", "inertia moving with the inner ring",
       bounds="nonnegative", default=0.0, source="inner_ring.attached_inertia"),
    Field("inner_ring.tilt", "choice", "bearing", default="free", choices=TILT_CONDITIONS,
          doc="free: the ring tilts under zero moment; held: kept square (a second support), "
              "the reaction moment reported", source="inner_ring.tilt"),
    *_flexible("inner"),
    *_flexible("outer"),
    _q("contact.damping", "damping", "N s/m", "ball-race contact damping", bounds="nonnegative",
       source="contact.damping"),
    _q("contact.damping_depth", "length", "um", "penetration over which contact damping ramps in",
       source="contact.damping_depth"),
    _q("contact.pocket_damping", "damping", "N s/m", "ball-pocket contact damping", bounds="nonnegative",
       source="contact.pocket_damping"),
    _q("contact.land_damping", "damping", "N s/m", "cage-land contact damping", bounds="nonnegative",
       source="contact.land_damping"),
    _q("friction.mu_static", "dimensionless", "", "friction coefficient at v_static", bounds="nonnegative",
       default=_default(ContactLaw, "mu_static"), source="contact.mu_static"),
    _q("friction.v_static", "speed", "m/s", "sliding speed of the static friction peak",
       default=_default(ContactLaw, "v_static"), source="contact.v_static"),
    _q("friction.mu_dynamic", "dimensionless", "", "friction coefficient from v_dynamic on",
       bounds="nonnegative", default=_default(ContactLaw, "mu_dynamic"), source="contact.mu_dynamic"),
    _q("friction.v_dynamic", "speed", "m/s", "sliding speed from which friction is dynamic (> v_static)",
       default=_default(ContactLaw, "v_dynamic"), source="contact.v_dynamic"),
    Field("friction.law", "choice", "bearing", default=_default(ContactLaw, "law"), choices=FRICTION_LAWS,
          doc="the contact friction law: coulomb_step (the study's, default) or ehl_bair_winer (lubricated: "
              "film traction, boundary friction mu_static below lambda 1; docs/model.md section 4.1)",
          source="contact.law"),
    _q("lubricant.kinematic_viscosity", "kinematic_viscosity", "mm^2/s",
       "an override: the oil's (a grease: its base oil's) kinematic viscosity at the operating temperature; "
       "left out, it follows from the base oil (grade or viscosity_40/_100) and the ring temperatures "
       "(ASTM D341 / Walther)", default="(none: from the oil at the operating temperature)",
       source="lubricant.kinematic_viscosity",
       why="must be positive: a kinematic viscosity is a positive quantity (e.g. \"68 mm^2/s\")"),
    Field("lubricant.method", "choice", "bearing", default=_default(Lubricant, "method"), choices=LUBRICATIONS,
          doc="how the bearing is lubricated, for the friction-moment estimate's f0 (Palmgren); "
              "default grease, an assumption", source="lubricant.method"),
    Field("lubricant.grade", "integer", "bearing", default=68, minimum=min(ISO_VG_GRADES),
          maximum=max(ISO_VG_GRADES), source="lubricant.grade",
          doc="ISO VG grade of the base oil (ISO 3448: nu40 in mm^2/s), or give viscosity_40 and "
              "viscosity_100; default 68, an assumption (the study names no lubricant)",
          why="must be an ISO 3448 grade (" + ", ".join(str(g) for g in ISO_VG_GRADES) + ")"),
    _q("lubricant.viscosity_40", "kinematic_viscosity", "mm^2/s",
       "kinematic viscosity of the base oil at 40 degC (instead of grade; with viscosity_100)",
       default="from grade", source="lubricant.viscosity_40"),
    _q("lubricant.viscosity_100", "kinematic_viscosity", "mm^2/s",
       "kinematic viscosity of the base oil at 100 degC; default for VG 68 only: 8.5 mm^2/s (VI 94, "
       "ASTM D2270)", default="(8.5 mm^2/s for VG 68)", source="lubricant.viscosity_100"),
    _q("lubricant.density", "density", "kg/m^3", "density of the base oil (eta0 = rho nu); default 880 "
       "kg/m^3, a VG 68 mineral oil at 15 degC, an assumption", default=DENSITY_DEFAULT,
       source="lubricant.density"),
    _q("lubricant.pressure_viscosity", "inverse_pressure", "GPa^-1",
       "pressure-viscosity coefficient alpha of the base oil; default 2e-8 Pa^-1 (20 GPa^-1), a mineral oil "
       "(Hamrock, NASA RP-1255)", default=PRESSURE_VISCOSITY_DEFAULT, source="lubricant.pressure_viscosity",
       why="must be positive (write e.g. \"20 GPa^-1\" or \"2e-8 Pa^-1\")"),
    Field("lubricant.ep_additives", "boolean", "bearing", default=False, source="lubricant.ep_additives",
          doc="EP additives proven effective: ISO 281's EP rule (kappa < 1, e_C >= 0.2: a_ISO at kappa = 1, "
              "at most 3)"),
    Field("lubricant.contamination", "string", "bearing", default=CONTAMINATION_DEFAULT_LEVEL,
          source="lubricant.contamination",
          doc="ISO 281 contamination factor e_C: a number in [0, 1], or a Table 13 level (" +
              ", ".join(CONTAMINATION_GUIDE) + "), taken at the lower bound of its d_m column; default "
                                               "normal cleanliness"),
    _q("lubricant.ball_roughness", "length", "um", "rms roughness of the balls; default 0.0625 um "
       "(Hamrock & Dowson's ball-bearing example)", bounds="nonnegative", default=BALL_ROUGHNESS_DEFAULT,
       source="lubricant.ball_roughness"),
    _q("lubricant.raceway_roughness", "length", "um", "rms roughness of the raceways; default 0.175 um "
       "(Hamrock & Dowson's ball-bearing example)", bounds="nonnegative", default=RACEWAY_ROUGHNESS_DEFAULT,
       source="lubricant.raceway_roughness"),
    _q("temperature.inner_ring", "temperature", "degC",
       "operating temperature of the inner ring (the clearance, the lubricant at the mean of the rings'); "
       "default 40 degC, an assumption", bounds=_TEMPERATURE_BOUNDS, default=OPERATING_TEMPERATURE_DEFAULT,
       source="inner_ring_temperature", why=_TEMPERATURE_WHY),
    _q("temperature.outer_ring", "temperature", "degC",
       "operating temperature of the outer ring; default 40 degC, an assumption", bounds=_TEMPERATURE_BOUNDS,
       default=OPERATING_TEMPERATURE_DEFAULT, source="outer_ring_temperature", why=_TEMPERATURE_WHY),
    _q("temperature.reference", "temperature", "degC",
       "temperature at which radial_clearance is given (and a pair's preload set); default 20 degC",
       bounds=_TEMPERATURE_BOUNDS, default=REFERENCE_TEMPERATURE, source="reference_temperature",
       why=_TEMPERATURE_WHY),
    *_imperfections("imperfections", "every row"),
    *_imperfections("rows[].imperfections", "this row (overrides [imperfections])"),
    *_imperfections("pair.imperfections[]", "that row of a pair (two entries, the row at -row_spacing/2 "
                                            "first; overrides the others)"),
    _q("rows[].pitch_diameter", "length", "mm", "pitch diameter of the row", source="rows[].pitch_diameter"),
    _q("rows[].axial_position", "length", "mm", "axial position of the row", bounds=None, default=0.0,
       source="rows[].axial_position"),
    _q("rows[].radial_clearance", "length", "mm",
       "radial internal clearance of the row; negative: an interference (a radial preload)", bounds=None,
       default=0.0, source="rows[].radial_clearance"),
    Field("rows[].balls.count", "integer", "bearing", minimum=3, maximum=MAX_ROW_BALLS,
          doc="number of balls in the row", why="the dynamics keep a row's balls in a scratch of that width",
          source="rows[].ball_count"),
    _q("rows[].balls.diameter", "length", "mm", "ball diameter", source="rows[].ball_diameter"),
    *_arcs("inner_groove", "inner_arcs", "inner"),
    *_arcs("outer_groove", "outer_arcs", "outer"),
    _q("rows[].cage.inner_diameter", "length", "mm", "cage bore", source="rows[].cage.inner_diameter"),
    _q("rows[].cage.outer_diameter", "length", "mm", "cage outer diameter", source="rows[].cage.outer_diameter"),
    _q("rows[].cage.width", "length", "mm", "cage width", source="rows[].cage.width"),
    _q("rows[].cage.pocket_clearance", "length", "mm", "diametral play of a ball in its pocket",
       bounds="nonnegative", source="rows[].cage.pocket_clearance"),
    _q("rows[].cage.land_clearance", "length", "mm",
       "radial play at the guiding land (required and positive when outer-land guided)",
       bounds="nonnegative", default=0.0, source="rows[].cage.land_clearance"),
    Field("rows[].cage.guidance", "choice", "bearing", choices=("outer-land", "ball"),
          doc="what guides the cage", source="rows[].cage.guidance"),
    *_material("rows[].cage", "rows[].cage.material", "the cage", thermal=False),
    _q("rows[].cage.land_stiffness", "stiffness_hertz", "N/m^1.5",
       "cage-land contact stiffness (required and positive when outer-land guided)",
       bounds="nonnegative", default=0.0, source="rows[].cage.land_stiffness"),
]

_PAIR = [
    Field("pair.arrangement", "choice", "bearing", choices=tuple(ARRANGEMENTS), source="arrangement",
          doc="how the pair's two rows are mirrored (the one [[rows]] entry is their design)"),
    _q("pair.row_spacing", "length", "mm", "axial distance between the two rows' centre planes",
       why="must be positive: the rows sit at -row_spacing/2 and +row_spacing/2"),
    _q("pair.preload", "force", "kN", "axial preload force; the statics find the ring offset that gives it",
       bounds="nonnegative", default=0.0, source="preload",
       why="must not be negative: a preload force presses the rows against each other"),
    _q("pair.preload_offset", "length", "um",
       "total axial offset of the rows' inner raceways that preloads the pair (rvcore.statics.preload), instead of preload",
       bounds=None, default=0.0, source="preload_offset"),
]

#: The profile's channel tables, in ``rvcore.profile.CH_*`` order: name -> (kind of the
#: absolute ``value``, display unit, whether ``fraction`` (of the operating point) is
#: allowed, whether the table is required). ``moment`` left out follows ``radial_load``'s
#: table; ``load_direction`` is an angle offset added to ``load_angle`` (a fraction of an
#: angle means nothing), 0 when left out (rvcore.profile).
_CHANNEL_KINDS = {"radial_load": ("force", "kN", True, True), "axial_load": ("force", "kN", True, True),
                  "speed": ("angular_speed", "deg/s", True, True),
                  "moment": ("moment", "N m", True, False),
                  "load_direction": ("angle", "deg", False, False)}
_CHANNEL_DOC = {"moment": "tilting moment about the axis normal to the radial load",
                "load_direction": "offset of the radial load's direction added to load_angle"}

_PROFILE = [
    Field("name", "string", "profile", default="<file stem>", doc="the profile's name", source="name"),
    Field("description", "string", "profile", default="", doc="free text", source="description", hashed=False),
    _q("duration", "time", "s", "length of the duty cycle", file="profile", source="duration"),
]
for _c, (_kind, _unit, _fraction, _required) in _CHANNEL_KINDS.items():
    _what = _CHANNEL_DOC.get(_c, _c)
    _opt = "" if _required else " (optional table)"
    _PROFILE += [
        Field(f"{_c}.time", "list", "profile", "time", "nonnegative", unit="s",
              doc=f"breakpoint times of {_c}, strictly increasing{_opt}", source=f"{_c}.times"),
    ]
    if _fraction:
        _PROFILE += [Field(f"{_c}.fraction", "list", "profile", "dimensionless", default="(or value)",
                           doc=f"{_what} at each breakpoint as a fraction of the operating point")]
    _PROFILE += [
        Field(f"{_c}.value", "list", "profile", _kind, default="(or fraction)" if _fraction else REQUIRED,
              unit=_unit, doc=f"{_what} at each breakpoint, absolute"),
        Field(f"{_c}.interpolation", "choice", "profile", default="linear", choices=tuple(INTERPOLATIONS),
              doc="how values run between breakpoints", source=f"{_c}.interpolation"),
    ]
_PROFILE += [Field(f"phases.{_p}", "list", "profile", "time", "nonnegative", unit="s", length=2,
                   doc=f"[start, end] of the {_p} phase's window") for _p in PHASES]

_SOLVER_DOC = {
    "output_rate": ("frequency", "Hz", "positive", "stored samples per second"),
    "method": (None, "", None, "integrator: imex (the default: contacts, friction and damping implicit) or rk4 (the reference)"),
    "step_safety": ("dimensionless", "", "fraction", "fraction of the method's step bounds"),
    "time_step": ("time", "us", "nonnegative", "one fixed step throughout; 0 derives the steps from the stiffest contact (imex: longer where the loads and speed are held)"),
    "start_time": ("time", "s", "nonnegative", "start of the simulated window"),
    "end_time": ("time", "s", "nonnegative", "end of the simulated window; 0: the profile's duration"),
    "friction": (None, "", None, "friction on (false only for conservation checks)"),
    "damping": (None, "", None, "contact damping on"),
    "gravity": (None, "", None, "gravity on every body (false only for conservation checks)"),
    "seed": (None, "", None, "seed of the random start; -1: every ball at its pocket centre"),
}


#: Reasons given when a solver setting is out of its bounds, where the generic one says too little.
_SOLVER_WHY = {"step_safety": "must lie in (0, 1]: it is a fraction of the method's explicit stability "
                              "limit, and 1 is that limit (a larger step may diverge or silently lose accuracy)"}


def _solver_field(f) -> Field:
    unit_kind, unit, bounds, doc = _SOLVER_DOC[f.name]
    path = f"solver.{f.name}"
    if isinstance(f.default, bool):
        return Field(path, "boolean", "solver", default=f.default, doc=doc, source=f.name)
    if isinstance(f.default, str):
        from rvcore.integrate.methods import NAMES as METHODS
        return Field(path, "choice", "solver", default=f.default, choices=METHODS, doc=doc, source=f.name)
    if isinstance(f.default, int):
        return Field(path, "integer", "solver", default=f.default, minimum=-1, maximum=MAX_SEED, doc=doc,
                     source=f.name, why="2**53 - 1: seeds are stored as exact floats")
    return _q(path, unit_kind, unit, doc, file="solver", bounds=bounds, default=f.default, source=f.name,
              why=_SOLVER_WHY.get(f.name, ""))


_SOLVER = [_solver_field(f) for f in dataclasses.fields(SolverSettings)]

_OPERATING_POINT = [
    # Refused rather than read as a direction: the metrics, the cage slip, the fits and the
    # report take the speed as a magnitude, and nothing checks a reversed spin.
    _q("speed", "angular_speed", "deg/s", "steady inner-ring speed (a magnitude)", file="operating_point",
       bounds="nonnegative", why="must not be negative: the speed is a magnitude (the direction of "
       "rotation is not an input)", source="speed"),
    _q("radial_load", "force", "kN", "radial load (its direction is load_angle)", file="operating_point",
       bounds="nonnegative", why="must not be negative (its direction is load_angle)", source="radial_load"),
    _q("axial_load", "force", "kN", "axial load towards +z", file="operating_point", bounds=None,
       source="axial_load"),
    _q("moment", "moment", "N m", "tilting moment", file="operating_point", bounds=None, default=0.0,
       source="moment"),
    _q("load_angle", "angle", "deg", "direction of the radial load from +x", file="operating_point",
       bounds=None, default=0.0, source="load_angle"),
]

#: A sweep file's ``[statistics]`` table (:mod:`pipeline.schema.statistics`, which checks it).
_STATISTICS = [
    Field("statistics.method", "choice", "statistics", default="sobol", choices=("sobol", "lhs"),
          doc="sampling of the draws (scipy.stats.qmc): scrambled Sobol' points (more draws keep the first "
              "ones) or a Latin hypercube (changing draws redraws all)"),
    Field("statistics.draws", "integer", "statistics", minimum=2, maximum=2**16,
          doc="N, the draws of the imperfections per grid point (a power of 2 for sobol)"),
    Field("statistics.seed", "integer", "statistics", minimum=0,
          doc="seed of the scrambling (or the hypercube): it fixes the draws and so their case ids"),
    Field("statistics.inputs", "list", "statistics", default="every input the bearing has a limit for",
          doc="named tolerance inputs drawn within the class: inner/outer_eccentricity(_angle), "
              "inner/outer_waviness, ball_diameter_deviation"),
    Field("statistics.sensitivity", "boolean", "statistics", default=False,
          doc="Saltelli's design (N·(d+2) cases a point) for first-order and total Sobol' indices"),
]

#: Every field, in file order.
FIELDS: tuple = tuple(_BEARING + _PAIR + _PROFILE + _SOLVER + _OPERATING_POINT + _STATISTICS)

#: Tables that may be left out as a whole although some of their keys are required when they
#: are given: left out, the dataclass fields their keys hold keep their defaults (no pair:
#: ``arrangement`` "", no preload).
OPTIONAL_TABLES = {"bearing": ("pair",)}

#: Keys a table refuses with a reason of their own, before any "unknown key": a ``fraction`` in
#: a channel that takes only a ``value`` (``load_direction``, an angle offset).
REFUSED_KEYS = {"profile": {f"{_c}.fraction": f"{_c} takes only 'value' (an angle in {_unit}, added to the "
                                              f"operating point's load_angle): a fraction of an angle means nothing"
                            for _c, (_kind, _unit, _fraction, _required) in _CHANNEL_KINDS.items()
                            if not _fraction}}

_BY_PATH = {(f.file, f.path): f for f in FIELDS}
_INDEX = re.compile(r"\[\d+\]")


def pattern(key_path: str) -> str:
    """``"rows[0].balls.count"`` -> ``"rows[].balls.count"``."""
    return _INDEX.sub("[]", key_path)


def fields_of(file: str) -> tuple:
    """The fields of one file (one of :data:`FILES`)."""
    return tuple(f for f in FIELDS if f.file == file)


def field(file: str, key_path: str) -> Field | None:
    """The field at ``key_path`` (indices allowed: ``rows[0].cage.width``), or None.

    An item of a list field (``gravity[1]``, ``phases.steady[0]``) gives the list's field.
    """
    p = pattern(key_path)
    f = _BY_PATH.get((file, p))
    if f is None and p.endswith("[]"):
        f = _BY_PATH.get((file, p[:-2]))
        if f is not None and f.kind != "list":
            return None
    return f


@functools.cache
def keys_under(file: str, table: str) -> tuple:
    """The keys a table allows, in schema order: ``keys_under("bearing", "rows[]")`` ->
    ``("pitch_diameter", ..., "balls", "inner_groove", ...)``; ``""`` is the top level."""
    prefix = f"{table}." if table else ""
    out = []
    for f in fields_of(file):
        if f.path.startswith(prefix):
            head = f.path[len(prefix):].split(".")[0].removesuffix("[]")
            out.append(head)
    return tuple(dict.fromkeys(out))


@functools.cache
def refused_keys(file: str, table: str) -> dict:
    """``{key: reason}`` of the keys :data:`REFUSED_KEYS` refuses in one table (``""`` the top level)."""
    prefix = f"{table}." if table else ""
    return {p[len(prefix):]: why for p, why in REFUSED_KEYS.get(file, {}).items()
            if p.startswith(prefix) and "." not in p[len(prefix):]}


def solver_fields() -> dict:
    """``{"output_rate": Field, ...}`` of the sweep's ``[solver]`` table."""
    return {f.path.removeprefix("solver."): f for f in fields_of("solver")}


def profile_channels() -> dict:
    """``{"radial_load": (kind, unit, fraction_allowed, required), ...}``: the profile's
    channel tables in ``rvcore.profile.CH_*`` order."""
    return dict(_CHANNEL_KINDS)


def operating_point() -> dict:
    """``{"speed": "angular_speed", ...}``: the operating point's keys and kinds."""
    return {f.path: f.unit_kind for f in fields_of("operating_point")}


def set_target(key: str) -> tuple:
    """(file, key path inside it) of a ``--set`` / sweep key: ``"solver.time_step"`` ->
    ``("solver", "solver.time_step")``, ``"profile.duration"`` -> ``("profile", "duration")``,
    ``"bearing.mounting"`` or ``"friction.mu_static"`` -> ``("bearing", ...)``."""
    if ("operating_point", key) in _BY_PATH:
        return "operating_point", key
    head, _, rest = key.partition(".")
    if head == "solver":
        return "solver", key
    if head in ("bearing", "profile") and rest:
        return head, rest
    return "bearing", key


def check_set_key(key: str, value=None, file="--set") -> Field:
    """The field a ``--set KEY=...`` names; ConfigError naming the known keys if none."""
    target, inner = set_target(key)
    f = field(target, inner)
    if f is None:
        head = pattern(inner).split(".")[0]
        near = [g.path for g in fields_of(target) if g.path.split(".")[0] == head]
        known = near or list(keys_under(target, ""))
        raise ConfigError(file, key, value,
                          f"unknown {target.replace('_', ' ')} key (known{' here' if near else ''}: "
                          f"{', '.join(known)}; `rvsweep check --fields` lists every key)")
    return f


def unhashed(file: str) -> tuple:
    """The top-level dataclass attributes of one file that the case id leaves out
    (:attr:`Field.hashed` false: free text), e.g. ``("description", "source")``."""
    return tuple(f.source for f in fields_of(file) if not f.hashed)


def item_class(hint):
    """The dataclass of a ``tuple[Row, ...]`` annotation's items, else None: how the loader
    (:func:`pipeline.schema.convert.from_fields`) and the read-back
    (:func:`pipeline.schema.stored.rebuild`) know an array of tables from a plain tuple."""
    if typing.get_origin(hint) in (typing.Union, types.UnionType):   # tuple[Waviness, ...] | None
        hint = next((h for h in typing.get_args(hint) if h is not type(None)), hint)
    args = typing.get_args(hint)
    if typing.get_origin(hint) is tuple and len(args) == 2 and args[1] is Ellipsis \
            and dataclasses.is_dataclass(args[0]):
        return args[0]
    return None


def dataclass_of(hint):
    """The dataclass of a ``Cage`` or ``Channel | None`` annotation (an optional table, None
    when left out), else None: how the loader and the read-back know a nested dataclass."""
    if dataclasses.is_dataclass(hint):
        return hint
    args = [a for a in typing.get_args(hint) if a is not type(None)]
    if typing.get_origin(hint) in (typing.Union, types.UnionType) and len(args) == 1 \
            and dataclasses.is_dataclass(args[0]):
        return args[0]
    return None


def field_map(file: str) -> dict:
    """``{path: Field}`` of one file's fields."""
    return {f.path: f for f in fields_of(file)}
