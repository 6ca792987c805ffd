"""rvcore drops its numba cache when any of its sources changed (rvcore._cache)."""
from __future__ import annotations

from rvcore import _cache


def test_stale_cache_files_are_dropped_and_current_ones_kept(tmp_path, monkeypatch):
    pkg = tmp_path / "rvcore"
    (pkg / "__pycache__").mkdir(parents=True)
    (pkg / "contact.py").write_text("x = 1\n")
    monkeypatch.setattr(_cache, "_PACKAGE", pkg)
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    kernel = pkg / "__pycache__" / "integrator.integrate-1.py311.nbi"
    kernel.write_text("cached")
    _cache.drop_stale_numba_cache()          # no stamp yet: the cache's sources are unknown
    assert not kernel.exists()
    kernel.write_text("cached")
    _cache.drop_stale_numba_cache()          # same sources: kept
    assert kernel.exists()
    (pkg / "contact.py").write_text("x = 2\n")
    _cache.drop_stale_numba_cache()          # another module changed: dropped
    assert not kernel.exists()
