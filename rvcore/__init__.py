"""rvcore: contact dynamics of RV-reducer main bearings. SI in, SI out; no I/O, no dask.

Modules, one job each (docs/model.md describes the model they implement):

Physics
- ``geometry``        bearing, rows, groove arcs, cages, materials (frozen dataclasses)
- ``hertz``           Hertz point-contact constants from the elliptic integrals
- ``contact``         every contact law once: STEP, Hertz with its damper, friction, penetrations
- ``friction_law``    the friction law as data: its name and its record of parameters
- ``ring_pose``       the inner ring's rotation, angular velocity and frame
- ``raceway``         an imperfect raceway's radial shift and slope at a contact; its turned angle
- ``imperfections``   eccentricities, waviness, ball sizes; a tolerance class realized from a seed
- ``tolerances``      ISO 492 runout and ISO 3290 ball grades (tables with their sources)
- ``model``           a Bearing compiled into flat arrays for the numba kernels
- ``kernels``         the equations of motion (the right-hand side)
- ``races``           the ball contacts of a row, every ball at once (the vectorised passes)
- ``implicit``        the stiff velocity tangent of the contacts (the IMEX scheme's blocks)
- ``energy``          kinetic and potential energy (the conservation checks)
- ``profile``         service-cycle breakpoint tables (the run protocol as data)
- ``quasistatic``     rigid-ring equilibrium under radial, axial and moment loads
- ``stiffness``       the tangent stiffness of the equilibrium
- ``preload``         mirrored pairs and the offset that gives a preload
- ``operating``       the steady operating point and the statics there
- ``runout``          the runout path of an imperfect bearing over a revolution

Ratings
- ``iso281``          ISO 281 load rating, equivalent load and L10
- ``life``            ISO/TS 16281 reference rating life, static and over a duty cycle
- ``static_rating``   ISO 76 static load rating and safety factor
- ``friction_moment`` Palmgren's friction moment

Numerics and the case
- ``outputs``         the one table of outputs and the per-step signals they come from
- ``accumulate``      the table as index arrays: series columns, phase reductions
- ``timestep``        each integrator's fixed step from the bearing's rates
- ``rk4``             one step of classical RK4 (the reference)
- ``imex``            one step of the implicit–explicit scheme
- ``arrowhead``       the scheme's block-arrowhead matrix factored and solved
- ``pocket_check``    the IMEX step's check on the cage-pocket impacts' energy
- ``integrator``      the loop: steps, blow-up checks, output lines, reductions
- ``initial_state``   the state a case starts from; the peak contact load
- ``settings``        SolverSettings and Sensor
- ``results``         CaseResult and the metrics read back from the accumulators
- ``spectra``         the steady phase's spectra and kinematic frequencies
- ``driver``          ``run_case``: the one entry point for a dynamic case
- ``numba_cache``     numba's cache of the kernels, one directory per version of the sources
"""

from .numba_cache import use_source_keyed_cache

# numba checks a cached kernel only against its own file's timestamp, so a kernel that
# inlines a function from another module (integrate -> rhs -> contact laws) would keep
# the old code after that module changed: every version of the sources caches in a
# directory of its own (rvcore.numba_cache), set before any kernel module is imported.
use_source_keyed_cache()
