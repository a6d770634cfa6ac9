"""The scenes: one module per task (observation, reward, termination) on the shared base."""

from .paper_airplane import PaperAirplaneEnv, PaperAirplaneParams, PaperAirplaneVectorEnv
from .submarine_wake import SubmarineWakeEnv, SubmarineWakeParams, SubmarineWakeVectorEnv

__all__ = [
    "PaperAirplaneEnv",
    "PaperAirplaneParams",
    "PaperAirplaneVectorEnv",
    "SubmarineWakeEnv",
    "SubmarineWakeParams",
    "SubmarineWakeVectorEnv",
]
