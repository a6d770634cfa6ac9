"""Fixed point (``Simulator(dtype="fixed32" | "fixed64")``, physics/fixed/): the compiled
integer kernel equals the plain-Python integer reference bit for bit on each shipped craft the
format holds, the same for any batch size and thread count, the projectile's error is what the
format's rounding predicts, and bad inputs are refused naming the value."""

from __future__ import annotations

import math

import numba
import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Ground, Simulator, SwellWave, WakeField, World
from fluidsim_envs.physics.fixed import FixedSimulator
from fluidsim_envs.physics.fixed import laws as LW
from fluidsim_envs.physics.fixed import reference as REF
from tests.bad_inputs.table import Row, check, params

AIR, WATER = World(), World(water=True)
DART, UUV = Craft.load("paper_airplane"), Craft.load("uuv")
SI = {"length_m": 1.0, "mass_kg": 1.0, "time_s": 1.0}
# craft, world, initial state, controls (None: all 0), format, fraction bits, integrator
CASES = {
    "dart_fixed32_q14": (
        "paper_airplane", AIR, dict(pos=(0, 0, 20), lin_vel=(6, 0.5, 0), ang_vel=(0.3, 0, 0.2)),
        [0.3, -0.6, 0.2], "fixed32", 14, "symplectic_euler",
    ),
    "dart_fixed64_q24_prescaled": (
        "paper_airplane", AIR, dict(pos=(0, 0, 20), lin_vel=(6, 0, 0)),
        [-0.2, 0.5, 0.0], "fixed64", 24, "prescaled_symplectic_euler",
    ),
    "buoy_fixed64_q20": (
        "buoy", WATER, dict(pos=(0, 0, 0.15), quat=(0.99, 0.1, 0.05, 0), ang_vel=(0.2, 0.1, 0)),
        None, "fixed64", 20, "symplectic_euler",
    ),
    "buoy_fixed32_q16_prescaled": (
        "buoy", WATER, dict(pos=(0, 0, -0.1), lin_vel=(0.3, 0, 0.5)),
        None, "fixed32", 16, "prescaled_symplectic_euler",
    ),
    "uuv_fixed32_q14": (
        "uuv", WATER, dict(pos=(0, 0, -3), lin_vel=(1.5, 0, 0.2)),
        [0.8, 0.3, -0.4], "fixed32", 14, "symplectic_euler",
    ),
    "uuv_fixed64_q30": (  # 64-bit words and split products at 30 bits; the depth saturates
        "uuv", WATER, dict(pos=(0, 0, -3), lin_vel=(1.5, 0, 0.2)),
        [-0.7, 0.1, 0.9], "fixed64", 30, "symplectic_euler",
    ),
}  # fmt: skip
STEPS = 12


def _make(name, num_envs=1, parallel=False):
    craft, world, init, ctrl, dtype, bits, method = CASES[name]
    sim = Simulator(Craft.load(craft), world, num_envs, 1 / 120, method, dtype,
                    parallel=parallel, fraction_bits=bits)  # fmt: skip
    sim.reset(**init)
    c = None if ctrl is None else np.tile(np.asarray(ctrl, float), (num_envs, 1))
    return sim, c


@pytest.mark.parametrize("name", sorted(CASES))
def test_kernel_equals_the_plain_python_reference_bit_for_bit(name):
    sim, ctrl = _make(name)
    assert isinstance(sim, FixedSimulator)
    start = np.asarray(sim.fixed_state, dtype=np.int64).copy()
    sim.step(ctrl, steps=STEPS)
    state, flags = REF.run(start, sim.fixed_model, sim.fixed_controls, STEPS)
    assert np.array_equal(np.asarray(state, dtype=np.int64), sim.fixed_state)
    assert [bool(f) for f in flags] == sim.diverged.tolist()
    moved = np.asarray(state, dtype=np.int64) != start
    assert moved[..., LW.OX : LW.OX + 3].any() and moved[..., LW.OQ : LW.OQ + 4].any()
    # the comparison can fail: the last bit of one starting word changes the trajectory's
    nudged = start.copy()
    nudged[0, 0, LW.OV + 2] += 1
    other, _ = REF.run(nudged, sim.fixed_model, sim.fixed_controls, STEPS)
    assert not np.array_equal(np.asarray(other, dtype=np.int64), sim.fixed_state)


def _words(rng, n, lim):
    """n random words up to lim, magnitudes spread over every bit length."""
    mags = np.floor(2.0 ** rng.uniform(0, np.log2(lim), n)).astype(np.int64)
    return [int(m) * int(s) for m, s in zip(mags, rng.choice([-1, 1], n), strict=True)]


def test_the_arithmetic_is_exact_on_random_words():
    """qmul is floor((a b + 2^(s-1)) / 2^s) saturated, compiled and plain alike, for random
    32- and 64-bit words (the 64-bit product split in four); qdiv and isqrt likewise."""
    laws = REF.plain_laws()
    assert not hasattr(laws.qmul, "py_func")  # not a numba dispatcher
    rng = np.random.default_rng(3)
    for lim in ((1 << 31) - 1, (1 << 61) - 1):
        a, b = _words(rng, 400, lim), _words(rng, 400, lim)
        for s in (1, 14, 30):
            for x, y in zip(a + [lim, -lim, lim], b + [lim, lim, 3], strict=True):
                want = max(-lim, min(lim, (x * y + (1 << (s - 1))) >> s))
                assert LW.qmul(x, y, s, lim) == laws.qmul(x, y, s, lim) == want, (x, y, s)
                d = abs(y) or 1
                if abs(x) < 1 << (61 - s):  # qdiv shifts larger numerators down first
                    want = max(-lim, min(lim, ((x << s) + (d >> 1)) // d))
                    assert LW.qdiv(x, d, s, lim) == laws.qdiv(x, d, s, lim) == want, (x, d, s)
    for n in _words(rng, 300, (1 << 63) - 1) + [0, 1, (1 << 63) - 1]:
        assert LW.isqrt(abs(n)) == laws.isqrt(abs(n)) == math.isqrt(abs(n))


def test_integer_sine_and_the_deflected_normals_follow_the_float_laws():
    """laws.sincos within 2 units of 2^-30 over +-15 rad; the dart's deflected control
    surfaces within a word or two of forces.rotate_about_axis (float64)."""
    angles = np.linspace(-15.0, 15.0, 2001)
    words = np.floor(angles * 2.0**LW.ANGLE_BITS + 0.5).astype(np.int64)
    got = np.array([LW.sincos(int(t)) for t in words], dtype=np.float64) / 2.0**LW.ANGLE_BITS
    exact = words / 2.0**LW.ANGLE_BITS
    assert np.abs(got - np.stack([np.cos(exact), np.sin(exact)], 1)).max() < 2 * 2.0**-30
    sim = Simulator(DART, AIR, 1, dtype="fixed64", fraction_bits=24)
    sim.reset()
    controls = np.array([[0.7, -0.4, 1.0]])
    sim.step(controls)
    flaps = [p for p in DART.plates if p.hinge_axis is not None]
    mix = {
        p.name: row
        for p, row in zip(flaps, sim.fixed_model.mix[0].reshape(len(flaps), 3), strict=True)
    }
    for i, p in enumerate(flaps):
        theta = float(mix[p.name] @ controls[0]) / 2.0**LW.ANGLE_BITS
        n, h = np.array(p.normal), np.array(p.hinge_axis)
        want = (
            n * np.cos(theta) + np.cross(h, n) * np.sin(theta) + h * (h @ n) * (1 - np.cos(theta))
        )
        got = sim.fixed_inputs[0, 0, 3 * i : 3 * i + 3] / 2.0**24
        assert np.abs(got - want).max() < 4 * 2.0**-24, (p.name, got, want)


def test_one_env_equals_the_same_env_in_a_batch_of_70_on_any_thread_count():
    name = "uuv_fixed32_q14"
    alone, ctrl = _make(name)
    alone.step(ctrl, steps=STEPS)
    rng = np.random.default_rng(7)
    craft, world, init, c, dtype, bits, method = CASES[name]
    pos, vel = rng.normal(0, 1, (70, 3)) - (0, 0, 4), rng.normal(0, 1, (70, 3))
    controls = rng.uniform(-1, 1, (70, 3))
    controls[37] = c
    results = []
    for threads in (1, 2):
        batch = Simulator(Craft.load(craft), world, 70, 1 / 120, method, dtype, parallel=True,
                          fraction_bits=bits)  # fmt: skip
        batch.reset(pos=pos, lin_vel=vel)
        batch.reset(**init, env_ids=[37])
        previous = numba.get_num_threads()
        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
        try:
            batch.step(controls, steps=STEPS)
        finally:
            numba.set_num_threads(previous)
        results.append(np.array(batch.fixed_state))
        assert np.array_equal(batch.fixed_state[37], alone.fixed_state[0])
    assert np.array_equal(results[0], results[1])


def test_projectile_error_is_the_formats_rounding():
    """100 steps of dt = 1/100 from rest at g = 9.81 (the source article's test): symplectic
    Euler's discrete closed form is z = -g dt^2 n (n + 1) / 2 = -4.95405. In fixed point
    each kick adds the same rounded word, so z misses it by at most the roundings, half a
    word each: of g (times dt^2 n (n + 1) / 2), of the kick (times dt n (n + 1) / 2), of
    each of the n drifts, and of the step h = dt / T (30 bits) in each kick and drift."""
    ball = Craft(name="ball", mass_kg=1.0, inertia_kgm2=(0.4, 0.4, 0.4))
    n, dt, sum_n = 100, 0.01, 5050
    for dtype, bits in (("fixed32", 14), ("fixed32", 20), ("fixed64", 30)):
        sim = Simulator(ball, World(), 1, dt, dtype=dtype, fraction_bits=bits)
        sim.reset()
        sim.step(steps=n)
        u = sim.units
        word_z = u.length_m / 2.0**bits
        word_v = word_z / u.time_s
        word_g = word_v / u.time_s
        word_t = u.time_s * 2.0**-LW.STEP_BITS  # dt's word as h holds it
        bound = 0.5 * (word_g * dt * dt * sum_n + word_v * dt * sum_n + word_z * n)
        bound += 0.5 * word_t * 9.81 * dt * sum_n * 2
        err = abs(sim.pos[0, 0, 2] - -4.95405)
        assert 0 < err <= bound, (dtype, bits, err, bound)
        v_bound = 0.5 * (word_g * dt + word_v + word_t * 9.81) * n
        assert abs(sim.lin_vel[0, 0, 2] - -9.81) <= v_bound, (dtype, bits)


def test_reset_state_reads_back_within_a_word():
    """reset's floats become words and come back (ang_vel through L = R I R^T w and back)."""
    sim = Simulator(UUV, WATER, 3, dtype="fixed64", fraction_bits=20)
    q = np.array([0.9, 0.3, -0.2, 0.1]) / np.linalg.norm([0.9, 0.3, -0.2, 0.1])
    state = dict(pos=(1.5, -2.0, -3.25), quat=q, lin_vel=(1.2, -0.3, 0.4), ang_vel=(0.2, -0.1, 0.3))
    sim.reset(**state)
    word = 2.0**-20
    u = sim.units
    for name, scale in (("pos", u.length_m), ("quat", 1.0), ("lin_vel", u.length_m / u.time_s)):
        got = getattr(sim, name)
        assert got.shape == (3, 1, len(state[name]))
        assert np.abs(got - state[name]).max() <= scale * word, name
    assert np.abs(sim.ang_vel - state["ang_vel"]).max() < 1e-4
    assert sim.fixed_state.dtype == np.int64 and not sim.fixed_state.flags.writeable
    assert sim.clock.tolist() == [0.0] * 3


def test_q14_falls_behind_the_float_trajectory_and_q24_follows_it():
    """The dart's 1 s glide from float64 (same integrator, dt): Q14 in the derived units is
    within centimetres, Q24 within micrometres (docs/study_fixed.csv has the full sweep)."""
    craft, init = Craft.load("paper_airplane"), dict(pos=(0, 0, 20), lin_vel=(6, 0, 0))
    ref = Simulator(craft, AIR, 1, 1 / 120)
    ref.reset(**init)
    ref.step(steps=120)
    errs = []
    for bits in (14, 24):
        sim = Simulator(craft, AIR, 1, 1 / 120, dtype="fixed64", fraction_bits=bits)
        sim.reset(**init)
        sim.step(steps=120)
        errs.append(np.abs(sim.pos - ref.pos).max())
    assert errs[0] < 0.05 and errs[1] < 1e-4 and errs[1] < errs[0] / 100, errs


def test_a_runaway_saturates_and_is_flagged_not_wrapped():
    ball = Craft(name="ball", mass_kg=1.0, inertia_kgm2=(0.4, 0.4, 0.4))
    world = World(max_fluid_speed_mps=1000.0)  # no speed flag: the word's range flags it
    sim = Simulator(ball, world, 2, 0.01, dtype="fixed32", fraction_bits=20)
    sim.reset(pos=[(0, 0, 0), (0, 0, 0)], lin_vel=[(0, 0, 0), (0, 0, -100)])
    sim.step(steps=100)
    assert sim.diverged.tolist() == [False, False]
    sim.step(steps=1100)  # the second falls past the format's range (2^11 units of 0.5 m)
    assert sim.diverged.tolist() == [False, True]
    z = sim.fixed_state[1, 0, LW.OX + 2]
    assert z == -((1 << 31) - 1)  # saturated at the word, not wrapped to a positive number


ROWS = [
    Row("fixed_unknown_dtype", lambda: Simulator(UUV, WATER, dtype="fixed16"), ValueError,
        ["dtype", "fixed16", "fixed32", "fixed64"]),
    Row("fixed_fraction_bits_zero", lambda: Simulator(UUV, WATER, dtype="fixed32",
        fraction_bits=0), ValueError, ["fraction_bits", "0", "[1, 30]", "fixed32"]),
    Row("fixed32_fraction_bits_31", lambda: Simulator(UUV, WATER, dtype="fixed32",
        fraction_bits=31), ValueError, ["fraction_bits", "31", "fixed32"]),
    Row("fixed64_fraction_bits_40", lambda: Simulator(UUV, WATER, dtype="fixed64",
        fraction_bits=40), ValueError, ["fraction_bits", "40", "fixed64"]),
    Row("fixed_fraction_bits_float", lambda: Simulator(UUV, WATER, dtype="fixed64",
        fraction_bits=14.5), ValueError, ["fraction_bits", "14.5"]),
    Row("fixed_fraction_bits_with_float_dtype", lambda: Simulator(UUV, WATER,
        fraction_bits=14), ValueError, ["fraction_bits", "fixed"]),
    Row("fixed_dart_inertia_zero_in_si_q14", lambda: Simulator(DART, AIR, dtype="fixed32",
        units=SI), ValueError, ["paper_airplane", "fixed32 with 14 fraction bits", "inertia",
        "zero"]),
    Row("fixed_uuv_mass_overflow", lambda: Simulator(UUV, WATER, dtype="fixed32",
        units={"mass_kg": 1e-3}), ValueError, ["uuv", "mass_kg", "172", "fixed32", "largest"]),
    Row("fixed_unsupported_integrator", lambda: Simulator(UUV, WATER, integrator="rk4",
        dtype="fixed64"), ValueError, ["integrator", "rk4", "symplectic_euler",
        "prescaled_symplectic_euler"]),
    Row("fixed_contact", lambda: Simulator(DART, World(ground=Ground()), dtype="fixed32"),
        ValueError, ["fixed32", "contact"]),
    Row("fixed_swell", lambda: Simulator(UUV, World(water=True, swell=[SwellWave(0.5, 40.0)]),
        dtype="fixed32"), ValueError, ["fixed32", "swell"]),
    Row("fixed_wake", lambda: Simulator(UUV, WATER, dtype="fixed64", wake=WakeField()),
        ValueError, ["fixed64", "wake"]),
    Row("fixed_prescaled_time_unit", lambda: Simulator(UUV, WATER, dtype="fixed64",
        integrator="prescaled_symplectic_euler", units={"time_s": 1.0}), ValueError,
        ["prescaled", "time_s", "1.0"]),
    Row("fixed_reset_out_of_range", lambda: Simulator(UUV, WATER, dtype="fixed32",
        fraction_bits=24).reset(pos=(500.0, 0, 0)), ValueError, ["pos", "500", "fixed32"]),
]  # fmt: skip


@pytest.mark.parametrize("row", params(ROWS))
def test_bad_input(row):
    check(row)
