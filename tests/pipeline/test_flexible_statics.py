"""Flexible rings from the bearing file to the outputs (issue 41): ``rvsweep statics`` sets the
flexible rings' numbers beside the rigid rings' (a very stiff seat gives the rigid ones
within 0.1 %), the sweep's ``statics.nc`` carries them with units and the report shows them,
and a dynamic run takes a flexible bearing's rings into the dynamics."""
from __future__ import annotations

import copy
import json
import math
from pathlib import Path

import numpy as np
import pytest
import tomli_w
import xarray as xr

from pipeline.cli import main
from pipeline.schema.tomlfile import read_toml

ROOT = Path(__file__).resolve().parents[2]
REDUCED = ROOT / "sweeps" / "bearings" / "reduced-test.toml"

#: the compared numbers of the JSON, the rigid rings' under "rigid_rings"
COMPARED = ("max_contact_load_N", "static_safety_factor_pressure", "reference_rating_life_L10r_Mrev",
            "radial_stiffness_N_per_m", "axial_stiffness_N_per_m", "tilting_stiffness_Nm_per_rad")


def flexible_bearing(tmp_path, k_seat: float, name="flex.toml") -> Path:
    """The 12-ball reduced bearing, its inner ring on a seat of ``k_seat`` [N m^-2] both ways."""
    raw = copy.deepcopy(read_toml(REDUCED))
    raw["name"] = "reduced-flexible"
    raw["inner_ring"]["flexible"] = {"support": "foundation", "seat_radial_stiffness": f"{k_seat!r} Pa",
                                     "seat_axial_stiffness": f"{k_seat!r} Pa", "max_order": 30}
    path = tmp_path / name
    path.write_text(tomli_w.dumps(raw))
    return path


def statics(capsys, *args) -> dict:
    assert main(["statics", "--json", *args]) == 0
    return json.loads(capsys.readouterr().out)


def test_a_very_stiff_seat_gives_the_rigid_rings_statics_within_a_tenth_of_a_percent(tmp_path, capsys):
    """A seat of 1e16 N/m^2 per unit circumference: K_k = π·k·R ~ 5e15 N/m against contacts of
    ~1e8 N/m, so the raceways move by picometres and every number is the rigid rings'."""
    out = statics(capsys, "--bearing", str(flexible_bearing(tmp_path, 1e16)), "--radial-load", "30kN",
                  "--axial-load", "10kN")
    assert out["flexible_rings"] == {"inner": "foundation", "outer": "rigid"}
    for key in COMPARED:
        assert out["flexible"][key] == pytest.approx(out["rigid_rings"][key], rel=1e-3), key
    np.testing.assert_allclose(out["flexible"]["ball_contact_load_N"], out["rigid_rings"]["ball_contact_load_N"],
                               rtol=1e-3, atol=1e-3 * out["rigid_rings"]["max_contact_load_N"])
    assert out["ring_deformation_m"]["inner_ring_max_radial_deformation"] < 1e-9
    assert out["ring_deformation_m"]["outer_ring_ovalisation"] is None   # rigid
    # the flexible numbers are the output's own headline numbers
    assert out["max_contact_load_N"] == out["flexible"]["max_contact_load_N"]


def test_a_soft_seat_spreads_the_load_and_keeps_l10_and_the_balance(tmp_path, capsys):
    """A soft seat: the ring bends under the heaviest balls, which share the load with their
    neighbours (a smaller Q_max, the same resultant); ISO 281's L10 depends on the applied
    loads only, so it does not move; the bearing is softer."""
    out = statics(capsys, "--bearing", str(flexible_bearing(tmp_path, 2e9)), "--radial-load", "30kN",
                  "--axial-load", "10kN", "--no-gravity")
    f, r = out["flexible"], out["rigid_rings"]
    assert f["max_contact_load_N"] < r["max_contact_load_N"]
    assert f["basic_rating_life_L10_Mrev"] == r["basic_rating_life_L10_Mrev"]
    assert f["radial_stiffness_N_per_m"] < r["radial_stiffness_N_per_m"]
    assert max(abs(x) for x in out["force_residual"][:3]) < 1e-3 * 30e3
    assert out["ring_deformation_m"]["inner_ring_ovalisation"] > 0.0


def test_the_text_output_sets_flexible_beside_rigid(tmp_path, capsys):
    assert main(["statics", "--bearing", str(flexible_bearing(tmp_path, 2e9)), "--radial-load", "30kN",
                 "--axial-load", "10kN", "--runout", "2"]) == 0
    text = capsys.readouterr().out
    assert "flexible | rigid rings | change" in text and "inner ring deformation ovalisation" in text
    assert "Q_inner rigid[N]" in text
    assert "runout path          (rigid rings)" in text   # rvcore.statics.runout solves rigid rings


def test_a_rigid_bearing_prints_nothing_of_flexible_rings(capsys):
    out = statics(capsys, "--bearing", str(REDUCED), "--radial-load", "30kN", "--axial-load", "10kN")
    assert "flexible_rings" not in out and "rigid_rings" not in out


def short_window(tmp_path) -> Path:
    """A 4 ms profile at full load and speed from the start: a short window of the dynamics."""
    path = tmp_path / "window.toml"
    full = {"time": ["0 s", "4 ms"], "fraction": [1, 1], "interpolation": "linear"}
    phases = {"startup": ["0 s", "1 ms"], "steady": ["1 ms", "3 ms"], "deceleration": ["3 ms", "4 ms"]}
    path.write_text(tomli_w.dumps({"name": "window", "duration": "4 ms", "radial_load": full,
                                   "axial_load": full, "speed": full, "phases": phases}))
    return path


def test_simulate_runs_a_flexible_bearing_with_its_rings_modes(tmp_path, capsys):
    """`rvsweep simulate` of a flexible bearing runs the dynamics with its rings' modes: the
    inner ring's raceway deforms (the outputs of its deformation are positive and finite)
    and the rigid outer ring's stays round (its ovalisation exactly 0); the case file carries
    the modes' truncation figure (the file's orders against the dynamics')."""
    out = tmp_path / "case.nc"
    code = main(["simulate", "--bearing", str(flexible_bearing(tmp_path, 2e9)), "--profile",
                 str(short_window(tmp_path)), "--speed", "120deg/s", "--radial-load", "30kN",
                 "--axial-load", "10kN", "--out", str(out)])
    assert code == 0, capsys.readouterr().err
    with xr.open_dataset(out) as ds:
        deformation = ds["max_ring_radial_deformation"].values
        oval_i, oval_o = ds["inner_ring_ovalisation"].values, ds["outer_ring_ovalisation"].values
        truncation = float(ds["ring_mode_truncation"])
        assert ds["ring_mode_truncation"].attrs["units"] == "1"
    assert truncation > 0.0      # the file's 30 orders against the dynamics' 0-6, on a soft seat
    assert np.all(np.isfinite(deformation)) and deformation.max() > 0.0
    assert np.all(np.isfinite(oval_i)) and oval_i.max() > 0.0
    assert np.all(oval_o == 0.0)


def test_compute_case_gives_run_case_the_files_rings(tmp_path):
    """A flexible bearing's case gets its rings with the bearing file's 30 orders (run_case
    keeps the dynamics' DYNAMICS_MAX_ORDER of them as states, the rest serve the steady
    statics' truncation figure); a rigid bearing's call is unchanged."""
    from pipeline.run.cases import compute_case
    from pipeline.schema import sweep_from_dict

    def case(bearing):
        return sweep_from_dict({"name": "s", "bearing": str(bearing), "profile": "profiles/short.toml",
                                "axes": {"speed": ["120 deg/s"]},
                                "fixed": {"radial_load": "30 kN", "axial_load": "10 kN"}}, tmp_path / "s.toml").cases[0]

    called = []
    assert compute_case(case(flexible_bearing(tmp_path, 2e9)), case_fn=lambda *a, **k: called.append(k)).ok
    rings = called[-1]["rings"]
    assert rings.inner_radial.orders.tolist() == list(range(31))
    assert rings.inner_axial.orders.tolist() == list(range(31))
    assert rings.outer_radial is None and rings.outer_axial is None
    assert compute_case(case(REDUCED), case_fn=lambda *a, **k: called.append(k)).ok
    assert "rings" not in called[-1]


def test_statics_nc_carries_the_flexible_and_rigid_numbers_and_the_report_shows_them(tmp_path):
    from pipeline.io.statics import FLEXIBLE_VARIABLES, statics_dataset, write_statics
    from pipeline.report.loads import flexible_blocks, read_statics
    from pipeline.report.render import Table
    from pipeline.run.corners import corner_statics
    from pipeline.schema import sweep_from_dict

    sweep = sweep_from_dict({"name": "s", "bearing": str(flexible_bearing(tmp_path, 2e9)),
                             "profile": "profiles/short.toml", "axes": {"speed": ["120 deg/s"]},
                             "fixed": {"radial_load": "30 kN", "axial_load": "10 kN"}}, tmp_path / "s.toml")
    corner = corner_statics(sweep.cases[0])
    assert not corner.error and corner.values["flexible_rings"] == 1
    write_statics(statics_dataset([corner], gravity=True, tilt="free", sweep_name="s"), tmp_path)
    with xr.open_dataset(tmp_path / "statics.nc") as ds:
        for name in FLEXIBLE_VARIABLES:
            assert ds[name].attrs["units"] and ds[name].attrs["long_name"], name
        assert float(ds["max_contact_load"][0]) < float(ds["max_contact_load_rigid"][0])
        assert math.isnan(float(ds["outer_ring_ovalisation"][0]))   # the outer ring is rigid
        # the flexible ball loads balance the same radial load as the rigid ones (Σ Q·cos α·cos ψ)
        assert ds["ball_load"].shape == ds["ball_load_rigid"].shape
    c, = read_statics(tmp_path).corners
    assert c.flexible is not None and c.flexible["ball_load_rigid"].shape == c.ball_load.shape
    tables = [b for b in flexible_blocks([c]) if isinstance(b, Table)]
    assert len(tables) == 2 and any("Q_max" in row[1] for row in tables[0].rows)


def test_statics_nc_of_a_rigid_sweep_has_no_flexible_variables(tmp_path):
    from pipeline.io.statics import FLEXIBLE_VARIABLES, statics_dataset
    from pipeline.run.corners import corner_statics
    from pipeline.schema import sweep_from_dict

    sweep = sweep_from_dict({"name": "s", "bearing": str(REDUCED), "profile": "profiles/short.toml",
                             "axes": {"speed": ["120 deg/s"]}, "fixed": {"radial_load": "30 kN",
                                                                        "axial_load": "10 kN"}},
                            tmp_path / "s.toml")
    ds = statics_dataset([corner_statics(sweep.cases[0])], gravity=True, tilt="free")
    assert not set(FLEXIBLE_VARIABLES) & set(ds.data_vars)


def test_check_says_which_rings_are_flexible(tmp_path, capsys):
    assert main(["check", str(flexible_bearing(tmp_path, 2e9))]) == 0
    assert "rings: inner foundation, outer rigid" in capsys.readouterr().out
    assert main(["check", "--json", str(REDUCED)]) == 0
    assert json.loads(capsys.readouterr().out)["ring_supports"] == {"inner": "rigid", "outer": "rigid"}


@pytest.mark.parametrize("worst", [math.nan, 0.004, 0.031])
def test_the_report_states_the_orders_and_warns_where_the_modes_are_not_converged(tmp_path, worst):
    """The report's flexible section says that statics.nc keeps the file's orders and the
    cases 0-6, gives the largest truncation figure over the sweep and where, and warns when
    any case's exceeds 2 %; rigid rings (every figure NaN): nothing."""
    import types

    from pipeline.report.loads import mode_truncation_blocks
    from pipeline.report.render import Para, Warning_
    from pipeline.schema import load_bearing

    speeds, loads = [120.0, 660.0], [20e3, 40e3]
    v = np.full((2, 2), math.nan if math.isnan(worst) else 0.001)
    v[1, 0] = worst
    metrics = xr.Dataset({"ring_mode_truncation": (("speed", "radial_load"), v)},
                         coords={"speed": speeds, "radial_load": loads})
    bearing = load_bearing(flexible_bearing(tmp_path, 2e9))
    ctx = types.SimpleNamespace(metrics=metrics, configuration=types.SimpleNamespace(bearing=bearing))
    blocks = mode_truncation_blocks(ctx)
    if math.isnan(worst):
        assert blocks == []
        return
    text = " ".join(b.text for b in blocks if isinstance(b, Para))
    assert "inner ring 0–30" in text and "orders 0–6" in text
    assert f"{worst * 100:.3g} % at 660 °/s, 20 kN" in text
    warnings = [b.text for b in blocks if isinstance(b, Warning_)]
    if worst > 0.02:
        assert len(warnings) == 1 and "not converged for this seat" in warnings[0]
        assert "1 of 4 cases" in warnings[0]
    else:
        assert not warnings and "below the 2 %" in text
