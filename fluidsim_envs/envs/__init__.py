"""The scenes' envs, under their old import path. Moved to :mod:`fluidsim_envs.scenes`."""

# A deprecated import path, kept for one release as thin re-exports (this package and its
# modules); it goes in the next release: import from fluidsim_envs.scenes instead.
from ..scenes.boat_on_step import BoatOnStepEnv, BoatOnStepParams, BoatOnStepVectorEnv
from ..scenes.paper_airplane import PaperAirplaneEnv, PaperAirplaneParams, PaperAirplaneVectorEnv
from ..scenes.submarine_wake import SubmarineWakeEnv, SubmarineWakeParams, SubmarineWakeVectorEnv

__all__ = [
    "BoatOnStepEnv",
    "BoatOnStepParams",
    "BoatOnStepVectorEnv",
    "PaperAirplaneEnv",
    "PaperAirplaneParams",
    "PaperAirplaneVectorEnv",
    "SubmarineWakeEnv",
    "SubmarineWakeParams",
    "SubmarineWakeVectorEnv",
]
