"""A sweep's ``[statistics]`` table: N draws of the bearing's imperfections per grid point
(docs/inputs.md, "Tolerance statistics"; issue 43).

::

    [statistics]
    method = "sobol"          # "sobol" (scrambled Sobol' points) or "lhs" (Latin hypercube)
    draws = 64                # N: a power of 2 for "sobol"
    seed = 1                  # the scrambling's (or the hypercube's) seed: the draws are fixed by it
    inputs = ["inner_eccentricity", "inner_eccentricity_angle"]   # default: every input the bearing has
    sensitivity = true        # Saltelli's design A, B, AB_i for Sobol' indices (needs "sobol")

Each draw is a point ``u`` of the unit hypercube, one column per value it sets
(:data:`INPUTS`, in the order of ``inputs``, each row of the bearing in turn), mapped onto
the class's limits by :func:`apply_draw`; the case then carries the drawn values explicitly
in its bearing, so that its hashed configuration (its id) identifies the draw. The sweep
gains the axis ``draw`` (0 … N−1) and, with ``sensitivity``, the categorical axis
``sample``: ``A``, ``B`` and ``AB_<input>`` (A with that input's columns from B), N·(d + 2)
cases per grid point for d inputs.

Resuming and adding draws: ``qmc.Sobol(d, scramble=True, seed=s).random(N)`` is the first
N points of one fixed sequence, so raising N keeps the first draws (and their case ids)
and computes only the new ones (tests/pipeline/test_statistics.py checks it). A Latin
hypercube is stratified for its own N: changing N redraws every draw, and every case is
new (``rvsweep check`` and docs/inputs.md say so).

Notes
-----
The inputs and their limits (:data:`INPUTS`; each is uniform between its limits, an
assumption: ISO 492 gives limits, not distributions):

- ``inner_eccentricity``, ``outer_eccentricity``: ``e ∈ [0, K/2]`` with K the class's
  ``K_ia`` / ``K_ea`` (:mod:`rvcore.standards.iso492`), or ``[0, e]`` where the bearing
  file gives the eccentricity itself;
- ``inner_eccentricity_angle``, ``outer_eccentricity_angle``: the high point in ``[0, 2π)``;
- ``inner_waviness``, ``outer_waviness``: each term's amplitude in ``[0, A_k]``, A_k the
  bearing file's (ISO 492 gives no waviness limit: the file's terms are the limits);
- ``ball_diameter_deviation``: each ball's in ``±V_DwL/2`` of the row's ball grade
  (ISO 3290-1), as :func:`rvcore.bearing.imperfections.realize_row` draws it;
- ``inner_axial_runout``, ``outer_axial_runout``: the tilted groove's amplitude ``a ∈ [0, S/2]``
  with S the class's ``S_ia`` / ``S_ea`` (classes 5 and 4; Normal and 6 have none), or
  ``[0, a]`` where the file gives the amplitude; ``inner_axial_angle``, ``outer_axial_angle``:
  its high point in ``[0, 2π)``. A case whose class tabulates none (Normal, 6) keeps none:
  the input is not drawn there (:class:`ZeroByClass`).

A new imperfection is one more :class:`ToleranceInput` entry in :data:`INPUTS`: how many
columns it takes in a row and what a row's ``u`` sets.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from rvcore.bearing.imperfections import Imperfections, Waviness
from rvcore.standards.iso492 import (ToleranceError, axial_runout_limits, ball_lot_variation, default_ball_grade,
                                     inner_runout, outer_runout)

from ..errors import ConfigError
from . import fields as _fields
from .reader import short

#: The draw axis: draw k of ``draws = N`` (0 … N−1).
DRAW = "draw"
#: The Saltelli design's axis (with ``sensitivity``): ``A``, ``B``, ``AB_<input>``.
SAMPLE = "sample"
#: Sampling methods of ``scipy.stats.qmc`` (the schema's, :mod:`pipeline.schema.fields`).
METHODS = _fields.field("statistics", "statistics.method").choices
#: The keys of ``[statistics]``.
KEYS = tuple(f.path.removeprefix("statistics.") for f in _fields.fields_of("statistics"))
#: Most draws per grid point (the whole sweep is bounded by the sweep's MAX_CASES too).
MAX_DRAWS = _fields.field("statistics", "statistics.draws").maximum


class NoLimit(ValueError):
    """An input has nothing to draw within in this row (said why)."""


class ZeroByClass(NoLimit):
    """The row's tolerance class tabulates no limit for this input (ISO 492 gives Normal and 6
    no axial runout): a case of that class keeps its bearing's value (none), and the input is
    not drawn there; a base bearing of that class does not offer the input."""


@dataclass(frozen=True)
class ToleranceInput:
    """One named tolerance input of ``[statistics]``.

    Parameters
    ----------
    name : str
    doc : str
        One line: what it draws, within which limits.
    columns : callable
        ``columns(row) -> int``: the hypercube's columns it takes in one row.
    draw : callable
        ``draw(row, bearing, u) -> dict``: the :class:`~rvcore.bearing.imperfections.Imperfections`
        fields a row's columns ``u`` (in [0, 1)) set; raises :class:`NoLimit` where the row
        gives no limit.
    """

    name: str
    doc: str
    columns: Callable
    draw: Callable


def _one(row) -> int:
    return 1


def _eccentricity_limit(ring: str, bearing, cls: str) -> float:
    """Half the class's radial runout K_ia or K_ea (ISO 492) [m]."""
    runout = inner_runout(bearing.bore, cls) if ring == "inner" else outer_runout(bearing.outer_diameter, cls)
    return runout / 2


def _axial_limit(ring: str, bearing, cls: str) -> float | None:
    """Half the class's axial runout S_ia or S_ea (ISO 492) [m]; None where the class has none."""
    return axial_runout_limits(bearing.bore, bearing.outer_diameter, cls)[0 if ring == "inner" else 1]


def _amplitude(ring: str, key: str, class_limit, what: str, classes: str = ""):
    """The draw of one raceway's amplitude ``key`` (``inner_eccentricity``, ``inner_axial_amplitude``)
    uniform in [0, limit]: the file's value where it gives one, else ``class_limit(ring, bearing,
    class)``; a class that tabulates none raises :class:`ZeroByClass`, no class :class:`NoLimit`."""
    def draw(row, bearing, u):
        imp = row.imperfections
        given = getattr(imp, key)
        limit = 0.0
        if given is not None:
            limit = float(given)
        elif imp.tolerance_class:
            try:
                limit = class_limit(ring, bearing, imp.tolerance_class)
            except ToleranceError as exc:
                raise NoLimit(str(exc)) from None
            if limit is None:
                raise ZeroByClass(f"ISO 492 gives class {imp.tolerance_class} no {ring} {what}")
        if not limit > 0:
            raise NoLimit(f"the row has no {ring} {what} to draw within: give imperfections.tolerance_class"
                          f"{classes} or imperfections.{key}")
        return {key: float(u[0]) * limit}
    return draw


def _high_point(amplitude, key: str):
    """The draw of the high point ``key`` of ``amplitude``'s imperfection, uniform in [0, 2π): only
    where that imperfection has a limit (:class:`NoLimit` without one)."""
    def draw(row, bearing, u):
        amplitude(row, bearing, u)
        return {key: 2.0 * math.pi * float(u[0])}
    return draw


def _eccentricity(ring: str):
    return _amplitude(ring, f"{ring}_eccentricity", _eccentricity_limit, "eccentricity")


def _angle(ring: str):
    return _high_point(_eccentricity(ring), f"{ring}_eccentricity_angle")


def _axial_runout(ring: str):
    return _amplitude(ring, f"{ring}_axial_amplitude", _axial_limit, "axial runout", " (classes 5, 4)")


def _axial_angle(ring: str):
    return _high_point(_axial_runout(ring), f"{ring}_axial_angle")


def _waviness_columns(ring: str):
    return lambda row: len(getattr(row.imperfections, f"{ring}_waviness"))


def _waviness(ring: str):
    def draw(row, bearing, u):
        terms = getattr(row.imperfections, f"{ring}_waviness")
        if not terms or not any(w.amplitude > 0 for w in terms):
            raise NoLimit(f"the row has no {ring} waviness terms to draw amplitudes within: give "
                          f"imperfections.{ring}_waviness (their amplitudes are the limits)")
        return {f"{ring}_waviness": tuple(Waviness(w.order, float(x) * w.amplitude, w.phase)
                                          for w, x in zip(terms, u))}
    return draw


def _balls(row, bearing, u):
    imp = row.imperfections
    try:
        grade = imp.ball_grade or (default_ball_grade(imp.tolerance_class, row.ball_diameter)
                                   if imp.tolerance_class else "")
    except ToleranceError as exc:
        raise NoLimit(str(exc)) from None
    if not grade:
        raise NoLimit("the row has no ball grade to draw within: give imperfections.tolerance_class or "
                      "imperfections.ball_grade")
    half = ball_lot_variation(grade) / 2
    return {"ball_diameter_deviation": tuple(float(half * (2.0 * x - 1.0)) for x in u)}


#: The named tolerance inputs, in their default order.
INPUTS = {t.name: t for t in (
    ToleranceInput("inner_eccentricity", "inner raceway eccentricity, uniform in [0, K_ia/2] (or [0, e] given)",
                   _one, _eccentricity("inner")),
    ToleranceInput("inner_eccentricity_angle", "inner raceway high point, uniform in [0, 360) deg",
                   _one, _angle("inner")),
    ToleranceInput("outer_eccentricity", "outer raceway eccentricity, uniform in [0, K_ea/2] (or [0, e] given)",
                   _one, _eccentricity("outer")),
    ToleranceInput("outer_eccentricity_angle", "outer raceway high point, uniform in [0, 360) deg",
                   _one, _angle("outer")),
    ToleranceInput("inner_waviness", "each inner waviness term's amplitude, uniform in [0, A_k] of the file",
                   _waviness_columns("inner"), _waviness("inner")),
    ToleranceInput("outer_waviness", "each outer waviness term's amplitude, uniform in [0, A_k] of the file",
                   _waviness_columns("outer"), _waviness("outer")),
    ToleranceInput("ball_diameter_deviation", "each ball's diameter deviation, uniform in +-V_DwL/2 of its grade",
                   lambda row: row.ball_count, _balls),
    ToleranceInput("inner_axial_runout", "inner raceway axial runout amplitude, uniform in [0, S_ia/2] (or [0, a] "
                   "given)", _one, _axial_runout("inner")),
    ToleranceInput("inner_axial_angle", "inner raceway axial runout's high point, uniform in [0, 360) deg",
                   _one, _axial_angle("inner")),
    ToleranceInput("outer_axial_runout", "outer raceway axial runout amplitude, uniform in [0, S_ea/2] (or [0, a] "
                   "given)", _one, _axial_runout("outer")),
    ToleranceInput("outer_axial_angle", "outer raceway axial runout's high point, uniform in [0, 360) deg",
                   _one, _axial_angle("outer")),
)}


@dataclass(frozen=True)
class StatisticsSpec:
    """A validated ``[statistics]`` table (see the module docstring)."""

    method: str
    draws: int
    seed: int
    inputs: tuple
    sensitivity: bool = False


def _available(bearing) -> tuple:
    """The inputs the base bearing can draw in every row (the default ``inputs``)."""
    out = []
    for name, t in INPUTS.items():
        ok = True
        for row in bearing.rows:
            try:
                t.draw(row, bearing, np.full(t.columns(row), 0.5))
            except NoLimit:
                ok = False
        if ok and all(t.columns(row) > 0 for row in bearing.rows):
            out.append(name)
    return tuple(out)


def parse_statistics(raw, file, bearing) -> StatisticsSpec | None:
    """``[statistics]`` of a sweep file (None without one), checked against the base
    ``bearing``: one :class:`~pipeline.errors.ConfigError` line per problem."""
    if raw is None:
        return None
    if not isinstance(raw, dict):
        raise ConfigError(file, "statistics", short(raw), "must be a table ([statistics])")
    for k, v in raw.items():
        if k not in KEYS:
            raise ConfigError(file, f"statistics.{k}", short(v), f"unknown key (allowed: {', '.join(KEYS)})")
    method = raw.get("method", "sobol")
    if method not in METHODS:
        raise ConfigError(file, "statistics.method", short(method), f"must be one of {', '.join(METHODS)}")
    if "draws" not in raw:
        raise ConfigError(file, "statistics.draws", None, "missing: give the number of draws per grid point")
    n = raw["draws"]
    if isinstance(n, bool) or not isinstance(n, int) or not 2 <= n <= MAX_DRAWS:
        raise ConfigError(file, "statistics.draws", short(n), f"must be a whole number from 2 to {MAX_DRAWS}")
    if method == "sobol" and n & (n - 1):
        lower = 1 << (n.bit_length() - 1)
        raise ConfigError(file, "statistics.draws", n, "Sobol' points are balanced only in powers of 2: give "
                                                       f"{lower} or {2 * lower} (or method = \"lhs\")")
    if "seed" not in raw:
        raise ConfigError(file, "statistics.seed", None, "missing: the draws are fixed by their seed; give one "
                                                          "(e.g. seed = 1)")
    seed = raw["seed"]
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**63:
        raise ConfigError(file, "statistics.seed", short(seed), "must be a whole number of at least 0")
    sens = raw.get("sensitivity", False)
    if not isinstance(sens, bool):
        raise ConfigError(file, "statistics.sensitivity", short(sens), "must be true or false")
    if sens and method != "sobol":
        raise ConfigError(file, "statistics.sensitivity", sens, "Sobol' indices need method = \"sobol\" "
                                                                 "(Saltelli's design is drawn from Sobol' points)")
    if "inputs" in raw:
        inputs = raw["inputs"]
        if not isinstance(inputs, list) or not inputs or not all(isinstance(x, str) for x in inputs):
            raise ConfigError(file, "statistics.inputs", short(inputs), "must be a list of input names "
                                                                        f"(known: {', '.join(INPUTS)})")
        for i, name in enumerate(inputs):
            if name not in INPUTS:
                raise ConfigError(file, f"statistics.inputs[{i}]", name, f"unknown input (known: {', '.join(INPUTS)})")
            if name in inputs[:i]:
                raise ConfigError(file, f"statistics.inputs[{i}]", name, "listed twice")
            t = INPUTS[name]
            for r, row in enumerate(bearing.rows):
                try:
                    t.draw(row, bearing, np.full(t.columns(row), 0.5))
                except NoLimit as exc:
                    raise ConfigError(file, f"statistics.inputs[{i}]", name,
                                      f"{exc}" + (f" (row {r})" if len(bearing.rows) > 1 else "")) from None
        inputs = tuple(inputs)
    else:
        inputs = _available(bearing)
        if not inputs:
            raise ConfigError(file, "statistics", None, "the bearing has no tolerance to draw: give it "
                                                        "imperfections.tolerance_class (or limits of its own)")
    if sens and len(inputs) < 2:
        raise ConfigError(file, "statistics.sensitivity", sens, "Sobol' indices need at least two inputs (one input "
                                                                 "explains all the variance; its AB sample is B)")
    return StatisticsSpec(method, n, seed, inputs, sens)


def statistics_note(spec: StatisticsSpec) -> str:
    """One line for ``rvsweep check``: the draws, and what changing their number does."""
    how = ("Sobol' points: more draws keep these and add new cases" if spec.method == "sobol"
           else "Latin hypercube: changing draws redraws every draw (all cases new)")
    return (f"{spec.draws} {spec.method} draws a grid point (seed {spec.seed}) of {', '.join(spec.inputs)}"
            + (f"; Saltelli design for Sobol' indices ({len(spec.inputs) + 2} samples a draw)" if spec.sensitivity
               else "") + f"; {how}")


def columns(spec: StatisticsSpec, bearing) -> dict:
    """``{input: [(row, column slice)]}``: where each input's values sit in a draw's columns."""
    out, k = {}, 0
    for name in spec.inputs:
        t = INPUTS[name]
        out[name] = []
        for r, row in enumerate(bearing.rows):
            w = t.columns(row)
            out[name].append((r, slice(k, k + w)))
            k += w
    return out


def dimension(spec: StatisticsSpec, bearing) -> int:
    """d: the hypercube's columns for ``bearing``."""
    return sum(INPUTS[name].columns(row) for name in spec.inputs for row in bearing.rows)


def sample_names(spec: StatisticsSpec) -> tuple:
    """The ``sample`` axis' values: ``A``, ``B``, ``AB_<input>`` (with ``sensitivity``)."""
    return ("A", "B") + tuple(f"AB_{name}" for name in spec.inputs)


def unit_design(method: str, draws: int, seed: int, groups: dict, sensitivity: bool) -> dict:
    """The draws in the unit hypercube.

    Parameters
    ----------
    method : str
        ``"sobol"`` or ``"lhs"``.
    draws : int
        N.
    seed : int
        Seed of the scrambling (or of the hypercube).
    groups : dict
        ``{input: list of column indices}``; their union is ``range(d)``.
    sensitivity : bool
        Saltelli's design.

    Returns
    -------
    dict
        ``{sample: (N, d) array}``: ``{"A": …}`` alone without ``sensitivity``; with it
        ``A``, ``B`` and ``AB_<input>``, A with the input's columns from B.

    Notes
    -----
    Saltelli's A and B are the two halves of one scrambled Sobol' sequence of dimension 2d,
    as :func:`scipy.stats.sobol_indices` draws them (``sample_A_B``); ``AB_i`` takes the
    whole group of an input from B, so an input of several columns (the balls) has one
    index.
    """
    from scipy.stats import qmc

    d = sum(len(c) for c in groups.values())
    if method == "lhs":
        return {"A": qmc.LatinHypercube(d, seed=seed).random(draws)}
    if not sensitivity:
        return {"A": qmc.Sobol(d, scramble=True, seed=seed).random(draws)}
    base = qmc.Sobol(2 * d, scramble=True, seed=seed).random(draws)
    a, b = base[:, :d], base[:, d:]
    out = {"A": a, "B": b}
    for name, cols in groups.items():
        ab = a.copy()
        ab[:, cols] = b[:, cols]
        out[f"AB_{name}"] = ab
    return out


@dataclass(frozen=True)
class Draws:
    """A sweep's draws: the spec, where each input's columns sit in the base bearing and
    the unit design (:func:`unit_design`)."""

    spec: StatisticsSpec
    layout: dict
    design: dict
    widths: tuple

    @classmethod
    def of(cls, spec: StatisticsSpec, bearing) -> "Draws":
        layout = columns(spec, bearing)
        groups = {name: [c for _, s in places for c in range(s.start, s.stop)] for name, places in layout.items()}
        design = unit_design(spec.method, spec.draws, spec.seed, groups, spec.sensitivity)
        return cls(spec, layout, design, _widths(spec, bearing))

    def row(self, draw: int, sample: str = "A") -> np.ndarray:
        return self.design[sample][int(draw)]


def _widths(spec, bearing) -> tuple:
    return tuple((name, r, INPUTS[name].columns(row)) for name in spec.inputs for r, row in enumerate(bearing.rows))


def apply_draw(bearing, draws: Draws, draw: int, sample: str, file, where: str):
    """``bearing`` with every row's imperfections set explicitly from one draw.

    Parameters
    ----------
    bearing : rvcore.bearing.geometry.Bearing
        A case's resolved bearing (rows with :class:`~rvcore.bearing.imperfections.Imperfections`).
    draws : Draws
    draw : int
        The draw's index.
    sample : str
        ``"A"`` without ``sensitivity``.
    file, where :
        For the one-line refusal: the sweep file and the case's key.

    Raises
    ------
    ConfigError
        A case whose bearing takes other columns than the base bearing (a ball count or a
        waviness axis) or gives an input no limit (a class without a tabulated runout).
    """
    if _widths(draws.spec, bearing) != draws.widths:
        raise ConfigError(file, where, None, "[statistics] draws need the same rows, balls and waviness terms in "
                                             "every case (this case's bearing has other counts than the base one)")
    u = draws.row(draw, sample)
    fields = [dict() for _ in bearing.rows]
    for name, places in draws.layout.items():
        for r, s in places:
            try:
                fields[r].update(INPUTS[name].draw(bearing.rows[r], bearing, u[s]))
            except ZeroByClass:   # this case's class has none (Normal's axial runout): kept as it is
                continue
            except NoLimit as exc:
                raise ConfigError(file, where, None, f"statistics input {name}: {exc}") from None
    rows = tuple(dataclasses.replace(row, imperfections=dataclasses.replace(row.imperfections, **f))
                 if isinstance(row.imperfections, Imperfections) else row for row, f in zip(bearing.rows, fields))
    return dataclasses.replace(bearing, rows=rows)
