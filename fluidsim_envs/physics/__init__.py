"""Batched rigid-body physics with fluid samples (numba kernels; no gymnasium, torch or rerun).

>>> from fluidsim_envs.physics import Craft, World, Simulator, WakeField
"""

from .contact import Ground
from .craft import (
    Buoyancy,
    Control,
    Craft,
    CraftError,
    Cylinder,
    Plate,
    Shape,
    Surface,
    Thruster,
)
from .kernels import EVALS_PER_STEP, INTEGRATORS, SENSE_FIELDS
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
    "Ground",
    "Plate",
    "Shape",
    "Simulator",
    "Surface",
    "SpatialHash",
    "SENSE_FIELDS",
    "SwellWave",
    "Thruster",
    "Tracers",
    "WakeField",
    "World",
]
