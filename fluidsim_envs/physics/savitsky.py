"""Moved to :mod:`fluidsim_envs.physics.reference.savitsky`; this name stays for one release."""

from fluidsim_envs.physics.reference.savitsky import (  # noqa: F401
    PlaningState,
    PrismaticHull,
    savitsky,
    savitsky_at_trim,
    savitsky_sweep,
)
