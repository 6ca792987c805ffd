"""``rvsweep check``: exit status, warnings, one-line errors and the JSON it prints."""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

from pipeline.cli import main

ROOT = Path(__file__).resolve().parents[2]
STUDY = ROOT / "sweeps" / "bearings" / "rv-main-study.toml"
BUILDABLE = ROOT / "sweeps" / "bearings" / "rv-main-buildable.toml"
FOUR_POINT = ROOT / "sweeps" / "bearings" / "four-point-example.toml"
PROFILE = ROOT / "sweeps" / "profiles" / "study.toml"

KEYS = ("pitch_diameter_m", "ball_diameter_m", "ball_count", "contact_angle_rad",
        "inner_groove_ratio", "outer_groove_ratio", "radial_clearance_m", "hertz_k_inner",
        "hertz_k_outer", "warnings")


def overlap_numbers():
    """(need, have) in mm for Table 2: 51 balls of 23 mm on (320 + 383)/2."""
    return f"{23.0 / math.sin(math.pi / 51):.1f}", f"{(320 + 383) / 2:.1f}"


@pytest.fixture
def no_flag_copy(tmp_path):
    """The study file without its allow_ball_overlap line."""
    lines = [ln for ln in STUDY.read_text().splitlines() if not ln.startswith("allow_ball_overlap")]
    assert len(lines) == len(STUDY.read_text().splitlines()) - 1
    path = tmp_path / "study-no-flag.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


def hamrock_brewe_k(d, dm, f, alpha, inner, e, nu):
    """Hertz K [N/m^1.5] from the Hamrock-Brewe closed forms (within ~3 % of exact)."""
    gamma = d * math.cos(alpha) / dm
    rx = 2 / d + (2 / d) * (gamma / (1 - gamma) if inner else -gamma / (1 + gamma))
    ry = 2 / d - 1 / (f * d)
    ratio = max(rx, ry) / min(rx, ry)
    kappa = 1.0339 * ratio**0.636
    ell_e = 1.0003 + 0.5968 / ratio
    ell_k = 1.5277 + 0.6023 * math.log(ratio)
    e_eff = e / (1 - nu**2)
    return math.pi * kappa * e_eff * math.sqrt(2 * ell_e / (rx + ry) / 9) / ell_k**1.5


def test_study_file_passes_with_the_overlap_warning(capsys):
    assert main(["check", str(STUDY)]) == 0
    out, err = capsys.readouterr()
    need, have = overlap_numbers()
    warnings = [ln for ln in err.splitlines() if ln.startswith("warning:")]
    assert len(warnings) == 1
    assert f"need a pitch diameter of at least {need} mm; this bearing's is {have} mm" in warnings[0]
    assert "351.5 mm" in out and "51 balls of 23 mm" in out and "warning" in out


def test_without_the_flag_it_fails_in_one_line(capsys, no_flag_copy):
    assert main(["check", str(no_flag_copy)]) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    need, have = overlap_numbers()
    assert str(no_flag_copy) in lines[0] and "rows[0].balls.count" in lines[0]
    assert need in lines[0] and have in lines[0]
    assert "Traceback" not in err and out == ""


def _rvsweep():
    exe = Path(sys.executable).parent / "rvsweep"
    return [str(exe)] if exe.exists() else [sys.executable, "-m", "pipeline.cli"]


@pytest.mark.slow  # over 25 s of CPU: make test-all
def test_subprocess_exit_status_and_no_traceback(no_flag_copy):
    env = dict(os.environ, PYTHONWARNINGS="ignore")
    bad = subprocess.run(_rvsweep() + ["check", str(no_flag_copy)], capture_output=True,
                         text=True, cwd=ROOT, env=env, timeout=120)
    assert bad.returncode == 2
    lines = bad.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in bad.stderr
    assert lines[0].startswith("rvsweep check: error: ")
    assert overlap_numbers()[0] in lines[0]
    good = subprocess.run(_rvsweep() + ["check", "sweeps/bearings/rv-main-study.toml"],
                          capture_output=True, text=True, cwd=ROOT, env=env, timeout=120)
    assert good.returncode == 0
    assert "warning:" in good.stderr and overlap_numbers()[0] in good.stderr


def test_json_has_the_keys_and_physical_values(capsys):
    assert main(["check", "--json", str(STUDY)]) == 0
    data = json.loads(capsys.readouterr().out)
    assert isinstance(data, dict)
    for k in KEYS:
        assert k in data, k
    assert data["ball_count"] == 51
    assert data["pitch_diameter_m"] == pytest.approx((0.320 + 0.383) / 2)
    assert data["ball_diameter_m"] == pytest.approx(0.023)
    assert data["contact_angle_rad"] == pytest.approx(math.radians(15))
    assert (data["inner_groove_ratio"], data["outer_groove_ratio"]) == (0.52, 0.53)
    assert data["radial_clearance_m"] == 0.0
    assert len(data["warnings"]) == 1 and "need a pitch diameter" in data["warnings"][0]
    # Hertz K: the inner contact (convex race, tighter groove) is stiffer than the outer,
    # and both agree with the Hamrock-Brewe closed forms computed here within 3 %.
    a = math.radians(15)
    ki = hamrock_brewe_k(0.023, 0.3515, 0.52, a, True, 208e9, 0.3)
    ko = hamrock_brewe_k(0.023, 0.3515, 0.53, a, False, 208e9, 0.3)
    assert data["hertz_k_inner"] == pytest.approx(ki, rel=0.03)
    assert data["hertz_k_outer"] == pytest.approx(ko, rel=0.03)
    assert data["hertz_k_inner"] > data["hertz_k_outer"]
    # Ball mass rho*pi*D^3/6 and the epicyclic cage ratio (1 - D cos(a)/d_m)/2.
    assert data["ball_mass_kg"] == pytest.approx(7800 * math.pi * 0.023**3 / 6)
    assert data["cage_speed_ratio"] == pytest.approx(0.5 * (1 - 0.023 * math.cos(a) / 0.3515))
    assert data["min_pitch_diameter_m"] == pytest.approx(0.023 / math.sin(math.pi / 51))


def test_json_for_several_files_is_a_list(capsys):
    assert main(["check", "--json", str(BUILDABLE), str(PROFILE)]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [d["kind"] for d in data] == ["bearing", "profile"]
    assert data[1]["duration_s"] == pytest.approx(4.6)
    assert data[1]["phases"]["steady"] == pytest.approx([0.8, 3.8])


def test_buildable_file_passes_without_warning(capsys):
    assert main(["check", str(BUILDABLE)]) == 0
    out, err = capsys.readouterr()
    assert "warning" not in err
    assert "42 balls" in out


def test_four_point_file_passes(capsys):
    assert main(["check", "--json", str(FOUR_POINT)]) == 0
    out, err = capsys.readouterr()
    data = json.loads(out)
    assert data["raceway"] == "four-point" and data["warnings"] == []
    assert [a["contact_angle_rad"] for a in data["inner_arcs"]] == pytest.approx(
        [math.radians(30), -math.radians(30)])
    assert err == ""


def test_profile_file_passes(capsys):
    assert main(["check", str(PROFILE)]) == 0
    out, _ = capsys.readouterr()
    assert "startup 0.3-0.8 s" in out


def test_one_bad_file_among_good_ones_fails(capsys, no_flag_copy):
    assert main(["check", str(BUILDABLE), str(no_flag_copy)]) == 2
    out, err = capsys.readouterr()
    assert "rv-main-buildable" in out  # the good file is still reported
    assert len([ln for ln in err.splitlines() if "error:" in ln]) == 1


def test_unrecognised_file_is_an_error(capsys, tmp_path):
    path = tmp_path / "what.toml"
    path.write_text('title = "nothing we know"\n')
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and "not a bearing file" in err and len(err.strip().splitlines()) == 1


def test_missing_file_is_an_error(capsys, tmp_path):
    assert main(["check", str(tmp_path / "absent.toml")]) == 2
    err = capsys.readouterr().err
    assert "no such file" in err and "Traceback" not in err


def test_sweep_file_is_recognised(capsys, tmp_path):
    sweep = tmp_path / "grid.toml"
    sweep.write_text(
        f'name = "grid"\nbearing = "{STUDY.as_posix()}"\nprofile = "{PROFILE.as_posix()}"\n'
        '[axes]\nspeed = ["120 deg/s", "660 deg/s"]\nradial_load = ["20 kN", "30 kN", "40 kN"]\n'
        '[fixed]\naxial_load = "10 kN"\n')
    assert main(["check", "--json", str(sweep)]) == 0
    out, err = capsys.readouterr()
    data = json.loads(out)
    assert data["kind"] == "sweep" and data["case_count"] == 2 * 3
    # The study bearing's overlap caveat reaches the sweep's check too.
    assert any("need a pitch diameter" in w for w in data["warnings"])
    assert "warning:" in err


# --------------------------------------------------------------------------- defaults, schema


def _run_cli(args, cwd):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "pipeline.cli", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)


def test_check_without_a_file_checks_the_shipped_sweep_and_its_files_from_anywhere(tmp_path):
    from pipeline.schema.shipped import DEFAULT_SWEEP, shipped_file
    from pipeline.schema import read_toml

    res = _run_cli(["check", "--json"], cwd=tmp_path)          # outside the checkout
    assert res.returncode == 0, res.stderr
    data = json.loads(res.stdout)
    assert [d["kind"] for d in data] == ["sweep", "bearing", "profile"]
    sweep = shipped_file(DEFAULT_SWEEP)
    raw = read_toml(sweep)
    assert Path(data[0]["file"]) == sweep
    assert Path(data[1]["file"]).resolve() == (sweep.parent / raw["bearing"]).resolve()
    assert Path(data[2]["file"]).resolve() == (sweep.parent / raw["profile"]).resolve()


def test_a_missing_file_that_names_a_shipped_one_is_that_file(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["check", "--json", "bearings/rv-main-buildable.toml"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert Path(data["file"]).resolve() == BUILDABLE.resolve()
    assert main(["check", "bearings/no-such-bearing.toml"]) == 2
    err = capsys.readouterr().err
    assert "bearings/no-such-bearing.toml" in err and "no such file" in err


def test_check_prints_values_in_the_schemas_display_units(capsys):
    from pipeline.schema import fields

    assert main(["check", str(BUILDABLE)]) == 0
    out = capsys.readouterr().out
    for key in ("envelope.bore", "rows[].balls.diameter", "rows[].pitch_diameter"):
        assert fields.field("bearing", key).unit == "mm"
    assert "bore 320 mm" in out and "balls of 23 mm" in out and "pitch diameter of 351.5 mm" in out
    unit = fields.field("bearing", "rows[].inner_groove.arcs[].contact_angle").unit
    assert f"nominal contact angle 15 {unit}" in out


def test_check_fields_lists_every_field_of_the_schema(capsys):
    from pipeline.schema import FIELDS

    assert main(["check", "--fields", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert len(rows) == len(FIELDS)
    by_key = {r["key"]: r for r in rows}
    assert by_key["rows[].balls.diameter"]["unit"] == "mm" and by_key["rows[].balls.diameter"]["default"] == "required"
    assert by_key["solver.step_safety"]["kind"].startswith("quantity")
    assert "profile.duration" in by_key and all(r["doc"] for r in rows)
    assert main(["check", "--fields"]) == 0
    text = capsys.readouterr().out.splitlines()
    assert len(text) == len(FIELDS) and text[0].startswith("name")


def test_sweep_help_says_it_defaults_to_the_shipped_sweep(capsys):
    with pytest.raises(SystemExit):
        main(["sweep", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "default: the shipped study sweep" in out and "names a shipped file" in out


def test_sweep_without_an_argument_loads_the_shipped_default():
    from pipeline.commands.sweep import sweep_path
    from pipeline.schema.shipped import DEFAULT_SWEEP, shipped_file

    assert sweep_path(None) == shipped_file(DEFAULT_SWEEP)
    assert sweep_path("study.toml") == shipped_file(DEFAULT_SWEEP) or Path("study.toml").exists()


HEAVY = ("numba", "xarray", "pint", "scipy", "dask", "distributed", "matplotlib", "netCDF4")


def _modules_after(argv) -> set:
    """The top-level packages a fresh interpreter has imported after ``main(argv)``."""
    code = ("import sys, contextlib, io\n"
            "from pipeline.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):\n"
            f"    main({argv!r})\n"
            "print(' '.join(sorted({m.split('.')[0] for m in sys.modules})))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)})
    return set(out.stdout.split())


def test_help_loads_no_numerical_package():
    """`rvsweep --help` and a command's `--help` that needs no schema load none of numba,
    xarray, pint, scipy, dask or matplotlib (the packages' names are imported on use,
    pipeline.exports); a command line adds its own command's arguments only. `simulate
    --help` shows --method's choices from the schema, so it loads rvcore and numba."""
    for argv in (["--help"], ["--version"], ["sweep", "--help"], ["check", "--help"]):
        assert not _modules_after(argv) & set(HEAVY), argv
    assert "numba" in _modules_after(["simulate", "--help"])
    with pytest.raises(SystemExit):   # each command's own arguments are still there
        main(["simulate", "--help"])


def test_check_loads_no_output_package():
    """Validating the study sweep reads the schema (pint, rvcore's geometry and Hertz
    constants: numba, scipy) but nothing of the output side (pint itself imports dask
    where it is installed)."""
    loaded = _modules_after(["check", str(ROOT / "sweeps" / "study.toml")])
    assert {"pint", "numba"} <= loaded
    assert not loaded & {"xarray", "distributed", "matplotlib", "netCDF4"}, loaded & set(HEAVY)


# --------------------------------------------------------------------------- numbers without units
def _sweep_with(tmp_path, fixed: str) -> Path:
    p = tmp_path / "bare.toml"
    p.write_text(f'name = "bare"\nbearing = "{ROOT / "sweeps" / "bearings" / "reduced-test.toml"}"\n'
                 f'profile = "{ROOT / "sweeps" / "profiles" / "short.toml"}"\n'
                 '[axes]\nspeed = ["120 deg/s"]\n'
                 f'[fixed]\n{fixed}\n[solver]\nstep_safety = 0.8\ntime_step = 0\n')
    return p


@pytest.mark.filterwarnings("ignore::pipeline.errors.UnitlessNumberWarning")   # main prints them
def test_a_load_without_its_unit_is_read_in_si_and_said(capsys, tmp_path):
    """`radial_load = 30` is 30 N (the documented reading of a plain number), a thousandth
    of what an engineer who meant kN expects: the check passes and says so in one line that
    names the file, the key, the value as typed and the SI value read. The dimensionless
    step_safety and the zero time_step need no unit and get no warning."""
    p = _sweep_with(tmp_path, 'radial_load = 30\naxial_load = "10 kN"')
    assert main(["check", str(p)]) == 0
    err = capsys.readouterr().err.splitlines()
    said = [line for line in err if "without a unit" in line]
    assert said == [f"warning: {p}: fixed.radial_load = 30: a number without a unit, read in SI: 30 N"]


@pytest.mark.filterwarnings("ignore::pipeline.errors.UnitlessNumberWarning")
def test_a_flag_without_its_unit_is_said_as_typed(capsys):
    """On the command line the warning names the option and its text, as an error would:
    `--radial-load 30` is 30 N; a zero angle needs no unit."""
    assert main(["statics", "--bearing", str(BUILDABLE), "--radial-load", "30", "--axial-load", "10 kN",
                 "--load-angle", "0"]) == 0
    err = capsys.readouterr().err
    assert "warning: --radial-load '30': a number without a unit, read in SI: 30 N" in err
    assert "--axial-load" not in err and "--load-angle" not in err


def test_an_angle_without_its_unit_is_refused(capsys, tmp_path):
    """`--load-angle 30` could mean 30° or 30 rad (1719°, the load at 279°): refused in one
    line naming the option and its text, before any work; in a file, naming the file and
    the key. With its unit it runs."""
    assert main(["statics", "--bearing", str(BUILDABLE), "--radial-load", "30 kN", "--load-angle", "30"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--load-angle '30'" in err and "deg" in err and "rad" in err
    p = _sweep_with(tmp_path, 'radial_load = "30 kN"\naxial_load = "10 kN"\nload_angle = 30')
    assert main(["check", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and str(p) in err and "load_angle" in err and "needs its unit" in err
    p = _sweep_with(tmp_path, 'radial_load = "30 kN"\naxial_load = "10 kN"\nload_angle = "30 deg"')
    assert main(["check", str(p)]) == 0


def test_a_refused_value_without_its_unit_is_one_error_line(capsys, tmp_path):
    """The warning waits for the file to be accepted: a plain number that is then refused
    gives the error's one line only."""
    p = _sweep_with(tmp_path, 'radial_load = 1e12\naxial_load = "10 kN"')
    assert main(["check", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "more than the bearing can carry" in err and "warning" not in err

