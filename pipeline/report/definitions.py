"""What the designer's numbers are: the tilt condition, the two static safety factors, the
two stiffnesses, the loaded-ball rule and what each torque includes.

Every number of this section is read from ``metrics.nc`` (the per-case scalars at the
steady operating point and the phase metrics); nothing is recomputed here. Which basis the
catalogue ratings took (ISO 76's f0 reduced, ISO 281's C_r refused, where the grooves are
more open than 0.52/0.53 D_w) and which of Palmgren's rows the friction moment used are read
from the stored configuration's bearing (rvcore.standards.iso16281.rating_caveats,
rvcore.standards.palmgren.palmgren_basis).
"""
from __future__ import annotations

import math

import numpy as np

from rvcore.contact.laws import LOADED_BALL_LOAD
from rvcore.standards.palmgren import palmgren_basis, published_spread_text
from rvcore.standards.iso16281 import rating_caveats

from .context import Context
from .render import Bullets, Heading, Para, Table, Warning_, fmt_number

#: Steady-phase index of the study's phases (start-up, steady, deceleration).
_STEADY = 1


def _span(ctx: Context, name: str, scale: float = 1.0, phase: int | None = None):
    """``(min, max)`` of a metric over every case, or None where the sweep lacks it."""
    if name not in ctx.metrics:
        return None
    da = ctx.metrics[name]
    if phase is not None and "phase" in da.dims:
        da = da.isel(phase=phase)
    v = np.asarray(da.values, dtype=np.float64) * scale
    v = v[np.isfinite(v)]
    return (float(v.min()), float(v.max())) if v.size else None


def _text(span, unit: str = "") -> str:
    if span is None:
        return "not in this sweep"
    lo, hi = span
    body = fmt_number(lo, 3) if math.isclose(lo, hi, rel_tol=1e-3) else f"{fmt_number(lo, 3)} to {fmt_number(hi, 3)}"
    return f"{body} {unit}".strip()


def _stability(ctx: Context) -> list:
    """A warning where the ring is statically unstable at some operating point (its tangent
    stiffness over its free coordinates is not positive definite), a line where it is not."""
    if "statically_stable" not in ctx.metrics:
        return []
    v = np.asarray(ctx.metrics["statically_stable"].values, dtype=np.float64)
    v = v[np.isfinite(v)]
    if not v.size:
        return []
    unstable = int(np.count_nonzero(v == 0.0))
    if not unstable:
        return [Para("**Stability.** At every operating point the ring's quasi-static tangent stiffness is "
                     "positive definite over its free coordinates: it returns from any small displacement.")]
    return [Warning_(f"**The ring is statically unstable at {unstable} of {v.size} operating points**: its "
                     "tangent stiffness is not positive definite there, so a small displacement grows instead "
                     "of returning. A single row free to tilt (a deep-groove row, which has no tilt "
                     "stiffness of its own) rocks onto its most loaded ball and settles tilted; its transient "
                     "metrics then record that divergence, not a vibration (docs/validation.md, the "
                     "deep-groove family). A shaft on a second support holds the ring: "
                     "`inner_ring.tilt = \"held\"`.")]


def _bearing(ctx: Context):
    """The sweep's :class:`rvcore.bearing.geometry.Bearing` from its stored configuration, or None."""
    conf = getattr(ctx, "configuration", None)
    return None if conf is None else conf.bearing


def _rating_basis(ctx: Context) -> list:
    """A warning where a catalogue rating is reduced or refused for this bearing (groove radii
    above ISO 76's and ISO 281's 0.52/0.53 D_w), naming which; nothing where the tables hold."""
    b = _bearing(ctx)
    caveats = rating_caveats(b) if b is not None else []
    if not caveats:
        return []
    return [Warning_("**Catalogue ratings outside their tables.** " + " ".join(c.rstrip(".") + "." for c in caveats)
                     + " The pressure route (4200 MPa / p_max)³ takes this bearing's own grooves and stands.")]


def _palmgren_basis(ctx: Context) -> str:
    b = _bearing(ctx)
    return palmgren_basis(b.rows[0].nominal_contact_angle) if b is not None else "not known (no configuration)"


def section_definitions(ctx: Context) -> list:
    """The "What the designer's numbers are" section (a list of blocks)."""
    tilt = str(ctx.sweep.attrs.get("inner_ring_tilt", "free"))
    blocks = [Heading(2, "What the designer's numbers are")]
    held = tilt == "held"
    blocks.append(Para(
        f"**Inner-ring tilt: {tilt}** (`inner_ring.tilt` in the bearing file). "
        + ("The ring is held square, as a shaft on a second support holds it: both tilts are fixed at 0 in the "
           "statics, the stiffness and the dynamics, and the support's moment is reported "
           f"(`tilt_reaction_moment_*`; steady peak {_text(_span(ctx, 'tilt_reaction_moment_peak', 1.0, _STEADY), 'N m')})."
           if held else
           "The ring tilts freely under zero moment. A single row under a radial load then tilts and puts its "
           "heaviest ball under more load than a ring held square by a second support would: the peak pressure, "
           "the safety factor, the lives and the stiffness all depend on this condition. Set "
           "`inner_ring.tilt = \"held\"` for a ring held square.")))
    blocks += _stability(ctx)
    s_cycle = _span(ctx, "static_safety_factor_min")
    rows = [["(4200 MPa / p_max)³ along the cycle, smallest", "ISO 76 3.2, 3.6; this model's Hertz pressure",
             _text(s_cycle)],
            ["(4200 MPa / p_max)³ at the steady point (statics)", "ISO 76 3.2, 3.6; the statics' load distribution",
             _text(_span(ctx, "static_safety_factor_steady"))],
            ["C0r / P0r at the steady loads", "ISO 76 6.1.1 (f0, Table 1), 6.2 (X0, Y0, Table 2)",
             _text(_span(ctx, "static_safety_factor_catalogue"))]]
    blocks.append(Para(
        "**Static safety factor.** ISO 76 defines s₀ = C₀/P₀, a ratio of loads. The 4200 MPa of radial ball "
        "bearings is the contact pressure at C₀, and a Hertz pressure goes as the load^(1/3), so from a peak "
        "pressure s₀ = (4200 MPa / p_max)³. The catalogue formula takes Stribeck's idealised load distribution "
        "(Q_max = 5 F_r / (Z cos α)), ISO 76's osculations 0.52/0.53 (f₀ reduced where the "
        "grooves are more open), no tilt and no moment; the pressure route "
        "takes this bearing's own load distribution, so the two differ by how far that distribution departs from "
        "the idealisation."))
    blocks.append(Table(["s₀", "definition", "over the sweep"], rows))
    blocks += _rating_basis(ctx)
    stiff = [(f"{k} stiffness", _span(ctx, f"{k}_stiffness", f), _span(ctx, f"{k}_stiffness_compliant", f), u)
             for k, f, u in (("radial", 1e-6, "N/µm"), ("axial", 1e-6, "N/µm"), ("tilting", 1e-3, "N m/mrad"))]
    blocks.append(Para(
        "**Stiffness.** Direct: K_ii of the tangent stiffness, the load per unit displacement with every "
        "other coordinate held (the catalogue convention). Compliant: 1/C_ii, C = K⁻¹, every other coordinate "
        "free: what one load change meets. Both at the steady operating point."))
    blocks.append(Table(["", "direct", "compliant"],
                        [[name, _text(d, u), _text(c, u)] for name, d, c, u in stiff]))
    drive = _span(ctx, "inner_ring_drive_torque_mean", 1.0, _STEADY)
    palm = _span(ctx, "friction_moment_palmgren")
    blocks.append(Para(
        "**Torque.** The model's drive torque (`inner_ring_drive_torque`) is the moment the prescribed spin "
        "needs against the contact forces of this model: the study's dry Coulomb friction with its STEP "
        "transitions at the ball–race, ball–pocket and cage–land point contacts, the contact damping, and the "
        "ring's inertia. It leaves out what makes most of a real bearing's friction moment: differential slip "
        "across the contact ellipse (the contacts are points), elastohydrodynamic rolling resistance, the "
        "lubricant's viscous drag and churning, and seals. Beside it, Palmgren's empirical friction moment "
        "(`friction_moment_palmgren` = load term f₁ F_β d_m + viscous term M_v, Harris & Kotzalas; valid for "
        "steady running at moderate load and speed, run in, fully lubricated, no seals; lubricant viscosity "
        "from the bearing file's `[lubricant]`, default ISO VG 68 at 40 °C)."))
    blocks.append(Bullets([
        f"steady mean of the model's drive torque: {_text(drive, 'N m')}",
        f"Palmgren's friction moment at the steady point: {_text(palm, 'N m')} (load term "
        f"{_text(_span(ctx, 'friction_moment_palmgren_load'), 'N m')}, viscous term "
        f"{_text(_span(ctx, 'friction_moment_palmgren_viscous'), 'N m')}); constants: {_palmgren_basis(ctx)}",
        f"how uncertain Palmgren's moment is: {published_spread_text()}",
        "the two are different quantities: read the drive torque as this model's contact friction, not as the "
        "bearing's friction moment"]))
    blocks.append(Para(
        f"**Loaded balls** (`loaded_ball_count`): balls carrying more than {fmt_number(LOADED_BALL_LOAD, 3)} N on both "
        "the inner and the outer race, i.e. passing load from ring to ring; a ball resting on one race under "
        "its weight or centrifugal force does not count."))
    return blocks
