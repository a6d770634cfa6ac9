"""The water surface: flat at z = 0, or swell, a sum of a few linear deep-water waves.

Each wave is a long-crested sinusoid of linear (Airy) wave theory,

    eta(x, y, t) = sum_j a_j cos(kx_j x + ky_j y - omega_j t + phase_j),

with wavenumber ``k = 2 pi / wavelength`` along the direction of travel and the deep-water
dispersion relation ``omega = sqrt(g k)``: a crest moves at the phase speed
``omega / k = sqrt(g / k)`` (Lamb, *Hydrodynamics*, sec. 229). Linear theory holds for gentle
waves only: the steepness ``a k`` is capped at :data:`MAX_STEEPNESS`, well below Stokes'
limiting wave (``a k ~ 0.44``, crest angle 120 degrees), beyond which real waves break.

The swell moves the surface only (hydrostatic swell): the water under it stays still, without
the waves' orbital velocities. A sample's water fraction and buoyancy depth are measured from
the local surface height under it.

The scalar :func:`surface_height` is the one implementation of the formula: env kernels may
call it and :meth:`World.surface_height` evaluates it on arrays. The step kernel evaluates the
same sum in two parts: once per step each environment's time phases
``phase_j - omega_j t`` (:func:`time_phase`, in float64 from the float64 clock, wrapped to
[-pi, pi] so that they keep their precision in a float32 simulation), then per sample
``a_j cos(kx_j x + ky_j y + time phase)`` with :func:`wave_cos`, a branch-free cosine that
vectorizes across environments. The waves come from a table ``swell[n, 5]`` (float64) of rows
``(a, kx, ky, omega, phase)``, built by :func:`swell_table`; calm water is the empty table.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields

import numpy as np
from numba import njit

from . import checks as CK

MAX_WAVES = 4
# a k at most 0.3: there Stokes' second-order correction already raises crests (and flattens
# troughs) by a k / 2 = 15% of the amplitude; steeper, linear theory is no fair model, and
# Stokes' limiting wave (the steepest before breaking) is at a k ~ 0.44.
MAX_STEEPNESS = 0.3
SW_A, SW_KX, SW_KY, SW_OMEGA, SW_PHASE = 0, 1, 2, 3, 4  # columns of a swell table
NSW = 5

_INLINE = dict(cache=True, error_model="numpy", inline="always", fastmath={"contract"})
_JIT = dict(cache=True, error_model="numpy", fastmath={"contract"})


@dataclass(frozen=True)
class SwellWave:
    """One long-crested deep-water wave of the swell.

    Args:
        amplitude_m: crest height above the mean level (>= 0; half the crest-to-trough height).
        wavelength_m: crest-to-crest distance (> 0).
        direction_deg: the direction the wave travels toward, in the horizontal plane:
            0 = +x, 90 = +y.
        phase_rad: phase at the origin at t = 0 (0: a crest at the origin at t = 0).

    Examples:
        >>> wave = SwellWave(amplitude_m=0.5, wavelength_m=40.0, direction_deg=90.0)
        >>> round(wave.steepness, 4), round(wave.period_s(9.81), 3)
        (0.0785, 5.062)
    """

    amplitude_m: float
    wavelength_m: float
    direction_deg: float = 0.0
    phase_rad: float = 0.0

    def __post_init__(self) -> None:
        for f in fields(self):
            object.__setattr__(self, f.name, CK.number("SwellWave", f.name, getattr(self, f.name)))
        CK.number("SwellWave", "amplitude_m", self.amplitude_m, ge=0.0)
        CK.number("SwellWave", "wavelength_m", self.wavelength_m, gt=0.0)
        if self.steepness > MAX_STEEPNESS * (1.0 + 1e-12):  # a = 0.3 wavelength / 2 pi passes
            raise ValueError(
                f"SwellWave: steepness 2 pi amplitude / wavelength = {self.steepness:.4g} "
                f"(amplitude_m={self.amplitude_m!r}, wavelength_m={self.wavelength_m!r}) "
                f"exceeds {MAX_STEEPNESS}: linear wave theory does not hold for waves that "
                "steep (Stokes' limiting wave, where waves break, is at about 0.44)"
            )

    @property
    def wavenumber(self) -> float:
        """k = 2 pi / wavelength (rad/m)."""
        return 2.0 * math.pi / self.wavelength_m

    @property
    def steepness(self) -> float:
        """a k = 2 pi amplitude / wavelength (dimensionless)."""
        return self.amplitude_m * self.wavenumber

    def angular_frequency(self, gravity_mps2: float) -> float:
        """omega = sqrt(g k), deep-water dispersion (rad/s)."""
        return math.sqrt(gravity_mps2 * self.wavenumber)

    def period_s(self, gravity_mps2: float) -> float:
        """2 pi / omega (s); infinite without gravity (a frozen surface)."""
        omega = self.angular_frequency(gravity_mps2)
        return 2.0 * math.pi / omega if omega > 0.0 else math.inf

    @classmethod
    def coerce(cls, value, where: str) -> SwellWave:
        """A SwellWave from itself, a tuple ``(amplitude_m, wavelength_m[, direction_deg[,
        phase_rad]])`` or a dict with those keys."""
        if isinstance(value, cls):
            return value
        if isinstance(value, Mapping):
            valid = [f.name for f in fields(cls)]
            unknown = sorted(set(value) - set(valid))
            if unknown:
                raise ValueError(f"{where}: unknown key(s) {unknown}; valid keys are {valid}")
            missing = [k for k in valid[:2] if k not in value]
            if missing:
                raise ValueError(f"{where}: missing key(s) {missing} in {dict(value)!r}")
            return cls(**value)
        if isinstance(value, (tuple, list)) and 2 <= len(value) <= 4:
            return cls(*value)
        raise ValueError(
            f"{where} must be a SwellWave, a dict or a tuple (amplitude_m, wavelength_m"
            f"[, direction_deg[, phase_rad]]), got {value!r}"
        )


def coerce_swell(swell) -> tuple[SwellWave, ...]:
    """Validate a World's ``swell``: a sequence of at most :data:`MAX_WAVES` waves, each a
    :class:`SwellWave`, a dict or a tuple (a single SwellWave or dict is taken as one wave)."""
    if isinstance(swell, (SwellWave, Mapping)):
        swell = (swell,)
    if isinstance(swell, (str, bytes)) or not hasattr(swell, "__iter__"):
        raise ValueError(f"World: swell must be a sequence of waves, got {swell!r}")
    waves = tuple(SwellWave.coerce(w, f"World: swell[{i}]") for i, w in enumerate(swell))
    if len(waves) > MAX_WAVES:
        raise ValueError(
            f"World: swell has {len(waves)} waves; at most {MAX_WAVES} are allowed "
            "(each costs a cosine per sample per force evaluation)"
        )
    return waves


def swell_table(waves: tuple[SwellWave, ...], gravity_mps2: float) -> np.ndarray:
    """The kernels' table ``[n, 5]`` float64 of rows ``(a, kx, ky, omega, phase)``."""
    table = np.zeros((len(waves), NSW), dtype=np.float64)
    for j, w in enumerate(waves):
        k = w.wavenumber
        d = math.radians(w.direction_deg)
        table[j] = (w.amplitude_m, k * math.cos(d), k * math.sin(d), math.sqrt(gravity_mps2 * k),
                    w.phase_rad)  # fmt: skip
    return table


# wave_cos: pi = PI_A + PI_B + PI_C (Cody and Waite's reduction): PI_A and PI_B hold 26
# significant bits each, so n PI_A and n PI_B are exact for |n| < 2^27 and x - n PI_A is exact
# (Sterbenz), with or without fused multiply-add; PI_C is the rest of pi, rounded.
PI_A = 3.1415926218032837  # 0x1.921fb5p+1
PI_B = 3.1786509424591713e-08  # 0x1.110b46p-25
PI_C = 1.2246467991473532e-16
INV_PI = 0.3183098861837907
INV_TWO_PI = 0.15915494309189535
# the Taylor coefficients (-1)^k / (2k)! of cos, k = 1..10
_COS_TAYLOR = tuple((-1.0) ** k / math.factorial(2 * k) for k in range(1, 11))
C1, C2, C3, C4, C5, C6, C7, C8, C9, C10 = _COS_TAYLOR


@njit(**_INLINE)
def wave_exp(x):
    """exp(x) for x <= 0 in float64, branch-free so that loops calling it vectorize (numba's
    math.exp is a library call): exp(x / 128) by its Taylor series to degree 12 (truncation
    below 1e-14 for |x| <= 60), squared seven times (a relative error within 2e-12 of libm's;
    tests/physics/test_orbital.py). Below -60 it returns exp(-60), about 1e-26: the decay
    of a wave's motion with depth, where it is nothing."""
    y = max(x, -60.0) * 0.0078125
    e = 1.0 / 479001600.0
    e = 1.0 / 39916800.0 + y * e
    e = 1.0 / 3628800.0 + y * e
    e = 1.0 / 362880.0 + y * e
    e = 1.0 / 40320.0 + y * e
    e = 1.0 / 5040.0 + y * e
    e = 1.0 / 720.0 + y * e
    e = 1.0 / 120.0 + y * e
    e = 1.0 / 24.0 + y * e
    e = 1.0 / 6.0 + y * e
    e = 0.5 + y * e
    e = 1.0 + y * e
    e = 1.0 + y * e
    for _ in range(7):
        e = e * e
    return e


@njit(**_INLINE)
def wave_cos(x):
    """cos(x) in float64, branch-free so that loops calling it vectorize (numba's math.cos is a
    libm call, which does not). x = n pi + r with |r| <= pi/2 and cos(x) = (-1)^n cos(r); cos r
    by its Taylor series to r^20 (truncation below 2e-17 at pi/2). Within a few units in the
    last place of libm's cos for |x| up to 4e8 (tests/physics/test_swell.py)."""
    n = np.floor(x * INV_PI + 0.5)
    r = ((x - n * PI_A) - n * PI_B) - n * PI_C
    z = r * r
    c = C9 + z * C10
    c = C8 + z * c
    c = C7 + z * c
    c = C6 + z * c
    c = C5 + z * c
    c = C4 + z * c
    c = C3 + z * c
    c = C2 + z * c
    c = C1 + z * c
    c = 1.0 + z * c
    return c * (1.0 - 2.0 * (n - 2.0 * np.floor(0.5 * n)))  # (-1)^n


@njit(**_INLINE)
def wrap_phase(x):
    """x - 2 pi n, the angle equal to x in [-pi, pi] (the reduction of :func:`wave_cos`)."""
    n = np.floor(x * INV_TWO_PI + 0.5)
    return ((x - n * (2.0 * PI_A)) - n * (2.0 * PI_B)) - n * (2.0 * PI_C)


@njit(**_INLINE)
def time_phase(t, swell, j):
    """The part of wave j's phase that depends on time only, ``phase - omega t``, wrapped to
    [-pi, pi]: the step kernel stores it per environment once per step."""
    return wrap_phase(swell[j, SW_PHASE] - swell[j, SW_OMEGA] * t)


@njit(**_INLINE)
def surface_height(x, y, t, swell):
    """Height eta (m) of the water surface above z = 0 at the horizontal point (x, y) and
    time t (s), in float64: ``sum a cos(kx x + ky y - omega t + phase)`` over the rows of
    ``swell`` (0 for the empty table: calm water)."""
    eta = 0.0
    for j in range(swell.shape[0]):
        phase = swell[j, SW_KX] * x + swell[j, SW_KY] * y + time_phase(t, swell, j)
        eta += swell[j, SW_A] * wave_cos(phase)
    return eta


@njit(**_JIT)
def surface_heights(x, y, t, swell, out):
    """``out[i] = surface_height(x[i], y[i], t[i], swell)`` for flat float64 arrays."""
    for i in range(out.shape[0]):
        out[i] = surface_height(x[i], y[i], t[i], swell)


# --------------------------------------------------------------------------------------------
# irregular seas


def jonswap(omega, hs_m: float, tp_s: float, gamma: float = 3.3) -> np.ndarray:
    """The JONSWAP spectrum S(omega) (m^2 s / rad, one-sided) of significant height ``hs_m``
    and peak period ``tp_s`` (DNV-RP-C205, 2010, 3.5.5): the Pierson-Moskowitz form
    ``5/16 Hs^2 wp^4 w^-5 exp(-5/4 (w / wp)^-4)`` times the normalizing ``1 - 0.287 ln
    gamma`` and the peak enhancement ``gamma^exp(-(w - wp)^2 / (2 sigma^2 wp^2))``,
    sigma 0.07 below the peak and 0.09 above. ``gamma`` 1 is Pierson-Moskowitz."""
    w = np.asarray(omega, dtype=np.float64)
    wp = 2.0 * math.pi / tp_s
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        pm = 5.0 / 16.0 * hs_m**2 * wp**4 * w**-5.0 * np.exp(-1.25 * (w / wp) ** -4.0)
        sigma = np.where(w <= wp, 0.07, 0.09)
        peak = gamma ** np.exp(-((w - wp) ** 2) / (2.0 * sigma**2 * wp**2))
        s = (1.0 - 0.287 * math.log(gamma)) * pm * peak
    return np.where(w > 0.0, s, 0.0)


def irregular_sea(hs_m: float, tp_s: float, gamma: float = 3.3, waves: int = MAX_WAVES,
                  direction_deg: float = 0.0, spread_deg: float = 0.0, seed: int = 0,
                  gravity_mps2: float = 9.81) -> tuple[SwellWave, ...]:  # fmt: skip
    """A sea of ``waves`` components from the JONSWAP spectrum (:func:`jonswap`): the
    spectrum cut into bands of equal energy, each a wave at its band's mean frequency
    (deep-water wavelength ``2 pi g / w^2``) with the band's energy (amplitude
    ``sqrt(2 m0 / waves)``, m0 the spectrum's zeroth moment: the components' m0 is the
    spectrum's, whose ``4 sqrt(m0)`` is ``hs_m`` to within the normalization's 1-2%), a
    random phase and a direction within ``spread_deg`` of ``direction_deg``,
    drawn from ``seed``."""
    CK.number("irregular_sea", "hs_m", hs_m, gt=0.0)
    CK.number("irregular_sea", "tp_s", tp_s, gt=0.0)
    CK.number("irregular_sea", "gamma", gamma, ge=1.0, le=10.0)
    CK.number("irregular_sea", "waves", waves, ge=1, le=MAX_WAVES, integer=True)
    wp = 2.0 * math.pi / tp_s
    w = np.linspace(0.2 * wp, 6.0 * wp, 20001)  # holds all but ~1e-4 of the energy
    s = jonswap(w, hs_m, tp_s, gamma)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (s[1:] + s[:-1]) * np.diff(w))])
    m0 = cum[-1]
    edges = np.interp(np.linspace(0.0, m0, waves + 1), cum, w)
    rng = np.random.default_rng(seed)
    out = []
    for j in range(waves):
        inside = (w >= edges[j]) & (w <= edges[j + 1])
        mean_w = np.sum(w[inside] * s[inside]) / np.sum(s[inside])
        out.append(
            SwellWave(
                amplitude_m=math.sqrt(2.0 * m0 / waves),
                wavelength_m=2.0 * math.pi * gravity_mps2 / mean_w**2,
                direction_deg=direction_deg + spread_deg * (2.0 * rng.random() - 1.0),
                phase_rad=2.0 * math.pi * rng.random(),
            )
        )
    return tuple(out)
