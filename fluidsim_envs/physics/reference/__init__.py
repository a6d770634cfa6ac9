"""Reference models the tests and benchmarks check the simulator against; the simulator itself
imports none of them.

- :mod:`~fluidsim_envs.physics.reference.savitsky`: Savitsky's (1964) planing-hull method, the
  running trim and resistance of a prismatic hull in closed form.
- :mod:`~fluidsim_envs.physics.reference.tetra`: a rigid body as four point masses (the
  tetrahedron of the ``verlet_tetra`` integrator), in NumPy: ``match_inertia`` and the momenta.
"""
