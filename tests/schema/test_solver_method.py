"""``solver.method``: the integrator as an input field.

It is a choice of :data:`rvcore.integrate.methods.METHODS`, written in ``[solver]``, ``[fixed]``,
``[[cases]]``, as a categorical sweep axis or with ``rvsweep simulate --method``; it reaches
the case's :class:`rvcore.simulation.run.SolverSettings` and its id, and survives the stored
configuration. A bad value is one ConfigError naming file, key, value and the choices.
No case is run (rvcore.integrate.imex may not exist yet): only what the loader builds is checked.
"""
from __future__ import annotations

import argparse
import dataclasses

import pytest

from pipeline.cli import main
from pipeline.commands.common import one_case_sweep
from pipeline.errors import ConfigError
from pipeline.run.cluster import estimated_cost
from pipeline.schema import read_sweep_file, stored_configuration
from pipeline.schema import fields as schema
from rvcore.simulation.settings import SolverSettings
from rvcore.integrate.methods import NAMES as METHODS
from tests.schema.test_sweepfile import GRID, make_sweep

ONE_POINT = """
[axes]
speed = ["120 deg/s"]

[fixed]
radial_load = "20 kN"
axial_load = "10 kN"
"""


def test_the_field_is_a_choice_of_the_integrators_with_the_settings_default():
    f = schema.solver_fields()["method"]
    assert f.kind == "choice" and f.choices == METHODS
    assert f.default == SolverSettings().method
    assert f.axis_kind == "category"


@pytest.mark.parametrize("method", METHODS)
def test_solver_table_sets_the_method_of_every_case(tmp_path, method):
    s = read_sweep_file(make_sweep(tmp_path, f'[solver]\nmethod = "{method}"\n' + GRID))
    assert s.settings.method == method
    assert {c.settings.method for c in s.cases} == {method}
    # the stored configuration gives it back
    assert stored_configuration(s.configuration).settings.method == method


def test_rk4_and_imex_cases_of_one_point_have_different_ids(tmp_path):
    ids = {m: read_sweep_file(make_sweep(tmp_path, f'[solver]\nmethod = "{m}"\n' + ONE_POINT, name=f"{m}.toml"))
           .cases[0].case_id for m in METHODS}
    assert len(set(ids.values())) == len(METHODS)
    # the default written out is the same case as the default left out
    default = read_sweep_file(make_sweep(tmp_path, ONE_POINT, name="default.toml")).cases[0].case_id
    assert default == ids[SolverSettings().method]


def test_method_as_a_categorical_axis(tmp_path):
    body = GRID.replace("[fixed]", '"solver.method" = ["rk4", "imex"]\n\n[fixed]')
    s = read_sweep_file(make_sweep(tmp_path, body))
    axis = s.axis("solver.method")
    assert axis.kind == "category" and axis.coords == ("rk4", "imex") and axis.units == "1"
    assert len(s.cases) == 2 * 2 * 2
    assert sorted(c.settings.method for c in s.cases) == sorted(["rk4", "imex"] * 4)
    assert len({c.case_id for c in s.cases}) == len(s.cases)
    for c in s.cases:
        assert c.point["solver.method"] == c.settings.method


def test_method_in_fixed_and_in_cases(tmp_path):
    s = read_sweep_file(make_sweep(tmp_path, GRID + '"solver.method" = "imex"\n'))
    assert {c.settings.method for c in s.cases} == {"imex"}
    body = ('[[cases]]\nspeed = "120 deg/s"\nradial_load = "20 kN"\naxial_load = "10 kN"\n"solver.method" = "rk4"\n'
            '[[cases]]\nspeed = "120 deg/s"\nradial_load = "20 kN"\naxial_load = "10 kN"\n"solver.method" = "imex"\n')
    s = read_sweep_file(make_sweep(tmp_path, body, name="cases.toml"))
    assert [c.settings.method for c in s.cases] == ["rk4", "imex"]
    assert s.cases[0].case_id != s.cases[1].case_id


def _assert_names_the_choices(err: ConfigError, path, key, value):
    assert err.file == str(path) and err.key == key and err.value == value
    for m in METHODS:
        assert f'"{m}"' in err.reason
    text = str(err)
    assert "\n" not in text and str(path) in text and key in text and repr(value) in text


@pytest.mark.parametrize("where, body, key", [
    ("solver", '[solver]\nmethod = "rk5"\n' + GRID, "solver.method"),
    ("axis", GRID.replace("[fixed]", '"solver.method" = ["rk4", "rk5"]\n\n[fixed]'), "axes.solver.method[1]"),
    ("fixed", GRID + '"solver.method" = "rk5"\n', "fixed.solver.method"),
])
def test_an_unknown_method_is_one_config_error_listing_the_choices(tmp_path, where, body, key):
    path = make_sweep(tmp_path, body)
    with pytest.raises(ConfigError) as e:
        read_sweep_file(path)
    _assert_names_the_choices(e.value, path, key, "rk5")


def test_a_method_that_is_not_a_string_is_rejected(tmp_path):
    path = make_sweep(tmp_path, "[solver]\nmethod = 4\n" + GRID)
    with pytest.raises(ConfigError) as e:
        read_sweep_file(path)
    _assert_names_the_choices(e.value, path, "solver.method", 4)


def test_a_range_of_methods_is_rejected(tmp_path):
    body = GRID.replace("[fixed]", '"solver.method" = {start = "rk4", stop = "imex", step = 1}\n\n[fixed]')
    with pytest.raises(ConfigError, match="a range needs numbers"):
        read_sweep_file(make_sweep(tmp_path, body))


def test_check_command_reports_a_bad_method_in_one_line(tmp_path, capsys):
    path = make_sweep(tmp_path, '[solver]\nmethod = "rk5"\n' + GRID)
    assert main(["check", str(path)]) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "solver.method = 'rk5'" in lines[0] and '"imex"' in lines[0]


def test_check_command_lists_the_methods_of_an_axis(tmp_path, capsys):
    body = GRID.replace("[fixed]", '"solver.method" = ["rk4", "imex"]\n\n[fixed]')
    assert main(["check", str(make_sweep(tmp_path, body))]) == 0
    assert "solver.method (2 values, rk4, imex)" in capsys.readouterr().out


def test_stored_configuration_rejects_an_unknown_method(tmp_path):
    s = read_sweep_file(make_sweep(tmp_path, '[solver]\nmethod = "imex"\n' + GRID))
    text = s.configuration.replace('method = "imex"', 'method = "rk5"')
    assert 'method = "rk5"' in text
    with pytest.raises(ConfigError) as e:
        stored_configuration(text)
    assert e.value.key == "solver.method" and e.value.value == "rk5"


def test_a_stored_rk4_configuration_names_its_method_and_is_rk4_whatever_the_default(tmp_path, monkeypatch):
    s = read_sweep_file(make_sweep(tmp_path, '[solver]\nmethod = "rk4"\n' + GRID))
    assert 'method = "rk4"' in s.configuration   # every setting is stored, defaults included
    for default in METHODS:
        monkeypatch.setattr(SolverSettings, "__init__", _with_default_method(SolverSettings.__init__, default))
        assert stored_configuration(s.configuration).settings.method == "rk4"
        monkeypatch.undo()
    # the default (IMEX) is written out, so that it reads back as itself
    s = read_sweep_file(make_sweep(tmp_path, GRID, name="default.toml"))
    assert 'method = "imex"' in s.configuration
    assert stored_configuration(s.configuration).settings.method == "imex"


def _with_default_method(init, method):
    def patched(self, *args, **kw):
        kw.setdefault("method", method)
        init(self, *args, **kw)
    return patched


def _cli_args(tmp_path, method=None, sets=()):
    make_sweep(tmp_path, GRID)
    return argparse.Namespace(bearing=str(tmp_path / "bearings" / "reduced-test.toml"), speed="120 deg/s",
                              radial_load="20 kN", axial_load="10 kN", moment="0 N*m", load_angle="0 deg",
                              set=list(sets), method=method)


def test_simulate_method_option_sets_the_method(tmp_path):
    assert one_case_sweep(_cli_args(tmp_path), profile=None).cases[0].settings.method == "imex"   # the default
    assert one_case_sweep(_cli_args(tmp_path, "rk4"), profile=None).cases[0].settings.method == "rk4"
    assert one_case_sweep(_cli_args(tmp_path, "imex"), profile=None).cases[0].settings.method == "imex"
    with pytest.raises(ConfigError, match="given twice"):
        one_case_sweep(_cli_args(tmp_path, "imex", ["solver.method=rk4"]), profile=None)
    with pytest.raises(SystemExit):   # argparse: not one of the choices
        main(["simulate", "--bearing", "x.toml", "--speed", "1 deg/s", "--out", "x.nc", "--method", "rk5"])


def test_cost_estimate_counts_the_longer_imex_step(tmp_path):
    s = read_sweep_file(make_sweep(tmp_path, GRID))
    c = s.cases[0]
    rk4 = dataclasses.replace(c, settings=dataclasses.replace(c.settings, method="rk4"))
    imex = dataclasses.replace(c, settings=dataclasses.replace(c.settings, method="imex"))
    assert estimated_cost(imex) < estimated_cost(rk4)
