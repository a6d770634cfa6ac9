"""Dryden turbulence and the 1-cosine gust (scenes/turbulence.py) against their definitions
in MIL-HDBK-1797 (1997, appendix A 4.9.2) and MIL-F-8785C (1980, 3.7.2): the low-altitude
intensities and scale lengths, each component's variance sigma^2, and each component's
sample spectrum against the model's over the decade 0.044-0.5 Hz.

Tolerances from the estimators: 64 independent series of 16384 steps at 30 Hz. A standard
deviation's error is about 1 / sqrt(2 n_eff), n_eff = 64 x 546 s / (2 tau) (u and v:
tau = 5.2 s, about 3400, 1.2%; w: 0.71 s, 25000). Welch's estimate averages 64 x 15
segments (3.2% per bin: 15% is five of it); the Hann window's leakage from below the decade
adds to the lowest bins of u and v (measured: per bin 0.92-1.09, each decade's mean within
1.5%)."""

import math

import numpy as np
import pytest
from scipy.signal import welch

from fluidsim_envs.scenes import noise as NZ
from fluidsim_envs.scenes import turbulence as T

E, N, STEP = 64, 16384, 1 / 30
H_M, V_MPS = 5.0, 7.0


@pytest.fixture(scope="module")
def series():
    w20 = T.W20_MPS["light"]
    keys = NZ.keys_from_uniforms(np.random.default_rng(0).random(E))
    ids, count = np.arange(E), np.zeros(E, np.int64)
    state, out = np.zeros((E, T.NSTATE)), np.zeros((E, 3))
    height, speed, w = np.full(E, H_M), np.full(E, V_MPS), np.full(E, w20)
    x = np.zeros((N, E, 3))
    for k in range(N):
        count[:] = k
        T.dryden(ids, k == 0, keys, count, height, speed, w, STEP, state, out)
        x[k] = out
    return x, T.scales(H_M, w20)


def test_low_altitude_scales_are_the_handbooks():
    """h = 100 ft, W20 = 30 kt (moderate): sigma_w = 3 kt; L_w = h; the u scale and
    intensity from (0.177 + 0.000823 h)."""
    su, sw, lu, lw = T.scales(100 * T.FT_M, 30 * T.KNOT_MPS)
    d = 0.177 + 0.0823
    assert sw == pytest.approx(3 * T.KNOT_MPS)
    assert su == pytest.approx(sw / d**0.4)
    assert lu == pytest.approx(100 / d**1.2 * T.FT_M)
    assert lw == pytest.approx(100 * T.FT_M)
    assert T.scales(0.5, 10.0) == T.scales(10 * T.FT_M, 10.0)  # the 10-ft floor


def test_each_component_has_its_variance(series):
    x, (su, sw, lu, lw) = series
    std = x.std(axis=(0, 1))
    for got, want, tau in ((std[0], su, lu / V_MPS), (std[1], su, lu / V_MPS),
                           (std[2], sw, lw / V_MPS)):  # fmt: skip
        n_eff = E * N * STEP / (2 * tau)
        assert abs(got / want - 1) < 5 / math.sqrt(2 * n_eff), (got, want)


def test_sample_spectra_follow_the_model_over_a_decade(series):
    x, (su, sw, lu, lw) = series
    f, p = welch(x, fs=1 / STEP, nperseg=2048, axis=0)
    p = p.mean(axis=1)
    band = (f >= 0.04) & (f <= 0.5)
    assert f[band][-1] / f[band][0] >= 9.5
    for c, (sigma, length, second) in enumerate(((su, lu, False), (su, lu, True),
                                                 (sw, lw, True))):  # fmt: skip
        model = 2 * math.pi * T.spectrum(2 * math.pi * f[band], sigma, length, V_MPS, second)
        ratio = p[band, c] / model
        assert np.all(np.abs(ratio - 1) < 0.15), (c, ratio)
        assert abs(ratio.mean() - 1) < 0.05, (c, ratio.mean())


def test_the_model_spectra_integrate_to_sigma_squared():
    w = np.linspace(0, 2000, 2_000_001)
    for second in (False, True):
        total = np.trapezoid(T.spectrum(w, 1.3, 20.0, 7.0, second), w)
        assert total == pytest.approx(1.69, rel=2e-3)  # the tail beyond 2000 rad/s: 0.1%


def test_one_minus_cosine_gust_shape_and_peak():
    t = np.linspace(-1, 4, 501)
    g = np.array([T.gust(x, 1.0, 2.0, 3.0) for x in t])
    inside = (t >= 1.0) & (t <= 3.0)
    np.testing.assert_allclose(g[inside], 1.5 * (1 - np.cos(np.pi * (t[inside] - 1.0))), atol=1e-12)
    assert np.all(g[~inside] == 0.0)
    assert g.max() == pytest.approx(3.0) and t[np.argmax(g)] == pytest.approx(2.0)
