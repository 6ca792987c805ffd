"""The operating clearance: the rows' radial internal clearance at the rings' operating
temperatures, by thermal expansion. Pure functions, SI in and out (temperatures in K).

Notes
-----
A row's radial clearance ``P_d`` is given at the reference temperature ``T_ref`` (20 °C,
the temperature of ISO 5753-1's clearance measurement and of drawings). With the raceway
(groove-bottom) diameters ``d_i = d_m − D − P_d/2`` and ``d_o = d_m + D + P_d/2`` of the
model's centred ball (:mod:`rvcore.bearing.geometry`), each part grows freely by its own
``α_T·ΔT``::

    P_d' = P_d + α_r·ΔT_o·d_o − α_r·ΔT_i·d_i − 2·α_b·ΔT_b·D
         = P_d + α_r·ΔT_o·P_d + α_r·(ΔT_o − ΔT_i)·d_i + 2·D·(α_r·ΔT_o − α_b·ΔT_b)

with ``ΔT_i``, ``ΔT_o`` the inner and outer ring's rise over ``T_ref``, ``α_r`` the rings'
and ``α_b`` the balls' coefficient, and the balls at the mean of the two rings'
temperatures, ``ΔT_b = (ΔT_i + ΔT_o)/2`` (an assumption). The second form is the one
computed: for rings and balls of one material at one temperature it is ``α·ΔT·P_d``
exactly (0 for a zero clearance), as free expansion of one body says. A warmer inner ring
takes clearance up (about ``α·(T_i − T_o)·d_m``, the usual rule).

What is left out: the fits (a shrink fit's interference and its change with temperature),
the shaft's and housing's own expansion, and the growth of every other dimension (d_m, D,
the groove radii, by ``α·ΔT`` ≲ 1e-3 of themselves): only the clearance, a small
difference of large diameters, moves. A pair keeps the axial offset of its inner raceways
that set its preload at ``T_ref`` (:mod:`rvcore.statics.preload`); its operating preload
follows from the operating clearance in the statics and the dynamics.

Coefficient of bearing steel: ``α_T = 11.5e-6 K⁻¹`` (100Cr6 / GCr15 / AISI 52100 between 20
and 100 °C: the value steel makers' data sheets and the bearing makers' catalogues give,
11.5e-6 to 12.5e-6 K⁻¹; the lower one is issue 40's). Not re-checked against a data sheet
this session.
"""
from __future__ import annotations

import dataclasses

__all__ = ["STEEL_THERMAL_EXPANSION", "REFERENCE_TEMPERATURE", "OPERATING_TEMPERATURE_DEFAULT",
           "clearance_change", "operating_bearing"]

#: Linear thermal expansion coefficient of bearing steel [K⁻¹] (module Notes).
STEEL_THERMAL_EXPANSION = 11.5e-6
#: Temperature at which a bearing's clearance is given, 20 °C [K].
REFERENCE_TEMPERATURE = 293.15
#: Default operating temperature of both rings, 40 °C [K]: the temperature of the VG grade's
#: viscosity, an assumption (the study names none).
OPERATING_TEMPERATURE_DEFAULT = 313.15


def clearance_change(radial_clearance, pitch_diameter, ball_diameter, inner_temperature,
                     outer_temperature, reference_temperature=REFERENCE_TEMPERATURE,
                     ring_expansion=STEEL_THERMAL_EXPANSION, ball_expansion=STEEL_THERMAL_EXPANSION) -> float:
    """Change of a row's radial internal clearance from the reference to the operating
    temperatures [m] (module Notes).

    Parameters
    ----------
    radial_clearance : float
        ``P_d`` at ``reference_temperature`` [m].
    pitch_diameter, ball_diameter : float
        ``d_m``, ``D`` [m].
    inner_temperature, outer_temperature, reference_temperature : float
        ``T_i``, ``T_o``, ``T_ref`` [K].
    ring_expansion, ball_expansion : float
        ``α_r``, ``α_b`` [K⁻¹].

    Returns
    -------
    float
        ``P_d' − P_d`` [m]; exactly 0.0 where both rings are at ``T_ref``.
    """
    dti = float(inner_temperature) - float(reference_temperature)
    dto = float(outer_temperature) - float(reference_temperature)
    dtb = 0.5 * (dti + dto)
    d_i = pitch_diameter - ball_diameter - 0.5 * radial_clearance
    return (ring_expansion * dto * radial_clearance + ring_expansion * (dto - dti) * d_i
            + 2.0 * ball_diameter * (ring_expansion * dto - ball_expansion * dtb))


def operating_bearing(bearing):
    """``bearing`` with each row's radial clearance at the operating temperatures.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
        With its rows' clearances at ``bearing.reference_temperature`` and an empty
        ``nominal_radial_clearances``.

    Returns
    -------
    rvcore.bearing.geometry.Bearing
        The same object where no clearance moves (both rings at the reference, or one
        material at one temperature around a zero clearance); else a copy whose rows carry
        the operating clearance and whose ``nominal_radial_clearances`` keeps the given
        ones.
    """
    if bearing.nominal_radial_clearances:
        raise ValueError("the bearing's clearances are already at the operating temperatures")
    rows, nominal, moved = [], [], False
    for row in bearing.rows:
        d = clearance_change(row.radial_clearance, row.pitch_diameter, row.ball_diameter,
                             bearing.inner_ring_temperature, bearing.outer_ring_temperature,
                             bearing.reference_temperature, bearing.ring_material.thermal_expansion,
                             bearing.ball_material.thermal_expansion)
        nominal.append(row.radial_clearance)
        if d != 0.0:
            moved = True
            row = dataclasses.replace(row, radial_clearance=row.radial_clearance + d)
        rows.append(row)
    if not moved:
        return bearing
    return dataclasses.replace(bearing, rows=tuple(rows), nominal_radial_clearances=tuple(nominal))
