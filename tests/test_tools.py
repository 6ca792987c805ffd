"""The repository's tools: ``tools/compile_bytecode.py`` (run by ``make venv``)."""
import importlib.util
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
