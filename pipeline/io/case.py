"""One case as labelled data: the only place where core arrays become an xarray.Dataset.

The case dataset (one per ``cases/<id>.nc``) is the public interface of a case:

- dimension ``elapsed_time`` [s], the output samples;
- dimension ``phase`` (int8 flags 0 startup, 1 steady, 2 deceleration);
- scalar coordinates ``speed`` [degree s-1], ``radial_load`` [N], ``axial_load`` [N];
- every output of the case, with the dimensions, units and long_name the output table
  gives it (:mod:`rvcore.output_table`; listed in docs/outputs.md): time series over
  ``elapsed_time``, phase metrics over ``phase``, scalars, the steady phase's spectra over
  ``frequency`` or ``kinematic``; a bearing of several rows adds ``row`` to its cage
  variables;
- with virtual sensors, dimension ``sensor`` (int8 flags named by the sensors) with
  coordinates ``sensor_position_x|y|z`` and ``sensor_direction_x|y|z``;
- scalar coordinate ``realization`` (the seed of the random start; −1 centred);
- global attributes: ``Conventions``, ``title``, ``source``, ``history``,
  ``references``, ``configuration`` (resolved TOML), ``configuration_hash``,
  ``git_commit`` (when known), ``bearing``, ``profile``, ``caveats`` (geometry caveats,
  '' when none) and ``assumptions``.
"""
from __future__ import annotations

import functools
import math
import subprocess
from pathlib import Path

import numpy as np
import xarray as xr

from rvcore.output_table import (DUTY_CYCLE as OUT_DUTY_CYCLE, OUTPUTS, PHASE as OUT_PHASE, SERIES as OUT_SERIES,
                            SPECTRUM as OUT_SPECTRUM, STEADY as OUT_STEADY, outputs_of, units_and_long_names)
from rvcore.profile import PHASES

from .. import __version__
from .files import history_line, write_atomic
from .netcdf import encoding_for

REFERENCES = (
    "Dynamic characteristics of the main bearing of rotary vector reducers under typical "
    "service conditions (multibody study; speed 120-660 deg/s, radial load 20-40 kN)."
)

#: name -> (units, long_name) of every time series (the output table, rvcore.output_table).
SERIES = units_and_long_names(OUT_SERIES, over="")
SERIES.update(units_and_long_names(OUT_SERIES, over="row"))
#: name -> (units, long_name) of every phase metric.
PHASE_METRICS = {**units_and_long_names(OUT_PHASE, over=""), **units_and_long_names(OUT_PHASE, over="row")}
#: Sensor variables: name -> (units, long_name); series over (elapsed_time, sensor).
SENSOR_SERIES = units_and_long_names(OUT_SERIES, over="sensor")
#: Sensor phase metrics over (phase, sensor).
SENSOR_METRICS = units_and_long_names(OUT_PHASE, over="sensor")
#: The steady phase's spectra (rvcore.recording.spectra): name -> (dims, units, long_name).
SPECTRA = {o.name: (o.dims, o.units, o.long_name) for o in outputs_of(OUT_SPECTRUM)}
#: Variables of a bearing with several rows of balls gain a trailing ``row`` dimension
#: (one value per row); a single row keeps the dims of :data:`VARIABLES`.
PER_ROW = tuple(o.name for o in OUTPUTS if o.over == "row")
#: Scalars at the steady operating point (no dims in a case file), from the statics there.
STEADY = units_and_long_names(OUT_STEADY)
#: Duty-cycle life scalars (no dims): ``CaseResult.life``.
DUTY_CYCLE = units_and_long_names(OUT_DUTY_CYCLE)

#: Every labelled variable: name -> (dims, units, long_name), in the table's order.
VARIABLES = {o.name: (o.dims, o.units, o.long_name) for o in OUTPUTS}


@functools.lru_cache(maxsize=1)
def git_commit() -> str:
    """The source tree's git commit, or '' outside a git checkout: asked of git once a
    process (13 ms of a worker's every case before), as the code it runs was read once."""
    here = Path(__file__).resolve().parent
    try:
        out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=here, capture_output=True,
                             text=True, timeout=5)
        return out.stdout.strip() if out.returncode == 0 else ""
    except (OSError, subprocess.SubprocessError):
        return ""


def phase_coordinate() -> xr.DataArray:
    """The int8 ``phase`` coordinate with CF flag attributes."""
    return xr.DataArray(
        np.arange(len(PHASES), dtype=np.int8), dims="phase",
        attrs={"long_name": "phase of the duty cycle",
               "flag_values": np.arange(len(PHASES), dtype=np.int8),
               "flag_meanings": " ".join(PHASES)},
    )


def kinematic_coordinate() -> xr.DataArray:
    """The int8 ``kinematic`` coordinate (which kinematic frequency) with CF flag attributes."""
    from rvcore.recording.spectra import KINEMATIC_NAMES

    return xr.DataArray(np.arange(len(KINEMATIC_NAMES), dtype=np.int8), dims="kinematic",
                        attrs={"long_name": "kinematic frequency of the bearing",
                               "flag_values": np.arange(len(KINEMATIC_NAMES), dtype=np.int8),
                               "flag_meanings": " ".join(KINEMATIC_NAMES)})


def sensor_coordinates(sensors) -> dict:
    """The ``sensor`` dimension's coordinates for a sequence of ``rvcore.simulation.settings.Sensor``."""
    names = [s.name.replace(" ", "_") for s in sensors]
    rows = np.array([s.as_row() for s in sensors], dtype=np.float64).reshape(-1, 6)
    coords = {"sensor": ("sensor", np.arange(len(names), dtype=np.int8),
                         {"long_name": "virtual displacement sensor",
                          "flag_values": np.arange(len(names), dtype=np.int8),
                          "flag_meanings": " ".join(names)})}
    for k, axis in enumerate("xyz"):
        coords[f"sensor_position_{axis}"] = ("sensor", rows[:, k], {
            "units": "m", "long_name": f"{axis} of the ring point each sensor reads (unloaded ring, bearing frame)"})
        coords[f"sensor_direction_{axis}"] = ("sensor", rows[:, 3 + k], {
            "units": "1", "long_name": f"{axis} component of each sensor's unit measuring direction"})
    return coords


def case_dataset(result, *, speed: float, radial_load: float, axial_load: float,
                 configuration: str = "", configuration_hash: str = "",
                 bearing_name: str = "", profile_name: str = "",
                 caveats=(), assumptions=(), history: str | None = None,
                 sensors=(), realization: int = -1) -> xr.Dataset:
    """Label one :class:`rvcore.simulation.run.CaseResult`.

    Parameters
    ----------
    result : rvcore.simulation.run.CaseResult
    speed : float
        Operating speed [rad s^-1]; stored as the ``speed`` coordinate in degree s-1.
    radial_load, axial_load : float
        Operating loads [N].
    configuration, configuration_hash : str
        The resolved configuration as TOML and its hash.
    caveats, assumptions : sequence of str
        Geometry caveats (e.g. accepted ball overlap) and assumed parameter names.
    sensors : sequence of rvcore.simulation.settings.Sensor
        The sensors the case was run with (labels the ``sensor`` dimension).
    realization : int
        Seed of the random start (−1: balls at their pocket centres).
    """
    t = np.asarray(result.time, dtype=np.float64)
    coords = {
        "elapsed_time": ("elapsed_time", t, {"units": "s", "long_name": "simulated time since the start of the cycle"}),
        "phase": phase_coordinate(),
        # rounded to 12 significant digits so that 120 deg/s reads back as 120, not 119.99999999999999
        "speed": ((), float(f"{np.degrees(speed):.12g}"), {"units": "degree s-1", "long_name": "steady inner-ring speed"}),
        "radial_load": ((), float(radial_load), {"units": "N", "long_name": "steady radial load"}),
        "axial_load": ((), float(axial_load), {"units": "N", "long_name": "steady axial load"}),
        "realization": ((), np.int32(realization), {
            "long_name": "seed of the random start of the balls in their pockets (-1: centred start)"}),
    }
    if len(sensors):
        coords.update(sensor_coordinates(sensors))
    spectra = result.spectra
    if "frequency" in spectra:
        coords["frequency"] = ("frequency", np.asarray(spectra["frequency"], dtype=np.float64),
                               {"units": "Hz", "long_name": "frequency of the steady phase's spectra"})
        coords["kinematic"] = kinematic_coordinate()
    data = {}
    for name, (dims, units, long_name) in VARIABLES.items():
        if not dims:
            source = {**result.steady, **result.life}
        elif name in SPECTRA:
            source = spectra
        else:
            source = result.series if dims[0] == "elapsed_time" else result.phase_metrics
        if name in source and ("sensor" not in dims or len(sensors)):
            values = np.asarray(source[name], dtype=np.float64)
            if name in PER_ROW and values.ndim == len(dims) + 1:
                dims = dims + ("row",)
                coords.setdefault("row", ("row", np.arange(values.shape[-1], dtype=np.int8),
                                          {"long_name": "row of balls (index in the bearing file's rows)",
                                           "units": "1"}))
            data[name] = (dims, values, {"units": units, "long_name": long_name})
    caveat_text = " | ".join(caveats)
    attrs = {
        "Conventions": "CF-1.8",
        "title": f"RV main-bearing dynamics: {bearing_name}, {profile_name} cycle, "
                 f"{math.degrees(speed):.6g} deg/s, {radial_load / 1e3:.6g} kN radial, {axial_load / 1e3:.6g} kN axial",
        "source": f"rv-bearing-sweep {__version__} (rvcore numba contact dynamics)",
        "history": history or history_line("rvcore.simulation.run.run_case"),
        "references": REFERENCES,
        "configuration": configuration,
        "configuration_hash": configuration_hash,
        "git_commit": git_commit(),
        "bearing": bearing_name,
        "profile": profile_name,
        "caveats": caveat_text,
        "assumptions": ", ".join(assumptions),
        # how the inner ring's tilts were held (docs/model.md §11): every result depends on it
        "inner_ring_tilt": str(result.info.get("inner_ring_tilt", "free")),
    }
    for key, value in result.info.items():
        if key == "inner_ring_tilt":
            continue
        if isinstance(value, (int, float, str, np.integer, np.floating)):
            attrs[f"solver_{key}"] = value
    return xr.Dataset(data_vars=data, coords=coords, attrs=attrs)


def write_case(ds: xr.Dataset, path) -> Path:
    """Write a case dataset to ``path`` atomically (:func:`pipeline.io.files.write_atomic`)."""
    return write_atomic(ds, path, encoding=encoding_for(ds))


def variables_markdown() -> str:
    """docs/outputs.md's "Variables of a case" tables, from the output table: one table a
    kind (series, phase metrics, steady scalars, duty cycle, spectra), one line a row with
    its name, units, dimensions and long_name (tests/pipeline/test_output_table.py holds
    the docs to it)."""
    from rvcore.output_table import DUTY_CYCLE, PHASE, SERIES, SPECTRUM, STEADY

    titles = ((SERIES, "Time series, sampled at the output rate"),
              (PHASE, "Phase metrics, reduced at every integrator step"),
              (STEADY, "Scalars at the steady operating point (the statics there)"),
              (DUTY_CYCLE, "The duty cycle's life"),
              (SPECTRUM, "The steady phase's spectra"))
    parts = []
    for kind, title in titles:
        parts += [f"### {title}", "", "| name | units | dimensions | long_name |", "|---|---|---|---|"]
        for o in outputs_of(kind):
            dims = ", ".join(o.dims + (("row",) if o.over == "row" else ())) or "(case)"
            parts.append(f"| `{o.name}` | `{o.units}` | {dims} | {o.long_name.replace('|', '/')} |")
        parts.append("")
    return "\n".join(parts)
