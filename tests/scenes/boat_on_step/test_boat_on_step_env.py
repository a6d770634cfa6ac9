"""BoatOnStep-v0's task logic (gates, buoys, capsize, leaving the course, finishing, the
observation and the engine's power curve), its terminal state and its parameters' checks (the
env contract is tests/scenes/test_contract.py)."""

import math

import gymnasium as gym
import numpy as np
import pytest

import fluidsim_envs  # noqa: F401  (registers the envs)
from fluidsim_envs.scenes.boat_on_step import (
    GATES,
    OBS,
    BoatOnStepEnv,
    BoatOnStepVectorEnv,
)
from fluidsim_envs.scenes.boat_on_step import kernel as TK

ID = "fluidsim/BoatOnStep-v0"


def actions_for(seed, steps, n=1):
    """A fixed action sequence [steps, n, 3]: mostly ahead, rudder and tabs wiggling."""
    rng = np.random.default_rng(seed)
    a = rng.normal(0.0, 0.5, size=(steps, n, 3))
    a[..., 0] += 0.6
    return np.clip(a, -1, 1)


# ---- helpers: independent geometry --------------------------------------------------------


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array(
        [
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
            w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
            w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        ]
    )


def attitude_quat(yaw, trim=0.0, heel=0.0):
    """Yaw about world z, then trim (bow up +: a negative rotation about body y), then heel
    (starboard side down +: a positive rotation about body x)."""
    qz = np.array([math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])
    qy = np.array([math.cos(-trim / 2), 0.0, math.sin(-trim / 2), 0.0])
    qx = np.array([math.cos(heel / 2), math.sin(heel / 2), 0.0, 0.0])
    return qmul(qmul(qz, qy), qx)


def rotation(q):
    """Body -> world rotation matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def gate_point(venv, e, gate, along, across):
    """World (x, y) at ``along`` (+ past the line) and ``across`` (+ left) of gate ``gate``."""
    gx, gy, h = venv.course[e, gate]
    return (
        gx + along * math.cos(h) - across * math.sin(h),
        gy + along * math.sin(h) + across * math.cos(h),
    )


def place(venv, e, gate, along, across, speed=0.0, heel_deg=0.0, astern=False):
    """Put sub-env e's boat at (along, across) of ``gate``, at its floating height and trim,
    moving along the gate's direction of travel at ``speed``, heading that way (``astern``:
    the other way, making way stern first), and re-run the task's start (then aim it at
    ``gate``)."""
    h = venv.course[e, gate, TK.G_HEADING]
    x, y = gate_point(venv, e, gate, along, across)
    venv.sim.reset(
        pos=(x, y, venv.rest_height_m),
        quat=attitude_quat(h + math.pi * astern, venv.rest_trim_rad, math.radians(heel_deg)),
        lin_vel=(speed * math.cos(h), speed * math.sin(h), 0.0),
        env_ids=[e],
    )
    st, _, body = venv.sim.kernel_arrays()
    TK.start(st, body, venv.course, venv.task, venv._cfg, np.array([e]))
    if gate != 1:
        venv.task[TK.K_GATE, e] = gate
        venv.task[TK.K_SIDE, e] = along
        venv.task[TK.K_DIST, e] = math.hypot(along, across)


def expected_gate_xy(venv, e, gate):
    """The gate's center in the boat's heading frame, from sim state and course."""
    R = rotation(venv.sim.quat[e, 0])
    heading = math.atan2(R[1, 0], R[0, 0])
    dx = venv.course[e, gate, 0] - venv.sim.pos[e, 0, 0]
    dy = venv.course[e, gate, 1] - venv.sim.pos[e, 0, 1]
    c, s = math.cos(heading), math.sin(heading)
    return np.array([c * dx + s * dy, -s * dx + c * dy])


# ---- the episode boundary and bad inputs, as this scene has them ---------------------------


def test_terminal_observation_is_the_terminal_state():
    """Leaving the course ends the episode: the vector env returns the next episode's first
    observation and puts the terminal one in final_obs (and its flags in final_info); the
    single env returns the terminal observation itself."""
    params = {"course_half_width_m": 5.0, "start_heading_deg": 60.0}
    venv = BoatOnStepVectorEnv(num_envs=3, **params)
    obs, _ = venv.reset(seed=[11, 12, 13])
    single = BoatOnStepEnv(**params)
    s_obs, _ = single.reset(seed=11)
    ahead = np.array([1.0, 0.0, 0.0])
    for _ in range(400):
        obs, r, term, trunc, info = venv.step(np.tile(ahead, (3, 1)))
        s_obs, *_, s_term, s_trunc, s_info = single.step(ahead)
        if s_term or s_trunc:
            break
    assert s_term and s_info["left_course"] and not s_info["success"]
    assert term[0] and info["_final_obs"][0]
    np.testing.assert_array_equal(info["final_obs"][0], s_obs)
    fin = info["final_info"]
    assert fin["left_course"][0] and not fin["success"][0] and not fin["capsized"][0]
    assert not fin["physics_diverged"][0]
    assert fin["reward_terms"]["crash"][0] == -venv.params.w_crash
    assert s_obs[OBS["u"]] > 3.0  # the terminal state is under way ...
    # ... and the returned one is the next episode's start: at rest, at its floating height,
    # the first gate a first leg away, exactly what the single env's next reset gives
    first, _ = single.reset()
    np.testing.assert_array_equal(obs[0], first)
    assert np.all(obs[0, OBS["u"] : OBS["r"] + 1] == 0.0) and obs[0, OBS["heave"]] == 0.0
    assert obs[0, OBS["speed_error"]] == obs[0, OBS["target_speed"]]
    lo, hi = venv.params.first_leg_m
    assert lo - 1e-3 <= np.hypot(*obs[0, OBS["gate_x"] : OBS["gate_y"] + 1]) <= hi + 1e-3
    # the episode's reward terms sum to its return
    assert sum(fin["episode_terms"][k][0] for k in venv.reward_terms) == pytest.approx(
        sum(s_info["episode_terms"].values())
    )


def test_bad_inputs_name_the_bad_value():
    with pytest.raises(TypeError, match=r"unknown parameter\(s\) \['w_gates'\]; valid: .*'w_gate'"):
        gym.make(ID, w_gates=1.0)
    with pytest.raises(TypeError, match=r"unknown parameter\(s\) \['dtt'\]"):
        gym.make_vec(ID, num_envs=2, vectorization_mode="vector_entry_point", dtt=0.01)
    cases = [
        ({"dt": 0.0}, r"dt must be a finite number in \[1e-05, 0.05\], got 0.0"),
        ({"target_speed_mps": (20.0, 10.0)}, r"target_speed_mps must have low <= high"),
        ({"target_speed_mps": (10.0,)}, "target_speed_mps must be a \\(low, high\\) pair"),
        ({"turn_deg": (-200.0, 0.0)}, "turn_deg must be a finite number"),
        ({"buoy_radius_m": 2.0, "gate_half_width_m": 2.0}, "buoy_radius_m .* gate_half_width_m"),
        ({"engine_power_w": -5.0}, "engine_power_w must be"),
        ({"w_gate": float("nan")}, "w_gate must be"),
        ({"capsize_heel_deg": 5.0}, "capsize_heel_deg must be"),
    ]
    for kwargs, msg in cases:
        with pytest.raises(ValueError, match=msg):
            BoatOnStepEnv(**kwargs)
    with pytest.raises(ValueError, match=r"shape \(3,\).*throttle, rudder, trim_tabs"):
        env = BoatOnStepEnv()
        env.reset(seed=0)
        env.step(np.zeros(2))


# ---- the task -----------------------------------------------------------------------------


def test_gate_passed_between_the_buoys_targets_the_next_gate():
    """Sub-env 0 runs through gate 1 between its buoys (2 m left of center); sub-env 1 runs
    parallel to it but stops short of the line."""
    venv = BoatOnStepVectorEnv(num_envs=2)
    venv.reset(seed=3)
    place(venv, 0, 1, along=-0.2, across=2.0, speed=8.0)
    place(venv, 1, 1, along=-12.0, across=2.0, speed=8.0)
    obs, r, term, trunc, info = venv.step(np.zeros((2, 3)))
    assert info["gate_passed"].tolist() == [True, False]
    assert not info["gate_missed"].any() and not info["hit_buoy"].any() and not term.any()
    assert info["reward_terms"]["gate"].tolist() == [venv.params.w_gate, 0.0]
    assert info["gates_passed"].tolist() == [1, 0]
    assert venv.task[TK.K_GATE].tolist() == [2.0, 1.0]
    ix = OBS["gate_x"]
    # sub-env 0 now aims at gate 2 (a leg ahead), sub-env 1 still at gate 1 (just ahead)
    np.testing.assert_allclose(obs[0, ix : ix + 2], expected_gate_xy(venv, 0, 2), atol=1e-3)
    np.testing.assert_allclose(obs[1, ix : ix + 2], expected_gate_xy(venv, 1, 1), atol=1e-3)
    assert np.hypot(*obs[0, ix : ix + 2]) > venv.params.leg_m[0] - 1.0
    assert np.hypot(*obs[1, ix : ix + 2]) < 12.0
    # the gate counts once
    obs, r, term, trunc, info = venv.step(np.zeros((2, 3)))
    assert not info["gate_passed"][0] and info["reward_terms"]["gate"][0] == 0.0


def test_gate_line_crossed_outside_the_buoys_is_missed():
    venv = BoatOnStepVectorEnv(num_envs=2)
    venv.reset(seed=3)
    half = venv.params.gate_half_width_m
    place(venv, 0, 1, along=-0.2, across=half + 4.0, speed=8.0)  # left of the left buoy
    place(venv, 1, 1, along=-0.2, across=-(half + 4.0), speed=8.0)  # right of the right one
    obs, r, term, trunc, info = venv.step(np.zeros((2, 3)))
    assert info["gate_missed"].tolist() == [True, True]
    assert not info["gate_passed"].any() and not info["hit_buoy"].any()
    assert info["reward_terms"]["gate"].tolist() == [-venv.params.w_gate] * 2
    assert info["gates_missed"].tolist() == [1, 1] and venv.task[TK.K_GATE].tolist() == [2, 2]
    ix = OBS["gate_x"]
    for e in range(2):
        np.testing.assert_allclose(obs[e, ix : ix + 2], expected_gate_xy(venv, e, 2), atol=1e-3)


def test_gate_run_stern_first_is_missed():
    """A gate counts bow first: sub-env 0 backs through gate 1's middle (its bow pointing back
    along the course), sub-env 1 runs through it ahead; the one backing it misses it."""
    venv = BoatOnStepVectorEnv(num_envs=2)
    venv.reset(seed=3)
    place(venv, 0, 1, along=-0.2, across=0.0, speed=6.0, astern=True)
    place(venv, 1, 1, along=-0.2, across=0.0, speed=6.0)
    obs, r, term, trunc, info = venv.step(np.array([[-1.0, 0.0, 0.0], [0.0, 0.0, 0.0]]))
    assert info["gate_missed"].tolist() == [True, False]
    assert info["gate_passed"].tolist() == [False, True]
    assert info["reward_terms"]["gate"].tolist() == [-venv.params.w_gate, venv.params.w_gate]
    assert venv.task[TK.K_GATE].tolist() == [2, 2]


def test_hull_on_a_buoy_is_flagged_and_penalized():
    """Sub-env 0 lies on gate 2's left buoy, sub-env 1 on its right one, sub-env 2 in the
    middle of the gate (no buoy within reach)."""
    venv = BoatOnStepVectorEnv(num_envs=3)
    venv.reset(seed=6)
    half = venv.params.gate_half_width_m
    for e, across in enumerate((half, -half, 0.0)):
        place(venv, e, 2, along=-0.5, across=across)
    buoys = venv.buoys[:, 2:4]  # gate 2's pair
    assert np.allclose(buoys[0, 0], gate_point(venv, 0, 2, 0.0, half))
    assert np.allclose(buoys[1, 1], gate_point(venv, 1, 2, 0.0, -half))
    obs, r, term, trunc, info = venv.step(np.zeros((3, 3)))
    assert info["hit_buoy"].tolist() == [True, True, False]
    w = venv.params.w_buoy
    assert info["reward_terms"]["buoy"].tolist() == [-w, -w, 0.0]
    assert not term.any()  # the buoys are markers: no episode end


def test_capsized_boat_terminates():
    venv = BoatOnStepVectorEnv(num_envs=3)
    venv.reset(seed=1)
    for e, heel in enumerate((80.0, -80.0, 30.0)):
        place(venv, e, 1, along=-50.0, across=0.0, heel_deg=heel)
    o = np.zeros_like(venv._obs)
    venv._observe(o, np.arange(3))
    np.testing.assert_allclose(np.degrees(o[:, OBS["heel"]]), [80.0, -80.0, 30.0], atol=1e-4)
    obs, r, term, trunc, info = venv.step(np.zeros((3, 3)))
    assert term.tolist() == [True, True, False]
    assert info["final_info"]["capsized"].tolist() == [True, True, False]
    crash = info["reward_terms"]["crash"]
    assert crash.tolist() == [-venv.params.w_crash] * 2 + [0.0]


def test_bow_stuffed_at_speed_terminates():
    """The stem under the surface while making way ends the episode; the same attitude at
    rest, or a bow just clear of the water at speed, does not."""
    venv = BoatOnStepVectorEnv(num_envs=3)
    venv.reset(seed=4)
    stem = next(p for p in venv.craft.plates if p.name == "stem").offset_m
    for e, (trim_deg, speed) in enumerate(((-12.0, 15.0), (-12.0, 0.0), (0.0, 15.0))):
        place(venv, e, 1, along=-50.0, across=0.0, speed=speed)
        h = venv.course[e, 1, TK.G_HEADING]
        t = math.radians(trim_deg)
        # trimmed bow down, the hull placed so that the stem sits 20 cm under water; level, at
        # its floating height (the stem well clear)
        z = -0.2 - stem[0] * math.sin(t) - stem[2] * math.cos(t) if trim_deg else None
        x, y, z_rest = venv.sim.pos[e, 0]
        vel = (speed * math.cos(h), speed * math.sin(h), 0.0)
        venv.sim.reset(pos=(x, y, z_rest if z is None else z), quat=attitude_quat(h, t),
                       lin_vel=vel, env_ids=[e])  # fmt: skip
    obs, r, term, trunc, info = venv.step(np.zeros((3, 3)))
    assert info["final_info"]["bow_stuffed"].tolist() == [True, False, False]
    assert term.tolist() == [True, False, False]
    assert np.isfinite(obs).all()


def test_leaving_the_course_terminates():
    venv = BoatOnStepVectorEnv(num_envs=2)
    venv.reset(seed=2)
    # 100 m and 30 m to the side of the first leg's middle (course_half_width_m is 60)
    for e, off in enumerate((100.0, 30.0)):
        leg = math.hypot(*venv.course[e, 1, :2])
        place(venv, e, 1, along=-leg / 2, across=off)
    obs, r, term, trunc, info = venv.step(np.zeros((2, 3)))
    assert term.tolist() == [True, False]
    assert info["final_info"]["left_course"].tolist() == [True, False]
    assert not info["final_info"]["success"].any()
    assert info["reward_terms"]["crash"].tolist() == [-venv.params.w_crash, 0.0]


def test_running_every_gate_is_a_success():
    """A short straight course run at full throttle straight ahead: sub-env 0 on the course
    line passes the six gates in turn and finishes with success; sub-env 1, started 10 m to
    the side of it, crosses every gate's line outside the buoys and finishes without."""
    venv = BoatOnStepVectorEnv(
        num_envs=2,
        first_leg_m=(20.0, 20.0),
        leg_m=(12.0, 12.0),
        turn_deg=(0.0, 0.0),
        start_heading_deg=0.0,
        gate_half_width_m=5.0,
    )
    venv.reset(seed=0)
    place(venv, 1, 1, along=-20.0, across=10.0)
    passed, missed, fin = [], [], None
    for _ in range(400):
        obs, r, term, trunc, info = venv.step(np.tile([1.0, 0.0, 0.0], (2, 1)))
        passed.append(info["gate_passed"].copy())
        missed.append(info["gate_missed"].copy())
        if info["gate_passed"][0]:
            assert info["reward_terms"]["gate"][0] == venv.params.w_gate
        if term.any() or trunc.any():
            fin = info["final_info"]
            break
    assert term.tolist() == [True, True] and not trunc.any()
    passed, missed = np.array(passed), np.array(missed)
    assert passed.sum(axis=0).tolist() == [GATES, 0]
    assert missed.sum(axis=0).tolist() == [0, GATES]
    assert fin["gates_passed"].tolist() == [GATES, 0]
    assert fin["gates_missed"].tolist() == [0, GATES]
    assert fin["success"].tolist() == [True, False]
    for flag in ("capsized", "left_course", "bow_stuffed", "hit_buoy", "physics_diverged"):
        assert not fin[flag].any(), flag
    w = venv.params.w_gate
    assert fin["episode_terms"]["gate"].tolist() == [GATES * w, -GATES * w]
    assert fin["episode_terms"]["crash"].tolist() == [0.0, 0.0]


SWELL = ((0.3, 30.0, 45.0), (0.15, 12.0, -60.0))


@pytest.mark.parametrize("swell", [(), SWELL], ids=["calm", "swell"])
def test_observation_matches_the_simulator_state(swell):
    """speed_error, trim, heel, heave, body velocities and rates and the gate columns, from
    the simulator's pos/quat/lin_vel/ang_vel and the course, computed here; heave from the
    surface under the boat at the sub-env's clock."""
    venv = BoatOnStepVectorEnv(num_envs=3, swell=swell)
    obs, _ = venv.reset(seed=21)
    acts = actions_for(8, 60, 3)
    acts[:, :, 0] = 1.0
    checked = 0
    for k, a in enumerate(acts):
        obs, r, term, trunc, info = venv.step(a)
        if k % 15 != 14:
            continue
        for e in range(3):
            if term[e] or trunc[e]:
                continue
            R = rotation(venv.sim.quat[e, 0])
            pos, vel, omega = venv.sim.pos[e, 0], venv.sim.lin_vel[e, 0], venv.sim.ang_vel[e, 0]
            target = venv.task[TK.K_TARGET, e]
            gate = int(info["gates_passed"][e] + info["gates_missed"][e]) + 1
            expect = {
                "speed_error": target - math.hypot(vel[0], vel[1]),
                "trim": math.asin(R[2, 0]),  # the bow's elevation
                "heel": math.atan2(R[2, 1], R[2, 2]),  # the left side's rise
                "heave": pos[2]
                - venv.world.surface_height(pos[0], pos[1], venv.sim.clock[e])
                - venv.rest_height_m,
                "target_speed": target,
            }
            for name, value in expect.items():
                assert obs[e, OBS[name]] == pytest.approx(value, rel=1e-6, abs=1e-6), name
            u, p = OBS["u"], OBS["p"]
            np.testing.assert_allclose(obs[e, u : u + 3], R.T @ vel, rtol=1e-6, atol=1e-5)
            np.testing.assert_allclose(obs[e, p : p + 3], R.T @ omega, rtol=1e-6, atol=1e-5)
            gx, gy = expected_gate_xy(venv, e, gate)
            ix = OBS["gate_x"]
            np.testing.assert_allclose(obs[e, ix : ix + 2], (gx, gy), rtol=1e-6, atol=1e-4)
            bearing = math.atan2(gy, gx)
            b = OBS["gate_bearing_sin"]
            np.testing.assert_allclose(
                obs[e, b : b + 2], (math.sin(bearing), math.cos(bearing)), atol=1e-6
            )
            heading = math.atan2(R[1, 0], R[0, 0])
            d = venv.course[e, gate, TK.G_HEADING] - heading
            h = OBS["gate_heading_sin"]
            np.testing.assert_allclose(obs[e, h : h + 2], (math.sin(d), math.cos(d)), atol=1e-6)
            checked += 1
    assert checked >= 9
    assert obs[:, OBS["u"]].min() > 5.0  # under way: the speed columns are not trivially 0


def test_actions_turn_and_trim_as_documented():
    """From the same planing run (half throttle: about 16 m/s, below the speeds where full
    rudder spins the boat out): rudder + turns the bow to starboard (yaw rate < 0) and
    rudder - to port, symmetrically; trim tabs + push the bow down, - let it rise."""
    venv = BoatOnStepVectorEnv(
        num_envs=5, start_heading_deg=0.0, first_leg_m=(5000.0, 5000.0), course_half_width_m=1e4
    )
    venv.reset(seed=[1] * 5)
    for _ in range(100):
        venv.step(np.tile([0.5, 0.0, 0.0], (5, 1)))
    a = np.array([[1, 0, 0], [1, 1, 0], [1, -1, 0], [1, 0, 1], [1, 0, -1]], dtype=float)
    a[:, 0] = 0.5
    for _ in range(20):
        obs, r, term, trunc, info = venv.step(a)
    assert not (term.any() or trunc.any())
    yaw_rate, trim = obs[:, OBS["r"]], obs[:, OBS["trim"]]
    assert abs(yaw_rate[0]) < 1e-9
    assert yaw_rate[1] < -0.05 and yaw_rate[2] == pytest.approx(-yaw_rate[1], rel=1e-6)
    assert trim[3] < trim[0] - 1e-3 < trim[4] - 2e-3


# ---- the engine ---------------------------------------------------------------------------


def test_thrust_follows_the_power_curve():
    """Full ahead gives min(max_thrust_n, engine_power_w / u); full astern min_thrust_n; idle
    nothing, in the kernel and in the force the simulator applies."""
    venv = BoatOnStepVectorEnv(num_envs=1)
    cfg = venv._cfg
    prop = venv.craft.thrusters[0]
    power = venv.params.engine_power_w
    for u in (1.0, 5.0, 12.0, 17.0, 18.0, 20.0, 25.0, 35.0):
        full = TK.thrust_command(u, 1.0, cfg)
        assert full == pytest.approx(min(prop.max_thrust_n, power / u), rel=1e-12)
        assert full * u <= power * (1 + 1e-12)
        assert TK.thrust_command(u, 0.5, cfg) == pytest.approx(0.5 * full, rel=1e-12)
        assert TK.thrust_command(u, -1.0, cfg) == prop.min_thrust_n
        assert TK.thrust_command(u, 0.0, cfg) == 0.0
    # the power limit binds above power / max_thrust (17.8 m/s)
    assert TK.thrust_command(25.0, 1.0, cfg) < prop.max_thrust_n
    # at rest the only horizontal force is the propeller's (the craft's channel: none at 0,
    # linear to max_thrust_n at +1 and to min_thrust_n at -1)
    venv.reset(seed=0)
    st, _, _ = venv.sim.kernel_arrays()
    ctrl = np.zeros((1, 3))
    trim = venv.rest_trim_rad
    for throttle, thrust in ((1.0, prop.max_thrust_n), (0.0, 0.0), (-1.0, prop.min_thrust_n)):
        TK.controls(st, np.array([[throttle, 0.0, 0.0]]), cfg, ctrl)
        force, _ = venv.sim.wrench(ctrl)
        horizontal = math.hypot(force[0, 0, 0], force[0, 0, 1])
        assert horizontal == pytest.approx(abs(thrust) * math.cos(trim), rel=1e-9, abs=1e-6)


def test_less_power_less_top_speed():
    """Full throttle, straight ahead on a long first leg: the power-limited top speed
    satisfies thrust x speed = engine_power_w, and halving the power lowers it."""
    top = {}
    for power in (80_000.0, 40_000.0):
        venv = BoatOnStepVectorEnv(
            num_envs=1,
            engine_power_w=power,
            first_leg_m=(5000.0, 5000.0),
            start_heading_deg=0.0,
            course_half_width_m=1e4,
        )
        venv.reset(seed=0)
        speeds = []
        for _ in range(500):  # 25 s
            obs, r, term, trunc, info = venv.step(np.array([[1.0, 0.0, 0.0]]))
            assert not (term[0] or trunc[0])
            speeds.append(float(obs[0, OBS["u"]]))
        u = speeds[-1]
        assert abs(speeds[-1] - speeds[-41]) < 0.05 * u  # steady
        thrust = TK.thrust_command(u, 1.0, venv._cfg)
        # on top speed the engine's power, not the propeller's static thrust, is the limit
        assert thrust < venv.craft.thrusters[0].max_thrust_n
        assert thrust * u == pytest.approx(power, rel=1e-9)
        top[power] = u
    assert top[40_000.0] < top[80_000.0] - 1.0


def test_swell_starts_each_episode_at_its_own_moment_with_the_boat_afloat():
    """Each episode draws its moment of the swell (the sub-env's clock) from its own seed; the
    boat starts floating on the surface under it, and then rides the waves."""
    seeds = [5, 6, 7, 5]
    venv = BoatOnStepVectorEnv(num_envs=4, swell=SWELL)
    venv.reset(seed=seeds)
    clock = venv.sim.clock.copy()
    assert len(set(clock[:3])) == 3 and clock[3] == clock[0]
    assert np.all((clock >= 0.0) & (clock <= 86400.0))
    surface = venv.world.surface_height(0.0, 0.0, clock)
    np.testing.assert_allclose(venv.sim.pos[:, 0, 2], venv.rest_height_m + surface, atol=1e-12)
    heights = []
    for _ in range(100):  # 5 s idle
        venv.step(np.zeros((4, 3)))
        heights.append(venv.sim.pos[:, 0, 2].copy())
    assert np.ptp(heights, axis=0).min() > 0.1  # it heaves with the swell
    one = BoatOnStepVectorEnv(num_envs=1, swell=SWELL)
    one.reset(seed=[6])
    for _ in range(100):
        one.step(np.zeros((1, 3)))
    np.testing.assert_array_equal(one.sim.pos[0], venv.sim.pos[1])  # batch-independent


def test_bad_swell_names_the_swell():
    with pytest.raises(ValueError, match="swell.*steepness"):
        BoatOnStepVectorEnv(num_envs=1, swell=[(2.0, 10.0, 0.0)])
    with pytest.raises(ValueError, match="swell"):
        BoatOnStepVectorEnv(num_envs=1, swell=[("big", 10.0)])
