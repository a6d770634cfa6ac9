"""Does a sweep trial train as fast as ``fluidsim-train``? One config, the same steps, run in
turn as ``fluidsim-train`` (torch's default of a thread per core, and one thread) and as a
one-trial ``fluidsim-sweep`` on local Ray at ``--cpus-per-trial`` 2 and 1 (:data:`VARIANTS`),
each alone on the machine; each run's training env-steps per second and wall time from its
``run.yaml`` (``timing``: the run's own clock, without Ray's start), and the whole command's
wall time.

    python -m benchmarks.bench_sweep_trial                     # dart v1 PPO, 300,000 steps
    python -m benchmarks.bench_sweep_trial --config submarine_wake_v1_ppo --repeats 2

Why: the v1 races (``benchmarks.sweep_envs``, one trial at a time at ``--cpus-per-trial 2``)
trained the dart at about 3,800 env-steps/s, while the multi-seed runs (``benchmarks.results``,
two one-core trials side by side) ran at about 10,000 each. A race's times to the target are
only as good as the trials' speed. The variants rule out Ray's worker niceness, the
``OMP_NUM_THREADS`` Ray sets and numba's threads, and find it in torch's: a trial whose torch
has one thread (``fluidsim-sweep --torch-threads 1``, now the default) keeps
``fluidsim-train``'s pace. Writes ``docs/bench_sweep_trial.csv``; run it on a quiet machine
(the load average before and after each run is in the CSV).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

from benchmarks.common import DOCS, ROOT, describe, write_csv

CSV = DOCS / "bench_sweep_trial.csv"
COLUMNS = (
    "config", "variant", "repeat", "timesteps", "run_wall_s", "env_steps_per_s",
    "command_wall_s", "load_before", "load_after",
)  # fmt: skip
TWO = ("--cpus-per-trial", "2", "--torch-threads")
#: variant -> (module, its arguments besides the config, the folder and the overrides, and
#: environment variables). Ray starts its workers at niceness 15 (``RAY_worker_niceness``) so
#: that its own processes stay responsive; a trial's threads then yield to any of them.
VARIANTS = {
    "fluidsim-train, torch threads default": ("fluidsim_envs.rl.train", [], {}),
    "fluidsim-train, torch threads 1": ("fluidsim_envs.rl.train", ["torch_threads=1"], {}),
    # a 2-CPU trial as the races ran it (torch's threads = its CPUs), and what might explain
    # its slowness: Ray's worker niceness, Ray's OMP_NUM_THREADS (the CPUs it was given),
    # OpenMP threads spinning at barriers while Ray's own processes preempt one of them,
    # numba's threads or torch's
    "fluidsim-sweep, --cpus-per-trial 2 --torch-threads 2, Ray's niceness 15": (
        "fluidsim_envs.rl.sweep", [*TWO, "2"], {"RAY_worker_niceness": "15"}
    ),
    "fluidsim-sweep, --cpus-per-trial 2 --torch-threads 2, niceness 0": (
        "fluidsim_envs.rl.sweep", [*TWO, "2"], {"RAY_worker_niceness": "0"}
    ),
    "fluidsim-train, OMP_NUM_THREADS=2 (as Ray sets it)": (
        "fluidsim_envs.rl.train", [], {"OMP_NUM_THREADS": "2"}
    ),
    "fluidsim-sweep, --cpus-per-trial 2 --torch-threads 2, OMP_WAIT_POLICY=passive": (
        "fluidsim_envs.rl.sweep", [*TWO, "2"], {"OMP_WAIT_POLICY": "passive"}
    ),
    "fluidsim-sweep, --cpus-per-trial 2 --torch-threads 2, numba threads 1": (
        "fluidsim_envs.rl.sweep", [*TWO, "2"], {"NUMBA_NUM_THREADS": "1"}
    ),
    "fluidsim-train, numba threads 1": ("fluidsim_envs.rl.train", [], {"NUMBA_NUM_THREADS": "1"}),
    # the fix: one torch thread in a trial (fluidsim-sweep's default)
    "fluidsim-sweep, --cpus-per-trial 2 --torch-threads 1": (
        "fluidsim_envs.rl.sweep", [*TWO, "1"], {}
    ),
    "fluidsim-sweep, --cpus-per-trial 1": ("fluidsim_envs.rl.sweep", ["--cpus-per-trial", "1"], {}),
}  # fmt: skip


def command(variant: str, config: str, steps: int, folder: Path) -> list[str]:
    module, extra, _ = VARIANTS[variant]
    sets = [f"total_timesteps={steps}", f"eval.freq={steps // 3}", "checkpoint.freq=0"]
    if module.endswith("train"):
        tail = ["--set", *sets, *extra, "--run-dir", str(folder), "--no-progress-bar"]
    else:
        tail = ["--seeds", "1", *extra, "--set", *sets, "--sweep-dir", str(folder)]
    return [sys.executable, "-m", module, config, *tail]


def run_yaml(folder: Path) -> dict:
    paths = [folder / "run.yaml", *sorted(folder.glob("runs/*/run.yaml"))]
    return yaml.safe_load(next(p for p in paths if p.is_file()).read_text())


def measure(variant: str, config: str, steps: int, repeat: int) -> tuple:
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "run"
        start = time.perf_counter()
        env = {**os.environ, **VARIANTS[variant][2]}
        subprocess.run(command(variant, config, steps, folder), check=True, cwd=ROOT, env=env,
                       stdout=subprocess.DEVNULL)  # fmt: skip
        wall = time.perf_counter() - start
        meta = run_yaml(folder)
    timing = meta["timing"][-1]
    row = (
        config, variant, repeat, meta["num_timesteps"], timing["wall_s"],
        timing["env_steps_per_s"], round(wall, 1), load_before, os.getloadavg()[0],
    )  # fmt: skip
    print(f"{variant:55s} {timing['env_steps_per_s']:>9,.0f} env-steps/s, run {timing['wall_s']}"
          f" s, command {wall:.0f} s (load {load_before:.2f})", flush=True)  # fmt: skip
    return row


def markdown() -> str:
    """docs/bench_sweep_trial.csv as a table: each variant's env-steps/s against
    ``fluidsim-train``'s default."""
    from benchmarks.common import read_csv

    if not CSV.is_file():
        return "(no docs/bench_sweep_trial.csv yet: `python -m benchmarks.bench_sweep_trial`)\n"
    _, rows = read_csv(CSV)
    base = float(rows[0]["env_steps_per_s"])
    lines = [
        "| config | variant | env-steps/s | vs fluidsim-train | run (s) | load before |",
        "|---|---|--:|--:|--:|--:|",
    ]
    for r in rows:
        rate = float(r["env_steps_per_s"])
        lines.append(
            f"| {r['config']} | {r['variant']} | {rate:,.0f} | {rate / base:.2f}x | "
            f"{float(r['run_wall_s']):.1f} | {float(r['load_before']):.2f} |"
        )
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--config", default="paper_airplane_v1_ppo")
    parser.add_argument("--steps", type=int, default=300_000)
    parser.add_argument("--repeats", type=int, default=1, help="rounds of every variant")
    parser.add_argument("--variants", nargs="+", choices=list(VARIANTS), default=list(VARIANTS))
    args = parser.parse_args(argv)
    machine = describe()
    rows = [
        measure(variant, args.config, args.steps, r)
        for r in range(args.repeats)
        for variant in args.variants
    ]
    write_csv(CSV, COLUMNS, rows, machine)
    return 0


if __name__ == "__main__":
    sys.exit(main())
