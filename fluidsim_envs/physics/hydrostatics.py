"""Hydrostatic equilibrium of a floating craft in calm water, from its buoyancy samples alone.

The kernel's buoyancy law (``forces.buoyancy_force``) gives each area sample ``rho g A depth``
and each volume sample ``rho g V`` once submerged; at rest nothing else acts. The craft floats
where that total equals its weight (Archimedes) and its moment about the center of gravity
vanishes: this module solves those two equations for the height of the center of gravity and
the trim, upright (no heel). Used as the reference the simulated craft must settle to, and as
the rest height scenes measure heave from.
"""

from __future__ import annotations

import math

import numpy as np

from .craft import Craft


def _bisect(f, lo: float, hi: float, tol: float = 1e-12) -> float:
    flo = f(lo)
    if flo * f(hi) > 0.0:
        raise ValueError(f"no root of the hydrostatic balance between {lo} and {hi}")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        fm = f(mid)
        if (fm < 0.0) == (flo < 0.0):
            lo, flo = mid, fm
        else:
            hi = mid
        if hi - lo < tol:
            break
    return 0.5 * (lo + hi)


def static_float(
    craft: Craft, water_density_kgm3: float = 1025.0, gravity_mps2: float = 9.81
) -> tuple[float, float]:
    """Height of the center of gravity above the surface (m) and trim (rad, bow up +) at which
    ``craft`` floats upright at rest, with a sharp surface (``surface_blend_m = 0``).

    Raises ValueError when the buoyancy samples cannot carry the craft's weight.

    Examples:
        >>> from fluidsim_envs.physics import Craft
        >>> height, trim = static_float(Craft.load("speedboat"))
        >>> round(height, 3), round(math.degrees(trim), 2)
        (0.144, 1.42)
    """
    pts = np.array([b.offset_m for b in craft.buoyancy], dtype=float).reshape(-1, 3)
    area = np.array([b.area_m2 or 0.0 for b in craft.buoyancy])
    volume = np.array([b.volume_m3 or 0.0 for b in craft.buoyancy])
    if not len(pts):
        raise ValueError(f"craft {craft.name!r} has no buoyancy samples: it cannot float")
    rho_g = water_density_kgm3 * gravity_mps2
    weight = craft.mass_kg * gravity_mps2
    span = float(np.max(np.abs(pts))) + 1.0

    def forces(z: float, trim: float):
        c, s = math.cos(trim), math.sin(trim)
        height = z + pts[:, 0] * s + pts[:, 2] * c  # world z of each sample (y plays no part)
        arm = pts[:, 0] * c - pts[:, 2] * s  # its lever arm ahead of the center of gravity
        f = rho_g * (area * np.maximum(0.0, -height) + volume * (height < 0.0))
        return f.sum(), (f * arm).sum()

    if forces(-span, 0.0)[0] < weight:
        raise ValueError(
            f"craft {craft.name!r}: its buoyancy ({forces(-span, 0.0)[0]:.6g} N fully "
            f"immersed) cannot carry its weight ({weight:.6g} N)"
        )

    def height_at(trim: float) -> float:
        return _bisect(lambda z: forces(z, trim)[0] - weight, -span, span)

    trim = _bisect(lambda t: forces(height_at(t), t)[1], -0.5, 0.5)
    return height_at(trim), trim
