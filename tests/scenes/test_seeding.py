"""Seed streams (fluidsim_envs.seeding): a training run and the pilots' tuning draw episodes
that no evaluation flies, at any seed, and a stream is chosen only with a seed."""

import gymnasium as gym
import numpy as np
import pytest

import fluidsim_envs  # noqa: F401
from fluidsim_envs import seeding
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.wrappers.sb3 import make_sb3_vec_env

V1 = [s.id for s in SCENES.values() if s.id.endswith("-v1")]
E = 32


def _first_obs(env_id, seed, stream):
    venv = gym.make_vec(env_id, num_envs=E, vectorization_mode="vector_entry_point")
    options = None if stream == "evaluation" else {"stream": stream}
    obs, _ = venv.reset(seed=seed, options=options)
    venv.close()
    return obs


@pytest.mark.parametrize("env_id", V1)
def test_no_training_episode_is_an_evaluation_episode(env_id):
    """The first observation of every sub-env, at seeds 0-2 in each stream: no row of one
    stream is a row of another (a first observation carries the episode's drawn start, craft
    and sensor noise), while one stream at one seed is the same episodes again."""
    rows = {}
    for stream in seeding.STREAMS:
        for seed in (0, 1, 2):
            for row in _first_obs(env_id, seed, stream):
                rows.setdefault(row.tobytes(), set()).add(stream)
    assert len(rows) == len(seeding.STREAMS) * 3 * E  # every row is one episode's own
    again = _first_obs(env_id, 1, "training")
    np.testing.assert_array_equal(again, _first_obs(env_id, 1, "training"))


def test_a_single_env_in_a_stream_is_the_vector_envs_sub_env():
    """gym.make's env seeded s in a stream starts as sub-env 0 of a batch seeded [s, ...]
    there does (the list form spawns one child per seed, in every stream)."""
    env_id = V1[0]
    one = gym.make(env_id)
    obs, _ = one.reset(seed=7, options={"stream": "training"})
    venv = gym.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point")
    batch, _ = venv.reset(seed=[7, 8], options={"stream": "training"})
    np.testing.assert_array_equal(obs, batch[0])
    plain, _ = venv.reset(seed=[7, 8])
    assert not np.array_equal(plain[0], batch[0])


def test_the_sb3_adapter_seeds_its_stream():
    env_id = V1[0]
    adapter = make_sb3_vec_env(env_id, 4, seed=5, stream="training")
    venv = gym.make_vec(env_id, num_envs=4, vectorization_mode="vector_entry_point")
    expected, _ = venv.reset(seed=5, options={"stream": "training"})
    np.testing.assert_array_equal(adapter.reset(), expected)
    keys = [s.spawn_key for s in adapter.seed(5)]
    assert keys == [(seeding.KEYS["training"], i) for i in range(4)]


@pytest.mark.parametrize(
    "seed, options, message",
    [
        (0, {"stream": "train"}, "unknown seed stream 'train'; streams are"),
        (0, {"stream": 3}, "unknown seed stream 3"),
        (None, {"stream": "training"}, "pass a seed with it"),
    ],
)
def test_a_bad_stream_is_named(seed, options, message):
    venv = gym.make_vec(V1[0], num_envs=2, vectorization_mode="vector_entry_point")
    with pytest.raises(ValueError, match=message):
        venv.reset(seed=seed, options=options)
    with pytest.raises(ValueError, match="unknown seed stream 'tests'"):
        make_sb3_vec_env(V1[0], 2, stream="tests")
