"""rvcore caches its numba kernels in a directory of their sources' own (rvcore._numba)."""
from __future__ import annotations

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
    first = numba_cache.cache_dir()
    assert first == numba_cache.cache_dir() and first.parent == pkg / "__pycache__"
    (pkg / "contact.py").write_text("x = 2\n")
    assert numba_cache.cache_dir() != first
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "elsewhere"))
    assert numba_cache.cache_dir().parent == tmp_path / "elsewhere"


def test_numba_caches_in_the_directory_of_these_sources():
    """rvcore sets numba's cache directory at import, before any kernel is defined."""
    assert numba.config.CACHE_DIR == str(numba_cache.cache_dir())


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
    assert before.name == numba_cache.cache_dir().name            # the same sources, the same key
    laws = copy / "contact" / "laws.py"
    assert laws.exists() and laws.parent != copy                 # a module of a sub-package
    laws.write_text(laws.read_text() + "\n# an edit\n")
    assert numba_cache.cache_dir().name != before.name
    laws.write_text(laws.read_text().removesuffix("\n# an edit\n"))
    assert numba_cache.cache_dir().name == before.name            # the key is of the contents
    (copy / "contact" / "laws.py").rename(copy / "contact" / "moved.py")
    assert numba_cache.cache_dir().name != before.name            # a move is a change too
