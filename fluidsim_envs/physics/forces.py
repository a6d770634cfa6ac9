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
NU_WATER_M2S = 1.18831e-6
NU_AIR_M2S = 1.4607e-5
# the kernels take their inverses (1 / nu: the Reynolds number per m and m/s; a product is
# cheaper than a quotient), as float32 pairs (hi + lo): float32 arithmetic reads a pair to
# float32's precision, float64 to ~1e-15
INV_NU_WATER_HI = np.float32(1.0 / NU_WATER_M2S)
INV_NU_WATER_LO = np.float32(1.0 / NU_WATER_M2S - float(INV_NU_WATER_HI))
INV_NU_AIR_HI = np.float32(1.0 / NU_AIR_M2S)
INV_NU_AIR_LO = np.float32(1.0 / NU_AIR_M2S - float(INV_NU_AIR_HI))
RE_MIN = np.float32(1e5)  # the ITTC-1957 line is a turbulent line: Re held above this
# 0.075 ln(10)^2, the ITTC-1957 line's constant for natural logarithms, and ln(128 / 100)
# (the line takes ln(Re / 100) = ln(Re / 128) + ln 1.28: Re / 128 is exact), as pairs
_ITTC = 0.075 * math.log(10.0) ** 2
ITTC_HI = np.float32(_ITTC)
ITTC_LO = np.float32(_ITTC - float(ITTC_HI))
LN128_HI = np.float32(math.log(1.28))
LN128_LO = np.float32(math.log(1.28) - float(LN128_HI))
I128 = np.float32(2.0**-7)
# log: x = 2^e r with e from exact halvings (the powers of two below) and r in [1/sqrt 2,
# sqrt 2]; ln r = 2 atanh(u), u = (r - 1) / (r + 1), |u| <= 0.1716, by the [7/6] Pade
# approximant atanh(u) = u P(u^2) / Q(u^2) (truncation 1.9e-15 relative there); integer
# coefficients, exact in float32
P0, P1, P2, P3 = (np.float32(c) for c in (15015.0, -19250.0, 5943.0, -256.0))
Q0, Q1, Q2, Q3 = (np.float32(c) for c in (15015.0, -24255.0, 11025.0, -1225.0))
INV_SQRT2 = np.float32(math.sqrt(0.5))  # a threshold only: any value near it would do
LN2_HI = np.float32(math.log(2.0))  # ln 2 as a float32 pair (hi + lo), as _ITTC
LN2_LO = np.float32(math.log(2.0) - float(LN2_HI))
E32, E16, E8, E4, E2 = (np.float32(2.0**k) for k in (32, 16, 8, 4, 2))
I32, I16, I8, I4, I2 = (np.float32(2.0**-k) for k in (32, 16, 8, 4, 2))
K32, K16, K8, K4, K2 = (np.float32(k) for k in (32, 16, 8, 4, 2))


@njit(**_JIT)
def _halve(r, e, test, scale, k):
    """(r scale, e + k) where r test >= 1 (r test < 2), else (r, e): the select written as
    arithmetic (b is exactly 0 or 1, each product exact for a power-of-two ``scale``), so
    that it vectorizes; conditional expressions here made the loop scalar, 9 times slower."""
    b = min(ONE, np.floor(r * test))
    return r * scale * b + r * (ONE - b), e + k * b


@njit(**_JIT)
def log_branch_free(x):
    """ln(x) for x in [1, 2^64), with no call and no branch, so that the loops calling it
    vectorize: numba's math.log is a libm call, 12 ns a value here. x is halved by exact
    powers of two (2^32, 2^16, ..., 2, then 2 again above sqrt 2) into r in
    [0.707, 1.415] while their exponents add up in e; ``ln x = e ln 2 + 2 atanh((r - 1) /
    (r + 1))``. Within 2.0e-15 relative in float64 and 1.1e-7 in float32 over x in
    [1e3, 1e12] (tests/physics/test_one_sided_and_friction.py)."""
    r, e = _halve(x, x * ZERO, I32, I32, K32)  # e: 0 in the caller's float type
    r, e = _halve(r, e, I16, I16, K16)
    r, e = _halve(r, e, I8, I8, K8)
    r, e = _halve(r, e, I4, I4, K4)
    r, e = _halve(r, e, I2, I2, K2)
    r, e = _halve(r, e, HALF, HALF, ONE)
    r, e = _halve(r, e, INV_SQRT2, HALF, ONE)  # r in [1, 2): halved from sqrt 2 up
    # u P(u^2) / Q(u^2) with u = a / b, a = r - 1, b = r + 1, over the common factor b^6:
    # one quotient instead of two
    a, b = r - ONE, r + ONE
    aa, bb = a * a, b * b
    num = a * (P0 * bb * bb * bb + aa * (P1 * bb * bb + aa * (P2 * bb + aa * P3)))
    den = b * (Q0 * bb * bb * bb + aa * (Q1 * bb * bb + aa * (Q2 * bb + aa * Q3)))
    return e * LN2_HI + e * LN2_LO + TWO * num / den


@njit(**_JIT)
def ittc1957(re):
    """The ITTC-1957 model-ship correlation line, ``C_f = 0.075 / (log10 Re - 2)^2``, for a
    Reynolds number held at ``RE_MIN`` or above (below it the line, fitted to turbulent
    flow, means nothing; at 1e2 it is singular). Written ``0.075 ln(10)^2 / ln(Re / 100)^2``."""
    d = log_branch_free(max(re, RE_MIN) * I128) + LN128_HI + LN128_LO
    inv = ONE / (d * d)
    return ITTC_HI * inv + ITTC_LO * inv


@njit(**_JIT)
def inverse_viscosity(frac):
    """1 / nu (s/m^2) at a sample with water fraction ``frac`` (``water_fraction``): the
    water's and the air's, blended across the surface layer as the density is."""
    water = INV_NU_WATER_HI * frac + INV_NU_WATER_LO * frac
    return INV_NU_AIR_HI * (ONE - frac) + INV_NU_AIR_LO * (ONE - frac) + water


@njit(**_JIT)
def friction_force(vx, vy, vz, nx, ny, nz, rho, inv_nu, area, cf, ittc, length, vmax, fmax):
    """Skin friction on a plate with unit normal n moving at v relative to the fluid: the
    shear along the plate's plane, against the tangential velocity ``v_t = v - (v . n) n``,
    ``F = -1/2 rho C_f A |v_t| v_t`` (the seed's surface drag along the plane of the sample).

    ``C_f = cf + ittc * ittc1957(Re)`` with ``Re = |v| length / nu`` (``inv_nu`` = 1 / nu,
    :func:`inverse_viscosity`): a constant coefficient,
    or (``ittc`` = 1) the ITTC-1957 line plus ``cf`` as its roughness allowance. Both faces
    feel it (a wetted face is sheared whichever way the normal flow goes). |v| is clamped to
    ``vmax`` as in :func:`plate_force` (the force scales by the clamp's square), the force to
    ``fmax``. ``area`` is the wetted area the shear acts on."""
    speed, _, scale = speed_clamp(vx, vy, vz, vmax)
    vn = vx * nx + vy * ny + vz * nz
    tx, ty, tz = vx - vn * nx, vy - vn * ny, vz - vn * nz
    c = cf + ittc * ittc1957(speed * scale * length * inv_nu)
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
