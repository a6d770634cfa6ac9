"""Benchmark the numba step kernel on the paper_airplane craft (13 fluid samples, 3 controls).

Measures, and prints as a table and writes as CSV (``--out``):

1. ``throughput``: body-steps per second at E = 1, 64, 1024, 16384 environments, float32 and
   float64, for the serial kernel on 1 thread and the parallel kernel on 1 and 2 threads. Each
   figure is the best of several timed calls ``sim.step(controls, steps=k)``, k chosen so one
   call lasts ~0.3 s (body-steps/s = E * k / seconds), after a warm-up call and a reset.
2. ``call_overhead``: microseconds per ``sim.step(controls, steps=1)`` at E = 1 (serial), the
   median of many calls: the cost of one round trip through Python.
3. ``integrators``: body-steps per second at E = 16384 on 2 threads for every integrator.
4. ``swell``: body-steps per second at E = 16384 on 2 threads over water, calm (0 waves) and
   with 1, 2 and 4 swell waves (the ``integrator`` column holds the number of waves): the cost
   of the surface height under every sample (the same glide, above the water: the swell costs
   the same wherever the samples are).
5. ``compile_cold`` / ``compile_cached``: seconds taken by the first ``sim.step()`` in a fresh
   Python process (E = 64, float64, serial), with ``NUMBA_CACHE_DIR`` pointing at an empty
   directory, then again in a second process that finds the cache filled by the first.

The machine (CPU, core count, numba and numpy versions, threading layer, load average) is
printed first and written as ``#`` comment lines at the top of the CSV.

Run it with ``python -m benchmarks.bench_kernel`` (or ``make bench``); ``--quick`` gives a
shorter, noisier run. Timings are disturbed by anything else running on the machine.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time

import numba
import numpy as np

from benchmarks.common import Table, arguments, describe, timed, write_csv
from fluidsim_envs.physics import INTEGRATORS, Craft, Simulator, World

CRAFT = "paper_airplane"
DT = 1.0 / 240.0
NUM_ENVS = (1, 64, 1024, 16384)
DTYPES = {"float32": np.float32, "float64": np.float64}
# (kernel, threads) rows of the throughput table; the serial kernel ignores the thread count
KERNELS = (("serial", 1), ("parallel", 1), ("parallel", 2))
COLUMNS = ("section", "dtype", "integrator", "num_envs", "threads", "kernel", "value", "unit")

# Run in a fresh interpreter: print the seconds taken by the first step (compile or cache load).
CHILD = f"""
import time
import numpy as np
from fluidsim_envs.physics import Craft, Simulator, World
sim = Simulator(Craft.load({CRAFT!r}), World(), num_envs=64, dt={DT!r}, dtype=np.float64,
                parallel=False)
t0 = time.perf_counter()
sim.step()
print(time.perf_counter() - t0)
"""


def make_sim(
    num_envs: int,
    dtype: str,
    kernel: str = "serial",
    integrator: str = "symplectic_euler",
    world: World | None = None,
) -> tuple[Simulator, np.ndarray]:
    sim = Simulator(
        Craft.load(CRAFT),
        World() if world is None else world,
        num_envs=num_envs,
        dt=DT,
        integrator=integrator,
        dtype=DTYPES[dtype],
        parallel=kernel == "parallel",
    )
    rng = np.random.default_rng(0)
    controls = rng.uniform(-0.3, 0.3, size=(num_envs, len(sim.control_names)))
    return sim, controls


def timed_call(sim: Simulator, controls: np.ndarray, steps: int) -> float:
    """Seconds for one ``sim.step(controls, steps)`` from a fresh gliding state."""

    def glide():
        sim.reset(pos=(0.0, 0.0, 10.0), lin_vel=(6.0, 0.0, 0.0))

    return timed(lambda: sim.step(controls, steps=steps), setup=glide)


def body_steps_per_s(sim: Simulator, controls: np.ndarray, target_s: float, repeats: int) -> float:
    """Best body-steps/s over ``repeats`` calls, each sized to last about ``target_s``."""
    timed_call(sim, controls, 1)  # warm-up: compile or load from the cache, start the threads
    steps, t = 1, timed_call(sim, controls, 1)
    while t < target_s / 10:
        steps *= 10
        t = timed_call(sim, controls, steps)
    steps = max(1, round(steps * target_s / t))
    best = min(timed_call(sim, controls, steps) for _ in range(repeats))
    if sim.diverged.any():
        print(f"  warning: {int(sim.diverged.sum())} environments diverged", file=sys.stderr)
    return sim.num_envs * sim.num_bodies * steps / best


def call_overhead_us(calls: int) -> float:
    """Median microseconds per ``sim.step(controls, steps=1)`` at E = 1 (serial kernel)."""
    sim, controls = make_sim(1, "float64")
    sim.reset(pos=(0.0, 0.0, 10.0), lin_vel=(6.0, 0.0, 0.0))
    sim.step(controls)
    times = np.empty(calls)
    for i in range(calls):  # timed inline: a helper's extra call would show at this scale
        t0 = time.perf_counter_ns()
        sim.step(controls, steps=1)
        times[i] = time.perf_counter_ns() - t0
    return float(np.median(times)) / 1e3


def first_step_seconds(cache_dir: str) -> float:
    """Seconds for the first step in a fresh interpreter using numba's cache in ``cache_dir``."""
    env = {**os.environ, "NUMBA_CACHE_DIR": cache_dir}
    out = subprocess.run(
        [sys.executable, "-c", CHILD], env=env, capture_output=True, text=True, check=True
    )
    return float(out.stdout.split()[-1])


def main() -> None:
    parser = arguments(__doc__, "shorter, noisier measurements", "bench_kernel.csv")
    args = parser.parse_args()
    target_s, repeats, calls = (0.05, 3, 2000) if args.quick else (0.3, 5, 20000)

    info = describe()
    table = Table(COLUMNS, (14, 8, 17, -6, -8, 9, -15, 1))
    record = table.add
    for dtype in DTYPES:
        for num_envs in NUM_ENVS:
            for kernel, threads in KERNELS:
                numba.set_num_threads(threads)
                sim, controls = make_sim(num_envs, dtype, kernel)
                rate = body_steps_per_s(sim, controls, target_s, repeats)
                record(
                    "throughput",
                    dtype,
                    "symplectic_euler",
                    num_envs,
                    threads,
                    kernel,
                    rate,
                    "body-steps/s",
                )

    record(
        "call_overhead",
        "float64",
        "symplectic_euler",
        1,
        1,
        "serial",
        call_overhead_us(calls),
        "us/call",
    )

    numba.set_num_threads(2)
    for dtype in ("float64", "float32"):
        for integrator in INTEGRATORS:
            sim, controls = make_sim(16384, dtype, "parallel", integrator)
            rate = body_steps_per_s(sim, controls, target_s, repeats)
            record("integrators", dtype, integrator, 16384, 2, "parallel", rate, "body-steps/s")

    for dtype in ("float64", "float32"):
        for waves in (0, 1, 2, 4):
            swell = [(0.3, 20.0 + 7.0 * j, 40.0 * j) for j in range(waves)]
            world = World(water=True, swell=swell)
            sim, controls = make_sim(16384, dtype, "parallel", world=world)
            rate = body_steps_per_s(sim, controls, target_s, repeats)
            record("swell", dtype, f"{waves} waves", 16384, 2, "parallel", rate, "body-steps/s")

    with tempfile.TemporaryDirectory(prefix="numba-cache-") as cache_dir:
        for section in ("compile_cold", "compile_cached"):
            record(
                section,
                "float64",
                "symplectic_euler",
                64,
                1,
                "serial",
                first_step_seconds(cache_dir),
                "s",
            )

    print(f"\nwrote {write_csv(args.out, COLUMNS, table.rows, info)}")


if __name__ == "__main__":
    main()
