"""rvcore: contact dynamics of RV-reducer main bearings. SI in, SI out; no I/O, no dask.

Modules, one domain each:

- ``geometry``    bearing, rows, groove arcs, materials (frozen dataclasses)
- ``hertz``       Hertz point-contact constants from the elliptic integrals
- ``model``       a Bearing compiled into flat arrays for the numba kernels
- ``kernels``     numba contact laws, friction law and equations of motion
- ``integrator``  numba fixed-step RK4 with phase accumulators
- ``profile``     service-cycle breakpoint tables (the run protocol as data)
- ``quasistatic`` rigid-ring equilibrium under radial, axial and moment loads
- ``driver``      ``run_case``: the one entry point for a dynamic case
"""

from ._cache import use_source_keyed_cache

# numba checks a cached kernel only against its own file's timestamp, so a kernel that
# inlines a function from another module (integrate -> rhs -> contact laws) would keep
# the old code after that module changed: every version of the sources caches in a
# directory of its own (rvcore._cache), set before any kernel module is imported.
use_source_keyed_cache()
