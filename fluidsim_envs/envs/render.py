"""The software rasterizer of the rgb_array frames. Moved to ``fluidsim_envs.scenes.render``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.render instead.
from ..scenes.render import *  # noqa: F401, F403
