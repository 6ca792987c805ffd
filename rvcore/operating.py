"""The steady operating point of a duty cycle and the bearing's statics there, SI.

A designer reads stiffness and load distribution "at the operating point": the loads the
profile applies in the middle of its steady phase. The statics there (rigid rings, Hertz
at every contact, balls in equilibrium, the ring's weight included) give the ball loads
per row and the tangent stiffness.
"""
from __future__ import annotations

from .profile import PHASES, OperatingPoint, Profile
from .quasistatic import StaticResult, solve_statics


def steady_time(profile: Profile) -> float:
    """The middle of the profile's steady phase [s]."""
    for name, start, end in profile.phases:
        if name == PHASES[1]:
            return 0.5 * (start + end)
    raise ValueError(f"profile {profile.name!r} has no {PHASES[1]} phase")


def steady_loads(profile: Profile, op: OperatingPoint):
    """Loads the profile applies in the middle of its steady phase.

    Returns
    -------
    radial_load : float
        [N]
    axial_load : float
        [N]
    moment : float
        Tilting moment about the axis normal to the radial load [N m].
    load_angle : float
        Direction of the radial load [rad].
    """
    resolved = profile.resolve(op)
    t = steady_time(profile)
    return resolved.value(0, t), resolved.value(1, t), op.moment, op.load_angle


def steady_statics(bearing, profile: Profile, op: OperatingPoint, *, gravity: bool = True) -> StaticResult:
    """Quasi-static equilibrium, ball loads and stiffness at the steady operating point."""
    fr, fa, m, psi = steady_loads(profile, op)
    return solve_statics(bearing, fr, fa, m, psi, gravity=gravity, stiffness=True)
