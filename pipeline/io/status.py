"""``status.json``: where each case of a sweep stands. One layout, one writer, one reader.

The layout (values SI, as in ``CaseSpec.point``)::

    {"<case id>": {"speed": 2.0944, "radial_load": 20000.0, "axial_load": 10000.0,
                   "<axis key>": ..., "state": "ok" | "failed" | "not_run",
                   "reason": "...", "traceback": "...",   (failed only)
                   "seconds": 12.3, "index": 0, "sha256": "<hex>",   (ok only)
                   "units": {"speed": "rad s-1", "radial_load": "N", ..., "seconds": "s"}}, ...}

``units`` names the UDUNITS unit of every operating-point value and of ``seconds``
(the wall time the case took). ``sha256`` is the SHA-256 of the case file as written
(:func:`pipeline.io.files.file_digest`); a resume compares it before reusing the file.

While a sweep runs, ``status.json`` is written whole twice (when the run starts and when
it ends, :func:`write_status`); in between each finished case appends one line to
``status.jsonl`` (:class:`StatusLog`), ``{"case": "<case id>", "status": {...}}`` with the
entry above, flushed and fsync'ed, so that the cost of recording a case does not grow
with the sweep. :func:`read_status` applies those lines over ``status.json`` (the last
line of a case wins; a torn last line, from a kill inside its write, is skipped), and
:func:`write_status` folds them in and removes the log: a killed sweep loses no
finished case's record.
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

from ..errors import UserError
from .files import write_error, write_text_atomic
from .netcdf import CASE_STATUS

STATUS_FILE = "status.json"
#: The append-only log of the cases finished since ``status.json`` was last written whole.
STATUS_LOG = "status.jsonl"


@dataclass
class CaseState:
    """Where one case stands: ``state`` is 'ok', 'failed' or 'not_run'."""

    case_id: str
    index: int
    point: dict
    state: str = "not_run"
    reason: str = ""
    traceback: str = ""
    seconds: float | None = None
    computed: bool = False
    sha256: str = ""

    def as_json(self) -> dict:
        d = dict(self.point)
        d["state"] = self.state
        if self.state == "failed":
            d["reason"] = self.reason
            d["traceback"] = self.traceback
        if self.seconds is not None:
            d["seconds"] = round(self.seconds, 3)
        d["index"] = self.index
        if self.state == "ok" and self.sha256:
            d["sha256"] = self.sha256
        d["units"] = _units(self.point)
        return d


def _units(point: dict) -> dict:
    """UDUNITS units of the operating-point values of ``point`` and of ``seconds``."""
    from ..schema.sweepaxes import OPERATING_POINT
    from ..schema.units import si_udunits

    out = {k: si_udunits(OPERATING_POINT[k]) for k in point if k in OPERATING_POINT}
    out["seconds"] = "s"
    return out


def write_status(folder, states: dict) -> Path:
    """Write ``status.json`` of a sweep folder atomically from ``{case id: CaseState}``,
    then remove ``status.jsonl`` (its lines are in ``states``): the compaction.

    ``states`` must hold every case the log records (the runner's do). Killed between
    the two steps, the log's lines are applied again over the new file by
    :func:`read_status`, which changes nothing."""
    folder = Path(folder)
    doc = {cid: st.as_json() for cid, st in states.items()}
    path = write_text_atomic(folder / STATUS_FILE, json.dumps(doc, indent=1) + "\n")
    (folder / STATUS_LOG).unlink(missing_ok=True)
    return path


class StatusLog:
    """``status.jsonl`` of a sweep folder, opened for appending: one line per finished case.

    Each :meth:`append` writes ``{"case": id, "status": entry}`` as one line, flushes it and
    fsyncs it [O(1) per case, whatever the number of cases]; :func:`write_status` later
    folds the lines into ``status.json``. Use it as a context manager, or :meth:`close` it.
    """

    def __init__(self, folder):
        self.path = Path(folder) / STATUS_LOG
        self._fh = None

    def append(self, state: CaseState) -> None:
        """Record ``state`` (durable when this returns)."""
        line = json.dumps({"case": state.case_id, "status": state.as_json()}) + "\n"
        try:
            if self._fh is None:
                self._fh = open(self.path, "a", encoding="utf-8")
            self._fh.write(line)
            self._fh.flush()
            os.fsync(self._fh.fileno())
        except OSError as exc:
            raise write_error(self.path, exc) from None

    def close(self) -> None:
        if self._fh is not None:
            fh, self._fh = self._fh, None
            fh.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _apply_log(data: dict, log: Path) -> dict:
    """``data`` with the lines of ``status.jsonl`` applied in order (the last line of a case
    wins); lines that do not parse (a torn last line) are skipped."""
    try:
        text = log.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return data
    for line in text.splitlines():
        try:
            record = json.loads(line)
        except ValueError:
            continue
        if isinstance(record, dict) and isinstance(record.get("case"), str) and isinstance(record.get("status"), dict):
            data[record["case"]] = record["status"]
    return data


def status_counts(status: dict) -> dict:
    """``{"ok": n, "failed": n, "not_run": n}`` of a :func:`read_status` mapping."""
    counts = {s: 0 for s in CASE_STATUS}
    for entry in status.values():
        counts[entry.get("state", "not_run")] += 1
    return counts


def read_status(out_dir) -> dict:
    """``status.json`` of a sweep folder ({} when there is none).

    It maps each case id to its values and state::

        {"<case id>": {"speed": 2.0944, "radial_load": 20000.0, "axial_load": 10000.0,
                       "<axis key>": ..., "state": "ok" | "failed" | "not_run",
                       "reason": "...", "traceback": "...",  (failed only)
                       "seconds": 12.3, "index": 0}, ...}

    Values are SI (speed in rad s-1, loads in N), as in ``CaseSpec.point``; ``seconds``
    is the case's wall time on its worker and ``index`` its position in the sweep. The
    lines of ``status.jsonl`` (cases finished since ``status.json`` was written whole) are
    applied over it.
    """
    path = Path(out_dir) / STATUS_FILE
    log = Path(out_dir) / STATUS_LOG
    data = {}
    if path.is_file():
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except json.JSONDecodeError as exc:
            raise UserError(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno})") from None
        if not isinstance(data, dict) or not all(isinstance(v, dict) for v in data.values()):
            raise UserError(f"{path}: expected an object mapping case ids to their state")
    if log.is_file():
        data = _apply_log(data, log)
    return data
