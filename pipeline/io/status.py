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
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from ..errors import UserError
from .files import write_text_atomic
from .netcdf import CASE_STATUS

STATUS_FILE = "status.json"


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
    """Write ``status.json`` of a sweep folder atomically from ``{case id: CaseState}``."""
    doc = {cid: st.as_json() for cid, st in states.items()}
    return write_text_atomic(Path(folder) / STATUS_FILE, json.dumps(doc, indent=1) + "\n")


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
    is the case's wall time on its worker and ``index`` its position in the sweep.
    """
    path = Path(out_dir) / STATUS_FILE
    if not path.is_file():
        return {}
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise UserError(f"{path}: not valid JSON ({exc.msg} at line {exc.lineno})") from None
    if not isinstance(data, dict) or not all(isinstance(v, dict) for v in data.values()):
        raise UserError(f"{path}: expected an object mapping case ids to their state")
    return data
