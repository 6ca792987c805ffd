"""The report's figures stay readable: contrasting colours, legible legends, every trace
visible (issue rows 13), and one convention for the case-status flags (row 14)."""
from __future__ import annotations

import matplotlib
import pytest
import numpy as np
import xarray as xr

from pipeline.report.figures import trace_style
from pipeline.report.summary import COLUMNS, Summary, figure_designer


def test_traces_drawn_over_each_other_differ_in_style():
    """Cases with the same displacements (120 and 660 °/s at one load) are drawn over each
    other: each must differ from every other in dash pattern or width, the first widest."""
    styles = [trace_style(k, 4) for k in range(4)]
    assert len({(s["ls"], round(s["lw"], 3)) for s in styles}) == 4
    assert styles[0]["lw"] > styles[-1]["lw"] >= 1.0


def _luminance(colour) -> float:
    r, g, b, _ = matplotlib.colors.to_rgba(colour)
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


def test_designer_figure_lines_contrast_with_white_and_legends_are_legible(tmp_path, monkeypatch):
    """Two or three values per axis used to take the colour map's pale-yellow end: every
    line now has a luminance well below white's, and the legends are 8 pt or more."""
    captured = {}
    import pipeline.report.summary as summary

    def save(fig, path):
        captured["fig"] = fig
    monkeypatch.setattr(summary, "save_figure", save)
    col = next(c for c in COLUMNS if c.key == "safety")
    s = Summary(speeds=np.array([120.0, 390.0, 660.0]), loads=np.array([20e3, 30e3, 40e3]),
                values={col.key: np.arange(9.0).reshape(3, 3) + 2.0}, safety_phase=None, safety_time=None)
    figure_designer(s, col, tmp_path / "x.png", ens=False)
    for ax in captured["fig"].axes:
        for line in ax.get_lines():
            assert _luminance(line.get_color()) < 0.8, line.get_color()
        legend = ax.get_legend()
        assert all(t.get_fontsize() >= 8 for t in legend.get_texts())


def test_case_status_has_one_convention_in_sweep_and_metrics(smoke_run):
    """``case_status`` of sweep.nc and metrics.nc: the same flags, meanings and long name."""
    with xr.open_dataset(smoke_run.out / "sweep.nc") as sw, xr.open_dataset(smoke_run.out / "metrics.nc") as m:
        a, b = dict(sw["case_status"].attrs), dict(m["case_status"].attrs)
    assert a.keys() == b.keys()
    for key in a:
        assert np.array_equal(np.atleast_1d(a[key]), np.atleast_1d(b[key])), key


def test_status_json_names_the_units_of_its_values(smoke_run):
    """status.json gives each case's operating point in SI and says so: the speed in
    rad s-1 (the sweep coordinate of the NetCDF files is degree s-1), loads in N."""
    import json

    status = json.loads((smoke_run.out / "status.json").read_text())
    for entry in status.values():
        assert entry["units"]["speed"] == "rad s-1" and entry["units"]["radial_load"] == "N"
        assert entry["units"]["seconds"] == "s"


def test_figures_drawn_at_the_end_are_the_bytes_drawn_at_once(tmp_path):
    """Inside ``drawn_at_the_end`` nothing is drawn until the block ends; then every
    figure is written (half of them by a forked process where the platform forks), each
    the same PNG bytes as drawn at once. A block that fails draws nothing."""
    from pipeline.report import figures as F

    def figs():
        out = []
        for k in range(5):
            fig, axes = F.new_figure(1, 1, (3, 2))
            axes[0, 0].plot(np.arange(10.0), np.arange(10.0) ** (k + 1), label=f"x^{k + 1}")
            axes[0, 0].set_xlabel("time [s]")
            out.append(fig)
        return out

    for k, fig in enumerate(figs()):
        F.save_figure(fig, tmp_path / f"now{k}.png")
    with F.drawn_at_the_end():
        for k, fig in enumerate(figs()):
            F.save_figure(fig, tmp_path / f"end{k}.png")
            assert not (tmp_path / f"end{k}.png").exists()
    for k in range(5):
        assert (tmp_path / f"end{k}.png").read_bytes() == (tmp_path / f"now{k}.png").read_bytes()
    with pytest.raises(RuntimeError):
        with F.drawn_at_the_end():
            F.save_figure(figs()[0], tmp_path / "never.png")
            raise RuntimeError("a section failed")
    assert not (tmp_path / "never.png").exists()
    assert F._PENDING is None
