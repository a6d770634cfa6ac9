"""Scripted baseline pilots (PID autopilots), the bar trained policies must beat."""

from .paper_airplane_pilot import PaperAirplanePilot, PilotGains

__all__ = ["PaperAirplanePilot", "PilotGains"]
