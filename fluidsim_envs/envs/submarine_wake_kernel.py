"""SubmarineWake-v0's task kernels and layouts.

Moved to ``fluidsim_envs.scenes.submarine_wake.kernel``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.submarine_wake.kernel instead.
from ..scenes.submarine_wake.kernel import *  # noqa: F401, F403
