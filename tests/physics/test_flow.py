"""Per-environment wind and current, and the wrench accessor."""

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Plate, Simulator, World


def test_uniform_wind_is_a_galilean_shift():
    """A body in uniform wind W moving at v + W sees the same air as one moving at v in still
    air (Galilean invariance): the trajectories differ by W t exactly, up to rounding."""
    craft = Craft.load("paper_airplane")
    wind = np.array([2.0, -1.0, 0.3])
    windy = Simulator(craft, World(), num_envs=2, dt=1 / 240)
    still = Simulator(craft, World(), num_envs=2, dt=1 / 240)
    windy.set_wind(wind, env_ids=[1])  # env 0 keeps the World's calm air
    q = (0.98, 0.05, -0.1, 0.15)
    v0 = np.array([5.0, 0.5, -0.5])
    windy.reset(
        pos=(0.0, 0.0, 10.0),
        quat=q,
        lin_vel=np.stack([v0, v0 + wind])[:, None],
        ang_vel=(0.3, -1, 0.5),
    )
    still.reset(pos=(0.0, 0.0, 10.0), quat=q, lin_vel=v0, ang_vel=(0.3, -1, 0.5))
    windy.step(steps=240)
    still.step(steps=240)
    np.testing.assert_array_equal(windy.pos[0], still.pos[0])
    np.testing.assert_allclose(windy.lin_vel[1] - wind, still.lin_vel[1], atol=1e-9)
    np.testing.assert_allclose(windy.pos[1] - wind * 1.0, still.pos[1], atol=1e-9)
    np.testing.assert_allclose(windy.quat[1], still.quat[1], atol=1e-9)
    np.testing.assert_array_equal(windy.wind_mps, [[0, 0, 0], wind])


def test_set_wind_rejects_bad_values():
    sim = Simulator(Craft.load("paper_airplane"), num_envs=3)
    with pytest.raises(ValueError, match="wind_mps has non-finite"):
        sim.set_wind((0.0, np.nan, 0.0))
    with pytest.raises(ValueError, match=r"does not broadcast to \[2, 3\]"):
        sim.set_wind(np.zeros((3, 3)), env_ids=[0, 2])
    with pytest.raises(ValueError, match="env_ids"):
        sim.set_current((1.0, 0.0, 0.0), env_ids=[3])


def test_wrench_of_one_plate_is_the_closed_form():
    """A plate of area A, normal z, offset r, moving along -z at speed V: F = 1/2 rho A V^2
    along +z by the plate law of DESIGN.md; head-on that is all drag, so efficiency e keeps
    (1 - e) of it. The
    torque about the center of mass is r x F."""
    r = np.array([0.3, -0.2, 0.1])
    craft = Craft(
        name="plate",
        mass_kg=1.0,
        inertia_kgm2=(1.0, 1.0, 1.0),
        plates=(Plate("p", tuple(r), (0.0, 0.0, 1.0), 0.5, efficiency=0.7),),
    )
    sim = Simulator(craft, World(air_density_kgm3=1.2), num_envs=1)
    sim.reset(lin_vel=(0.0, 0.0, -4.0))
    force, torque = sim.wrench()
    expected = np.array([0.0, 0.0, 0.5 * 1.2 * 0.5 * 16.0 * (1.0 - 0.7)])
    np.testing.assert_allclose(force[0, 0], expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(torque[0, 0], np.cross(r, expected), rtol=1e-12, atol=1e-12)
