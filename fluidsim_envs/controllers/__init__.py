"""Scripted baseline pilots (PID autopilots), the bar trained policies must beat."""

from .paper_airplane_pilot import PaperAirplanePilot, PilotGains
from .submarine_wake_pilot import StationGains, SubmarineWakePilot

__all__ = ["PaperAirplanePilot", "PilotGains", "StationGains", "SubmarineWakePilot"]
