"""The lubricant: ISO VG grades, the viscosity at a temperature (ASTM D341 / Walther), the
dynamic viscosity, the pressure–viscosity coefficient and the surfaces' composite
roughness. Pure functions, SI in and out (kinematic viscosity in m² s⁻¹, temperatures in
K); where a standard writes its formula in its own units (mm² s⁻¹) the conversion is
inside and said there.

The bearing's lubricant (:class:`rvcore.bearing.geometry.Lubricant`) is resolved here into
what the other layers take: :func:`operating_viscosity` (Palmgren's viscous term, ISO 281's
κ, the film) and :func:`contact_lubricant` (η0, α and σ of the contacts).

Notes
-----
ISO VG grade (ISO 3448): the grade number is the midpoint kinematic viscosity at 40 °C in
mm² s⁻¹; a grade admits ±10 % around it.

Viscosity–temperature relation (ASTM D341, the Walther form)::

    log10 log10(ν + 0.7) = A − B·log10 T          ν in mm² s⁻¹, T in K

Two points (ν40 at 313.15 K, ν100 at 373.15 K) fix A and B. The constant 0.7 mm² s⁻¹ is
the simple form's; ASTM D341 adds small exponential terms to it below 2.0 mm² s⁻¹, so the
simple form used here is valid for ν ≥ 2.0 mm² s⁻¹ only, and is refused below. ASTM D341
also warns that its line holds only where the oil is a homogeneous liquid (between its
cloud point and its initial boiling point), which this module cannot check: the caller
keeps the temperature inside the oil maker's data.

Dynamic viscosity: ``η = ρ·ν``, with the density at the same temperature (an input: no
thermal expansion law is carried here).

References
----------
ISO 3448:1992, *Industrial liquid lubricants — ISO viscosity classification*.
ASTM D341, *Viscosity-Temperature Equations and Charts for Liquid Petroleum or
Hydrocarbon Products* (the 0.7 constant, the ν ≥ 2.0 mm²/s limit of the simple form and
the homogeneous-liquid warning were checked against the standard's published scope and
equations as reproduced by public pages; the standard itself was not at hand).
"""
from __future__ import annotations

import math

from ..standards.inputs import finite_positive

__all__ = [
    "ISO_VG_GRADES",
    "ISO_VG_TOLERANCE",
    "WALTHER_SHIFT",
    "WALTHER_MIN_VISCOSITY",
    "T40",
    "T100",
    "PRESSURE_VISCOSITY_DEFAULT",
    "BALL_ROUGHNESS_DEFAULT",
    "RACEWAY_ROUGHNESS_DEFAULT",
    "LubricantError",
    "iso_vg_viscosity",
    "walther_coefficients",
    "kinematic_viscosity",
    "dynamic_viscosity",
    "composite_roughness",
    "VG68_VISCOSITY_100",
    "DENSITY_DEFAULT",
    "base_oil",
    "lubricant_temperature",
    "operating_viscosity",
    "contamination_of",
    "contact_lubricant",
]

#: ISO VG grades: midpoint kinematic viscosity at 40 °C [mm² s⁻¹], ISO 3448:1992 Table 1
#: (the grade number is the midpoint).
ISO_VG_GRADES = (2, 3, 5, 7, 10, 15, 22, 32, 46, 68, 100, 150, 220, 320, 460, 680, 1000, 1500,
                 2200, 3200)
#: Relative tolerance of a grade around its midpoint, ±10 % (ISO 3448:1992 Table 1).
ISO_VG_TOLERANCE = 0.10

#: The shift of ASTM D341's simple Walther form, ``log log(ν + 0.7)`` [mm² s⁻¹].
WALTHER_SHIFT = 0.7
#: Lowest kinematic viscosity for which ASTM D341's simple form (shift 0.7 alone) holds
#: [mm² s⁻¹]; below it the standard adds exponential terms.
WALTHER_MIN_VISCOSITY = 2.0
#: The reference temperatures of ISO 3448 / ASTM D341 data sheets, 40 °C and 100 °C [K].
T40 = 313.15
T100 = 373.15

#: Default pressure–viscosity coefficient α [Pa⁻¹]: 2.0e-8 Pa⁻¹, a typical value for a
#: mineral oil near 40 °C (the order Hamrock's lubricant tables give, 1.5e-8 to 2.5e-8 Pa⁻¹
#: for mineral oils: B. J. Hamrock, *Fundamentals of Fluid Film Lubrication*, NASA RP-1255,
#: 1991, ch. 4) and the value of issue 40's reference contact. Not a property of a named
#: oil: give the oil maker's value, or a correlation (Gold et al. 2001, So & Klaus 1980),
#: when you have one. The value was not re-checked against the book this session.
PRESSURE_VISCOSITY_DEFAULT = 2.0e-8

#: Default rms roughnesses [m] of the balls (0.0625 µm) and of the raceways (0.175 µm):
#: the values of the ball-bearing worked example in B. J. Hamrock & D. Dowson, *Ball
#: Bearing Lubrication*, Wiley 1981 (also B. J. Hamrock, NASA RP-1255, 1991, the rolling
#: element bearing chapter), composite 0.186 µm. Ground and honed raceways of today are
#: often smoother; give measured values when you have them. Quoted from the example as
#: remembered; not re-checked against the book this session.
BALL_ROUGHNESS_DEFAULT = 0.0625e-6
RACEWAY_ROUGHNESS_DEFAULT = 0.175e-6


#: Default kinematic viscosity at 100 °C of the default base oil, ISO VG 68 [m² s⁻¹]:
#: 8.5 mm² s⁻¹, a viscosity index of 94 by ASTM D2270 (its table gives, at
#: ν100 = 8.5 mm² s⁻¹, L = 111.5 and H = 65.32 mm² s⁻¹, so
#: VI = (L − 68)/(L − H)·100 = 94.2), i.e. a solvent-refined paraffinic mineral oil of the
#: usual VI 95 rounded to the table's 0.1 mm² s⁻¹ row. The L and H values were read from the
#: D2270 table as the open ``fluids`` library (C. Bell) reproduces it; the standard itself
#: was not at hand. Give the oil maker's ν100 when you have it.
VG68_VISCOSITY_100 = 8.5e-6

#: Default density of the base oil [kg m⁻³]: 880, a paraffinic mineral oil of ISO VG 68 at
#: 15 °C (data sheets give 0.87–0.89 kg/L). Its fall with temperature (about 0.06 % per K)
#: is neglected: η0 = ρ·ν is low by at most about 2 % at 60 °C. An assumption.
DENSITY_DEFAULT = 880.0


class LubricantError(ValueError):
    """A lubricant input or a temperature outside what the relations here cover (said why)."""


def _finite_positive(name: str, value, unit: str) -> float:
    return finite_positive(name, value, unit, LubricantError)


def iso_vg_viscosity(grade) -> float:
    """Midpoint kinematic viscosity at 40 °C of an ISO VG grade [m² s⁻¹].

    Parameters
    ----------
    grade : int or str
        The grade number (``68``, ``"68"`` or ``"VG 68"``) [-], one of :data:`ISO_VG_GRADES`.

    Returns
    -------
    float
        ν40 [m² s⁻¹] (ISO 3448:1992: the grade number in mm² s⁻¹).
    """
    text = str(grade).strip().upper().replace("ISO", "").replace("VG", "").strip()
    try:
        g = int(float(text))
    except ValueError:
        raise LubricantError(f"ISO VG grade must be one of {ISO_VG_GRADES}, got {grade!r}") from None
    if g not in ISO_VG_GRADES or float(text) != g:
        raise LubricantError(f"ISO VG grade must be one of {ISO_VG_GRADES}, got {grade!r}")
    return g * 1e-6


def _loglog(nu_mm2s: float) -> float:
    return math.log10(math.log10(nu_mm2s + WALTHER_SHIFT))


def walther_coefficients(nu40, nu100):
    """ASTM D341 constants ``(A, B)`` of the line through ν40 and ν100 [-].

    Parameters
    ----------
    nu40, nu100 : float
        Kinematic viscosities at 40 °C and 100 °C [m² s⁻¹], ``nu40 > nu100 ≥ 2.0e-6``.

    Returns
    -------
    A, B : float
        ``log10 log10(ν + 0.7) = A − B·log10 T`` with ν in mm² s⁻¹ and T in K [-].

    Notes
    -----
    ``B = [loglog(ν40) − loglog(ν100)] / [log10 T100 − log10 T40]``,
    ``A = loglog(ν40) + B·log10 T40``.
    """
    n40 = _finite_positive("nu40", nu40, "m^2/s") * 1e6
    n100 = _finite_positive("nu100", nu100, "m^2/s") * 1e6
    if n100 < WALTHER_MIN_VISCOSITY:
        raise LubricantError(f"nu100 = {n100:.6g} mm^2/s is below {WALTHER_MIN_VISCOSITY} mm^2/s, "
                             "where ASTM D341's simple form (shift 0.7) does not hold")
    if not n40 > n100:
        raise LubricantError(f"nu40 = {n40:.6g} mm^2/s must exceed nu100 = {n100:.6g} mm^2/s "
                             "(an oil thins as it warms)")
    b = (_loglog(n40) - _loglog(n100)) / (math.log10(T100) - math.log10(T40))
    a = _loglog(n40) + b * math.log10(T40)
    return a, b


def kinematic_viscosity(temperature, nu40, nu100) -> float:
    """Kinematic viscosity at a temperature, ASTM D341 / Walther [m² s⁻¹].

    Parameters
    ----------
    temperature : float
        T [K], > 0.
    nu40, nu100 : float
        The oil's kinematic viscosities at 40 °C and 100 °C [m² s⁻¹]
        (:func:`walther_coefficients`).

    Returns
    -------
    float
        ν(T) [m² s⁻¹]: ``10^(10^(A − B·log10 T)) − 0.7`` mm² s⁻¹.

    Raises
    ------
    LubricantError
        An input out of range, or a result below 2.0 mm² s⁻¹ (outside the simple form's
        validity; the oil is too hot for it).
    """
    t = _finite_positive("temperature", temperature, "K")
    a, b = walther_coefficients(nu40, nu100)
    if t == T40:      # the line's own data points, exactly (not through 10^10^x's rounding)
        return float(nu40)
    if t == T100:
        return float(nu100)
    nu = 10.0 ** (10.0 ** (a - b * math.log10(t))) - WALTHER_SHIFT
    if not nu >= WALTHER_MIN_VISCOSITY:
        raise LubricantError(f"at {t:.6g} K the oil's viscosity would be {nu:.6g} mm^2/s, below "
                             f"{WALTHER_MIN_VISCOSITY} mm^2/s where ASTM D341's simple form holds")
    return nu * 1e-6


def dynamic_viscosity(kinematic, density) -> float:
    """Dynamic viscosity ``η = ρ·ν`` [Pa s].

    Parameters
    ----------
    kinematic : float
        ν [m² s⁻¹], at the temperature of ``density``.
    density : float
        ρ [kg m⁻³] at the same temperature.
    """
    return _finite_positive("kinematic viscosity", kinematic, "m^2/s") * \
        _finite_positive("density", density, "kg/m^3")


def composite_roughness(sigma1=BALL_ROUGHNESS_DEFAULT, sigma2=RACEWAY_ROUGHNESS_DEFAULT) -> float:
    """Composite rms roughness ``σ = sqrt(σ1² + σ2²)`` of two surfaces [m].

    Parameters
    ----------
    sigma1, sigma2 : float
        rms roughnesses (Rq) of the two surfaces [m], ≥ 0; by default the ball's and the
        raceway's (:data:`BALL_ROUGHNESS_DEFAULT`, :data:`RACEWAY_ROUGHNESS_DEFAULT`).
    """
    s = []
    for name, v in (("sigma1", sigma1), ("sigma2", sigma2)):
        try:
            x = float(v)
        except (TypeError, ValueError):
            raise LubricantError(f"{name} must be a number, got {v!r}") from None
        if not (math.isfinite(x) and x >= 0.0):
            raise LubricantError(f"{name} must be a finite roughness >= 0 m, got {v!r}")
        s.append(x)
    return math.hypot(s[0], s[1])


# --------------------------------------------------------------------------- a bearing's lubricant


def base_oil(lubricant) -> tuple:
    """``(ν40, ν100)`` [m² s⁻¹] of a :class:`rvcore.bearing.geometry.Lubricant`.

    Parameters
    ----------
    lubricant : rvcore.bearing.geometry.Lubricant
        Its ``viscosity_40`` and ``viscosity_100`` where given; else ``grade``'s midpoint
        ν40 (ISO 3448; ISO VG 68 when no grade is given) and, for ν100, ``viscosity_100``
        or :data:`VG68_VISCOSITY_100` (the only grade whose ν100 is built in).

    Raises
    ------
    LubricantError
        A grade other than 68 without ``viscosity_100``.
    """
    nu40 = lubricant.viscosity_40
    if nu40 is None:
        grade = 68 if lubricant.grade is None else lubricant.grade
        nu40 = iso_vg_viscosity(grade)
    nu100 = lubricant.viscosity_100
    if nu100 is None:
        if lubricant.viscosity_40 is not None or lubricant.grade not in (None, 68):
            raise LubricantError("viscosity_100 is needed: the only built-in ν100 is ISO VG 68's "
                                 "(8.5 mm^2/s, VI 94); give the oil's from its data sheet")
        nu100 = VG68_VISCOSITY_100
    return float(nu40), float(nu100)


def lubricant_temperature(bearing) -> float:
    """Temperature of the lubricant in the contacts' inlets [K]: the mean of the inner and
    outer ring temperatures (``bearing.inner_ring_temperature``,
    ``bearing.outer_ring_temperature``), an assumption (the ball runs between the two).

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    """
    return 0.5 * (bearing.inner_ring_temperature + bearing.outer_ring_temperature)


def operating_viscosity(bearing) -> float:
    """Kinematic viscosity of the lubricant at the operating temperature [m² s⁻¹].

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing

    Returns
    -------
    float
        ``lubricant.kinematic_viscosity`` where given (an override: the viscosity at the
        operating temperature, as measured or from the oil maker), else the base oil's
        ASTM D341 / Walther line (:func:`kinematic_viscosity`, :func:`base_oil`) at
        :func:`lubricant_temperature`.
    """
    lub = bearing.lubricant
    if lub.kinematic_viscosity is not None:
        return float(lub.kinematic_viscosity)
    nu40, nu100 = base_oil(lub)
    return kinematic_viscosity(lubricant_temperature(bearing), nu40, nu100)


def contamination_of(bearing) -> float:
    """The contamination factor e_C of the bearing's lubricant [-].

    ``lubricant.contamination`` where given (a number in [0, 1]); else the lower bound of
    ISO 281:2007 Table 13's default level
    (:data:`rvcore.standards.iso281_modified.CONTAMINATION_DEFAULT_LEVEL`, "normal
    cleanliness") in the column of the first row's pitch diameter.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
    """
    from ..standards.iso281_modified import CONTAMINATION_DEFAULT_LEVEL, contamination_factor

    ec = bearing.lubricant.contamination
    if ec is not None:
        return float(ec)
    return contamination_factor(CONTAMINATION_DEFAULT_LEVEL, bearing.rows[0].pitch_diameter, "low")


def contact_lubricant(bearing) -> tuple[float, float, float]:
    """(η0 [Pa s] at the operating temperature, α [1/Pa], composite roughness σ [m]).

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing

    Returns
    -------
    tuple of float
        ``η0 = ρ·ν`` (:func:`operating_viscosity`, ``lubricant.density``), the
        pressure–viscosity coefficient ``lubricant.pressure_viscosity`` and
        ``σ = sqrt(σ_ball² + σ_raceway²)`` (:func:`composite_roughness`).
    """
    lub = bearing.lubricant
    eta0 = dynamic_viscosity(operating_viscosity(bearing), lub.density)
    return (eta0, float(lub.pressure_viscosity),
            composite_roughness(lub.ball_roughness, lub.raceway_roughness))
