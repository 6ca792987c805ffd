"""The statics at the sweep's extreme operating points, computed when a sweep finishes.

A designer reads the load distribution "at the operating point": the loads the profile
applies in the middle of its steady phase. Of the finished cases, those at the corners of
the load-like quantities that vary over the sweep (radial load, axial load, tilting
moment, the pair's preload) are solved once more with
:func:`rvcore.statics.operating.steady_statics` (the bearing's rings, and where they are
flexible the rigid rings' beside them; Hertz at every contact, balls in equilibrium, the
ring's weight when the sweep has gravity on), on the very bearing,
profile and operating point the case ran with, and stored in ``statics.nc``
(:mod:`pipeline.io.statics`) for the report to read.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from rvcore.rings.flexible import bearing_rings
from rvcore.statics.flexible import headline, ring_deformation
from rvcore.statics.operating import steady_loads, steady_statics

from ..io.statics import STATICS_FILE, CornerStatics, statics_dataset, write_statics

#: The load-like quantities whose corners are the extreme operating points.
LOAD_QUANTITIES = ("radial_load", "axial_load", "moment", "preload")

#: Largest number of extreme cases stored.
MAX_CORNERS = 4


def case_loads(spec) -> dict:
    """Steady radial and axial load [N], tilting moment [N m], load angle [rad] and the
    pair's preload [N] of a case (:class:`pipeline.schema.CaseSpec`)."""
    fr, fa, m, psi = steady_loads(spec.profile, spec.operating_point)
    return {"radial_load": fr, "axial_load": fa, "moment": m, "load_angle": psi, "preload": spec.bearing.preload}


def extreme_cases(specs: list) -> list:
    """The cases nearest to the corners of the load-like quantities that vary among ``specs``.

    With one or two such quantities, every corner (min/max of each, at most
    :data:`MAX_CORNERS`); with more, the all-smallest and the all-largest corner. Distance
    is measured in each quantity's span; ties go to the slowest case, then to the first in
    the sweep's order, so that cases that differ only in speed or realization (one
    operating point for the statics) give one corner. Without any varying load, the first
    case alone.
    """
    if not specs:
        return []
    specs = sorted(specs, key=lambda s: s.operating_point.speed)   # stable: the sweep's order within a speed
    q = np.array([[case_loads(s)[k] for k in LOAD_QUANTITIES] for s in specs], dtype=np.float64)
    varying = [j for j in range(q.shape[1]) if np.ptp(q[:, j]) > 1e-9 * max(np.abs(q[:, j]).max(), 1.0)]
    if not varying:
        return [specs[0]]
    lo, hi = q[:, varying].min(axis=0), q[:, varying].max(axis=0)
    if len(varying) <= 2:
        corners = np.array(np.meshgrid(*zip(lo, hi), indexing="ij")).reshape(len(varying), -1).T
    else:
        corners = np.array([lo, hi])
    out, seen = [], []
    for corner in corners:
        k = int(np.argmin((((q[:, varying] - corner) / (hi - lo)) ** 2).sum(axis=1)))
        if tuple(q[k]) not in seen:
            seen.append(tuple(q[k]))
            out.append(specs[k])
    return out[:MAX_CORNERS]


def corner_statics(spec) -> CornerStatics:
    """The statics of one case at its steady operating point, as :mod:`pipeline.io.statics` stores them."""
    loads = case_loads(spec)
    op = spec.operating_point
    values = {**loads, "speed": op.speed, "solved": 0}
    rings = bearing_rings(spec.bearing)
    try:   # flexible rings: theirs, and the rigid rings' beside them
        st = steady_statics(spec.bearing, spec.profile, op, gravity=spec.settings.gravity,
                            rings=None if rings.rigid else rings)
        st_rigid = None if rings.rigid else steady_statics(spec.bearing, spec.profile, op,
                                                           gravity=spec.settings.gravity)
    except (ValueError, ArithmeticError) as exc:   # NoEquilibriumError is a ValueError
        return CornerStatics(spec.case_id, values, f"{type(exc).__name__}: {exc}")
    rows = spec.bearing.rows
    values.update(
        solved=1, radial_displacement=st.radial_displacement, axial_displacement=st.axial_displacement,
        max_contact_load=st.max_contact_load, max_contact_pressure=st.max_contact_pressure,
        ball_azimuth=np.asarray(st.azimuths, dtype=np.float64), ball_row=np.asarray(st.row_of_ball),
        ball_load=np.asarray(st.ball_loads, dtype=np.float64),
        contact_angle=np.asarray(st.contact_angles, dtype=np.float64), arc_ring=np.asarray(st.arc_rings),
        row_radial_load=st.row_radial_loads, row_axial_load=st.row_axial_loads,
        row_axial_position=np.array([r.axial_position for r in rows]),
        row_contact_angle=np.array([r.nominal_contact_angle for r in rows]))
    if st_rigid is not None:
        values.update(flexible_rings=1, ball_load_rigid=np.asarray(st_rigid.ball_loads, dtype=np.float64),
                      **headline(spec.bearing, st), **{f"{k}_rigid": v for k, v in headline(spec.bearing,
                                                                                            st_rigid).items()},
                      **ring_deformation(rings, st))
    return CornerStatics(spec.case_id, values)


def store_corner_statics(sweep, out, states: dict) -> Path | None:
    """Solve the statics at the extreme finished cases of ``sweep`` and write ``statics.nc``.

    Parameters
    ----------
    sweep : pipeline.schema.Sweep
    out : path-like
        The sweep's folder.
    states : dict
        Case id -> :class:`pipeline.io.CaseState`; only the cases in state "ok" count.

    Returns
    -------
    Path or None
        The file, or None when no case finished (a ``statics.nc`` of an earlier run is
        then removed: it would describe cases this run did not keep).
    """
    out = Path(out)
    done = [s for s in sweep.cases if getattr(states.get(s.case_id), "state", "") == "ok"]
    if not done:
        (out / STATICS_FILE).unlink(missing_ok=True)
        return None
    corners = [corner_statics(s) for s in extreme_cases(done)]
    tilt = " and ".join(sorted({s.bearing.inner_ring.tilt for s in done}))
    ds = statics_dataset(corners, gravity=bool(done[0].settings.gravity), tilt=tilt, sweep_name=sweep.name)
    return write_statics(ds, out)


def store_corner_statics_or_warn(sweep, out, states: dict) -> Path | None:
    """:func:`store_corner_statics`, with any failure one warning line instead of an error:
    the cases and ``sweep.nc`` are the run's results, and the report says when the
    statics are missing."""
    try:
        return store_corner_statics(sweep, out, states)
    except Exception as exc:  # noqa: BLE001 - see the docstring
        print(f"warning: the statics at the extreme operating points were not stored "
              f"({type(exc).__name__}: {exc})", file=sys.stderr)
        return None
