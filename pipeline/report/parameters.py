"""The report's appendix of the configuration, alone: one function, :func:`section_parameters`.

Every value comes from the sweep's stored configuration
(:class:`pipeline.schema.StoredConfiguration`), laid out by the one input schema
(:func:`pipeline.schema.parameter_table`): file key paths, values in the schema's
engineering units written as a reader writes them (120 °/s, 1 µm; never the SI the core
computes in), each field's doc, and whether the bearing file marks it assumed. The
sweep's axes and fixed values go through the same formatting.
"""
from __future__ import annotations

import numpy as np

from ..schema import parameter_table
from ..schema.fields import field
from ..schema.parameters import format_value
from .context import Context, ensemble_text, realizations, sensors
from .render import Bullets, Heading, Para, Table, fmt_number, fmt_kn

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
    shown = ", ".join(fmt_number(v + 0.0, 4) for v in g)
    return f"gravity: on, g = ({shown}) m/s² in the bearing frame{along}"


#: The heading of the configuration appendix (the report's last section).
HEADING = "Appendix: bearing, profile and parameters"


def section_parameters(ctx: Context) -> list:
    """The blocks of the appendix :data:`HEADING`: the configuration in engineering units."""
    attrs = ctx.sweep.attrs
    conf = ctx.configuration
    blocks = [Heading(2, HEADING)]
    items = [f"bearing: **{attrs.get('bearing', '') or 'not named'}**",
             f"profile: **{attrs.get('profile', '') or 'not named'}**"]
    if "axial_load" in ctx.metrics.coords:
        vals = np.atleast_1d(ctx.metrics["axial_load"].values)
        items.append("axial load: " + ", ".join(fmt_kn(float(v)) for v in vals))
    if conf is not None:
        items.append(_gravity_text(conf))
    if realizations(ctx.metrics) is not None:
        items.append(f"ensemble: {ensemble_text(ctx)} per grid point")
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
    rows = [[f"`{r.key}`", r.value, r.doc, "**assumed**" if r.assumed else ""]
            for r in parameter_table(conf.bearing, conf.profile, conf.settings, symbols=True)]
    for kind, values in (("axis", conf.axes), ("fixed", conf.fixed)):
        for key, value in values.items():
            f = field("operating_point", key)
            shown = format_value(f, value, symbols=True) if f is not None else str(value)
            rows.append([f"`{key}`", shown, f"sweep {kind}" + (f": {f.doc}" if f is not None else ""), ""])
    blocks.append(Table(["key", "value", "meaning", "assumption"], rows))
    return blocks
