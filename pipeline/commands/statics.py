"""rvsweep statics: quasi-static equilibrium of a bearing under a load."""
from __future__ import annotations

import json
import math

import numpy as np

from ..errors import UserError
from .common import add_load_arguments, one_case_sweep

HELP = "quasi-static equilibrium: displacements, contact angles and ball loads"


#: Units of the ring's force and moment, the rows of K[i][j] = -dF_i/du_j.
_LOAD_UNITS = ("N", "N", "N", "N m", "N m")


def add_arguments(parser):
    add_load_arguments(parser, speed=False)
    parser.add_argument("--speed", default=None,
                        help='inner-ring speed, e.g. "120deg/s" or "20 rpm": adds the lubrication outputs '
                             "(ISO 281's kappa, a_ISO and L_nm; the film of the heaviest-loaded inner contact)")
    parser.add_argument("--moment-x", default="0 N*m",
                        help='moment about the x axis, e.g. "2 kN*m" (added to --moment; default 0)')
    parser.add_argument("--moment-y", default="0 N*m",
                        help='moment about the y axis, e.g. "-1.5kNm" (added to --moment; default 0)')
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    parser.add_argument("--no-gravity", action="store_true",
                        help="leave out the inner ring's weight (it is included by default, along the mounting)")
    parser.add_argument("--runout", type=int, default=None, metavar="N",
                        help="also the quasi-static runout path: the pose at N ring angles over one revolution "
                             "(an imperfect bearing's; see [imperfections])")
    parser.add_argument("--seed", type=int, default=-1, metavar="S",
                        help="the realization whose tolerance-class draws (high points, ball sizes) every "
                             "number uses, as a sweep's case with that seed; default -1 (high points at 0)")


def stiffness_units() -> list:
    """Units of each entry of the stiffness matrix, as nested lists like the matrix."""
    from rvcore.statics.stiffness import COORDINATE_UNITS

    return [[f"{_LOAD_UNITS[i]}/{COORDINATE_UNITS[j]}" for j in range(5)] for i in range(5)]


def _moments(args) -> tuple:
    """(moment_x, moment_y) [N m] of the command line."""
    from ..schema.units import parse_quantity

    return tuple(parse_quantity(getattr(args, a), "moment", file="command line", key=f"--{a.replace('_', '-')}")
                 for a in ("moment_x", "moment_y"))


def _finite(x):
    """A float for JSON: None where it is not finite (an unloaded bearing's infinite life)."""
    return float(x) if x is not None and math.isfinite(x) else None


def run(args):
    from rvcore.bearing.imperfections import realize
    from rvcore.standards.iso16281 import LifeError, dynamic_rating_basis, static_life
    from rvcore.statics.preload import preload_force
    from rvcore.statics.equilibrium import NoEquilibriumError, solve_statics
    from rvcore.contact.laws import LOADED_BALL_LOAD
    from rvcore.statics.stiffness import COORDINATES, stiffness_scalars
    from rvcore.rings.flexible import bearing_rings

    _check_runout(args)   # before any work
    sweep = one_case_sweep(args, profile=None)
    case = sweep.cases[0]
    op, bearing = case.operating_point, case.bearing
    if args.speed is not None and not op.speed > 0.0:   # before any work
        raise UserError(f"--speed {args.speed!r}: the lubrication outputs need a speed > 0 (leave --speed "
                        "out for none)")
    # the realization of --seed (a tolerance class's high-point angles and ball sizes, as a
    # sweep's case with that seed runs): the headline numbers, the lives and the runout
    # path all come from this one bearing (issue 39 item 13)
    bearing = realize(bearing, args.seed)
    mx, my = _moments(args)
    rings = bearing_rings(bearing)

    def solve(r):
        return solve_statics(bearing, op.radial_load, op.axial_load, op.moment, op.load_angle,
                             moment_x=mx, moment_y=my, gravity=not args.no_gravity, rings=r)

    try:   # a flexible bearing: its rings' equilibrium, and the rigid rings' beside it
        st = solve(None if rings.rigid else rings)
        st_rigid = None if rings.rigid else solve(None)
    except NoEquilibriumError as exc:
        raise UserError(str(exc)) from None
    path = _runout(args, bearing, op, mx, my)
    flexible = _flexible(bearing, rings, st, st_rigid)
    k = np.asarray(st.stiffness_matrix, dtype=float)
    k_radial, k_axial, k_tilt = stiffness_scalars(k, op.load_angle)
    kc_radial, kc_axial, kc_tilt = st.free_stiffness_scalars()
    preload = preload_force(bearing)
    pair = len(bearing.rows) > 1
    for w in bearing.warnings:
        print(f"warning: {w}", file=__import__("sys").stderr)
    inner = st.arc_rings == 0
    q_in = np.where(inner[None, :], st.ball_loads, 0.0).sum(axis=1)
    q_out = np.where(~inner[None, :], st.ball_loads, 0.0).sum(axis=1)
    # ISO 281 P_r from the applied loads (the ring's weight is a part of them only when
    # gravity is on, as in the equilibrium); ISO/TS 16281 from the load distribution
    fr, fa = float(np.hypot(*st.applied[:2])), float(st.applied[2])
    try:
        life = static_life(bearing, st, fr, fa)
        life_note = ""
    except LifeError as exc:
        life = dict.fromkeys(("reference_rating_life_L10r_Mrev", "basic_rating_life_L10_Mrev",
                              "dynamic_load_rating_N", "equivalent_load_N"), math.nan)
        life_note = str(exc)
    ratings = _ratings(bearing, st, fr, fa)
    lub = _lubrication(bearing, st, op.speed) if args.speed is not None else None
    if args.json:
        obj = {
            "bearing": bearing.name,
            "radial_load_N": op.radial_load, "axial_load_N": op.axial_load, "moment_Nm": op.moment,
            "radial_displacement_m": st.radial_displacement,
            "axial_displacement_m": st.axial_displacement,
            "inner_ring_x_m": st.displacement[0], "inner_ring_y_m": st.displacement[1],
            "inner_ring_z_m": st.displacement[2],
            "inner_ring_tilt_x_rad": st.displacement[3], "inner_ring_tilt_y_rad": st.displacement[4],
            "inner_ring_tilt": st.tilt,
            "tilt_reaction_moment_Nm": np.asarray(st.reaction_moment, dtype=float).tolist(),
            "tilt_note": ("free: the ring tilts under zero moment; held: both tilts fixed at 0 by a support "
                          "(a shaft on a second bearing), tilt_reaction_moment_Nm the moment about x, y it "
                          "applies (inner_ring.tilt in the bearing file, or --set inner_ring.tilt=held)"),
            "loaded_ball_count": st.loaded_ball_count,
            "loaded_ball_note": (f"balls carrying more than {LOADED_BALL_LOAD:g} N on both the inner and the "
                                 "outer race"),
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
            "moment_x_Nm": mx, "moment_y_Nm": my,
            "applied_moment_Nm": st.applied[3:5].tolist(),
            "row_count": len(bearing.rows),
            "arrangement": bearing.arrangement,
            "preload_N": preload,
            "preload_offset_m": bearing.preload_offset,
            "stiffness_matrix": k.tolist(),
            "stiffness_matrix_labels": list(COORDINATES),
            "stiffness_matrix_units": stiffness_units(),
            "stiffness_matrix_note": ("K[i][j] = -dF_i/du_j at the equilibrium: rows the ring's force "
                                      "and moment (Fx, Fy, Fz [N], Mx, My [N m]), columns its pose "
                                      "(x, y, z [m], tilt_x, tilt_y [rad]); SI"),
            # max|K(h/2) - K(h)|/max|K| of the plain central difference (rvcore.statics.stiffness):
            # how converged the difference is before its Richardson extrapolation
            "stiffness_matrix_step_change": st.stiffness_change,
            "radial_stiffness_N_per_m": k_radial,
            "axial_stiffness_N_per_m": k_axial,
            "tilting_stiffness_Nm_per_rad": k_tilt,
            "radial_stiffness_compliant_N_per_m": _finite(kc_radial),
            "axial_stiffness_compliant_N_per_m": _finite(kc_axial),
            "tilting_stiffness_compliant_Nm_per_rad": _finite(kc_tilt),
            "stiffness_note": ("*_stiffness: direct terms K_ii of the tangent stiffness in the load frame, "
                               "every other coordinate held; *_stiffness_compliant: 1/C_ii of the compliance "
                               "C = K^-1, every other coordinate free (a held ring's tilts stay held: its "
                               "tilting value is null)"),
            "reference_rating_life_L10r_Mrev": _finite(life["reference_rating_life_L10r_Mrev"]),
            "basic_rating_life_L10_Mrev": _finite(life["basic_rating_life_L10_Mrev"]),
            "dynamic_load_rating_N": _finite(life["dynamic_load_rating_N"]),
            "equivalent_load_N": _finite(life["equivalent_load_N"]),
            "dynamic_load_rating_source": ("catalogue" if bearing.dynamic_load_rating > 0 else "ISO 281 geometry"),
            "dynamic_rating_basis": dynamic_rating_basis(bearing),
            "static_rating_basis": ratings.pop("rating_basis"),
            "seed": args.seed,
            "rating_life_note": ("10^6 revolutions of the inner ring, 90 % reliability, no life modification "
                                 "factor; L10r per ISO/TS 16281 from the ball loads, L10 per ISO 281 with "
                                 "P = X F_r + Y F_a; null: infinite (nothing loaded) or not rated"
                                 + (f" ({life_note})" if life_note else "")),
            **{k: _finite(v) if isinstance(v, float) else v for k, v in ratings.items()},
            "static_safety_factor_note": ("ISO 76 3.6 s0 = C0/P0, a load ratio, two ways: "
                                          "static_safety_factor_pressure = (4200 MPa / max_contact_pressure)^3 from "
                                          "this load distribution (ISO 76 3.2: 4200 MPa at C0; p_max ~ Q^(1/3)); "
                                          "static_safety_factor_catalogue = C0r/P0r, C0r = f0 i Z Dw^2 cos(alpha) "
                                          "(6.1.1, Table 1), P0r = max(X0 Fr + Y0 Fa, Fr) (6.2, Table 2): "
                                          "Stribeck's idealised distribution, no tilt, no moment; f0 reduced where "
                                          "the groove radii exceed 0.52/0.53 Dw (static_rating_basis)"),
            "friction_moment_note": ("Palmgren's load term f1 F_beta d_m at these loads, f1 = z (P0r/C0r)^y with "
                                     "the C0r above; its viscous term needs a speed and is in each case file "
                                     "(friction_moment_palmgren_viscous); null where it does not apply (pairs, "
                                     "four-point rows). Constants: "
                                     + _palmgren_basis(bearing) + "; " + _published_spread()),
            "warnings": list(bearing.warnings),
            **_temperature_json(bearing),
        }
        if flexible is not None:
            obj.update(flexible)
        if lub is not None:
            obj.update(lub)
        else:
            obj["lubrication_note"] = _NO_SPEED
        if path is not None:
            obj["runout_path"] = {"ring_angle_rad": path["ring_angle"].tolist(),
                                  "ball_angle_rad": path["ball_angle"].tolist(),
                                  "radial_displacement_m": path["radial_displacement"].tolist(),
                                  "axial_displacement_m": path["axial_displacement"].tolist(),
                                  "tilt_x_rad": path["displacement"][:, 3].tolist(),
                                  "tilt_y_rad": path["displacement"][:, 4].tolist(),
                                  "radial_displacement_range_m": path["radial_displacement_range"],
                                  "axial_displacement_range_m": path["axial_displacement_range"]}
            if flexible is not None:   # rvcore.statics.runout solves rigid rings
                obj["runout_path"]["rings"] = "rigid"
        if pair:
            obj["row_axial_load_N"] = np.asarray(st.row_axial_loads, dtype=float).tolist()
            obj["row_radial_load_N"] = np.asarray(st.row_radial_loads, dtype=float).tolist()
        print(json.dumps(obj, indent=1))
        return 0
    print(f"bearing {bearing.name}: F_r = {op.radial_load / 1e3:.6g} kN at {math.degrees(op.load_angle):.4g} deg, "
          f"F_a = {op.axial_load / 1e3:.6g} kN, M = {op.moment:.6g} N m")
    weight = st.applied[:3] - np.array([op.radial_load * math.cos(op.load_angle),
                                        op.radial_load * math.sin(op.load_angle), op.axial_load])
    print("  ring weight          " + ("left out (--no-gravity)" if args.no_gravity else
                                      "(" + ", ".join(f"{w:.4g}" for w in weight) + ") N, included"))
    if mx or my:
        print(f"  moment x, y          {mx:.6g}, {my:.6g} N m (added to M)")
    if pair:
        print(f"  rows                 {len(bearing.rows)}, {bearing.arrangement or 'as given'}; preload "
              f"{preload / 1e3:.4g} kN (ring offset {bearing.preload_offset * 1e6:.4g} um)")
        for r, (fa, fr) in enumerate(zip(st.row_axial_loads, st.row_radial_loads)):
            print(f"  row {r} load           axial {fa / 1e3:10.4f} kN, radial {fr / 1e3:.4f} kN")
    print(f"  radial displacement  {st.radial_displacement * 1e6:10.4f} um")
    print(f"  axial displacement   {st.axial_displacement * 1e6:10.4f} um")
    print(f"  tilt x, y            {st.displacement[3] * 1e3:10.5f}, {st.displacement[4] * 1e3:.5f} mrad "
          + ("(free: zero moment)" if st.tilt == "free" else "(held at 0)"))
    if st.tilt == "held":
        print(f"  reaction moment x, y {st.reaction_moment[0]:10.1f}, {st.reaction_moment[1]:.1f} N m "
              "(the support holding the tilt)")
    print(f"  loaded balls         {st.loaded_ball_count} of {st.ball_loads.shape[0]} "
          f"(more than {LOADED_BALL_LOAD:g} N on both races)")
    print(f"  max contact load     {st.max_contact_load:10.1f} N")
    print(f"  max Hertz pressure   {st.max_contact_pressure / 1e9:10.4f} GPa")
    print(f"  static safety s0     {_num(ratings['static_safety_factor_pressure'])} = (4200 MPa/p_max)^3, "
          f"{_num(ratings['static_safety_factor_catalogue'])} = C0r/P0r (ISO 76; C0r "
          f"{_num(ratings['static_load_rating_N'] / 1e3)} kN, P0r {_num(ratings['static_equivalent_load_N'] / 1e3)} kN)")
    print(f"  rating basis         C0r: {ratings['rating_basis']}")
    print(f"  friction moment      {_num(ratings['friction_moment_load_term_Nm'])} N m (Palmgren's load term, f1 "
          "from P0r/C0r above; the model's own torque is in a simulation)")
    # engineering units: N/m -> N/um, N m/rad -> N m/mrad
    # direct: every other coordinate held; compliant: every other coordinate free
    print(f"  radial stiffness     {k_radial * 1e-6:10.4g} N/um direct, {kc_radial * 1e-6:.4g} N/um compliant "
          "(along the radial load)")
    print(f"  axial stiffness      {k_axial * 1e-6:10.4g} N/um direct, {kc_axial * 1e-6:.4g} N/um compliant")
    print(f"  tilting stiffness    {k_tilt * 1e-3:10.4g} N m/mrad direct, "
          + ("- (tilt held)" if st.tilt == "held" else f"{kc_tilt * 1e-3:.4g} N m/mrad compliant"))
    print("                       (direct: the other coordinates held; compliant: the others free)")
    _print_life(life, bearing, life_note)
    if flexible is not None:
        _print_flexible(flexible)
    _print_lubrication(bearing, lub)
    print(f"  force balance        {np.abs(st.residual[:3]).max():.3g} N, {np.abs(st.residual[3:]).max():.3g} N m")
    if path is not None:
        print(f"  runout path          {'(rigid rings) ' if flexible is not None else ''}over one revolution, "
              f"{len(path['ring_angle'])} ring angles: delta_r range "
              f"{path['radial_displacement_range'] * 1e6:.4g} um, delta_a range "
              f"{path['axial_displacement_range'] * 1e6:.4g} um")
        print("    ring[deg]  delta_r[um]  delta_a[um]  tilt_x[urad]  tilt_y[urad]")
        for a, r_, z_, (tx, ty) in zip(path["ring_angle"], path["radial_displacement"], path["axial_displacement"],
                                       path["displacement"][:, 3:5]):
            print(f"    {math.degrees(a):9.2f}  {r_ * 1e6:11.4f}  {z_ * 1e6:11.4f}  {tx * 1e6:12.4f}  {ty * 1e6:12.4f}")
    rigid_in = None if flexible is None else flexible["rigid_rings"]["ball_inner_load_N"]
    print("  ball  azimuth[deg]  Q_inner[N]  Q_outer[N]  " + ("" if rigid_in is None else "Q_inner rigid[N]  ")
          + "angles[deg] (per arc, inner first)")
    for j in range(st.ball_loads.shape[0]):
        angles = " ".join("   -  " if math.isnan(a) else f"{math.degrees(a):6.2f}" for a in st.contact_angles[j])
        beside = "" if rigid_in is None else f"{rigid_in[j]:16.2f}  "
        print(f"  {j:4d}  {math.degrees(st.azimuths[j]):12.2f}  {q_in[j]:10.2f}  {q_out[j]:10.2f}  {beside}{angles}")
    return 0


def _flexible(bearing, rings, st, st_rigid) -> dict | None:
    """A flexible bearing's JSON additions: the rigid rings' numbers beside the flexible ones
    (:func:`rvcore.statics.flexible.headline`), and the rings' deformation [SI]; None when rigid."""
    if st_rigid is None:
        return None
    from rvcore.statics.flexible import DEFORMATION, HEADLINE, headline, ring_deformation

    def ring_loads(result):
        inner = result.arc_rings == 0
        return np.where(inner[None, :], result.ball_loads, 0.0).sum(axis=1).tolist()

    def side(result):
        h = headline(bearing, result)
        h["reference_rating_life_L10r"] *= 1e-6   # revolutions -> 10^6 revolutions, as above
        h["basic_rating_life_L10"] *= 1e-6
        out = {f"{k}{_HEADLINE_SUFFIX[k]}": (_finite(h[k]) if k != "loaded_ball_count" else int(h[k]))
               for k in HEADLINE}
        out.update(ball_contact_load_N=result.ball_loads.tolist(), ball_inner_load_N=ring_loads(result),
                   radial_displacement_m=result.radial_displacement, axial_displacement_m=result.axial_displacement,
                   tilt_rad=result.displacement[3:5].tolist(),
                   stiffness_matrix=np.asarray(result.stiffness_matrix, dtype=float).tolist())
        return out

    deformation = ring_deformation(rings, st)
    return {
        "flexible_rings": {r: getattr(bearing, f"{r}_ring_support").kind
                           if getattr(bearing, f"{r}_ring_support") is not None else "rigid"
                           for r in ("inner", "outer")},
        "flexible": side(st), "rigid_rings": side(st_rigid),
        "ring_deformation_m": {k: _finite(v) for k, v in deformation.items()},
        "ring_iterations": st.ring_iterations,
        "flexible_rings_note": (
            "the bearing's rings are flexible in their supports (docs/model.md section 16): every other number "
            "of this output is the flexible rings' equilibrium; 'flexible' and 'rigid_rings' set the compared "
            "numbers side by side, the rigid rings solved at the same loads. "
            + "; ".join(f"{k}: {w}" for k, (_, w) in HEADLINE.items())
            + ". ring_deformation_m: " + "; ".join(f"<ring>_ring_{k}: {w}" for k, (_, w) in DEFORMATION.items())
            + " (null: that ring or direction rigid). SI, the lives in 10^6 revolutions (_Mrev)."),
    }


#: The unit suffixes of the compared numbers in the JSON (lives in 10^6 rev, as above).
_HEADLINE_SUFFIX = {"max_contact_load": "_N", "max_contact_pressure": "_Pa", "loaded_ball_count": "",
                    "static_safety_factor": "_pressure", "reference_rating_life_L10r": "_Mrev",
                    "basic_rating_life_L10": "_Mrev", "radial_stiffness": "_N_per_m",
                    "axial_stiffness": "_N_per_m", "tilting_stiffness": "_Nm_per_rad"}


def _print_flexible(flexible: dict) -> None:
    """The flexible rings' numbers beside the rigid rings', with the change, and the rings'
    deformation, in engineering units."""
    f, r = flexible["flexible"], flexible["rigid_rings"]
    rings = flexible["flexible_rings"]
    print(f"  flexible rings       inner {rings['inner']}, outer {rings['outer']} "
          f"({flexible['ring_iterations']} iterations); flexible | rigid rings | change:")
    rows = (("max contact load", "max_contact_load_N", 1.0, "N"),
            ("max Hertz pressure", "max_contact_pressure_Pa", 1e-9, "GPa"),
            ("loaded balls", "loaded_ball_count", 1.0, ""),
            ("static safety s0", "static_safety_factor_pressure", 1.0, ""),
            ("life L10r", "reference_rating_life_L10r_Mrev", 1.0, "Mrev"),
            ("life L10", "basic_rating_life_L10_Mrev", 1.0, "Mrev"),
            ("radial stiffness", "radial_stiffness_N_per_m", 1e-6, "N/um"),
            ("axial stiffness", "axial_stiffness_N_per_m", 1e-6, "N/um"),
            ("tilting stiffness", "tilting_stiffness_Nm_per_rad", 1e-3, "N m/mrad"))
    for label, key, scale, unit in rows:
        a, b = f[key], r[key]
        change = (f"{(a / b - 1.0) * 100:+7.1f} %" if a is not None and b not in (None, 0) else "      -")
        print(f"    {label:18s} {_num(None if a is None else a * scale)} | "
              f"{_num(None if b is None else b * scale)} {unit:8s} {change}")
    d = flexible["ring_deformation_m"]
    for ring in ("inner", "outer"):
        if rings[ring] == "rigid":
            continue
        print(f"  {ring} ring deformation ovalisation {_num(d[f'{ring}_ring_ovalisation'] * 1e6)} um, largest radial "
              f"{_num(d[f'{ring}_ring_max_radial_deformation'] * 1e6)} um, axial "
              f"{_num(d[f'{ring}_ring_max_axial_deformation'] * 1e6)} um")


def _runout(args, bearing, op, mx: float, my: float):
    """The quasi-static runout path of ``--runout N`` (None without it)."""
    if args.runout is None:
        return None
    if mx or my:
        raise UserError("--runout takes --moment only (about the axis normal to the radial load), "
                        "not --moment-x/--moment-y")
    from rvcore.statics.equilibrium import NoEquilibriumError
    from rvcore.statics.runout import runout_path

    try:
        return runout_path(bearing, op.radial_load, op.axial_load, op.moment, op.load_angle,
                           points=args.runout, gravity=not args.no_gravity, seed=args.seed)
    except NoEquilibriumError as exc:
        raise UserError(str(exc)) from None


def _check_runout(args) -> None:
    """``--runout N`` within its bounds, before any work: at least 2 ring angles, at most
    :data:`pipeline.schema.physical.MAX_RUNOUT_POINTS`."""
    from ..schema.physical import MAX_RUNOUT_POINTS

    if args.runout is None:
        return
    if args.runout < 2:
        raise UserError(f"--runout {args.runout}: give at least 2 ring angles (leave --runout out "
                        "for no runout path)")
    if args.runout > MAX_RUNOUT_POINTS:
        raise UserError(f"--runout {args.runout}: more than the {MAX_RUNOUT_POINTS} ring angles (one every "
                        f"{360 / MAX_RUNOUT_POINTS:g} deg) a runout path takes; each is a full quasi-static solve")


def _palmgren_basis(bearing) -> str:
    from rvcore.standards.palmgren import palmgren_basis

    return palmgren_basis(bearing.rows[0].nominal_contact_angle)


def _published_spread() -> str:
    from rvcore.standards.palmgren import published_spread_text

    return published_spread_text()


def _num(x) -> str:
    """``x`` to 4 significant digits, or '-' where not rated."""
    return f"{x:10.4g}" if x is not None and math.isfinite(x) else "         -"


def _ratings(bearing, st, fr: float, fa: float) -> dict:
    """ISO 76's s0 both ways and Palmgren's load term at these loads [SI]; NaN where not rated."""
    from rvcore.standards.palmgren import FrictionMomentError, friction_moment
    from rvcore.standards.iso16281 import LifeError
    from rvcore.standards.iso76 import (StaticRatingError, static_safety_factor,
                                      static_safety_factor_from_pressure)

    out = {"static_safety_factor_pressure": float(static_safety_factor_from_pressure(st.max_contact_pressure))}
    try:
        cat = static_safety_factor(bearing, fr, abs(fa))
    except (LifeError, StaticRatingError) as exc:
        cat = dict.fromkeys(("static_safety_factor", "static_load_rating_N", "static_equivalent_load_N"), math.nan)
        cat["rating_basis"] = f"not rated: {exc}"
    out["rating_basis"] = cat["rating_basis"]
    out["static_safety_factor_catalogue"] = float(cat["static_safety_factor"])
    out["static_load_rating_N"] = float(cat["static_load_rating_N"])
    out["static_equivalent_load_N"] = float(cat["static_equivalent_load_N"])
    try:
        out["friction_moment_load_term_Nm"] = float(friction_moment(bearing, fr, abs(fa), 0.0)["load_moment_N_m"])
    except (LifeError, StaticRatingError, FrictionMomentError):
        out["friction_moment_load_term_Nm"] = math.nan
    return out


def _print_life(life: dict, bearing, note: str) -> None:
    """The rating lives in engineering units (10^6 rev, kN)."""
    def mrev(x):
        return "inf (unloaded)" if x == math.inf else ("-" if not math.isfinite(x) else f"{x:10.4g} Mrev")

    c = life["dynamic_load_rating_N"]
    src = ("catalogue" if bearing.dynamic_load_rating > 0 else
           "ISO 281 from the geometry, Table 2 f_c within groove radii 0.52/0.53 Dw")
    print(f"  load rating C_r      {c / 1e3:10.4g} kN ({src})" if math.isfinite(c) else
          f"  load rating C_r      -  ({note})")
    print(f"  life L10r            {mrev(life['reference_rating_life_L10r_Mrev'])} (ISO/TS 16281, ball loads)")
    p = life["equivalent_load_N"]
    print(f"  life L10             {mrev(life['basic_rating_life_L10_Mrev'])} (ISO 281, P = "
          + (f"{p / 1e3:.4g} kN)" if math.isfinite(p) else "- )"))


_NO_SPEED = ("no lubrication outputs: the film, kappa and a_ISO depend on the speed; give --speed "
             "(e.g. --speed 120deg/s)")


def _temperature_json(bearing) -> dict:
    """The temperatures and the operating clearance [K, m]."""
    nominal = bearing.nominal_radial_clearances or tuple(r.radial_clearance for r in bearing.rows)
    return {"inner_ring_temperature_K": bearing.inner_ring_temperature,
            "outer_ring_temperature_K": bearing.outer_ring_temperature,
            "reference_temperature_K": bearing.reference_temperature,
            "operating_clearance_m": [r.radial_clearance for r in bearing.rows],
            "nominal_clearance_m": list(nominal),
            "clearance_note": ("radial internal clearance of each row: nominal at the reference temperature, "
                               "operating at the rings' temperatures (thermal expansion, "
                               "rvcore.bearing.thermal); the statics use the operating one")}


def _lubrication(bearing, st, speed: float) -> dict:
    """The lubrication outputs of ``--speed`` (:func:`rvcore.statics.lubrication.lubrication_at`), SI,
    with the notes saying what each is."""
    from rvcore.bearing.lubricant import LubricantError, lubricant_temperature

    from rvcore.statics.lubrication import lubrication_at

    try:
        r = lubrication_at(bearing, st, speed)
    except LubricantError as exc:
        raise UserError(f"[lubricant]: {exc}") from None
    out = {"speed_rad_per_s": float(speed), "lubricant_temperature_K": lubricant_temperature(bearing)}
    for k, v in r.items():
        out[k] = _finite(v) if isinstance(v, float) else v
    out["lubrication_units"] = {
        "operating_viscosity": "m2 s-1", "reference_viscosity_nu1": "m2 s-1", "kappa": "1", "a_iso": "1",
        "contamination_factor": "1", "fatigue_load_limit": "N", "equivalent_load": "N",
        "basic_rating_life_L10": "revolutions", "modified_rating_life_L_nm": "revolutions",
        "film_thickness_central": "m", "film_thickness_min": "m", "film_contact_load": "N",
        "entrainment_speed": "m s-1", "composite_roughness": "m", "lambda": "1", "speed_rad_per_s": "rad s-1",
        "lubricant_temperature_K": "K"}
    out["lubrication_note"] = (
        "ISO 281:2007 clause 9 at this speed: kappa = nu/nu1 (nu at the mean ring temperature, ASTM D341; nu1 "
        "from n and d_m), a_ISO for ball bearings with e_C and C_u = C0/22 (100/d_m)^0.5, L_nm = a_1 a_ISO L10 "
        "in revolutions (a_1 = 1, 90 %; L10 of ISO 281 with P = X Fr + Y Fa; L10r has no a_ISO); kappa above 4 "
        "taken as 4, kappa_outside_iso281 true below 0.1 (boundary lubrication: a_ISO taken at 0.1, outside the "
        "standard). Film: Hamrock-Dowson, fully flooded and isothermal, the heaviest-loaded inner contact at its "
        "contact angle, pure rolling; grease starvation makes it an upper bound, measured films scatter about "
        "+-30 % around it; lambda = h_min/sigma; regime: boundary < 1 <= mixed < 3 <= full film"
        + ("; the contact's ellipticity lies outside Hamrock-Dowson's fitted 1-8 (extrapolated)"
           if r.get("film_extrapolated") else ""))
    return out


def _print_lubrication(bearing, lub) -> None:
    """The ring temperatures and operating clearance, then the lubrication outputs in
    engineering units (mm^2/s, um, Mrev)."""
    t = _temperature_json(bearing)
    print(f"  temperatures         inner {t['inner_ring_temperature_K'] - 273.15:.4g}, outer "
          f"{t['outer_ring_temperature_K'] - 273.15:.4g} degC; clearance "
          + ", ".join(f"{c * 1e6:.4g}" for c in t["operating_clearance_m"]) + " um operating, "
          + ", ".join(f"{c * 1e6:.4g}" for c in t["nominal_clearance_m"])
          + f" um at {t['reference_temperature_K'] - 273.15:.4g} degC")
    if lub is None:
        print(f"  lubrication          none: {_NO_SPEED}")
        return

    def g(x, scale=1.0, fmt="10.4g"):
        return format(x * scale, fmt) if x is not None else "         -"

    print(f"  lubricant            {g(lub['operating_viscosity'], 1e6)} mm^2/s at "
          f"{lub['lubricant_temperature_K'] - 273.15:.4g} degC; nu1 {g(lub['reference_viscosity_nu1'], 1e6)} "
          f"mm^2/s (ISO 281)")
    flag = "  OUTSIDE ISO 281 (kappa < 0.1: boundary)" if lub["kappa_outside_iso281"] else ""
    print(f"  kappa, a_ISO         {g(lub['kappa'])}, {g(lub['a_iso'])} (e_C {lub['contamination_factor']:.3g}"
          f"{', EP rule' if lub['ep_rule'] else ''}){flag}")
    print(f"  life L_nm            {g(lub['modified_rating_life_L_nm'], 1e-6)} Mrev (a_ISO x L10, ISO 281 "
          "clause 9, 90 %)")
    print(f"  film h_c, h_min      {g(lub['film_thickness_central'], 1e6)}, "
          f"{g(lub['film_thickness_min'], 1e6)} um (Hamrock-Dowson, inner contact at "
          f"{g(lub['film_contact_load'], 1.0, '.4g')} N, u {g(lub['entrainment_speed'], 1.0, '.4g')} m/s; "
          "flooded: an upper bound under grease)")
    print(f"  lambda, regime       {g(lub['lambda'])}, {lub['regime'] or '-'} (sigma "
          f"{g(lub['composite_roughness'], 1e6, '.4g')} um)")
