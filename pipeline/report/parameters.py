"""The report's parameters section, alone: one function, :func:`section_parameters`.

Every value comes from the sweep's stored configuration
(:class:`pipeline.schema.StoredConfiguration`) by its dataclass field, with its unit.
This module is the one place to switch to ``pipeline.schema.parameter_table`` once it
exists; until then the table is built here from the dataclasses.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from .context import Context, _ensemble_text, realizations, sensors
from .render import Bullets, Heading, Para, Table, _g, _kn

#: SI unit of each dataclass field of the stored configuration (rvcore.geometry,
#: rvcore.profile, rvcore.driver), by field name; fields not listed are dimensionless
#: or text.
_UNITS = {
    **dict.fromkeys(("bore", "outer_diameter", "width", "ball_diameter", "pitch_diameter",
                     "axial_position", "radial_clearance", "inner_diameter", "pocket_clearance",
                     "land_clearance", "shoulder_diameter", "damping_depth", "position"), "m"),
    "density": "kg/m³", "youngs_modulus": "Pa", "land_stiffness": "N/m^1.5", "attached_mass": "kg",
    "attached_inertia": "kg m²", **dict.fromkeys(("damping", "pocket_damping", "land_damping"), "N s/m"),
    **dict.fromkeys(("v_static", "v_dynamic"), "m/s"), "gravity": "m/s²", "contact_angle": "rad",
    **dict.fromkeys(("duration", "time_step", "start_time", "end_time", "times"), "s"),
    "output_rate": "Hz",
}

#: Bearing-file key paths (as ``Bearing.assumptions`` lists them) and the dataclass key
#: paths they set, for marking assumed values; the rest are spelled alike.
_FILE_TO_FIELD = {"inner_groove.arcs": "inner_arcs", "outer_groove.arcs": "outer_arcs",
                  "balls.count": "ball_count", "balls.diameter": "ball_diameter",
                  "cage.density": "cage.material.density", "cage.youngs_modulus": "cage.material.youngs_modulus",
                  "cage.poisson_ratio": "cage.material.poisson_ratio", "mounting": "gravity"}

#: Fields left out of the table: shown elsewhere (assumptions, warnings) or not results.
_HIDDEN = ("assumptions", "warnings", "extra")


def _field_path(file_key: str) -> str:
    """The dataclass key path a bearing-file key path sets."""
    for file_part, field_part in _FILE_TO_FIELD.items():
        if file_key == file_part or file_key.endswith("." + file_part):
            return file_key[: len(file_key) - len(file_part)] + field_part
    return file_key


def _leaves(obj, prefix: str):
    """``[(key path, field name, value)]`` of a dataclass, tuples of dataclasses indexed."""
    if dataclasses.is_dataclass(obj):
        out = []
        for f in dataclasses.fields(obj):
            if f.name not in _HIDDEN:
                out += _leaves(getattr(obj, f.name), f"{prefix}.{f.name}")
        return out
    if isinstance(obj, tuple) and obj and all(dataclasses.is_dataclass(v) for v in obj):
        return [leaf for i, v in enumerate(obj) for leaf in _leaves(v, f"{prefix}[{i}]")]
    return [(prefix, prefix.rsplit(".", 1)[-1], obj)]


def _show(value) -> str:
    """A value for the table: floats to 12 digits, long sequences shortened."""
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float):
        return f"{value:.12g}"
    if isinstance(value, (list, tuple)):
        items = [_show(v) for v in value[:4]] if len(value) > 8 else [_show(v) for v in value]
        more = f", … ({len(value)} values)" if len(value) > 8 else ""
        return "[" + ", ".join(items) + more + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_show(v)}" for k, v in value.items()) + "}"
    return str(value)


def _gravity_text(conf) -> str:
    """'gravity: on, g = (0, −9.807, 0) m/s² in the bearing frame (along −y …)'."""
    if not conf.settings.gravity:
        return "gravity: off (`solver.gravity = false`)"
    g = np.asarray(conf.bearing.gravity, dtype=np.float64)
    norm = float(np.linalg.norm(g))
    along = ""
    if norm > 0:
        k = int(np.argmax(np.abs(g)))
        if abs(g[k]) >= (1 - 1e-9) * norm:
            axis = "vertical" if k == 2 else "horizontal"
            along = f" (along {'−' if g[k] < 0 else '+'}{'xyz'[k]}: the bearing axis {axis})"
    shown = ", ".join(_g(v + 0.0, 4) for v in g)
    return f"gravity: on, g = ({shown}) m/s² in the bearing frame{along}"


def section_parameters(ctx: Context) -> list:
    """The blocks of the section 'Bearing, profile and parameters'."""
    attrs = ctx.sweep.attrs
    conf = ctx.configuration
    blocks = [Heading(2, "Bearing, profile and parameters")]
    items = [f"bearing: **{attrs.get('bearing', '') or 'not named'}**",
             f"profile: **{attrs.get('profile', '') or 'not named'}**"]
    if "axial_load" in ctx.metrics.coords:
        vals = np.atleast_1d(ctx.metrics["axial_load"].values)
        items.append("axial load: " + ", ".join(_kn(float(v)) for v in vals))
    if conf is not None:
        items.append(_gravity_text(conf))
    if realizations(ctx.metrics) is not None:
        items.append(f"ensemble: {_ensemble_text(ctx)} per grid point")
    sens = sensors(ctx.metrics)
    if sens:
        items.append(f"virtual displacement sensors: {len(sens)} (see below)")
    if attrs.get("configuration_hash"):
        items.append(f"configuration hash: `{attrs['configuration_hash']}`")
    if attrs.get("source"):
        items.append(f"source: {attrs['source']}")
    blocks.append(Bullets(items))
    if conf is None:
        blocks.append(Para(f"Configuration: {ctx.config_error}; the parameter table is left out."))
        return blocks
    assumptions = list(conf.bearing.assumptions)
    if assumptions:
        blocks.append(Para("**Assumed values** (the study does not give them; marked 'assumed' in the table below): "
                           + ", ".join(f"`{a}`" for a in assumptions) + "."))
    assumed = tuple(f"bearing.{_field_path(a)}" for a in assumptions)

    def is_assumed(path: str) -> bool:
        return any(path == a or path.startswith(a + ".") or path.startswith(a + "[") for a in assumed)

    leaves = (_leaves(conf.bearing, "bearing") + _leaves(conf.profile, "profile")
              + _leaves(conf.settings, "solver")
              + [leaf for i, s in enumerate(conf.sensors) for leaf in _leaves(s, f"sensors[{i}]")]
              + [(f"axes.{k}", k, v) for k, v in conf.axes.items()]
              + [(f"fixed.{k}", k, v) for k, v in conf.fixed.items()])
    rows = []
    for path, name, value in leaves:
        unit = _UNITS.get(name, "") if not isinstance(value, (str, bool)) else ""
        rows.append([f"`{path}`", _show(value) + (f" {unit}" if unit else ""),
                     "**assumed**" if is_assumed(path) else ""])
    blocks.append(Para("The sweep's resolved configuration, in SI units (axes and fixed values: speed in rad/s, "
                       "loads in N):"))
    blocks.append(Table(["key", "value", "assumption"], rows))
    return blocks
