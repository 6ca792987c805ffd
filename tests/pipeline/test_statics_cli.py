"""``rvsweep statics`` and ``check`` on the preloaded pair: negative values after a space,
--moment-x/--moment-y, the stiffness matrix and the per-row loads in --json, and
``check --json``'s row_count and preload_N."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from pipeline.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[2]
PAIR = str(ROOT / "sweeps" / "bearings" / "rv-main-pair.toml")
BUILDABLE = str(ROOT / "sweeps" / "bearings" / "rv-main-buildable.toml")


def statics(capsys, *args) -> dict:
    assert main(["statics", "--json", *args]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("command", ["statics", "simulate"])
def test_negative_value_after_a_space_parses(command):
    """argparse takes "-10kN" for a value, not an option, in every command with loads."""
    argv = [command, "--bearing", BUILDABLE, "--axial-load", "-10kN", "--moment", "-2.5 kN*m",
            "--load-angle", "-.5deg"]
    if command == "simulate":
        argv += ["--speed", "-120deg/s", "--out", "case.nc"]
    args = build_parser().parse_args(argv)
    assert (args.axial_load, args.moment, args.load_angle) == ("-10kN", "-2.5 kN*m", "-.5deg")


def test_an_unknown_option_is_still_an_error(capsys):
    with pytest.raises(SystemExit):
        build_parser().parse_args(["statics", "--bearing", BUILDABLE, "--axial-lode", "1kN"])


def test_negative_axial_load_mirrors_the_pair(capsys):
    """The back-to-back pair is mirror-symmetric about z = 0: -F_a moves the ring as far
    as +F_a, the other way, and the rows swap their loads."""
    pos = statics(capsys, "--bearing", PAIR, "--axial-load", "10kN", "--no-gravity")
    neg = statics(capsys, "--bearing", PAIR, "--axial-load", "-10kN", "--no-gravity")
    assert neg["axial_load_N"] == -10e3
    assert neg["inner_ring_z_m"] == pytest.approx(-pos["inner_ring_z_m"], rel=1e-6)
    assert neg["row_axial_load_N"] == pytest.approx(pos["row_axial_load_N"][::-1], abs=1e-3)
    # axial equilibrium: the preloaded rows push opposite ways, their difference is F_a
    fa = pos["row_axial_load_N"]
    assert abs(fa[0] - fa[1]) == pytest.approx(10e3, rel=1e-6)


def test_statics_json_has_the_stiffness_and_row_loads(capsys):
    out = statics(capsys, "--bearing", PAIR, "--radial-load", "20kN", "--axial-load", "5kN", "--no-gravity")
    k = np.array(out["stiffness_matrix"])
    assert k.shape == (5, 5)
    assert out["stiffness_matrix_labels"] == ["x", "y", "z", "tilt_x", "tilt_y"]
    assert np.array(out["stiffness_matrix_units"]).shape == (5, 5)
    # K is the Hessian of the contact energy: symmetric, positive definite when held
    assert np.allclose(k, k.T, rtol=1e-3, atol=1e-3 * np.abs(k).max())
    assert np.all(np.linalg.eigvalsh((k + k.T) / 2) > 0)
    # with the radial load along +x (load angle 0), the scalars are the direct terms
    assert out["radial_stiffness_N_per_m"] == pytest.approx(k[0, 0])
    assert out["axial_stiffness_N_per_m"] == pytest.approx(k[2, 2])
    assert out["tilting_stiffness_Nm_per_rad"] == pytest.approx(k[4, 4])
    assert out["row_count"] == 2 and out["preload_N"] == pytest.approx(3.5e3, rel=1e-6)
    assert len(out["row_axial_load_N"]) == len(out["row_radial_load_N"]) == 2
    # radial equilibrium: the rows share the 20 kN
    assert sum(out["row_radial_load_N"]) == pytest.approx(20e3, rel=1e-4)


def test_moment_y_is_the_moment_at_load_angle_zero_and_moment_x_at_minus_90(capsys):
    """--moment turns about (-sin ψ, cos ψ, 0): y at ψ = 0, x at ψ = -90 deg."""
    base = ["--bearing", PAIR, "--no-gravity"]
    m = statics(capsys, *base, "--moment", "2kN*m")
    my = statics(capsys, *base, "--moment-y", "2kN*m")
    mx = statics(capsys, *base, "--moment-x", "2 kN*m")
    m90 = statics(capsys, *base, "--moment", "2kN*m", "--load-angle", "-90deg")
    assert my["inner_ring_tilt_y_rad"] == pytest.approx(m["inner_ring_tilt_y_rad"], rel=1e-6)
    assert mx["inner_ring_tilt_x_rad"] == pytest.approx(m90["inner_ring_tilt_x_rad"], rel=1e-6)
    assert mx["inner_ring_tilt_x_rad"] > 0 and my["inner_ring_tilt_y_rad"] > 0
    # the axisymmetric pair tilts as far about x as about y
    assert mx["inner_ring_tilt_x_rad"] == pytest.approx(my["inner_ring_tilt_y_rad"], rel=1e-4)
    assert mx["moment_x_Nm"] == 2e3 and mx["applied_moment_Nm"] == pytest.approx([2e3, 0.0], abs=1e-9)


def test_back_to_back_is_stiffer_in_tilt_than_face_to_face(capsys):
    """A tilt θ about y moves a ball's inner contact along its line of contact by
    θ·cos ψ·(z_row·cos α − (d_m/2)·sin α): the lever arm is the distance of the line of
    contact from the bearing centre, (d_m/2)·sin|α| + (s/2)·cos α back-to-back (the lines
    meet the axis outside the rows) and (d_m/2)·sin|α| − (s/2)·cos α face-to-face. With
    the same rows and preload every contact has the same stiffness in both, so the
    tilting stiffnesses stand as the squared arms (up to the small stiffness of the
    contact angles turning under the preload)."""
    base = ["--bearing", PAIR, "--no-gravity"]
    o = statics(capsys, *base)
    x = statics(capsys, *base, "--set", "pair.arrangement=face-to-face")
    r, s, a = 351.5e-3 / 2, 30e-3, math.radians(30)   # the file's pitch, spacing and angle
    arm_o, arm_x = r * math.sin(a) + s / 2 * math.cos(a), r * math.sin(a) - s / 2 * math.cos(a)
    ratio = o["tilting_stiffness_Nm_per_rad"] / x["tilting_stiffness_Nm_per_rad"]
    assert ratio == pytest.approx((arm_o / arm_x) ** 2, rel=0.05)
    # the axial stiffness does not depend on the arrangement (same rows, same preload)
    assert o["axial_stiffness_N_per_m"] == pytest.approx(x["axial_stiffness_N_per_m"], rel=1e-3)


def test_plain_statics_prints_engineering_units(capsys):
    assert main(["statics", "--bearing", PAIR, "--axial-load", "-5kN", "--moment-x", "1kNm"]) == 0
    out = capsys.readouterr().out
    assert "N/um" in out and "N m/mrad" in out and "row 1 load" in out


def test_check_json_row_count_and_preload(capsys):
    assert main(["check", "--json", PAIR, BUILDABLE]) == 0
    pair, single = json.loads(capsys.readouterr().out)
    assert pair["row_count"] == 2 and pair["arrangement"] == "back-to-back"
    assert pair["preload_N"] == pytest.approx(3.5e3, rel=1e-6)   # the file's pair.preload
    assert pair["preload_offset_m"] > 0
    assert single["row_count"] == 1 and single["preload_N"] == 0.0


def test_check_prints_the_pair(capsys):
    assert main(["check", PAIR]) == 0
    out = capsys.readouterr().out
    assert "back-to-back pair, rows 30 mm apart; preload 3.5 kN" in out
    assert "axial position -15 mm" in out and "axial position 15 mm" in out


def test_loaded_balls_are_those_carrying_load_on_both_races(capsys):
    """At 3.1 preloads of thrust one row of the pair is unloaded (its contacts carry the
    statics' round-off, ~1e-16 N): only the other row's 42 balls carry load."""
    out = statics(capsys, "--bearing", PAIR, "--axial-load", "10850N", "--no-gravity")
    q_in, q_out = np.array(out["ball_inner_load_N"]), np.array(out["ball_outer_load_N"])
    rows = np.array(out["row_axial_load_N"])
    assert rows.min() < 1e-6 * rows.max()            # one row really carries nothing
    assert out["loaded_ball_count"] == 42
    # counted by the rule the JSON states: more than 1 N on both races
    assert out["loaded_ball_count"] == int(np.count_nonzero((q_in > 1.0) & (q_out > 1.0)))


def test_statics_says_how_the_tilt_is_held_and_which_stiffness_is_which(capsys):
    """Free (the file's default) the single row tilts under zero moment; held, its tilt is
    0 and the reaction moment is reported. Both stiffnesses are in the JSON, named."""
    free = statics(capsys, "--bearing", BUILDABLE, "--radial-load", "30kN", "--axial-load", "10kN", "--no-gravity")
    held = statics(capsys, "--bearing", BUILDABLE, "--radial-load", "30kN", "--axial-load", "10kN", "--no-gravity",
                   "--set", "inner_ring.tilt=held")
    assert free["inner_ring_tilt"] == "free" and held["inner_ring_tilt"] == "held"
    assert abs(free["inner_ring_tilt_y_rad"]) > 1e-4 and free["tilt_reaction_moment_Nm"] == [0.0, 0.0]
    assert held["inner_ring_tilt_x_rad"] == 0.0 and held["inner_ring_tilt_y_rad"] == 0.0
    assert abs(held["tilt_reaction_moment_Nm"][1]) > 100.0
    for key in ("radial_stiffness", "axial_stiffness"):
        assert 0 < free[f"{key}_compliant_N_per_m"] < free[f"{key}_N_per_m"]
    assert held["tilting_stiffness_compliant_Nm_per_rad"] is None


def test_runout_path_of_an_eccentric_inner_raceway_spans_two_e(capsys):
    """``--runout``: the quasi-static pose over one revolution. An inner raceway eccentric
    by e turns with the ring and carries it round a circle of radius e: along the load
    the path spans 2e (1 %); a fixed outer eccentricity only shifts it."""
    e = 25e-6
    out = statics(capsys, "--bearing", BUILDABLE, "--radial-load", "30kN", "--axial-load", "10kN", "--no-gravity",
                  "--set", "imperfections.inner_eccentricity=25um", "--set", "imperfections.outer_eccentricity=10um",
                  "--runout", "12")
    path = out["runout_path"]
    assert len(path["ring_angle_rad"]) == 12
    assert path["radial_displacement_range_m"] == pytest.approx(2 * e, rel=0.01)


def test_runout_path_of_a_tilted_inner_groove_tilts_a_free_ring(capsys):
    """``--runout`` with an inner axial runout a on a ring free to tilt: the ring follows
    its groove's plane, a tilt of a/c_r (c_r = d_m/2 + (f_i − ½)·D·cos α, the radius of
    the groove's centres of curvature) turning with it, 2 %; its centre stays."""
    a, c_r = 10e-6, 0.3515 / 2 + (0.52 - 0.5) * 0.023 * math.cos(math.radians(15.0))
    args = ("--bearing", BUILDABLE, "--radial-load", "30kN", "--axial-load", "10kN", "--no-gravity", "--runout", "8")
    tilted = statics(capsys, *args, "--set", "imperfections.inner_axial_amplitude=10um")["runout_path"]
    perfect = statics(capsys, *args)["runout_path"]
    tilt = np.hypot(np.subtract(tilted["tilt_x_rad"], perfect["tilt_x_rad"]),
                    np.subtract(tilted["tilt_y_rad"], perfect["tilt_y_rad"]))
    np.testing.assert_allclose(tilt, a / c_r, rtol=0.02)
    assert np.abs(np.subtract(tilted["axial_displacement_m"], perfect["axial_displacement_m"])).max() < 0.02 * a


def test_seed_moves_the_headline_numbers_of_a_class_normal_bearing(capsys):
    """``--seed S`` realizes the tolerance class's draws (the raceways' high-point angles,
    the balls' sizes) for the headline numbers as for the runout path (issue 39): two
    seeds of an ISO 492 Normal bearing put the eccentric raceways and the larger balls in
    different places, so δ_r, the peak ball load and L10r differ; one seed twice gives the
    same numbers to the bit."""
    base = ["--bearing", BUILDABLE, "--radial-load", "20kN", "--axial-load", "5kN", "--no-gravity",
            "--set", "imperfections.tolerance_class=normal"]
    a = statics(capsys, *base, "--seed", "1")
    b = statics(capsys, *base, "--seed", "2")
    a2 = statics(capsys, *base, "--seed", "1")
    keys = ("radial_displacement_m", "max_contact_load_N", "reference_rating_life_L10r_Mrev")
    assert all(a[k] == a2[k] for k in keys)
    assert a["seed"] == 1 and b["seed"] == 2
    # the Normal class's K_ia/2 = 30 um eccentricity in another direction: the ring moves by
    # micrometres, far beyond the solver's tolerance
    assert abs(a["radial_displacement_m"] - b["radial_displacement_m"]) > 1e-7
    assert a["max_contact_load_N"] != b["max_contact_load_N"]
    assert a["reference_rating_life_L10r_Mrev"] != b["reference_rating_life_L10r_Mrev"]


def test_open_groove_bearing_says_which_ratings_it_refused_and_reduced(capsys):
    """The 6010 file (grooves 0.625 D_w): ISO 281's C_r, L10, L10r null with the reason in
    ``dynamic_rating_basis`` and the life note; the catalogue s0 from the reduced f0 with
    ``static_rating_basis`` saying so; the pressure route stays. s0 = C0r/P0r with
    P0r = F_r (pure radial load, no gravity)."""
    out = statics(capsys, "--bearing", str(ROOT / "sweeps" / "bearings" / "deep-groove-6010.toml"),
                  "--radial-load", "500N", "--no-gravity", "--set", "inner_ring.tilt=held")
    assert out["dynamic_load_rating_N"] is None and out["basic_rating_life_L10_Mrev"] is None
    assert out["reference_rating_life_L10r_Mrev"] is None
    assert "not rated" in out["dynamic_rating_basis"] and "0.625" in out["rating_life_note"]
    assert "reduced" in out["static_rating_basis"]
    assert out["static_safety_factor_catalogue"] == pytest.approx(out["static_load_rating_N"] / 500.0, rel=1e-9)
    assert out["static_safety_factor_pressure"] > 0
    assert "30-40 deg" not in out["friction_moment_note"] and "deep-groove row" in out["friction_moment_note"]
