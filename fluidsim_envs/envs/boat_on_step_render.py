"""BoatOnStep-v0's frames. Moved to ``fluidsim_envs.scenes.boat_on_step.view``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.boat_on_step.view instead.
from ..scenes.boat_on_step.view import *  # noqa: F401, F403
