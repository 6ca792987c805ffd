"""The files shipped with the package: default sweep, bearings, profiles, reference fits.

They live in the checkout's ``sweeps/`` folder, where users read and copy them and where
``make sweep`` points. A wheel carries the same folder as ``pipeline/sweeps`` (see
``[tool.hatch.build.targets.wheel.force-include]`` in ``pyproject.toml``), found here
through :mod:`importlib.resources`, so a non-editable install has its default sweep too.
An editable install or a plain checkout has no ``pipeline/sweeps``; there the folder
beside the package is the one.
"""
from __future__ import annotations

from importlib import resources
from pathlib import Path

DEFAULT_SWEEP = "study.toml"
DEFAULT_BEARING = "bearings/rv-main-study.toml"
DEFAULT_PROFILE = "profiles/study.toml"
REFERENCE_FITS = "reference/study-fits.toml"


def shipped_root() -> Path:
    """The folder of shipped TOML files [-]: installed with the wheel, else the checkout's."""
    installed = resources.files("pipeline").joinpath("sweeps")
    if installed.is_dir():
        return Path(str(installed))
    return Path(__file__).resolve().parents[2] / "sweeps"


def shipped_file(relative: str) -> Path:
    """One shipped file, e.g. ``shipped_file("bearings/rv-main-study.toml")`` [-]."""
    return shipped_root() / relative
