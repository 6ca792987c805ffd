"""The start a sweep's speeds share: the load ramp before the inner ring turns. SI throughout.

Why
---
On the study cycle the inner ring stands still until 0.3 s while the loads ramp up, so the
ten speeds of one load and seed compute the same first 0.3 s (8 % of a case). A run is
therefore made of two calls of the loop (:class:`rvcore.integrate.loop.Scratch`): the
start, up to the last output time before the speed leaves zero (:func:`shared_until`),
and the rest. The start is computed from the profile with its speed set to zero
(:func:`zero_speed`), its steps and tolerances sized on that profile's peak contact
load, so that it depends on nothing the speed sets; then every case that would compute
the same start (the same bearing, imperfections, loads, settings and initial state:
:func:`start_key` hashes every array and number the loop reads) takes a copy of it from
:data:`STARTS`, a process's store of the starts it computed last. A case computed alone
(``rvsweep simulate``) takes the same two calls, so its results are the same bits whether
its start was computed or copied.

Where the speed is not zero at the run's start (a profile that starts turning, a run that
starts later) nothing is shared and the run is one call.

A sweep's workers share their starts through a folder as well (:meth:`StartStore.share`):
a start computed by one worker is written there (``<key>.npz``, every array as it is), and
a worker that has not computed it reads it instead. Two workers on one machine took each
start's turn of a load's speeds from each other and computed every start about twice.
"""
from __future__ import annotations

import dataclasses
import hashlib
import math
import os
import threading
from collections import OrderedDict
from pathlib import Path

import numpy as np

#: Starts a process keeps (:class:`StartStore`): a sweep's worker takes its cases a load
#: at a time, each load's seeds in turn, so a few suffice; each is the state, the method's
#: scratch, the accumulators and the start's output lines (0.76 MB on the study
#: bearing at 1 kHz).
KEEP = 16
#: The most bytes the kept starts may hold together [B] (the newest is kept whatever its
#: size): a high output rate makes a start's output lines large.
BUDGET = 64 * 2**20


def shared_until(resolved, t_start: float, t_end: float, output_rate: float) -> float:
    """The output time [s] up to which a run does not depend on the speed's value: the
    last one at or before the end of the speed channel's leading zeros, and after
    ``t_start`` and before ``t_end``; ``t_start`` where there is none (no shared start).

    The speed channel is exactly zero up to the last of its leading breakpoints whose
    values are all zero (linear and smoothstep interpolation between two zeros give zero).
    """
    times, values, _ = resolved.speed
    end = -math.inf
    for t, v in zip(times, values):
        if v != 0.0:
            break
        end = float(t)
    if len(times) and all(v == 0.0 for v in values):
        end = math.inf          # a profile that never turns: no speed to share a start over
    if not end > t_start or end == math.inf:
        return t_start
    k = int(math.floor((min(end, t_end) - t_start) * output_rate + 1e-9))
    t_split = t_start + k / output_rate
    return t_split if t_start < t_split < t_end else t_start


def zero_speed(profile, op):
    """``profile`` resolved at ``op`` with its speed set to zero."""
    return profile.resolve(dataclasses.replace(op, speed=0.0))


def start_key(method_name: str, arrays, numbers) -> str:
    """A hash of everything a start's computation reads: the method's name, ``arrays``
    (their dtypes, shapes and bytes) and ``numbers`` (as ``float.hex``)."""
    h = hashlib.sha256(method_name.encode())
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(f"{a.dtype.str}{a.shape}".encode())
        h.update(a.tobytes())
    for x in numbers:
        h.update(float(x).hex().encode())
    return h.hexdigest()


@dataclasses.dataclass
class Start:
    """A computed start: the state at its end, the loop's scratch, the diagnostics, the
    accumulators, the output lines and their times."""

    y: np.ndarray
    scratch: object
    diag: np.ndarray
    bdiag: np.ndarray
    acc: np.ndarray
    out: np.ndarray
    out_time: np.ndarray

    def copy(self) -> "Start":
        return Start(self.y.copy(), self.scratch.copy(), self.diag.copy(), self.bdiag.copy(), self.acc.copy(),
                     self.out.copy(), self.out_time.copy())

    def save(self, path) -> None:
        """Write every array of the start to ``path`` (``.npz``, uncompressed), atomically:
        a temporary name beside it, then ``os.replace``."""
        from rvcore.integrate.loop import Scratch

        path = Path(path)
        tmp = path.with_name(f".{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
        s = self.scratch
        arrays = {name: getattr(self, name) for name in _START_ARRAYS}
        arrays.update({f"scratch_{name}": getattr(s, name) for name in _SCRATCH_ARRAYS})
        if not isinstance(s, Scratch):
            raise TypeError(f"a start's scratch is a Scratch, not {type(s).__name__}")
        try:
            with open(tmp, "wb") as fh:
                np.savez(fh, method_name=np.array(s.method_name), **arrays)
            os.replace(tmp, path)
        finally:
            tmp.unlink(missing_ok=True)

    @classmethod
    def load(cls, path) -> "Start":
        """The start :meth:`save` wrote to ``path`` (no pickled objects are read)."""
        from rvcore.integrate.loop import Scratch

        with np.load(path, allow_pickle=False) as f:
            scratch = object.__new__(Scratch)
            scratch.method_name = str(f["method_name"])
            for name in _SCRATCH_ARRAYS:
                setattr(scratch, name, f[f"scratch_{name}"])
            return cls(scratch=scratch, **{name: f[name] for name in _START_ARRAYS})

    @property
    def nbytes(self) -> int:
        """The bytes its arrays hold [B]."""
        s = self.scratch
        return sum(a.nbytes for a in (self.y, self.diag, self.bdiag, self.acc, self.out, self.out_time, s.work,
                                      s.jwork, s.schur, s.state, s.inner, s.carry))


#: The arrays of a :class:`Start` and of its scratch (:class:`rvcore.integrate.loop.Scratch`).
_START_ARRAYS = ("y", "diag", "bdiag", "acc", "out", "out_time")
_SCRATCH_ARRAYS = ("work", "jwork", "schur", "state", "inner", "carry")


class StartStore:
    """The last :data:`KEEP` starts a process computed (no more than :data:`BUDGET` bytes
    of them but the newest), by :func:`start_key`; ``hits`` and ``misses`` count the
    lookups, ``shared`` the hits read from the folder. Safe to share between threads
    (cases run in threads, the kernels releasing the GIL).

    With a folder (:meth:`share`), every start put is also written there as
    ``<key>.npz`` (:meth:`Start.save`), and a start this process has not computed is read
    from there when another process wrote it. The key hashes everything the start's
    computation reads, not the code: a folder serves one run of one code (a sweep's
    workers; the sweep makes it and removes it)."""

    def __init__(self, keep: int = KEEP, budget: int = BUDGET):
        self.keep = keep
        self.budget = budget
        self._starts = OrderedDict()
        self._lock = threading.Lock()
        self.hits = 0
        self.misses = 0
        self.shared = 0
        self.folder = None
        self._initial = OrderedDict()

    def share(self, folder) -> None:
        """Share the starts through ``folder`` (an existing folder; None: this process's
        alone)."""
        self.folder = Path(folder) if folder is not None else None

    def get(self, key: str):
        """A copy of the start stored under ``key`` (here, else in the folder), or None."""
        with self._lock:
            start = self._starts.get(key)
            if start is not None:
                self.hits += 1
                self._starts.move_to_end(key)
                return start.copy()
            folder = self.folder
        start = self._read(folder, key) if folder is not None else None
        with self._lock:
            if start is None:
                self.misses += 1
                return None
            self.hits += 1
            self.shared += 1
            self._keep(key, start)
            return start.copy()

    @staticmethod
    def _read(folder: Path, key: str):
        path = folder / f"{key}.npz"
        try:
            return Start.load(path)
        except Exception:   # none there (yet), or not whole (zipfile, numpy, OSError): compute it
            return None

    def put(self, key: str, start: Start) -> None:
        """Store a copy of ``start`` under ``key``, dropping the oldest beyond :data:`KEEP`;
        with a folder, write it there too."""
        folder = self.folder
        if folder is not None:
            try:
                start.save(folder / f"{key}.npz")
            except OSError:   # a full disk or a folder gone: the others compute it themselves
                pass
        start = start.copy()
        with self._lock:
            self._keep(key, start)

    def _keep(self, key: str, start: Start) -> None:
        """Hold ``start`` (the caller holds the lock)."""
        self._starts[key] = start
        self._starts.move_to_end(key)
        held = sum(s.nbytes for s in self._starts.values())
        while len(self._starts) > 1 and (len(self._starts) > self.keep or held > self.budget):
            held -= self._starts.popitem(last=False)[1].nbytes

    def initial(self, key: str):
        """A copy of the initial state and the start's peak contact load [N] kept under
        ``key`` (:meth:`keep_initial`), or None."""
        with self._lock:
            kept = self._initial.get(key)
            return None if kept is None else (kept[0].copy(), kept[1])

    def keep_initial(self, key: str, y, q_peak: float) -> None:
        """Keep a start's initial state ``y`` and peak contact load ``q_peak`` [N] under
        ``key``, which hashes what they are computed from (the model, the profile at zero
        speed, the start time and the seed): the grid's speeds of one load and seed share
        them, and take them from here instead of solving their statics again (two
        quasi-static solves, about 0.04 s of a study case)."""
        with self._lock:
            self._initial[key] = (np.array(y, dtype=float), float(q_peak))
            self._initial.move_to_end(key)
            while len(self._initial) > self.keep:
                self._initial.popitem(last=False)

    def clear(self) -> None:
        with self._lock:
            self._starts.clear()
            self._initial.clear()
            self.hits = self.misses = self.shared = 0


#: This process's starts (:func:`rvcore.simulation.run.run_case` reads and fills it).
STARTS = StartStore()
