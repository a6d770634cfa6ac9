"""PaperAirplane-v0's scripted pilot. Moved to ``fluidsim_envs.scenes.paper_airplane.pilot``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.paper_airplane.pilot instead.
from ..scenes.paper_airplane.pilot import *  # noqa: F401, F403
