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
def plate_force(vx, vy, vz, nx, ny, nz, rho, area, efficiency, vmax, fmax, one_sided=ZERO):
    """Force on a flat plate with unit normal n moving at v relative to the fluid.

    ``F = -1/2 rho A |v| (v . n) n``: along the normal, proportional to V^2 sin(alpha) for an
    angle of attack alpha (both faces act, so it works at any attitude). Then the fraction
    ``efficiency`` of its component along the flow is removed: ``F -= eff (F . v^) v^``.
    Written as ``k (|v| n - eff (v . n)/|v| v)`` with ``k = -1/2 rho A (v . n)`` so that it
    stays finite at rest.

    ``one_sided`` (0 or 1): 1 keeps only the face the normal points out of (the wet face of a
    hull's bottom, whose normal points out of the hull). That face is pressed when the plate
    moves toward its normal side, ``v . n > 0``, and the force then pushes back along -n;
    moving away (``v . n <= 0``) the plate gives nothing, the seed's rule of not processing a
    surface that points away from the velocity. Branch-free: ``v . n`` becomes
    ``v . n - one_sided min(v . n, 0)``, which is ``v . n`` exactly when ``one_sided`` is 0.
    """
    speed, inv, scale = speed_clamp(vx, vy, vz, vmax)
    vn = vx * nx + vy * ny + vz * nz
    k = -HALF * rho * area * (vn - one_sided * min(vn, ZERO)) * scale * scale
    c = efficiency * vn * inv
    return clamp_force(
        k * (speed * nx - c * vx), k * (speed * ny - c * vy), k * (speed * nz - c * vz), fmax
    )


# Kinematic viscosities for the skin friction's Reynolds number (the World's densities are
# seawater at 15 deg C and sea-level air, so these are the same states'):
# seawater, 15 deg C, salinity 35 g/kg: 1.18831e-6 m^2/s (ITTC Recommended Procedure
# 7.5-02-01-03, "Fresh Water and Seawater Properties", 2011);
# air, ISA sea level, 15 deg C: mu / rho = 1.7894e-5 Pa s / 1.225 kg/m^3 = 1.4607e-5 m^2/s
# (U.S. Standard Atmosphere 1976).
NU_WATER_M2S = np.float32(1.18831e-6)
NU_AIR_M2S = np.float32(1.4607e-5)
RE_MIN = np.float32(1e5)  # the ITTC-1957 line is a turbulent line: Re held above this
# 0.075 ln(10)^2, the ITTC-1957 line's constant for natural logarithms, as a float32 pair
# (hi + lo): float32 arithmetic reads it to float32's precision, float64 to ~1e-15
_ITTC = 0.075 * math.log(10.0) ** 2
ITTC_HI = np.float32(_ITTC)
ITTC_LO = np.float32(_ITTC - float(ITTC_HI))
HUNDRED = np.float32(100.0)
# Pade [5/4] of atanh(u) = u (945 - 735 u^2 + 64 u^4) / (945 - 1050 u^2 + 225 u^4)
P0, P1, P2 = np.float32(945.0), np.float32(735.0), np.float32(64.0)
Q1, Q2 = np.float32(1050.0), np.float32(225.0)
LOG_ROOTS = 8  # square roots taken before the series: ln x = 2^9 atanh((s - 1) / (s + 1))
LOG_SCALE = np.float32(2.0 ** (LOG_ROOTS + 1))


@njit(**_JIT)
def log_branch_free(x):
    """ln(x) for x in [1e3, 1e12], branch-free so that the loops calling it vectorize (numba's
    math.log is a libm call: 12 ns a value here, against 4). ``LOG_ROOTS`` square roots bring
    x to s = x^(1/256) in [1.027, 1.12], then ``ln s = 2 atanh((s - 1) / (s + 1))`` by its
    [5/4] Pade approximant (|u| < 0.06: truncation ~1e-17). Every constant is an integer or a
    power of two, exact in float32: the error is the square roots' rounding times 256, ~1e-14
    relative in float64, ~3e-6 in float32 (tests/physics/test_forces.py)."""
    s = x
    for _ in range(LOG_ROOTS):
        s = math.sqrt(s)
    u = (s - ONE) / (s + ONE)
    u2 = u * u
    return LOG_SCALE * u * (P0 - u2 * (P1 - P2 * u2)) / (P0 - u2 * (Q1 - Q2 * u2))


@njit(**_JIT)
def ittc1957(re):
    """The ITTC-1957 model-ship correlation line, ``C_f = 0.075 / (log10 Re - 2)^2``, for a
    Reynolds number held at ``RE_MIN`` or above (below it the line, fitted to turbulent
    flow, means nothing; at 1e2 it is singular). Written ``0.075 ln(10)^2 / ln(Re / 100)^2``."""
    d = log_branch_free(max(re, RE_MIN) / HUNDRED)
    inv = ONE / (d * d)
    return ITTC_HI * inv + ITTC_LO * inv


@njit(**_JIT)
def viscosity(frac):
    """Kinematic viscosity (m^2/s) at a sample with water fraction ``frac`` (``water_fraction``):
    blended across the surface layer as the density is."""
    return NU_AIR_M2S * (ONE - frac) + NU_WATER_M2S * frac  # exact at 0 and 1


@njit(**_JIT)
def friction_force(vx, vy, vz, nx, ny, nz, rho, nu, area, cf, ittc, length, vmax, fmax):
    """Skin friction on a plate with unit normal n moving at v relative to the fluid: the
    shear along the plate's plane, against the tangential velocity ``v_t = v - (v . n) n``,
    ``F = -1/2 rho C_f A |v_t| v_t`` (the seed's surface drag along the plane of the sample).

    ``C_f = cf + ittc * ittc1957(Re)`` with ``Re = |v| length / nu``: a constant coefficient,
    or (``ittc`` = 1) the ITTC-1957 line plus ``cf`` as its roughness allowance. Both faces
    feel it (a wetted face is sheared whichever way the normal flow goes). |v| is clamped to
    ``vmax`` as in :func:`plate_force` (the force scales by the clamp's square), the force to
    ``fmax``. ``area`` is the wetted area the shear acts on."""
    speed, _, scale = speed_clamp(vx, vy, vz, vmax)
    vn = vx * nx + vy * ny + vz * nz
    tx, ty, tz = vx - vn * nx, vy - vn * ny, vz - vn * nz
    c = cf + ittc * ittc1957(speed * scale * length / nu)
    k = -HALF * rho * c * area * math.sqrt(tx * tx + ty * ty + tz * tz) * scale * scale
    return clamp_force(k * tx, k * ty, k * tz, fmax)


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
