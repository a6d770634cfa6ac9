"""The env contract, once for every scene of SCENES (single env and vector env): gymnasium's and
SB3's env checkers, vector == single across episode ends, the same seed giving the same
trajectory for any batch size, the episode boundary (final_obs, final_info, autoreset), the
time limit, pickling, divergence ending an episode with info["physics_diverged"], bad inputs,
saturating actions and rgb_array frames. A new scene gets all of it by registering.

The scene-specific tests (reward terms, task physics, the scene's own parameters) live beside
each scene in tests/scenes/<scene>/.

Conventions a scene keeps (and these tests hold it to): its reward terms include ``crash``,
worth ``-params.w_crash`` on a diverged step, and its final info has a ``success`` flag.
"""

import pickle
import re

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env as gym_check_env

import fluidsim_envs  # noqa: F401  (registers the envs)
from fluidsim_envs.scenes import SCENES

IDS = list(SCENES)


@pytest.fixture(params=IDS, ids=[i.split("/")[1] for i in IDS])
def scene(request):
    return SCENES[request.param]


def n_actions(scene):
    return len(scene.vector_cls.action_names)


def actions_for(scene, seed, steps, n=1):
    """A fixed, wiggly action sequence [steps, n, A] (a pilot that moves every control, the
    first one mostly ahead)."""
    rng = np.random.default_rng(seed)
    a = rng.normal(0.0, 0.5, size=(steps, n, n_actions(scene)))
    a[..., 0] += 0.3
    return np.clip(a, -1, 1)


# ---- the checkers -------------------------------------------------------------------------


def test_gymnasium_check_env(scene):
    gym_check_env(gym.make(scene.id).unwrapped)
    gym_check_env(gym.make(scene.id, render_mode="rgb_array").unwrapped, skip_render_check=False)


def test_sb3_check_env(scene):
    sb3_env_checker = pytest.importorskip("stable_baselines3.common.env_checker")
    sb3_env_checker.check_env(scene.env_cls(), warn=True)


def test_sb3_vec_env_checker_through_the_adapter(scene):
    """The vector env through the SB3 adapter passes SB3's VecEnv checks (spaces, reset, step
    shapes and dtypes)."""
    pytest.importorskip("stable_baselines3")
    from stable_baselines3.common.vec_env.base_vec_env import VecEnv

    from fluidsim_envs.wrappers.sb3 import SB3VecEnv

    venv = SB3VecEnv(scene.vector_cls(num_envs=3))
    assert isinstance(venv, VecEnv)
    venv.seed(0)
    obs = venv.reset()
    assert obs.shape == (3, scene.vector_cls.obs_dim) and obs.dtype == np.float32
    venv.step_async(actions_for(scene, 0, 1, 3)[0])
    obs, reward, done, infos = venv.step_wait()
    assert obs.shape == (3, scene.vector_cls.obs_dim) and reward.shape == (3,)
    assert done.shape == (3,) and len(infos) == 3
    venv.close()


# ---- vector == single, determinism ---------------------------------------------------------


def run_single(scene, seed, actions):
    """Roll the single env through ``actions``, resetting (unseeded) after each episode end;
    the observations, rewards, (terminated, truncated) and the terminal steps' observations
    and infos."""
    env = scene.env_cls(**scene.short_episodes)
    obs, _ = env.reset(seed=seed)
    rows, rewards, dones, finals = [obs], [], [], {}
    for k, a in enumerate(actions):
        obs, r, term, trunc, info = env.step(a)
        rewards.append(r)
        dones.append((term, trunc))
        if term or trunc:
            finals[k] = (obs, info)
            obs, _ = env.reset()
        rows.append(obs)
    return np.array(rows), np.array(rewards), np.array(dones), finals


def test_vector_env_matches_single_env_across_episode_ends(scene):
    """Sub-env i of a vector env seeded with a list of seeds is, bit for bit, the single env
    seeded with seed i, through several same-step autoresets: observations, rewards, flags,
    and at each end the terminal observation (final_obs) and final info."""
    seeds = [3, 17, 99]
    acts = actions_for(scene, 0, 120, len(seeds))
    venv = gym.make_vec(
        scene.id, num_envs=3, vectorization_mode="vector_entry_point", **scene.short_episodes
    )
    for key, value in scene.short_episodes.items():
        assert getattr(venv.unwrapped.params, key) == value
    obs, _ = venv.reset(seed=seeds)
    vobs, vrew, vdone, vinfo = [obs], [], [], []
    for a in acts:
        obs, r, term, trunc, info = venv.step(a)
        vobs.append(obs)
        vrew.append(r)
        vdone.append(np.stack([term, trunc], 1))
        vinfo.append(info)
    vobs, vrew, vdone = np.array(vobs), np.array(vrew), np.array(vdone)
    for i, s in enumerate(seeds):
        sobs, srew, sdone, finals = run_single(scene, s, acts[:, i])
        assert sdone.any(axis=1).sum() >= 2  # the comparison crosses episode boundaries
        np.testing.assert_array_equal(vobs[:, i], sobs)
        np.testing.assert_array_equal(vrew[:, i], srew)
        np.testing.assert_array_equal(vdone[:, i], sdone)
        for k, (s_obs, s_info) in finals.items():
            info = vinfo[k]
            assert info["_final_obs"][i] and info["_final_info"][i]
            np.testing.assert_array_equal(info["final_obs"][i], s_obs)
            final = info["final_info"]
            for key, value in s_info.items():
                if isinstance(value, dict):
                    for term, v in value.items():
                        assert final[key][term][i] == v, (key, term)
                else:
                    assert final[key][i] == value, key
            # the episode's reward terms sum to its return
            start = max([j for j in finals if j < k], default=-1) + 1
            assert sum(final["episode_terms"][t][i] for t in venv.unwrapped.reward_terms) == (
                pytest.approx(srew[start : k + 1].sum())
            )


@pytest.mark.parametrize(
    "num_envs, idx, steps",
    [
        (1, [0], 40),
        (7, [0, 3, 6], 40),
        (130, [0, 63, 64, 129], 30),  # across the kernel's 64-env blocks
        (1100, list(range(7)), 20),  # >= 1024 bodies: the threaded kernels, time limits
    ],
)
def test_same_seed_same_trajectory_for_any_num_envs(scene, num_envs, idx, steps):
    """Sub-env i's trajectory depends only on its seed and actions: the batch of num_envs and
    a small batch holding the same seeds (plus one other) agree bit for bit, resets included;
    and an int seed gives sub-env i the same start for any batch size."""
    seeds = [1000 + i for i in range(num_envs)]
    acts = actions_for(scene, 7, steps, num_envs)
    params = {"max_episode_steps": 15}
    env = scene.vector_cls(num_envs=num_envs, **params)
    ref = scene.vector_cls(num_envs=len(idx) + 1, **params)
    assert env.sim.parallel == (num_envs * env.sim.num_bodies >= 1024)
    obs, _ = env.reset(seed=seeds)
    ref_obs, _ = ref.reset(seed=[seeds[i] for i in idx] + [1])
    np.testing.assert_array_equal(obs[idx], ref_obs[:-1])
    ref_act = np.zeros((len(idx) + 1, n_actions(scene)))
    for a in acts:
        ref_act[:-1] = a[idx]
        obs, r, term, trunc, _ = env.step(a)
        ref_obs, ref_r, ref_term, ref_trunc, _ = ref.step(ref_act)
        np.testing.assert_array_equal(obs[idx], ref_obs[:-1])
        np.testing.assert_array_equal(r[idx], ref_r[:-1])
        np.testing.assert_array_equal(term[idx], ref_term[:-1])
        np.testing.assert_array_equal(trunc[idx], ref_trunc[:-1])
    # an int seed: SeedSequence(seed).spawn(E)[i] does not depend on E
    k = min(num_envs, 2)
    obs, _ = env.reset(seed=5)
    ref_obs, _ = scene.vector_cls(num_envs=2, **params).reset(seed=5)
    np.testing.assert_array_equal(obs[:k], ref_obs[:k])


def test_episode_starts_do_not_depend_on_how_far_ahead_they_are_drawn(scene, monkeypatch):
    """Each episode start takes its uniforms from its sub-env's pool, drawn ahead from the
    sub-env's generator (scenes/base.py): a pool of one episode's draws, refilled at every
    start, gives the same trajectories, resets included, bit for bit."""
    from fluidsim_envs.scenes import base

    def run():
        env = scene.vector_cls(num_envs=3, max_episode_steps=6)
        out = [env.reset(seed=[4, 5, 6])[0]]
        for a in actions_for(scene, 3, 20, 3):
            obs, r, *_ = env.step(a)
            out += [obs, r[:, None]]
        return env, np.concatenate(out, axis=None)

    pooled_env, pooled = run()
    monkeypatch.setattr(base, "POOL_DRAWS", 1)
    single_env, single = run()
    assert single_env._pool_episodes == 1 and pooled_env._pool_episodes > 1
    np.testing.assert_array_equal(pooled, single)


# ---- the episode boundary -----------------------------------------------------------------


def test_time_limit_truncates_without_terminating(scene):
    env = gym.make(scene.id, max_episode_steps=5)
    env.reset(seed=0)
    for k in range(5):
        _, _, term, trunc, _ = env.step(np.zeros(n_actions(scene)))
        assert not term
        assert trunc == (k == 4)
    venv = scene.vector_cls(num_envs=2, max_episode_steps=5)
    venv.reset(seed=0)
    for k in range(5):
        _, _, term, trunc, info = venv.step(np.zeros((2, n_actions(scene))))
        assert not term.any()
        assert trunc.tolist() == [k == 4] * 2
    assert info["episode_steps"].tolist() == [5, 5] and info["_final_obs"].all()
    assert venv.episode_steps.tolist() == [0, 0]  # the next episode has started


def test_gym_make_s_time_limit_is_the_env_s(scene):
    """``gym.make(id, max_episode_steps=N)``: the env's own limit (on which it truncates and
    scores an episode's last step) is N too, longer than its default as well; the spec says
    the default without it, and ``make_vec`` hands N to the vector env."""
    default = scene.params_cls().max_episode_steps
    for n in (5, default + 100):
        env = gym.make(scene.id, max_episode_steps=n)
        assert env.unwrapped.params.max_episode_steps == env.spec.max_episode_steps == n
        assert gym.make(env.spec).unwrapped.params.max_episode_steps == n
    env = gym.make(scene.id)
    assert env.spec.max_episode_steps == env.unwrapped.params.max_episode_steps == default
    venv = gym.make_vec(scene.id, 2, max_episode_steps=7)
    assert venv.unwrapped.params.max_episode_steps == 7
    venv.close()


def test_is_success_at_the_episode_s_end(scene):
    """Gymnasium's and SB3's ``is_success`` (what ``Monitor`` and ``EvalCallback`` read) is in
    the info of each episode's last step, equal to the scene's ``success``; not before."""
    env = gym.make(scene.id, max_episode_steps=3)
    env.reset(seed=0)
    infos = [env.step(np.zeros(n_actions(scene)))[4] for _ in range(3)]
    assert "is_success" not in infos[0] and "is_success" not in infos[1]
    assert infos[2]["is_success"] == infos[2]["success"]
    venv = scene.vector_cls(num_envs=2, max_episode_steps=3)
    venv.reset(seed=0)
    for _ in range(3):
        *_, info = venv.step(np.zeros((2, n_actions(scene))))
    assert info["_is_success"].all()
    np.testing.assert_array_equal(info["final_info"]["is_success"], info["final_info"]["success"])


def test_the_sync_vector_mode_against_the_native_one(scene):
    """What docs/environments.md says of ``gym.make_vec(..., vectorization_mode="sync")``:
    Gymnasium seeds its sub-env i with ``seed + i`` (a single env's seed), so it flies, step
    for step across episode ends, the native vector env reset with the list ``[seed + i]``
    once it autoresets in the same step (``autoreset_mode=SAME_STEP``, the native env's
    mode). The native env reset with the integer ``seed`` agrees with it in sub-env 0 only."""
    from gymnasium.vector import AutoresetMode

    n, steps = 3, 7
    sync = gym.make_vec(scene.id, n, vectorization_mode="sync", max_episode_steps=3,
                        vector_kwargs={"autoreset_mode": AutoresetMode.SAME_STEP})  # fmt: skip
    native = gym.make_vec(scene.id, n, max_episode_steps=3)
    one_seed = gym.make_vec(scene.id, n, max_episode_steps=3)
    obs, _ = sync.reset(seed=5)
    np.testing.assert_array_equal(obs, native.reset(seed=[5 + i for i in range(n)])[0])
    other = one_seed.reset(seed=5)[0]
    np.testing.assert_array_equal(obs[0], other[0])
    assert not np.array_equal(obs[1:], other[1:])
    for a in actions_for(scene, 1, steps, n):  # two episode ends
        a_sync, a_native = sync.step(a), native.step(a)
        for x, y in zip(a_sync[:4], a_native[:4], strict=True):
            np.testing.assert_array_equal(x, y)
    for v in (sync, native, one_seed):
        v.close()


def test_a_reset_draws_the_new_episode_not_the_last_action(scene):
    """After steps and ``reset(seed=0)`` the frame (its HUD included) is a fresh env's at
    ``reset(seed=0)``: no action of the episode before shows."""
    used = scene.vector_cls(num_envs=1, render_mode="rgb_array")
    used.reset(seed=0)
    for _ in range(2):
        used.step(np.ones((1, n_actions(scene))))
    used.reset(seed=0)
    assert not used.last_action.any()
    fresh = scene.vector_cls(num_envs=1, render_mode="rgb_array")
    fresh.reset(seed=0)
    np.testing.assert_array_equal(used.render(), fresh.render())


def test_observations_keep_to_the_space_s_bounds(scene):
    """The space bounds a column where physics does (unit "1": sines, cosines, a direction's
    components, normalized positions, fractions; none that an instrument reads, whose noise
    has no bound) and every observation keeps to them, saturating actions included."""
    venv = scene.vector_cls(num_envs=16)
    space = venv.single_observation_space
    bounded = np.isfinite(space.high)
    units = [u for _, u, _ in venv.observation_layout[: venv.obs_dim]]
    assert bounded.any() and all(units[j] == "1" for j in np.flatnonzero(bounded))
    obs, _ = venv.reset(seed=0)
    rng = np.random.default_rng(0)
    for _ in range(200):
        assert ((obs >= space.low) & (obs <= space.high)).all()
        obs, *_ = venv.step(np.sign(rng.normal(size=(16, n_actions(scene)))))


def test_step_after_the_end_needs_a_reset(scene):
    env = scene.env_cls(max_episode_steps=2)
    with pytest.raises(RuntimeError, match="call reset first"):
        env.step(np.zeros(n_actions(scene)))  # never started
    env.reset(seed=0)
    env.step(np.zeros(n_actions(scene)))
    *_, trunc, _ = env.step(np.zeros(n_actions(scene)))
    assert trunc
    with pytest.raises(RuntimeError, match="call reset first"):
        env.step(np.zeros(n_actions(scene)))


def test_reset_of_some_sub_envs_keeps_the_others(scene):
    venv = scene.vector_cls(num_envs=3)
    obs0, _ = venv.reset(seed=1)
    for a in actions_for(scene, 2, 5, 3):
        obs, *_ = venv.step(a)
    again, _ = venv.reset(seed=1, options={"env_ids": [1]})
    np.testing.assert_array_equal(again[[0, 2]], obs[[0, 2]])
    np.testing.assert_array_equal(again[1], obs0[1])
    assert venv.episode_steps.tolist() == [5, 0, 5] and venv.episodes.tolist() == [1, 2, 1]


# ---- pickling -----------------------------------------------------------------------------


def test_pickle_round_trip_continues_identically(scene):
    env = scene.env_cls()
    env.reset(seed=2)
    for a in actions_for(scene, 2, 10)[:, 0]:
        env.step(a)
    clone = pickle.loads(pickle.dumps(env))
    for a in actions_for(scene, 3, 20)[:, 0]:
        out, out_clone = env.step(a), clone.step(a)
        np.testing.assert_array_equal(out[0], out_clone[0])
        assert out[1:4] == out_clone[1:4]


def test_vector_env_pickle_round_trip_continues_identically_across_resets(scene):
    venv = scene.vector_cls(num_envs=3, max_episode_steps=25)
    venv.reset(seed=5)
    for a in actions_for(scene, 4, 10, 3):
        venv.step(a)
    clone = pickle.loads(pickle.dumps(venv))
    for a in actions_for(scene, 5, 30, 3):  # past an autoreset: the generators travel too
        out, out_clone = venv.step(a), clone.step(a)
        for x, y in zip(out[:4], out_clone[:4], strict=True):
            np.testing.assert_array_equal(x, y)
    assert venv.episode_steps.max() < 25
    np.testing.assert_array_equal(venv.episode_steps, clone.episode_steps)


# ---- divergence ---------------------------------------------------------------------------


def test_diverged_state_ends_the_episode_with_a_flag_and_finite_observation(scene):
    venv = scene.vector_cls(num_envs=2)
    venv.reset(seed=4)
    acts = actions_for(scene, 6, 6, 2)
    for a in acts[:5]:
        venv.step(a)
    before = venv.step(acts[5])[0][1].copy()
    assert not venv.sim.diverged.any()
    scene.diverge(venv, 1)  # sub-env 1's state blows up
    obs, r, term, trunc, info = venv.step(acts[5])
    assert info["physics_diverged"].tolist() == [False, True]
    assert term.tolist() == [False, True] and not trunc.any()
    assert np.isfinite(obs).all() and np.isfinite(r).all()
    np.testing.assert_array_equal(info["final_obs"][1], before)  # the last finite one
    assert info["reward_terms"]["crash"][1] == -venv.params.w_crash
    assert r[1] <= -venv.params.w_crash  # the other terms are penalties or nothing
    assert info["final_info"]["physics_diverged"][1] and not info["final_info"]["success"][1]
    obs, *_ = venv.step(np.zeros((2, n_actions(scene))))  # it was reset: it runs on
    assert np.isfinite(obs).all() and not venv.sim.diverged.any()


def test_single_env_divergence_keeps_the_last_finite_observation(scene):
    env = scene.env_cls()
    env.reset(seed=9)
    for a in actions_for(scene, 8, 3)[:, 0]:
        obs, *_ = env.step(a)
    scene.diverge(env.vector, 0)
    obs2, r, term, trunc, info = env.step(np.zeros(n_actions(scene)))
    assert term and not trunc and info["physics_diverged"]
    np.testing.assert_array_equal(obs2, obs)
    assert info["reward_terms"]["crash"] == -env.params.w_crash
    assert np.isfinite(r)
    with pytest.raises(RuntimeError, match="call reset first"):
        env.step(np.zeros(n_actions(scene)))


# ---- bad inputs ---------------------------------------------------------------------------


def test_bad_parameters_name_the_bad_value(scene):
    with pytest.raises(TypeError, match=r"unknown parameter\(s\) \['wnd'\]; valid: .*'dt'"):
        gym.make(scene.id, wnd=1.0)
    with pytest.raises(TypeError, match=r"unknown parameter\(s\) \['dtt'\]"):
        gym.make_vec(scene.id, num_envs=2, vectorization_mode="vector_entry_point", dtt=0.01)
    cases = [
        ({"dt": 0.0}, r"dt must be a finite number in \[1e-05, .*\], got 0.0"),
        ({"dt": -0.01}, "dt must be"),
        ({"substeps": 2.5}, "substeps must be an integer"),
        ({"substeps": 4.0}, r"substeps must be an integer in \[1, 1000\], got 4.0"),
        ({"integrator": "bogus"}, r"integrator must be one of .*got 'bogus'"),
        ({"dtype": "float16"}, "dtype must be one of"),
        ({"max_episode_steps": 0}, "max_episode_steps must be"),
        ({"w_crash": float("nan")}, "w_crash must be"),
    ]
    for kwargs, msg in cases:
        with pytest.raises(ValueError, match=msg):
            scene.env_cls(**kwargs)
    for bad in (0, -1, 2.5, True):
        with pytest.raises(ValueError, match="num_envs must be a positive integer"):
            scene.vector_cls(num_envs=bad)
    with pytest.raises(ValueError, match="render_mode must be None or one of"):
        scene.vector_cls(num_envs=1, render_mode="human")


def test_bad_actions_name_the_bad_value(scene):
    n = n_actions(scene)
    env = scene.env_cls()
    env.reset(seed=0)
    a = np.zeros(n)
    a[1] = np.nan
    with pytest.raises(ValueError, match=r"actions contain nan at \(0, 1\)"):
        env.step(a)
    a = np.zeros(n)
    a[0] = np.inf
    with pytest.raises(ValueError, match=r"actions contain inf at \(0, 0\)"):
        env.step(a)
    names = ", ".join(scene.vector_cls.action_names)
    with pytest.raises(ValueError, match=rf"shape \({n},\) \({names}\)"):
        env.step(np.zeros(n + 1))
    venv = scene.vector_cls(num_envs=2)
    venv.reset(seed=0)
    with pytest.raises(ValueError, match=rf"shape \(2, {n}\)"):
        venv.step(np.zeros(n))
    with pytest.raises(ValueError, match=r"expected 2 seeds, one per sub-env, got 3"):
        venv.reset(seed=[1, 2, 3])


def test_actions_saturate_at_the_limits(scene):
    """Box(-1, 1) commands beyond the limits act as the limit (the actuators saturate)."""
    n = n_actions(scene)
    a, b = scene.env_cls(), scene.env_cls()
    a.reset(seed=8)
    b.reset(seed=8)
    big = np.resize([5.0, -3.0, 1.5], n)
    for _ in range(3):
        oa = a.step(big)
        ob = b.step(np.clip(big, -1.0, 1.0))
        np.testing.assert_array_equal(oa[0], ob[0])
        assert oa[1:4] == ob[1:4]
    np.testing.assert_array_equal(a.vector.last_action[0], np.clip(big, -1.0, 1.0))


# ---- the observation layout and the docstring ---------------------------------------------


def test_observation_layout_is_declared_once(scene):
    """One names tuple: the space's width, distinct names, the layout's units and text."""
    names = scene.obs_names
    assert len(names) == len(set(names)) == scene.vector_cls.obs_dim
    assert scene.env_cls().observation_space.shape == (len(names),)
    assert all(unit and text for _, unit, text in scene.observation)


def test_docstring_sections_and_observation_table(scene):
    """Gymnasium's env docstring convention; the observation table covers every column, in
    the layout's order; every reward term is documented."""
    doc = scene.env_cls.__doc__
    for section in (
        "Description",
        "Action Space",
        "Observation Space",
        "Rewards",
        "Starting State",
        "Episode End",
        "Arguments",
        "Version History",
    ):
        assert f"## {section}\n" in doc, section
    names = scene.obs_names
    assert f"({len(names)},)" in doc
    rows = re.findall(r"^\s*\| (\d+)(?:-(\d+))? \| ([^|]+?) \|", doc, flags=re.M)
    covered = []
    for lo, hi, cells in rows:
        lo = int(lo)
        covered += range(lo, int(hi or lo) + 1)
        assert cells.split(",")[0].strip() == names[lo], (lo, cells)
    assert covered == list(range(len(names)))
    for term in scene.vector_cls.reward_terms:
        assert f"``{term}``" in doc.split("## Rewards")[1].split("## Starting State")[0], term


# ---- frames -------------------------------------------------------------------------------


def test_render_rgb_array_frames(scene):
    env = gym.make(scene.id, render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
    for a in actions_for(scene, 1, 5)[:, 0]:
        env.step(a)
    later = env.render()
    assert later.shape == frame.shape and not np.array_equal(later, frame)  # the view follows
    venv = scene.vector_cls(num_envs=2, render_mode="rgb_array")
    venv.reset(seed=0)
    frames = venv.render()
    assert isinstance(frames, tuple) and len(frames) == 2 and frames[0].shape == frame.shape
    assert scene.vector_cls(num_envs=1).render() is None  # no render_mode: a warning, no frame


def test_record_video_writes_an_episode(scene, tmp_path):
    """gymnasium's RecordVideo turns the rgb_array frames into a video file."""
    pytest.importorskip("moviepy")
    from gymnasium.wrappers import RecordVideo

    env = gym.make(scene.id, render_mode="rgb_array", max_episode_steps=20)
    env = RecordVideo(env, str(tmp_path), episode_trigger=lambda e: True, disable_logger=True)
    env.reset(seed=0)
    while not any(env.step(np.zeros(n_actions(scene)))[2:4]):
        pass
    env.close()
    videos = list(tmp_path.glob("*.mp4"))
    assert len(videos) == 1 and videos[0].stat().st_size > 1000
