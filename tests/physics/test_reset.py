"""Simulator.reset takes what a new user passes first: ``[E, 3]`` rows for a one-body craft;
with several bodies an array that could mean either environments or bodies is refused."""

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Simulator, World

BALL = Craft(name="ball", mass_kg=1.0, inertia_kgm2=(0.4, 0.4, 0.4))


def test_one_body_takes_a_row_per_environment():
    sim = Simulator(BALL, World(), num_envs=3)
    pos = np.arange(9.0).reshape(3, 3)
    sim.reset(pos=pos, lin_vel=pos + 1, quat=np.tile([1.0, 0, 0, 0], (3, 1)))
    np.testing.assert_array_equal(sim.pos[:, 0], pos)
    np.testing.assert_array_equal(sim.lin_vel[:, 0], pos + 1)
    sim.reset(pos=[[5.0, 6.0, 7.0]], env_ids=[1])
    np.testing.assert_array_equal(sim.pos[1, 0], [5.0, 6.0, 7.0])


def test_several_bodies_take_a_row_per_body_and_refuse_the_ambiguous_case():
    sim = Simulator([BALL, BALL], World(), num_envs=3)
    sim.reset(pos=[[0.0, 0.0, 1.0], [0.0, 0.0, 2.0]])  # [B, 3]: every environment alike
    np.testing.assert_array_equal(sim.pos[:, :, 2], [[1.0, 2.0]] * 3)
    two = Simulator([BALL, BALL], World(), num_envs=2)
    with pytest.raises(ValueError, match=r"ambiguous with 2 environments of 2 bodies"):
        two.reset(pos=np.zeros((2, 3)))
    two.reset(pos=np.zeros((2, 2, 3)))  # explicit [E, B, 3] is fine
    with pytest.raises(ValueError, match=r"does not broadcast to \[3, 2, 3\]"):
        sim.reset(pos=np.zeros((3, 3)))
