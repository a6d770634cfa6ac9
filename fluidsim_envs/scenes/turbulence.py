"""Moving air for a flying scene: continuous turbulence after the Dryden model and a discrete
1-cosine gust, added to the episode's mean wind each action.

**Dryden turbulence** (MIL-HDBK-1797, 1997, appendix A, section 4.9.2; the low-altitude
forms of MIL-F-8785C, 1980, section 3.7.2). Below 1000 ft, with h the height in feet and
W20 the mean wind speed at 20 ft:

- scale lengths ``L_u = 2 L_v = h / (0.177 + 0.000823 h)^1.2`` and ``2 L_w = h``;
- intensities ``sigma_w = 0.1 W20`` and ``sigma_u = sigma_v = sigma_w / (0.177 + 0.000823
  h)^0.4``;
- spectra, for a vehicle at airspeed V (temporal frequency w in rad/s, one-sided, each
  integrating to its sigma^2):
  ``Phi_u(w) = sigma_u^2 (2 L_u / (pi V)) / (1 + (L_u w / V)^2)`` and, with
  ``L' = 2 L_v`` or ``2 L_w``, ``Phi(w) = sigma^2 (L' / (pi V)) (1 + 3 (L' w / V)^2) /
  (1 + (L' w / V)^2)^2``.

The u component is a first-order Gauss-Markov process (time constant L_u / V), stepped
exactly. The v and w components are the second-order form, realized as two first-order
lags of time constant tau = L' / V in cascade, x1 (white noise in) and z (x1 in), with the
output ``sqrt(3) x1 + (1 - sqrt(3)) z``: its transfer function is ``(1 + sqrt(3) tau s) /
(1 + tau s)^2``, the Dryden form. Each step moves [x1, z] by the exact transition of the
pair over the action period h and adds noise with the exact covariance
``Q = Sigma - Phi Sigma Phi^T`` (Sigma the pair's stationary covariance, ``var(x1) =
sigma^2 / 2``, ``cov = var(z) = sigma^2 / 4``), so the output's variance is sigma^2 at any
step length; an episode starts in the stationary state. Heights below 10 ft take the
10-ft values (the model's floor). The components are along the vehicle's horizontal
heading (u), to its left (v) and up (w).

``turbulence`` picks W20: ``"wind"`` the episode's own mean wind, ``"light"``,
``"moderate"``, ``"severe"`` the handbook's 15, 30 and 45 knots, ``"none"`` no turbulence.

**Gust.** One discrete gust per episode, ``v(t) = A / 2 (1 - cos(2 pi (t - t0) / T))`` for
``t0 <= t <= t0 + T`` (the handbook's 1-cosine shape in time at the vehicle's speed): peak
A at the middle, from a random direction, at a random moment of the first ``gust_within_s``
seconds.

The normals come from :mod:`.noise` (the sub-env's key, its step, a lane per channel).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ..physics.state import OV, OX
from . import noise as NZ

FT_M = 0.3048
KNOT_MPS = 0.514444
# W20 (m/s) of each level; "wind": the episode's mean wind
W20_MPS = {"none": 0.0, "wind": math.nan, "light": 15 * KNOT_MPS, "moderate": 30 * KNOT_MPS,
           "severe": 45 * KNOT_MPS}  # fmt: skip
LEVELS = tuple(W20_MPS)
H_MIN_FT, H_MAX_FT = 10.0, 1000.0  # the low-altitude model's range
V_MIN_MPS = 0.5  # below this airspeed the time constants are held (a dart at rest)
NSTATE = 5  # u, v's pair, w's pair
_LANE = 3000  # noise lanes: 3000 + channel (clear of the sensors' lanes)
_SQ3 = math.sqrt(3.0)


@njit(cache=True)
def scales(height_m, w20_mps):
    """(sigma_u, sigma_w, L_u, L_w) in SI at ``height_m`` for W20 ``w20_mps``: the
    low-altitude forms (``L_w`` here is the handbook's ``2 L_w = h``)."""
    h = min(max(height_m / FT_M, H_MIN_FT), H_MAX_FT)
    d = 0.177 + 0.000823 * h
    sigma_w = 0.1 * w20_mps
    return sigma_w / d**0.4, sigma_w, h / d**1.2 * FT_M, h * FT_M


@njit(cache=True, inline="always")
def _first_order(x, tau, sigma, step, n):
    a = math.exp(-step / tau)
    return a * x + sigma * math.sqrt(max(1.0 - a * a, 0.0)) * n


@njit(cache=True, inline="always")
def _pair(x1, z, tau, sigma, step, n1, n2):
    """The Dryden pair over one step: exact transition and noise covariance."""
    s1 = 0.5 * sigma * sigma
    r = step / tau
    a = math.exp(-r)
    a2 = a * a
    q11 = s1 * (1.0 - a2)
    q12 = s1 * (0.5 - a2 * (r + 0.5))
    q22 = s1 * (0.5 - a2 * (r * r + r + 0.5))
    l11 = math.sqrt(max(q11, 0.0))
    l21 = q12 / l11 if l11 > 0.0 else 0.0
    l22 = math.sqrt(max(q22 - l21 * l21, 0.0))
    x1n = a * x1 + l11 * n1
    zn = a * (r * x1 + z) + l21 * n1 + l22 * n2
    return x1n, zn


@njit(cache=True)
def gust(t, start_s, duration_s, peak):
    """The 1-cosine gust's speed at time ``t`` (s): 0 outside [start, start + duration]."""
    x = (t - start_s) / duration_s
    if x < 0.0 or x > 1.0:
        return 0.0
    return 0.5 * peak * (1.0 - math.cos(2.0 * math.pi * x))


@njit(cache=True, inline="always")
def _step_one(s, k, t, height, airspeed, w20, step, start):
    """One sub-env's turbulence state ``s`` [NSTATE] advanced (or begun) one step; returns
    (u, v, w)."""
    su, sw, lu, lw = scales(height, w20)
    n0, n1 = NZ.normal_pair(k, t, _LANE)
    n2, n3 = NZ.normal_pair(k, t, _LANE + 1)
    n4, _ = NZ.normal_pair(k, t, _LANE + 2)
    if start:
        s[0] = su * n0
        h1 = math.sqrt(0.5) * su  # Cholesky of sigma^2 [[1/2, 1/4], [1/4, 1/4]]
        s[1], s[2] = h1 * n1, 0.5 * h1 * (n1 + n2)
        h1 = math.sqrt(0.5) * sw
        s[3], s[4] = h1 * n3, 0.5 * h1 * (n3 + n4)
    else:
        v = max(airspeed, V_MIN_MPS)
        s[0] = _first_order(s[0], lu / v, su, step, n0)
        s[1], s[2] = _pair(s[1], s[2], lu / v, su, step, n1, n2)
        s[3], s[4] = _pair(s[3], s[4], lw / v, sw, step, n3, n4)
    return s[0], _SQ3 * s[1] + (1.0 - _SQ3) * s[2], _SQ3 * s[3] + (1.0 - _SQ3) * s[4]


@njit(cache=True, error_model="numpy")
def dryden(ids, start, keys, counter, height, airspeed, w20, step, state, out):
    """Advance (or, ``start``, begin in the stationary state) the turbulence of sub-envs
    ``ids``: ``height`` [E] (m), ``airspeed`` [E] (m/s), ``w20`` [E] (m/s) per sub-env,
    ``step`` the action period (s); writes (u, v, w) into ``out`` [E, 3] (heading frame)."""
    for i in range(ids.size):
        e = ids[i]
        out[e, 0], out[e, 1], out[e, 2] = _step_one(
            state[e], keys[e], counter[e], height[e], airspeed[e], w20[e], step, start
        )


@njit(cache=True, error_model="numpy", inline="always")
def _air_range(lo, hi, ids, start, keys, counter, st, mean, w20, gusts, step, state, flow):
    for i in range(lo, hi):
        e = ids[i]
        n = 0 if start else counter[e]
        ax, ay = st[OV, 0, e] - mean[e, 0], st[OV + 1, 0, e] - mean[e, 1]
        az = st[OV + 2, 0, e] - mean[e, 2]
        if not (math.isfinite(ax + ay + az) and math.isfinite(st[OX + 2, 0, e])):
            for c in range(3):  # a diverged state (its episode ends): the air held still
                flow[c, e] = mean[e, c]
            continue
        level = math.sqrt(ax * ax + ay * ay)
        c, s = (ax / level, ay / level) if level > 1e-9 else (1.0, 0.0)
        speed = math.sqrt(level * level + az * az)
        u, v, w = _step_one(state[e], keys[e], 0 if start else n + 1, st[OX + 2, 0, e], speed,
                            w20[e], step, start)  # fmt: skip
        g = gust(n * step, gusts[e, 0], gusts[e, 1], gusts[e, 2])
        flow[0, e] = mean[e, 0] + c * u - s * v + g * gusts[e, 3]
        flow[1, e] = mean[e, 1] + s * u + c * v + g * gusts[e, 4]
        flow[2, e] = mean[e, 2] + w + g * gusts[e, 5]


@njit(cache=True, error_model="numpy")
def air(ids, start, keys, counter, st, mean, w20, gusts, step, state, flow):
    """The air each sub-env of ``ids`` flies in over its next step, into ``flow[0:3]``: its
    episode's ``mean`` wind [E, 3], plus Dryden turbulence at its height and airspeed from
    its state ``st`` [13, B, E] (in its air-relative heading frame), plus its gust
    (``gusts`` [E, 6]: start (s), duration (s), peak (m/s), unit direction). ``counter``
    [E]: the steps each has taken in its episode (its noise counter is that plus one; at
    ``start``, 0: the episode's first air)."""
    _air_range(0, ids.size, ids, start, keys, counter, st, mean, w20, gusts, step, state, flow)


@njit(cache=True, error_model="numpy", parallel=True)
def air_parallel(ids, start, keys, counter, st, mean, w20, gusts, step, state, flow):
    """:func:`air` on every thread, 64 sub-envs a task (each writes its own rows only)."""
    for b in prange((ids.size + 63) // 64):
        _air_range(b * 64, min(ids.size, b * 64 + 64), ids, start, keys, counter, st, mean,
                   w20, gusts, step, state, flow)  # fmt: skip


def spectrum(omega, sigma, length_m, airspeed, second_order: bool):
    """The Dryden one-sided spectrum (m^2/s^2 per rad/s) at ``omega`` (rad/s): the u form
    (first order, L_u) or the v/w form (``length_m`` = L')."""
    x = np.asarray(omega) * length_m / airspeed
    if second_order:
        return sigma**2 * length_m / (math.pi * airspeed) * (1 + 3 * x**2) / (1 + x**2) ** 2
    return sigma**2 * 2 * length_m / (math.pi * airspeed) / (1 + x**2)
