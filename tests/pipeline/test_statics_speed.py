"""``rvsweep statics --speed`` (issue 40): the lubrication outputs in SI, each checked against
the published formula computed here (ISO 281:2007 clause 9's ν1, κ, a_ISO and L_nm;
Hamrock–Dowson's speed exponents; λ = h_min/σ), on the issue's exact command."""
from __future__ import annotations

import json
import math

import pytest

from pipeline.cli import main

#: The issue's command, less --json.
COMMAND = ["statics", "--bearing", "bearings/rv-main-study.toml", "--radial-load", "30kN",
           "--axial-load", "10kN"]


@pytest.fixture(scope="module")
def outputs():
    """The JSON of the issue's command at 120 and 240 deg/s and without --speed."""
    import contextlib
    import io

    out = {}
    for speed in ("120deg/s", "240deg/s", None):
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(io.StringIO()):
            assert main([*COMMAND, "--json"] + ([] if speed is None else ["--speed", speed])) == 0
        out[speed] = json.loads(buf.getvalue())
    return out


def test_the_issue_command_reports_the_lubrication_keys_in_si(outputs):
    d = outputs["120deg/s"]
    units = d["lubrication_units"]
    for key, unit in (("kappa", "1"), ("a_iso", "1"), ("modified_rating_life_L_nm", "revolutions"),
                      ("film_thickness_min", "m"), ("film_thickness_central", "m"),
                      ("operating_viscosity", "m2 s-1"), ("reference_viscosity_nu1", "m2 s-1"), ("lambda", "1")):
        assert isinstance(d[key], float), key
        assert units[key] == unit
    assert d["regime"] in ("boundary", "mixed", "full film")
    assert d["kappa_outside_iso281"] is False
    assert d["speed_rad_per_s"] == pytest.approx(math.radians(120.0), rel=1e-12)
    # SI: a film of the order of 0.1 µm is 1e-7 m, a viscosity of 68 mm²/s 6.8e-5 m²/s
    assert 1e-8 < d["film_thickness_min"] < d["film_thickness_central"] < 1e-6
    assert d["operating_clearance_m"] == [0.0]


def test_kappa_is_nu_over_iso281_nu1(outputs):
    """ν = 68 mm²/s (ISO VG 68 at 40 °C, the grade's definition; both rings at the default
    40 °C); ν1 = 45000·n^−0.83·d_m^−0.5 (n < 1000 r/min) with n = 20 r/min and d_m = 351.5 mm."""
    d = outputs["120deg/s"]
    nu1 = 45000.0 * 20.0 ** -0.83 * 351.5 ** -0.5 * 1e-6
    assert d["operating_viscosity"] == pytest.approx(68e-6, rel=1e-12)
    assert d["reference_viscosity_nu1"] == pytest.approx(nu1, rel=1e-9)
    assert d["kappa"] == pytest.approx(68e-6 / nu1, rel=1e-9)


def test_a_iso_and_l_nm_follow_iso281_clause_9(outputs):
    """a_ISO = 0.1·[1 − (2.5671 − 2.2649/κ^0.054381)^0.83·(e_C·C_u/P)^(1/3)]^−9.3 for
    0.1 ≤ κ < 0.4, C_u = C_0/22·(100/d_m)^0.5, e_C = 0.6 (Table 13, normal cleanliness,
    d_m ≥ 100 mm, lower bound); L_nm = a_ISO·L10 (a_1 = 1)."""
    d = outputs["120deg/s"]
    kappa = d["kappa"]
    assert 0.1 <= kappa < 0.4
    assert d["contamination_factor"] == pytest.approx(0.6)
    cu = d["static_load_rating_N"] / 22.0 * (100.0 / 351.5) ** 0.5
    assert d["fatigue_load_limit"] == pytest.approx(cu, rel=1e-9)
    x = 0.6 * cu / d["equivalent_load"]
    a = 0.1 * (1.0 - (2.5671 - 2.2649 / kappa ** 0.054381) ** 0.83 * x ** (1.0 / 3.0)) ** -9.3
    assert d["a_iso"] == pytest.approx(a, rel=1e-9)
    assert d["modified_rating_life_L_nm"] == pytest.approx(a * d["basic_rating_life_L10_Mrev"] * 1e6, rel=1e-9)


def test_the_film_scales_with_speed_as_hamrock_dowson(outputs):
    """The loads do not depend on the speed in the statics, so doubling it doubles the
    entrainment speed: h_c × 2^0.67, h_min × 2^0.68; λ = h_min/σ with σ = √(0.0625² + 0.175²) µm."""
    slow, fast = outputs["120deg/s"], outputs["240deg/s"]
    assert fast["film_contact_load"] == pytest.approx(slow["film_contact_load"], rel=1e-12)
    assert fast["entrainment_speed"] == pytest.approx(2.0 * slow["entrainment_speed"], rel=1e-12)
    assert fast["film_thickness_central"] / slow["film_thickness_central"] == pytest.approx(2 ** 0.67, rel=1e-9)
    assert fast["film_thickness_min"] / slow["film_thickness_min"] == pytest.approx(2 ** 0.68, rel=1e-9)
    sigma = math.hypot(0.0625, 0.175) * 1e-6
    assert slow["lambda"] == pytest.approx(slow["film_thickness_min"] / sigma, rel=1e-9)


def test_without_speed_there_are_no_lubrication_outputs_and_it_says_why(outputs, capsys):
    d = outputs[None]
    assert "kappa" not in d and "film_thickness_min" not in d
    assert "--speed" in d["lubrication_note"]
    assert main(COMMAND) == 0
    text = capsys.readouterr().out
    assert "lubrication          none" in text and "--speed" in text


def test_the_text_output_carries_the_lubrication_lines(capsys):
    assert main([*COMMAND, "--speed", "660deg/s"]) == 0
    text = capsys.readouterr().out
    for words in ("kappa, a_ISO", "life L_nm", "film h_c, h_min", "lambda, regime",
                  "temperatures         inner 40, outer 40 degC; clearance 0 um operating, 0 um at 20 degC"):
        assert words in text


def test_a_zero_speed_is_one_line(capsys):
    assert main([*COMMAND, "--speed", "0 deg/s"]) != 0
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].endswith("--speed '0 deg/s': the lubrication outputs need a speed > 0 (leave --speed out "
                            "for none)")
    assert not any("Traceback" in line for line in err)
