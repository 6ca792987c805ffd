"""The friction laws as data: their names and one record of parameters. SI throughout.

A law is one record of :data:`FRICTION_LAW_SIZE` floats (:func:`pack_friction_law`): its
kind, whether friction is on, the Coulomb/STEP parameters and, from :data:`LAW_EHL0` on,
the lubricated law's (:func:`pack_ehl_traction_law`), packed once per case
(:func:`rvcore.bearing.layout.compile_bearing`) and passed whole to the law functions of
:mod:`rvcore.contact.laws`, which dispatch on the kind to the law's module
(``coulomb_step``: :mod:`rvcore.contact.coulomb_step`; ``ehl_bair_winer``:
:mod:`rvcore.contact.traction_ehl`); nothing else reads a law's parameters. A bearing file
names its law with ``friction.law`` (``pipeline/schema/fields.py``), a field of
:class:`rvcore.bearing.geometry.ContactLaw` that :func:`rvcore.bearing.layout.compile_bearing`
passes as ``kind``. A further law is a name in :data:`FRICTION_LAWS`, its module beside
``coulomb_step`` and its select in each dispatcher of :mod:`rvcore.contact.laws`.

The lubricated law's columns live here (not in :mod:`rvcore.contact.traction_ehl`, which
re-exports them) because the record is packed by :mod:`rvcore.bearing.layout`, a layer
below ``contact``.
"""
from __future__ import annotations

import math

import numpy as np

#: The laws by name; ``coulomb_step`` is the study's Coulomb law with STEP transitions
#: (docs/model.md §4), ``ehl_bair_winer`` the lubricated law (docs/model.md §4.1,
#: :mod:`rvcore.contact.traction_ehl`).
FRICTION_LAWS = ("coulomb_step", "ehl_bair_winer")
COULOMB_STEP, EHL_BAIR_WINER = 0, 1
#: The two laws' names, as a bearing file spells them (``friction.law``).
DRY_LAW, LUBRICATED_LAW = FRICTION_LAWS[COULOMB_STEP], FRICTION_LAWS[EHL_BAIR_WINER]
#: Columns of the record: the law's index in FRICTION_LAWS, friction on (1) or off (0),
#: μ_s [-], v_s [m s^-1], μ_d [-], v_d [m s^-1], 1/v_s [s m^-1]; then, from LAW_EHL0, the
#: lubricated law's sub-record (EHL_* columns below; zeros for the Coulomb law).
LAW_KIND, LAW_ON, LAW_MU_S, LAW_V_S, LAW_MU_D, LAW_V_D, LAW_INV_VS = range(7)
LAW_EHL0 = 7

#: Columns of the lubricated law's sub-record (from LAW_EHL0): η0 [Pa s], α [Pa⁻¹],
#: τ_L0 [Pa], γ_L [-], μ_b [-], v_b [m s⁻¹], λ_b [-], λ_f [-], the slope cap c [s m⁻¹]
#: of the film's traction at zero slip (:mod:`rvcore.contact.traction_ehl`, Notes) and the
#: composite roughness σ [m].
(EHL_ETA0, EHL_ALPHA, EHL_TAU_L0, EHL_GAMMA_L, EHL_MU_B, EHL_V_B, EHL_LAMBDA_B, EHL_LAMBDA_F,
 EHL_SLOPE_CAP, EHL_SIGMA) = range(10)
EHL_LAW_SIZE = 10
FRICTION_LAW_SIZE = LAW_EHL0 + EHL_LAW_SIZE

#: Defaults of :func:`pack_ehl_traction_law` (sources: :mod:`rvcore.contact.traction_ehl`).
TAU_L0_DEFAULT = 0.0
GAMMA_L_DEFAULT = 0.07
MU_B_DEFAULT = 0.1
V_B_DEFAULT = 0.1
LAMBDA_B_DEFAULT = 1.0
LAMBDA_F_DEFAULT = 3.0
#: No cap (the pure law); the dynamics packs a finite one (rvcore.bearing.layout).
SLOPE_CAP_DEFAULT = math.inf
#: Composite roughness when none is given [m] (rvcore.bearing.lubricant's defaults, 0.186 µm).
SIGMA_DEFAULT = 0.186e-6


def pack_ehl_traction_law(eta0: float, alpha: float, *, tau_l0: float = TAU_L0_DEFAULT,
                          gamma_l: float = GAMMA_L_DEFAULT, mu_b: float = MU_B_DEFAULT,
                          v_b: float = V_B_DEFAULT, lambda_b: float = LAMBDA_B_DEFAULT,
                          lambda_f: float = LAMBDA_F_DEFAULT, slope_cap: float = SLOPE_CAP_DEFAULT,
                          sigma: float = SIGMA_DEFAULT) -> np.ndarray:
    """The lubricated law's sub-record (columns above).

    Parameters
    ----------
    eta0 : float
        Dynamic viscosity at the contact's temperature, ambient pressure [Pa s], > 0.
    alpha : float
        Pressure–viscosity coefficient [Pa⁻¹], ≥ 0.
    tau_l0 : float
        Limiting shear stress at zero pressure [Pa], ≥ 0.
    gamma_l : float
        Its pressure coefficient [-], ≥ 0, with ``tau_l0 + gamma_l > 0``.
    mu_b : float
        Boundary friction coefficient [-], ≥ 0.
    v_b : float
        Slip speed over which boundary friction rises to μ_b [m s⁻¹], > 0.
    lambda_b, lambda_f : float
        Film parameters of pure boundary and of full film [-], ``0 ≤ λ_b < λ_f``.
    slope_cap : float
        Cap ``c`` of the film's traction slope dμ/ds at zero slip [s m⁻¹], > 0 (``inf``:
        none; :mod:`rvcore.contact.traction_ehl`, Notes, "Slope cap").
    sigma : float
        Composite rms roughness of ball and raceway [m], > 0 (λ = h_min/σ).
    """
    values = dict(eta0=eta0, alpha=alpha, tau_l0=tau_l0, gamma_l=gamma_l, mu_b=mu_b, v_b=v_b,
                  lambda_b=lambda_b, lambda_f=lambda_f, sigma=sigma)
    for name, v in values.items():
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0.0):
            raise ValueError(f"EHL traction law: {name} must be a finite number >= 0, got {v!r}")
    if not (isinstance(slope_cap, (int, float)) and slope_cap > 0.0):
        raise ValueError(f"EHL traction law: slope_cap must be a number > 0 (inf: none), got {slope_cap!r}")
    if eta0 <= 0.0 or v_b <= 0.0 or sigma <= 0.0 or tau_l0 + gamma_l <= 0.0 or not lambda_b < lambda_f:
        raise ValueError("EHL traction law: need eta0 > 0, v_b > 0, sigma > 0, tau_l0 + gamma_l > 0 and "
                         f"lambda_b < lambda_f, got {values}")
    return np.array([eta0, alpha, tau_l0, gamma_l, mu_b, v_b, lambda_b, lambda_f, slope_cap, sigma],
                    dtype=float)


def pack_friction_law(mu_s: float, v_s: float, mu_d: float, v_d: float, *, on: bool = True,
                      kind: str = DRY_LAW, ehl: np.ndarray | None = None) -> np.ndarray:
    """The record of a friction law (layout above).

    Parameters
    ----------
    mu_s, mu_d : float
        Static and dynamic coefficients [-].
    v_s, v_d : float
        Their slip speeds, ``0 < v_s < v_d`` [m s^-1].
    on : bool
        False switches every friction force off (the conservation checks).
    kind : str
        One of :data:`FRICTION_LAWS`.
    ehl : ndarray or None
        The lubricated law's sub-record (:func:`pack_ehl_traction_law`), required when
        ``kind`` is ``ehl_bair_winer`` [SI per column].
    """
    if kind not in FRICTION_LAWS:
        raise ValueError(f"friction law {kind!r} must be one of {', '.join(FRICTION_LAWS)}")
    law = np.zeros(FRICTION_LAW_SIZE)
    law[LAW_KIND] = FRICTION_LAWS.index(kind)
    law[LAW_ON] = 1.0 if on else 0.0
    law[LAW_MU_S], law[LAW_V_S], law[LAW_MU_D], law[LAW_V_D] = mu_s, v_s, mu_d, v_d
    law[LAW_INV_VS] = 1.0 / v_s
    if kind == LUBRICATED_LAW:
        if ehl is None or len(ehl) != EHL_LAW_SIZE:
            raise ValueError("the ehl_bair_winer law needs its sub-record (pack_ehl_traction_law)")
        law[LAW_EHL0:] = ehl
    return law
