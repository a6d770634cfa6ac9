"""PaperAirplane-v0's own behaviour: touchdown and the terminal state, the floor, a steep dive,
its parameters' checks (the env contract is tests/scenes/test_contract.py)."""

import gymnasium as gym
import numpy as np
import pytest

import fluidsim_envs  # noqa: F401  (registers the envs)
from fluidsim_envs.scenes.paper_airplane import OBS, PaperAirplaneEnv, PaperAirplaneVectorEnv

ID = "fluidsim/PaperAirplane-v0"


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
    assert s_obs[OBS["height"]] < 0.1
    p = venv.params
    assert p.launch_height_m[0] <= obs[0, OBS["height"]] <= p.launch_height_m[1]
    # the episode's reward terms sum to its return
    assert sum(info["final_info"]["episode_terms"][k][0] for k in venv.reward_terms) == (
        pytest.approx(sum(s_info["episode_terms"].values()))
    )


def test_bad_parameters_name_the_bad_value():
    with pytest.raises(ValueError, match="launch_height_m must have low <= high"):
        PaperAirplaneEnv(launch_height_m=(8.0, 4.0))
    with pytest.raises(ValueError, match="ceiling_m"):
        PaperAirplaneEnv(ceiling_m=5.0)
    with pytest.raises(TypeError, match=r"unknown parameter\(s\) \['wnd'\]; valid: .*'dt'"):
        gym.make(ID, wnd=1.0)


def test_dart_lands_on_the_floor_not_through_it():
    """The floor is solid (contact.py): at touchdown every corner of the dart's collision
    boxes is at most a few millimetres under it, whatever the throw. Measured over 5212
    landings of random throws and actions (6 seeds of 256 envs, 300 steps): the deepest
    corner of the step's final state was 2.9 mm under (the contact pushes the impact out,
    and the later substeps of the action turn the dart about its touching corner); 1% of
    landings went deeper than 1.2 mm. The bound is 4 mm."""
    venv = PaperAirplaneVectorEnv(num_envs=64)
    venv.reset(seed=21)
    rng = np.random.default_rng(21)
    hull = venv._hull
    seen = 0
    for _ in range(900):
        obs, r, term, trunc, info = venv.step(np.clip(rng.normal(0, 0.5, (64, 3)), -1, 1))
        for e in np.flatnonzero(term & ~info["out_of_arena"] & ~info["physics_diverged"]):
            final = info["final_obs"][e]
            up = -final[[OBS["gx"], OBS["gy"], OBS["gz"]]]  # the world z in the body frame
            assert final[OBS["height"]] + (hull @ up).min() > -4e-3
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
