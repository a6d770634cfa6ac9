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
shorter, noisier run; ``--sections swell`` (for example) runs only those sections and keeps the
other sections' rows of the CSV at ``--out``, with their run's ``#`` lines. Timings are
disturbed by anything else running on the machine.

:func:`markdown` and :func:`cost_markdown` are docs/benchmarks.md's kernel table and sentences
(``python -m benchmarks.report`` writes them from the CSV).
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import time

import numba
import numpy as np

from benchmarks.common import (
    DOCS,
    Table,
    arguments,
    describe,
    prose,
    read_csv,
    timed,
    write_csv,
)
from fluidsim_envs.physics import INTEGRATORS, Craft, Simulator, World

CRAFT = "paper_airplane"
DT = 1.0 / 240.0
NUM_ENVS = (1, 64, 1024, 16384)
DTYPES = {"float32": np.float32, "float64": np.float64}
# (kernel, threads) rows of the throughput table; the serial kernel ignores the thread count
KERNELS = (("serial", 1), ("parallel", 1), ("parallel", 2))
COLUMNS = ("section", "dtype", "integrator", "num_envs", "threads", "kernel", "value", "unit")
SECTIONS = ("throughput", "call_overhead", "integrators", "swell", "compile")
WAVES = (0, 1, 2, 4)
CSV = DOCS / "bench_kernel.csv"
KEPT = "rows of sections not run kept from: "  # a comment line of a partial run


def section_of(row_section: str) -> str:
    """The ``--sections`` name of a CSV row's section (``compile`` for both compile rows)."""
    return "compile" if row_section.startswith("compile_") else row_section


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

    def glide():  # high enough that a call of seconds never reaches the water (swell section:
        # from 10 m the dart glided into it and diverged, and a diverged env skips its work)
        sim.reset(pos=(0.0, 0.0, 100.0), lin_vel=(6.0, 0.0, 0.0))

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


def kept_rows(path, sections) -> tuple[list[str], list[tuple]]:
    """The rows of ``path`` outside ``sections`` (``compile`` stands for both compile rows),
    and the comment lines that say which run they come from."""
    if not path.is_file():
        return [], []
    comments, rows = read_csv(path)
    keep = [r for r in rows if section_of(r["section"]) not in sections]
    if not keep:
        return [], []
    origin = [c.removeprefix(KEPT) for c in comments if c.startswith(KEPT)]
    if not origin:
        origin = ["; ".join(c for c in comments if c.startswith(("command:", "load average")))]
    cells = [tuple(r[c] for c in COLUMNS) for r in keep]
    return [KEPT + origin[0]], cells


def main() -> None:
    parser = arguments(__doc__, "shorter, noisier measurements", "bench_kernel.csv")
    parser.add_argument(
        "--sections", nargs="+", choices=SECTIONS, default=list(SECTIONS),
        help="run only these sections; keep the others' rows from --out (default: all)",
    )  # fmt: skip
    args = parser.parse_args()
    target_s, repeats, calls = (0.05, 3, 2000) if args.quick else (0.3, 5, 20000)
    kept_notes, kept = kept_rows(args.out, args.sections)

    info = describe()
    table = Table(COLUMNS, (14, 8, 17, -6, -8, 9, -15, 1))
    record = table.add
    if "throughput" in args.sections:
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

    if "call_overhead" in args.sections:
        overhead = call_overhead_us(calls)
        record("call_overhead", "float64", "symplectic_euler", 1, 1, "serial", overhead, "us/call")

    numba.set_num_threads(2)
    if "integrators" in args.sections:
        for dtype in ("float64", "float32"):
            for integrator in INTEGRATORS:
                sim, controls = make_sim(16384, dtype, "parallel", integrator)
                rate = body_steps_per_s(sim, controls, target_s, repeats)
                record("integrators", dtype, integrator, 16384, 2, "parallel", rate, "body-steps/s")

    if "swell" in args.sections:
        for dtype in ("float64", "float32"):
            for waves in WAVES:
                swell = [(0.3, 20.0 + 7.0 * j, 40.0 * j) for j in range(waves)]
                world = World(water=True, swell=swell)
                sim, controls = make_sim(16384, dtype, "parallel", world=world)
                rate = body_steps_per_s(sim, controls, target_s, repeats)
                where = f"{waves} waves"
                record("swell", dtype, where, 16384, 2, "parallel", rate, "body-steps/s")

    if "compile" in args.sections:
        with tempfile.TemporaryDirectory(prefix="numba-cache-") as cache_dir:
            for section in ("compile_cold", "compile_cached"):
                seconds = first_step_seconds(cache_dir)
                record(section, "float64", "symplectic_euler", 64, 1, "serial", seconds, "s")

    rows = [*kept, *table.rows]
    order = {name: i for i, name in enumerate(SECTIONS)}
    rows.sort(key=lambda r: order[section_of(r[0])])  # stable: each section's own order
    print(f"\nwrote {write_csv(args.out, COLUMNS, rows, [*info, *kept_notes])}")


# ---- the docs --------------------------------------------------------------------------------


def _rates(path) -> tuple[list[str], dict]:
    comments, rows = read_csv(path)
    return comments, {
        (r["section"], r["dtype"], r["integrator"], r["num_envs"], r["threads"], r["kernel"]): (
            float(r["value"])
        )
        for r in rows
    }


def _machine(comments: list[str]) -> str:
    """``2 cores, AMD EPYC, x86_64; numba 0.68.1, numpy 2.4.6`` from the ``#`` lines."""
    cpu = next((c for c in comments if c.startswith("cpu: ")), "cpu: ?")[5:]
    cores = next((c for c in comments if c.startswith("os.cpu_count: ")), "")
    cores = cores.split(",")[0].removeprefix("os.cpu_count: ")
    versions = next((c for c in comments if c.startswith("python ")), "")
    numba_v = re.search(r"numba [\d.]+", versions)
    numpy_v = re.search(r"numpy [\d.]+", versions)
    model, arch = (cpu.rsplit(" (", 1) + [""])[:2]
    return (
        f"{cores} cores, {model}, {arch.rstrip(')')}; "
        f"{numba_v.group(0) if numba_v else '?'}, {numpy_v.group(0) if numpy_v else '?'}"
    )


def _load(comments: list[str], key: str = "load average at start: ") -> str:
    line = next((c for c in comments if c.startswith(key)), "")
    return line.removeprefix(key).split(",")[0] or "?"


def markdown(path=None) -> str:
    """docs/benchmarks.md's kernel table (millions of body-steps/s, the serial kernel on
    1 thread and the parallel one on 2) and the cost of swell, from docs/bench_kernel.csv."""
    path = CSV if path is None else path
    if not path.is_file():
        return "(no docs/bench_kernel.csv yet: run python -m benchmarks.bench_kernel)"
    comments, v = _rates(path)
    head = ["num_envs"]
    cells = []
    for dtype in DTYPES:
        head += [f"{dtype}, 1 thread", f"{dtype}, 2 threads"]
    for n in NUM_ENVS:
        row = [str(n)]
        for dtype in DTYPES:
            for threads, kernel in (("1", "serial"), ("2", "parallel")):
                key = ("throughput", dtype, "symplectic_euler", str(n), threads, kernel)
                row.append(f"{v[key] / 1e6:.1f}" if key in v else "")
        cells.append(row)
    lines = [
        prose(
            f"Measured on the project's CI machine kind ({_machine(comments)}), symplectic "
            f"Euler, {Craft.load(CRAFT).num_samples} fluid samples per body, in millions of "
            "body-steps per second:"
        ),
        "",
        "| " + " | ".join(head) + " |",
        "|---:|" + "---:|" * (len(head) - 1),
        *("| " + " | ".join(row) + " |" for row in cells),
        "",
    ]
    kept = next((c.removeprefix(KEPT) for c in comments if c.startswith(KEPT)), "")
    load = _load([c.strip() for c in kept.split(";")]) if kept else _load(comments)
    note = (
        "(1 thread: the serial kernel; 2 threads: the parallel one. Below 1024 bodies the "
        "simulator picks the serial kernel, since one block of 64 environments runs on one "
        f"thread anyway. One run, load average {load} at its start.)"
    )
    swell = {w: v.get(("swell", "float64", f"{w} waves", "16384", "2", "parallel")) for w in WAVES}
    if all(swell.values()):
        where = "" if not kept else f" (another run, load average {_load(comments)} at its start)"
        rates = [f"{swell[w] / 1e6:.1f} M" for w in WAVES]
        note += (
            " Over water with swell the same dart, in float64 at 16384 envs on 2 threads"
            f"{where}, runs {rates[0]} body-steps/s in calm water, {rates[1]} with one wave, "
            f"{rates[2]} with two and {rates[3]} with four: every sample looks up the surface "
            "under it."
        )
    else:
        note += (
            " (No swell rows in docs/bench_kernel.csv yet: "
            "`python -m benchmarks.bench_kernel --sections swell` adds them.)"
        )
    lines.append(prose(note))
    return "\n".join(lines)


def cost_markdown(path=None) -> str:
    """docs/benchmarks.md's sentences on what the integrators and a call cost, from
    docs/bench_kernel.csv's ``integrators``, ``call_overhead`` and ``compile_cached`` rows."""
    path = CSV if path is None else path
    if not path.is_file():
        return "(no docs/bench_kernel.csv yet: run python -m benchmarks.bench_kernel)"
    _, v = _rates(path)

    def ratio(m: str) -> str:
        return (
            f"{v['integrators', 'float64', m, '16384', '2', 'parallel'] / base:.2f}"
            if ("integrators", "float64", m, "16384", "2", "parallel") in v
            else "?"
        )

    base = v.get(("integrators", "float64", "symplectic_euler", "16384", "2", "parallel"), 1.0)
    overhead = v.get(("call_overhead", "float64", "symplectic_euler", "1", "1", "serial"))
    cached = v.get(("compile_cached", "float64", "symplectic_euler", "64", "1", "serial"))
    from benchmarks.bench_compile import first_step_range

    return prose(
        "Cost follows force evaluations per step: at 16384 envs on 2 threads in float64, "
        f"velocity Verlet runs at {ratio('velocity_verlet')} and RK2 at {ratio('rk2')} times "
        f"symplectic Euler's rate, RK4 at {ratio('rk4')}, explicit Euler at "
        f"{ratio('explicit_euler')}. One `sim.step` call from Python costs "
        f"{overhead:.1f} us at E = 1 (the median); the first call compiles the kernels "
        f"({first_step_range()} per env on 2 cores, where the time goes per kernel: "
        "`python -m benchmarks.bench_compile`, "
        "[bench_compile.csv](bench_compile.csv); the process says so on stderr), later "
        f"processes load them from numba's cache in {cached:.2f} s (docs/bench_kernel.csv). These "
        "are absolute numbers from one run on a shared machine."
    )


if __name__ == "__main__":
    main()
