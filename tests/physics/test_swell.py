"""Swell on the water surface: the closed form, floating bodies, the clock, determinism, and
calm water unchanged.

The surface of a linear deep-water wave is ``eta = a cos(k . x - omega t + phase)`` with
``omega = sqrt(g k)``: a crest moves at the phase speed ``omega / k = sqrt(g / k)``
(Lamb, *Hydrodynamics*, 6th ed., sec. 229).
"""

import math

import numba
import numpy as np
import pytest

from fluidsim_envs.physics import (
    Buoyancy,
    Craft,
    Cylinder,
    Plate,
    Simulator,
    SwellWave,
    World,
)
from fluidsim_envs.physics.surface import surface_height, wave_cos

G = 9.81
RHO = 1025.0


def omega_of(wavelength_m):
    return math.sqrt(G * 2.0 * math.pi / wavelength_m)


def raft(length_m=2.0, width_m=1.0, draft_m=0.1):
    """A flat raft: 8 x 2 area-buoyancy samples spread evenly over its length and width
    (a horizontal area, so hydrostatic pressure makes each a spring), floating at ``draft_m``;
    three horizontal plates under it damp heave and pitch."""
    xs = (np.arange(8) + 0.5) * length_m / 8 - length_m / 2
    area = length_m * width_m / 16
    mass = RHO * length_m * width_m * draft_m
    h = 0.2
    inertia = (
        mass / 12 * (width_m**2 + h**2),
        mass / 12 * (length_m**2 + h**2),
        mass / 12 * (length_m**2 + width_m**2),
    )
    buoyancy = tuple(
        Buoyancy(f"b{i}{j}", (float(x), y, 0.0), "area", area_m2=area)
        for i, x in enumerate(xs)
        for j, y in enumerate((-width_m / 4, width_m / 4))
    )
    plates = (
        Plate("mid", (0.0, 0.0, -0.05), (0.0, 0.0, 1.0), 0.5),
        Plate("bow", (0.9 * length_m / 2, 0.0, -0.05), (0.0, 0.0, 1.0), 0.2),
        Plate("stern", (-0.9 * length_m / 2, 0.0, -0.05), (0.0, 0.0, 1.0), 0.2),
    )
    return Craft(name="raft", mass_kg=mass, inertia_kgm2=inertia, buoyancy=buoyancy, plates=plates)


def kitchen_sink():
    """Every kind of sample: plates (one driven by a control), a cylinder, area and volume
    buoyancy, a thruster: a craft that crosses the surface exercises every force loop."""
    return Craft(
        name="sink",
        mass_kg=50.0,
        inertia_kgm2=(4.0, 9.0, 11.0),
        plates=(
            Plate("keel", (0.0, 0.0, -0.2), (0.0, 1.0, 0.0), 0.3, efficiency=0.5),
            Plate("hull", (0.3, 0.0, -0.15), (0.0, 0.2, 1.0), 0.6, efficiency=0.2),
            Plate("fin", (-0.8, 0.0, -0.1), (0.0, 0.0, 1.0), 0.1, 0.8, hinge_axis=(0, 1, 0)),
        ),
        cylinders=(Cylinder("body", (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), 0.4),),
        buoyancy=(
            Buoyancy("front", (0.6, 0.0, -0.1), "area", area_m2=0.2),
            Buoyancy("back", (-0.6, 0.0, -0.1), "area", area_m2=0.2),
            Buoyancy("core", (0.0, 0.0, 0.0), "volume", volume_m3=0.03),
        ),
        controls=({"name": "fin", "max_deflection_deg": 20.0, "surfaces": [{"sample": "fin"}]},),
    )


def random_states(n, seed=5):
    rng = np.random.default_rng(seed)
    return dict(
        pos=np.concatenate([rng.uniform(-20, 20, (n, 1, 2)), rng.uniform(-0.4, 0.2, (n, 1, 1))], 2),
        quat=rng.normal(size=(n, 1, 4)) * (0.2, 0.1, 0.1, 0.1) + (1, 0, 0, 0),
        lin_vel=rng.uniform(-3, 3, (n, 1, 3)),
        ang_vel=rng.uniform(-1, 1, (n, 1, 3)),
    )


def trajectory(sim):
    return np.concatenate([sim.pos, sim.quat, sim.lin_vel, sim.ang_vel], axis=-1)


SWELL = (
    SwellWave(0.4, 12.0, 30.0, 0.3),
    SwellWave(0.15, 5.0, -70.0, 1.1),
)


# ---- the surface: closed form ----------------------------------------------------------------


def test_one_wave_is_the_closed_form():
    a, lam, deg, phase = 0.3, 20.0, 30.0, 0.4
    world = World(water=True, swell=[SwellWave(a, lam, deg, phase)])
    rng = np.random.default_rng(0)
    x, y, t = rng.uniform(-50, 50, 200), rng.uniform(-50, 50, 200), rng.uniform(0, 100, 200)
    k = 2 * np.pi / lam
    d = np.radians(deg)
    exact = a * np.cos(k * (np.cos(d) * x + np.sin(d) * y) - np.sqrt(G * k) * t + phase)
    np.testing.assert_allclose(world.surface_height(x, y, t), exact, rtol=0, atol=1e-12)
    # the scalar the kernels inline gives the same numbers
    table = world.swell_table()
    np.testing.assert_array_equal(
        [surface_height(x[i], y[i], t[i], table) for i in range(5)],
        world.surface_height(x, y, t)[:5],
    )


@pytest.mark.parametrize("scale", [1.0, 1e2, 1e4, 1e8])
def test_wave_cos_is_cos(scale):
    """The kernels' branch-free cosine agrees with libm's to a few units in the last place of
    1, however large the phase (the reduction x - n pi carries pi to ~1e-32)."""
    x = np.random.default_rng(3).uniform(-scale, scale, 20000)
    x[:4] = (0.0, np.pi / 2, -np.pi, 2.5 * np.pi)
    got = np.array([wave_cos(v) for v in x])
    np.testing.assert_allclose(got, np.cos(x), rtol=0, atol=5e-16)
    assert np.all(np.abs(got) <= 1.0 + 1e-15)


def test_two_waves_add_and_arguments_broadcast():
    w1, w2 = SwellWave(0.3, 20.0, 0.0), SwellWave(0.1, 7.0, 120.0, 2.0)
    world = World(water=True, swell=(w1, w2))
    x = np.linspace(-10, 10, 7)[:, None]
    y = np.linspace(-5, 5, 3)[None, :]
    eta = world.surface_height(x, y, 2.5)
    assert eta.shape == (7, 3)
    one = World(water=True, swell=(w1,)).surface_height(x, y, 2.5)
    two = World(water=True, swell=(w2,)).surface_height(x, y, 2.5)
    np.testing.assert_allclose(eta, one + two, rtol=0, atol=1e-14)
    calm = World(water=True).surface_height(x, y, 2.5)
    assert calm.shape == (7, 3) and not calm.any()


@pytest.mark.parametrize("direction_deg", [0.0, 90.0, 225.0])
def test_crest_moves_at_the_deep_water_phase_speed(direction_deg):
    """A crest at the origin at t = 0 is at distance c t along the direction of travel at
    time t, with c = sqrt(g lambda / (2 pi)) (Lamb, sec. 229); e.g. 12.5 m/s for 100 m."""
    lam, a = 100.0, 1.0
    world = World(water=True, swell=[SwellWave(a, lam, direction_deg)])
    c = math.sqrt(G * lam / (2 * math.pi))
    assert c == pytest.approx(12.49, abs=0.01)
    u = np.array([math.cos(math.radians(direction_deg)), math.sin(math.radians(direction_deg))])
    for t in (0.0, 1.7, 5.0):
        s = np.linspace(-2.0, 2.0, 401) + c * t  # distance along the direction of travel
        eta = world.surface_height(s * u[0], s * u[1], t)
        assert eta.max() == pytest.approx(a, abs=1e-12)
        assert s[np.argmax(eta)] == pytest.approx(c * t, abs=0.01)
    # the period: one wavelength passes a fixed point in 2 pi / omega
    period = world.swell[0].period_s(G)
    assert period == pytest.approx(lam / c)
    np.testing.assert_allclose(
        world.surface_height(3.0, 4.0, [1.0, 1.0 + period]),
        2 * [world.surface_height(3.0, 4.0, 1.0)],
        atol=1e-12,
    )


def test_simulator_surface_height_uses_each_clock():
    world = World(water=True, swell=SWELL)
    sim = Simulator(raft(), world, num_envs=3)
    sim.set_clock([0.0, 2.0, 7.5])
    x = np.array([[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]])
    eta = sim.surface_height(x, -1.0)
    np.testing.assert_array_equal(
        eta, world.surface_height(x, -1.0, np.array([0.0, 2.0, 7.5])[:, None])
    )


# ---- forces: buoyancy under the local surface ----------------------------------------------


def test_buoyancy_in_swell_is_the_hydrostatic_sum():
    """At rest the only forces are buoyancy: each area sample pushes up with rho g A times its
    depth under the surface right above it, eta(x_s, y_s, t) - z_s (0 when above it)."""
    craft = raft()
    world = World(water=True, swell=SWELL)
    sim = Simulator(craft, world, num_envs=4)
    q = np.array([0.98, 0.05, -0.12, 0.3])
    q /= np.linalg.norm(q)
    sim.reset(pos=(3.0, -2.0, -0.15), quat=q)
    clocks = np.array([0.0, 1.3, 4.0, 11.1])
    sim.set_clock(clocks)
    force, torque = sim.wrench()
    w, x, y, z = q
    rot = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )
    r = np.array([b.offset_m for b in craft.buoyancy]) @ rot.T  # world offsets [S, 3]
    p = r + (3.0, -2.0, -0.15)
    areas = np.array([b.area_m2 for b in craft.buoyancy])
    for e, t in enumerate(clocks):
        depth = np.maximum(0.0, world.surface_height(p[:, 0], p[:, 1], t) - p[:, 2])
        assert 0 < np.count_nonzero(depth)
        f = np.zeros((len(areas), 3))
        f[:, 2] = RHO * G * areas * depth
        np.testing.assert_allclose(force[e, 0], f.sum(0), rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(torque[e, 0], np.cross(r, f).sum(0), rtol=1e-12, atol=1e-9)


def test_floating_body_follows_long_swell():
    """Quasi-static limit: a raft of 2 m in swell of 100 m (period 8 s, its heave natural
    period 0.63 s) rides the surface: the heave amplitude is a / (1 - (omega / omega_n)^2),
    0.6% above the wave amplitude, and the raft stays at its draft under the surface under
    it. Four environments start a quarter period apart (their clocks) at their equilibria."""
    a, lam, draft = 0.5, 100.0, 0.1
    world = World(water=True, swell=[SwellWave(a, lam, 0.0)])
    period = world.swell[0].period_s(G)
    dt = 0.01
    sim = Simulator(raft(draft_m=draft), world, num_envs=4, dt=dt)
    clocks = period * np.arange(4) / 4
    sim.set_clock(clocks)
    omega = omega_of(lam)
    eta0 = a * np.cos(-omega * clocks)
    deta0 = a * omega * np.sin(-omega * clocks)
    sim.reset(pos=np.stack([0 * clocks, 0 * clocks, eta0 - draft], 1)[:, None],
              lin_vel=np.stack([0 * clocks, 0 * clocks, deta0], 1)[:, None])  # fmt: skip
    steps_per_period = int(round(period / dt))
    z, gap = [], []
    for _ in range(2 * steps_per_period):
        sim.step()
        p = sim.pos[:, 0]
        z.append(p[:, 2].copy())
        gap.append(sim.surface_height(p[:, 0], p[:, 1]) - p[:, 2])
    z, gap = np.array(z), np.array(gap)
    heave = (z.max(0) - z.min(0)) / 2
    expected = a / (1 - (omega / math.sqrt(G / draft)) ** 2)
    np.testing.assert_allclose(heave, expected, rtol=0.02)
    # the raft keeps its draft under the moving surface within 2% of the wave amplitude
    assert np.abs(gap - draft).max() < 0.02 * a
    assert not sim.diverged.any()


def test_body_spanning_a_short_wave_barely_heaves():
    """A raft as long as the wave (2 m) spans a crest and a trough: the waves' lift on its
    buoyancy samples cancels (the pressure integral of cos(k x) over one wavelength is 0), so
    it pitches but barely heaves, whereas the same wave 50 times as long lifts it by a."""
    a, draft = 0.05, 0.1
    heave = {}
    for lam in (2.0, 100.0):
        world = World(water=True, swell=[SwellWave(a, lam, 0.0)])
        craft = raft(draft_m=draft)
        sim = Simulator(craft, world, num_envs=1, dt=0.005)
        under = np.array([b.offset_m for b in craft.buoyancy])  # the mean surface under it
        level = world.surface_height(under[:, 0], under[:, 1], 0.0).mean()
        sim.reset(pos=(0.0, 0.0, level - draft))  # at rest at its equilibrium at t = 0
        period = world.swell[0].period_s(G)
        sim.step(steps=int(3 * period / 0.005))  # transients decay
        z = []
        for _ in range(int(2 * period / 0.005)):
            sim.step()
            z.append(sim.pos[0, 0, 2])
        heave[lam] = (max(z) - min(z)) / 2
    assert heave[100.0] == pytest.approx(a, rel=0.03)
    assert heave[2.0] < 0.1 * a, heave


@pytest.mark.parametrize("integrator,order", [("velocity_verlet", 2), ("rk2", 2), ("rk4", 4)])
def test_stage_times_keep_the_order_of_accuracy(integrator, order):
    """One area sample on a point mass in swell: m z'' = rho g A (eta(t) - z) - m g, a forced
    undamped oscillator with the exact solution z = -d + a / (1 - r^2) cos(omega t) (r =
    omega / omega_n) from that start at rest. Each force evaluation sees the surface at its
    stage time, so halving dt divides the error by 2^order (a surface held at the step's
    start would make every method first order)."""
    a, lam, d, area = 0.3, 10.0, 0.5, 0.01
    mass = RHO * area * d
    craft = Craft(
        name="bob",
        mass_kg=mass,
        inertia_kgm2=(1.0, 1.0, 1.0),
        buoyancy=(Buoyancy("b", (0.0, 0.0, 0.0), "area", area_m2=area),),
    )
    world = World(water=True, swell=[SwellWave(a, lam, 0.0)])
    omega, omega_n = omega_of(lam), math.sqrt(G / d)
    amp = a / (1 - (omega / omega_n) ** 2)
    t_end = 4.0
    errors = []
    for dt in (0.02, 0.01, 0.005):
        sim = Simulator(craft, world, num_envs=1, dt=dt, integrator=integrator)
        sim.reset(pos=(0.0, 0.0, amp - d))
        sim.step(steps=int(round(t_end / dt)))
        assert sim.clock[0] == pytest.approx(t_end, abs=1e-9)
        errors.append(abs(sim.pos[0, 0, 2] - (-d + amp * math.cos(omega * t_end))))
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all(ratios > 0.9 * 2**order), (errors, ratios)


# ---- the clock -------------------------------------------------------------------------------


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_clock_advances_by_dt_per_step(dtype):
    dt = 1 / 120
    sim = Simulator(raft(), World(water=True, swell=SWELL), num_envs=3, dt=dt, dtype=dtype)
    assert sim.clock.dtype == np.float64 and not sim.clock.any()
    sim.set_clock([0.0, 1.0, -2.5])
    sim.step(steps=7)
    t = np.array([0.0, 1.0, -2.5])
    step = float(np.asarray(dt, dtype=dtype))  # the dt the kernel steps with
    for _ in range(7):
        t += step
    np.testing.assert_array_equal(sim.clock, t)
    with pytest.raises(ValueError, match="read-only"):
        sim.clock[0] = 1.0
    sim.reset()  # reset keeps the clock
    np.testing.assert_array_equal(sim.clock, t)


def test_the_calm_clock_runs_too():
    sim = Simulator(raft(), World(water=True), num_envs=2, dt=0.25)
    sim.step(steps=4)
    np.testing.assert_array_equal(sim.clock, [1.0, 1.0])


@pytest.mark.parametrize("integrator", ["symplectic_euler", "rk4"])
def test_steps_split_over_calls_equal_one_call(integrator):
    world = World(water=True, swell=SWELL)
    sims = [Simulator(kitchen_sink(), world, num_envs=5, dt=1 / 200, integrator=integrator)
            for _ in range(2)]  # fmt: skip
    controls = np.linspace(-1, 1, 5)[:, None]
    for sim in sims:
        sim.reset(**random_states(5))
        sim.set_clock(np.linspace(0.0, 9.0, 5))
    sims[0].step(controls, steps=13)
    sims[0].step(controls, steps=29)
    sims[1].step(controls, steps=42)
    np.testing.assert_array_equal(trajectory(sims[0]), trajectory(sims[1]))
    np.testing.assert_array_equal(sims[0].clock, sims[1].clock)


def test_set_clock_per_environment():
    world = World(water=True, swell=SWELL)
    state = random_states(3)
    sim = Simulator(kitchen_sink(), world, num_envs=3, dt=1 / 200)
    sim.reset(**state)
    sim.set_clock(4.0)
    sim.set_clock([1.5, 7.25], env_ids=[0, 2])
    np.testing.assert_array_equal(sim.clock, [1.5, 4.0, 7.25])
    sim.step(steps=100)
    for e, t0 in enumerate((1.5, 4.0, 7.25)):
        alone = Simulator(kitchen_sink(), world, num_envs=1, dt=1 / 200)
        alone.reset(**{k: v[e : e + 1] for k, v in state.items()})
        alone.set_clock(t0)
        alone.step(steps=100)
        np.testing.assert_array_equal(trajectory(alone)[0], trajectory(sim)[e])
    # and the clock matters: the same body at another time ends elsewhere
    other = Simulator(kitchen_sink(), world, num_envs=1, dt=1 / 200)
    other.reset(**{k: v[:1] for k, v in state.items()})
    other.step(steps=100)
    assert not np.array_equal(trajectory(other)[0], trajectory(sim)[0])


# ---- determinism and calm water --------------------------------------------------------------


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("integrator", ["symplectic_euler", "rk4"])
def test_swell_is_bit_identical_for_any_batch_size(dtype, integrator):
    world = World(water=True, swell=SWELL)
    n, steps = 200, 60
    state = random_states(n)
    clocks = np.random.default_rng(1).uniform(0, 20, n)
    controls = np.random.default_rng(2).uniform(-1, 1, (n, 1))

    def run(ids, parallel, threads=1):
        numba.set_num_threads(threads)
        sim = Simulator(kitchen_sink(), world, num_envs=len(ids), dt=1 / 150,
                        integrator=integrator, dtype=dtype, parallel=parallel)  # fmt: skip
        sim.reset(**{k: v[ids] for k, v in state.items()})
        sim.set_clock(clocks[ids])
        for _ in range(steps // 20):
            sim.step(controls[ids], steps=20)
        return trajectory(sim)

    try:
        serial = run(np.arange(n), False)
        parallel = run(np.arange(n), True, threads=2)
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    assert np.all(np.isfinite(serial))
    np.testing.assert_array_equal(serial, parallel)
    seven = run(np.arange(64 - 3, 64 + 4), False)  # across a block boundary
    np.testing.assert_array_equal(seven, serial[61:68])
    for i in (0, 63, 64, 199):
        np.testing.assert_array_equal(run(np.array([i]), False)[0], serial[i])


@pytest.mark.parametrize("integrator", ["symplectic_euler", "velocity_verlet", "rk2", "rk4"])
def test_calm_water_is_unchanged(integrator):
    """Calm water (the default, or an explicitly empty swell) and swell of amplitude 0 (which
    runs the swell code with a surface at z = 0) give bit-identical trajectories."""
    worlds = [
        World(water=True),
        World(water=True, swell=()),
        World(water=True, swell=[]),
        World(water=True, swell=[SwellWave(0.0, 10.0, 40.0, 0.5)]),
    ]
    assert worlds[0] == worlds[1] == worlds[2]
    out = []
    for world in worlds:
        sim = Simulator(kitchen_sink(), world, num_envs=9, dt=1 / 200, integrator=integrator)
        sim.reset(**random_states(9))
        sim.set_clock(np.linspace(0, 30, 9))
        sim.step(np.linspace(-1, 1, 9)[:, None], steps=150)
        out.append(trajectory(sim))
    assert np.all(np.isfinite(out[0]))
    for other in out[1:]:
        np.testing.assert_array_equal(other, out[0])


# ---- bad inputs ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "swell,match",
    [
        ([(-0.1, 10.0)], r"amplitude_m must be a finite number >= 0, got -0\.1"),
        ([(0.1, 0.0)], r"wavelength_m must be a finite number > 0, got 0\.0"),
        ([(0.1, -3.0)], r"wavelength_m must be a finite number > 0, got -3\.0"),
        ([(float("nan"), 10.0)], r"amplitude_m must be a finite number, got nan"),
        ([(0.1, 10.0, float("inf"))], r"direction_deg must be a finite number, got inf"),
        ([(1.0, 10.0)], r"steepness .* = 0\.6283 \(amplitude_m=1\.0, wavelength_m=10\.0\)"),
        ([(0.1, 10.0)] * 5, r"swell has 5 waves; at most 4"),
        ([{"amplitude_m": 0.1, "wavelength": 10.0}], r"unknown key\(s\) \['wavelength'\]"),
        ([{"amplitude_m": 0.1}], r"missing key\(s\) \['wavelength_m'\]"),
        (["big"], r"swell\[0\] must be a SwellWave.*'big'"),
        ([(0.1,)], r"swell\[0\] must be a SwellWave"),
        (0.5, r"swell must be a sequence of waves, got 0\.5"),
        ([("0.1", 10.0)], r"amplitude_m must be a finite number, got '0\.1'"),
    ],
)
def test_bad_swell_is_rejected_by_name(swell, match):
    with pytest.raises(ValueError, match=match):
        World(water=True, swell=swell)


def test_swell_accepts_waves_tuples_and_dicts():
    world = World(
        water=True,
        swell=[SwellWave(0.2, 30.0), (0.1, 12.0, 45.0), {"amplitude_m": 0.3, "wavelength_m": 60.0,
                                                          "phase_rad": 1.0}],
    )  # fmt: skip
    assert world.swell == (
        SwellWave(0.2, 30.0, 0.0, 0.0),
        SwellWave(0.1, 12.0, 45.0, 0.0),
        SwellWave(0.3, 60.0, 0.0, 1.0),
    )
    assert World(water=True, swell=SwellWave(0.2, 30.0)).swell == (SwellWave(0.2, 30.0),)
    assert hash(world) == hash(World(water=True, swell=list(world.swell)))
    # the steepness limit is inclusive: a k = 0.3 exactly is allowed
    SwellWave(0.3 * 10.0 / (2 * math.pi), 10.0)


def test_swell_needs_water():
    with pytest.raises(ValueError, match=r"swell needs water=True \(got water=False"):
        World(swell=[(0.1, 10.0)])


def test_bad_clock_is_rejected():
    sim = Simulator(raft(), World(water=True, swell=SWELL), num_envs=3)
    with pytest.raises(ValueError, match=r"set_clock: t has non-finite values: nan"):
        sim.set_clock(float("nan"))
    with pytest.raises(ValueError, match=r"non-finite values: \[0.0, inf\]"):
        sim.set_clock([0.0, math.inf], env_ids=[0, 1])
    with pytest.raises(ValueError, match=r"does not broadcast to \[3\]"):
        sim.set_clock([1.0, 2.0])
    with pytest.raises(ValueError, match="env_ids"):
        sim.set_clock(1.0, env_ids=[3])
    assert not sim.clock.any()
