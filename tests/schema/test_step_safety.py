"""``solver.step_safety`` is a fraction of the integrator's explicit stability limit: above
1 it is refused with one line naming the value and the limit (accepted, a step safety of 5
gave the reduced case a start-up range of 0.84 µm against 1.90 µm, and exit 0)."""
from __future__ import annotations

import pytest

from pipeline.errors import ConfigError
from pipeline.schema import read_sweep_file
from pipeline.schema.fields import solver_fields

from .test_sweepfile import GRID, make_sweep


@pytest.mark.parametrize("body, key", [
    (GRID + "[solver]\nstep_safety = 5\n", "solver.step_safety"),
    (GRID + "[solver]\nstep_safety = 0\n", "solver.step_safety"),
])
def test_step_safety_outside_0_to_1_is_one_line_naming_value_and_limit(tmp_path, body, key):
    p = make_sweep(tmp_path, body)
    with pytest.raises(ConfigError) as err:
        read_sweep_file(p)
    msg = str(err.value)
    assert "\n" not in msg and str(p) in msg
    assert err.value.key == key
    assert err.value.value == float(body.rsplit("= ", 1)[1]) and f"{key} = {err.value.value!r}:" in msg, msg
    assert "(0, 1]" in msg and "stability limit" in msg, msg


def test_step_safety_on_an_axis_above_1_is_refused(tmp_path):
    p = make_sweep(tmp_path, GRID.replace("[fixed]", '"solver.step_safety" = [0.5, 1.5]\n\n[fixed]'))
    with pytest.raises(ConfigError) as err:
        read_sweep_file(p)
    assert "\n" not in str(err.value) and "= 1.5:" in str(err.value) and "(0, 1]" in str(err.value)
    assert err.value.key == "axes.solver.step_safety[1]"


def test_step_safety_of_1_is_the_limit_itself_and_allowed(tmp_path):
    sweep = read_sweep_file(make_sweep(tmp_path, GRID + "[solver]\nstep_safety = 1\n"))
    assert all(c.settings.step_safety == 1.0 for c in sweep.cases)
    assert solver_fields()["step_safety"].bounds_text() == "in (0, 1]"
