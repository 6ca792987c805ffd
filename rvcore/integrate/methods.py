"""The integration methods by name, and the two kernels through which the loop calls them.

Like ``scipy.integrate._ivp``'s ``METHODS``: a name (``solver.method``) and the module that
implements :mod:`rvcore.integrate.protocol`. The loop (:func:`rvcore.integrate.loop.integrate`)
and the run (:func:`rvcore.simulation.run.run_case`) know no method by name; they pass
the method's code (its place in :data:`METHODS`) to :func:`evaluate` and :func:`step`.

Why a branch per method here and not the method's kernel passed to the loop: numba
compiles a kernel that takes another kernel as an argument (or closes over one) anew in
every process (its on-disk cache cannot key on the function), which would cost every
sweep worker the minute of the loop's compile. The branches are inlined and cost nothing.
A new method is a module beside :mod:`rvcore.integrate.rk4`, an entry in :data:`METHODS`
and its branch in :func:`evaluate`, :func:`step` and :func:`begin_segment`.
"""
from __future__ import annotations

from .._numba import kernel

from . import imex, rk4

#: The methods by their ``solver.method`` names, in code order: ``rk4`` the reference,
#: ``imex`` the default (the IMEX scheme).
METHODS = {"rk4": rk4, "imex": imex}
#: Their names, in code order.
NAMES = tuple(METHODS)
RK4, IMEX = NAMES.index("rk4"), NAMES.index("imex")


def method(name: str):
    """The module of method ``name``; a ValueError names the known ones."""
    if name not in METHODS:
        raise ValueError(f"unknown integrator {name!r}: use one of {', '.join(NAMES)}")
    return METHODS[name]


def time_step(model, peak_contact_load: float, name: str, *, safety: float = 0.8, held: bool = False) -> float:
    """The fixed step [s] of the method named ``name``: its module's ``time_step``;
    ``held``: where the loads and speed are held (:mod:`rvcore.integrate.schedule`)."""
    return method(name).time_step(model, peak_contact_load, safety=safety, held=held)


@kernel(inline=True)
def begin_segment(code, segment, work, state):
    """Method ``code``'s ``begin_segment``: a stretch of the step schedule begins
    (:mod:`rvcore.integrate.schedule`)."""
    if code == IMEX:
        imex.begin_segment(segment, work, state)
    else:
        rk4.begin_segment(segment, work, state)


@kernel(inline=True)
def evaluate(code, t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur, state):
    """Method ``code``'s ``evaluate``: the right-hand side at the step's start into ``work[0]``."""
    if code == IMEX:
        imex.evaluate(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur, state)
    else:
        rk4.evaluate(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur, state)


@kernel(inline=True)
def step(code, t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur, state,
         inner, acc, reductions, phases):
    """Method ``code``'s ``step``: ``(torque, power, inertial torque, end-weight divisor)``
    (:func:`rvcore.integrate.rk4.step`)."""
    if code == IMEX:
        return imex.step(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur,
                         state, inner, acc, reductions, phases)
    return rk4.step(t, y, dt, params, rows, arcs, pockets, table, meta, diag, bdiag, work, jwork, schur, state,
                    inner, acc, reductions, phases)
