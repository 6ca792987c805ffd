"""What a case returns: :class:`CaseResult`, and the phase metrics, energies and lives
read back from the integrator's accumulators by the output table. SI throughout."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .plan import (ABS_MAX, COUNT, ENERGIES, FINITE_MEAN, INTEGRAL, MAX, MAX_AND_TIME, MIN, S_M2, S_MAX, S_MEAN, S_MIN,
                         S_N, S_TMAX, S_TMIN, STATISTICS, SUM, Plan, row_slot, transform)
from ..standards.iso16281 import duty_cycle_life
from ..output_table import DUTY_CYCLE, N_ROW_SIGNALS, N_SIGNALS, PHASE, SLOT, outputs_of


@dataclass
class CaseResult:
    """Arrays of one case, SI.

    ``series`` maps an output's name (:data:`rvcore.output_table.OUTPUTS`) to an array over ``time``; with sensors,
    ``series["sensor_displacement"]`` is over ``(time, sensor)``.
    ``phase_metrics`` maps a metric name to an array over the phases (PHASES order), or
    over ``(phase, sensor)`` for the ``sensor_displacement_*`` metrics.
    ``final_state`` is the integrator state at the end, to continue a run.
    ``steady`` holds scalars at the steady operating point from the statics there
    (the ``steady`` outputs of :mod:`rvcore.output_table`).
    ``life_sums`` are the integrator's life sums (the contract of ``rvcore.standards.iso16281``):
    ``"inner"`` and ``"outer"`` over ``(phase + 1, row)`` [N³ rev] and ``"revolutions"``
    over ``phase + 1`` [rev], the last line the whole simulated cycle.
    ``life`` holds the duty-cycle scalars (the ``duty_cycle`` outputs).
    ``spectra`` holds the steady phase's amplitude spectra and the bearing's kinematic
    frequencies (:func:`rvcore.recording.spectra.steady_spectra`, ``kinematic_frequency`` [Hz]).
    ``energy`` maps ``friction``, ``damping`` (dissipated), ``drive`` (∫T·ω dt),
    ``load`` (work of the applied loads and gravity) and ``tilt`` (the power the
    small-tilt ring equations leave out, see ``rvcore.dynamics.rhs.rhs``) to arrays over
    ``phase + 1`` [J], the last line the whole cycle, integrated with RK4's weights.
    """

    time: np.ndarray
    series: dict
    phase_metrics: dict
    final_state: np.ndarray
    info: dict = field(default_factory=dict)
    ball_diag: np.ndarray | None = None  # per ball at the end: Q_inner, Q_outer, F_inner_radial, F_outer_radial, Q_pocket
    steady: dict = field(default_factory=dict)  # the steady outputs: statics at the steady point
    life_sums: dict = field(default_factory=dict)
    life: dict = field(default_factory=dict)
    energy: dict = field(default_factory=dict)
    spectra: dict = field(default_factory=dict)  # rvcore.recording.spectra.steady_spectra and "kinematic_frequency"


class SimulationError(RuntimeError):
    """The integration blew up; the message gives the simulated time and the body."""


def _transformed(code, values):
    return np.array([transform(code, float(v)) for v in values])


def _slots(o, plan: Plan):
    """``(instance, slot, other slot)`` of each copy of phase output ``o``."""
    if o.over == "row":
        return [(r, row_slot(o.signal, r), row_slot(o.other, r) if o.other else -1) for r in range(plan.n_rows)]
    if o.over == "sensor":
        s0 = N_SIGNALS + N_ROW_SIGNALS * plan.n_rows
        return [(s, s0 + s, -1) for s in range(plan.n_sensors)]
    return [(-1, SLOT[o.signal], SLOT[o.other] if o.other else -1)]


def _phase_values(o, acc, plan: Plan, slot: int, other: int, phases, edge_tolerance: float):
    """One copy of phase output ``o`` over the phases, from the accumulators."""
    ok = acc[:, COUNT] > 0
    nn = np.where(ok, acc[:, COUNT], np.nan)
    red = o.reduce
    if red == "mean":
        return acc[:, plan.column(slot, SUM)] / nn
    if red == "finite_mean":
        c = plan.column(slot, FINITE_MEAN)
        return acc[:, c] / np.where(acc[:, c + 1] > 0, acc[:, c + 1], np.nan)
    if red == "slip":
        return 1.0 - acc[:, plan.column(slot, SUM)] / acc[:, plan.column(other, SUM)]
    if red in ("max", "min", "abs_max", "integral"):
        kind = {"max": MAX, "min": MIN, "abs_max": ABS_MAX, "integral": INTEGRAL}[red]
        values = acc[:, plan.column(slot, kind)]
        # an extreme still at its start (±inf): the signal was never a number (NaN: none)
        ok = ok & ~np.isinf(values) if kind in (MAX, MIN) else ok
        return np.where(ok, _transformed(o.transform, values) if kind in (MAX, MIN) else values, np.nan)
    if red == "max_time":
        c = plan.column(slot, MAX_AND_TIME)
        return np.where(ok & np.isfinite(_transformed(o.transform, acc[:, c])), acc[:, c + 1], np.nan)
    c = plan.column(slot, STATISTICS)
    a = acc[:, c:c + 7]
    counted = a[:, S_N] > 0
    tmin, tmax = a[:, S_TMIN], a[:, S_TMAX]
    if red == "range":
        values = a[:, S_MAX] - a[:, S_MIN]
    elif red == "stats_mean":
        values = a[:, S_MEAN]
    elif red == "std":
        values = np.sqrt(np.maximum(a[:, S_M2], 0.0) / np.where(counted, a[:, S_N], 1.0))
    elif red == "min_time":
        values = tmin
    elif red == "max_time_of":
        values = tmax
    else:   # range_at_edge: an extreme within one output interval of the window's edge
        start, end = phases[:, 0], phases[:, 1]

        def near(t):
            return (np.abs(t - start) <= edge_tolerance) | (np.abs(end - t) <= edge_tolerance)
        values = (near(tmin) | near(tmax)).astype(float)
    return np.where(counted, values, np.nan)


def read_phase_metrics(acc, plan: Plan, phases, edge_tolerance: float) -> dict:
    """Every phase output of :mod:`rvcore.output_table` but ``fatigue_damage`` (the lives
    give it, :func:`duty_cycle_outputs`), over the phases; ``(phase, row)`` for a bearing
    of several rows, ``(phase, sensor)`` for the sensors.

    ``edge_tolerance`` [s] (one output interval) decides ``*_range_at_edge``: 1 where an
    extreme lies that close to its phase window's start or end, so that the range may be
    cut off by the window.
    """
    acc = acc[:phases.shape[0]]      # the last line is the whole cycle
    out = {}
    with np.errstate(invalid="ignore", divide="ignore"):
        for o in outputs_of(PHASE):
            if o.reduce == "life":
                continue
            if o.reduce in ("window_start", "window_end"):
                out[o.name] = phases[:, 0 if o.reduce == "window_start" else 1].astype(float).copy()
                continue
            copies = [_phase_values(o, acc, plan, slot, other, phases, edge_tolerance)
                      for _, slot, other in _slots(o, plan)]
            if not copies:
                continue
            if o.over == "sensor" or (o.over == "row" and plan.n_rows > 1):
                out[o.name] = np.column_stack(copies)
            else:
                out[o.name] = copies[0]
    return out


def read_energies(acc, plan: Plan) -> dict:
    """The energies over ``phase + 1`` [J] (the last line the whole cycle): ``friction``,
    ``damping`` (dissipated), ``drive`` (∫T·ω dt), ``load`` (work of the loads and
    gravity) and ``tilt`` (what the small-tilt ring equations leave out)."""
    return {name: acc[:, plan.column(SLOT[signal], INTEGRAL)].copy() for name, signal in ENERGIES.items()}


def read_life_sums(acc, plan: Plan) -> dict:
    """The life sums (the contract of :mod:`rvcore.standards.iso16281`): ``inner`` and ``outer`` over
    ``(phase + 1, row)`` [N³ rev], ``revolutions`` over ``phase + 1`` [rev]; and the same sums
    with each step's over its a_ISO, ``inner_modified`` and ``outer_modified`` [N³ rev], and
    ``revolutions_kappa_below_scope`` [rev] (:func:`rvcore.recording.plan.fill_state_signals`)."""
    def rows(name):
        return np.column_stack([acc[:, plan.column(row_slot(name, r), SUM)] for r in range(plan.n_rows)])
    return {"inner": rows("life_sum_inner"), "outer": rows("life_sum_outer"),
            "revolutions": acc[:, plan.column(SLOT["revolutions"], SUM)].copy(),
            "inner_modified": rows("life_sum_inner_modified"), "outer_modified": rows("life_sum_outer_modified"),
            "revolutions_kappa_below_scope": acc[:, plan.column(SLOT["revolutions_kappa_below_scope"], SUM)].copy()}


def duty_cycle_outputs(bearing, life_sums: dict, n_phases: int) -> dict:
    """The duty-cycle life of a case from its life sums.

    Returns the ``duty_cycle`` outputs of :mod:`rvcore.output_table` that
    ``rvcore.standards.iso16281.duty_cycle_life`` gives, plus ``fatigue_damage`` over the phases when it gives that per phase (an array
    of ``n_phases`` values, or ``n_phases + 1`` with the whole cycle last).
    """
    life = duty_cycle_life(bearing, life_sums)
    # an infinite life (nothing loads the turning bearing, or it does not turn) is stored
    # as NaN, like static_safety_factor with nothing loaded: no inf in a case file
    out = {k: float(life[k]) if math.isfinite(float(life[k])) else math.nan
           for k in (o.name for o in outputs_of(DUTY_CYCLE)) if k in life}
    out.update(modified_cycle_outputs(bearing, life_sums, out.get("rating_life_L10r", math.nan)))
    if "fatigue_damage" in life:
        damage = np.atleast_1d(np.asarray(life["fatigue_damage"], dtype=float))
        if damage.size == n_phases + 1:
            out.setdefault("fatigue_damage_cycle", float(damage[-1]))
            damage = damage[:n_phases]
        out["fatigue_damage"] = damage
    return out


def modified_cycle_outputs(bearing, life_sums: dict, l10r: float) -> dict:
    """The duty cycle's modified life from the modified life sums (:func:`read_life_sums`).

    Returns
    -------
    dict
        ``rating_life_L_nm`` [rev]: :func:`rvcore.standards.iso16281.duty_cycle_life` of the
        modified sums (each step's damage over its a_ISO; a_1 = 1), NaN where not rated or
        infinite; ``a_iso_cycle`` [-], its ratio to ``l10r`` (L10r [rev]);
        ``kappa_below_scope_fraction`` [-], the revolutions at κ < 0.1 over the cycle's.
        Empty without the modified sums.
    """
    if "inner_modified" not in life_sums:
        return {}
    modified = duty_cycle_life(bearing, {"inner": life_sums["inner_modified"], "outer": life_sums["outer_modified"],
                                         "revolutions": life_sums["revolutions"]})
    lnm = float(modified["rating_life_L10r"])
    lnm = lnm if math.isfinite(lnm) else math.nan
    revs = float(life_sums["revolutions"][-1])
    low = float(life_sums["revolutions_kappa_below_scope"][-1])
    return {"rating_life_L_nm": lnm,
            "a_iso_cycle": lnm / l10r if math.isfinite(lnm) and math.isfinite(l10r) and l10r > 0 else math.nan,
            "kappa_below_scope_fraction": low / revs if revs > 0 else math.nan}
