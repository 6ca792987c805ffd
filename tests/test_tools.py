"""The repository's tools: ``tools/compile_bytecode.py`` (run by ``make venv``)."""
import importlib.util
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def cached(prefix: Path, module: str) -> bool:
    """Whether ``module``'s bytecode was written under the cache ``prefix``."""
    origin = Path(importlib.util.find_spec(module).origin).resolve()
    tag = sys.implementation.cache_tag
    return (prefix / origin.parent.relative_to("/") / f"{origin.stem}.{tag}.pyc").is_file()


def test_compile_bytecode_writes_each_groups_modules(tmp_path):
    # One module of each of the two parallel groups, a command module and a dependency of
    # each: all written, whichever process imported them.
    env = dict(os.environ, PYTHONPYCACHEPREFIX=str(tmp_path), PYTHONDONTWRITEBYTECODE="1")
    run = subprocess.run([sys.executable, str(ROOT / "tools" / "compile_bytecode.py")], env=env,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "bytecode written" in run.stdout
    for module in ("pipeline.cli", "pipeline.commands.sweep", "matplotlib.pyplot",
                   "rvcore.simulation.run", "distributed.client", "xarray.backends.netCDF4_"):
        assert cached(tmp_path, module), module
