"""``rvsweep``: the command line. Each subcommand lives in ``pipeline.commands.<name>``.

A subcommand module defines ``HELP`` (one line), ``add_arguments(parser)`` and
``run(args) -> int``. Errors derived from :class:`pipeline.errors.UserError` are printed
as one line on stderr with exit status 2; nothing else is caught, so genuine bugs keep
their traceback.
"""
from __future__ import annotations

import argparse
import importlib
import sys
import warnings

from .commands.common import accept_negative_values
from .errors import UnitlessNumberWarning, UserError

COMMANDS = ("check", "statics", "simulate", "sweep", "report", "compare", "bench")


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The ``rvsweep`` parser. ``only``: the one subcommand whose arguments are added
    (``""``: none, for ``rvsweep --help``; None: every one). A subcommand's arguments may
    need the schema (``--method``'s choices) or the report (its targets), and with them
    numba, pint and xarray: a command line adds only its own command's."""
    from . import __version__

    parser = argparse.ArgumentParser(
        prog="rvsweep",
        description="Contact-dynamics sweeps of RV-reducer main bearings.",
    )
    parser.add_argument("--version", action="version", version=f"rvsweep {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in COMMANDS:
        module = importlib.import_module(f"pipeline.commands.{name}")
        p = sub.add_parser(name, help=module.HELP, description=module.HELP)
        if only is None or only == name:
            module.add_arguments(p)
            accept_negative_values(p)   # --axial-load -10kN
        p.set_defaults(_run=module.run)
    return parser


def _command(argv) -> str:
    """The subcommand a command line names: its first word that is not an option
    (``rvsweep`` itself takes only ``--help`` and ``--version``), or ``""``."""
    return next((a for a in argv if not a.startswith("-")), "")


def _warning_line(show):
    """``warnings.showwarning`` that prints a :class:`~pipeline.errors.UnitlessNumberWarning`
    as one ``warning:`` line (its text names the file or flag, the key and the value), and
    any other warning as ``show`` does."""
    said = set()

    def showwarning(message, category, filename, lineno, file=None, line=None):
        if not issubclass(category, UnitlessNumberWarning):
            show(message, category, filename, lineno, file, line)
        elif str(message) not in said:   # each text once
            said.add(str(message))
            print(f"warning: {message}", file=sys.stderr)
    return showwarning


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    command = _command(argv)
    parser = build_parser(command if command in COMMANDS else "")
    args = parser.parse_args(argv)
    with warnings.catch_warnings():
        warnings.showwarning = _warning_line(warnings.showwarning)
        warnings.simplefilter("always", UnitlessNumberWarning)
        return _run(args)


def _run(args) -> int:
    try:
        return int(args._run(args) or 0)
    except UserError as exc:
        print(f"rvsweep {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into `head` and closed: not an error
        sys.stderr.close()
        return 0
    except KeyboardInterrupt:
        print(f"rvsweep {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
