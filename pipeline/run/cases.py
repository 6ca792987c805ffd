"""One case of a sweep: compute it (on any worker), label it and write its file.

:func:`compute_and_write` computes a case, labels it (:func:`label_case`) and writes its
file where the worker can reach the sweep's ``cases/`` folder (a local cluster, a serial
run, a cluster on a shared file system), returning only the file's SHA-256: the parent
then records a line of status per case, a cost that does not depend on the case. A worker
that cannot reach the folder returns the :class:`rvcore.simulation.run.CaseResult`, and
the parent labels and writes it as before. Either way the labelling is the same
function, so the files do not depend on where a case ran.
"""
from __future__ import annotations

import time
import traceback
from dataclasses import dataclass
from pathlib import Path

import xarray as xr

from ..io import case_dataset, history_line
from ..schema import CaseSpec

#: Keys of ``CaseResult.info`` that vary from run to run (timings): they go into the
#: ``history`` line of a case file, not into its attributes, so that case files are
#: identical whatever ran them.
TIMING_INFO = ("wall_time",)


def flexible(bearing) -> bool:
    """Whether either of ``bearing``'s rings is flexible (``inner_ring_support``,
    ``outer_ring_support``)."""
    return bearing.inner_ring_support is not None or bearing.outer_ring_support is not None


def case_keywords(spec: CaseSpec) -> dict:
    """The keywords of ``run_case`` for ``spec`` besides its four arguments: its sensors,
    and a flexible bearing's rings (:func:`rvcore.rings.flexible.bearing_rings`) with the
    bearing file's ``max_order``: the dynamics keep their orders up to
    :data:`rvcore.dynamics.ring_modes.DYNAMICS_MAX_ORDER` (``run_case`` truncates them), and
    the steady statics on every order give the case's ``ring_mode_truncation``
    (docs/model.md §16.1). A rigid bearing's call is as before (no ``rings``)."""
    keywords = {"sensors": spec.sensors}
    if flexible(spec.bearing):
        from rvcore.rings.flexible import bearing_rings

        keywords["rings"] = bearing_rings(spec.bearing)
    return keywords


@dataclass
class CaseOutcome:
    """What a worker sends back for one case.

    Parameters
    ----------
    case_id : str
    ok : bool
    result : rvcore.simulation.run.CaseResult or None
        The arrays when ``ok``.
    reason : str
        One line: why it failed.
    traceback : str
        The full traceback of the failure ('' when ok).
    seconds : float
        Wall time of the case on its worker [s].
    """

    case_id: str
    ok: bool
    result: object = None
    reason: str = ""
    traceback: str = ""
    seconds: float = 0.0
    #: the SHA-256 of the case file when the worker wrote it ('' when it did not)
    sha256: str = ""
    #: one line when the worker could not write the file because of where it goes
    #: (a full disk, a read-only folder): the sweep stops with it
    write_error: str = ""

    @property
    def written(self) -> bool:
        return bool(self.sha256)


def _default_case_fn():
    # Looked up at call time so that the core (or a test's monkeypatch) is current.
    from rvcore.simulation import run as driver

    return driver.run_case


def failure_reason(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    line = f"{type(exc).__name__}: {text[0]}" if text else type(exc).__name__
    return line if len(line) <= 500 else line[:497] + "..."


def compute_case(spec: CaseSpec, case_fn=None) -> CaseOutcome:
    """Run one case; never raises for a failing case (the outcome carries the reason).

    Parameters
    ----------
    spec : pipeline.schema.sweepfile.CaseSpec
        The resolved case (SI).
    case_fn : callable, optional
        ``case_fn(bearing, profile, op, settings, sensors=(), rings=...) -> CaseResult``
        (``rings`` only for a flexible bearing, :func:`case_keywords`); default
        ``rvcore.simulation.run.run_case``.
    """
    t0 = time.perf_counter()
    fn = case_fn if case_fn is not None else _default_case_fn()
    try:
        result = fn(spec.bearing, spec.profile, spec.operating_point, spec.settings, **case_keywords(spec))
    except Exception as exc:  # the case failed: record why and let the others go on
        return CaseOutcome(spec.case_id, False, None, failure_reason(exc), traceback.format_exc(),
                           time.perf_counter() - t0)
    return CaseOutcome(spec.case_id, True, result, seconds=time.perf_counter() - t0)


def compute_and_write(spec: CaseSpec, case_fn=None, cases_dir=None, source: str = "",
                      sweep_name: str = "", marker: str = "") -> CaseOutcome:
    """:func:`compute_case`, then, where this process sees the sweep's ``cases_dir`` (its
    ``marker`` file is there), label the result and write ``<cases_dir>/<case id>.nc``
    atomically here. There the run's core cases also share their starts with the other
    workers' through the folder beside the marker (:func:`starts_folder`).

    Parameters
    ----------
    spec : pipeline.schema.sweepfile.CaseSpec
    case_fn : callable, optional
        As for :func:`compute_case`.
    cases_dir : str or Path, optional
        The sweep's ``cases/`` folder [-]; None, or a folder not seen from here (a worker
        on another host), returns the result for the parent to write.
    source, sweep_name : str
        For the file's ``history`` line (:func:`label_case`).
    marker : str
        A file the parent made in ``cases_dir`` for this run: a worker on another host
        that has a folder of the same name, but not this one, does not see it and
        returns the result.

    Returns
    -------
    CaseOutcome
        ``sha256`` set and no result when the file was written here; ``write_error`` set
        when the place is at fault (nothing else is wrong with the case); a case whose
        arrays cannot be written fails with the reason.
    """
    from ..io import WriteError, file_digest, write_atomic

    here = cases_dir is not None and bool(marker) and (Path(cases_dir) / marker).is_file()
    if here and case_fn is None:
        share_starts(Path(cases_dir) / starts_folder(marker))
    try:
        outcome = compute_case(spec, case_fn)
    finally:
        if here and case_fn is None:
            share_starts(None)
    if not outcome.ok or not here:
        return outcome
    try:
        ds = label_case(spec, outcome.result, source=source or source_name(case_fn), sweep_name=sweep_name)
        path = write_atomic(ds, Path(cases_dir) / f"{spec.case_id}.nc")
        outcome.sha256 = file_digest(path)
    except WriteError as exc:   # a full disk, a read-only folder: the sweep stops
        outcome.write_error = str(exc)
    except Exception as exc:  # bad result arrays: this case fails
        outcome.ok = False
        outcome.reason = f"could not write the case file: {failure_reason(exc)}"
        outcome.traceback = traceback.format_exc()
    outcome.result = None   # the file holds it; nothing large goes back to the parent
    return outcome


def starts_folder(marker: str) -> str:
    """The name of the folder beside a run's marker file in ``cases/`` through which its
    workers share the starts of the grid's speeds (:mod:`rvcore.simulation.shared_start`):
    ``.rvsweep-<random>.starts``. The run makes it and removes it when it ends."""
    return marker.rsplit(".", 1)[0] + ".starts"


def share_starts(folder) -> None:
    """Let this process's starts (``rvcore.simulation.shared_start.STARTS``) be shared
    through ``folder`` where the run made it (None, or a folder that is not there: keep
    them to this process)."""
    from rvcore.simulation.shared_start import STARTS

    ok = folder is not None and Path(folder).is_dir() and not Path(folder).is_symlink()
    STARTS.share(folder if ok else None)


def label_case(spec: CaseSpec, result, *, source: str = "rvcore.simulation.run.run_case",
               sweep_name: str = "") -> xr.Dataset:
    """The case file's dataset: :func:`pipeline.io.case.case_dataset` with the case's id.

    Timings in ``result.info`` (:data:`TIMING_INFO`) go into the ``history`` line
    rather than into attributes, so that two runs of the same case give the same data
    and attributes; only ``history`` carries when and how long.
    """
    op = spec.operating_point
    info = dict(result.info)
    timings = {k: info.pop(k) for k in TIMING_INFO if k in info}
    if timings:
        result = _with_info(result, info)
    spent = "".join(f", {k} {v:.3f} s" for k, v in timings.items() if isinstance(v, (int, float)))
    where = f" in sweep {sweep_name}" if sweep_name else ""
    history = history_line(f"{source}: case {spec.case_id}{where}{spent}")
    return case_dataset(
        result, speed=op.speed, radial_load=op.radial_load, axial_load=op.axial_load,
        configuration=spec.configuration, configuration_hash=spec.case_id,
        bearing_name=spec.bearing.name, profile_name=spec.profile.name,
        caveats=spec.bearing.warnings, assumptions=spec.bearing.assumptions, history=history,
        sensors=spec.sensors, realization=int(spec.settings.seed))


def _with_info(result, info):
    import copy

    new = copy.copy(result)
    new.info = info
    return new


def source_name(case_fn) -> str:
    if case_fn is None:
        return "rvcore.simulation.run.run_case"
    return f"{getattr(case_fn, '__module__', '?')}.{getattr(case_fn, '__qualname__', repr(case_fn))}"


def run_one_case(spec: CaseSpec, case_fn=None) -> xr.Dataset:
    """Build, run and label one case (in this process); raises if the case fails."""
    fn = case_fn if case_fn is not None else _default_case_fn()
    result = fn(spec.bearing, spec.profile, spec.operating_point, spec.settings, **case_keywords(spec))
    return label_case(spec, result, source=source_name(case_fn))
