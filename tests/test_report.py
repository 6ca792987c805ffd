"""``rvsweep report`` on a small synthetic sweep: sections, figures, the 12-row table, caveats,
missing cases, the computed physics paragraph and reproducibility."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from pipeline.cli import main
from pipeline.fits import default_reference_path, load_reference_fits
from pipeline.report import build_report
from tests.test_metrics import CAVEAT, FAILED_REASON, FILE_STYLE_CONFIG, build_synthetic_sweep

SECTIONS = ("# Sweep report", "## Bearing, profile and parameters", "## Cases", "## Time histories",
            "## Metrics against speed and load", "## Fits beside the study's (Tables 3 and 4)",
            "## Where our physics agrees with the study and where it does not", "## Files")


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    d = build_synthetic_sweep(tmp_path_factory.mktemp("rep"))  # 3x3, 390 °/s at 20 kN failed
    files = build_report(d)
    return d, files, (d / "report" / "report.md").read_text(), (d / "report" / "report.html").read_text()


def test_every_section_and_figure(built):
    d, files, md, html = built
    for s in SECTIONS:
        assert s in md
    assert (d / "metrics.nc").exists() and (d / "fits.nc").exists()
    names = sorted(p.name for p in (d / "report" / "figures").glob("*.png"))
    expected = ["time_histories.png"] + [f"metric_{p}_{x}_{m}.png" for p, x, m in (
        ("startup", "radial", "range"), ("deceleration", "radial", "range"), ("steady", "radial", "mean"),
        ("startup", "axial", "range"), ("deceleration", "axial", "range"), ("steady", "axial", "mean"))]
    assert names == sorted(expected)
    for name in names:
        data = (d / "report" / "figures" / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        assert b"Software" not in data and b"matplotlib" not in data  # no version metadata
        assert f"](figures/{name})" in md
        assert f'src="figures/{name}"' in html
    assert "<h2>Cases</h2>" in html and "<table>" in html


def test_comparison_table_has_the_twelve_rows(built):
    _, _, md, html = built
    refs = load_reference_fits(default_reference_path())
    rows = [ln for ln in md.splitlines() if re.match(r"\| Table [34], row \d", ln)]
    assert len(rows) == 12
    for ref in refs:
        assert sum(ln.startswith(f"| {ref.label} |") for ln in rows) == 1
        assert f"<td>{ref.label}</td>" in html
    # Each row is fitted at the study's fixed value, which the grid holds.
    for ln in rows:
        cells = [c.strip() for c in ln.strip("|").split("|")]
        assert cells[1] == ("30 kN" if "Table 3" in ln else "120 °/s")


def test_comparison_values_in_study_units(built):
    """The synthetic steady δ_r is 2e-9 m/N·F_r − 1e-7 m/(rad/s)·ω: check the two mean-radial rows."""
    _, _, md, _ = built
    rows = {ln.split("|")[1].strip(): [c.strip() for c in ln.strip("|").split("|")]
            for ln in md.splitlines() if re.match(r"\| Table [34], row \d", ln)}
    t3 = rows["Table 3, row 3: Steady-State, Mean Radial Displacement"]
    slope_mm_per_deg_s = -1e-7 * 1e3 * math.pi / 180.0  # m per rad/s -> mm per °/s
    assert t3[4].startswith(f"{slope_mm_per_deg_s:.2e} [")
    assert t3[-1] == "yes"  # the study's slope is negative too
    t4 = rows["Table 4, row 3: Steady-State, Mean Radial Displacement"]
    assert t4[4].startswith(f"{2e-9 * 1e3:.2e} [")
    assert t4[-1] == "yes"
    assert t4[7] == "3"  # three loads at 120 °/s


def test_parameters_with_assumptions_marked(built):
    _, _, md, _ = built
    assert "bearing: **study-table2**" in md and "profile: **study**" in md
    line = next(ln for ln in md.splitlines() if ln.startswith("| `bearing.rows[0].radial_clearance`"))
    assert "**assumed**" in line
    # a bearing-file key (rows[0].outer_groove.arcs) marks its resolved spelling (outer_arcs)
    line = next(ln for ln in md.splitlines() if ln.startswith("| `bearing.rows[0].outer_arcs[0].contact_angle`"))
    assert "**assumed**" in line
    line = next(ln for ln in md.splitlines() if ln.startswith("| `bearing.rows[0].ball_diameter`"))
    assert "assumed" not in line
    assert "case_ids" not in md


def test_caveat_is_prominent(built):
    _, _, md, html = built
    body = md.split("## Bearing", 1)[0]  # before the first section
    assert "> **Geometry caveat.**" in body and CAVEAT in body
    assert '<div class="caveat">' in html


def test_missing_case_is_reported(built):
    _, files, md, _ = built
    assert files.missing == 1
    cases = md.split("## Cases", 1)[1].split("\n## ", 1)[0]
    assert "9 cases, 8 finished ok, 1 failed or missing" in cases
    row = next(ln for ln in cases.splitlines() if ln.startswith("| 390 °/s"))
    assert "| 20 kN |" in row and "| failed |" in row and FAILED_REASON in row and "excluded" in row


def test_physics_paragraph_numbers_are_computed(built):
    """F_c = m_b·(d_m/2)·ω_c² from the configuration and the synthetic cage speed."""
    _, _, md, _ = built
    text = md.split("## Where our physics agrees", 1)[1]
    m_b = 7800.0 * math.pi / 6.0 * 0.023**3  # configuration: D = 23 mm, rho = 7800 kg/m^3
    omega = math.radians(660.0)
    # synthetic steady phase: mean cage speed 0.468·ω, slip 0.005 against the epicyclic speed
    omega_c = 0.468 * omega / (1.0 - 0.005)
    f_c = m_b * (0.3515 / 2.0) * omega_c**2
    assert f"F_c = m_b·(d_m/2)·ω_c² = {f_c:.3g} N" in text
    q = 30e3 / 10.0  # synthetic max inner contact load: F_r/10 in the steady phase
    assert f"averages {q / 1e3:.3g} kN" in text
    assert f"{100 * f_c / q:.2g} %" in text
    # the study's mean axial displacement at 120 °/s against ours
    study = 1.996 + 7.9e-6 * 120.0
    assert f"{study:.4g} mm" in text
    ours_mm = (1e-9 * 10e3 + 5e-8 * math.radians(120.0)) * 1e3
    assert f"ours at the same point is {ours_mm:.3g} mm" in text


def test_report_is_reproducible_and_works_without_caveat_or_phase_table(tmp_path):
    # no phase table (windows from the speed ramps), bearing keys as in a bearing file
    d = build_synthetic_sweep(tmp_path, speeds_deg=(120.0, 660.0), loads=(30e3, 40e3), missing=(),
                              caveat="", config=FILE_STYLE_CONFIG)
    build_report(d)
    first = {p.name: p.read_bytes() for p in (d / "report").rglob("*") if p.is_file()}
    build_report(d)
    second = {p.name: p.read_bytes() for p in (d / "report").rglob("*") if p.is_file()}
    assert first == second and len(first) == 9
    md = first["report.md"].decode()
    # the centrifugal estimate reads the file-style keys too (pitch diameter given)
    m_b = 7800.0 * math.pi / 6.0 * 0.023**3
    assert f"m_b = {m_b:.3g} kg" in md and "d_m/2 = 175.8 mm" in md
    assert "Geometry caveat" not in md
    assert "Every case of the grid finished." in md
    m = re.search(r"where the inner-ring speed ramps.*?: start-up ([\d.]+)–([\d.]+) s, steady ([\d.]+)–([\d.]+) s, "
                  r"deceleration ([\d.]+)–([\d.]+) s", md)
    assert m, md
    got = np.array([float(x) for x in m.groups()])
    dt = 4.6 / 460  # the synthetic output step
    np.testing.assert_allclose(got, [0.3, 0.8, 0.8, 3.8, 3.8, 4.3], atol=dt * 1.01)


def test_cli_on_a_partial_sweep_of_case_files(tmp_path, capsys):
    d = build_synthetic_sweep(tmp_path, speeds_deg=(120.0, 660.0), loads=(30e3, 40e3),
                              missing=((660.0, 40e3),), with_sweep_nc=False, flat_status=True)
    assert main(["report", str(d)]) == 0
    out = capsys.readouterr().out
    assert "report.md" in out and "1 case(s) failed or missing" in out
    md = (d / "report" / "report.md").read_text()
    assert "4 cases, 3 finished ok, 1 failed or missing" in md
    row = next(ln for ln in md.splitlines() if ln.startswith("| 660 °/s | 40 kN |"))
    assert "| failed |" in row and FAILED_REASON in row


def test_cli_errors_are_one_line(tmp_path, capsys):
    assert main(["report", str(tmp_path / "nowhere")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "nowhere" in err
    (tmp_path / "empty").mkdir()
    assert main(["report", str(tmp_path / "empty")]) == 2
    assert "neither sweep.nc nor any cases" in capsys.readouterr().err
    bad = tmp_path / "rig.toml"
    bad.write_text("title = 'x'\nfoo = 1\n")
    d = build_synthetic_sweep(tmp_path / "s", speeds_deg=(120.0, 660.0), loads=(30e3, 40e3), missing=())
    assert main(["report", str(d), "--reference", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "rig.toml: foo" in err
