"""Counter-based random numbers for the noise a step adds inside compiled kernels: sensor
noise, a sensor's wandering bias, turbulence.

A step needs fresh noise for every sub-env, and the same seed must give the same numbers
for any batch size and thread count. Calling each sub-env's NumPy generator every step is
a Python loop over sub-envs (thousands of calls a step). Instead each sub-env holds a 64-bit
``key``, drawn at every episode start from its own generator (through the episode's pool of
uniforms, so it obeys the seeding contract of ``scenes/base.py``), and a number is a pure
function of (key, counter, lane): the counter is the sub-env's step in its episode and the
lane names the quantity (a sensor column, a turbulence channel). Nothing is carried between
calls, so the numbers do not depend on which thread or batch computes them.

The function is splitmix64's output mix (Steele, Lea and Flood, "Fast splittable
pseudorandom number generators", OOPSLA 2014), a bijection of 64-bit words with full
avalanche, applied twice: to the counter and lane, then to that XOR the key. Its uniforms
take the top 53 bits; its normals come from Box and Muller's transform of two uniforms
(tests/scenes/test_noise.py checks moments, independence of lanes and counters, and the
normal's tails against the closed forms).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_JIT = dict(cache=True, inline="always")

_GAMMA = np.uint64(0x9E3779B97F4A7C15)  # splitmix64's increment (the golden ratio)
_M1 = np.uint64(0xBF58476D1CE4E5B9)
_M2 = np.uint64(0x94D049BB133111EB)
_S30, _S27, _S31, _S11 = np.uint64(30), np.uint64(27), np.uint64(31), np.uint64(11)
_LANE = np.uint64(0xD1B54A32D192ED03)  # an odd constant spreading lanes over the word
_TWO_53 = 2.0**-53
LANES = 1 << 16  # lanes per counter: a lane is a number in [0, LANES)


@njit(**_JIT)
def mix64(z):
    """splitmix64's finalizer: a bijection of uint64 with full avalanche."""
    z = (z ^ (z >> _S30)) * _M1
    z = (z ^ (z >> _S27)) * _M2
    return z ^ (z >> _S31)


@njit(**_JIT)
def uniform(key, counter, lane):
    """A uniform in [0, 1) from ``key`` (uint64), ``counter`` and ``lane`` (ints >= 0)."""
    c = np.uint64(counter) * _GAMMA + np.uint64(lane) * _LANE
    z = mix64(key ^ mix64(c))
    return np.float64(z >> _S11) * _TWO_53


@njit(**_JIT)
def normal(key, counter, lane):
    """A standard normal from lanes ``2 lane`` and ``2 lane + 1`` (Box-Muller)."""
    u1 = uniform(key, counter, 2 * lane)
    u2 = uniform(key, counter, 2 * lane + 1)
    return math.sqrt(-2.0 * math.log1p(-u1)) * math.cos(2.0 * math.pi * u2)


@njit(**_JIT)
def normal_pair(key, counter, lane):
    """Two independent standard normals from lanes ``2 lane`` and ``2 lane + 1`` (both of
    Box and Muller's outputs: half the logarithms and roots of two :func:`normal` calls)."""
    u1 = uniform(key, counter, 2 * lane)
    u2 = uniform(key, counter, 2 * lane + 1)
    r = math.sqrt(-2.0 * math.log1p(-u1))
    a = 2.0 * math.pi * u2
    return r * math.cos(a), r * math.sin(a)


def keys_from_uniforms(u: np.ndarray) -> np.ndarray:
    """64-bit keys from uniforms in [0, 1) (an episode's draws): the 53 bits each holds,
    spread by the mix so that nearby uniforms give unrelated keys."""
    bits = np.floor(np.asarray(u, dtype=np.float64) * 2.0**53).astype(np.uint64)
    return _mix_array(bits)


def foreign_keys(rng: np.random.Generator, n: int) -> np.ndarray:
    """``n`` keys that no episode start gives (a planner's rollouts: noise of their own).

    An episode's key is ``mix64(bits + GAMMA)`` with ``bits < 2**53`` (:func:`keys_from_uniforms`)
    and ``mix64`` is a bijection, so keys mixed from words outside ``[GAMMA, GAMMA + 2**53)``
    are never an episode's: these mix ``GAMMA + 2**53 + r``, r drawn below ``2**62`` (no wrap
    past ``2**64``)."""
    r = rng.integers(0, 2**62, size=n, dtype=np.uint64)
    return _mix_array(r + np.uint64(2**53))


@njit(cache=True)
def _mix_array(bits):
    out = np.empty_like(bits)
    for i in range(bits.size):
        out[i] = mix64(bits[i] + _GAMMA)
    return out


@njit(cache=True)
def normals(keys, counter, lane, out):
    """``out[i] = normal(keys[i], counter, lane)``: for tests and for numpy callers."""
    for i in range(keys.size):
        out[i] = normal(keys[i], counter, lane)
