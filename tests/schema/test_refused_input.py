"""Input that must be refused (issue 39, items 6-9): each runs the command line and asserts
exit status 2, ONE line on stderr naming the file or flag, the key, the value as typed and
the reason, no traceback, and nothing done.

The physical bounds are checked against numbers computed here, independently of
``pipeline.schema.physical``: the ball's static-limit approach from Hamrock & Brewe's
closed-form Hertz approximations (not the code's elliptic-integral solution), the free
contact angle from the groove geometry, the trough curvature of a cosine wave.
"""
from __future__ import annotations

import math
import os
import re
from pathlib import Path

import pytest

from pipeline.cli import main

REPO = Path(__file__).resolve().parents[2]
REDUCED = REPO / "sweeps" / "bearings" / "reduced-test.toml"
SHORT = REPO / "sweeps" / "profiles" / "short.toml"

#: Internals that must not reach a user.
LEAKS = ("Traceback", "RecursionError", "OverflowError", "MemoryError", "pint", "tomllib")

# The reduced test bearing (sweeps/bearings/reduced-test.toml): 12 balls of 23 mm on a pitch
# of 351.5 mm at 15 deg, f_i = 0.52, f_o = 0.53, steel of 208 GPa and 0.3.
D, DM, ALPHA, FI, FO, Z = 23e-3, 351.5e-3, math.radians(15.0), 0.52, 0.53, 12
E_PRIME = 208e9 / (1 - 0.3**2)        # Hamrock & Brewe's E' = 2 / ((1-v1^2)/E1 + (1-v2^2)/E2)
P0 = 4200e6                           # ISO 76: ball bearings, a permanent dent of 1e-4 D


def _hamrock_brewe(f, inner):
    """(p_max / W^(1/3), delta / W^(2/3)) of a ball on a groove, Hamrock & Brewe (1983)'s
    simplified formulas: k = a_r^(2/pi), E = 1 + (pi/2 - 1)/a_r, F = pi/2 + (pi/2 - 1) ln a_r."""
    g = D * math.cos(ALPHA) / DM
    race = D / 2 * (1 - g) / g if inner else -D / 2 * (1 + g) / g   # rolling-direction radius
    rx = 1 / (2 / D + 1 / race)
    ry = 1 / (2 / D - 1 / (f * D))
    r = 1 / (1 / rx + 1 / ry)
    ar = ry / rx
    k = ar ** (2 / math.pi)
    ell = 1 + (math.pi / 2 - 1) / ar
    big_f = math.pi / 2 + (math.pi / 2 - 1) * math.log(ar)
    a = (6 * k**2 * ell * r / (math.pi * E_PRIME)) ** (1 / 3)
    b = (6 * ell * r / (math.pi * k * E_PRIME)) ** (1 / 3)
    delta = big_f * (9 / (2 * ell * r) * (1 / (math.pi * k * E_PRIME)) ** 2) ** (1 / 3)
    return 3 / (2 * math.pi * a * b), delta


def _static_limit():
    """(Q0 [N], delta0 [m]) of one ball of the reduced bearing, by Hamrock & Brewe."""
    (pi_, di), (po, do) = _hamrock_brewe(FI, True), _hamrock_brewe(FO, False)
    q0 = min((P0 / pi_) ** 3, (P0 / po) ** 3)
    return q0, di * q0 ** (2 / 3) + do * q0 ** (2 / 3)


Q0, DELTA0 = _static_limit()


def _one_line(capsys, code) -> str:
    out, err = capsys.readouterr()
    assert code == 2 and err.count("\n") == 1, (code, err)
    assert not any(leak in err for leak in LEAKS), err
    return err


def _bearing(tmp_path, replace=(), append="", name="bad.toml") -> Path:
    text = REDUCED.read_text()
    for old, new in replace:
        assert old in text
        text = text.replace(old, new)
    p = tmp_path / name
    p.write_text(text + append)
    return p


def _check(capsys, path):
    return main(["check", str(path)])


# --------------------------------------------------------------------------- physical bounds


def test_static_limit_matches_hamrock_brewe():
    """The bound every physical rule uses: Q0 and delta0 within 5 % of Hamrock & Brewe's
    closed forms (their stated accuracy is a few per cent)."""
    from pipeline.schema.bearingfile import load_bearing
    from pipeline.schema.physical import static_limit

    b = load_bearing(REDUCED)
    q0, d0 = static_limit(b, b.rows[0])
    assert q0 == pytest.approx(Q0, rel=0.05) and d0 == pytest.approx(DELTA0, rel=0.05)


def test_an_interference_of_5_mm_is_refused(capsys, tmp_path):
    p = _bearing(tmp_path, [('radial_clearance = "0 mm"', 'radial_clearance = "-5 mm"')])
    err = _one_line(capsys, _check(capsys, p))
    assert f"{p}: rows[0].radial_clearance = '-5 mm': an interference" in err and "ISO 76" in err


@pytest.mark.parametrize("factor, ok", [(0.9, True), (1.1, False)])
def test_a_radial_preload_is_bounded_by_the_static_limit(capsys, tmp_path, factor, ok):
    """An interference -P_d presses a ball by -P_d/2 (each arc moves by P_d/4): allowed up to
    delta0, the approach at 4200 MPa, computed here by Hamrock & Brewe."""
    typed = f"{-2 * DELTA0 * factor * 1e6:.1f} um"
    p = _bearing(tmp_path, [('radial_clearance = "0 mm"', f'radial_clearance = "{typed}"')])
    code = _check(capsys, p)
    if ok:
        assert code == 0, capsys.readouterr().err
    else:
        assert f"rows[0].radial_clearance = '{typed}'" in _one_line(capsys, code)


@pytest.mark.parametrize("factor, ok", [(0.95, True), (1.05, False)])
def test_a_clearance_is_bounded_by_the_free_contact_angle_of_90_deg(capsys, tmp_path, factor, ok):
    """cos(a0) = 1 - P_d / (2 (f_i + f_o - 1) D): 90 deg, over the shoulders, at P_d = 2A."""
    two_a = 2 * (FI + FO - 1) * D
    typed = f"{two_a * factor * 1e3:.4f} mm"
    p = _bearing(tmp_path, [('radial_clearance = "0 mm"', f'radial_clearance = "{typed}"')])
    code = _check(capsys, p)
    if ok:
        assert code == 0, capsys.readouterr().err
    else:
        err = _one_line(capsys, code)
        assert f"rows[0].radial_clearance = '{typed}'" in err and "90 deg" in err


def test_a_clearance_of_5_mm_is_refused(capsys, tmp_path):
    p = _bearing(tmp_path, [('radial_clearance = "0 mm"', 'radial_clearance = "5 mm"')])
    assert "rows[0].radial_clearance = '5 mm': the balls would touch" in _one_line(capsys, _check(capsys, p))


def test_a_ball_30_mm_smaller_is_refused(capsys, tmp_path):
    devs = ", ".join(['"-30 mm"'] + ['"0 um"'] * (Z - 1))
    p = _bearing(tmp_path, append=f"\n[imperfections]\nball_diameter_deviation = [{devs}]\n")
    err = _one_line(capsys, _check(capsys, p))
    assert "imperfections.ball_diameter_deviation[0] = '-30 mm': a ball of -7 mm" in err


@pytest.mark.parametrize("factor, ok", [(0.9, True), (1.1, False)])
def test_a_ball_deviation_is_bounded_by_the_static_limit(capsys, tmp_path, factor, ok):
    typed = f"{DELTA0 * factor * 1e6:.1f} um"
    devs = ", ".join(['"0 um"'] * (Z - 1) + [f'"{typed}"'])
    p = _bearing(tmp_path, append=f"\n[imperfections]\nball_diameter_deviation = [{devs}]\n")
    code = _check(capsys, p)
    if ok:
        assert code == 0, capsys.readouterr().err
    else:
        assert f"imperfections.ball_diameter_deviation[{Z - 1}] = '{typed}'" in _one_line(capsys, code)


def test_an_eccentricity_of_5_mm_is_refused_and_a_tolerance_class_one_is_not(capsys, tmp_path):
    from rvcore.standards.iso492 import inner_runout

    p = _bearing(tmp_path, append='\n[imperfections]\ninner_eccentricity = "5 mm"\n')
    err = _one_line(capsys, _check(capsys, p))
    assert "imperfections.inner_eccentricity = '5 mm': moves the inner raceway" in err
    # ISO 492's widest class at this bore (320 mm): e = K_ia / 2 is far inside the bound
    e = inner_runout(0.320, "normal") / 2
    assert e < DELTA0
    p = _bearing(tmp_path, append=f'\n[imperfections]\ninner_eccentricity = "{e * 1e6:.3f} um"\n', name="ok.toml")
    assert _check(capsys, p) == 0, capsys.readouterr().err


def test_an_axial_runout_of_5_mm_is_refused_and_class_5_s_is_not(capsys, tmp_path):
    """Rule 6 of pipeline.schema.physical: the groove moved 5 mm along the axis; ISO 492
    class 5's S_ia/2 at the study's bore (10 µm, along a 15° line of contact 2.6 µm) passes."""
    from rvcore.standards.iso492 import axial_runout_limits

    p = _bearing(tmp_path, append='\n[imperfections]\nouter_axial_amplitude = "5 mm"\n')
    err = _one_line(capsys, _check(capsys, p))
    assert "imperfections.outer_axial_amplitude = '5 mm': moves the outer groove along the axis" in err
    a = axial_runout_limits(0.320, 0.383, "5")[0]
    assert a * math.sin(math.radians(15.0)) < DELTA0
    p = _bearing(tmp_path, append=f'\n[imperfections]\ninner_axial_amplitude = "{a * 1e6:.3f} um"\n', name="ok.toml")
    assert _check(capsys, p) == 0, capsys.readouterr().err


def test_waviness_of_5_mm_is_refused(capsys, tmp_path):
    p = _bearing(tmp_path, append='\n[imperfections]\n[[imperfections.outer_waviness]]\n'
                                  'order = 100000\namplitude = "5 mm"\n')
    err = _one_line(capsys, _check(capsys, p))
    assert "imperfections.outer_waviness[0].amplitude = '5 mm'" in err


@pytest.mark.parametrize("ring, sign", [("inner", -1), ("outer", 1)])
def test_a_waviness_order_is_bounded_by_the_ball_bridging_its_troughs(capsys, tmp_path, ring, sign):
    """A cosine wave A cos(k phi) on a circle of radius R curves its troughs by A k^2 / R^2
    (concave), against the circle's own 1/R (the inner raceway convex, the outer concave);
    the ball of curvature 2/D reaches the trough bottom only while that is less than 2/D.
    The largest order is computed here from that and tried with one more lobe."""
    amplitude = 0.5e-6
    radius = (DM + sign * D * math.cos(ALPHA)) / 2
    k_max = math.floor(radius * math.sqrt((2 / D - sign / radius) / amplitude))
    for k, ok in ((k_max - 1, True), (k_max + 1, False), (100000, False)):
        p = _bearing(tmp_path, append=f'\n[imperfections]\n[[imperfections.{ring}_waviness]]\n'
                                      f'order = {k}\namplitude = "0.5 um"\n', name=f"w{k}.toml")
        code = _check(capsys, p)
        if ok:
            assert code == 0, capsys.readouterr().err
        else:
            err = _one_line(capsys, code)
            assert f"imperfections.{ring}_waviness[0].order = {k}:" in err and "bridges" in err


@pytest.mark.parametrize("typed, reason", [("0", "at least 2"), ("1", "at least 2"),
                                           ("100000000", "more than the 3600")])
def test_statics_runout_points_are_bounded(capsys, typed, reason):
    err = _one_line(capsys, main(["statics", "--bearing", str(REDUCED), "--runout", typed]))
    assert f"--runout {typed}: " in err and reason in err


# --------------------------------------------------------------------------- machine limits


@pytest.mark.parametrize("typed", ["9**9**9 N", "2**2**20 N", "2^10 kN", "10 N*m**99999", "5 m^2^3 N"])
def test_power_towers_are_refused_before_evaluation(capsys, typed):
    err = _one_line(capsys, main(["statics", "--bearing", str(REDUCED), "--radial-load", typed]))
    assert f"--radial-load {typed!r}: not a quantity" in err


def test_a_value_thousands_of_characters_long_is_refused(capsys):
    typed = "9" * 5000 + " N"
    err = _one_line(capsys, main(["statics", "--bearing", str(REDUCED), "--radial-load", typed]))
    assert "not a quantity: 5002 characters" in err and len(err) < 400


def test_check_refuses_a_device_before_reading_it(capsys):
    err = _one_line(capsys, main(["check", "/dev/zero"]))
    assert "/dev/zero: not a regular file" in err


def test_check_refuses_a_fifo_without_waiting_for_a_writer(capsys, tmp_path):
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    assert "not a regular file" in _one_line(capsys, main(["check", str(fifo)]))


def test_check_refuses_a_file_larger_than_the_cap_before_reading_it(capsys, tmp_path):
    from pipeline.schema.tomlfile import MAX_INPUT_BYTES

    big = tmp_path / "big.toml"
    with big.open("wb") as fh:          # sparse: nothing is written but the size
        fh.truncate(MAX_INPUT_BYTES + 1)
    err = _one_line(capsys, main(["check", str(big)]))
    assert f"{big}: {MAX_INPUT_BYTES + 1} bytes: larger than the 16 MiB" in err


def test_a_toml_nested_3000_deep_is_one_line(capsys, tmp_path):
    deep = tmp_path / "deep.toml"
    deep.write_text("a = " + "[" * 3000 + "]" * 3000 + "\n")
    assert f"{deep}: nested too deep" in _one_line(capsys, main(["check", str(deep)]))


def _sweep(tmp_path, body, name="s.toml", top="") -> Path:
    p = tmp_path / name
    p.write_text(f'{top}bearing = "{REDUCED.as_posix()}"\nprofile = "{SHORT.as_posix()}"\n'
                 '[axes]\nspeed = ["120 deg/s"]\nradial_load = ["20 kN"]\n' + body)
    return p


def test_an_output_rate_whose_record_would_not_fit_is_refused(capsys, tmp_path):
    """1e9 Hz over the short cycle's 0.46 s is 4.6e8 samples of 44 signals of 8 bytes
    (rvcore.output_table.signal_count for one row): 151 GiB, against a 1 GiB cap."""
    from rvcore.output_table import signal_count

    p = _sweep(tmp_path, '[fixed]\naxial_load = "10 kN"\n[solver]\noutput_rate = "1e9 Hz"\n')
    err = _one_line(capsys, main(["check", str(p)]))
    gib = 1e9 * 0.46 * signal_count(1, 0) * 8 / 2**30
    assert f"{p}: solver.output_rate = '1e9 Hz'" in err and f"{gib:.4g} GiB" in err


def test_an_output_rate_above_the_fixed_step_is_refused(capsys, tmp_path):
    p = _sweep(tmp_path, '[fixed]\naxial_load = "10 kN"\n[solver]\noutput_rate = "600 kHz"\ntime_step = "2 us"\n')
    err = _one_line(capsys, main(["check", str(p)]))
    assert "solver.output_rate = '600 kHz': " in err and "500000 states a second" in err


# --------------------------------------------------------------------------- names and paths


def test_a_sweep_name_with_a_trailing_newline_is_refused(capsys, tmp_path):
    p = _sweep(tmp_path, '[fixed]\naxial_load = "10 kN"\n', top='name = "smoke\\n"\n')
    assert "name = 'smoke\\n': must be a folder name" in _one_line(capsys, main(["check", str(p)]))


@pytest.mark.parametrize("command", ["sweep", "simulate"])
def test_an_empty_out_is_refused_before_any_work(capsys, tmp_path, command, monkeypatch):
    monkeypatch.chdir(tmp_path)
    argv = (["sweep", str(REPO / "sweeps" / "smoke.toml"), "--serial", "--no-progress", "--out", ""]
            if command == "sweep" else
            ["simulate", "--bearing", str(REDUCED), "--speed", "120deg/s", "--out", ""])
    assert "--out '': empty" in _one_line(capsys, main(argv))
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- lines that misled


def test_a_utf8_bom_is_accepted(capsys, tmp_path):
    """Decided: a byte order mark carries no meaning, so it is dropped (tomllib refused it
    as "invalid TOML at line 1"). The file then reads as the same bearing."""
    from pipeline.schema.bearingfile import load_bearing

    p = tmp_path / "bom.toml"
    p.write_bytes(b"\xef\xbb\xbf" + REDUCED.read_bytes())
    assert _check(capsys, p) == 0
    assert load_bearing(p).rows == load_bearing(REDUCED).rows


def test_a_load_no_set_of_balls_carries_is_refused_before_the_time_gate(capsys):
    """Each ball carries at most Q0 before it is dented, and its share of a radial force is
    at most its load: 12 balls carry at most 12 Q0 (Q0 by Hamrock & Brewe here)."""
    err = _one_line(capsys, main(["statics", "--bearing", str(REDUCED), "--radial-load", "1e15 N"]))
    assert "--radial-load '1e15 N': more than the bearing can carry" in err
    cap = float(re.search(r"carry at most ([0-9.e+]+) N", err).group(1))
    assert cap == pytest.approx(Z * Q0, rel=0.05)
    # within the cap (at 90 % of it) the load is not refused by this rule
    assert main(["check", str(REDUCED)]) == 0


def test_a_2_to_the_70_integer_load_is_refused_by_the_bound(capsys, tmp_path):
    p = _sweep(tmp_path, f"[fixed]\naxial_load = {2**70}\n")
    err = _one_line(capsys, main(["sweep", str(p), "--serial", "--no-progress", "--out", str(tmp_path / "o")]))
    assert f"fixed.axial_load = {2**70}: more than the bearing can carry" in err and "--yes" not in err
    assert not (tmp_path / "o").exists() or not any((tmp_path / "o").rglob("*.nc"))


@pytest.mark.parametrize("top, key", [(f"realizations = {2**70}\n", "realizations"),
                                      (f"seed = {2**70}\nrealizations = 2\n", "seed")])
def test_huge_ensemble_integers_are_refused_before_the_seeds_are_listed(capsys, tmp_path, top, key):
    p = _sweep(tmp_path, '[fixed]\naxial_load = "10 kN"\n', top=top)
    assert f"{key} = {2**70}: " in _one_line(capsys, main(["check", str(p)]))


def test_a_solver_seed_of_2_to_the_70_is_refused(capsys):
    err = _one_line(capsys, main(["statics", "--bearing", str(REDUCED), "--set", f"solver.seed={2**70}"]))
    assert f"--set 'solver.seed={2**70}': must be at most {2**53 - 1}" in err


def test_a_bearing_file_given_as_a_profile_says_so(capsys, tmp_path):
    p = tmp_path / "s.toml"
    p.write_text(f'bearing = "{REDUCED.as_posix()}"\nprofile = "{REDUCED.as_posix()}"\n'
                 '[axes]\nspeed = ["120 deg/s"]\nradial_load = ["20 kN"]\n[fixed]\naxial_load = "10 kN"\n')
    err = _one_line(capsys, main(["check", str(p)]))
    assert f"{p}: profile = '{REDUCED.as_posix()}': this is a bearing file, not a profile file" in err
    assert "unknown key" not in err


def test_a_profile_given_as_a_bearing_says_so(capsys):
    err = _one_line(capsys, main(["statics", "--bearing", str(SHORT)]))
    assert f"--bearing {str(SHORT)!r}: this is a profile file, not a bearing file" in err


def test_a_copied_sweep_file_finds_the_shipped_files_it_names(capsys, tmp_path, monkeypatch):
    """README: "Shipped files can be named from anywhere"; a copy of sweeps/smoke.toml in
    another folder names bearings/reduced-test.toml, which is not beside it."""
    from pipeline.schema import read_sweep_file

    monkeypatch.chdir(tmp_path)
    copy = tmp_path / "elsewhere" / "smoke.toml"
    copy.parent.mkdir()
    copy.write_text((REPO / "sweeps" / "smoke.toml").read_text())
    assert main(["check", str(copy)]) == 0, capsys.readouterr().err
    sweep = read_sweep_file(copy)
    assert sweep.bearing_file.resolve() == REDUCED.resolve() and sweep.profile_file.resolve() == SHORT.resolve()
    assert [c.case_id for c in sweep.cases] == [c.case_id for c in read_sweep_file(REPO / "sweeps" / "smoke.toml").cases]


def test_a_missing_file_next_to_nothing_shipped_is_still_refused(capsys, tmp_path):
    p = tmp_path / "s.toml"
    p.write_text('bearing = "bearings/no-such.toml"\nprofile = "profiles/short.toml"\n'
                 '[axes]\nspeed = ["120 deg/s"]\nradial_load = ["20 kN"]\n[fixed]\naxial_load = "10 kN"\n')
    err = _one_line(capsys, main(["check", str(p)]))
    assert "bearing = 'bearings/no-such.toml': no such bearing file" in err


@pytest.mark.parametrize("body, key", [
    ('radial_load = ["20 kN"]\n[fixed]\naxial_load = "10 kN"\n"contact.damping" = "9**9**9 N s/m"\n',
     "fixed.contact.damping"),
    ('radial_load = {start = "2**2**20 N", stop = "3 kN", step = "1 kN"}\n[fixed]\naxial_load = "10 kN"\n',
     "axes.radial_load.start"),
])
def test_power_towers_in_a_sweep_file_are_refused_before_pint_sees_them(capsys, tmp_path, body, key):
    """A sweep asks pint for the kind of an override's or a range's unit before parsing it:
    that question is not put to pint for a power tower either."""
    p = tmp_path / "s.toml"
    p.write_text(f'bearing = "{REDUCED.as_posix()}"\nprofile = "{SHORT.as_posix()}"\n'
                 '[axes]\nspeed = ["120 deg/s"]\n' + body)
    err = _one_line(capsys, main(["check", str(p)]))
    assert f"{p}: {key} = " in err and "not a quantity" in err
