"""What every scene shares. Moved to ``fluidsim_envs.scenes.base``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.base instead.
from ..scenes.base import *  # noqa: F401, F403
