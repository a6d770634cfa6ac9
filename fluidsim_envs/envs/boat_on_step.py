"""BoatOnStep-v0: the env. Moved to ``fluidsim_envs.scenes.boat_on_step.env``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.boat_on_step.env instead.
from ..scenes.boat_on_step.env import *  # noqa: F401, F403
from ..scenes.boat_on_step.env import GATES, REWARD_TERMS  # noqa: F401
