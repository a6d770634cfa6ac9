"""PaperAirplane-v0: the env. Moved to ``fluidsim_envs.scenes.paper_airplane.env``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.paper_airplane.env instead.
from ..scenes.paper_airplane.env import *  # noqa: F401, F403
from ..scenes.paper_airplane.env import REWARD_TERMS  # noqa: F401
