"""Synthetic case results for testing the pipeline layers without running dynamics.

The numbers are made up (a smooth function of the operating point plus optional noise);
they exercise labelling, writing, combining, fitting and reporting, not physics.
"""
from __future__ import annotations

import numpy as np

from rvcore.recording.results import CaseResult
from rvcore.profile import PHASES, study_profile


def synthetic_result(speed: float, radial_load: float, axial_load: float = 10e3, *,
                     n: int = 461, noise: float = 0.0, seed: int = 0) -> CaseResult:
    """A CaseResult shaped like a real one. ``speed`` [rad/s], loads [N]."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 4.6, n)
    p = study_profile()
    from rvcore.profile import OperatingPoint
    rp = p.resolve(OperatingPoint(speed, radial_load, axial_load))
    fr = np.array([rp.value(0, x) for x in t])
    fa = np.array([rp.value(1, x) for x in t])
    w = np.array([rp.value(2, x) for x in t])
    dr = 2e-9 * fr - 1e-7 * w + noise * rng.standard_normal(n)
    da = 1e-9 * fa + 5e-8 * w + noise * rng.standard_normal(n)
    zeros = np.zeros(n)
    series = {
        "radial_displacement": dr, "axial_displacement": da,
        "inner_ring_x": dr, "inner_ring_y": zeros, "inner_ring_z": da,
        "inner_ring_tilt_x": zeros, "inner_ring_tilt_y": zeros,
        "applied_radial_load": fr, "applied_axial_load": fa, "inner_ring_speed": w,
        "cage_speed": 0.468 * w, "max_inner_contact_load": fr / 10, "max_outer_contact_load": fr / 10,
        "loaded_ball_count": np.full(n, 25.0), "max_contact_pressure": 1e9 + fr * 1e4,
    }
    metrics = {}
    for name, x in (("radial_displacement", dr), ("axial_displacement", da)):
        rng_, mean_, std_ = [], [], []
        for (_, s, e) in p.phases:
            m = (t >= s) & (t < e)
            rng_.append(np.ptp(x[m])); mean_.append(x[m].mean()); std_.append(x[m].std())
        metrics[f"{name}_range"] = np.array(rng_)
        metrics[f"{name}_mean"] = np.array(mean_)
        metrics[f"{name}_std"] = np.array(std_)
    metrics["cage_speed_mean"] = np.array([0.234, 0.468, 0.234]) * speed
    metrics["inner_ring_speed_mean"] = np.array([0.5, 1.0, 0.5]) * speed
    metrics["cage_slip"] = np.array([0.01, 0.005, 0.01])
    # the cage slip's definition, 1 - mean cage speed / epicyclic speed, fixes the latter
    metrics["epicyclic_cage_speed"] = metrics["cage_speed_mean"] / (1.0 - metrics["cage_slip"])
    metrics["peak_contact_pressure"] = np.full(len(PHASES), 1e9 + radial_load * 1e4)
    return CaseResult(time=t, series=series, phase_metrics=metrics, final_state=np.zeros(3),
                      info={"steps": 1000})
