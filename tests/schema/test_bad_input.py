"""Bad input gets one clear line: quantities with trailing text, text that is no quantity,
command-line values named by their option as typed, a negative speed."""
from __future__ import annotations

from pathlib import Path

import pytest

from pipeline.cli import main
from pipeline.errors import ConfigError
from pipeline.schema.units import parse_quantity

REPO = Path(__file__).resolve().parents[2]
REDUCED = str(REPO / "sweeps" / "bearings" / "reduced-test.toml")

#: Internals of pint (or of Python) that must not reach a user.
LEAKS = ("AssertionError", "DefinitionSyntaxError", "UndefinedUnitError", "Traceback", "pint")


@pytest.mark.parametrize("text, kind", [
    ("30kN💥", "force"), ("30kN#x", "force"), ("120 deg/s💥", "angular_speed"),
    ("30 kN 2", "force"), ("30 kN*2", "force"), ("660 deg/s junk", "angular_speed"),
])
def test_trailing_text_is_not_a_quantity(text, kind):
    with pytest.raises(ConfigError) as err:
        parse_quantity(text, kind, file="f.toml", key="k")
    assert "not a quantity" in str(err.value) and repr(text) in str(err.value)


@pytest.mark.parametrize("text", ["ﾟ∀ﾟ", "３０kN", "30 kN/", "30 foo", "nan N"])
def test_text_that_is_no_quantity_says_so_without_pint_internals(text):
    with pytest.raises(ConfigError) as err:
        parse_quantity(text, "force", file="f.toml", key="k")
    msg = str(err.value)
    assert msg.startswith("f.toml: k = ") and ("not a quantity" in msg or "not a finite" in msg), msg
    assert not any(leak in msg for leak in LEAKS), msg


@pytest.mark.parametrize("text, kind, si", [
    ("30 kN", "force", 30e3), ("-10kN", "force", -10e3), ("1e3 N", "force", 1e3),
    ("660 deg/s", "angular_speed", 11.519173063162574), ("110 rpm", "angular_speed", 110 * 2 * 3.141592653589793 / 60),
    ("9.81 m/s^2", "acceleration", 9.81), ("1e9 N/m^1.5", "stiffness_hertz", 1e9),
    ("7800 kg/m^3", "density", 7800.0), ("2 kNm", "moment", 2e3), ("2 kN*m", "moment", 2e3),
    ("30 µm", "length", 30e-6), ("30 μm", "length", 30e-6), (".5 mm", "length", 5e-4),
    ("250 N s/m", "damping", 250.0), ("1 kg m^2", "inertia", 1.0),
])
def test_what_engineers_write_still_parses(text, kind, si):
    assert parse_quantity(text, kind) == pytest.approx(si, rel=1e-12)


def _one_line(capsys, code):
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert not any(leak in err for leak in LEAKS), err
    return err


@pytest.mark.parametrize("typed, reason", [
    ("30 kg", "wrong units"), ("-30kN", "must not be negative"), ("30kN💥", "not a quantity"),
])
def test_command_line_errors_name_the_option_and_the_value_as_typed(capsys, typed, reason):
    code = main(["statics", "--bearing", REDUCED, "--radial-load", typed])
    err = _one_line(capsys, code)
    assert f"--radial-load {typed!r}: {reason}" in err, err
    assert "cases[0]" not in err and "command line" not in err and "-30000" not in err


def test_a_bad_set_value_is_named_as_typed(capsys):
    code = main(["statics", "--bearing", REDUCED, "--set", "solver.output_rate=3kg"])
    assert "--set 'solver.output_rate=3kg': wrong units" in _one_line(capsys, code)


def test_a_negative_speed_is_refused_in_one_line(capsys, tmp_path):
    code = main(["simulate", "--bearing", REDUCED, "--speed", "-660deg/s", "--radial-load", "30kN",
                 "--out", str(tmp_path / "case.nc")])
    err = _one_line(capsys, code)
    assert "--speed '-660deg/s': must not be negative" in err and "direction" in err
    assert not (tmp_path / "case.nc").exists()


def test_a_negative_speed_axis_is_refused(tmp_path):
    from tests.schema.test_sweepfile import GRID, make_sweep
    from pipeline.schema import read_sweep_file

    path = make_sweep(tmp_path, GRID.replace('"120 deg/s"', '"-120 deg/s"'))
    with pytest.raises(ConfigError) as err:
        read_sweep_file(path)
    assert "axes.speed[0]" in str(err.value) and "must not be negative" in str(err.value)


def test_check_prints_the_overlap_warning_once(capsys):
    """The default check reads the study sweep and its bearing: both carry the caveat."""
    assert main(["check"]) == 0
    out, err = capsys.readouterr()
    assert (out + err).count("need a pitch diameter of at least") == 1, out + err
    assert "warning:" in err


@pytest.mark.parametrize("path, kind", [("bearings/reduced-test.toml", "bearing"),
                                        ("profiles/short.toml", "profile")])
def test_sweep_given_another_kind_of_file_says_what_it_is(capsys, path, kind):
    code = main(["sweep", str(REPO / "sweeps" / path), "--serial", "--no-progress"])
    err = _one_line(capsys, code)
    assert f"this is a {kind} file, not a sweep file" in err and "unknown key" not in err


def test_a_grid_too_large_is_refused_in_one_line_before_it_is_built(capsys, tmp_path):
    """A 1000 x 1000 grid took two minutes of silence to expand; now one line says how many
    cases it is and the limit, before any case is built (the check is on the axes' sizes)."""
    from pipeline.schema.sweepfile import MAX_CASES

    sweep = tmp_path / "huge.toml"
    sweep.write_text(f'''name = "huge"
bearing = "{(REPO / "sweeps/bearings/reduced-test.toml").as_posix()}"
profile = "{(REPO / "sweeps/profiles/short.toml").as_posix()}"
[axes]
speed = {{start = "1 deg/s", stop = "1000 deg/s", step = "1 deg/s"}}
radial_load = {{start = "1 kN", stop = "1000 kN", step = "1 kN"}}
[fixed]
axial_load = "10 kN"
''')
    assert main(["check", str(sweep)]) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "1000 x 1000 = 1000000 cases" in err[0] and str(MAX_CASES) in err[0]


def test_more_balls_in_a_row_than_the_dynamics_hold_is_refused_in_one_line(capsys, tmp_path):
    from rvcore.bearing.layout import MAX_ROW_BALLS

    text = (REPO / "sweeps" / "bearings" / "rv-main-study.toml").read_text()
    assert "\ncount = 51\n" in text
    path = tmp_path / "many-balls.toml"
    path.write_text(text.replace("\ncount = 51\n", f"\ncount = {MAX_ROW_BALLS + 1}\n"))
    err = _one_line(capsys, main(["check", str(path)]))
    assert f"rows[0].balls.count = {MAX_ROW_BALLS + 1}: must be at most {MAX_ROW_BALLS}" in err
