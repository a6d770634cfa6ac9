"""Drawing crafts and the ground. Moved to ``fluidsim_envs.scenes.drawing``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.drawing instead.
from ..scenes.drawing import *  # noqa: F401, F403
