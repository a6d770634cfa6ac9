"""Scripted baseline pilots (PID autopilots), the bar trained policies must beat."""

from .boat_on_step_pilot import BoatOnStepPilot, HelmGains
from .paper_airplane_pilot import PaperAirplanePilot, PilotGains
from .submarine_wake_pilot import StationGains, SubmarineWakePilot

__all__ = [
    "BoatOnStepPilot",
    "HelmGains",
    "PaperAirplanePilot",
    "PilotGains",
    "StationGains",
    "SubmarineWakePilot",
]
