"""The friction law as data: its name and its record of parameters. SI throughout.

A law is one record of :data:`FRICTION_LAW_SIZE` floats (:func:`pack_friction_law`): its
kind, whether friction is on, and its parameters, packed once per case
(:func:`rvcore.bearing.layout.compile_bearing`) and passed whole to the law functions of
:mod:`rvcore.contact.laws`, which dispatch on the kind to the law's module
(``coulomb_step``: :mod:`rvcore.contact.coulomb_step`); nothing else reads a law's
parameters. A second law is a name in :data:`FRICTION_LAWS`, its module beside
``coulomb_step`` and its select in each dispatcher of :mod:`rvcore.contact.laws`.
A bearing file cannot name its law yet: that takes a ``friction.law`` key
(``pipeline/schema/fields.py``), a field of :class:`rvcore.bearing.geometry.ContactLaw`,
and :func:`rvcore.bearing.layout.compile_bearing` passing it as ``kind`` (the study's law
is the only one, and adding the field would change the hashed configuration).
"""
from __future__ import annotations

import numpy as np

#: The laws by name; ``coulomb_step`` is the study's Coulomb law with STEP transitions
#: (docs/model.md §4).
FRICTION_LAWS = ("coulomb_step",)
COULOMB_STEP = 0
#: Columns of the record: the law's index in FRICTION_LAWS, friction on (1) or off (0),
#: μ_s [-], v_s [m s^-1], μ_d [-], v_d [m s^-1], 1/v_s [s m^-1].
LAW_KIND, LAW_ON, LAW_MU_S, LAW_V_S, LAW_MU_D, LAW_V_D, LAW_INV_VS = range(7)
FRICTION_LAW_SIZE = 7


def pack_friction_law(mu_s: float, v_s: float, mu_d: float, v_d: float, *, on: bool = True,
                      kind: str = "coulomb_step") -> np.ndarray:
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
    """
    law = np.zeros(FRICTION_LAW_SIZE)
    law[LAW_KIND] = FRICTION_LAWS.index(kind)
    law[LAW_ON] = 1.0 if on else 0.0
    law[LAW_MU_S], law[LAW_V_S], law[LAW_MU_D], law[LAW_V_D] = mu_s, v_s, mu_d, v_d
    law[LAW_INV_VS] = 1.0 / v_s
    return law
