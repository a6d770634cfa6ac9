"""Batched rigid-body physics with fluid samples (numba kernels; no gymnasium, torch or rerun).

>>> from fluidsim_envs.physics import Craft, World, Simulator, WakeField
"""

from .craft import Buoyancy, Control, Craft, CraftError, Cylinder, Plate, Surface, Thruster
from .kernels import EVALS_PER_STEP, INTEGRATORS
from .simulator import Simulator
from .surface import SwellWave
from .tracers import SpatialHash, Tracers
from .wake import WakeField
from .world import World

__all__ = [
    "EVALS_PER_STEP",
    "INTEGRATORS",
    "Buoyancy",
    "Control",
    "Craft",
    "CraftError",
    "Cylinder",
    "Plate",
    "Simulator",
    "Surface",
    "SpatialHash",
    "SwellWave",
    "Thruster",
    "Tracers",
    "WakeField",
    "World",
]
