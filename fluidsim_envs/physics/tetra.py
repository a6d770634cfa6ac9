"""The tetrahedron helpers live in :mod:`fluidsim_envs.physics.reference.tetra`; ``match_inertia``
(and, for one release, the others) stay importable from here."""

from fluidsim_envs.physics.reference.tetra import (  # noqa: F401
    VERTICES,
    match_inertia,
    momenta,
    particle_velocities,
    second_moment,
)
