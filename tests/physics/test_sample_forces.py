"""Simulator.sample_forces: each sample's point and force, recorded by the step kernel's own
force loops, adds up to Simulator.wrench (net force, and torque about the center of mass)."""

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Simulator, SwellWave, WakeField, World

E = 70  # two blocks of environments (kernels.BLOCK = 64): the second block is checked too


def _random_state(sim: Simulator, rng: np.random.Generator, height_m: float) -> np.ndarray:
    """Random poses near ``height_m`` with brisk motion; returns controls [E, C] in [-1, 1]."""
    E, B = sim.num_envs, sim.num_bodies
    quat = rng.normal(size=(E, B, 4)) * [1.0, 0.2, 0.2, 1.0]  # mostly upright
    sim.reset(
        pos=rng.normal(0.0, 0.3, (E, B, 3)) + [0.0, 0.0, height_m],
        quat=quat,
        lin_vel=rng.normal(0.0, 4.0, (E, B, 3)) + [8.0, 0.0, 0.0],
        ang_vel=rng.normal(0.0, 1.0, (E, B, 3)),
    )
    return rng.uniform(-1.0, 1.0, (E, len(sim.control_names)))


def _check_sums(sim: Simulator, controls: np.ndarray, envs) -> None:
    force, torque = sim.wrench(controls)
    for e in envs:
        points, forces, body = sim.sample_forces(controls, env_index=e)
        assert points.shape == forces.shape == (body.size, 3)
        assert np.all(np.isfinite(points)) and np.all(np.isfinite(forces))
        for b in range(sim.num_bodies):
            mine = body == b
            assert mine.sum() == sim.crafts[b].num_samples
            net = forces[mine].sum(axis=0)
            arm = points[mine] - sim.pos[e, b]
            moment = np.cross(arm, forces[mine]).sum(axis=0)
            scale_f = np.linalg.norm(force[e, b])
            scale_t = np.linalg.norm(torque[e, b])
            assert scale_f > 0.0 and scale_t > 0.0  # a state where something pushes
            np.testing.assert_allclose(net, force[e, b], rtol=0.0, atol=1e-9 * scale_f)
            np.testing.assert_allclose(moment, torque[e, b], rtol=0.0, atol=1e-9 * scale_t)
            # the samples sit on the body: within its reach of the center of mass
            reach = max(np.linalg.norm(s.offset_m) for s in _samples(sim.crafts[b]))
            assert np.linalg.norm(arm, axis=1).max() <= reach * (1 + 1e-12)


def _samples(craft: Craft):
    return (*craft.plates, *craft.cylinders, *craft.buoyancy, *craft.thrusters)


def test_paper_airplane_samples_sum_to_the_wrench():
    sim = Simulator(Craft.load("paper_airplane"), World(), num_envs=E)
    controls = _random_state(sim, np.random.default_rng(1), height_m=5.0)
    _check_sums(sim, controls, envs=(0, 37, E - 1))


@pytest.mark.parametrize("swell", [(), (SwellWave(0.4, 15.0, 30.0),)], ids=["calm", "swell"])
def test_speedboat_samples_sum_to_the_wrench(swell):
    world = World(water=True, swell=swell)
    sim = Simulator(Craft.load("speedboat"), world, num_envs=E)
    controls = _random_state(sim, np.random.default_rng(2), height_m=0.1)
    sim.set_clock(np.linspace(0.0, 30.0, E))
    _check_sums(sim, controls, envs=(3, E - 2))
    # the thruster is a sample: a full throttle's thrust is the craft's maximum, along its axis
    (prop,) = Craft.load("speedboat").thrusters
    controls[:, 0] = 1.0
    _, forces, _ = sim.sample_forces(controls, env_index=3)
    assert np.linalg.norm(forces[-1]) == pytest.approx(prop.max_thrust_n, rel=1e-12)


def test_several_bodies_and_a_wake():
    """Two bodies per environment (sample rows body by body) in a submarine's wake."""
    wake = WakeField(length_m=20.0, radius_m=2.0, noise=0.3)
    crafts = [Craft.load("uuv"), Craft.load("speedboat")]
    sim = Simulator(crafts, World(water=True), num_envs=E, wake=wake)
    controls = _random_state(sim, np.random.default_rng(3), height_m=-1.0)
    sim.set_wake_source(pos=(-5.0, 1.0, -3.0), quat=(1.0, 0.0, 0.0, 0.0), lin_vel=(2.0, 0, 0))
    _check_sums(sim, controls, envs=(5, 66))
    _, _, body = sim.sample_forces(controls, env_index=5)
    assert body.tolist() == [0] * crafts[0].num_samples + [1] * crafts[1].num_samples


def test_one_env_controls_float32_and_bad_input():
    sim = Simulator(Craft.load("paper_airplane"), World(), num_envs=3, dtype=np.float32)
    controls = _random_state(sim, np.random.default_rng(4), height_m=5.0)
    every = sim.sample_forces(controls, env_index=2)
    mine = sim.sample_forces(controls[2], env_index=2)  # only this env's channels
    for a, b in zip(every, mine, strict=True):
        np.testing.assert_array_equal(a, b)
    force, _ = sim.wrench(controls)
    np.testing.assert_allclose(every[1].sum(0), force[2, 0], rtol=1e-5)
    # the control surfaces feel their deflection: other controls give other forces
    other = sim.sample_forces(-controls[2], env_index=2)[1]
    assert not np.allclose(other, every[1])
    with pytest.raises(ValueError, match=r"env_index must be an integer in \[0, 3\), got 3"):
        sim.sample_forces(env_index=3)
    with pytest.raises(ValueError, match="controls must have shape"):
        sim.sample_forces(np.zeros(2), env_index=0)
    with pytest.raises(ValueError, match="controls must lie in"):
        sim.sample_forces(np.full(3, 2.0), env_index=0)
