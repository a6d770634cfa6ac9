"""SubmarineWake-v0: the env. Moved to ``fluidsim_envs.scenes.submarine_wake.env``."""

# A deprecated import path, kept for one release as a thin re-export; it goes in the next
# release: import from fluidsim_envs.scenes.submarine_wake.env instead.
from ..scenes.submarine_wake.env import *  # noqa: F401, F403
from ..scenes.submarine_wake.env import (  # noqa: F401
    LEAD_LENGTH_M,
    LEAD_RADIUS_M,
    REWARD_TERMS,
    ROUTE_SEGMENTS,
    UUV_RADIUS_M,
)
