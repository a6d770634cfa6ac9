"""The scripted baseline pilots, under their old import path. Moved to each scene's package
(``fluidsim_envs.scenes.<scene>.pilot``; ``SCENES[id].pilot`` makes one for a vector env)."""

# A deprecated import path, kept for one release as thin re-exports (this package and its
# modules); it goes in the next release: import from fluidsim_envs.scenes instead.
from ..scenes.boat_on_step.pilot import BoatOnStepPilot, HelmGains
from ..scenes.paper_airplane.pilot import PaperAirplanePilot, PilotGains
from ..scenes.submarine_wake.pilot import StationGains, SubmarineWakePilot

__all__ = [
    "BoatOnStepPilot",
    "HelmGains",
    "PaperAirplanePilot",
    "PilotGains",
    "StationGains",
    "SubmarineWakePilot",
]
