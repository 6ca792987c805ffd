"""rvsweep statics: quasi-static equilibrium of a bearing under a load."""
from __future__ import annotations

import json
import math

import numpy as np

from ..errors import UserError
from ._common import add_load_arguments, one_case_sweep

HELP = "quasi-static equilibrium: displacements, contact angles and ball loads"


def add_arguments(parser):
    add_load_arguments(parser, speed=False)
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    parser.add_argument("--no-gravity", action="store_true",
                        help="leave out the inner ring's weight (it is included by default, along the mounting)")


def run(args):
    from rvcore.quasistatic import NoEquilibriumError, solve_statics

    sweep = one_case_sweep(args, profile=None)
    case = sweep.cases[0]
    op, bearing = case.operating_point, case.bearing
    try:
        st = solve_statics(bearing, op.radial_load, op.axial_load, op.moment, op.load_angle,
                           gravity=not args.no_gravity)
    except NoEquilibriumError as exc:
        raise UserError(str(exc)) from None
    for w in bearing.warnings:
        print(f"warning: {w}", file=__import__("sys").stderr)
    inner = st.arc_rings == 0
    q_in = np.where(inner[None, :], st.ball_loads, 0.0).sum(axis=1)
    q_out = np.where(~inner[None, :], st.ball_loads, 0.0).sum(axis=1)
    if args.json:
        obj = {
            "bearing": bearing.name,
            "radial_load_N": op.radial_load, "axial_load_N": op.axial_load, "moment_Nm": op.moment,
            "radial_displacement_m": st.radial_displacement,
            "axial_displacement_m": st.axial_displacement,
            "inner_ring_x_m": st.displacement[0], "inner_ring_y_m": st.displacement[1],
            "inner_ring_z_m": st.displacement[2],
            "inner_ring_tilt_x_rad": st.displacement[3], "inner_ring_tilt_y_rad": st.displacement[4],
            "loaded_ball_count": st.loaded_ball_count,
            "max_contact_load_N": st.max_contact_load,
            "max_contact_pressure_Pa": st.max_contact_pressure,
            "ball_azimuth_rad": st.azimuths.tolist(),
            "arc_ring": ["inner" if r == 0 else "outer" for r in st.arc_rings],
            "ball_contact_load_N": st.ball_loads.tolist(),
            "ball_contact_angle_rad": [[None if math.isnan(a) else a for a in row] for row in st.contact_angles],
            "ball_inner_load_N": q_in.tolist(), "ball_outer_load_N": q_out.tolist(),
            "force_residual": st.residual.tolist(),
            "gravity_m_per_s2": [0.0, 0.0, 0.0] if args.no_gravity else list(bearing.gravity),
            "applied_force_with_ring_weight_N": st.applied[:3].tolist(),
            "warnings": list(bearing.warnings),
        }
        print(json.dumps(obj, indent=1))
        return 0
    print(f"bearing {bearing.name}: F_r = {op.radial_load / 1e3:.6g} kN at {math.degrees(op.load_angle):.4g} deg, "
          f"F_a = {op.axial_load / 1e3:.6g} kN, M = {op.moment:.6g} N m")
    weight = st.applied[:3] - np.array([op.radial_load * math.cos(op.load_angle),
                                        op.radial_load * math.sin(op.load_angle), op.axial_load])
    print("  ring weight          " + ("left out (--no-gravity)" if args.no_gravity else
                                      "(" + ", ".join(f"{w:.4g}" for w in weight) + ") N, included"))
    print(f"  radial displacement  {st.radial_displacement * 1e6:10.4f} um")
    print(f"  axial displacement   {st.axial_displacement * 1e6:10.4f} um")
    print(f"  tilt x, y            {st.displacement[3] * 1e3:10.5f}, {st.displacement[4] * 1e3:.5f} mrad")
    print(f"  loaded balls         {st.loaded_ball_count} of {st.ball_loads.shape[0]}")
    print(f"  max contact load     {st.max_contact_load:10.1f} N")
    print(f"  max Hertz pressure   {st.max_contact_pressure / 1e9:10.4f} GPa")
    print(f"  force balance        {np.abs(st.residual[:3]).max():.3g} N, {np.abs(st.residual[3:]).max():.3g} N m")
    print("  ball  azimuth[deg]  Q_inner[N]  Q_outer[N]  angles[deg] (per arc, inner first)")
    for j in range(st.ball_loads.shape[0]):
        angles = " ".join("   -  " if math.isnan(a) else f"{math.degrees(a):6.2f}" for a in st.contact_angles[j])
        print(f"  {j:4d}  {math.degrees(st.azimuths[j]):12.2f}  {q_in[j]:10.2f}  {q_out[j]:10.2f}  {angles}")
    return 0
