"""Argument helpers shared by the commands: input files (shipped names too) and the
one-case sweep of statics and simulate. ``--set`` goes through the one parser,
:func:`pipeline.schema.parse_sets`, and is checked against the schema."""
from __future__ import annotations

import re
from pathlib import Path

#: What argparse takes for a value, not an option, when it starts with "-": a minus sign
#: then a digit or a point and a digit ("-10kN", "-3.5 kN", "-.5deg", "-1e3 N").
_NEGATIVE_VALUE = re.compile(r"^-\.?\d.*$", re.DOTALL)


def accept_negative_values(parser) -> None:
    """Let ``--axial-load -10kN`` (a negative quantity after a space) parse as a value.

    argparse takes every token that starts with "-" for an option unless it looks like a
    negative *number* (``-10``, ``-1.5``), so ``--axial-load -10kN`` failed with "expected
    one argument" while ``--axial-load=-10kN`` worked. Why this and not rewriting argv
    (``--opt -10kN`` -> ``--opt=-10kN``): argparse asks exactly one question, "is this
    token a negative number?", through the parser's ``_negative_number_matcher``; widening
    that one pattern to "minus, then a digit" answers it for quantities with units in
    every option of the parser, with no second parser of argv to keep in step. The
    attribute is private but has existed since Python 2.7 (it is read by ``.match`` up to
    3.12 and ``.fullmatch`` later, which the pattern's ``.*$`` serves both);
    ``tests/pipeline/test_statics_cli.py`` fails if argparse ever stops consulting it. No
    option of rvsweep starts with "-<digit>", so nothing else is taken for a value.
    """
    parser._negative_number_matcher = _NEGATIVE_VALUE

#: How --help says that shipped files may be named.
SHIPPED_HELP = ("a path; one that does not exist but names a shipped file (relative to the "
                "shipped sweeps/ folder, e.g. bearings/rv-main-study.toml) is that file")


def input_file(arg) -> Path:
    """``arg`` as a path; when no such file exists but ``arg`` names a shipped file
    (``bearings/rv-main-study.toml``, or ``sweeps/bearings/...``), the shipped file."""
    from ..schema.shipped import shipped_file

    p = Path(arg).expanduser()
    if p.exists() or p.is_absolute():
        return p
    rel = Path(*p.parts[1:]) if p.parts and p.parts[0] == "sweeps" else p
    shipped = shipped_file(str(rel))
    return shipped if shipped.is_file() else p


def check_out_option(value, flag: str = "--out") -> None:
    """Refuse an ``--out`` that names nothing: empty or only blanks (``--out ''`` wrote
    into the current folder), or holding a control character (a newline typed into a
    path)."""
    from ..errors import UserError

    if not str(value).strip():
        raise UserError(f"{flag} {value!r}: empty; name a folder or file (e.g. {flag} results)")
    bad = next((ch for ch in str(value) if ord(ch) < 32 or ord(ch) == 127), None)
    if bad is not None:
        raise UserError(f"{flag} {value!r}: holds the control character {bad!r}; a path should not")


def add_load_arguments(parser, *, speed: bool) -> None:
    parser.add_argument("--bearing", required=True, metavar="FILE", help="bearing TOML file: " + SHIPPED_HELP)
    if speed:
        parser.add_argument("--speed", required=True, help='steady inner-ring speed, e.g. "660deg/s" or "110 rpm"')
    parser.add_argument("--radial-load", default="0 N", help='radial load, e.g. "30kN" (default 0)')
    parser.add_argument("--axial-load", default="0 N", help='axial load towards +z, e.g. "10kN" (default 0)')
    parser.add_argument("--moment", default="0 N*m", help='tilting moment, e.g. "0Nm" (default 0)')
    parser.add_argument("--load-angle", default="0 deg", help="direction of the radial load from +x (default 0)")
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help='override a bearing, profile (profile.<key>) or solver (solver.<field>) '
                             'value, with units, e.g. --set friction.mu_static=0.05 '
                             '--set solver.output_rate="2 kHz"; `rvsweep check --fields` lists the keys')


def add_method_argument(parser) -> None:
    """``--method {rk4,imex}``: the integrator (``solver.method``; its choices, default
    and doc come from the schema)."""
    from ..schema.fields import solver_fields

    f = solver_fields()["method"]
    parser.add_argument("--method", choices=f.choices, default=None,
                        help=f"{f.doc} (default {f.default}; the same as --set solver.method=NAME)")


def split_sets(items) -> tuple:
    """``--set`` items as ([solver] table, values for a case): parsed by
    :func:`pipeline.schema.parse_sets`, each key checked against the schema."""
    from ..schema import check_set_key, parse_sets

    solver, values = {}, {}
    for key, value in parse_sets(items).items():
        check_set_key(key, value)
        if key.startswith("solver."):
            solver[key.split(".", 1)[1]] = value
        else:
            values[key] = value
    return solver, values


def one_case_sweep(args, *, profile: str | None):
    """A one-case sweep built from the command line, validated like a sweep file."""
    import warnings

    from ..errors import ConfigError, UnitlessNumberWarning
    from ..schema import sweep_from_dict

    speed = getattr(args, "speed", None)
    fixed = {"speed": "0 deg/s" if speed is None else speed, "radial_load": args.radial_load,
             "axial_load": args.axial_load, "moment": args.moment, "load_angle": args.load_angle}
    solver, values = split_sets(args.set)
    method = getattr(args, "method", None)
    if method is not None:
        if "method" in solver:
            raise ConfigError("--method", "solver.method", method,
                              f"given twice (also as --set solver.method={solver['method']})")
        solver["method"] = method
    fixed.update(values)
    raw = {"name": "cli", "bearing": str(input_file(args.bearing).resolve()),
           "profile": str(input_file(profile).resolve()) if profile else str(default_profile()),
           "solver": solver, "cases": [fixed]}
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always", UnitlessNumberWarning)
        try:
            sweep = sweep_from_dict(raw, Path.cwd() / "command line")
        except ConfigError as exc:
            raise _as_typed(exc, args) from None
    for w in said:   # told again as typed (--radial-load '30'), outside the recording
        if issubclass(w.category, UnitlessNumberWarning):
            where = _typed_where(w.message, args)
            warnings.warn(UnitlessNumberWarning(where, None, None, w.message.reason) if where
                          else w.message, stacklevel=2)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return sweep


#: The one-case sweep's keys and the options that set them.
_FLAGS = {"speed": "--speed", "radial_load": "--radial-load", "axial_load": "--axial-load",
          "moment": "--moment", "load_angle": "--load-angle"}


def _shown(text, most: int = 80):
    """``text`` as typed, cut in the middle when longer than ``most`` characters."""
    text = str(text)
    return text if len(text) <= most else f"{text[:most // 2]}...{text[-most // 4:]}"


def _typed_where(exc, args):
    """Where the command line's one case has the value that ``exc`` (a ConfigError or an
    UnitlessNumberWarning) is about, as the user typed it: the option and its text
    ("--radial-load '30 kg'"), not the sweep's internal key and SI value; None when the
    value comes from a bearing or profile file (that file's own message says it) or from
    nowhere the command line names."""
    key = exc.key or ""
    if exc.file != str(Path.cwd() / "command line"):
        return None
    if key.startswith("cases[0]."):
        key = key[len("cases[0]."):]
        if key in _FLAGS:
            return f"{_FLAGS[key]} {_shown(getattr(args, key))!r}"
    if key in ("bearing", "profile") and getattr(args, key, None):
        return f"--{key} {getattr(args, key)!r}"
    typed = next((item for item in args.set if item.split("=", 1)[0].strip() == key), None)
    if typed is not None:
        return f"--set {typed!r}"
    return None


def _as_typed(exc, args):
    """A schema error about the command line's one case, told as the user typed it
    (:func:`_typed_where`)."""
    from ..errors import UserError

    where = _typed_where(exc, args)
    return exc if where is None else UserError(f"{where}: {exc.reason}")


def default_profile() -> Path:
    """The study's cycle shipped with the project."""
    from ..schema.shipped import DEFAULT_PROFILE, shipped_file

    return shipped_file(DEFAULT_PROFILE)
