"""Benchmark the submarine's wake field and the tracer particles that show it.

Measures, and prints as a table and writes as CSV (``--out``):

1. ``field``: wake-field evaluations per second, ``wake_velocity_batch`` over N points
   (1e6; 1e5 with ``--quick``) spread evenly over the tracers' default box around a hull
   moving at 5 m/s, with the field's parts switched on one after the other: displacement
   only, + screw vortices, + turbulence (the default WakeField).
2. ``tracers``: ``Tracers.advance`` calls per second (and tracer-steps per second) for 2000
   and 20000 tracers in the default wake, advected by the field itself (``exact``) or by
   about 512 macro particles (``macro``), with the serial kernel and the parallel one on
   all of numba's threads. Each figure is the best of several timed runs of a few advances
   (dt = 1/30 s, one substep) after a warm-up.
3. ``macro_error``: how far the macro blend is from the field: RMS of the velocity
   difference over the RMS velocity, at 20000 points in the box, for 512 and 2000 macro
   particles.

The machine (CPU, core count, numba and numpy versions, threading layer, load average) is
printed first and written as ``#`` comment lines at the top of the CSV.

Run it with ``python -m benchmarks.bench_wake``; ``--quick`` gives a shorter, noisier run.
Timings are disturbed by anything else running on the machine.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from benchmarks.common import Table, arguments, best_of, describe, write_csv
from fluidsim_envs.physics import WakeField
from fluidsim_envs.physics.tracers import MacroParticles, Tracers, default_box
from fluidsim_envs.physics.wake import source_row, wake_velocity_batch

SPEED = 5.0  # m/s, along body x
DT = 1.0 / 30.0
MACRO = 512
PARTS = {
    "displacement": dict(vortices=False, noise=0.0),
    "+vortices": dict(noise=0.0),
    "+noise": dict(),
}
COLUMNS = ("section", "wake", "count", "mode", "kernel", "threads", "value", "unit")


def box_points(wake: WakeField, n: int, seed: int = 0) -> np.ndarray:
    """n points spread evenly over the tracers' default box (hull at the origin)."""
    lo, hi = np.array(default_box(wake)).T
    return lo + np.random.default_rng(seed).random((n, 3)) * (hi - lo)


def field_rate(wake: WakeField, n: int, repeats: int) -> float:
    """Wake-field evaluations per second over n points."""
    pts = box_points(wake, n)
    out = np.empty_like(pts)
    src = source_row((0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0), (SPEED, 0.0, 0.0))
    prm = wake.params()
    return n / best_of(lambda: wake_velocity_batch(pts, src, prm, out), repeats)


def advance_rate(count: int, macro: int, parallel: bool, advances: int, repeats: int) -> float:
    """Tracers.advance calls per second: ``advances`` steps after a fresh (untimed) reset."""
    tr = Tracers(WakeField(), count=count, macro=macro, parallel=parallel)
    quat, vel = (1.0, 0.0, 0.0, 0.0), (SPEED, 0.0, 0.0)

    def reset():
        tr.reset((0.0, 0.0, -50.0), quat, vel, np.random.default_rng(0))

    def run():
        for k in range(1, advances + 1):
            tr.advance(DT, (SPEED * DT * k, 0.0, -50.0), quat, vel)

    return advances / best_of(run, repeats, reset)


def macro_error(count: int) -> float:
    """RMS |macro blend - field| / RMS |field| over the default box."""
    wake = WakeField()
    m = MacroParticles(wake, default_box(wake), count)
    pose = ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0), (SPEED, 0.0, 0.0))
    m.sample(*pose)
    pts = box_points(wake, 20000, seed=1)
    exact = wake.velocity(pts, *pose)
    return math.sqrt(np.sum((m.velocity(pts) - exact) ** 2) / np.sum(exact**2))


def main() -> None:
    parser = arguments(__doc__, "shorter, noisier measurements", "bench_wake.csv")
    args = parser.parse_args()
    points, repeats, advances = (100_000, 3, 5) if args.quick else (1_000_000, 5, 20)
    threads = numba.config.NUMBA_NUM_THREADS

    info = describe()
    table = Table(COLUMNS, (12, 13, -8, 6, 9, -7, -16, 1))
    record = table.add
    numba.set_num_threads(1)
    for name, parts in PARTS.items():
        rate = field_rate(WakeField(**parts), points, repeats)
        record("field", name, points, "exact", "serial", 1, rate, "evals/s")

    for count in (2000, 20000):
        for mode, macro in (("exact", 0), ("macro", MACRO)):
            for kernel, nthreads in (("serial", 1), ("parallel", threads)):
                numba.set_num_threads(nthreads)
                rate = advance_rate(count, macro, kernel == "parallel", advances, repeats)
                record("tracers", "+noise", count, mode, kernel, nthreads, rate, "advances/s")
                record(
                    "tracers",
                    "+noise",
                    count,
                    mode,
                    kernel,
                    nthreads,
                    rate * count,
                    "tracer-steps/s",
                )
    numba.set_num_threads(threads)

    for count in (MACRO, 2000):
        record("macro_error", "+noise", count, "macro", "serial", 1, macro_error(count), "rel. RMS")

    print(f"\nwrote {write_csv(args.out, COLUMNS, table.rows, info)}")


if __name__ == "__main__":
    main()
