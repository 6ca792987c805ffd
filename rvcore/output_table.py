"""Every output of a case, in one table: name, dimensions, units, long_name, what it is
made from and how it is reduced. SI throughout; units in UDUNITS spelling.

Two tables, one derived from the other:

- :data:`SIGNALS`, the per-step quantities: the slots of the diagnostics vector
  ``diag`` that the right-hand side (:mod:`rvcore.dynamics.rhs`) and the integrator's loop
  (:mod:`rvcore.recording.plan`) write at every step's state. Fixed slots first, then
  :data:`ROW_SIGNALS` once per row of balls, then one slot per virtual sensor.
- :data:`OUTPUTS`, every variable a case file holds: a time series is a signal
  (through a transform) sampled at the output rate; a phase metric is a signal reduced
  over each phase window at every integrator step (sum, extreme, extreme and its time,
  running statistics, integral); a steady scalar comes from the statics at the steady
  operating point (:mod:`rvcore.statics.operating`); the duty-cycle lives from the integrator's
  life sums (:mod:`rvcore.standards.iso16281`); the spectra from the steady phase's series
  (:mod:`rvcore.recording.spectra`).

Everything else derives from these two: the kernels' slot constants, the integrator's
output columns and accumulator columns (:func:`rvcore.recording.plan.build_plan`), the phase
metrics of :class:`rvcore.recording.results.CaseResult`, the case file's variables
(:mod:`pipeline.io.case`), ``metrics.nc`` and the report's tables. docs/outputs.md lists
the same rows, and a test holds it to them.

Adding an output: a row in :data:`OUTPUTS` (and, when no signal carries it yet, a row in
:data:`SIGNALS` and the line of the kernel or of :func:`rvcore.recording.plan.fill_state_signals`
that computes it). README, "Where to add things".
"""
from __future__ import annotations

from dataclasses import dataclass

# ---- per-step signals -------------------------------------------------------------

#: Where a signal is written: by the right-hand side at every evaluation (``kernel``; the
#: intermediate stages rewrite only the ones marked ``stage``), by the integrator's loop
#: from the state and the profile at the step's start (``state``), or after the step
#: (``step``: the stage-weighted drive torque and its band-limited value).
KERNEL, STAGE, STATE, STEP = "kernel", "stage", "state", "step"


@dataclass(frozen=True)
class Signal:
    """One slot of the per-step diagnostics vector."""

    name: str
    units: str
    meaning: str
    written: str = KERNEL


SIGNALS = (
    Signal("max_inner_contact_load", "N", "largest ball to inner-race normal force", STAGE),
    Signal("max_outer_contact_load", "N", "largest ball to outer-race normal force", STAGE),
    Signal("loaded_ball_count", "1", "balls carrying more than rvcore.contact.laws.LOADED_BALL_LOAD on both races", STAGE),
    Signal("max_contact_pressure_cubed", "Pa3", "largest p_max^3 over every contact", STAGE),
    Signal("max_penetration", "m", "deepest penetration of any contact (blow-up check)", STAGE),
    Signal("penetration_ball", "1", "state offset of the ball with the deepest penetration", STAGE),
    Signal("drive_torque", "N m", "moment about the ring's spin axis the prescribed spin needs", STAGE),
    Signal("friction_power", "W", "sum of |F_t . u| over every friction contact"),
    Signal("damping_power", "W", "sum of (q - K delta^1.5) d(delta)/dt over every contact: the dampers' dissipation"),
    Signal("tilt_power", "W", "power the small-tilt ring equations leave out (rvcore.dynamics.rhs.rhs, Notes)"),
    Signal("max_pocket_force", "N", "largest ball-pocket normal force"),
    Signal("cage_land_force", "N", "largest cage-land normal force"),
    Signal("max_race_sliding_speed_squared", "m2 s-2", "largest squared sliding speed at a loaded ball-race contact"),
    Signal("max_race_pv_sixth", "Pa6 m6 s-6", "largest (p_max s)^6 at a ball-race contact"),
    Signal("max_race_pressure_cubed", "Pa3", "largest p_max^3 over the ball-race contacts (ISO 76)"),
    Signal("sin_contact_angle_min", "1", "smallest |n_z| of the loaded race contacts (2 when none is loaded)"),
    Signal("sin_contact_angle_max", "1", "largest |n_z| of the loaded race contacts (-1 when none is loaded)"),
    Signal("drive_power", "W", "the drive's power T omega"),
    Signal("tilt_reaction_moment_x", "N m", "moment about x that holds a held ring's tilt at 0 (0 when free)"),
    Signal("tilt_reaction_moment_y", "N m", "moment about y that holds a held ring's tilt at 0 (0 when free)"),
    Signal("film_central", "m", "smallest Hamrock-Dowson central film over the loaded ball-race contacts (NaN when "
                                "none is loaded)"),
    Signal("film_minimum", "m", "smallest Hamrock-Dowson minimum film over the loaded ball-race contacts (NaN when "
                                "none is loaded)"),
    Signal("film_parameter", "1", "smallest film parameter h_min/sigma over the loaded ball-race contacts (NaN when "
                                  "none is loaded)"),
    Signal("max_ring_radial_deformation", "m", "largest |w| of a flexible ring's raceway at a ball (0 when rigid)"),
    Signal("max_ring_axial_deformation", "m", "largest |u| of a flexible ring's raceway at a ball (0 when rigid)"),
    Signal("inner_ring_x", "m", "inner-ring centre x", STATE),
    Signal("inner_ring_y", "m", "inner-ring centre y", STATE),
    Signal("inner_ring_z", "m", "inner-ring centre z", STATE),
    Signal("inner_ring_tilt_x", "rad", "inner-ring tilt about x", STATE),
    Signal("inner_ring_tilt_y", "rad", "inner-ring tilt about y", STATE),
    Signal("radial_displacement", "m", "ring displacement along the radial load's direction at t", STATE),
    Signal("axial_displacement", "m", "ring displacement along the axis", STATE),
    Signal("applied_radial_load", "N", "the profile's radial load", STATE),
    Signal("applied_axial_load", "N", "the profile's axial load", STATE),
    Signal("inner_ring_speed", "rad s-1", "the profile's inner-ring speed", STATE),
    Signal("applied_moment", "N m", "the profile's tilting moment", STATE),
    Signal("load_direction", "rad", "the profile's radial-load direction", STATE),
    Signal("tilt_reaction_moment", "N m", "magnitude of the moment that holds a held ring square", STATE),
    Signal("revolutions", "1", "revolutions of the inner ring over the step", STATE),
    Signal("kappa", "1", "ISO 281 viscosity ratio nu/nu1 at the step's speed (0 at standstill)", STATE),
    Signal("a_iso", "1", "ISO 281 a_ISO of the step: its kappa, e_C C_u over its ISO/TS 16281 equivalent reference "
                         "load (NaN when nothing is loaded)", STATE),
    Signal("revolutions_kappa_below_scope", "1", "revolutions of the step when its kappa is below ISO 281's 0.1, "
                                                 "else 0", STATE),
    Signal("inner_ring_ovalisation", "m", "amplitude of the inner ring's k = 2 radial mode (0 when rigid)", STATE),
    Signal("outer_ring_ovalisation", "m", "amplitude of the outer ring's k = 2 radial mode (0 when rigid)", STATE),
    Signal("drive_torque_step", "N m", "the step's drive torque, stage-weighted (the impulse the step gave)", STEP),
    Signal("drive_torque_band_limited", "N m", "the step's drive torque band-limited to "
                                                "rvcore.integrate.loop.TORQUE_BANDWIDTH", STEP),
    Signal("drive_power_step", "W", "the step's drive power, stage-weighted (the work the step's impulse did)", STEP),
    Signal("load_power_step", "W", "the work of the applied loads and of gravity on every body over the step, over "
                                   "the step: their potential's fall across it, the loads at the step's midpoint "
                                   "(rvcore.integrate.loop.integrate)", STEP),
)

#: Signals once per row of balls, from slot ``N_SIGNALS + N_ROW_SIGNALS·r``.
ROW_SIGNALS = (
    Signal("cos_contact_angle", "1", "mean cos(alpha) over the row's loaded balls (0 when none is loaded)"),
    Signal("cage_speed", "rad s-1", "the row's cage angular speed", STATE),
    Signal("epicyclic_cage_speed", "rad s-1", "0.5 (1 - D cos(alpha)/d_m) omega at the balls' actual angles", STATE),
    Signal("epicyclic_cage_speed_nominal", "rad s-1", "the same at the nominal contact angle", STATE),
    Signal("life_sum_inner", "N3", "ISO/TS 16281 inner-race life sum of the step, d_rev (1/Z) sum Q_i^3", STATE),
    Signal("life_sum_outer", "N3", "outer-race life sum of the step, d_rev ((1/Z) sum Q_o^(10/3))^0.9", STATE),
    Signal("life_sum_inner_modified", "N3", "life_sum_inner of the step over its a_iso (0 when nothing is loaded)",
           STATE),
    Signal("life_sum_outer_modified", "N3", "life_sum_outer of the step over its a_iso (0 when nothing is loaded)",
           STATE),
)
#: After the row blocks, one slot per virtual sensor: its reading [m].
SENSOR_SIGNAL = Signal("sensor_displacement", "m", "the sensor's reading", STATE)

N_SIGNALS = len(SIGNALS)
N_ROW_SIGNALS = len(ROW_SIGNALS)
SLOT = {s.name: k for k, s in enumerate(SIGNALS)}
ROW_SLOT = {s.name: k for k, s in enumerate(ROW_SIGNALS)}


def signal_count(n_rows: int, n_sensors: int) -> int:
    """Length of the diagnostics vector for ``n_rows`` rows and ``n_sensors`` sensors."""
    return N_SIGNALS + N_ROW_SIGNALS * n_rows + n_sensors


# ---- outputs ---------------------------------------------------------------------

#: Transforms from a signal (or its reduction) to the output's value; the same function
#: serves a series and its phase extremes, since each is monotone.
IDENTITY, CUBE_ROOT, ROOT_OF_POSITIVE, SIXTH_ROOT, ARCSINE_LOADED, ISO76_LOAD_RATIO = range(6)

#: Reductions over a phase window (``reduce``):
#: ``mean`` the step-average of the signal; ``max``/``min`` its extreme; ``max_time`` the
#: time of the largest; ``abs_max`` the largest magnitude; ``integral`` ∫signal dt
#: (trapezoid over the steps); ``slip`` 1 − Σsignal/Σ``other``; ``range``, ``stats_mean``,
#: ``std``, ``min_time``, ``max_time_of``, ``range_at_edge`` the running statistics of a
#: displacement (extremes with their times, Welford's mean and variance); ``finite_mean``
#: the mean over the steps where the signal is finite (a film: the steps with a loaded
#: contact); ``window_start``
#: and ``window_end`` the phase window; ``life`` the Palmgren–Miner damage of
#: :mod:`rvcore.standards.iso16281` from the life sums.
SERIES, PHASE, STEADY, DUTY_CYCLE, SPECTRUM = "series", "phase", "steady", "duty_cycle", "spectrum"


@dataclass(frozen=True)
class Output:
    """One output variable of a case.

    ``kind`` is one of :data:`SERIES` (over ``elapsed_time``), :data:`PHASE` (over
    ``phase``), :data:`STEADY` and :data:`DUTY_CYCLE` (scalars) and :data:`SPECTRUM`
    (over ``frequency`` or ``kinematic``). ``over`` adds a trailing ``row`` (one value a
    row of balls; dropped for a single row) or ``sensor`` dimension. ``group`` sorts the
    outputs for ``metrics.nc`` and the report: ``displacement``, ``kinematics``,
    ``designer``, ``stiffness``, ``rating``, ``window``.
    """

    name: str
    kind: str
    units: str
    long_name: str
    signal: str = ""
    reduce: str = ""
    transform: int = IDENTITY
    over: str = ""
    other: str = ""
    group: str = "designer"
    spectrum_dims: tuple = ()

    @property
    def dims(self) -> tuple:
        """The output's dimensions in a case file (a single row drops ``row``)."""
        base = {SERIES: ("elapsed_time",), PHASE: ("phase",), STEADY: (), DUTY_CYCLE: ()}.get(
            self.kind, self.spectrum_dims)
        return base + (("sensor",) if self.over == "sensor" else ())


def _series(name, units, long_name, signal=None, transform=IDENTITY, over="", group="designer"):
    return Output(name, SERIES, units, long_name, signal or name, transform=transform, over=over, group=group)


def _phase(name, units, long_name, signal, reduce, transform=IDENTITY, over="", other="", group="designer"):
    return Output(name, PHASE, units, long_name, signal, reduce, transform, over, other, group)


def _displacement_metrics(name, what, signal, over=""):
    """The six per-phase statistics of one displacement signal."""
    return (
        _phase(f"{name}_range", "m", f"variation range (max - min) of {what} over the phase", signal, "range",
               over=over, group="displacement"),
        _phase(f"{name}_mean", "m", f"time mean of {what} over the phase", signal, "stats_mean", over=over,
               group="displacement"),
        _phase(f"{name}_std", "m", f"standard deviation of {what} over the phase", signal, "std", over=over,
               group="displacement"),
        _phase(f"{name}_min_time", "s", f"elapsed time at which {what} is smallest in the phase", signal,
               "min_time", over=over, group="displacement"),
        _phase(f"{name}_max_time", "s", f"elapsed time at which {what} is largest in the phase", signal,
               "max_time_of", over=over, group="displacement"),
        _phase(f"{name}_range_at_edge", "1", f"1 where an extreme of {what} lies within one output interval of "
                                            "the phase window's edge (the range may be cut off by the window)",
               signal, "range_at_edge", over=over, group="displacement"),
    )


_HELD = "(inner_ring.tilt = held; 0 when the tilt is free)"
_FILM = ("(each contact's own Hertz ellipse, load and entrainment speed; fully flooded, isothermal: an upper bound "
         "under grease; NaN when no contact is loaded)")

OUTPUTS = (
    # ---- time series, sampled at the output rate
    _series("radial_displacement", "m", "inner-ring displacement along the radial-load direction (delta_r)",
            group="displacement"),
    _series("axial_displacement", "m", "inner-ring displacement along the axial-load direction (delta_a)",
            group="displacement"),
    _series("inner_ring_x", "m", "inner-ring centre x", group="displacement"),
    _series("inner_ring_y", "m", "inner-ring centre y", group="displacement"),
    _series("inner_ring_z", "m", "inner-ring centre z (axial)", group="displacement"),
    _series("inner_ring_tilt_x", "rad", "inner-ring tilt about x", group="displacement"),
    _series("inner_ring_tilt_y", "rad", "inner-ring tilt about y", group="displacement"),
    _series("applied_radial_load", "N", "radial load applied by the profile", group="kinematics"),
    _series("applied_axial_load", "N", "axial load applied by the profile", group="kinematics"),
    _series("inner_ring_speed", "rad s-1", "prescribed inner-ring angular speed", group="kinematics"),
    _series("cage_speed", "rad s-1", "cage angular speed", over="row", group="kinematics"),
    _series("max_inner_contact_load", "N", "largest ball to inner-race normal force"),
    _series("max_outer_contact_load", "N", "largest ball to outer-race normal force"),
    _series("loaded_ball_count", "1", "number of balls carrying more than 1 N on both the inner and the outer "
                                      "race (rvcore.contact.laws.LOADED_BALL_LOAD)"),
    _series("max_contact_pressure", "Pa", "largest Hertz contact pressure", "max_contact_pressure_cubed", CUBE_ROOT),
    _series("applied_moment", "N m", "tilting moment applied by the profile, about the axis normal to the radial "
                                     "load", group="kinematics"),
    _series("load_direction", "rad", "direction of the radial load applied by the profile, from +x",
            group="kinematics"),
    _series("inner_ring_drive_torque", "N m", "moment about the inner ring's spin axis that the prescribed spin "
                                              "needs: polar inertia times the prescribed angular acceleration "
                                              "minus the contact forces' moment on the ring about that axis",
            "drive_torque"),
    _series("friction_power", "W", "power dissipated by friction at every ball-race, ball-pocket and cage-land "
                                   "contact, summed (sum of |F_t . v_slip|)"),
    _series("max_pocket_force", "N", "largest ball-pocket normal force (all rows)"),
    _series("cage_land_force", "N", "cage-land normal force (the largest over rows)"),
    _series("max_race_sliding_speed", "m s-1", "largest sliding speed at a loaded ball-race contact",
            "max_race_sliding_speed_squared", ROOT_OF_POSITIVE),
    _series("max_race_pv", "Pa m s-1", "largest product of the Hertz peak pressure and the sliding speed at a "
                                       "ball-race contact", "max_race_pv_sixth", SIXTH_ROOT),
    _series("min_contact_angle", "rad", "smallest contact angle of the loaded ball-race contacts, from the "
                                        "bearing's radial plane (NaN when none is loaded)",
            "sin_contact_angle_min", ARCSINE_LOADED),
    _series("max_contact_angle", "rad", "largest contact angle of the loaded ball-race contacts, from the "
                                        "bearing's radial plane (NaN when none is loaded)",
            "sin_contact_angle_max", ARCSINE_LOADED),
    _series("static_safety_factor", "1", "ISO 76 static safety factor s0 = C0/P0 from the Hertz pressure: "
                                         "(4200 MPa / largest ball-race Hertz pressure)^3 (radial ball bearings; "
                                         "NaN when no ball-race contact is loaded)",
            "max_race_pressure_cubed", ISO76_LOAD_RATIO),
    _series("tilt_reaction_moment_x", "N m", f"moment about x that the support applies to hold the inner ring's "
                                             f"tilt at 0 {_HELD}"),
    _series("tilt_reaction_moment_y", "N m", f"moment about y that the support applies to hold the inner ring's "
                                             f"tilt at 0 {_HELD}"),
    _series("sensor_displacement", "m", "inner-ring displacement read by each virtual sensor along its direction "
                                        "(a flexible inner ring's surface deformation included)",
            over="sensor", group="displacement"),
    _series("film_parameter", "1", f"smallest film parameter lambda = h_min/sigma over the loaded ball-race "
                                   f"contacts {_FILM}", group="lubrication"),
    _series("kappa", "1", "ISO 281 viscosity ratio kappa = nu/nu1 at the inner ring's speed (nu1 of ISO 281 "
                          "9.3.3 at n = |omega|; 0 at standstill)", group="lubrication"),
    _series("max_ring_radial_deformation", "m", "largest radial displacement (magnitude) of a flexible ring's "
                                                "raceway at a ball, relative to its support, either ring (0 when "
                                                "both rings are rigid)", group="displacement"),
    _series("max_ring_axial_deformation", "m", "largest axial displacement (magnitude) of a flexible ring's raceway "
                                               "at a ball, relative to its support, either ring (0 when both rings "
                                               "are rigid)", group="displacement"),
    _series("inner_ring_ovalisation", "m", "amplitude sqrt(a_c^2 + a_s^2) of the inner ring's ovalisation, its "
                                           "k = 2 radial mode (0 when rigid)", group="displacement"),
    _series("outer_ring_ovalisation", "m", "amplitude sqrt(a_c^2 + a_s^2) of the outer ring's ovalisation, its "
                                           "k = 2 radial mode (0 when rigid)", group="displacement"),

    # ---- phase metrics, reduced at every integrator step
    *_displacement_metrics("radial_displacement", "delta_r at the ring centre", "radial_displacement"),
    *_displacement_metrics("axial_displacement", "delta_a at the ring centre", "axial_displacement"),
    *_displacement_metrics("sensor_displacement", "the sensor reading", "sensor_displacement", over="sensor"),
    _phase("max_ring_radial_deformation_peak", "m", "largest radial displacement (magnitude) of a flexible ring's "
                                                    "raceway at a ball over the phase (0 when rigid)",
           "max_ring_radial_deformation", "max", group="displacement"),
    _phase("max_ring_axial_deformation_peak", "m", "largest axial displacement (magnitude) of a flexible ring's "
                                                   "raceway at a ball over the phase (0 when rigid)",
           "max_ring_axial_deformation", "max", group="displacement"),
    _phase("inner_ring_ovalisation_peak", "m", "largest amplitude of the inner ring's ovalisation over the phase "
                                               "(0 when rigid)", "inner_ring_ovalisation", "max", group="displacement"),
    _phase("outer_ring_ovalisation_peak", "m", "largest amplitude of the outer ring's ovalisation over the phase "
                                               "(0 when rigid)", "outer_ring_ovalisation", "max", group="displacement"),
    _phase("cage_speed_mean", "rad s-1", "time mean of the cage speed over the phase", "cage_speed", "mean",
           over="row", group="kinematics"),
    _phase("inner_ring_speed_mean", "rad s-1", "time mean of the inner-ring speed over the phase",
           "inner_ring_speed", "mean", group="kinematics"),
    _phase("epicyclic_cage_speed", "rad s-1", "time mean of the epicyclic cage speed 0.5*(1 - D*cos(alpha)/d_m)*"
                                              "omega at the loaded balls' actual mean cos(alpha)",
           "epicyclic_cage_speed", "mean", over="row", group="kinematics"),
    _phase("cage_slip", "1", "1 - mean cage speed / epicyclic cage speed at the balls' actual contact angles "
                             "(0: rolling without slip)", "cage_speed", "slip", over="row",
           other="epicyclic_cage_speed", group="kinematics"),
    _phase("cage_slip_nominal", "1", "1 - mean cage speed / epicyclic cage speed at the nominal contact angle",
           "cage_speed", "slip", over="row", other="epicyclic_cage_speed_nominal", group="kinematics"),
    _phase("peak_contact_pressure", "Pa", "largest Hertz contact pressure over the phase",
           "max_contact_pressure_cubed", "max", CUBE_ROOT, group="kinematics"),
    _phase("inner_ring_drive_torque_peak", "N m", "largest magnitude over the phase of the inner-ring drive torque "
                                                  "band-limited to 1 kHz", "drive_torque_band_limited", "abs_max"),
    _phase("inner_ring_drive_torque_mean", "N m", "time mean of the inner-ring drive torque over the phase",
           "drive_torque_step", "mean"),
    _phase("friction_power_mean", "W", "time mean of the friction power over the phase", "friction_power", "mean"),
    _phase("friction_energy", "J", "energy dissipated by friction over the phase (integral of the friction power)",
           "friction_power", "integral"),
    _phase("max_pocket_force_peak", "N", "largest ball-pocket normal force over the phase", "max_pocket_force",
           "max"),
    _phase("cage_land_force_peak", "N", "largest cage-land normal force over the phase", "cage_land_force", "max"),
    _phase("max_race_sliding_speed_peak", "m s-1", "largest ball-race sliding speed over the phase",
           "max_race_sliding_speed_squared", "max", ROOT_OF_POSITIVE),
    _phase("max_race_pv_peak", "Pa m s-1", "largest ball-race Hertz peak pressure times sliding speed over the "
                                           "phase", "max_race_pv_sixth", "max", SIXTH_ROOT),
    _phase("contact_angle_min", "rad", "smallest contact angle of a loaded ball-race contact over the phase",
           "sin_contact_angle_min", "min", ARCSINE_LOADED),
    _phase("contact_angle_max", "rad", "largest contact angle of a loaded ball-race contact over the phase",
           "sin_contact_angle_max", "max", ARCSINE_LOADED),
    _phase("static_safety_factor_min", "1", "smallest ISO 76 static safety factor s0 = (4200 MPa / peak ball-race "
                                            "Hertz pressure)^3 over the phase", "max_race_pressure_cubed", "max",
           ISO76_LOAD_RATIO),
    _phase("static_safety_factor_min_time", "s", "elapsed time at which the static safety factor is smallest in "
                                                 "the phase", "max_race_pressure_cubed", "max_time",
           ISO76_LOAD_RATIO),
    _phase("tilt_reaction_moment_mean", "N m", "time mean over the phase of the magnitude of the moment that holds "
                                               "the inner ring's tilt at 0 (0 when the tilt is free)",
           "tilt_reaction_moment", "mean"),
    _phase("tilt_reaction_moment_peak", "N m", "largest magnitude over the phase of the moment that holds the "
                                               "inner ring's tilt at 0 (0 when the tilt is free)",
           "tilt_reaction_moment", "max"),
    *(_phase(f"film_thickness_{what}_{red}", "m", f"{word} over the phase of the smallest Hamrock-Dowson {what} "
             f"film over the loaded ball-race contacts at each integrator step {_FILM}", f"film_{what}",
             {"min": "min", "mean": "finite_mean"}[red], group="lubrication")
      for what in ("central", "minimum") for red, word in (("min", "smallest value"), ("mean", "mean"))),
    _phase("film_parameter_min", "1", f"smallest film parameter lambda = h_min/sigma over the loaded ball-race "
                                      f"contacts and the phase's steps {_FILM}", "film_parameter", "min",
           group="lubrication"),
    _phase("film_parameter_mean", "1", "time mean over the phase of the smallest film parameter lambda = h_min/sigma "
                                       "over the loaded ball-race contacts (boundary < 1 <= mixed < 3 <= full film)",
           "film_parameter", "finite_mean", group="lubrication"),
    _phase("kappa_min", "1", "smallest ISO 281 viscosity ratio kappa = nu/nu1 over the phase (below 0.1: outside "
                             "ISO 281, a_ISO taken at 0.1)", "kappa", "min", group="lubrication"),
    _phase("kappa_mean", "1", "time mean of the ISO 281 viscosity ratio kappa = nu/nu1 over the phase", "kappa",
           "mean", group="lubrication"),
    _phase("fatigue_damage", "1", "Palmgren-Miner fatigue damage accumulated in the phase per cycle of the profile "
                                  "(ISO/TS 16281 contact loads at every integrator step)", "", "life"),
    _phase("phase_start", "s", "start of the phase window", "", "window_start", group="window"),
    _phase("phase_end", "s", "end of the phase window", "", "window_end", group="window"),

    # ---- at the steady operating point, from the statics there (rvcore.statics.operating)
    Output("radial_stiffness", STEADY, "N m-1", "radial stiffness at the steady operating point, direct term K_rr "
           "of the quasi-static tangent stiffness along the radial load: every other coordinate held",
           group="stiffness"),
    Output("axial_stiffness", STEADY, "N m-1", "axial stiffness at the steady operating point, direct term K_aa "
           "of the quasi-static tangent stiffness along the axis: every other coordinate held", group="stiffness"),
    Output("tilting_stiffness", STEADY, "N m rad-1", "tilting stiffness at the steady operating point, direct term "
           "of the quasi-static tangent stiffness about the axis normal to the radial load: every other coordinate "
           "held", group="stiffness"),
    Output("radial_stiffness_compliant", STEADY, "N m-1", "radial stiffness at the steady operating point with "
           "every other coordinate free, 1/C_rr of the compliance C = K^-1 (a held ring's tilts stay held)",
           group="stiffness"),
    Output("axial_stiffness_compliant", STEADY, "N m-1", "axial stiffness at the steady operating point with every "
           "other coordinate free, 1/C_aa of the compliance C = K^-1 (a held ring's tilts stay held)",
           group="stiffness"),
    Output("tilting_stiffness_compliant", STEADY, "N m rad-1", "tilting stiffness at the steady operating point "
           "with every other coordinate free, 1/C of the compliance C = K^-1 (NaN for a held ring)",
           group="stiffness"),
    Output("static_safety_factor_steady", STEADY, "1", "ISO 76 static safety factor s0 = (4200 MPa / p_max)^3 from "
           "the peak ball-race Hertz pressure of the statics at the steady operating point", group="rating"),
    Output("static_safety_factor_catalogue", STEADY, "1", "ISO 76 static safety factor s0 = C0r/P0r by the "
           "catalogue formula at the steady loads: C0r = f0 i Z Dw^2 cos(alpha) (ISO 76 Table 1 f0, reduced by "
           "the 4200 MPa definition where the groove radii exceed 0.52/0.53 Dw), P0r = max(X0 Fr + Y0 Fa, Fr) "
           "(NaN: not rated)", group="rating"),
    Output("friction_moment_palmgren", STEADY, "N m", "Palmgren's estimate of the bearing's friction moment at the "
           "steady operating point, M = f1 F_beta d_m + M_v (Palmgren's constants as Harris & Kotzalas tabulate "
           "them: the deep-groove row, or the angular-contact row for 30-40 deg at any angle; other published sets "
           "differ by about +-35 %; load and viscous terms; NaN where it does not apply: pairs, four-point rows)", group="rating"),
    Output("friction_moment_palmgren_load", STEADY, "N m", "load term f1 F_beta d_m of Palmgren's friction moment "
           "at the steady operating point", group="rating"),
    Output("friction_moment_palmgren_viscous", STEADY, "N m", "viscous term M_v of Palmgren's friction moment at "
           "the steady speed, with the bearing's lubricant viscosity", group="rating"),
    Output("statically_stable", STEADY, "1", "1 where the quasi-static tangent stiffness at the steady operating "
           "point is positive definite over the ring's free coordinates (it returns from any small displacement), "
           "0 where it is not: the ring rocks away, as a single deep-groove row free to tilt does",
           group="stiffness"),
    Output("basic_rating_life_L10", STEADY, "1", "ISO 281 basic rating life L10 = (C_r/P_r)^3 at the steady "
           "operating point, in revolutions of the inner ring (90 % reliability, no life modification factor; NaN: "
           "not rated or nothing loaded; not rated where the groove radii exceed ISO 281's 0.52/0.53 Dw and the "
           "bearing file gives no C_r)", group="rating"),
    Output("reference_rating_life_L10r", STEADY, "1", "ISO/TS 16281 basic reference rating life L10r from the ball "
           "loads of the statics at the steady operating point, in revolutions of the inner ring (90 % reliability, "
           "no life modification factor; NaN: not rated or nothing loaded; not rated where the groove radii exceed "
           "ISO 281's 0.52/0.53 Dw and the bearing file gives no C_r)", group="rating"),
    Output("modified_rating_life_L_nm", STEADY, "1", "ISO 281:2007 clause 9 modified rating life L_nm = a_1 a_ISO "
           "L10 at the steady operating point, in revolutions of the inner ring: basic_rating_life_L10 times a_ISO "
           "(lubrication by kappa, contamination e_C, fatigue load limit C_u; a_1 = 1, 90 % reliability); L10 "
           "includes none of them, L10r the ball-load distribution but no a_ISO (NaN: not rated, nothing loaded or "
           "no speed)", group="rating"),
    Output("a_iso_steady", STEADY, "1", "ISO 281 life modification factor a_ISO for ball bearings at the steady "
           "operating point (kappa limited to 0.1-4, capped at 50; the EP rule where the lubricant has EP "
           "additives)", group="rating"),
    Output("kappa_steady", STEADY, "1", "ISO 281 viscosity ratio kappa = nu/nu1 at the steady speed: the "
           "lubricant's operating viscosity over the reference viscosity nu1 (not limited; below 0.1 outside ISO "
           "281: boundary lubrication)", group="rating"),
    Output("operating_viscosity", STEADY, "m2 s-1", "kinematic viscosity of the lubricant (a grease: its base oil) "
           "at the operating temperature, the mean of the ring temperatures (ASTM D341 / Walther; or the bearing "
           "file's override)", group="rating"),
    Output("film_thickness_min_steady", STEADY, "m", "Hamrock-Dowson minimum film thickness of the heaviest-loaded "
           "inner contact at the steady operating point, pure rolling, fully flooded and isothermal: an upper "
           "bound under grease (starvation); measured films scatter about +-30 % around it", group="rating"),
    Output("film_parameter_steady", STEADY, "1", "film parameter lambda = h_min/sigma of the heaviest-loaded inner "
           "contact at the steady operating point (sigma the composite rms roughness; boundary < 1 <= mixed < 3 "
           "<= full film)", group="rating"),
    Output("operating_clearance", STEADY, "m", "radial internal clearance of rows[0] at the rings' operating "
           "temperatures (thermal expansion from the file's clearance at its reference temperature); the "
           "statics and the dynamics use it", group="rating"),
    Output("ring_mode_truncation", STEADY, "1", "flexible rings' truncation figure: the largest relative change "
           "of the radial and axial displacement and of the largest ball load Q_max of the flexible-ring statics at "
           "the steady operating point when the rings keep the dynamics' Fourier orders (0 to 6) instead of every "
           "order of the bearing file's max_order (each relative to its value with every order, a displacement's "
           "to at least a tenth of the ring's whole displacement; above 0.02 the orders the dynamics keep are not "
           "converged for the rings' seats; NaN for rigid rings)"),

    # ---- the duty cycle's life, from the integrator's life sums (rvcore.standards.iso16281)
    Output("rating_life_L10r", DUTY_CYCLE, "1", "ISO/TS 16281 reference rating life L10r of the duty cycle, in "
           "revolutions of the inner ring (Palmgren-Miner over the integrator steps; NaN where the groove radii "
           "exceed ISO 281's 0.52/0.53 Dw and the bearing file gives no C_r)", group="rating"),
    Output("rating_life_cycles", DUTY_CYCLE, "1", "ISO/TS 16281 reference rating life L10r of the duty cycle, in "
           "cycles of the profile", group="rating"),
    Output("fatigue_damage_cycle", DUTY_CYCLE, "1", "Palmgren-Miner fatigue damage of one cycle of the profile "
           "(1/rating_life_cycles)", group="rating"),
    Output("rating_life_L_nm", DUTY_CYCLE, "1", "ISO 281 clause 9 modified rating life L_nm = a_1 a_ISO L10 of the "
           "duty cycle on ISO/TS 16281's basis (its modified reference rating life L_nmr = a_1 a_ISO L10r), in "
           "revolutions of the inner ring: Palmgren-Miner over the integrator steps, each step's ring damages "
           "divided by its a_ISO (kappa at the step's speed, e_C C_u over the step's equivalent reference load "
           "C_r L10r_step^(-1/3)), combined as rating_life_L10r; a_1 = 1 (90 % reliability); NaN: not rated",
           group="rating"),
    Output("a_iso_cycle", DUTY_CYCLE, "1", "the duty cycle's damage-weighted a_ISO, rating_life_L_nm / "
           "rating_life_L10r", group="rating"),
    Output("kappa_below_scope_fraction", DUTY_CYCLE, "1", "fraction of the cycle's revolutions run at kappa < 0.1, "
           "outside ISO 281's a_ISO (boundary lubrication; there a_ISO is taken at kappa = 0.1, about 0.1)",
           group="rating"),

    # ---- the steady phase's spectra (rvcore.recording.spectra)
    Output("kinematic_frequency", SPECTRUM, "Hz", "the bearing's kinematic frequencies at the steady speed (rolling "
           "without slip at the nominal contact angle): shaft, cage, outer and inner ball pass, ball spin, and "
           "twice each", group="spectrum", spectrum_dims=("kinematic",)),
    *(Output(f"{n}_spectrum", SPECTRUM, "m", f"single-sided amplitude spectrum of {w} over the steady phase (mean "
             "removed, Hann window; a sinusoid of amplitude A at a bin centre reads A, between bins down to 0.85 A: read tone amplitudes from *_kinematic_amplitude)", group="spectrum",
             spectrum_dims=("frequency",)) for n, w in (("radial_displacement", "delta_r"),
                                                        ("axial_displacement", "delta_a"))),
    *(Output(f"{n}_kinematic_amplitude", SPECTRUM, "m", f"amplitude of {w} at each kinematic frequency, steady "
             "phase: a least-squares sinusoid fit at that frequency (Hann-weighted), exact for a clean tone between "
             "bins", group="spectrum", spectrum_dims=("kinematic",))
      for n, w in (("radial_displacement", "delta_r"), ("axial_displacement", "delta_a"))),
    Output("sensor_displacement_spectrum", SPECTRUM, "m", "single-sided amplitude spectrum of each sensor's reading "
           "over the steady phase (mean removed, Hann window; a sinusoid of amplitude A at a bin centre reads A, between bins down to 0.85 A: read tone amplitudes from *_kinematic_amplitude)", over="sensor",
           group="spectrum", spectrum_dims=("frequency",)),
    Output("sensor_displacement_kinematic_amplitude", SPECTRUM, "m", "amplitude of each sensor's reading at each "
           "kinematic frequency, steady phase: a least-squares sinusoid fit at that frequency (Hann-weighted)", over="sensor", group="spectrum",
           spectrum_dims=("kinematic",)),
)

#: The rows by name.
OUTPUT = {o.name: o for o in OUTPUTS}


def outputs_of(kind: str, *, over: str | None = None, group: str | None = None) -> tuple:
    """The rows of ``kind`` (and of ``over`` / ``group`` where given), in table order."""
    return tuple(o for o in OUTPUTS if o.kind == kind and (over is None or o.over == over)
                 and (group is None or o.group == group))


def units_and_long_names(kind: str, *, over: str | None = None) -> dict:
    """name -> (units, long_name) of the rows of ``kind``."""
    return {o.name: (o.units, o.long_name) for o in outputs_of(kind, over=over)}


def _check_table() -> None:
    """Every output names a known signal: a typo in a row fails at import, not mid-run."""
    known = set(SLOT) | set(ROW_SLOT) | {SENSOR_SIGNAL.name, ""}
    for o in OUTPUTS:
        for name in (o.signal, o.other):
            if name not in known:
                raise ValueError(f"rvcore.output_table: output {o.name!r} names an unknown signal {name!r}")
    if len(OUTPUT) != len(OUTPUTS):
        raise ValueError("rvcore.output_table: an output name appears twice")


_check_table()
