"""PaperAirplane-v0's env contract: checkers, vector == single, determinism across batch sizes,
the episode boundary, pickling, bad inputs and divergence."""

import pickle

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env as gym_check_env

import fluidsim_envs  # noqa: F401  (registers the envs)
from fluidsim_envs.envs import PaperAirplaneEnv, PaperAirplaneVectorEnv

ID = "fluidsim/PaperAirplane-v0"


def actions_for(seed, steps, n=1):
    """A fixed, wiggly action sequence [steps, n, 3] (a pilot that moves every surface)."""
    rng = np.random.default_rng(seed)
    return np.clip(rng.normal(0.0, 0.4, size=(steps, n, 3)), -1, 1)


def test_gymnasium_check_env():
    gym_check_env(gym.make(ID).unwrapped)
    gym_check_env(gym.make(ID, render_mode="rgb_array").unwrapped, skip_render_check=False)


def test_sb3_check_env():
    sb3_env_checker = pytest.importorskip("stable_baselines3.common.env_checker")
    sb3_env_checker.check_env(PaperAirplaneEnv(), warn=True)


LOW = {"launch_height_m": (1.5, 2.5)}  # short episodes: many boundaries per test


def run_single(seed, actions):
    """Roll the single env through ``actions``, resetting (unseeded) after each episode end."""
    env = gym.make(ID, **LOW)
    obs, _ = env.reset(seed=seed)
    rows = [obs]
    rewards, dones = [], []
    for a in actions:
        obs, r, term, trunc, _ = env.step(a)
        rewards.append(r)
        dones.append((term, trunc))
        if term or trunc:
            obs, _ = env.reset()
        rows.append(obs)
    return np.array(rows), np.array(rewards), np.array(dones)


def test_vector_env_matches_single_env_across_episode_ends():
    """Sub-env i of the vector env seeded with a list of seeds behaves exactly as the single
    env seeded with seed i, through several autoresets."""
    seeds = [3, 17, 99]
    acts = actions_for(0, 150, len(seeds))
    venv = gym.make_vec(ID, num_envs=3, vectorization_mode="vector_entry_point", **LOW)
    obs, _ = venv.reset(seed=seeds)
    vobs, vrew, vdone = [obs], [], []
    for a in acts:
        obs, r, term, trunc, _ = venv.step(a)
        vobs.append(obs)
        vrew.append(r)
        vdone.append(np.stack([term, trunc], 1))
    vobs, vrew, vdone = np.array(vobs), np.array(vrew), np.array(vdone)
    for i, s in enumerate(seeds):
        sobs, srew, sdone = run_single(s, acts[:, i])
        assert sdone.any(axis=1).sum() >= 2  # the comparison crosses episode boundaries
        np.testing.assert_array_equal(vobs[:, i], sobs)
        np.testing.assert_array_equal(vrew[:, i], srew)
        np.testing.assert_array_equal(vdone[:, i], sdone)


@pytest.mark.parametrize("num_envs", [1, 7, 1100])  # 1100 runs the threaded kernel
def test_same_seed_same_trajectory_for_any_num_envs(num_envs):
    """Sub-env i's trajectory depends only on the seed, not on the batch size or the kernel
    (serial below 1024 bodies, threaded above)."""
    ref = PaperAirplaneVectorEnv(num_envs=2)
    env = PaperAirplaneVectorEnv(num_envs=num_envs)
    ref_obs, _ = ref.reset(seed=5)
    obs, _ = env.reset(seed=5)
    acts = actions_for(1, 60, 2)
    k = min(num_envs, 2)
    np.testing.assert_array_equal(obs[:k], ref_obs[:k])
    for a in acts:
        big = np.zeros((num_envs, 3))
        big[:k] = a[:k]
        ref_obs, ref_r, *_ = ref.step(a)
        obs, r, *_ = env.step(big)
        np.testing.assert_array_equal(obs[:k], ref_obs[:k])
        np.testing.assert_array_equal(r[:k], ref_r[:k])


def test_terminal_observation_is_the_terminal_state():
    """At an episode end the vector env returns the next episode's first observation and puts
    the terminal one in final_obs; the single env returns the terminal one itself."""
    venv = PaperAirplaneVectorEnv(num_envs=4)
    obs, _ = venv.reset(seed=11)
    single = PaperAirplaneEnv()
    s_obs, _ = single.reset(seed=11)
    for _ in range(400):
        obs, r, term, trunc, info = venv.step(np.zeros((4, 3)))
        s_obs, *_, s_term, s_trunc, s_info = single.step(np.zeros(3))
        if s_term or s_trunc:
            break
    assert s_term and (s_info["landed"] or s_info["crashed"])
    assert term[0] and info["_final_obs"][0]
    np.testing.assert_array_equal(info["final_obs"][0], s_obs)
    assert info["final_info"]["landed"][0] == s_info["landed"]
    # touchdown: the terminal height is within the dart's half-span of the ground, while the
    # new episode starts at a launch height
    assert s_obs[9] < 0.1
    p = venv.params
    assert p.launch_height_m[0] <= obs[0, 9] <= p.launch_height_m[1]
    # the episode's reward terms sum to its return
    assert sum(info["final_info"]["episode_terms"][k][0] for k in venv.reward_terms) == (
        pytest.approx(sum(s_info["episode_terms"].values()))
    )


def test_time_limit_truncates_without_terminating():
    env = gym.make(ID, max_episode_steps=5, launch_height_m=(20.0, 20.0))
    env.reset(seed=0)
    for k in range(5):
        _, _, term, trunc, _ = env.step(np.zeros(3))
        assert not term
        assert trunc == (k == 4)


def test_pickle_round_trip_continues_identically():
    env = PaperAirplaneEnv()
    env.reset(seed=2)
    for a in actions_for(2, 10)[:, 0]:
        env.step(a)
    clone = pickle.loads(pickle.dumps(env))
    for a in actions_for(3, 20)[:, 0]:
        out, out_clone = env.step(a), clone.step(a)
        np.testing.assert_array_equal(out[0], out_clone[0])
        assert out[1:4] == out_clone[1:4]


def test_diverged_state_ends_the_episode_with_a_flag_and_finite_observation():
    venv = PaperAirplaneVectorEnv(num_envs=2)
    obs0, _ = venv.reset(seed=4)
    venv.sim._st[:, 0, 1] = np.inf  # sub-env 1's state blows up (a stand-in for a real blow-up)
    obs, r, term, trunc, info = venv.step(np.zeros((2, 3)))
    assert info["physics_diverged"].tolist() == [False, True]
    assert term[1] and not term[0]
    assert np.isfinite(obs).all() and np.isfinite(r).all()
    assert np.isfinite(info["final_obs"][1]).all()
    assert info["reward_terms"]["crash"][1] == -venv.params.w_crash
    obs, *_ = venv.step(np.zeros((2, 3)))  # it was reset: it flies on
    assert np.isfinite(obs).all()


def test_bad_inputs_name_the_bad_value():
    with pytest.raises(TypeError, match=r"unknown parameter\(s\) \['wnd'\]; valid: .*'dt'"):
        gym.make(ID, wnd=1.0)
    with pytest.raises(ValueError, match="dt must be"):
        PaperAirplaneEnv(dt=-0.01)
    with pytest.raises(ValueError, match="integrator must be one of"):
        PaperAirplaneEnv(integrator="leapfrog")
    with pytest.raises(ValueError, match="substeps must be an integer .*got 4.0"):
        PaperAirplaneEnv(substeps=4.0)
    with pytest.raises(ValueError, match="launch_height_m must have low <= high"):
        PaperAirplaneEnv(launch_height_m=(8.0, 4.0))
    with pytest.raises(ValueError, match="ceiling_m"):
        PaperAirplaneEnv(ceiling_m=5.0)
    env = PaperAirplaneEnv()
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"actions contain nan at \(0, 1\)"):
        env.step(np.array([0.0, np.nan, 0.0]))
    with pytest.raises(ValueError, match=r"shape \(1, 3\)"):
        env.step(np.zeros(4))
    venv = PaperAirplaneVectorEnv(num_envs=2)
    venv.reset(seed=0)
    with pytest.raises(ValueError, match=r"shape \(2, 3\)"):
        venv.step(np.zeros(3))


def test_actions_saturate_at_the_deflection_limits():
    """Box(-1, 1) commands beyond the limits act as the limit (the actuator saturates)."""
    a, b = PaperAirplaneEnv(), PaperAirplaneEnv()
    a.reset(seed=8)
    b.reset(seed=8)
    oa = a.step(np.array([5.0, -3.0, 1.5]))[0]
    ob = b.step(np.array([1.0, -1.0, 1.0]))[0]
    np.testing.assert_array_equal(oa, ob)


def test_render_rgb_array_frames():
    env = gym.make(ID, render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
    env.step(np.zeros(3))
    assert not np.array_equal(env.render(), frame)  # the view follows the flight


def test_record_video_writes_an_episode(tmp_path):
    """gymnasium's RecordVideo turns the rgb_array frames into a video file."""
    pytest.importorskip("moviepy")
    from gymnasium.wrappers import RecordVideo

    env = gym.make(ID, render_mode="rgb_array", launch_height_m=(2.0, 2.0))
    env = RecordVideo(env, str(tmp_path), episode_trigger=lambda e: True, disable_logger=True)
    env.reset(seed=0)
    while not any(env.step(np.zeros(3))[2:4]):
        pass
    env.close()
    videos = list(tmp_path.glob("*.mp4"))
    assert len(videos) == 1 and videos[0].stat().st_size > 1000


def test_dart_lands_on_the_floor_not_through_it():
    """The floor is solid (contact.py): at touchdown every corner of the dart's collision
    boxes is at or above the floor (within the contact's millimetre), whatever the throw."""
    venv = PaperAirplaneVectorEnv(num_envs=64)
    venv.reset(seed=21)
    hull = venv._hull
    seen = 0
    for _ in range(900):
        obs, r, term, trunc, info = venv.step(
            np.clip(venv.np_random.normal(0, 0.5, (64, 3)), -1, 1)
        )
        for e in np.flatnonzero(term & ~info["out_of_arena"] & ~info["physics_diverged"]):
            final = info["final_obs"][e]
            up = -final[6:9]  # the body frame's world z row: R^T (0, 0, 1)
            assert final[9] + (hull @ up).min() > -1e-3
            seen += 1
        if seen > 40:
            break
    assert seen > 40


def test_steep_dive_into_the_floor_is_a_crash():
    """The floor stops the dart within the step it hits, so the sink judged is the one the
    step before: a steep dive still reads as one."""
    env = PaperAirplaneEnv(
        launch_pitch_deg=(-80.0, -80.0), launch_speed_mps=(8.0, 8.0), launch_height_m=(0.5, 0.5)
    )
    env.reset(seed=0)
    for _ in range(300):
        *_, term, trunc, info = env.step(np.zeros(3))
        if term:
            break
    assert term and info["crashed"] and info["touchdown_sink_mps"] > env.params.crash_sink_mps
