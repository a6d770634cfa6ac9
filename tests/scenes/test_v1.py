"""The v1 envs (scenes/realism.py): difficulty levels and knobs, the episode's drawn physics,
the actuator columns, the sensors between the truth and the pilot, and determinism with
every knob on."""

import math

import gymnasium as gym
import numba
import numpy as np
import pytest

import fluidsim_envs  # noqa: F401  (registers the ids)
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes.probes import probe_columns
from fluidsim_envs.scenes.realism import LEVELS

V1 = [i for i in SCENES if i.endswith("-v1")]


def make_vec(env_id, n, **kwargs):
    return gym.make_vec(env_id, num_envs=n, vectorization_mode="vector_entry_point", **kwargs)


def rollout(venv, steps, seed):
    rng = np.random.default_rng(1)
    obs, _ = venv.reset(seed=seed)
    rows = [obs]
    for _ in range(steps):
        a = rng.uniform(-1, 1, venv.action_space.shape)
        obs, reward, *_ = venv.step(a)
        rows.append(obs)
    return np.array(rows)


def test_every_scene_has_a_v1():
    v0 = {i.replace("-v0", "-v1") for i in SCENES if i.endswith("-v0")}
    assert v0 == set(V1)


@pytest.mark.parametrize("env_id", V1)
def test_easy_is_v0_with_the_actuator_columns(env_id):
    """easy: v0's dynamics and exact readings. The first episode draws v0's numbers (its
    start uniforms come first), so the v0 columns are v0's bit for bit."""
    v0 = SCENES[env_id.replace("-v1", "-v0")]
    n0 = len(v0.observation)
    a = rollout(make_vec(env_id, 3, difficulty="easy", **v0.short_episodes), 5, seed=4)
    b = rollout(make_vec(v0.id, 3, **v0.short_episodes), 5, seed=4)
    np.testing.assert_array_equal(a[..., :n0], b)


@pytest.mark.parametrize("env_id", V1)
def test_actuator_columns_are_where_the_actuators_are(env_id):
    venv = make_vec(env_id, 4)
    venv.reset(seed=0)
    venv.step(np.ones((4, 3)))
    env = venv.unwrapped
    cols = env._positions
    assert [n for n, _, _ in SCENES[env_id].observation[cols]] == [
        f"{c}_position" for c in env.sim.control_names
    ]
    np.testing.assert_array_equal(env.observation[:, cols], env.sim.actuators.astype(np.float32))
    assert np.all(env.sim.actuators < 1.0)  # standard: lagging behind the command


def test_knobs_resolve_from_the_level_unless_given():
    env = gym.make("fluidsim/PaperAirplane-v1", difficulty="hard", sensor_scale=0.0)
    k = env.unwrapped.params.knobs
    assert k.sensor_scale == 0.0
    assert (
        k.sensor_latency_steps
        == LEVELS_OF("fluidsim/PaperAirplane-v1")["hard"]["sensor_latency_steps"]
    )
    assert gym.make("fluidsim/PaperAirplane-v1").unwrapped.params.knobs.actuators


def LEVELS_OF(env_id):
    import importlib

    return importlib.import_module(SCENES[env_id].vector_cls.__module__).LEVELS


def test_the_levels_are_the_three():
    assert LEVELS == ("easy", "standard", "hard")
    for env_id in V1:
        assert set(LEVELS_OF(env_id)) == set(LEVELS)


@pytest.mark.parametrize("env_id", V1)
def test_reset_info_holds_what_was_drawn(env_id):
    venv = make_vec(env_id, 64, difficulty="hard")
    _, info = venv.reset(seed=3)
    drawn = info["randomized"]
    env = venv.unwrapped
    k = env.params.knobs
    craft = env.sim.crafts[0]
    m = drawn["mass_kg"] / craft.mass_kg
    assert np.all((m >= k.mass_scale[0]) & (m <= k.mass_scale[1]))
    assert np.ptp(m) > 0.2 * (k.mass_scale[1] - k.mass_scale[0])
    assert np.all(np.abs(drawn["com_shift_z_m"]) <= k.com_shift_m)
    # the simulator flies what info says: the kinetic energy of a known velocity
    v = np.zeros((64, env.sim.num_bodies, 3))
    v[:, 0, 0] = 1.0
    env.sim.reset(lin_vel=v)
    np.testing.assert_allclose(env.sim.kinetic_energy()[:, 0], 0.5 * drawn["mass_kg"], rtol=1e-12)


def test_restarts_draw_again_and_say_so():
    venv = make_vec("fluidsim/PaperAirplane-v1", 8, launch_height_m=(1.5, 2.5),
                    max_episode_steps=10)  # fmt: skip
    _, info0 = venv.reset(seed=0)
    first = info0["randomized"]["mass_kg"].copy()
    for _ in range(10):
        _, _, term, trunc, info = venv.step(np.zeros((8, 3)))
        if "randomized" in info:
            done = info["_randomized"]
            assert np.all(done == (term | trunc))
            assert np.all(info["randomized"]["mass_kg"][done] != first[done])
            return
    pytest.fail("no episode ended")


def test_a_heavier_dart_glides_faster():
    """Steady glide: lift balances weight, so the trim speed goes as sqrt(m) at the same
    angle of attack (mass and inertia scale alike: the trim is unchanged). Measured: 6.676
    and 8.151 m/s for 1.5 times the mass (the top of the dart's range), 0.3% from
    sqrt(1.5); the tolerance leaves room for the phugoid's residual swing over the averaging
    window (about 2%)."""
    kw = dict(difficulty="easy", launch_height_m=(25.0, 25.0), launch_speed_mps=(6.7, 6.7),
              launch_pitch_deg=(0.0, 0.0), launch_roll_deg=(0.0, 0.0),
              wind_speed_mps=(0.0, 0.0))  # fmt: skip
    speeds = []
    for m in (1.0, 1.5):
        venv = make_vec("fluidsim/PaperAirplane-v1", 1, mass_scale=(m, m), **kw)
        venv.reset(seed=0)
        u = []
        for _ in range(220):
            obs, *_ = venv.step(np.zeros((1, 3)))
            u.append(np.linalg.norm(obs[0, :3]))
        speeds.append(np.mean(u[120:]))
    assert speeds[1] / speeds[0] == pytest.approx(math.sqrt(1.5), rel=0.02)


@pytest.mark.parametrize("env_id", V1)
def test_sensors_read_the_truth_with_noise(env_id):
    venv = make_vec(env_id, 32, sensor_latency_steps=0)
    venv.reset(seed=0)
    venv.step(np.zeros((32, 3)))
    env = venv.unwrapped
    diff = env.observation - env._truth
    read = np.array([r != "" for r in env.sensors.reader])
    assert np.all(diff[:, ~read] == 0.0)
    assert np.all(np.abs(diff[:, read]).mean(axis=0) > 0.0)
    assert np.isfinite(env.observation).all()


@pytest.mark.parametrize("env_id", V1)
def test_hard_is_deterministic_for_any_batch_and_thread_count(env_id):
    """Every knob on: sub-envs seeded alike step alike in a batch of 2 and of 1100 (the
    parallel kernels), on 1 thread and on 2."""
    seeds = [11, 12]
    small = rollout(make_vec(env_id, 2, difficulty="hard"), 12, seed=seeds)
    big = make_vec(env_id, 1100, difficulty="hard")
    runs = []
    threads = numba.get_num_threads()
    try:
        for n in sorted({1, min(2, numba.config.NUMBA_NUM_THREADS)}):
            numba.set_num_threads(n)
            obs, _ = big.reset(seed=seeds + list(range(100, 1198)))
            rows = [obs[:2]]
            rng = np.random.default_rng(1)
            for _ in range(12):
                a = np.zeros(big.action_space.shape)
                a[:2] = rng.uniform(-1, 1, (2, 3))
                obs, *_ = big.step(a)
                rows.append(obs[:2])
            runs.append(np.array(rows))
    finally:
        numba.set_num_threads(threads)
    for run in runs:
        np.testing.assert_array_equal(run, small)


def test_the_darts_air_moves_about_its_mean_wind():
    """Light turbulence and no gust: the air of a flying dart wanders about the episode's
    mean wind with about the Dryden intensities at its height (here within a factor of 2:
    a short flight's sample), and easy keeps v0's steady wind."""
    kw = dict(launch_height_m=(20.0, 25.0), max_episode_steps=60)
    venv = make_vec("fluidsim/PaperAirplane-v1", 64, difficulty="easy", turbulence="light",
                    gust_mps=0.0, **kw)  # fmt: skip
    venv.reset(seed=2)
    env = venv.unwrapped
    _, flow, _, _ = env.sim.start_arrays()
    gap = []
    for _ in range(60):
        venv.step(np.zeros((64, 3)))
        gap.append(flow[:3].T - env._mean_wind)
    gap = np.array(gap)
    assert np.all(np.abs(gap.mean(axis=(0, 1))) < 0.5)
    sw = gap[..., 2].std()
    assert 0.3 < sw < 1.6  # sigma_w = 0.1 x 15 kt = 0.77 m/s
    calm = make_vec("fluidsim/PaperAirplane-v1", 4, difficulty="easy", **kw)
    calm.reset(seed=2)
    wind = calm.unwrapped.sim.start_arrays()[1][:3].copy()
    calm.step(np.zeros((4, 3)))
    np.testing.assert_array_equal(calm.unwrapped.sim.start_arrays()[1][:3], wind)


def test_the_current_wanders_as_its_gauss_markov_law():
    """The UUV's current (scenes/currents.py) over 600 steps of 0.2 s and 2000 sub-envs:
    each component's wander has the configured standard deviation and autocorrelation
    exp(-lag / time) (five standard errors: 1 / sqrt(2000) for the correlation)."""
    from fluidsim_envs.scenes import currents as CU
    from fluidsim_envs.scenes import noise as NZ

    E, sigma, tau, h = 2000, 0.2, 30.0, 0.2
    keys = NZ.keys_from_uniforms(np.random.default_rng(5).random(E))
    mean, state, flow = np.zeros((E, 3)), np.zeros((E, 2)), np.zeros((6, E))
    count, ids = np.zeros(E, np.int64), np.arange(E)
    rows = []
    for k in range(151):
        count[:] = k
        CU.current(ids, k == 0, keys, count, mean, state, sigma, tau, h, flow)
        rows.append(flow[3].copy())
    x = np.array(rows)
    for k in (0, 150):
        assert abs(x[k].std() / sigma - 1) < 5 / math.sqrt(2 * E)
    r = np.corrcoef(x[0], x[150])[0, 1]
    assert abs(r - math.exp(-150 * h / tau)) < 5 / math.sqrt(E)


def test_the_uuvs_water_moves_only_where_its_level_says():
    venv = make_vec("fluidsim/SubmarineWake-v1", 8, difficulty="hard")
    venv.reset(seed=1)
    flow = venv.unwrapped.sim.start_arrays()[1]
    assert np.all(np.abs(flow[3:5]).max(axis=0) > 0.0)
    calm = make_vec("fluidsim/SubmarineWake-v1", 8, difficulty="hard", current_mps=0.0,
                    current_variation_mps=0.0)  # fmt: skip
    calm.reset(seed=1)
    assert not calm.unwrapped.sim.start_arrays()[1][3:].any()


# ---- observations read from the fluid samples (scenes/probes.py) -------------------------


def _columns(env_id, obs):
    return dict(zip(SCENES[env_id].obs_names, np.moveaxis(obs, -1, 0), strict=True))


@pytest.mark.parametrize("env_id", V1)
def test_observe_samples_only_adds_the_probes_columns(env_id):
    """At standard (sensors on), the same seed with and without the probes: the same
    trajectory and readings in every other column, bit for bit; the probes' columns end the
    observation, finite and alive."""
    probes = probe_columns(SCENES[env_id].vector_cls.plan.probes)
    on, off = make_vec(env_id, 3), make_vec(env_id, 3, observe_samples=False)
    n = off.unwrapped.obs_dim
    assert on.unwrapped.obs_dim == len(SCENES[env_id].observation) == n + len(probes) > n
    assert off.single_observation_space.shape == (n,)
    a, b = rollout(on, 8, seed=5), rollout(off, 8, seed=5)
    np.testing.assert_array_equal(a[..., :n], b)
    assert [c for c, _, _ in SCENES[env_id].observation[n:]] == [c for c, _, _ in probes]
    assert np.isfinite(a).all() and (a[1:, :, n:].std(axis=0) > 0.0).all()


def test_the_darts_vanes_and_pitots_read_its_airspeed_at_each_plate():
    """Exact instruments (easy): at each wing the inflow is the airspeed columns' (u, v, w)
    plus the rotation's (p, q, r) x r at the plate, reversed; its dynamic pressure is
    rho |inflow|^2 / 2 and its angle of attack asin(inflow . n / |inflow|), n the wing's
    normal (paper_airplane.toml). The observation is float32: 1e-5 relative (2e-6
    measured), 1e-5 rad."""
    env_id = "fluidsim/PaperAirplane-v1"
    venv = make_vec(env_id, 8, difficulty="easy")
    c = _columns(env_id, rollout(venv, 10, seed=6).astype(np.float64))
    craft = venv.unwrapped.sim.crafts[0]
    omega = np.stack([c["p"], c["q"], c["r"]], axis=-1)
    airspeed = np.stack([c["u"], c["v"], c["w"]], axis=-1)
    for plate in craft.plates:
        if plate.name not in ("left_wing", "right_wing"):
            continue
        inflow = -(airspeed + np.cross(omega, np.asarray(plate.offset_m)))
        speed = np.linalg.norm(inflow, axis=-1)
        normal = np.asarray(plate.normal) / np.linalg.norm(plate.normal)
        np.testing.assert_allclose(c[f"{plate.name}_q"], 0.5 * 1.225 * speed**2, rtol=1e-5)
        aoa = np.arcsin(inflow @ normal / speed)
        np.testing.assert_allclose(c[f"{plate.name}_aoa"], aoa, rtol=0.0, atol=1e-5)


def test_the_hulls_taps_at_rest_are_wet_aft_and_dry_forward():
    """Floating at rest (easy): the transom's stations under water and the bow's in the
    air, and each tap's gauge pressure the water's weight above it (rho g depth)."""
    venv = make_vec("fluidsim/BoatOnStep-v1", 2, difficulty="easy")
    obs, _ = venv.reset(seed=0)
    c = _columns("fluidsim/BoatOnStep-v1", obs)
    wet = np.array([c[f"station_{k}_wetted"] for k in range(8)])
    assert np.all(wet[0] == 1.0) and np.all(wet[-1] == 0.0)
    assert np.all(np.diff(wet, axis=0) <= 0.0)  # drier toward the bow
    env = venv.unwrapped
    flows = env.sim.sample_flows(
        [f"bottom_0_{s}_{j}" for s in ("port", "starboard") for j in (0, 1)]
    )
    depth = np.maximum(-flows[..., 5], 0.0).mean(axis=1)
    static_kpa = 1025.0 * 9.81 * depth / 1000.0
    dynamic_kpa = flows[..., 6].mean(axis=1) / 1000.0  # the plates' flow share: ~0 at rest
    np.testing.assert_allclose(c["station_0_pressure"], static_kpa + dynamic_kpa, rtol=1e-6)
    assert np.all(c["station_0_pressure"] > 1.0)  # about 0.2 m under water


def test_the_uuvs_lateral_line_reads_the_wake_less_its_own_motion():
    """Exact instruments (easy): the nose probe's inflow is the wake's water velocity at
    the nose (v0's flow sensor) less the nose's own velocity, (u, v, w) + (p, q, r) x r."""
    env_id = "fluidsim/SubmarineWake-v1"
    obs = rollout(make_vec(env_id, 4, difficulty="easy"), 12, seed=7)
    c = _columns(env_id, obs)
    nose = 1.2  # uuv.toml's nose plate, where v0's flow sensor is
    own = (c["u"], c["v"] + nose * c["r"], c["w"] - nose * c["q"])
    for axis, mine in zip("xyz", own, strict=True):
        expected = c[f"flow_{axis}"] - mine
        np.testing.assert_allclose(c[f"nose_flow_{axis}"], expected, rtol=0.0, atol=2e-5)
    assert np.abs(c["flow_y"]).max() > 1e-3  # the wake is there to be read


@pytest.mark.parametrize("env_id", V1)
def test_a_reset_reads_the_probes_as_a_fresh_env_does(env_id):
    """Without actuators (easy) the surfaces are centred at a reset: the new episode's
    first observation, probes included, does not depend on the last one's controls."""
    fresh = make_vec(env_id, 2, difficulty="easy")
    used = make_vec(env_id, 2, difficulty="easy")
    used.reset(seed=1)
    for _ in range(3):
        used.step(np.ones((2, 3)))
    np.testing.assert_array_equal(used.reset(seed=9)[0], fresh.reset(seed=9)[0])
