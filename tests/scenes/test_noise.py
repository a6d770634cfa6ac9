"""The counter-based noise of scenes/noise.py against the laws it claims: uniform on [0, 1),
standard normal (Box and Muller, 1958), numbers independent across lanes, counters and keys.
Tolerances: five standard errors of each estimator at the sample size used."""

import math

import numpy as np
import pytest

from fluidsim_envs.scenes import noise as NZ

N = 200_000


def _normals(keys, counter, lane):
    out = np.empty(keys.size)
    NZ.normals(keys, counter, lane, out)
    return out


@pytest.fixture(scope="module")
def keys():
    return NZ.keys_from_uniforms(np.random.default_rng(7).random(N))


def test_keys_are_distinct_and_spread(keys):
    assert np.unique(keys).size == N
    # the top bit is set for about half of the keys (the mix spreads nearby uniforms)
    top = (keys >> np.uint64(63)).astype(float)
    assert abs(top.mean() - 0.5) < 5 * 0.5 / math.sqrt(N)


def test_normal_moments(keys):
    z = _normals(keys, 3, 5)
    se = 1 / math.sqrt(N)
    assert abs(z.mean()) < 5 * se
    assert abs(z.var() - 1.0) < 5 * math.sqrt(2) * se
    assert abs(np.mean(z**4) - 3.0) < 5 * math.sqrt(96) * se  # var(z^4) = 105 - 9
    tail = np.mean(np.abs(z) > 3.0)  # 2 (1 - Phi(3)) = 0.0026998
    p = math.erfc(3 / math.sqrt(2))
    assert abs(tail - p) < 5 * math.sqrt(p * (1 - p) / N)


def test_uniforms_are_uniform(keys):
    u = np.array([NZ.uniform.py_func(k, 11, 2) for k in keys[:20000]])
    counts, _ = np.histogram(u, bins=20, range=(0.0, 1.0))
    expected = u.size / 20
    chi2 = ((counts - expected) ** 2 / expected).sum()
    assert chi2 < 43.8  # the chi-square(19) quantile at 0.999
    assert u.min() >= 0.0 and u.max() < 1.0


@pytest.mark.parametrize("other", [(3, 6), (4, 5), (1003, 5)])
def test_lanes_and_counters_are_independent(keys, other):
    a = _normals(keys, 3, 5)
    b = _normals(keys, *other)
    r = np.corrcoef(a, b)[0, 1]
    assert abs(r) < 5 / math.sqrt(N)
    assert not np.array_equal(a, b)


def test_same_inputs_same_numbers(keys):
    np.testing.assert_array_equal(_normals(keys[:100], 9, 1), _normals(keys[:100], 9, 1))
