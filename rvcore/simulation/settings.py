"""The settings of one dynamic case: the integrator's and the virtual sensors'. SI."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SolverSettings:
    """Numerical settings of one case.

    Parameters
    ----------
    output_rate : float
        Samples per second of the stored time series [Hz]. Phase metrics do not depend
        on it: they are accumulated at every integrator step.
    method : str
        The integrator: ``"imex"``, the default (the coupled implicit–explicit additive
        Runge–Kutta scheme of :mod:`rvcore.integrate.imex`: the ball–race Hertz stiffness, friction
        at small slip and contact damping implicit, the rest explicit; about 4× faster on
        the study cycle), or ``"rk4"`` (classical RK4, the reference it is checked against).
    step_safety : float
        Fraction of the method's bounds used as the fixed step [-], in each stretch of
        the step schedule (:mod:`rvcore.integrate.schedule`: IMEX takes a longer step
        where the loads and speed are held).
    time_step : float
        Explicit fixed step [s], the same throughout (no longer step where the loads are
        held); 0 derives the steps from the stiffest contact and friction rates (see
        ``rvcore.integrate.rk4.rk4_time_step``, ``rvcore.integrate.imex.imex_time_step``).
    start_time, end_time : float
        Simulated window [s]; ``end_time`` 0 means the profile's duration.
    friction : bool
        Friction on (False switches every friction force off, for conservation checks).
    damping : bool
        Contact damping on.
    gravity : bool
        Gravity on every body, along the bearing's mounting (False only for the
        conservation checks of docs/model.md §9).
    seed : int
        −1: every ball starts at its pocket centre. Otherwise the seed of the random
        start: each ball starts at a uniformly drawn position within its pocket's
        circumferential play (one realization of an ensemble).
    """

    output_rate: float = 1000.0
    method: str = "imex"
    step_safety: float = 0.8
    time_step: float = 0.0
    start_time: float = 0.0
    end_time: float = 0.0
    friction: bool = True
    damping: bool = True
    gravity: bool = True
    seed: int = -1


@dataclass(frozen=True)
class Sensor:
    """A displacement sensor fixed in space, aimed at the inner ring's bore or face.

    Parameters
    ----------
    name : str
    position : tuple of float
        The point of the (unloaded, centred) ring the sensor reads, in the bearing
        frame [m].
    direction : tuple of float
        Measuring direction [-] (normalised here): the reading is the ring's displacement
        at ``position`` along it (``rvcore.recording.plan.sensor_reading``).
    """

    name: str
    position: tuple
    direction: tuple

    def as_row(self) -> np.ndarray:
        d = np.asarray(self.direction, dtype=float)
        norm = float(np.linalg.norm(d))
        if not norm > 0.0:
            raise ValueError(f"sensor {self.name!r}: the direction must not be zero")
        return np.concatenate([np.asarray(self.position, dtype=float), d / norm])
