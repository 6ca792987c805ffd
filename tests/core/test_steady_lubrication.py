"""The per-case lubrication outputs at the steady point (rvcore.statics.operating,
issue 40): κ from ISO 281's ν1 computed here, L_nm = a_ISO·L10, and the operating
clearance the statics ran with."""
from __future__ import annotations

import math
from pathlib import Path

import pytest

from pipeline.schema import bearing_from_dict, read_toml
from rvcore.standards.iso16281 import static_life
from rvcore.statics.equilibrium import solve_statics
from rvcore.statics.operating import steady_lubrication

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def study():
    b = bearing_from_dict(read_toml(ROOT / "sweeps" / "bearings" / "rv-main-study.toml"), file="study.toml")
    return b, solve_statics(b, 30e3, 10e3, stiffness=False)


def test_steady_kappa_and_l_nm_at_660_deg_per_s(study):
    """n = 110 r/min, d_m = 351.5 mm: ν1 = 45000·n^−0.83·d_m^−0.5 mm²/s; ν = 68 mm²/s
    (VG 68 at the default 40 °C); L_nm = a_ISO·L10 with κ ≥ 1 giving a_ISO > 1."""
    b, st = study
    out = steady_lubrication(b, st, math.radians(660.0))
    nu1 = 45000.0 * 110.0 ** -0.83 * 351.5 ** -0.5
    assert out["kappa_steady"] == pytest.approx(68.0 / nu1, rel=1e-9)
    assert out["operating_viscosity"] == 68e-6
    l10 = static_life(b, st)["basic_rating_life_L10_Mrev"] * 1e6
    assert out["modified_rating_life_L_nm"] == pytest.approx(out["a_iso_steady"] * l10, rel=1e-12)
    assert out["a_iso_steady"] > 1.0
    assert out["film_thickness_min_steady"] > 0.0 and out["film_parameter_steady"] > 0.0
    assert out["operating_clearance"] == 0.0


def test_no_speed_no_lubrication_outputs(study):
    b, st = study
    out = steady_lubrication(b, st, 0.0)
    assert all(math.isnan(out[k]) for k in ("kappa_steady", "a_iso_steady", "modified_rating_life_L_nm",
                                            "film_thickness_min_steady", "film_parameter_steady"))
