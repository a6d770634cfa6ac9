"""Batch independence: a body evolves bit-identically alone or in a batch of 1000, serial or on
1 or 2 threads, in float64 and float32."""

import numba
import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Simulator, World


def initial_states(n, seed=7):
    rng = np.random.default_rng(seed)
    quat = rng.normal(size=(n, 1, 4))
    return dict(
        pos=rng.uniform(-5, 5, (n, 1, 3)) + (0, 0, 10),
        quat=quat,
        lin_vel=rng.uniform(-8, 8, (n, 1, 3)),
        ang_vel=rng.uniform(-5, 5, (n, 1, 3)),
    )


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("integrator", ["symplectic_euler", "rk4"])
def test_body_alone_equals_body_in_batch(dtype, integrator):
    plane = Craft.load("paper_airplane")
    n, picks, steps = 1000, [0, 1, 63, 64, 517, 999], 120
    state = initial_states(n)
    controls = np.random.default_rng(3).uniform(-1, 1, (steps, n, 3))

    def run(ids, parallel, threads):
        numba.set_num_threads(threads)
        sim = Simulator(
            plane,
            World(wind_mps=(1.0, -2.0, 0.5)),
            num_envs=len(ids),
            dt=1 / 240,
            integrator=integrator,
            dtype=dtype,
            parallel=parallel,
        )
        sim.reset(**{k: v[ids] for k, v in state.items()})
        for k in range(steps // 4):
            sim.step(controls[4 * k][ids], steps=4)
        return np.concatenate([sim.pos, sim.quat, sim.lin_vel, sim.ang_vel], axis=-1)

    try:
        batch2 = run(np.arange(n), True, 2)
        batch1 = run(np.arange(n), True, 1)
        serial = run(np.arange(n), False, 1)
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    assert np.all(np.isfinite(batch2))
    assert np.array_equal(batch2, batch1) and np.array_equal(batch2, serial)
    for i in picks:
        alone = run(np.array([i]), False, 1)
        assert np.array_equal(alone[0], batch2[i]), f"body {i} differs alone vs in batch"


def test_contact_impulses_and_runaway_flags_agree_serial_and_parallel():
    """The ground's impulse is per call: a dart lifted off the floor reads 0 the next call,
    serial or parallel. (numba dropped the parallel kernel's reset of it: every dart of a
    batch of 1024 or more kept its last touchdown's impulse and "landed" each step after.)"""
    from fluidsim_envs.physics import Ground

    plane = Craft.load("paper_airplane")
    out = {}
    for parallel in (False, True):
        sim = Simulator(plane, World(ground=Ground()), num_envs=130, dt=1 / 120, parallel=parallel)
        sim.reset(pos=[0.0, 0.0, 0.01])
        sim.step(steps=4)
        landed = sim.ground_impulse[:, 0].copy()
        sim.reset(pos=[0.0, 0.0, 5.0])
        sim.step(steps=4)
        out[parallel] = (landed, sim.ground_impulse[:, 0].copy(), sim.diverged.copy())
    assert (out[False][0] > 0).all()  # on the floor: pushed
    for a, b in zip(out[False], out[True], strict=True):
        np.testing.assert_array_equal(a, b)
    assert not out[True][1].any()  # lifted: nothing touches
