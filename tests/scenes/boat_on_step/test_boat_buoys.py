"""BoatOnStep-v0 with ``buoy_bodies=True``: the buoys float moored at their marks, a hull
that hits one pushes it aside and is slowed, and the scene stays deterministic."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fluidsim_envs.physics.state import OQ, OV, OX
from fluidsim_envs.scenes.boat_on_step import GATES, BoatOnStepVectorEnv


def test_untouched_buoys_hold_their_marks_and_waterline():
    """Left alone (the boat idling at the start, far away), every buoy stays at its mark at
    its draft, upright, for 10 s: moored floating bodies at rest in calm water."""
    venv = BoatOnStepVectorEnv(num_envs=2, buoy_bodies=True)
    venv.reset(seed=3)
    rest = -venv.marker.waterline_m
    for _ in range(200):
        venv.step(np.zeros((2, 3)))
    pos = venv.sim.pos[:, 1:]
    np.testing.assert_allclose(pos[..., :2], venv.buoys, atol=1e-4)
    np.testing.assert_allclose(pos[..., 2], rest, atol=1e-4)
    np.testing.assert_allclose(np.abs(venv.sim.quat[:, 1:, 0]), 1.0, atol=1e-8)
    assert not venv.sim.pair_impulse.any()
    np.testing.assert_allclose(venv.buoy_xy(1), venv.sim.pos[1, 1:, :2])


def test_buoys_ride_the_swell_from_the_start():
    """In swell each buoy starts on the surface under its mark (its draft below it)."""
    venv = BoatOnStepVectorEnv(num_envs=2, buoy_bodies=True, swell=[(0.3, 30.0, 45.0)])
    venv.reset(seed=5)
    pos = venv.sim.pos[:, 1:]
    z = venv.world.surface_height(pos[..., 0], pos[..., 1], venv.sim.clock[:, None])
    np.testing.assert_allclose(pos[..., 2] - z, -venv.marker.waterline_m, atol=1e-12)


def aim_at_buoy(venv, e, buoy, distance, speed, miss_m=0.0):
    """Move sub-env e's buoy ``buoy`` (1-based body) and its mark to ``distance`` ahead of
    the boat (``miss_m`` to its left), and set the boat moving at ``speed``."""
    st, _, _ = venv.sim.kernel_arrays()
    w, x, y, z = st[OQ : OQ + 4, 0, e]
    yaw = math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    fwd = np.array([math.cos(yaw), math.sin(yaw)])
    left = np.array([-fwd[1], fwd[0]])
    mark = st[OX : OX + 2, 0, e] + distance * fwd + miss_m * left
    venv.buoys[e, buoy - 1] = mark
    st[OX : OX + 2, buoy, e] = mark
    st[OV : OV + 2, 0, e] = speed * fwd


def test_hit_pushes_the_buoy_aside_and_slows_the_boat():
    """Two boats coasting at 8 m/s, one at a buoy 10 m ahead, one passing 20 m clear of it:
    the first touches it (``hit_buoy``, the pair's impulse, the buoy penalty), the buoy is
    thrown off its mark and the boat loses speed to it; the chain then pulls the buoy back."""
    venv = BoatOnStepVectorEnv(num_envs=2, buoy_bodies=True)
    venv.reset(seed=11)
    for e, miss in ((0, 0.0), (1, 20.0)):
        aim_at_buoy(venv, e, 1, 10.0, 8.0, miss)
    hits, drift, speed = np.zeros(2, dtype=bool), [], []
    for _ in range(80):  # 4 s
        _, _, term, _, info = venv.step(np.zeros((2, 3)))
        assert not term.any()
        hits |= info["hit_buoy"]
        if info["hit_buoy"][0]:
            assert venv.sim.pair_impulse[0, 0] > 0.0
            assert info["reward_terms"]["buoy"][0] == -venv.params.w_buoy
        drift.append(np.linalg.norm(venv.sim.pos[:, 1, :2] - venv.buoys[:, 0], axis=1))
        speed.append(np.linalg.norm(venv.sim.lin_vel[:, 0, :2], axis=1))
    drift, speed = np.array(drift), np.array(speed)
    assert hits.tolist() == [True, False]
    assert drift[:, 0].max() > 1.0 and drift[:, 1].max() < 1e-3
    # the buoy's momentum came out of the boat's (40 kg at up to 1.3 x 8 m/s: 0.4 m/s of 1 t)
    assert speed[-1, 1] - speed[-1, 0] > 0.2
    for _ in range(200):  # 10 s more: back toward its mark on the chain
        venv.step(np.zeros((2, 3)))
    back = np.linalg.norm(venv.sim.pos[0, 1, :2] - venv.buoys[0, 0])
    assert back < 0.5 * drift[:, 0].max()


@pytest.mark.parametrize("num_envs, idx", [(5, [0, 3, 4])])
def test_same_seed_same_trajectory_for_any_num_envs(num_envs, idx):
    """With buoy bodies too, sub-env i depends only on its seed and actions, resets
    included (bit for bit across batch sizes)."""
    seeds = [40 + i for i in range(num_envs)]
    rng = np.random.default_rng(0)
    acts = np.clip(rng.normal(0.6, 0.5, size=(30, num_envs, 3)), -1, 1)
    env = BoatOnStepVectorEnv(num_envs=num_envs, buoy_bodies=True, max_episode_steps=12)
    ref = BoatOnStepVectorEnv(num_envs=len(idx), buoy_bodies=True, max_episode_steps=12)
    obs, _ = env.reset(seed=seeds)
    ref_obs, _ = ref.reset(seed=[seeds[i] for i in idx])
    np.testing.assert_array_equal(obs[idx], ref_obs)
    for a in acts:
        obs, r, *_ = env.step(a)
        ref_obs, ref_r, *_ = ref.step(a[idx])
        np.testing.assert_array_equal(obs[idx], ref_obs)
        np.testing.assert_array_equal(r[idx], ref_r)
        np.testing.assert_array_equal(env.sim.pos[idx], ref.sim.pos)


def test_bad_buoy_options_name_the_value():
    with pytest.raises(ValueError, match="buoy_bodies must be True or False, got 'yes'"):
        BoatOnStepVectorEnv(buoy_bodies="yes")


def test_default_env_keeps_one_body():
    venv = BoatOnStepVectorEnv(num_envs=1)
    assert venv.sim.num_bodies == 1
    assert venv.sim.num_bodies + 2 * GATES == BoatOnStepVectorEnv(buoy_bodies=True).sim.num_bodies
