"""Errors a user sees as one clear line (the CLI prints ``str(error)`` and exits 2)."""
from __future__ import annotations


class UserError(Exception):
    """Base class of every error caused by user input; printed without a traceback."""


class _Located:
    """A message about one input value: ``file``, ``key`` (dotted path; None: the file or
    option itself), ``value`` as typed (None: not shown) and ``reason``, read as
    ``<file>: <key> = <value>: <reason>``."""

    def __init__(self, file, key: str | None, value, reason: str):
        self.file = str(file) if file is not None else "<input>"
        self.key = key
        self.value = value
        self.reason = reason
        where = self.file if not key else f"{self.file}: {key}"
        shown = "" if value is None else f" = {value!r}"
        super().__init__(f"{where}{shown}: {reason}")


class ConfigError(_Located, UserError):
    """A bad value in a configuration file.

    The message names the file, the key (dotted path), the value and the reason, e.g.
    ``sweeps/bearings/x.toml: rows[0].balls.diameter = '-3 mm': must be positive``.
    """


class UnitlessNumberWarning(_Located, UserWarning):
    """A dimensional input written as a number without a unit, read in SI.

    Like :class:`ConfigError`, the message names the file (or flag), the key, the value as
    typed and the reason, e.g. ``sweep.toml: axes.radial_load[0] = 30: a number without a
    unit, read in SI: 30 N``: a load meant in kN would otherwise run a thousand times too
    small without a word. ``rvsweep`` prints it as one ``warning:`` line.
    """
