"""SubmarineWake-v0's own physics (the lead's route, the station point, the flow sensor, the
wake's push), its terminal state, success verdict and parameters' checks (the env contract is
tests/scenes/test_contract.py)."""

import math

import gymnasium as gym
import numpy as np
import pytest

import fluidsim_envs  # noqa: F401  (registers the envs)
from fluidsim_envs.physics.kernels import quat_matrices
from fluidsim_envs.scenes.submarine_wake import OBS, SubmarineWakeEnv, SubmarineWakeVectorEnv
from fluidsim_envs.scenes.submarine_wake.kernel import L_HEADING, L_SPEED, L_TURN, L_X, L_Y, L_Z

ID = "fluidsim/SubmarineWake-v0"


def actions_for(seed, steps, n=1):
    rng = np.random.default_rng(seed)
    return np.clip(rng.normal(0.0, 0.5, size=(steps, n, 3)), -1, 1)


def test_terminal_observation_is_the_terminal_state():
    """Losing the lead ends the episode: the vector env returns the next episode's first
    observation and puts the terminal one in final_obs; the single env returns it itself."""
    venv = SubmarineWakeVectorEnv(num_envs=3, lost_distance_m=8.0)
    obs, _ = venv.reset(seed=[11, 12, 13])
    single = SubmarineWakeEnv(lost_distance_m=8.0)
    s_obs, _ = single.reset(seed=11)
    stop = np.array([-1.0, 0.0, 0.0])  # full astern: the lead draws away
    for _ in range(300):
        obs, r, term, trunc, info = venv.step(np.tile(stop, (3, 1)))
        s_obs, *_, s_term, s_trunc, s_info = single.step(stop)
        if s_term or s_trunc:
            break
    assert s_term and s_info["lost_lead"] and not s_info["success"]
    assert term[0] and info["_final_obs"][0]
    np.testing.assert_array_equal(info["final_obs"][0], s_obs)
    station = [OBS["station_x"], OBS["station_y"], OBS["station_z"]]
    assert np.linalg.norm(s_obs[station]) > 8.0  # the station point is out of reach
    assert np.linalg.norm(obs[0, station]) < 8.0  # the new episode starts near it
    assert info["final_info"]["episode_terms"]["crash"][0] == -venv.params.w_crash
    assert sum(info["final_info"]["episode_terms"][k][0] for k in venv.reward_terms) == (
        pytest.approx(sum(s_info["episode_terms"].values()))
    )


def test_time_limit_truncates_and_judges_success():
    env = gym.make(ID, max_episode_steps=5, success_radius_m=100.0)
    env.reset(seed=0)
    for k in range(5):
        _, _, term, trunc, info = env.step(np.zeros(3))
        assert not term
        assert trunc == (k == 4)
        assert info["success"]  # within 100 m all along
        assert info["on_station_fraction"] == 1.0


def test_bad_inputs_name_the_bad_value():
    with pytest.raises(TypeError, match=r"unknown parameter\(s\) \['nosie'\]; valid: .*'noise'"):
        gym.make(ID, nosie=0.1)
    with pytest.raises(ValueError, match="screws must be an integer in"):
        SubmarineWakeEnv(screws=3)
    with pytest.raises(ValueError, match="noise must be"):
        SubmarineWakeEnv(noise=-0.1)
    with pytest.raises(ValueError, match="lead_speed_mps must have low <= high"):
        SubmarineWakeEnv(lead_speed_mps=(2.0, 1.0))
    with pytest.raises(ValueError, match="floor_depth_m"):
        SubmarineWakeEnv(floor_depth_m=30.0)
    with pytest.raises(ValueError, match="wake must be True or False"):
        SubmarineWakeEnv(wake="yes")
    with pytest.raises(ValueError, match=r"wake_model must be one of \['exact', 'table'\]"):
        SubmarineWakeEnv(wake_model="fast")
    env = SubmarineWakeEnv()
    env.reset(seed=0)
    with pytest.raises(ValueError, match=r"actions contain nan at \(0, 2\)"):
        env.step(np.array([0.0, 0.0, np.nan]))


# ---- the scene ----------------------------------------------------------------------------


def rotation(sim, e=0):
    return quat_matrices(np.ascontiguousarray(sim.quat[e]))[0]


def test_lead_follows_its_route():
    """On a straight segment at constant speed the lead covers speed x time along its heading
    at constant depth; a steady turn rate r turns it by r t (kinematics of the route)."""
    venv = SubmarineWakeVectorEnv(
        num_envs=2, lead_turn_deg_s=(1.0, 1.0), lead_speed_mps=(1.5, 1.5), segment_s=(100, 100)
    )
    venv.reset(seed=0)
    venv.route[0, :, 2] = 0.0  # env 0 runs straight, env 1 turns at 1 deg/s
    venv.route[1, :, 2] = math.radians(1.0)
    venv.lead[L_TURN, :] = venv.route[:, 0, 2]  # the turn rate starts at its target
    start = venv.lead.copy()
    steps = 100
    for _ in range(steps):
        venv.step(np.zeros((2, 3)))
    t = steps * venv.params.dt * venv.params.substeps
    dx, dy = venv.lead[L_X, 0] - start[L_X, 0], venv.lead[L_Y, 0] - start[L_Y, 0]
    assert math.hypot(dx, dy) == pytest.approx(1.5 * t, rel=1e-12)
    off_course = math.remainder(math.atan2(dy, dx) - start[L_HEADING, 0], 2 * math.pi)
    assert off_course == pytest.approx(0.0, abs=1e-12)
    assert venv.lead[L_Z, 0] == start[L_Z, 0] and venv.lead[L_SPEED, 0] == 1.5
    turned = venv.lead[L_HEADING, 1] - start[L_HEADING, 1]
    assert turned == pytest.approx(math.radians(1.0) * t, rel=1e-12)
    # a turning lead at speed U and rate r moves on a circle of radius U / r: the chord
    chord = math.hypot(venv.lead[L_X, 1] - start[L_X, 1], venv.lead[L_Y, 1] - start[L_Y, 1])
    radius = 1.5 / math.radians(1.0)
    assert chord == pytest.approx(2 * radius * math.sin(turned / 2), rel=1e-4)


@pytest.mark.parametrize("wake_model", ["exact", "table"])
def test_observation_station_and_flow_sensor_are_consistent(wake_model):
    """The station columns rotate back to station point - position in the world, and the
    flow sensor reads WakeField.velocity at the nose (one implementation of the field)."""
    venv = SubmarineWakeVectorEnv(num_envs=3, wake_model=wake_model)
    obs, _ = venv.reset(seed=21)
    for a in actions_for(4, 30, 3):
        obs, *_ = venv.step(a)
    ix = OBS["station_x"]
    fx = OBS["flow_x"]
    for e in range(3):
        rot = rotation(venv.sim, e)
        lead = venv.lead[:, e]
        c, s = math.cos(lead[L_HEADING]), math.sin(lead[L_HEADING])
        off = venv.station[e]
        station = lead[[L_X, L_Y, L_Z]] + np.array(
            [c * off[0] - s * off[1], s * off[0] + c * off[1], off[2]]
        )
        pos = venv.sim.pos[e, 0]
        np.testing.assert_allclose(rot @ obs[e, ix : ix + 3], station - pos, atol=1e-4)
        nose = pos + rot[:, 0] * 1.2
        quat = (math.cos(lead[L_HEADING] / 2), 0.0, 0.0, math.sin(lead[L_HEADING] / 2))
        flow = venv.wake.velocity(
            nose[None], lead[[L_X, L_Y, L_Z]], quat, (lead[L_SPEED] * c, lead[L_SPEED] * s, 0.0),
            venv.noise_offset[e],
        )[0]  # fmt: skip
        assert np.linalg.norm(flow) > 1e-3
        np.testing.assert_allclose(rot @ obs[e, fx : fx + 3], flow, rtol=1e-5, atol=1e-6)


def test_the_wake_pushes_and_rolls_the_vehicle():
    """Same seeds, zero actions, the vehicle started on a screw vortex's flank (8 m behind the
    screws, 1.5 m off the axis, 1.2 m down where the pair has drifted), level and lined up
    with the lead: without the wake the symmetric vehicle does not roll at all; in the wake
    the vortex rolls it and pushes it off its path."""
    runs = {}
    place = dict(
        station_behind_m=(-28.0, -28.0),
        station_side_m=(1.5, 1.5),
        station_up_m=(-1.2, -1.2),
        start_error_m=0.0,
        start_heading_deg=0.0,
    )
    for wake in (False, True):
        venv = SubmarineWakeVectorEnv(num_envs=4, wake=wake, **place)
        obs, _ = venv.reset(seed=8)
        roll = np.zeros(4)
        for _ in range(30):
            obs, *_ = venv.step(np.zeros((4, 3)))
            roll = np.maximum(roll, np.abs(obs[:, OBS["p"]]))
        runs[wake] = (roll, venv.sim.pos[:, 0].copy())
    assert np.all(runs[False][0] < 1e-9)
    assert np.all(runs[True][0] > 0.01)
    assert np.all(np.linalg.norm(runs[True][1] - runs[False][1], axis=1) > 0.05)


def test_the_table_wake_flies_the_exact_wakes_episodes():
    """wake_model="table" (WakeField(model="table")) against the exact wake: the same seeds
    and actions give the same episodes to within what its field error (1e-5 of the lead's
    speed, RMS) moves the vehicle in 10 s (a few millimeters); without the wake they part
    by meters."""
    runs = {}
    acts = actions_for(5, 100, 4)
    for kw in (dict(), dict(wake_model="table"), dict(wake=False)):
        venv = SubmarineWakeVectorEnv(num_envs=4, **kw)
        venv.reset(seed=[1, 2, 3, 4])
        for a in acts:
            obs, *_ = venv.step(a)
        runs[tuple(kw.values())] = venv.sim.pos[:, 0].copy(), obs
    (exact, obs), (table, t_obs), (none, _) = runs.values()
    assert np.abs(table - exact).max() < 0.01  # m; measured 1e-3
    assert np.abs(none - exact).max() > 1.0  # measured 3.2
    np.testing.assert_allclose(t_obs, obs, atol=5e-3)  # measured 2.2e-4


def test_hitting_the_hull_and_the_floor_end_the_episode():
    venv = SubmarineWakeVectorEnv(num_envs=2)
    venv.reset(seed=1)
    lead = venv.lead
    pos = venv.sim.pos[:, 0].copy()
    pos[0] = lead[[L_X, L_Y, L_Z], 0]  # inside the lead's hull
    pos[1, 2] = -venv.params.floor_depth_m + 0.1  # on the floor
    venv.sim.reset(pos=pos[:, None], quat=venv.sim.quat, lin_vel=venv.sim.lin_vel)
    obs, r, term, trunc, info = venv.step(np.zeros((2, 3)))
    assert term.all()
    assert info["final_info"]["hit_hull"].tolist() == [True, False]
    assert info["final_info"]["hit_floor"].tolist() == [False, True]
