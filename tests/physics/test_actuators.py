"""Actuators (Simulator.set_actuators) against the first-order lag's closed form: after a
step of the command from 0 to 1 a channel is at 1 - exp(-t / tau), 63.2% at t = tau (exact
for a command held over each step, to rounding); and a rate limit it never exceeds."""

import math

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Simulator, World

DT = 1 / 120


@pytest.fixture(scope="module")
def dart():
    return Craft.load("paper_airplane")


def _sim(craft, E=2):
    sim = Simulator(craft, World(), num_envs=E, dt=DT, integrator="rk2")
    sim.reset(pos=(0.0, 0.0, 100.0), lin_vel=(6.0, 0.0, 0.0))
    return sim


def test_step_response_is_the_first_order_lag(dart):
    tau = 0.1
    sim = _sim(dart)
    sim.set_actuators(time_constant_s=tau, rate_limit_per_s=1e6)
    command = np.ones((2, 3))
    out = []
    for _ in range(36):  # 0.3 s
        sim.step(command, steps=1)
        out.append(sim.actuators[0, 0])
    t = DT * np.arange(1, 37)
    np.testing.assert_allclose(out, 1 - np.exp(-t / tau), rtol=0, atol=1e-14)
    k = round(tau / DT) - 1  # the step that ends at t = tau
    assert abs(out[k] - (1 - math.exp(-1))) < 1e-14  # 63.2%


def test_rate_limit_is_never_exceeded(dart):
    sim = _sim(dart)
    rate = 2.0  # control units per second: 40 deg/s on a 20-degree aileron
    sim.set_actuators(time_constant_s=0.01, rate_limit_per_s=rate)
    command = np.array([[1.0, -1.0, 0.5], [0.0, 0.0, 0.0]])
    last = sim.actuators.copy()
    moves = []
    for _ in range(80):
        sim.step(command, steps=1)
        moves.append(np.abs(sim.actuators - last).max())
        last = sim.actuators.copy()
    assert max(moves) <= rate * DT * (1 + 1e-12)
    assert moves[0] == pytest.approx(rate * DT)  # limited from the first step
    np.testing.assert_allclose(sim.actuators[0], [1.0, -1.0, 0.5], atol=1e-9)  # arrived


def test_surfaces_move_with_the_actuators_not_the_command(dart):
    """A full elevator commanded to a slow servo (0.5 control units/s: at most 1.7% of its
    travel in four steps) turns the dart by about that share of what an instant elevator
    does: the force follows the surface's position, not the command."""
    fast, slow, idle = _sim(dart), _sim(dart), _sim(dart)
    slow.set_actuators(time_constant_s=0.5, rate_limit_per_s=0.5)
    command = np.tile([0.0, 1.0, 0.0], (2, 1))
    fast.step(command, steps=4)
    slow.step(command, steps=4)
    idle.step(np.zeros((2, 3)), steps=4)
    q = [s.ang_vel[0, 0, 1] - idle.ang_vel[0, 0, 1] for s in (fast, slow)]
    assert abs(q[1]) < 0.05 * abs(q[0])
    assert q[1] * q[0] > 0.0  # the same way, less


def test_reset_centres_and_snapshots_keep_them(dart):
    sim = _sim(dart)
    sim.set_actuators(time_constant_s=0.05, rate_limit_per_s=3.0)
    sim.step(np.ones((2, 3)), steps=5)
    snap = sim.get_state()
    sim.step(np.ones((2, 3)), steps=3)
    after = sim.actuators.copy(), sim.pos.copy()
    sim.set_state(snap)
    sim.step(np.ones((2, 3)), steps=3)
    np.testing.assert_array_equal(sim.actuators, after[0])
    np.testing.assert_array_equal(sim.pos, after[1])
    sim.reset(env_ids=[1])
    assert np.all(sim.actuators[1] == 0.0) and np.all(sim.actuators[0] > 0.0)


def test_forces_at_given_controls_leave_the_actuators(dart):
    sim = _sim(dart)
    sim.set_actuators(time_constant_s=0.05, rate_limit_per_s=3.0)
    sim.step(np.full((2, 3), 0.5), steps=2)
    held, told = sim.actuators.copy(), sim.controls.copy()
    sim.wrench(np.ones((2, 3)))
    sim.sample_forces(np.zeros(3))
    np.testing.assert_array_equal(sim.actuators, held)
    np.testing.assert_array_equal(sim.controls, told)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"time_constant_s": 0.0, "rate_limit_per_s": 1.0}, "time_constant_s must be"),
        ({"time_constant_s": 0.1, "rate_limit_per_s": -1.0}, "rate_limit_per_s must be"),
        ({"time_constant_s": 0.1}, "both"),
        ({"time_constant_s": [0.1, 0.2], "rate_limit_per_s": 1.0}, "time_constant_s"),
    ],
)
def test_bad_actuators_are_named(dart, kwargs, match):
    with pytest.raises(ValueError, match=match):
        _sim(dart).set_actuators(**kwargs)
