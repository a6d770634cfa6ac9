"""BoatOnStep-v0's task kernels and layouts.

Moved to ``fluidsim_envs.scenes.boat_on_step.kernel``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.boat_on_step.kernel instead.
from ..scenes.boat_on_step.kernel import *  # noqa: F401, F403
