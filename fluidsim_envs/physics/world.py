"""The world a craft moves in: gravity, two fluids, the water surface, the stability clamps."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .craft import Vec3


@dataclass(frozen=True)
class World:
    """Gravity along -z; air above z = 0 and, with ``water=True``, water below it.

    Args:
        gravity_mps2: magnitude of gravity (>= 0), acting along -z.
        air_density_kgm3, water_density_kgm3: fluid densities (> 0).
        water: whether there is water below z = 0 (otherwise air everywhere, no buoyancy).
        wind_mps: uniform air velocity (world frame).
        current_mps: uniform water velocity (world frame).
        surface_blend_m: thickness of the layer around z = 0 across which a sample's density,
            fluid velocity and volume buoyancy blend linearly from air to water; 0 gives a sharp
            surface. A blend keeps forces continuous when samples cross the surface.
        max_fluid_speed_mps: clamp on each sample's speed relative to the fluid (the seed's
            350 mph); keeps forces finite whatever the state.
        max_sample_force_n: clamp on each sample's force magnitude.
    """

    gravity_mps2: float = 9.81
    air_density_kgm3: float = 1.225
    water_density_kgm3: float = 1025.0
    water: bool = False
    wind_mps: Vec3 = (0.0, 0.0, 0.0)
    current_mps: Vec3 = (0.0, 0.0, 0.0)
    surface_blend_m: float = 0.05
    max_fluid_speed_mps: float = 156.0
    max_sample_force_n: float = 1.0e7

    def __post_init__(self) -> None:
        def check(key: str, lo: float, strict: bool) -> None:
            value = getattr(self, key)
            ok = isinstance(value, (int, float)) and math.isfinite(value)
            ok = ok and (value > lo if strict else value >= lo)
            if not ok:
                rel = ">" if strict else ">="
                raise ValueError(f"World: {key} must be a finite number {rel} {lo}, got {value!r}")

        check("gravity_mps2", 0.0, strict=False)
        check("air_density_kgm3", 0.0, strict=True)
        check("water_density_kgm3", 0.0, strict=True)
        check("surface_blend_m", 0.0, strict=False)
        check("max_fluid_speed_mps", 0.0, strict=True)
        check("max_sample_force_n", 0.0, strict=True)
        if not isinstance(self.water, bool):
            raise ValueError(f"World: water must be True or False, got {self.water!r}")
        for key in ("wind_mps", "current_mps"):
            v = getattr(self, key)
            if len(v) != 3 or not all(isinstance(c, (int, float)) and math.isfinite(c) for c in v):
                raise ValueError(f"World: {key} must be 3 finite numbers, got {v!r}")
            object.__setattr__(self, key, tuple(float(c) for c in v))
