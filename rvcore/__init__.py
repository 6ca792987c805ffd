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
