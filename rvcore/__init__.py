"""rvcore: contact dynamics of RV-reducer main bearings. SI in, SI out; no I/O, no dask.

The map of the code: one sub-package a concept, one job a module (docs/model.md describes
the model they implement). The layers, lowest first: ``_numba``, ``hertz``, ``standards``,
``output_table``, ``bearing``, ``rings``, ``contact``, ``profile``, ``dynamics``, ``statics``,
``recording``, ``integrate``, ``simulation``. A module imports only from its own layer
and those below it; ``hertz`` only from ``_numba``, and ``standards`` only from ``_numba`` and
``hertz``; within a layer, no two modules import each other, directly or around a circle
(``tests/test_structure.py``, which holds pipeline to the same).

Shared
- ``_numba``                   the one kernel decorator (flags, error model) and numba's cache, one directory per version of the sources
- ``output_table``             the one table of outputs and the per-step signals they come from
- ``profile``                  service-cycle breakpoint tables (the run protocol as data)
- ``hertz``                    Hertz point-contact constants from the elliptic integrals (the theory ISO 76's C0 and the contact laws share)

``standards``: ISO standards and catalogue methods (imports nothing of rvcore but ``_numba`` and ``hertz``)
- ``standards.iso281``         ISO 281 load rating, equivalent load and L10; the rating geometry
- ``standards.iso281_modified`` ISO 281 clause 9: ν1, κ, C_u, a_ISO, L_nm and its duty-cycle sum
- ``standards.iso16281``       ISO/TS 16281 reference rating life, static and over a duty cycle
- ``standards.iso76``          ISO 76 static load rating and safety factor
- ``standards.iso492``         ISO 492 runout and ISO 3290 ball grades (tables with their sources)
- ``standards.palmgren``       Palmgren's friction moment
- ``standards.inputs``         the one check of a formula's input: a finite number > 0, else the caller's error

``bearing``: a bearing as data
- ``bearing.geometry``         bearing, rows, groove arcs, cages, materials (frozen dataclasses)
- ``bearing.imperfections``    eccentricities, waviness, ball sizes; a tolerance class realized from a seed
- ``bearing.lubricant``        ISO VG grades, Walther's viscosity-temperature law, roughness; a bearing's operating viscosity and contact lubricant
- ``bearing.thermal``          the operating clearance: the rows' clearance at the rings' temperatures
- ``bearing.checks``           the geometry checks: what makes a bearing unbuildable, as problems with a kind
- ``bearing.laws``             the friction law as data: its name and its record of parameters
- ``bearing.layout``           a Bearing compiled into flat arrays for the numba kernels

``rings``: flexible rings, their theory (issue 41; from the bearing file into the statics and, as states, the dynamics; rigid by default)
- ``rings.section``            a ring's section from its envelope and grooves, or given: area, centroid, second moments, torsion constant
- ``rings.modes``              thin-ring Fourier modes, in plane and out of plane with twist: modal masses, stiffnesses, damping
- ``rings.support``            what holds a ring: an elastic foundation, or a housing ring through a seat; the supported modes
- ``rings.deflection``         a ring's static deflection under point loads by the Fourier sum over its modes
- ``rings.flexible``           a bearing's rings each rigid or flexible in its support (``bearing_rings``); their raceways' displacements and deformation

``contact``: the contact laws
- ``contact.step``             the cubic STEP, the one smooth transition of the laws and the profiles
- ``contact.laws``             every contact law once: Hertz with its damper, friction dispatched on the law's kind, penetrations
- ``contact.coulomb_step``     the study's friction law (Coulomb with STEP transitions), its slopes and IMEX tangent
- ``contact.pose``             the inner ring's rotation, angular velocity and frame
- ``contact.film``             Hamrock–Dowson film thickness and λ at a contact
- ``contact.traction_ehl``     a lubricated traction law, Bair–Winer limiting shear (not yet registered)

``dynamics``: the equations of motion
- ``dynamics.raceway``         an imperfect raceway's radial shift and slope at a contact; its turned angle
- ``dynamics.races``           the ball contacts of a row, every ball at once (the vectorised passes)
- ``dynamics.ring_modes``      a flexible ring's Fourier modes as states: the raceway's displacement at a ball, the forces that drive them
- ``dynamics.rhs``             the right-hand side
- ``dynamics.tangent``         the stiff velocity tangent of the contacts (the IMEX scheme's blocks)
- ``dynamics.energy``          kinetic and potential energy (the conservation checks)

``statics``: rigid-ring statics
- ``statics.equilibrium``      the inner ring's equilibrium under radial, axial and moment loads, on rigid or flexible rings
- ``statics.stiffness``        the tangent stiffness of the equilibrium
- ``statics.preload``          mirrored pairs and the offset that gives a preload
- ``statics.operating``        the steady operating point and the statics there
- ``statics.runout``           the runout path of an imperfect bearing over a revolution
- ``statics.lubrication``      κ, a_ISO, L_nm and the film at an equilibrium (ISO 281 clause 9, Hamrock–Dowson)
- ``statics.flexible``         the statics on flexible rings beside the rigid rings': the numbers compared, the rings' deformation

``recording``: what a case records
- ``recording.plan``           the output table as index arrays: series columns, phase reductions, life sums
- ``recording.results``        CaseResult and the metrics read back from the accumulators
- ``recording.spectra``        the steady phase's spectra and kinematic frequencies

``integrate``: time integration
- ``integrate.loop``           the loop: steps, blow-up checks, output lines, reductions; it knows no method
- ``integrate.methods``        ``METHODS``: the methods by name, their steps by name, and the kernels the loop calls them through
- ``integrate.protocol``       what a method module supplies; the counters it shares with the loop
- ``integrate.step_size``      why a fixed step; the bearing's rates each method's step comes from
- ``integrate.rk4``            one step of classical RK4 (the reference), its stability limits and step
- ``integrate.imex``           one step of the implicit–explicit scheme, its step and its checks' tolerances
- ``integrate.arrowhead``      the scheme's block-arrowhead matrix factored and solved
- ``integrate.pocket_check``   the IMEX step's check on the cage-pocket impacts' energy
- ``integrate.schedule``       the step schedule: a longer step where the loads and speed are held, and in the unload

``simulation``: one dynamic case
- ``simulation.settings``      SolverSettings and Sensor
- ``simulation.initial_state`` the state a case starts from; the peak contact load
- ``simulation.run``           ``run_case``: the one entry point for a dynamic case
- ``simulation.shared_start``  the start before the ring turns, which a grid's speeds share

The public API, importable from ``rvcore`` itself: :data:`PUBLIC`.
"""

#: Version of the model's equations and numerics. Part of every case id
#: (:mod:`pipeline.schema.sweepfile`): bump it when a change to ``rvcore`` changes results,
#: so that resumed sweeps recompute every case. What each version changed is in CHANGELOG.md.
MODEL_VERSION = 24

from ._numba import use_source_keyed_cache

# numba checks a cached kernel only against its own file's timestamp, so a kernel that
# inlines a function from another module (integrate -> rhs -> contact laws) would keep
# the old code after that module changed: every version of the sources caches in a
# directory of its own (rvcore._numba), set before any kernel module is imported.
use_source_keyed_cache()

#: The names ``rvcore`` itself offers, and the module each lives in (imported on first use,
#: so ``import rvcore`` stays light).
PUBLIC = {
    "Bearing": "bearing.geometry", "Profile": "profile", "OperatingPoint": "profile",
    "SolverSettings": "simulation.settings", "Sensor": "simulation.settings",
    "run_case": "simulation.run", "CaseResult": "recording.results", "SimulationError": "recording.results",
    "solve_statics": "statics.equilibrium",
}


def __getattr__(name):
    if name in PUBLIC:
        import importlib

        return getattr(importlib.import_module(f"rvcore.{PUBLIC[name]}"), name)
    raise AttributeError(f"module 'rvcore' has no attribute {name!r}")
