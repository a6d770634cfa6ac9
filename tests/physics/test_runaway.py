"""A finite runaway is flagged (Simulator.diverged): the clamps keep forces finite past an
integrator's stability limit, so a blow-up shows as speed, distance or spin beyond what the
fluid samples' speed clamp, or the craft's own runaway speed and rate, allow, not as a NaN
(kernels._flag_runaways)."""

import numpy as np

from fluidsim_envs.physics import Craft, Simulator, World

# a free body: 1 kg, I = 1 kg m^2 about every axis; no samples, no gravity
BOX = Craft(name="box", mass_kg=1.0, inertia_kgm2=(1.0, 1.0, 1.0))
VMAX = 50.0  # m/s
WORLD = World(gravity_mps2=0.0, max_fluid_speed_mps=VMAX)


def _flags(lin_vel, ang_vel, steps=4):
    sim = Simulator(BOX, WORLD, num_envs=len(lin_vel), dt=0.01)
    sim.reset(lin_vel=np.asarray(lin_vel, float), ang_vel=np.asarray(ang_vel, float))
    sim.step(steps=steps)
    return sim.diverged.copy()


def test_speed_beyond_the_clamp_is_flagged_and_just_below_is_not():
    flags = _flags([[0.99 * VMAX, 0, 0], [1.01 * VMAX, 0, 0]], np.zeros((2, 3)))
    np.testing.assert_array_equal(flags, [False, True])


def test_spin_with_more_energy_than_the_mass_holds_at_the_clamp_speed_is_flagged():
    # L . w = I w^2 against m vmax^2: with I = m = 1, the bound is w = vmax
    flags = _flags(np.zeros((2, 3)), [[0, 0, 0.99 * VMAX], [0, 0, 1.01 * VMAX]])
    np.testing.assert_array_equal(flags, [False, True])


def test_a_craft_s_own_runaway_speed_and_rate_are_flagged_below_the_clamp():
    """A craft that declares its runaway speed and turn rate is flagged past them, far under
    the fluid clamp, and not just below them; a jump farther than its own speed allows in
    the call is flagged too."""
    craft = Craft(name="box", mass_kg=1.0, inertia_kgm2=(1.0, 1.0, 1.0),
                  runaway_speed_mps=10.0, runaway_rate_dps=360.0)  # fmt: skip
    sim = Simulator(craft, WORLD, num_envs=4, dt=0.01)
    w = np.radians(360.0)
    sim.reset(
        lin_vel=np.array([[9.9, 0, 0], [10.1, 0, 0], [0, 0, 0], [0, 0, 0]], float),
        ang_vel=np.array([[0, 0, 0], [0, 0, 0], [0, 0, 0.99 * w], [0, 0, 1.01 * w]], float),
    )
    sim.step(steps=4)
    np.testing.assert_array_equal(sim.diverged, [False, True, False, True])
    for name in ("paper_airplane", "uuv", "speedboat"):  # every craft an env flies declares
        assert np.isfinite(Craft.load(name).runaway).all(), name


def test_a_jump_farther_than_the_clamp_allows_in_one_call_is_flagged():
    """A parabolic pass of a point mass (GM = 1) from true anomaly -90 to +90 degrees: it
    starts and ends at r = 2 r_p at speed sqrt(GM / r_p) = 1, passes periapsis at sqrt(2), and
    moves a chord of 4 r_p in T = (8/3) sqrt(2 r_p^3 / GM) (Barker's equation). With the clamp
    speed just above 1 neither end is too fast, yet 4 r_p is farther than vmax T = 3.77 vmax:
    only the distance tells. With vmax = 1.1, vmax T = 4.15 > 4: not flagged."""
    period = 8.0 / 3.0 * np.sqrt(2.0)  # r_p = GM = 1
    steps = 4000
    flags = []
    for vmax in (1.02, 1.1):
        world = World(gravity_mps2=0.0, central_gravity_m3s2=1.0, max_fluid_speed_mps=vmax)
        sim = Simulator(BOX, world, num_envs=1, dt=period / steps, integrator="rk4")
        sim.reset(pos=[0.0, -2.0, 0.0], lin_vel=[np.sqrt(0.5), np.sqrt(0.5), 0.0])
        sim.step(steps=steps)
        np.testing.assert_allclose(sim.pos[0, 0], [0.0, 2.0, 0.0], atol=1e-6)  # the pass
        assert np.linalg.norm(sim.lin_vel[0, 0]) < 1.0 + 1e-6  # ends below either clamp
        flags.append(bool(sim.diverged[0]))
    assert flags == [True, False]


def test_the_envs_dart_past_its_limit_never_runs_away_unflagged():
    """The case the reliability issue reported: PaperAirplane-v0 at dt = 0.1 s with rk2 in a
    strong wind moved the dart far beyond what the clamp allows in one action (62 m) before
    any flag, with rewards of hundreds. Every such step is now flagged, and the reward of the
    rest stays bounded."""
    from benchmarks.fuzz import Case, run_case

    case = Case("fluidsim/PaperAirplane-v0", "extreme", "float64", "rk2", 0.1)
    r = run_case(case, env_steps=20_000, num_envs=64, seed=3)
    assert r["diverged"] > 0  # past the limit: runaways happen
    assert r["unflagged_runaways"] == 0
    assert r["nonfinite"] == 0
    assert r["max_reward"] <= 10.0 * r["reach_m"]  # progress is at most the distance moved
