"""One case as labelled data: the only place where core arrays become an xarray.Dataset.

The case dataset (one per ``cases/<id>.nc``) is the public interface of a case:

- dimension ``elapsed_time`` [s], the output samples;
- dimension ``phase`` (int8 flags 0 startup, 1 steady, 2 deceleration);
- scalar coordinates ``speed`` [degree s-1], ``radial_load`` [N], ``axial_load`` [N];
- time series, over ``elapsed_time`` (names of pipeline.md): ``radial_displacement``,
  ``axial_displacement``, ``inner_ring_x|y|z``, ``inner_ring_tilt_x|y``,
  ``applied_radial_load``, ``applied_axial_load``, ``inner_ring_speed``, ``cage_speed``,
  ``max_inner_contact_load``, ``max_outer_contact_load``, ``loaded_ball_count``,
  ``max_contact_pressure``, ``applied_moment``, ``load_direction``, and the designer's
  outputs ``inner_ring_drive_torque``, ``friction_power``,
  ``max_pocket_force``, ``cage_land_force``, ``max_race_sliding_speed``, ``max_race_pv``,
  ``min_contact_angle``, ``max_contact_angle``, ``static_safety_factor``;
- phase metrics, over ``phase``, accumulated at every integrator step:
  ``radial_displacement_range|mean|std|min_time|max_time|range_at_edge`` and the same for
  ``axial_displacement``, ``cage_speed_mean``, ``inner_ring_speed_mean``,
  ``epicyclic_cage_speed``, ``cage_slip``, ``cage_slip_nominal``,
  ``peak_contact_pressure``, the windows ``phase_start``/``phase_end``, the designer's
  ``inner_ring_drive_torque_peak|mean``, ``friction_power_mean``, ``friction_energy``,
  ``max_pocket_force_peak``, ``cage_land_force_peak``, ``max_race_sliding_speed_peak``,
  ``max_race_pv_peak``, ``contact_angle_min|max``, ``static_safety_factor_min|min_time``
  and, with rvcore.life, ``fatigue_damage``;
- duty-cycle scalars (with rvcore.life): ``rating_life_L10r``, ``rating_life_cycles``,
  ``fatigue_damage_cycle``;
- with virtual sensors, dimension ``sensor`` (int8 flags named by the sensors) with
  coordinates ``sensor_position_x|y|z`` and ``sensor_direction_x|y|z``:
  ``sensor_displacement`` over ``(elapsed_time, sensor)`` and
  ``sensor_displacement_range|mean|std|min_time|max_time|range_at_edge`` over
  ``(phase, sensor)``;
- scalar coordinate ``realization`` (the seed of the random start; −1 centred);
- global attributes: ``Conventions``, ``title``, ``source``, ``history``,
  ``references``, ``configuration`` (resolved TOML), ``configuration_hash``,
  ``git_commit`` (when known), ``bearing``, ``profile``, ``caveats`` (geometry caveats,
  '' when none) and ``assumptions``.
"""
from __future__ import annotations

import math
import subprocess
from pathlib import Path

import numpy as np
import xarray as xr

from rvcore.driver import DUTY_CYCLE_OUTPUTS
from rvcore.operating import STEADY_OUTPUTS
from rvcore.profile import PHASES

from .. import __version__
from .files import history_line, write_atomic
from .netcdf import encoding_for

REFERENCES = (
    "Dynamic characteristics of the main bearing of rotary vector reducers under typical "
    "service conditions (multibody study; speed 120-660 deg/s, radial load 20-40 kN)."
)

#: name -> (units, long_name) of every time series.
SERIES = {
    "radial_displacement": ("m", "inner-ring displacement along the radial-load direction (delta_r)"),
    "axial_displacement": ("m", "inner-ring displacement along the axial-load direction (delta_a)"),
    "inner_ring_x": ("m", "inner-ring centre x"),
    "inner_ring_y": ("m", "inner-ring centre y"),
    "inner_ring_z": ("m", "inner-ring centre z (axial)"),
    "inner_ring_tilt_x": ("rad", "inner-ring tilt about x"),
    "inner_ring_tilt_y": ("rad", "inner-ring tilt about y"),
    "applied_radial_load": ("N", "radial load applied by the profile"),
    "applied_axial_load": ("N", "axial load applied by the profile"),
    "inner_ring_speed": ("rad s-1", "prescribed inner-ring angular speed"),
    "cage_speed": ("rad s-1", "cage angular speed"),
    "max_inner_contact_load": ("N", "largest ball to inner-race normal force"),
    "max_outer_contact_load": ("N", "largest ball to outer-race normal force"),
    "loaded_ball_count": ("1", "number of balls carrying more than 1 N on both the inner and the outer race "
                               "(rvcore.contact.LOADED_BALL_LOAD)"),
    "max_contact_pressure": ("Pa", "largest Hertz contact pressure"),
    "applied_moment": ("N m", "tilting moment applied by the profile, about the axis normal to the radial load"),
    "load_direction": ("rad", "direction of the radial load applied by the profile, from +x"),
    "inner_ring_drive_torque": ("N m", "moment about the inner ring's spin axis that the prescribed spin needs: "
                                       "polar inertia times the prescribed angular acceleration minus the "
                                       "contact forces' moment on the ring about that axis"),
    "friction_power": ("W", "power dissipated by friction at every ball-race, ball-pocket and cage-land "
                            "contact, summed (sum of |F_t . v_slip|)"),
    "max_pocket_force": ("N", "largest ball-pocket normal force (all rows)"),
    "cage_land_force": ("N", "cage-land normal force (the largest over rows)"),
    "max_race_sliding_speed": ("m s-1", "largest sliding speed at a loaded ball-race contact"),
    "max_race_pv": ("Pa m s-1", "largest product of the Hertz peak pressure and the sliding speed at a "
                                "ball-race contact"),
    "min_contact_angle": ("rad", "smallest contact angle of the loaded ball-race contacts, from the bearing's "
                                 "radial plane (NaN when none is loaded)"),
    "max_contact_angle": ("rad", "largest contact angle of the loaded ball-race contacts, from the bearing's "
                                 "radial plane (NaN when none is loaded)"),
    "static_safety_factor": ("1", "ISO 76 static safety factor s0 = C0/P0 from the Hertz pressure: "
                                  "(4200 MPa / largest ball-race Hertz pressure)^3 (radial ball bearings; "
                                  "NaN when no ball-race contact is loaded)"),
    "tilt_reaction_moment_x": ("N m", "moment about x that the support applies to hold the inner ring's tilt "
                                      "at 0 (inner_ring.tilt = held; 0 when the tilt is free)"),
    "tilt_reaction_moment_y": ("N m", "moment about y that the support applies to hold the inner ring's tilt "
                                      "at 0 (inner_ring.tilt = held; 0 when the tilt is free)"),
}

def _extreme_metrics(name: str, what: str) -> dict:
    """The six per-phase metrics of one displacement signal (units, long_name)."""
    return {
        f"{name}_range": ("m", f"variation range (max - min) of {what} over the phase"),
        f"{name}_mean": ("m", f"time mean of {what} over the phase"),
        f"{name}_std": ("m", f"standard deviation of {what} over the phase"),
        f"{name}_min_time": ("s", f"elapsed time at which {what} is smallest in the phase"),
        f"{name}_max_time": ("s", f"elapsed time at which {what} is largest in the phase"),
        f"{name}_range_at_edge": ("1", f"1 where an extreme of {what} lies within one output interval of "
                                       "the phase window's edge (the range may be cut off by the window)"),
    }


#: name -> (units, long_name) of every phase metric.
PHASE_METRICS = {
    **_extreme_metrics("radial_displacement", "delta_r at the ring centre"),
    **_extreme_metrics("axial_displacement", "delta_a at the ring centre"),
    "cage_speed_mean": ("rad s-1", "time mean of the cage speed over the phase"),
    "inner_ring_speed_mean": ("rad s-1", "time mean of the inner-ring speed over the phase"),
    "epicyclic_cage_speed": ("rad s-1", "time mean of the epicyclic cage speed 0.5*(1 - D*cos(alpha)/d_m)*omega "
                                        "at the loaded balls' actual mean cos(alpha)"),
    "cage_slip": ("1", "1 - mean cage speed / epicyclic cage speed at the balls' actual contact angles "
                       "(0: rolling without slip)"),
    "cage_slip_nominal": ("1", "1 - mean cage speed / epicyclic cage speed at the nominal contact angle"),
    "peak_contact_pressure": ("Pa", "largest Hertz contact pressure over the phase"),
    "inner_ring_drive_torque_peak": ("N m", "largest magnitude over the phase of the inner-ring drive torque band-limited to 1 kHz"),
    "inner_ring_drive_torque_mean": ("N m", "time mean of the inner-ring drive torque over the phase"),
    "friction_power_mean": ("W", "time mean of the friction power over the phase"),
    "friction_energy": ("J", "energy dissipated by friction over the phase (integral of the friction power)"),
    "max_pocket_force_peak": ("N", "largest ball-pocket normal force over the phase"),
    "cage_land_force_peak": ("N", "largest cage-land normal force over the phase"),
    "max_race_sliding_speed_peak": ("m s-1", "largest ball-race sliding speed over the phase"),
    "max_race_pv_peak": ("Pa m s-1", "largest ball-race Hertz peak pressure times sliding speed over the phase"),
    "contact_angle_min": ("rad", "smallest contact angle of a loaded ball-race contact over the phase"),
    "contact_angle_max": ("rad", "largest contact angle of a loaded ball-race contact over the phase"),
    "static_safety_factor_min": ("1", "smallest ISO 76 static safety factor s0 = (4200 MPa / peak ball-race "
                                      "Hertz pressure)^3 over the phase"),
    "static_safety_factor_min_time": ("s", "elapsed time at which the static safety factor is smallest in the phase"),
    "tilt_reaction_moment_mean": ("N m", "time mean over the phase of the magnitude of the moment that holds "
                                         "the inner ring's tilt at 0 (0 when the tilt is free)"),
    "tilt_reaction_moment_peak": ("N m", "largest magnitude over the phase of the moment that holds the inner "
                                         "ring's tilt at 0 (0 when the tilt is free)"),
    "fatigue_damage": ("1", "Palmgren-Miner fatigue damage accumulated in the phase per cycle of the profile "
                            "(ISO/TS 16281 contact loads at every integrator step)"),
    "phase_start": ("s", "start of the phase window"),
    "phase_end": ("s", "end of the phase window"),
}

#: Sensor variables: name -> (units, long_name); series over (elapsed_time, sensor).
SENSOR_SERIES = {
    "sensor_displacement": ("m", "inner-ring displacement read by each virtual sensor along its direction"),
}
#: Sensor phase metrics over (phase, sensor).
SENSOR_METRICS = _extreme_metrics("sensor_displacement", "the sensor reading")

#: The steady phase's spectra (rvcore.spectra): name -> (dims, units, long_name).
SPECTRA = {
    "kinematic_frequency": (("kinematic",), "Hz", "the bearing's kinematic frequencies at the steady speed (rolling "
                                                  "without slip at the nominal contact angle): shaft, cage, outer and "
                                                  "inner ball pass, ball spin, and twice each"),
    **{f"{n}_spectrum": (("frequency",), "m", f"single-sided amplitude spectrum of {w} over the steady phase "
                                              "(mean removed, Hann window; a sinusoid of amplitude A reads A)")
       for n, w in (("radial_displacement", "delta_r"), ("axial_displacement", "delta_a"))},
    **{f"{n}_kinematic_amplitude": (("kinematic",), "m", f"largest spectral amplitude of {w} within one bin of each "
                                                         "kinematic frequency, steady phase")
       for n, w in (("radial_displacement", "delta_r"), ("axial_displacement", "delta_a"))},
    "sensor_displacement_spectrum": (("frequency", "sensor"), "m", "single-sided amplitude spectrum of each sensor's "
                                                                  "reading over the steady phase (mean removed, Hann "
                                                                  "window; a sinusoid of amplitude A reads A)"),
    "sensor_displacement_kinematic_amplitude": (("kinematic", "sensor"), "m", "largest spectral amplitude of each "
                                                                             "sensor's reading within one bin of each "
                                                                             "kinematic frequency, steady phase"),
}

#: Cage variables of a bearing with several rows of balls gain a trailing ``row``
#: dimension (one value per row); a single row keeps the dims of :data:`VARIABLES`.
PER_ROW = ("cage_speed", "cage_speed_mean", "epicyclic_cage_speed", "cage_slip", "cage_slip_nominal")

#: Scalars at the steady operating point (no dims in a case file), from the statics there.
STEADY = dict(STEADY_OUTPUTS)
#: Duty-cycle life scalars (no dims): ``CaseResult.life``, present when rvcore.life is.
DUTY_CYCLE = dict(DUTY_CYCLE_OUTPUTS)

#: Every labelled variable: name -> (dims, units, long_name).
VARIABLES = {
    **{k: ((), *v) for k, v in STEADY.items()},
    **{k: ((), *v) for k, v in DUTY_CYCLE.items()},
    **{k: (("elapsed_time",), *v) for k, v in SERIES.items()},
    **{k: (("elapsed_time", "sensor"), *v) for k, v in SENSOR_SERIES.items()},
    **{k: (("phase",), *v) for k, v in PHASE_METRICS.items()},
    **{k: (("phase", "sensor"), *v) for k, v in SENSOR_METRICS.items()},
    **SPECTRA,
}


def git_commit() -> str:
    """The source tree's git commit, or '' outside a git checkout."""
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
    from rvcore.spectra import KINEMATIC_NAMES

    return xr.DataArray(np.arange(len(KINEMATIC_NAMES), dtype=np.int8), dims="kinematic",
                        attrs={"long_name": "kinematic frequency of the bearing",
                               "flag_values": np.arange(len(KINEMATIC_NAMES), dtype=np.int8),
                               "flag_meanings": " ".join(KINEMATIC_NAMES)})


def sensor_coordinates(sensors) -> dict:
    """The ``sensor`` dimension's coordinates for a sequence of ``rvcore.driver.Sensor``."""
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
    """Label one :class:`rvcore.driver.CaseResult`.

    Parameters
    ----------
    result : rvcore.driver.CaseResult
    speed : float
        Operating speed [rad s^-1]; stored as the ``speed`` coordinate in degree s-1.
    radial_load, axial_load : float
        Operating loads [N].
    configuration, configuration_hash : str
        The resolved configuration as TOML and its hash.
    caveats, assumptions : sequence of str
        Geometry caveats (e.g. accepted ball overlap) and assumed parameter names.
    sensors : sequence of rvcore.driver.Sensor
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
        "history": history or history_line("rvcore.driver.run_case"),
        "references": REFERENCES,
        "configuration": configuration,
        "configuration_hash": configuration_hash,
        "git_commit": git_commit(),
        "bearing": bearing_name,
        "profile": profile_name,
        "caveats": caveat_text,
        "assumptions": ", ".join(assumptions),
        # how the inner ring's tilts were held (model.md §11): every result depends on it
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
