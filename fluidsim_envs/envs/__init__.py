"""The scenes: one module per task (observation, reward, termination) on the shared base."""

from .paper_airplane import PaperAirplaneEnv, PaperAirplaneParams, PaperAirplaneVectorEnv

__all__ = ["PaperAirplaneEnv", "PaperAirplaneParams", "PaperAirplaneVectorEnv"]
