"""The shipped PPO configs retuned for wall clock against their settings before the retune:
trained to the same ``total_timesteps`` from the same seeds, each final model evaluated with
the project's evaluator on the same 256 seeded episodes.

For each seed, config and variant (``before``: the shipped config with
:data:`benchmarks.bench_training.V0_BEFORE` set, the settings it had before the retune, but torch
on one thread; ``256x64``: the same with 256 envs x 64 steps: :data:`VARIANTS`), in that
order, so that both variants of a config run one after the other under much the same load:

1. ``fluidsim-train CONFIG --set seed=S [BEFORE] --run-dir RUNS/CONFIG-VARIANT-sS`` (the real
   CLI, in a subprocess), with the load average before and after written to the run folder's
   ``wallclock.yaml``; a run whose final model exists is not trained again;
2. :func:`fluidsim_envs.rl.evaluate.evaluate` of its final model on ``--episodes`` episodes
   (seed 0; without the planner: ``fluidsim-evaluate RUN --episodes 256 --no-planner``),
   unless its ``evaluation.csv`` exists;
3. ``docs/training_wallclock.csv``: one row per run: its settings, the training wall time
   and env-steps/s (``run.yaml``'s ``timing``), the load, and the trained policy's success
   rate and mean return with their 95% bootstrap intervals over the episodes.

    python -m benchmarks.train_wallclock --seeds 0 1        # trains what is missing (hours)
    python -m benchmarks.train_wallclock --total-timesteps boat_on_step_ppo=2000000  # shorter
    python -m benchmarks.train_wallclock --csv-only         # the CSV from the run folders

The table in docs/training.md comes from the CSV (``python -m benchmarks.report``:
:func:`markdown`). Run folders stay under ``runs/`` (not in git).
"""

from __future__ import annotations

import argparse
import csv
import os
import subprocess
import sys
import time
from pathlib import Path

import yaml

from benchmarks.bench_training import BEFORE as V1_BEFORE
from benchmarks.bench_training import CONFIGS as V1_CONFIGS
from benchmarks.bench_training import V0_BEFORE as BEFORE
from benchmarks.bench_training import V0_CONFIGS
from benchmarks.common import DOCS, ROOT, read_csv, write_csv
from fluidsim_envs import threads
from fluidsim_envs.rl.runs import MODEL, PICKLED

CSV = DOCS / "training_wallclock.csv"
#: the v1 configs' retune (issue 43): ``before`` their settings before it, ``after`` as they
#: ship, both on the threads fluidsim.threads chooses (torch on one)
CSV_V1 = DOCS / "training_wallclock_v1.csv"
CONFIGS = V0_CONFIGS + tuple(c for c in V1_CONFIGS if V1_BEFORE[c])
RUNS = ROOT / "runs" / "wallclock"
#: ``before``: the old learning settings with torch on one thread: torch's thread count
#: changes no hyperparameter (only the order of float sums), and with its default of two
#: threads on a loaded 2-core machine the old config ran many times slower
#: (docs/bench_training.csv), hours per run; its real wall clock is bench_training's.
#: ``256x64``: the rollout shape tried, the same 16384 transitions per rollout from 256 envs
#: x 64 steps (what paper_airplane_ppo ships; the other configs kept 64 x 256)
VARIANTS = {
    "before": (*BEFORE, "torch_threads=1"),
    "256x64": (*BEFORE, "torch_threads=1", "n_envs=256", "algorithm.n_steps=64"),
}


def variants(config: str) -> dict[str, tuple[str, ...]]:
    """The variants a config is trained in: the v0 retune's, or a v1 config's before and
    after issue 43."""
    if config in V0_CONFIGS:
        return VARIANTS
    return {"before": V1_BEFORE[config], "after": ()}


COLUMNS = (
    "config", "variant", "seed", "n_envs", "n_steps", "batch_size", "n_epochs", "torch_threads",
    "env_steps", "wall_s", "env_steps_per_s", "load_start", "load_end", "episodes",
    "success_rate", "success_rate_lo", "success_rate_hi",
    "return_mean", "return_mean_lo", "return_mean_hi",
    "pilot_return", "steps_to_pilot", "time_to_pilot_s",
)  # fmt: skip


def run_dir(runs: Path, config: str, variant: str, seed: int, steps: int | None = None) -> Path:
    """The run folder; ``steps``: a budget other than the config's ``total_timesteps``."""
    return runs / (f"{config}-{variant}-s{seed}" + (f"-t{steps}" if steps else ""))


def train(
    runs: Path, config: str, variant: str, seed: int, steps: int | None = None, sets=None
) -> Path:
    """The run of ``config`` / ``variant`` / ``seed`` (for ``steps`` env steps, else the
    config's ``total_timesteps``), trained unless it has finished; ``sets``: the variant's
    ``--set`` items (default: :data:`VARIANTS`')."""
    out = run_dir(runs, config, variant, seed, steps)
    if (out / MODEL).is_file():
        return out
    if (out / PICKLED[MODEL]).is_file():  # finished by an older version: never deleted
        raise SystemExit(
            f"{out}: its model is an SB3 pickle; convert the run once (python -m "
            f"fluidsim_envs.rl.convert {out} --allow-pickle) and run this again"
        )
    if out.exists():  # a run killed before its end: start it afresh, not resumed
        import shutil

        shutil.rmtree(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    cmd = [
        str(Path(sys.executable).with_name("fluidsim-train")),
        config,
        "--set",
        f"seed={seed}",
        *(variants(config)[variant] if sets is None else sets),
        *([f"total_timesteps={steps}"] if steps else []),
        "--run-dir",
        str(out),
        "--no-progress-bar",
    ]
    print(f"{time.strftime('%H:%M:%S')} {' '.join(cmd[1:])}", flush=True)
    load_start = os.getloadavg()[0]
    with (runs / f"{out.name}.log").open("w") as log:
        subprocess.run(cmd, check=True, stdout=log, stderr=subprocess.STDOUT, cwd=ROOT)
    load = {"load_start": round(load_start, 2), "load_end": round(os.getloadavg()[0], 2)}
    (out / "wallclock.yaml").write_text(yaml.safe_dump(load))
    return out


def evaluate(out: Path, episodes: int) -> Path:
    """``out``'s final model on ``episodes`` seeded episodes (seed 0), beside the pilots."""
    from fluidsim_envs.rl.evaluate import evaluate as evaluate_run

    path = out / "evaluation.csv"
    if not path.is_file():
        print(f"{time.strftime('%H:%M:%S')} evaluating {out.name}", flush=True)
        evaluate_run(out, episodes, 0, planner=False)
    return path


def row(out: Path, config: str, variant: str, seed: int) -> dict:
    """A CSV row from the run folder: its config, timing, load and evaluation."""
    cfg = yaml.safe_load((out / "config.yaml").read_text())
    meta = yaml.safe_load((out / "run.yaml").read_text())
    timing = meta["timing"][-1]
    load = yaml.safe_load((out / "wallclock.yaml").read_text())
    with (out / "evaluation.csv").open() as f:
        trained = next(
            r
            for r in csv.DictReader(ln for ln in f if not ln.startswith("#"))
            if r["policy"].startswith("trained")
        )
    a = cfg["algorithm"]
    target, steps, seconds = to_pilot(out, cfg["env_id"])
    return {
        "config": config,
        "variant": variant,
        "seed": seed,
        "n_envs": cfg["n_envs"],
        "n_steps": a["n_steps"],
        "batch_size": a["batch_size"],
        "n_epochs": a["n_epochs"],
        "torch_threads": meta.get("torch_threads", ""),
        "env_steps": timing["env_steps"],
        "wall_s": timing["wall_s"],
        "env_steps_per_s": timing["env_steps_per_s"],
        **load,
        **{c: trained[c] for c in COLUMNS[-10:-3]},
        "pilot_return": target,
        "steps_to_pilot": steps,
        "time_to_pilot_s": seconds,
    }


def to_pilot(out: Path, env_id: str) -> tuple[float | str, int | str, float | str]:
    """The tuned pilot's mean return at ``standard`` (a v1 env's; "" for v0), and the run's
    first evaluation at or above it: its timesteps and the run's wall-clock seconds then
    ("" when none reached it). The evaluations are the run's own (32 episodes every
    ``eval.freq`` steps): a first crossing, not a claim of the 256-episode table's kind."""
    if not env_id.endswith("-v1"):
        return "", "", ""
    from benchmarks.sweep_envs import pilot_return

    target = pilot_return(env_id)
    with (out / "eval" / "history.csv").open() as f:
        for r in csv.DictReader(f):
            if float(r["mean_return"]) >= target:
                return target, int(r["timesteps"]), float(r["wall_s"])
    return target, "", ""


# ---- the table -------------------------------------------------------------------------------


def _ci(r: dict, key: str, percent: bool) -> str:
    f = (lambda x: f"{100 * float(x):.0f}") if percent else (lambda x: f"{float(x):.1f}")
    unit = "%" if percent else ""
    return f"{f(r[key])}{unit} [{f(r[key + '_lo'])}, {f(r[key + '_hi'])}]"


def verdict(rows: list[dict], new: str = "256x64") -> str:
    """``new`` against ``before`` per seed: worse when its interval lies wholly below
    before's (success or return), better when wholly above, else within the intervals."""
    by = {(r["variant"], r["seed"]): r for r in rows}
    out = []
    for seed in dict.fromkeys(r["seed"] for r in rows):
        b, a = by.get(("before", seed)), by.get((new, seed))
        if b is None or a is None:
            continue
        words = []
        for key, name in (("success_rate", "success"), ("return_mean", "return")):
            if float(a[f"{key}_hi"]) < float(b[f"{key}_lo"]):
                words.append(f"{name} worse")
            elif float(a[f"{key}_lo"]) > float(b[f"{key}_hi"]):
                words.append(f"{name} better")
        out.append(f"seed {seed}: " + (", ".join(words) or "within the intervals"))
    return "; ".join(out)


def _to_pilot(r: dict) -> str:
    if not r["time_to_pilot_s"]:
        return f"not reached ({float(r['pilot_return']):.2f})"
    return f"{float(r['time_to_pilot_s']):,.0f} ({int(r['steps_to_pilot']):,})"


def markdown(path: Path = CSV) -> str:
    """docs/training_wallclock.csv as a table: per config, variant and seed, the settings,
    the training wall time and rate, and the final score with its intervals; a verdict line
    per config."""
    if not path.is_file():
        return f"(no docs/{path.name} yet: run python -m benchmarks.train_wallclock)"
    comments, rows = read_csv(path)
    pilot = bool(rows) and "time_to_pilot_s" in rows[0]  # the v1 table's column
    lines = [
        "| config | variant | seed | n_envs x n_steps, batch, epochs, torch threads "
        "| env steps | wall (s) | env-steps/s | load (start, end) "
        "| success [95% interval] | return [95% interval] |"
        + " to the tuned pilot's return: s (env steps) |"
        * pilot,
        "|---|---|---:|---|---:|---:|---:|---|---:|---:|" + "---:|" * pilot,
    ]
    for r in rows:
        lines.append(
            f"| {r['config']} | {r['variant']} | {r['seed']} | {r['n_envs']} x {r['n_steps']}, "
            f"{r['batch_size']}, {r['n_epochs']}, {r['torch_threads']} "
            f"| {int(r['env_steps']):,} | {float(r['wall_s']):,.0f} "
            f"| {float(r['env_steps_per_s']):,.0f} | {r['load_start']}, {r['load_end']} "
            f"| {_ci(r, 'success_rate', True)} | {_ci(r, 'return_mean', False)} |"
            + (f" {_to_pilot(r)} |" if pilot else "")
        )
    verdicts = [
        f"- {config}, {new} against before: {v}"
        for config in dict.fromkeys(r["config"] for r in rows)
        for new in [next(iter(variants(config).keys() - {"before"}))]
        if (v := verdict([r for r in rows if r["config"] == config], new))
    ]
    if verdicts:
        lines += ["", *verdicts]
    command = next((c[len("command: ") :] for c in comments if c.startswith("command: ")), "")
    episodes = rows[0]["episodes"] if rows else "?"
    lines += [
        "",
        f"`{command}`: each final model on the same {episodes} seeded episodes "
        "(`fluidsim-evaluate RUN --episodes 256 --no-planner`); intervals over the episodes.",
    ]
    return "\n".join(lines)


def markdown_v1() -> str:
    """docs/training_wallclock_v1.csv as :func:`markdown`'s table (the v1 retune)."""
    return markdown(CSV_V1)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    parser.add_argument("--configs", nargs="+", default=list(CONFIGS), choices=CONFIGS)
    parser.add_argument(
        "--variants", nargs="+", choices=["before", "256x64", "after"], help="default: all"
    )
    parser.add_argument("--episodes", type=int, default=256)
    parser.add_argument(
        "--total-timesteps",
        nargs="+",
        default=[],
        metavar="CONFIG=N",
        help="train CONFIG for N env steps, not its total_timesteps (both variants alike)",
    )
    parser.add_argument("--runs", type=Path, default=RUNS, help="where the run folders go")
    parser.add_argument("--out", type=Path, help=f"default: {CSV.name}, {CSV_V1.name} for v1")
    parser.add_argument("--csv-only", action="store_true", help="train nothing, evaluate nothing")
    args = parser.parse_args(argv)
    threads.apply(threads.choose())  # the one owner's counts, as the CLIs run on
    budgets = {}
    for item in args.total_timesteps:
        config, _, n = item.partition("=")
        if config not in CONFIGS or not n.isdigit() or int(n) < 1:
            parser.error(
                f"--total-timesteps expects CONFIG=N with CONFIG in {CONFIGS}, got {item!r}"
            )
        budgets[config] = int(n)
    rows = []
    for seed in args.seeds:
        for config in args.configs:
            for variant in args.variants or variants(config):
                if variant not in variants(config):
                    continue
                steps = budgets.get(config)
                out = run_dir(args.runs, config, variant, seed, steps)
                if not args.csv_only:
                    evaluate(train(args.runs, config, variant, seed, steps), args.episodes)
                if (out / "evaluation.csv").is_file() and (out / "wallclock.yaml").is_file():
                    rows.append(row(out, config, variant, seed))
                else:
                    print(f"missing: {out} (not trained or not evaluated)")
    v1 = all(c in V1_CONFIGS for c in args.configs)
    args.out = args.out or (CSV_V1 if v1 else CSV)
    notes = [
        f"{config} {name}: {' '.join(sets) or 'as shipped'}"
        for config in args.configs
        for name, sets in variants(config).items()
    ]
    notes += [f"{c}: {n:,} env steps, not its total_timesteps" for c, n in budgets.items()]
    write_csv(args.out, COLUMNS, ([r[c] for c in COLUMNS] for r in rows), notes)
    print(markdown(args.out))
    print(f"written: {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
