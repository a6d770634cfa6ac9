"""BoatOnStep-v0's scripted pilot. Moved to ``fluidsim_envs.scenes.boat_on_step.pilot``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.boat_on_step.pilot instead.
from ..scenes.boat_on_step.pilot import *  # noqa: F401, F403
