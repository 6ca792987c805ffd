"""The repository's tools: ``tools/compile_bytecode.py`` (run by ``make venv``) and ``tools/scale_check.py``."""
import importlib.util
import json
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def cached(prefix: Path, module: str) -> bool:
    """Whether ``module``'s bytecode was written under the cache ``prefix``."""
    origin = Path(importlib.util.find_spec(module).origin).resolve()
    tag = sys.implementation.cache_tag
    return (prefix / origin.parent.relative_to("/") / f"{origin.stem}.{tag}.pyc").is_file()


MODULES = ("pipeline.cli", "pipeline.commands.sweep", "matplotlib.pyplot", "rvcore.simulation.run",
           "distributed.client", "xarray.backends.netCDF4_")


def compile_bytecode(prefix: Path, cache: Path) -> str:
    """Run the tool with the bytecode cache under ``prefix`` and the kept lists under
    ``cache``; what it printed."""
    env = dict(os.environ, PYTHONPYCACHEPREFIX=str(prefix), PYTHONDONTWRITEBYTECODE="1",
               RVSWEEP_CACHE_DIR=str(cache))
    run = subprocess.run([sys.executable, str(ROOT / "tools" / "compile_bytecode.py")], env=env,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    return run.stdout


def test_compile_bytecode_writes_each_groups_modules_then_from_the_kept_list(tmp_path):
    # One module of each of the two parallel groups, a command module and a dependency of
    # each: all written, whichever process imported them; then the same from the list the
    # first run kept, which imports nothing.
    first = compile_bytecode(tmp_path / "first", tmp_path / "cache")
    assert "loaded" in first
    kept = list((tmp_path / "cache" / "bytecode").glob("*.json"))
    assert len(kept) == 1
    for module in MODULES:
        assert cached(tmp_path / "first", module), module
    again = compile_bytecode(tmp_path / "again", tmp_path / "cache")
    assert "the list kept" in again
    for module in MODULES:
        assert cached(tmp_path / "again", module), module
    # every project source, listed or not; the list's files are all the first run's
    project = {p for p in (tmp_path / "again").rglob("*.pyc")
               if (ROOT / "pipeline").resolve().relative_to("/").as_posix() in p.as_posix()}
    assert len(project) == len(list((ROOT / "pipeline").rglob("*.py")))
    # the first run's bytecode of the venv's packages and the project's, all written again
    # (the standard library's, compiled with Python itself, is not listed)
    places = [Path(sysconfig.get_paths()["purelib"]).resolve(), ROOT.resolve()]

    def written(prefix):
        return {p.relative_to(prefix) for p in prefix.rglob("*.pyc")
                if any(p.is_relative_to(prefix / place.relative_to("/")) for place in places)}

    first_files = written(tmp_path / "first")
    assert len(first_files) > 1000
    # but for a few that an import tried and that failed (dateutil's Windows zones, urllib3's
    # SOCKS), compiled then but not loaded, so not listed
    assert len(first_files - written(tmp_path / "again")) <= 0.01 * len(first_files)


SMALL_SWEEP = """name = "tiny"
bearing = "bearings/reduced-test.toml"
profile = "profiles/short.toml"

[axes]
speed = ["120 deg/s", "660 deg/s"]
radial_load = ["20 kN", "40 kN"]

[fixed]
axial_load = "10 kN"
"""


def test_scale_check_runs_the_sweep_its_combine_resume_and_report(tmp_path):
    # The tool's four commands on a 2 x 2 sweep: every case computed once, the resume after
    # sweep.nc is removed and the resume of the finished sweep computing none, sweep.nc
    # written again by the combine, and the report; the figures it prints carry their units.
    sweep = tmp_path / "tiny.toml"
    sweep.write_text(SMALL_SWEEP, encoding="utf-8")
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, str(ROOT / "tools" / "scale_check.py"), str(sweep), "--out", str(out),
                          "--workers", "1", "--json"], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    figures = json.loads(run.stdout)
    assert figures["cases"] == 4
    logs = out / "tiny-scale-check"
    assert "(4 computed, 0 reused)" in (logs / "1-sweep.log").read_text()
    for log in ("2-combine.log", "3-resume.log"):
        assert "(0 computed, 4 reused)" in (logs / log).read_text()
    assert (out / "tiny" / "sweep.nc").is_file() and (out / "tiny" / "report" / "report.md").is_file()
    assert figures["resume_and_combine_peak_rss_mb"] > 50 and figures["report_peak_rss_mb"] > 50
    assert 0 < figures["resume_finished_s"] and 0 < figures["report_s"]
    # the parent's CPU a case: a slope where it read two counts of finished cases apart, NaN
    # (not a made-up figure) otherwise
    per_case = figures["parent_cpu_ms_per_case"]
    assert per_case >= 0 or (per_case != per_case and figures["readings"] < 8)


def test_scale_checks_cpu_a_case_is_the_slope_through_the_middle_readings():
    spec = importlib.util.spec_from_file_location("scale_check", ROOT / "tools" / "scale_check.py")
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    # 2 ms a case from 5 to 95 % of 100 cases; a start before and a combine after that the
    # line leaves out
    readings = [(0, 0.0), (0, 3.0)] + [(n, 3.0 + 0.002 * n) for n in range(5, 96, 3)] + [(100, 9.0)]
    assert abs(tool.cpu_per_case(readings, 100) - 0.002) < 1e-12
    assert tool.cpu_per_case([(0, 1.0), (50, 2.0), (100, 3.0)], 100) != tool.cpu_per_case([(0, 1.0), (50, 2.0), (100, 3.0)], 100)
    # a parent whose CPU did not move while the cases ran costs exactly nothing a case, not a
    # round-off below zero (the readings of a tiny sweep, 1.23 s of CPU at every count)
    assert tool.cpu_per_case([(n, 1.23) for n in range(5, 96, 7)], 100) == 0.0


def test_scale_checks_line_count_counts_only_whole_lines(tmp_path):
    spec = importlib.util.spec_from_file_location("scale_check", ROOT / "tools" / "scale_check.py")
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    path = tmp_path / "status.jsonl"
    count = tool.LineCount(path)
    assert count() == 0
    path.write_bytes(b'{"a": 1}\n{"b"')
    assert count() == 1
    with open(path, "ab") as f:
        f.write(b': 2}\n{"c": 3}\n')
    assert count() == 3


def test_scale_check_refuses_a_worker_count_below_one_before_any_work(tmp_path):
    run = subprocess.run([sys.executable, str(ROOT / "tools" / "scale_check.py"), str(tmp_path / "none.toml"),
                          "--out", str(tmp_path / "out"), "--workers", "0"], capture_output=True, text=True, timeout=60)
    assert run.returncode == 2
    lines = run.stderr.strip().splitlines()
    assert "--workers" in lines[-1] and "'0'" in lines[-1] and "Traceback" not in run.stderr
    assert not (tmp_path / "out").exists()
