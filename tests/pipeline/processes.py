"""Helpers of the tests that start dask's own command-line processes (a scheduler and
workers as subprocesses): where the ``dask`` command is, and how to stop a process."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def dask_bin() -> Path:
    """The ``dask`` command of the project's venv, else the one beside this Python."""
    local = REPO / ".venv" / "bin" / "dask"
    return local if local.exists() else Path(sys.executable).parent / "dask"


def stop(proc: subprocess.Popen) -> None:
    """Terminate ``proc`` (kill it after 15 s) and reap it."""
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait(timeout=15)
