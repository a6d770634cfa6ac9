"""Irregular seas (physics/surface.py: jonswap, irregular_sea) against their definitions:
the JONSWAP spectrum of DNV-RP-C205 (2010, 3.5.5) has 4 sqrt(m0) = Hs to within its
normalizing factor's accuracy (DNV: 1-2%; measured below), the sea built from it has the
spectrum's m0, and a long record of its surface has the significant height 4 sqrt(m0) within
5% (a 4-component sea over 2000 s: the sample variance's error is under 1%)."""

import math

import numpy as np
import pytest

from fluidsim_envs.physics import World
from fluidsim_envs.physics.surface import irregular_sea, jonswap


@pytest.mark.parametrize("gamma", [1.0, 3.3, 7.0])
def test_jonswap_holds_its_significant_height(gamma):
    w = np.linspace(0.01, 40.0, 400001)
    m0 = np.trapezoid(jonswap(w, 0.6, 4.0, gamma), w)
    assert 4 * math.sqrt(m0) == pytest.approx(0.6, rel=0.02)


def test_the_peak_is_at_the_peak_period():
    w = np.linspace(0.5, 5.0, 100001)
    assert w[np.argmax(jonswap(w, 0.5, 3.0))] == pytest.approx(2 * math.pi / 3.0, rel=1e-3)


def test_a_record_of_the_sea_has_the_spectrums_height():
    waves = irregular_sea(0.5, 3.5, gamma=3.3, seed=4)
    w = np.linspace(0.01, 40.0, 400001)
    m0 = np.trapezoid(jonswap(w, 0.5, 3.5, 3.3), w)
    assert sum(x.amplitude_m**2 / 2 for x in waves) == pytest.approx(m0, rel=1e-3)
    world = World(water=True, swell=waves)
    t = np.arange(0.0, 2000.0, 0.05)
    eta = world.surface_height(np.zeros_like(t), np.zeros_like(t), t)
    assert 4 * eta.std() == pytest.approx(4 * math.sqrt(m0), rel=0.05)
    periods = sorted(2 * math.pi / math.sqrt(9.81 * x.wavenumber) for x in waves)
    assert periods[0] < 3.5 < periods[-1]  # the bands straddle the peak


def test_bad_seas_are_named():
    with pytest.raises(ValueError, match="hs_m"):
        irregular_sea(0.0, 3.0)
    with pytest.raises(ValueError, match="waves"):
        irregular_sea(0.5, 3.0, waves=9)
