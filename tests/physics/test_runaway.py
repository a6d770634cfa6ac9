"""A finite runaway is flagged (Simulator.diverged): the clamps keep forces finite past an
integrator's stability limit, so a blow-up shows as speed, distance or spin beyond what the
fluid samples' speed clamp allows, not as a NaN (kernels._flag_runaways)."""

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


def test_the_envs_dart_past_its_limit_never_runs_away_unflagged():
    """The case the reliability issue measured: PaperAirplane-v0 at dt = 0.1 s with rk2 in
    the strongest wind moved the dart up to 2,100 m in one action before any flag (the clamp
    allows 62 m). Every such step is now flagged, and the reward of the rest stays bounded."""
    from benchmarks.fuzz import Case, run_case

    case = Case("fluidsim/PaperAirplane-v0", "extreme", "float64", "rk2", 0.1)
    r = run_case(case, env_steps=20_000, num_envs=64, seed=3)
    assert r["diverged"] > 0  # past the limit: runaways happen
    assert r["unflagged_runaways"] == 0
    assert r["nonfinite"] == 0
    assert r["max_reward"] <= 10.0 * r["reach_m"]  # progress is at most the distance moved
