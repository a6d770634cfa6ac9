"""The scenes: one module per task (observation, reward, termination) on the shared base."""

from .boat_on_step import BoatOnStepEnv, BoatOnStepParams, BoatOnStepVectorEnv
from .paper_airplane import PaperAirplaneEnv, PaperAirplaneParams, PaperAirplaneVectorEnv
from .submarine_wake import SubmarineWakeEnv, SubmarineWakeParams, SubmarineWakeVectorEnv

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
