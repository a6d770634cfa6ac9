"""The SB3 adapter over our native vector envs behaves as SB3's own DummyVecEnv over the
single envs: same observations, rewards, dones and infos step by step, across episode
boundaries (terminal_observation and TimeLimit.truncated included)."""

from __future__ import annotations

import dataclasses

import gymnasium as gym
import numpy as np
import pytest
from stable_baselines3.common.env_checker import check_env
from stable_baselines3.common.vec_env import DummyVecEnv, VecMonitor, VecNormalize

import fluidsim_envs  # noqa: F401  (registers the ids)
from fluidsim_envs.wrappers.sb3 import SB3VecEnv, make_sb3_vec_env

N_ENVS = 4
# parameters that end episodes within a few dozen steps, by termination and by truncation
SHORT = {
    "fluidsim/PaperAirplane-v0": {"max_episode_steps": 40, "launch_height_m": (1.0, 3.0)},
    "fluidsim/SubmarineWake-v0": {"max_episode_steps": 30, "lost_distance_m": 5.0},
    "fluidsim/BoatOnStep-v0": {
        "max_episode_steps": 40,
        "substeps": 20,
        "course_half_width_m": 5.0,
        "start_heading_deg": 90.0,
    },
}


def _single(env_id: str, kwargs: dict):
    # gym.make(id, max_episode_steps=n) takes n for a TimeLimit wrapper, while make_vec hands
    # it to the env's parameters; put every kwarg into the spec so the env gets them all
    spec = dataclasses.replace(gym.spec(env_id), kwargs={**gym.spec(env_id).kwargs, **kwargs})
    return lambda: gym.make(spec)


def assert_same_info(a: dict, b: dict, where: str) -> None:
    assert a.keys() == b.keys(), f"{where}: keys {sorted(a)} != {sorted(b)}"
    for key in a:
        x, y = a[key], b[key]
        if isinstance(x, dict):
            assert_same_info(x, y, f"{where}[{key}]")
        elif isinstance(x, np.ndarray):
            assert isinstance(y, np.ndarray) and x.dtype == y.dtype, f"{where}[{key}]"
            np.testing.assert_array_equal(x, y, err_msg=f"{where}[{key}]")
        else:
            assert type(x) is type(y) and (x == y or (x != x and y != y)), (
                f"{where}[{key}]: {x!r} != {y!r}"
            )


@pytest.mark.parametrize("env_id", sorted(SHORT))
def test_matches_dummy_vec_env_across_episode_boundaries(env_id):
    kwargs = SHORT[env_id]
    ours = make_sb3_vec_env(env_id, N_ENVS, **kwargs)
    theirs = DummyVecEnv([_single(env_id, kwargs) for _ in range(N_ENVS)])
    # DummyVecEnv seeds single env i with 7 + i; seed_each gives our sub-env i that stream
    assert ours.seed_each(theirs.seed(7)) == [7, 8, 9, 10]
    np.testing.assert_array_equal(ours.reset(), theirs.reset())
    assert ours.reset_infos == theirs.reset_infos
    rng = np.random.default_rng(0)
    ended = {"terminated": 0, "truncated": 0}
    for t in range(120):
        actions = rng.uniform(-1.0, 1.0, (N_ENVS, 3)).astype(np.float32)
        o1, r1, d1, i1 = ours.step(actions)
        o2, r2, d2, i2 = theirs.step(actions)
        np.testing.assert_array_equal(o1, o2, err_msg=f"obs at step {t}")
        assert o1.dtype == o2.dtype and r1.dtype == r2.dtype and d1.dtype == d2.dtype
        np.testing.assert_array_equal(r1, r2, err_msg=f"rewards at step {t}")
        np.testing.assert_array_equal(d1, d2, err_msg=f"dones at step {t}")
        for i in range(N_ENVS):
            assert_same_info(i1[i], i2[i], f"step {t} env {i}")
            if d1[i]:
                ended["truncated" if i1[i]["TimeLimit.truncated"] else "terminated"] += 1
        assert ours.reset_infos == theirs.reset_infos
    # the comparison crossed boundaries of both kinds, several times
    assert ended["terminated"] >= 2 and ended["truncated"] >= 2, ended
    # reseeding replays the same episodes in both
    ours.seed_each(theirs.seed(3))
    np.testing.assert_array_equal(ours.reset(), theirs.reset())
    ours.close(), theirs.close()


@pytest.mark.parametrize("env_id", sorted(SHORT))
def test_seed_goes_through_the_envs_seed_sequence(env_id):
    """``seed(s)`` gives sub-env i ``SeedSequence(s).spawn(E)[i]``, as the vector env's own
    ``reset(seed=s)`` does: the same streams either way (episodes and their autoresets), for
    any batch size, and not the streams of SB3's default ``s + i``."""
    kwargs = SHORT[env_id]
    ours = make_sb3_vec_env(env_id, N_ENVS, seed=11, **kwargs)
    native = gym.make_vec(
        env_id, num_envs=N_ENVS, vectorization_mode="vector_entry_point", **kwargs
    )
    plus_i = gym.make_vec(
        env_id, num_envs=N_ENVS, vectorization_mode="vector_entry_point", **kwargs
    )
    obs = ours.reset()
    np.testing.assert_array_equal(obs, native.reset(seed=11)[0])
    seeded_plus_i = plus_i.reset(seed=[11 + i for i in range(N_ENVS)])[0]
    assert not np.array_equal(obs, seeded_plus_i), "seeded as seed + i"
    # a batch of two sees the first two streams of the batch of four
    two = make_sb3_vec_env(env_id, 2, seed=11, **kwargs)
    np.testing.assert_array_equal(two.reset(), obs[:2])
    rng = np.random.default_rng(2)
    ends = 0
    for t in range(60):  # through episode ends: the autoresets draw from the same streams
        actions = rng.uniform(-1.0, 1.0, (N_ENVS, 3)).astype(np.float32)
        o1, r1, d1, _ = ours.step(actions)
        o2, r2, term, trunc, _ = native.step(actions)
        np.testing.assert_array_equal(o1, o2, err_msg=f"obs at step {t}")
        np.testing.assert_array_equal(r1, r2.astype(np.float32), err_msg=f"rewards at step {t}")
        np.testing.assert_array_equal(d1, term | trunc, err_msg=f"dones at step {t}")
        np.testing.assert_array_equal(two.step(actions[:2])[0], o1[:2])
        ends += int(d1.sum())
    assert ends >= 2
    # reseeding replays the first reset
    assert [c.spawn_key for c in ours.seed(11)] == [(i,) for i in range(N_ENVS)]
    np.testing.assert_array_equal(ours.reset(), obs)
    with pytest.raises(ValueError, match="expected an int"):
        ours.seed(1.5)
    for venv in (ours, native, plus_i, two):
        venv.close()


def test_vec_env_api():
    """SB3's env checker on the single env the adapter batches, then the VecEnv API itself."""
    env_id = "fluidsim/PaperAirplane-v0"
    check_env(gym.make(env_id), warn=True)
    venv = make_sb3_vec_env(env_id, 3, seed=1, render_mode="rgb_array")
    assert isinstance(venv, SB3VecEnv) and venv.num_envs == 3
    assert venv.observation_space == venv.venv.single_observation_space
    assert venv.action_space == venv.venv.single_action_space
    obs = venv.reset()
    assert obs.shape == (3, *venv.observation_space.shape) and obs.dtype == np.float32
    assert venv.observation_space.contains(obs[0])
    venv.step_async(np.zeros((3, 3), dtype=np.float32))
    obs, rewards, dones, infos = venv.step_wait()
    assert rewards.shape == dones.shape == (3,) and len(infos) == 3
    assert all(info["TimeLimit.truncated"] is False for info in infos)
    # attributes are the vector env's, shared by every sub-env
    assert venv.get_attr("params")[0] is venv.venv.params
    assert venv.get_attr("render_mode", indices=[0, 2]) == ["rgb_array"] * 2
    assert venv.has_attr("params") and not venv.has_attr("no_such_attribute")
    venv.set_attr("custom_flag", 5)
    assert venv.venv.custom_flag == 5 and venv.get_attr("custom_flag") == [5, 5, 5]
    with pytest.raises(ValueError, match="shared by all 3 sub-envs"):
        venv.set_attr("custom_flag", 6, indices=[1])
    with pytest.raises(ValueError, match="shared by all 3 sub-envs"):
        venv.env_method("render", indices=1)
    assert venv.env_is_wrapped(gym.Wrapper) == [False] * 3
    images = venv.get_images()
    assert len(images) == 3 and images[0].ndim == 3 and images[0].dtype == np.uint8
    assert venv.render().ndim == 3  # tiled by VecEnv.render
    # options go to the next reset only: reset just sub-env 1, the others keep their rows
    venv.set_options({"env_ids": [1]})
    again = venv.reset()
    np.testing.assert_array_equal(again[[0, 2]], obs[[0, 2]])
    assert not np.array_equal(again[1], obs[1])
    assert venv._options == [{}] * 3
    venv.set_options([{"env_ids": [0]}, {}, {}])
    with pytest.raises(ValueError, match="one options dict"):
        venv.reset()
    venv.close()


def test_refuses_a_vector_env_without_same_step_autoreset():
    venv = gym.make_vec(
        "fluidsim/PaperAirplane-v0",
        num_envs=2,
        vectorization_mode="vector_entry_point",
        autoreset=False,
    )
    with pytest.raises(ValueError, match="same-step autoreset"):
        SB3VecEnv(venv)


def test_under_vec_normalize_and_vec_monitor():
    """The training stack: monitor the raw episodes, normalize what the learner sees."""
    kwargs = SHORT["fluidsim/PaperAirplane-v0"]
    venv = VecNormalize(VecMonitor(make_sb3_vec_env("fluidsim/PaperAirplane-v0", 4, **kwargs)))
    venv.seed(0)
    obs = venv.reset()
    assert obs.shape == (4, 15)
    rng = np.random.default_rng(1)
    episodes = []
    for _ in range(60):
        obs, rewards, dones, infos = venv.step(rng.uniform(-1, 1, (4, 3)).astype(np.float32))
        assert np.isfinite(obs).all() and np.isfinite(rewards).all()
        assert np.abs(obs).max() <= venv.clip_obs
        for i in np.flatnonzero(dones):
            episodes.append(infos[i]["episode"])
            # VecNormalize normalizes the terminal observation as well
            assert infos[i]["terminal_observation"].shape == (15,)
    assert len(episodes) >= 4
    assert all(ep["l"] <= kwargs["max_episode_steps"] for ep in episodes)
    assert venv.obs_rms.count > 4 * 60
    raw = venv.get_original_obs()
    assert raw.shape == (4, 15) and not np.allclose(raw, obs)
    venv.close()


def test_replace_steps_the_new_vector_env_and_refuses_other_spaces():
    """A curriculum's next stage: the adapter steps the new env (its own parameters) with
    the counters going on; a different count of envs or spaces is refused, naming both."""
    from fluidsim_envs.wrappers.sb3 import make_vector_env

    adapter = make_sb3_vec_env("fluidsim/PaperAirplane-v1", 2, seed=0)
    adapter.reset()
    adapter.step(np.zeros((2, *adapter.action_space.shape), np.float32))
    adapter.replace(make_vector_env("fluidsim/PaperAirplane-v1", 2, difficulty="easy"))
    assert adapter.venv.unwrapped.params.difficulty == "easy" and adapter.env_steps == 2
    adapter.seed(1)
    adapter.reset()
    adapter.step(np.zeros((2, *adapter.action_space.shape), np.float32))
    assert adapter.env_steps == 4
    for other in (
        make_vector_env("fluidsim/PaperAirplane-v1", 3),
        make_vector_env("fluidsim/PaperAirplane-v1", 2, observe_samples=False),
    ):
        with pytest.raises(ValueError, match=r"replace: the new vector env's \(num_envs"):
            adapter.replace(other)
        other.close()
    adapter.close()


def test_info_keys_carry_only_those_entries_and_sb3s_own():
    """With ``info_keys`` (what training passes), each sub-env's dict holds those entries and
    SB3's own (``TimeLimit.truncated``; at an episode's end ``terminal_observation`` and
    ``is_success``), with the values the full dicts hold, across episode boundaries."""
    env_id = "fluidsim/PaperAirplane-v0"
    kwargs = SHORT[env_id]
    full = make_sb3_vec_env(env_id, N_ENVS, seed=5, success_key="success", **kwargs)
    lean = make_sb3_vec_env(
        env_id, N_ENVS, seed=5, success_key="success", info_keys=("success",), **kwargs
    )
    np.testing.assert_array_equal(full.reset(), lean.reset())
    assert all(info.keys() <= {"success"} for info in lean.reset_infos)
    rng = np.random.default_rng(1)
    ends = 0
    for _ in range(60):
        actions = rng.uniform(-1.0, 1.0, (N_ENVS, 3)).astype(np.float32)
        o1, r1, d1, i1 = full.step(actions)
        o2, r2, d2, i2 = lean.step(actions)
        np.testing.assert_array_equal(o1, o2)
        np.testing.assert_array_equal(r1, r2)
        np.testing.assert_array_equal(d1, d2)
        for a, b, done in zip(i1, i2, d1, strict=True):
            sb3 = {"TimeLimit.truncated"} | (
                {"terminal_observation", "is_success"} if done else set()
            )
            assert b.keys() == {"success"} | sb3, sorted(b)
            assert_same_info({k: a[k] for k in b}, b, "lean info")
            ends += int(done)
    assert ends >= 2  # the comparison crossed episode boundaries
    full.close(), lean.close()
