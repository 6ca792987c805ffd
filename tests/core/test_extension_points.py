"""The two extension points of rvcore are real doors: an integrator is a module plus an
entry of ``rvcore.integrate.methods.METHODS``, a friction law a module plus a name that
``rvcore.contact.laws`` dispatches to on the record's kind."""
from __future__ import annotations

import ast
import inspect
import math

import numpy as np

from rvcore.bearing.laws import FRICTION_LAWS, LAW_KIND, pack_friction_law
from rvcore.contact import coulomb_step
from rvcore.contact import laws as contact
from rvcore.integrate import loop, methods
from rvcore.integrate.protocol import N_STATE
from rvcore.simulation import run

PROTOCOL = ("new_work", "new_state", "time_step", "rhs_evaluations", "evaluate", "step")


def _code_names(module) -> set:
    """Every name and string constant in a module's code, docstrings left out."""
    tree = ast.parse(inspect.getsource(module))
    docs = {id(n.body[0].value) for n in ast.walk(tree)
            if isinstance(n, (ast.Module, ast.FunctionDef, ast.ClassDef)) and n.body
            and isinstance(n.body[0], ast.Expr) and isinstance(n.body[0].value, ast.Constant)}
    out = set()
    for n in ast.walk(tree):
        if isinstance(n, ast.Name):
            out.add(n.id)
        elif isinstance(n, ast.Attribute):
            out.add(n.attr)
        elif isinstance(n, ast.alias):
            out.add(n.name)
        elif isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docs:
            out.add(n.value)
    return out


def test_every_method_module_supplies_the_protocol():
    for name, module in methods.METHODS.items():
        missing = [f for f in PROTOCOL if not hasattr(module, f)]
        assert not missing, f"{name} lacks {missing}"
        assert module.new_state().shape == (N_STATE,)


def test_the_loop_and_the_run_name_no_method():
    for module in (loop, run):
        names = {n.lower() for n in _code_names(module)}
        assert not names & {"rk4", "imex", "rk4_step", "imex_step", "substeps"}, module.__name__


def test_the_right_hand_side_count_is_the_method_s():
    """Four stages a step for both (their tableaux), plus the last step's end; IMEX's
    steps taken again add four a substep they computed."""
    assert methods.METHODS["rk4"].rhs_evaluations(10, 0) == 41
    imex = methods.METHODS["imex"]
    assert imex.rhs_evaluations(10, 6) == 41 + 6 * 4


def test_friction_dispatches_on_the_record_s_kind():
    """The study's record gives the study's law, bit for bit; a record of a kind no law
    has gives NaN (the blow-up check's), not the study's law."""
    law = pack_friction_law(0.1, 0.1, 0.02, 1.0)
    assert FRICTION_LAWS[int(law[LAW_KIND])] == "coulomb_step"
    for s in (0.0, 0.03, 0.1, 0.5, 2.0):
        assert contact.friction_coefficient(s, *contact.NO_FILM, law) == coulomb_step.coefficient(s, law)
        assert contact.friction_per_slip(s * s + 1e-12, *contact.NO_FILM, law) == coulomb_step.per_slip(s * s + 1e-12, law)
    # the law itself, independently: μ(v_d) = μ_d and μ = μ_s at v_s
    assert math.isclose(contact.friction_coefficient(1.0, *contact.NO_FILM, law), 0.02)
    assert math.isclose(contact.friction_coefficient(0.1, *contact.NO_FILM, law), 0.1)
    other = law.copy()
    other[LAW_KIND] = len(FRICTION_LAWS)
    assert math.isnan(contact.friction_coefficient(0.05, *contact.NO_FILM, other))
    assert math.isnan(contact.friction_per_slip(0.0025, *contact.NO_FILM, other))
    assert math.isnan(contact.friction_tangent_curvature(0.0025, *contact.NO_FILM, other))
    assert np.isnan(contact.friction_slope_at_zero_slip(other))
