"""``run_case``: the one entry point for a dynamic case. SI in, SI out.

Takes a bearing, a profile, an operating point and solver settings; returns a
:class:`CaseResult` of plain arrays. ``pipeline.case`` turns it into labelled data.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class SolverSettings:
    """Numerical settings of one case.

    Parameters
    ----------
    output_rate : float
        Samples per second of the stored time series [Hz]. Phase metrics do not depend
        on it: they are accumulated at every integrator step.
    step_safety : float
        Fraction of the explicit RK4 stability limit used as the fixed step [-].
    time_step : float
        Explicit fixed step [s]; 0 derives it from the stiffest contact and friction
        rates (see ``rvcore.integrator.stable_time_step``).
    start_time, end_time : float
        Simulated window [s]; ``end_time`` 0 means the profile's duration.
    friction : bool
        Friction on (False switches every friction force off, for conservation checks).
    damping : bool
        Contact damping on.
    """

    output_rate: float = 1000.0
    step_safety: float = 0.8
    time_step: float = 0.0
    start_time: float = 0.0
    end_time: float = 0.0
    friction: bool = True
    damping: bool = True


@dataclass
class CaseResult:
    """Arrays of one case, SI.

    ``series`` maps a pipeline.md variable name to an array over ``time``.
    ``phase_metrics`` maps a metric name to an array over the phases (PHASES order).
    ``final_state`` is the integrator state at the end, to continue a run.
    """

    time: np.ndarray
    series: dict
    phase_metrics: dict
    final_state: np.ndarray
    info: dict = field(default_factory=dict)


class SimulationError(RuntimeError):
    """The integration blew up; the message gives the simulated time and the body."""


def run_case(bearing, profile, op, settings: SolverSettings = SolverSettings(), initial_state=None) -> CaseResult:
    """Integrate one case through its duty cycle. (Implemented in a later commit.)"""
    raise NotImplementedError
