"""BoatOnStep-v1's ride (issue 23): the hull's motion judged by a seakeeping criterion, the
root mean square vertical acceleration at the stem against NORDFORSK's limit (NORDFORSK
1987, "Assessment of ship performance in a seaway": 0.275 g at the forward perpendicular
for craft under 100 m), in place of v0's porpoising term, which counted the sea's pitching
as the helm's (``python -m benchmarks.reward_terms --env fluidsim/BoatOnStep-v1``).

What is checked: the stem's velocity is the rigid body's at that point (the samples'
kinematics), the estimate is the root mean square of a known acceleration, a porpoising
hull in calm water fails the criterion and a steady one passes, and in a seaway the ride
roughens with speed (the trend of every planing-craft seakeeping series, e.g. Savitsky and
Brown 1976). v0 keeps its reward terms (here) and its trajectories (``benchmarks/golden.py``,
run by hand against the previous commit)."""

import math

import gymnasium as gym
import numpy as np
import pytest

import fluidsim_envs  # noqa: F401  (registers the ids)
from fluidsim_envs.physics.state import OV
from fluidsim_envs.scenes.boat_on_step import kernel as TK
from fluidsim_envs.scenes.boat_on_step.env import BoatOnStepVectorEnv
from fluidsim_envs.scenes.boat_on_step.v1 import O_RIDE, BoatOnStepV1Params, BoatOnStepV1VectorEnv

V1 = "fluidsim/BoatOnStep-v1"


def make_vec(n, **kwargs):
    return gym.make_vec(V1, num_envs=n, vectorization_mode="vector_entry_point", **kwargs)


def steady(level, throttle, tabs, seconds=35.0, settle_s=20.0, n=4):
    """Straight runs at fixed throttle and tabs (rudder amidships) on a course too wide to
    leave: the mean speed, ride estimate (g), ride term and porpoising flag after
    ``settle_s``."""
    venv = make_vec(n, difficulty=level, course_half_width_m=1e4, first_leg_m=(2e3, 2e3))
    obs, _ = venv.reset(seed=1)
    action = np.tile([throttle, 0.0, tabs], (n, 1))
    rows = []
    g = venv.unwrapped.world.gravity_mps2
    for t in range(int(seconds / 0.05)):
        obs, _, term, trunc, info = venv.step(action)
        assert not (term | trunc).any()
        if t * 0.05 >= settle_s:
            v = venv.unwrapped.sim.lin_vel[:, 0]
            speed = np.hypot(v[:, 0], v[:, 1]).mean()
            ride = info["reward_terms"]["ride"].mean()
            rows.append((speed, obs[:, O_RIDE].mean() / g, ride, info["porpoising"].mean()))
    venv.close()
    return dict(zip(("speed", "ride_g", "term", "porpoising"), np.mean(rows, axis=0), strict=True))


@pytest.mark.parametrize("shift_m", [0.0, 0.2])
def test_the_stem_moves_as_the_rigid_body_says(shift_m):
    """The stem's vertical velocity (the ride's input) is the rigid body's at that point,
    v + omega x r: in calm, still water and air the stem sample's inflow is exactly minus
    its velocity (Simulator.sample_flows, its own kinematics), to rounding; also where the
    episode's centre of mass is shifted (``com_shift_m``), which moves the stem's arm."""
    venv = make_vec(4, difficulty="easy", com_shift_m=shift_m)
    _, info = venv.reset(seed=3)
    shifted = np.abs(info["randomized"]["com_shift_x_m"])
    assert (shifted > 0.05).any() if shift_m else (shifted == 0.0).all()
    rng = np.random.default_rng(0)
    for _ in range(30):  # pitching and heaving
        venv.step(rng.uniform(-1, 1, (4, 3)))
    env = venv.unwrapped
    st, _, body = env.sim.kernel_arrays()
    mine = np.array([TK.bow_vertical_velocity(st, body, e, env._cfg) for e in range(4)])
    inflow_body = env.sim.sample_flows(["stem"])[:, 0, :3]
    q = env.sim.quat[:, 0]
    rot = np.array([_matrix(x) for x in q])
    inflow_world = np.einsum("eij,ej->ei", rot, inflow_body)
    np.testing.assert_allclose(mine, -inflow_world[:, 2], rtol=0.0, atol=1e-12)
    assert np.abs(mine).max() > 0.05  # moving


def _matrix(q):
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])  # fmt: skip


def test_the_estimate_is_the_rms_of_the_stems_acceleration():
    """Drive the estimator with a stem heaving as a sinusoid of amplitude A m/s at f Hz (the
    velocity set in the state, the hull otherwise at rest): the step-averaged acceleration
    has amplitude A omega sinc(omega dt / 2), so after ten windows the mean square,
    averaged over one period of its ripple at 2 f (which an exponential average leaves at
    2.1% here), is half its square. Measured: 2e-5 relative to it, the transient (exp(-10) on
    the mean square)."""
    venv = make_vec(1, difficulty="easy", ride_window_s=2.0)
    venv.reset(seed=0)
    env = venv.unwrapped
    st, _, body = env.sim.kernel_arrays()
    amp, f, dt = 0.3, 2.0, 0.05
    w = 2 * math.pi * f
    steps, ripple = 400, round(1 / (2 * f * dt))  # 20 s, then one period of a^2
    mean_square = []
    for k in range(steps + ripple):
        st[OV + 2, 0, 0] = amp * math.sin(w * k * dt)
        TK.score(0, 1, st, body, np.zeros(1, bool), np.zeros((1, 3)), env.course,
                 env.buoys, np.zeros(1, bool), env.task, *env.sim.surface_arrays(),
                 env._cfg, env._terms, env._flags)  # fmt: skip
        mean_square.append(env.task[TK.K_RIDE_VAR, 0])
    peak = amp * w * math.sin(w * dt / 2) / (w * dt / 2)
    assert math.sqrt(np.mean(mean_square[-ripple:])) == pytest.approx(peak / math.sqrt(2), rel=1e-4)
    spread = np.ptp(mean_square[-ripple:]) / np.mean(mean_square[-ripple:])
    assert 0.02 < spread < 0.05  # the ripple is there, and as small as the window makes it


def test_a_porpoising_hull_fails_the_criterion_in_calm_water():
    """Calm water (easy), tabs flush: at full throttle (25 m/s) the hull porpoises (v0's
    flag) and its stem's rms acceleration passes the limit (0.39 g measured), so the ride
    term charges it; at 0.8 throttle (23 m/s) it runs steady, 0.07 g, and free."""
    porpoising = steady("easy", 1.0, -1.0)
    calm = steady("easy", 0.8, -1.0)
    assert porpoising["porpoising"] == 1.0 and calm["porpoising"] == 0.0
    assert porpoising["ride_g"] > 0.3 and porpoising["term"] < 0.0
    assert calm["ride_g"] < 0.15 and calm["term"] == 0.0


def test_in_a_seaway_the_ride_roughens_with_speed():
    """Standard's 0.2 m sea, tabs flush: the faster the boat, the harder the stem slams
    (measured 0.43, 1.13 and 1.83 g rms at 8.5, 16.0 and 26.7 m/s; the ride term grows
    with it), which is the helm's choice the term charges: speed against the ride."""
    runs = [steady("standard", throttle, -1.0) for throttle in (0.25, 0.5, 1.0)]
    speeds = [r["speed"] for r in runs]
    rides = [r["ride_g"] for r in runs]
    assert np.all(np.diff(speeds) > 3.0)
    assert np.all(np.diff(rides) > 0.2)
    assert np.all(np.diff([r["term"] for r in runs]) < 0.0)


def test_v0_keeps_its_terms_and_v1_adds_the_ride():
    assert BoatOnStepVectorEnv.reward_terms == TK.REWARD_TERMS_V0
    assert BoatOnStepV1VectorEnv.reward_terms == TK.REWARD_TERMS_V0 + ("ride",)
    params = BoatOnStepV1Params()
    assert params.w_porpoise == 0.0 and params.ride_limit_g == 0.275


@pytest.mark.parametrize(
    "key,value", [("ride_limit_g", 0.0), ("ride_window_s", -1.0), ("w_ride", -0.5)]
)
def test_bad_ride_parameters_are_named(key, value):
    with pytest.raises(ValueError, match=key):
        gym.make(V1, **{key: value})
