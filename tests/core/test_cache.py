"""rvcore caches its numba kernels in a directory of their sources' own (rvcore._numba)."""
from __future__ import annotations

from pathlib import Path

import numba

from rvcore import _numba as numba_cache


def test_each_version_of_the_sources_has_its_own_cache_directory(tmp_path, monkeypatch):
    """Same sources, same directory; any change of any module, another one. A process of
    the old sources can then never write into the new sources' cache."""
    pkg = tmp_path / "rvcore"
    pkg.mkdir()
    (pkg / "contact.py").write_text("x = 1\n")
    monkeypatch.setattr(numba_cache, "_PACKAGE", pkg)
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.delenv("RVSWEEP_CACHE_DIR", raising=False)
    first = numba_cache.cache_dir()
    assert first == numba_cache.cache_dir() and first.parent.parent == numba_cache.cache_root()
    (pkg / "contact.py").write_text("x = 2\n")
    assert numba_cache.cache_dir() != first
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "elsewhere"))
    assert numba_cache.cache_dir().parent.parent == tmp_path / "elsewhere"


def test_numba_caches_in_the_directory_of_these_sources():
    """rvcore sets numba's cache directory at import, before any kernel is defined."""
    assert numba.config.CACHE_DIR == str(numba_cache.cache_dir()) == str(numba_cache._ACTIVE)


def test_an_edit_in_a_sub_package_of_a_scratch_copy_changes_the_cache_directory(tmp_path, monkeypatch):
    """The key covers every source under rvcore/, recursively: an edit to a module of a
    sub-package (here the contact laws of a copy of the real sources) gives another
    cache directory, so a kernel that inlines it is compiled again, never reused stale."""
    import shutil

    real = numba_cache._PACKAGE
    copy = tmp_path / "rvcore"
    shutil.copytree(real, copy, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(numba_cache, "_PACKAGE", copy)
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    before = numba_cache.cache_dir()
    assert before == numba_cache.cache_dir()            # the same sources, the same key
    laws = copy / "contact" / "laws.py"
    assert laws.exists() and laws.parent != copy                 # a module of a sub-package
    laws.write_text(laws.read_text() + "\n# an edit\n")
    assert numba_cache.cache_dir() != before
    laws.write_text(laws.read_text().removesuffix("\n# an edit\n"))
    assert numba_cache.cache_dir() == before            # the key is of the contents
    (copy / "contact" / "laws.py").rename(copy / "contact" / "moved.py")
    assert numba_cache.cache_dir() != before            # a move is a change too


def test_the_cache_directory_names_no_install_path(tmp_path, monkeypatch):
    """Two installs of the same sources at different paths get the same directory (under
    the user-wide root, keyed by the sources and the CPU), not one beside each."""
    import shutil

    real = numba_cache._PACKAGE
    monkeypatch.setenv("RVSWEEP_CACHE_DIR", str(tmp_path / "root"))
    dirs = []
    for name in ("a", "b/deeper"):
        copy = tmp_path / name / "rvcore"
        shutil.copytree(real, copy, ignore=shutil.ignore_patterns("__pycache__"))
        monkeypatch.setattr(numba_cache, "_PACKAGE", copy)
        dirs.append(numba_cache.cache_dir())
    assert dirs[0] == dirs[1]
    assert dirs[0].parent.parent == tmp_path / "root"
    assert dirs[0].name == numba_cache.cpu_key() and dirs[0].parent.name.startswith("rvcore-")


def test_the_cache_root_follows_the_environment(tmp_path, monkeypatch):
    for var in ("RVSWEEP_CACHE_DIR", "NUMBA_CACHE_DIR", "XDG_CACHE_HOME"):
        monkeypatch.delenv(var, raising=False)
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert numba_cache.cache_root() == tmp_path / "home" / ".cache" / "rv-bearing-sweep"
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert numba_cache.cache_root() == tmp_path / "xdg" / "rv-bearing-sweep"
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "numba"))
    assert numba_cache.cache_root() == tmp_path / "numba"
    monkeypatch.setenv("RVSWEEP_CACHE_DIR", str(tmp_path / "ours"))
    assert numba_cache.cache_root() == tmp_path / "ours"


def test_the_cpu_key_follows_the_target_numba_compiles_for(monkeypatch):
    """Another CPU name or feature set (what numba compiles for) is another directory."""
    import numba

    here = numba_cache.cpu_key()
    monkeypatch.setattr(numba.config, "CPU_NAME", "generic")
    assert numba_cache.cpu_key() != here and numba_cache.cpu_key().startswith("generic-")
    other = numba_cache.cpu_key()
    monkeypatch.setattr(numba.config, "CPU_FEATURES", "+sse2")
    assert numba_cache.cpu_key() != other


def test_rvcore_kernels_are_found_by_the_path_free_locator():
    """numba's locator for an rvcore kernel is ours, in the active directory, and names a
    sub-package, not a hash of the file's absolute path."""
    from rvcore.integrate import imex

    path = Path(imex.imex_step._cache._cache_path)
    assert path == Path(numba_cache._ACTIVE) / "integrate"
    assert type(imex.imex_step._cache._impl.locator).__name__ == "SourceKeyedLocator"
