"""SubmarineWake-v0's frames. Moved to ``fluidsim_envs.scenes.submarine_wake.view``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.submarine_wake.view instead.
from ..scenes.submarine_wake.view import *  # noqa: F401, F403
