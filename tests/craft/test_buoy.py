"""The marker buoy (fluidsim_envs/craft/buoy.py): the shipped file is generated from its
dimensions, and it floats where Archimedes' principle puts a sphere of its weight."""

from __future__ import annotations

import math
from importlib import resources

import numpy as np
import pytest

from fluidsim_envs.craft.buoy import WATER_DENSITY_KGM3, MarkerBuoy, buoy_toml
from fluidsim_envs.physics import Craft, Simulator, World


def test_shipped_file_is_generated_from_the_buoy_dimensions():
    shipped = (resources.files("fluidsim_envs.craft") / "buoy.toml").read_text()
    assert shipped == buoy_toml(), "run `python -m fluidsim_envs.craft.buoy`"


@pytest.mark.parametrize("radius", [0.4, 0.25, 1.0])
def test_draft_displaces_the_mass(radius):
    """Archimedes: the immersed spherical cap of height h, volume pi h^2 (3 r - h) / 3,
    weighs as much water as the buoy (the cap's volume: e.g. CRC Standard Mathematical
    Tables, spherical segment)."""
    b = MarkerBuoy.scaled(radius)
    h, r = b.draft_m, b.radius_m
    cap = math.pi * h * h * (3 * r - h) / 3
    assert WATER_DENSITY_KGM3 * cap == pytest.approx(b.mass_kg, rel=1e-12)
    assert h / r == pytest.approx(MarkerBuoy().draft_m / 0.4, rel=1e-9)  # similar buoys


@pytest.mark.parametrize("radius", [0.4, 1.0])
def test_buoy_floats_at_its_draft_and_rights_itself(radius):
    """Placed upright at its draft (center of gravity ``-waterline_m`` above calm water) it
    stays there: the samples' total force is its weight at that draft. Dropped
    10 cm high it bobs about that height, the bobbing dying away; tilted 10 degrees it rolls
    back and forth about upright, never past the tilt it started with."""
    b = MarkerBuoy.scaled(radius)
    sim = Simulator(Craft.from_dict(b.samples()), World(water=True), num_envs=3, dt=1 / 200)
    tilt = math.radians(10.0)
    rest = -b.waterline_m
    sim.reset(
        pos=[[[0.0, 0.0, rest]], [[0.0, 0.0, rest + 0.1]], [[0.0, 0.0, rest]]],
        quat=[[[1.0, 0.0, 0.0, 0.0]]] * 2 + [[[math.cos(tilt / 2), math.sin(tilt / 2), 0, 0]]],
    )
    heave, roll = [], []
    for _ in range(200 * 20):
        sim.step()
        heave.append(sim.pos[:, 0, 2] - rest)
        roll.append(2 * np.arcsin(np.abs(sim.quat[2, 0, 1])))
    heave, roll = np.array(heave), np.array(roll)
    assert np.abs(heave[:, 0]).max() < 2e-6  # the craft file's 6 decimals
    first, last = np.abs(heave[:1000, 1]).max(), np.abs(heave[-1000:, 1]).max()
    assert first > 0.05 and last < 0.5 * first
    assert roll.max() <= tilt * 1.01
    assert np.abs(sim.quat[:, 0, 2:]).max() < 1e-9  # a roll stays a roll


def test_heavier_than_its_volume_is_refused():
    with pytest.raises(ValueError, match="mass_kg 300.0 sinks a sphere of radius 0.4"):
        MarkerBuoy(mass_kg=300.0)
    with pytest.raises(ValueError, match="ballast_drop_m"):
        MarkerBuoy(ballast_drop_m=0.5)
    with pytest.raises(ValueError, match="radius_m must be a finite number > 0, got -1"):
        MarkerBuoy(radius_m=-1)


def test_speedboat_collision_boxes_cover_the_hull():
    """The hull's two boxes span the boat from the transom to the stem, keel to sheer."""
    boat = Craft.load("speedboat")
    lo = np.min([np.subtract(s.center_m, s.half_extents_m) for s in boat.shapes], axis=0)
    hi = np.max([np.add(s.center_m, s.half_extents_m) for s in boat.shapes], axis=0)
    np.testing.assert_allclose(hi[0] - lo[0], 5.0)  # length along the keel
    np.testing.assert_allclose(hi[1] - lo[1], 1.8)  # chine beam
    np.testing.assert_allclose(hi[2] - lo[2], 0.85)  # freeboard above the keel
