"""Errors a user sees as one clear line (the CLI prints ``str(error)`` and exits 2)."""
from __future__ import annotations


class UserError(Exception):
    """Base class of every error caused by user input; printed without a traceback."""


class ConfigError(UserError):
    """A bad value in a configuration file.

    The message names the file, the key (dotted path), the value and the reason, e.g.
    ``sweeps/bearings/x.toml: rows[0].balls.diameter = '-3 mm': must be positive``.
    """

    def __init__(self, file, key: str | None, value, reason: str):
        self.file = str(file) if file is not None else "<input>"
        self.key = key
        self.value = value
        self.reason = reason
        where = self.file if not key else f"{self.file}: {key}"
        shown = "" if value is None else f" = {value!r}"
        super().__init__(f"{where}{shown}: {reason}")
