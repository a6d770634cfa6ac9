"""The force laws, once: scalar numba functions that the step kernel inlines and tests call.

Every function takes and returns scalars in the caller's float type (float32 or float64). The
constants below are float32 so that they never promote float32 arithmetic to float64; they are
exact in both types.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .jit import INLINE

ZERO = np.float32(0.0)
HALF = np.float32(0.5)
ONE = np.float32(1.0)
TWO = np.float32(2.0)
TINY = np.float32(1e-30)  # guards 1/|v| at rest; a normal float32

_JIT = INLINE  # every force law is inlined into the loops that call it


@njit(**_JIT)
def speed_clamp(vx, vy, vz, vmax):
    """|v|, 1/|v| (finite at rest) and the factor that scales v down to length ``vmax`` at most.

    Both force laws are quadratic in v, so clamping v multiplies the force by the square of
    this factor: the kernels apply it to the force instead of rescaling v.
    """
    speed = math.sqrt(vx * vx + vy * vy + vz * vz)
    inv = ONE / max(speed, TINY)
    return speed, inv, min(ONE, vmax * inv)


@njit(**_JIT)
def clamp_force(fx, fy, fz, fmax):
    """Scale a force down to magnitude ``fmax`` at most."""
    f = math.sqrt(fx * fx + fy * fy + fz * fz)
    scale = min(ONE, fmax / max(f, TINY))
    return fx * scale, fy * scale, fz * scale


@njit(**_JIT)
def plate_force(vx, vy, vz, nx, ny, nz, rho, area, efficiency, vmax, fmax):
    """Force on a flat plate with unit normal n moving at v relative to the fluid.

    ``F = -1/2 rho A |v| (v . n) n``: along the normal, proportional to V^2 sin(alpha) for an
    angle of attack alpha (both faces act, so it works at any attitude). Then the fraction
    ``efficiency`` of its component along the flow is removed: ``F -= eff (F . v^) v^``.
    Written as ``k (|v| n - eff (v . n)/|v| v)`` with ``k = -1/2 rho A (v . n)`` so that it
    stays finite at rest.
    """
    speed, inv, scale = speed_clamp(vx, vy, vz, vmax)
    vn = vx * nx + vy * ny + vz * nz
    k = -HALF * rho * area * vn * scale * scale
    c = efficiency * vn * inv
    return clamp_force(
        k * (speed * nx - c * vx), k * (speed * ny - c * vy), k * (speed * nz - c * vz), fmax
    )


@njit(**_JIT)
def cylinder_force(vx, vy, vz, ax, ay, az, rho, area, vmax, fmax):
    """Cross-flow force on a slender cylinder with unit axis a (Hoerner's cross-flow principle):
    ``F = -1/2 rho A |v_perp| v_perp`` with ``v_perp = v - (v . a) a``; nothing along the axis."""
    _, _, scale = speed_clamp(vx, vy, vz, vmax)
    va = vx * ax + vy * ay + vz * az
    px = vx - va * ax
    py = vy - va * ay
    pz = vz - va * az
    k = -HALF * rho * area * math.sqrt(px * px + py * py + pz * pz) * scale * scale
    return clamp_force(k * px, k * py, k * pz, fmax)


@njit(**_JIT)
def water_fraction(z, water, inv_blend):
    """How much of a sample at height z is in water: 1 below the surface layer, 0 above it,
    linear across a layer of thickness 1/inv_blend centred on z = 0. ``water`` is 0 or 1."""
    return water * min(ONE, max(ZERO, HALF - z * inv_blend))


@njit(**_JIT)
def buoyancy_force(z, frac, water, rho_water, g, volume, area):
    """Upward buoyancy of a sample at height z: a volume sample gives rho g V times the
    submerged fraction ``frac``; an area sample gives rho g A depth (a spring). ``water`` is
    0 or 1 (a world without water floats nothing)."""
    return rho_water * g * (volume * frac + area * water * max(ZERO, -z))


@njit(**_JIT)
def thrust_of(c, lo, hi):
    """A thruster's thrust (N) at control value c in [-1, 1]: none at 0, linear to ``hi``
    (``max_thrust_n`` >= 0) at +1 and to ``lo`` (``min_thrust_n`` <= 0, astern) at -1."""
    return hi * max(c, ZERO) - lo * min(c, ZERO)


@njit(**_JIT)
def thrust_control(thrust, lo, hi):
    """The control value that gives ``thrust`` (N), :func:`thrust_of`'s inverse for a thrust
    in [lo, hi]: ``thrust / hi`` ahead, ``thrust / -lo`` astern. Scalars or arrays (a scene
    that maps its own action onto thrust, and then onto the craft's channel)."""
    ahead, astern = np.maximum(thrust, ZERO), np.minimum(thrust, ZERO)
    return ahead / max(hi, TINY) + astern / max(-lo, TINY)


@njit(**_JIT)
def rotate_about_axis(nx, ny, nz, hx, hy, hz, c, s):
    """Rodrigues' rotation of n about the unit axis h by the angle with cosine c and sine s."""
    hn = hx * nx + hy * ny + hz * nz
    return (
        nx * c + (hy * nz - hz * ny) * s + hx * hn * (ONE - c),
        ny * c + (hz * nx - hx * nz) * s + hy * hn * (ONE - c),
        nz * c + (hx * ny - hy * nx) * s + hz * hn * (ONE - c),
    )
