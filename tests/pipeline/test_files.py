"""How the files of a sweep behave: their mode, a damaged case file, a busy folder."""
from __future__ import annotations

import os
import stat

import numpy as np
import pytest
import xarray as xr

from pipeline.io.files import write_atomic, write_text_atomic


@pytest.fixture
def umask():
    """Set the umask for one test and restore it after."""
    old = os.umask(0o022)
    os.umask(old)
    yield lambda mask: os.umask(mask)
    os.umask(old)


@pytest.mark.parametrize("mask", [0o022, 0o027, 0o002])
def test_written_files_take_the_umask_mode(tmp_path, umask, mask):
    umask(mask)
    nc = write_atomic(xr.Dataset({"x": ("n", np.zeros(2))}), tmp_path / "a.nc", encoding={})
    txt = write_text_atomic(tmp_path / "a.json", "{}")
    expected = 0o666 & ~mask
    assert stat.S_IMODE(nc.stat().st_mode) == expected
    assert stat.S_IMODE(txt.stat().st_mode) == expected
