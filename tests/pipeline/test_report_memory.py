"""The report's memory does not grow with what one read of ``sweep.nc`` asks for (issue 42).

HDF5 builds a map of every chunk one read touches, and ``sweep.nc`` has one chunk per
case: a read of a whole per-case variable of 10,000 cases cost about 60 MB of resident
memory. ``open_results(lazy=True)`` reads the per-case values a slab of at most
``SLAB_ELEMENTS`` elements at a time. These tests count the elements each read asks the
NetCDF backend for (no timings, no resident-memory figures) and check that the values are
those of an eager read.
"""
from __future__ import annotations

import numpy as np
import pytest
from xarray.backends.netCDF4_ import NetCDF4ArrayWrapper

from pipeline.analysis import metrics as M
from pipeline.analysis import open_results
from tests.pipeline.test_report import synthetic_sweep


@pytest.mark.parametrize("shape, limit", [((6, 5, 3), 12), ((6, 5, 3), 2), ((6, 5, 3), 1000), ((7,), 3),
                                          ((2, 50), 10), ((4, 3, 2, 5), 7), ((), 4)])
def test_slabs_cover_every_element_once_within_the_limit(shape, limit):
    seen = np.zeros(shape, dtype=int)
    slabs = M.read_slabs(shape, limit)
    for key in slabs:
        seen[key] += 1
        n = int(np.prod([s.stop - s.start for s in key]))
        # at most `limit` elements, or one element of the leading dims when a row alone is larger
        assert n <= max(limit, shape[-1] if shape else 1)
    assert (seen == 1).all()
    if shape and int(np.prod(shape)) > limit:
        assert len(slabs) > 1


def _reads(monkeypatch):
    """Record the number of elements each read of the netCDF4 backend returns."""
    sizes = []
    original = NetCDF4ArrayWrapper._getitem

    def counting(self, key):
        out = original(self, key)
        sizes.append((self.variable_name, int(np.size(out))))
        return out

    monkeypatch.setattr(NetCDF4ArrayWrapper, "_getitem", counting)
    return sizes


@pytest.mark.parametrize("speeds", [(120.0, 390.0, 660.0), (120.0, 210.0, 300.0, 390.0, 480.0, 570.0, 660.0)])
def test_lazy_open_reads_per_case_values_in_bounded_slabs(tmp_path, monkeypatch, speeds):
    d = synthetic_sweep(tmp_path / "s", speeds_deg=speeds, statics=False)
    eager = open_results(d)
    limit = 4
    monkeypatch.setattr(M, "SLAB_ELEMENTS", limit)
    sizes = _reads(monkeypatch)
    lazy = open_results(d, lazy=True)
    try:
        per_case = [n for n, v in eager.data_vars.items()
                    if "speed" in v.dims and not {"elapsed_time", "frequency", "kinematic"} & set(v.dims)]
        series = [n for n, v in eager.data_vars.items() if "elapsed_time" in v.dims]
        assert per_case and series
        read = {name for name, _ in sizes}
        assert set(per_case) <= read                   # each read through the backend, counted
        assert max(n for name, n in sizes if name in per_case) <= limit   # whatever the grid's size
        assert any(eager[n].size > limit for n in per_case)
        for n in per_case:
            assert lazy[n].variable._in_memory
            assert lazy[n].dtype == eager[n].dtype
            assert lazy[n].identical(eager[n]), n
        for n in series:
            assert not lazy[n].variable._in_memory      # the time series stay on disk
    finally:
        lazy.close()
