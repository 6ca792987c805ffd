"""A sweep at scale, run as a user runs it: the parent's CPU a case, the combine, the resume, the report.

Usage::

    .venv/bin/python tools/scale_check.py tools/scale/scale-1000.toml --out /tmp/scale
    .venv/bin/python tools/scale_check.py tools/scale/scale-10000.toml --out /tmp/scale   # about 30 min on 2 cores

Four commands of the venv's ``rvsweep``, one after the other, each a process of its own:

1. ``rvsweep sweep FILE --out DIR --yes``, the cases computed. While they run, the sweep's own
   process's CPU time (all its threads: the local cluster's scheduler is among them; not the
   workers') is read with psutil twice a second, with the lines ``status.jsonl`` has then
   (one a finished case). The figure is the slope of a least-squares line through those
   readings from 5 % to 95 % of the cases [ms a case]: the parent's cost per case, without
   the start, the last cases' tail and the combine.
2. ``sweep.nc`` removed, the same command again: a resume that recomputes nothing, then the
   combine. Wall time [s] and peak RSS [MB]: the largest of the process and its reaped
   children (the combine's readers), as GNU ``time -v`` reports it (``os.wait4``).
3. The same command once more: the resume of a finished sweep [s].
4. ``rvsweep report DIR/NAME``: wall time [s] and peak RSS [MB].

The figures are printed one a line, with their units (``--json``: one JSON object). Nothing
here is part of the sweep: docs/performance.md ("Sweeps at scale") quotes what it printed.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import time
import tomllib
from pathlib import Path

#: How often the sweep's process and its status file are read while the cases run [s]
#: (often enough for a few hundred readings over a 1,000-case sweep, seldom enough to take
#: nothing measurable from the cases).
POLL = 0.5


def rvsweep() -> str:
    """The ``rvsweep`` beside this interpreter (the venv's), else the one on the PATH."""
    here = Path(sys.executable).with_name("rvsweep")
    return str(here) if here.exists() else (shutil.which("rvsweep") or "rvsweep")


def waited(process: subprocess.Popen) -> tuple[int, float]:
    """Wait for ``process``: its exit status and its peak RSS [MB] (the largest of the
    process and its reaped children, Linux's ``ru_maxrss`` in kB)."""
    _, status, usage = os.wait4(process.pid, 0)
    process.returncode = os.waitstatus_to_exitcode(status)
    return process.returncode, usage.ru_maxrss / 1024.0


class LineCount:
    """The complete lines of a growing file, read from where the last call stopped."""

    def __init__(self, path: Path):
        self.path, self.offset, self.lines = path, 0, 0

    def __call__(self) -> int:
        try:
            with open(self.path, "rb") as f:
                f.seek(self.offset)
                new = f.read()
        except FileNotFoundError:
            return self.lines
        end = new.rfind(b"\n") + 1      # a line being written counts once it is whole
        self.lines += new.count(b"\n", 0, end)
        self.offset += end
        return self.lines


def cpu_per_case(readings, n_cases: int) -> float:
    """The slope [s a case] of a least-squares line through ``readings`` (finished cases, CPU
    [s]) from 5 % to 95 % of ``n_cases``; NaN with fewer than two distinct counts there."""
    import numpy as np

    r = np.array([x for x in readings if 0.05 * n_cases <= x[0] <= 0.95 * n_cases], dtype=float).reshape(-1, 2)
    if np.unique(r[:, 0]).size < 2:
        return float("nan")
    # the slope from the centred readings: exactly 0 where the CPU did not move (a fit by
    # np.polyfit gave −5e-14 there, a negative cost)
    dx, dy = r[:, 0] - r[:, 0].mean(), r[:, 1] - r[:, 1].mean()
    return float(np.dot(dx, dy) / np.dot(dx, dx))


def run(command: list, log: Path) -> tuple[int, float, float]:
    """Run ``command`` with its output into ``log``: exit status, wall time [s], peak RSS [MB]."""
    t0 = time.perf_counter()
    with open(log, "wb") as out:
        p = subprocess.Popen(command, stdout=out, stderr=subprocess.STDOUT)
        rc, peak = waited(p)
    return rc, time.perf_counter() - t0, peak


def sweep_with_parent_cpu(command: list, status: Path, n_cases: int, log: Path) -> dict:
    """Run the sweep ``command`` of ``n_cases`` and read its process's CPU [s] against the
    finished cases (lines of ``status``) every :data:`POLL`: :func:`cpu_per_case` of them."""
    import psutil

    count = LineCount(status)
    readings = []
    t0 = time.perf_counter()
    with open(log, "wb") as out:
        p = subprocess.Popen(command, stdout=out, stderr=subprocess.STDOUT)
        proc = psutil.Process(p.pid)
        while p.poll() is None:
            try:
                t = proc.cpu_times()
            except psutil.Error:   # it ended between the two reads
                break
            readings.append((count(), t.user + t.system))
            time.sleep(POLL)
        rc = p.wait()
    used = [x for x in readings if 0.05 * n_cases <= x[0] <= 0.95 * n_cases]
    return {"rc": rc, "wall_s": time.perf_counter() - t0, "readings": len(used),
            "parent_cpu_ms_per_case": 1e3 * cpu_per_case(readings, n_cases)}


def positive_int(text: str) -> int:
    """``--workers``: a whole number of at least 1, else argparse's one-line error."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number of workers of at least 1")
    return value


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sweep", type=Path, help="the sweep file")
    ap.add_argument("--out", type=Path, required=True, help="the folder the sweep goes into (its NAME/ is replaced)")
    ap.add_argument("--workers", type=positive_int, default=None, help="local workers (default: one a core)")
    ap.add_argument("--json", action="store_true", help="one JSON object instead of lines")
    args = ap.parse_args(argv)
    from pipeline.errors import UserError
    from pipeline.schema import read_sweep_file

    try:   # the sweep's own check first, so that a bad file is one line, as rvsweep says it
        n_cases = len(read_sweep_file(args.sweep).cases)
    except UserError as exc:
        print(f"scale_check: {exc}", file=sys.stderr)
        return 2
    name = tomllib.loads(args.sweep.read_text(encoding="utf-8"))["name"]
    folder = args.out / name
    shutil.rmtree(folder, ignore_errors=True)
    args.out.mkdir(parents=True, exist_ok=True)
    sweep = [rvsweep(), "sweep", str(args.sweep), "--out", str(args.out), "--yes"]
    if args.workers:
        sweep += ["--workers", str(args.workers)]
    logs = args.out / f"{name}-scale-check"
    logs.mkdir(exist_ok=True)

    figures = {"sweep": str(args.sweep), "cases": n_cases}
    first = sweep_with_parent_cpu(sweep, folder / "status.jsonl", n_cases, logs / "1-sweep.log")
    if first["rc"] != 0:
        print(f"scale_check: the sweep failed (exit {first['rc']}): {logs / '1-sweep.log'}", file=sys.stderr)
        return 1
    figures.update(sweep_wall_s=first["wall_s"], parent_cpu_ms_per_case=first["parent_cpu_ms_per_case"],
                   readings=first["readings"])
    (folder / "sweep.nc").unlink(missing_ok=True)
    rc2, figures["resume_and_combine_s"], figures["resume_and_combine_peak_rss_mb"] = run(sweep, logs / "2-combine.log")
    rc3, figures["resume_finished_s"], _ = run(sweep, logs / "3-resume.log")
    rc4, figures["report_s"], figures["report_peak_rss_mb"] = run([rvsweep(), "report", str(folder)],
                                                                  logs / "4-report.log")
    failed = [f"{what} (exit {rc}, {log})" for what, rc, log in
              (("the combine", rc2, "2-combine.log"), ("the resume", rc3, "3-resume.log"),
               ("the report", rc4, "4-report.log")) if rc != 0]
    if failed:
        print(f"scale_check: failed: {', '.join(failed)} in {logs}", file=sys.stderr)
        return 1
    if args.json:
        print(json.dumps(figures, indent=1))
        return 0
    print(f"{args.sweep}: {figures['cases']} cases")
    print(f"  the sweep, cases and combine: {figures['sweep_wall_s']:.1f} s")
    print(f"  the sweep's own process, CPU a case while the cases ran: {figures['parent_cpu_ms_per_case']:.2f} ms "
          f"(a line through {figures['readings']} readings)")
    print(f"  resume with sweep.nc removed, then the combine: {figures['resume_and_combine_s']:.1f} s, "
          f"peak RSS {figures['resume_and_combine_peak_rss_mb']:.0f} MB")
    print(f"  resume of the finished sweep: {figures['resume_finished_s']:.1f} s")
    print(f"  report: {figures['report_s']:.1f} s, peak RSS {figures['report_peak_rss_mb']:.0f} MB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
