"""What an integration method supplies, and the counters it shares with the loop.

A method is one module (:mod:`rvcore.integrate.rk4`, :mod:`rvcore.integrate.imex`) and
one entry of :data:`rvcore.integrate.methods.METHODS`. The module supplies:

- ``new_work(model, pocket_tolerance, load_tolerance)``: its scratch arrays
  ``(work, jwork, schur)``; ``work[0]`` receives the right-hand side at each step's start;
- ``time_step(model, peak_contact_load, *, safety, held)``: its fixed step [s], where the
  loads and speed are held or not (:mod:`rvcore.integrate.schedule`);
- ``segment_constant(model, peak_contact_load, time_step)``: the constant a stretch of
  the step schedule at that step hands ``begin_segment``
  (:data:`rvcore.integrate.schedule.SEG_TOL`);
- ``load_tolerance(peak_contact_load)``: a second such constant, sized on the load alone
  (:data:`rvcore.integrate.schedule.SEG_LOAD_TOL`; IMEX: its tangents' load tolerance);
- ``falling_guard(model, peak_contact_load, *, safety, held)``: ``(slip², longest
  substep)`` where its step does not keep the friction law's falling slope within its
  bound (:data:`rvcore.integrate.schedule.SEG_SLIP2`, ``SEG_SUB_DT``; ``(0, 0)`` where it does);
- ``new_state()``: its counters for one run (:func:`new_state`, its own slots set);
- ``rhs_evaluations(n_steps, substeps)``: how many right-hand sides a run of ``n_steps``
  evaluated, with ``substeps`` substeps computed in the steps it took again;
- the kernels ``evaluate(...)`` (the right-hand side at the step's start, with whatever
  else the method takes from it), ``step(...)`` (one step) and ``begin_segment(segment,
  work, state)`` (a stretch of the schedule begins), which :mod:`rvcore.integrate.methods`
  dispatches to.

``state`` is an int64 array of :data:`N_STATE` counters the loop hands to every call: the
first three are read by the loop and the run (below), the rest belong to the method.
"""
from __future__ import annotations

import numpy as np

#: ``state[S_SUBSTEPPED]``: steps the method took again in substeps; ``state[S_REFRESHES]``:
#: steps at which it evaluated and factored its tangents (0 for a method without);
#: ``state[S_SUBSTEPS]``: the substeps it computed in the steps it took again, tries that
#: did not keep included.
S_SUBSTEPPED, S_REFRESHES, S_SUBSTEPS = 0, 1, 2
#: From this slot on, the method's own counters.
S_OWN = 3
N_STATE = 8


def new_state() -> np.ndarray:
    """Zeroed counters for one run."""
    return np.zeros(N_STATE, dtype=np.int64)
