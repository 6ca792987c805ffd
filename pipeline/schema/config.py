"""Bearing and profile files: TOML in, validated ``rvcore`` dataclasses out (SI).

This module describes the formats and gathers the public names; the work is done in
:mod:`.tomlfile` (reading, key paths, overrides), :mod:`.fields` (the schema: every
key's kind, bounds, default, unit and doc), :mod:`.reader`, :mod:`.bearingfile` and
:mod:`.profilefile`.

Every quantity goes through :func:`pipeline.schema.units.parse_quantity`, so a file may write
``"23 mm"``, ``"15 deg"``, ``"250 N s/m"`` or a plain SI number. Every problem is a
:class:`pipeline.errors.ConfigError` naming the file, the dotted key, the value as
written and the reason: unknown keys (anywhere, nested too), missing required keys,
wrong units, non-positive sizes, impossible geometry (the checks of
:mod:`rvcore.bearing.checks`).

Key paths
---------
Keys are written as dotted paths with list indices, exactly as the TOML nests them:
``friction.mu_static``, ``rows[0].balls.count``,
``rows[0].inner_groove.arcs[1].contact_angle``. The same paths are used in error
messages, in the ``assumptions`` list and by :func:`apply_override`.

Bearing file
------------
::

    name = "rv-main-study"            # optional, defaults to the file's stem
    description = "..."               # optional
    source = "..."                    # optional: where the numbers come from
    allow_ball_overlap = false        # optional; true turns a ball overlap into a warning
    assumptions = ["rows[0].radial_clearance", ...]   # keys whose values are assumed

    [envelope]     bore, outer_diameter, width
    [material]     density, youngs_modulus, poisson_ratio        (rings and balls);
                   thermal_expansion = 11.5e-6 K^-1
                   -- or [ring_material] and [ball_material], each with the same keys
    [lubricant]    optional (docs/model.md §15.1): grade = 68 or viscosity_40 and
                   viscosity_100; density, pressure_viscosity, ep_additives, contamination,
                   ball_roughness, raceway_roughness, method = "grease";
                   kinematic_viscosity overrides the viscosity at the operating temperature
    [temperature]  optional: inner_ring = 40 degC, outer_ring = 40 degC, reference = 20 degC
                   (the clearance's); the rows' clearances are turned into operating ones
    [inner_ring]   shoulder_diameter; attached_mass = 0, attached_inertia = 0
    [contact]      damping, damping_depth, pocket_damping, land_damping
    [friction]     mu_static = 0.1, v_static = 0.1 m/s, mu_dynamic = 0.02,
                   v_dynamic = 1 m/s  (the study's values are the defaults)
    [[rows]]       pitch_diameter; axial_position = 0, radial_clearance = 0
    [rows.balls]   count, diameter
    [[rows.inner_groove.arcs]]   curvature_ratio, contact_angle   (1 or 2 per ring)
    [[rows.outer_groove.arcs]]   curvature_ratio, contact_angle
    [rows.cage]    inner_diameter, outer_diameter, width, pocket_clearance, guidance
                   ("outer-land" | "ball"), density, youngs_modulus, poisson_ratio,
                   land_clearance and land_stiffness (required when outer-land guided)

A pair of mirrored rows gives one ``[[rows]]`` entry (without ``axial_position``), the
design of both, and a ``[pair]`` table::

    [pair]         arrangement ("back-to-back" | "face-to-face" | "tandem"), row_spacing;
                   preload = 0 (a force) or preload_offset = 0 (the inner raceways' offset),
                   not both; a tandem pair takes neither

The loader builds the rows at ∓row_spacing/2 with ``rvcore.statics.preload.mirrored_rows`` and,
when preloaded, solves the offset with ``rvcore.statics.preload.apply_preload``.
``rows[].radial_clearance`` may be negative: an interference (a radially preloaded row).

Assumptions: TOML comments are not readable by ``tomllib``, so each assumed value
carries a ``# ASSUMPTION: why`` comment for the reader *and* its key path in the
top-level ``assumptions`` list for the program. Each listed path must exist in the file
(a path to a table marks everything in it). They end up in ``Bearing.assumptions``.

Ball overlap: :func:`rvcore.bearing.checks.geometry_problems` reports balls that do not fit on their pitch circle
with the numbers (docs/model.md §10). With ``allow_ball_overlap = true`` that message goes
into ``Bearing.warnings`` (which every output must repeat) instead of being an error.

Profile file
------------
::

    name = "study"
    description = "..."
    duration = "4.6 s"
    [radial_load]  time = ["0 s", ...], fraction = [0, 1, 1, 0], interpolation = "linear"
    [axial_load]   (the same; ``value = ["10 kN", ...]`` instead of ``fraction`` gives
                   absolute values)
    [speed]        (the same; absolute values in angular speed, e.g. "660 deg/s")
    [moment]       optional; the same, the tilting moment about the axis normal to the
                   radial load: fraction of the operating point's moment, or
                   value = ["0 N m", "2 kN m", ...]. Left out, it follows [radial_load]'s
                   table: M(t) = M0·F_r(t)/F_r0 (zero throughout when M0 = 0)
    [load_direction]  optional; time = [...], value = ["0 deg", "90 deg", ...]: an offset
                   of the radial load's direction (and of the moment's axis), added to the
                   operating point's load_angle. ``value`` only: a ``fraction`` is an
                   error. Left out, a constant 0 (the direction is load_angle)
    [phases]       startup = ["0.3 s", "0.8 s"], steady = [...], deceleration = [...]

A breakpoint of any channel the profile file gives is a sweep axis like any profile key
(``profile.load_direction.value[0] = ["0 deg", "30 deg"]``,
``profile.moment.fraction[1]``); the operating point's ``moment`` and ``load_angle`` are
sweep axes of their own.
"""
from __future__ import annotations

from .bearingfile import bearing_from_dict, load_bearing
from .profilefile import load_profile, profile_from_dict
from .tomlfile import (apply_override, format_key_path, lookup, parse_key_path, parse_set, parse_sets,
                       parse_value, read_toml, resolve_path)

__all__ = [
    "read_toml", "bearing_from_dict", "load_bearing", "profile_from_dict", "load_profile",
    "apply_override", "resolve_path", "parse_key_path", "format_key_path", "lookup",
    "parse_set", "parse_sets", "parse_value",
]
