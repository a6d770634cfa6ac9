"""Simulator.set_external_force: a force and torque held on each body, against the closed
forms of constant loads under the default integrator (symplectic Euler)."""

from __future__ import annotations

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Simulator, World

INERTIA = (1.0, 2.0, 3.0)


def free_body():
    return Craft(name="block", mass_kg=2.0, inertia_kgm2=INERTIA)


def test_constant_force_and_torque_follow_the_closed_form():
    """A force F on a free mass from rest: v = F t / m exactly, and symplectic Euler's
    position x_n = (F / m) dt^2 n (n + 1) / 2 = (F / m) t (t + dt) / 2. A torque tau about a
    principal axis from rest: L = tau t, so w = tau t / I about that axis."""
    dt, n = 0.01, 100
    sim = Simulator(free_body(), World(gravity_mps2=0.0), num_envs=3, dt=dt)
    sim.set_external_force((4.0, 0.0, -1.0), torque_nm=(0.0, 0.0, 0.6), env_ids=[1])
    sim.step(steps=n)
    t = n * dt
    np.testing.assert_allclose(sim.lin_vel[1, 0], np.array([4.0, 0.0, -1.0]) * t / 2.0)
    np.testing.assert_allclose(sim.pos[1, 0], np.array([4.0, 0.0, -1.0]) / 2.0 * t * (t + dt) / 2)
    np.testing.assert_allclose(sim.ang_vel[1, 0], [0.0, 0.0, 0.6 * t / INERTIA[2]], atol=1e-12)
    # the others feel nothing
    assert not sim.pos[[0, 2]].any() and not sim.lin_vel[[0, 2]].any()
    force, torque = sim.external_force
    np.testing.assert_array_equal(force[1, 0], [4.0, 0.0, -1.0])
    np.testing.assert_array_equal(torque[1, 0], [0.0, 0.0, 0.6])


def test_force_is_held_through_reset_and_balances_gravity():
    """A force equal to the weight holds a body still in gravity, across a reset."""
    sim = Simulator(free_body(), World(), num_envs=2, dt=1 / 120)
    sim.set_external_force((0.0, 0.0, 2.0 * 9.81))
    sim.reset(pos=(1.0, 2.0, 3.0))
    sim.step(steps=240)
    np.testing.assert_allclose(sim.pos[:, 0], [[1.0, 2.0, 3.0]] * 2, atol=1e-12)


@pytest.mark.parametrize("integrator", ["rk4", "verlet_tetra"])
def test_every_integrator_applies_it(integrator):
    sim = Simulator(free_body(), World(gravity_mps2=0.0), dt=0.01, integrator=integrator)
    sim.set_external_force((2.0, 0.0, 0.0))
    sim.step(steps=50)
    np.testing.assert_allclose(sim.lin_vel[0, 0], [0.5, 0.0, 0.0], rtol=1e-12)


def test_bad_external_force_names_the_value():
    sim = Simulator([free_body(), free_body()], num_envs=2)
    with pytest.raises(ValueError, match=r"set_external_force: force_n of shape \(4,\)"):
        sim.set_external_force(np.zeros(4))
    with pytest.raises(ValueError, match="set_external_force: torque_nm has non-finite"):
        sim.set_external_force((0.0, 0.0, 0.0), torque_nm=(np.nan, 0.0, 0.0))
    with pytest.raises(ValueError, match="env_ids"):
        sim.set_external_force((1.0, 0.0, 0.0), env_ids=[5])
