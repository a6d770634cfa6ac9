"""SubmarineWake-v0's scripted pilot. Moved to ``fluidsim_envs.scenes.submarine_wake.pilot``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.submarine_wake.pilot instead.
from ..scenes.submarine_wake.pilot import *  # noqa: F401, F403
