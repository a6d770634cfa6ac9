"""What each learning option buys: each shipped v1 PPO config trained as shipped and with one
option switched (off where it ships on, on where it ships off), and with the other values
it was raced against (:data:`RACES`), a few training seeds each (and every seed a variant
has trained here), every final model on validation episodes at each level beside the
pilots.

    python -m benchmarks.ablation --configs paper_airplane_v1_ppo --seeds 2
    python -m benchmarks.ablation --table          # docs/ablation.md from docs/ablation.csv

The options (``fluidsim_envs/rl/config.py``): ``warm_start`` (the tuned pilot's actions and
returns fitted before PPO), ``levels`` (easy, standard and hard side by side), a
``privileged_critic`` (the value function reads the exact state) and ``frame_stack`` (the
last four observations). The validation episodes are their own: :data:`SEED` of the
evaluation stream, never the results' seed 0, so that choosing the shipped combination here
does not fit it to the episodes docs/results.md scores it on. Runs train on the training
stream, two at a time (one core each), through ``fluidsim-train``; each run's folder under
``sweeps/ablation/<config>/<variant>-<digest>/`` keeps its model and its evaluation (a run
done is not trained again; a changed config trains its variants anew).
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import yaml

from benchmarks.common import DOCS, ROOT, read_csv, write_csv
from fluidsim_envs.rl.runs import MODEL

CONFIGS = ("paper_airplane_v1_ppo", "submarine_wake_v1_ppo", "boat_on_step_v1_ppo")
LEVELS = ("easy", "standard", "hard")
SEED = 5  # the validation episodes: evaluation stream, not the results' seed 0
EPISODES = 256
FOLDER = ROOT / "sweeps" / "ablation"
CSV = DOCS / "ablation.csv"
PAGE = DOCS / "ablation.md"
COLUMNS = ("config", "variant", "overrides", "seed", "level", "mean_return", "success", "wall_s")
PILOTS = ("tuned pilot", "v0-tuned pilot", "hand-set pilot")

#: an option switched: (name when switched on, on, name when switched off, off)
OPTIONS = (
    ("warm start", ["warm_start.steps=500000"], "no warm start", ["warm_start.steps=0"]),
    ("levels", ["levels=[easy, standard, hard]", "curriculum=[]"], "standard only",
     ["levels=[]"]),
    ("privileged critic", ["privileged_critic=true"], "plain critic",
     ["privileged_critic=false"]),
    ("frame stack 4", ["frame_stack=4"], "no frame stack", ["frame_stack=1"]),
)  # fmt: skip


#: per config, other values raced against the shipped ones (what it shipped with before its
#: last race, or what lost the race)
RACES = {
    "paper_airplane_v1_ppo": {
        "a third at each level, 10 M steps": [
            "levels=[easy, standard, hard]", "total_timesteps=10000000"],
    },
    "boat_on_step_v1_ppo": {
        "a third at each level, 5 epochs, 6 M steps": [
            "levels=[easy, standard, hard]", "algorithm.n_epochs=5",
            "total_timesteps=6000000"],
    },
}  # fmt: skip


def variants(config: str) -> dict[str, list[str]]:
    """``shipped``, per option the config with it switched (its name says which way), and
    the config's :data:`RACES`."""
    from fluidsim_envs.rl.config import load_config

    cfg = load_config(config)
    shipped_on = {
        "warm start": bool(cfg.warm_start.steps),
        "levels": bool(cfg.levels),
        "privileged critic": cfg.privileged_critic,
        "frame stack 4": cfg.frame_stack > 1,
    }
    out = {"shipped": []}
    for on_name, on, off_name, off in OPTIONS:
        if shipped_on[on_name]:
            out[off_name] = off
        else:
            out[f"+ {on_name}"] = on
    return out | RACES.get(config, {})


def run_dir(config: str, variant: str, overrides: list[str], seed: int) -> Path:
    """Where ``variant``'s run with ``seed`` lives: under what it trains (the config digest
    with the variant's overrides), so that a shipped config that changes trains its variants
    again instead of finding the old ones."""
    from benchmarks.results import config_digest

    name = re.sub(r"[^a-z0-9]+", "_", variant.replace("+", "with").lower()).strip("_")
    return FOLDER / config / f"{name}-{config_digest(config, overrides)}" / f"seed{seed}"


def train(config: str, variant: str, overrides: list[str], seed: int) -> Path:
    """The run of ``variant`` with ``seed`` (trained here unless its final model exists)."""
    folder = run_dir(config, variant, overrides, seed)
    if (folder / MODEL).is_file():
        return folder
    cmd = [sys.executable, "-m", "fluidsim_envs.rl.train", config, "--set", *overrides,
           f"seed={seed}", "numba_threads=1", "torch_threads=1", "checkpoint.freq=0",
           "--run-dir", str(folder), "--no-progress-bar"]  # fmt: skip
    if (folder / "run.yaml").is_file():
        cmd = [sys.executable, "-m", "fluidsim_envs.rl.train", "--resume", str(folder),
               "--no-progress-bar"]  # fmt: skip
    folder.parent.mkdir(parents=True, exist_ok=True)
    print("$", " ".join(cmd), flush=True)
    with open(folder.parent / f"seed{seed}.log", "a") as log:
        subprocess.run(cmd, check=True, cwd=ROOT, stdout=log, stderr=subprocess.STDOUT)
    return folder


def evaluate(run: Path, level: str) -> dict[str, float]:
    """The run's final model on the validation episodes at ``level`` (cached in the run)."""
    from benchmarks.results import run_episodes

    got = run_episodes(run, EPISODES, SEED, level)
    return {"mean_return": float(np.mean(got["return"])), "success": float(np.mean(got["success"]))}


def pilots(env_id: str, level: str) -> dict[str, dict[str, float]]:
    """Each pilot's mean return and success rate on the validation episodes at ``level``
    (cached)."""
    from benchmarks.results import fly_baseline

    cache = FOLDER / "baselines" / f"{env_id.split('/')[1]}-{level}-{EPISODES}-{SEED}.yaml"
    if cache.is_file():
        return yaml.safe_load(cache.read_text())
    out = {}
    for p in PILOTS:
        got = fly_baseline(env_id, level, p, EPISODES, SEED)
        out[p] = {"mean_return": float(np.mean(got["return"])),
                  "success": float(np.mean(got["success"]))}  # fmt: skip
    cache.parent.mkdir(parents=True, exist_ok=True)
    cache.write_text(yaml.safe_dump(out))
    return out


def rows(config: str, seeds: int, workers: int) -> list[tuple]:
    """Train what is missing of ``config``'s variants and seeds, then evaluate each run. The
    shipped variant's runs are the results' (``benchmarks.results``: the same config, seeds
    and stream), where that has them here."""
    from benchmarks.results import local_runs
    from fluidsim_envs.rl.config import load_config

    shipped = local_runs(config)

    def seeds_of(variant, overrides):  # those asked for, and any trained here already
        here = run_dir(config, variant, overrides, 0).parent.glob(f"seed*/{MODEL}")
        return sorted(set(range(seeds)) | {int(p.parent.name[4:]) for p in here})

    jobs = [(v, o, s) for v, o in variants(config).items() for s in seeds_of(v, o)]
    if shipped:
        jobs = [j for j in jobs if j[0] != "shipped"] + [("shipped", [], s) for s in shipped]

    def run_of(job):
        variant, _, seed = job
        return shipped[seed] if variant == "shipped" and shipped else train(config, *job)

    with ThreadPoolExecutor(workers) as pool:
        runs = list(pool.map(run_of, jobs))
    out = []
    for (variant, overrides, seed), run in zip(jobs, runs, strict=True):
        wall = sum(t["wall_s"] for t in yaml.safe_load((run / "run.yaml").read_text())["timing"])
        for level in LEVELS:
            got = evaluate(run, level)
            score = (round(got["mean_return"], 4), round(got["success"], 4))
            out.append((config, variant, " ".join(overrides), seed, level, *score, round(wall, 1)))
    for level in LEVELS:  # the pilots' rows: no seed, no overrides
        for name, got in pilots(load_config(config).env_id, level).items():
            out.append((config, name, "", "-", level, round(got["mean_return"], 4),
                        round(got["success"], 4), ""))  # fmt: skip
    return out


def table() -> str:
    """docs/ablation.csv as a table: per config and variant, each level's mean return over
    seeds (the worst seed's after it) against the best pilot's there, and the wall time."""
    if not CSV.is_file():
        return "(no docs/ablation.csv yet: `python -m benchmarks.ablation`)\n"
    _, data = read_csv(CSV)
    lines = [
        "| config | variant | seeds | " + " | ".join(LEVELS) + " | wall (min) |",
        "|---|---|--:|" + "---|" * len(LEVELS) + "--:|",
    ]
    best = {}
    for config in [c for c in CONFIGS if any(r["config"] == c for r in data)]:
        flown = [r for r in data if r["config"] == config and r["variant"] in PILOTS]
        best[config] = {
            level: max(float(r["mean_return"]) for r in flown if r["level"] == level)
            for level in LEVELS
        }
        lines.append(
            f"| {config} | best pilot | | "
            + " | ".join(f"{best[config][level]:.2f}" for level in LEVELS) + " | |"
        )  # fmt: skip
        trained = [r["variant"] for r in data if r["config"] == config and r["seed"] != "-"]
        for variant in dict.fromkeys(trained):
            mine = [r for r in data if (r["config"], r["variant"]) == (config, variant)]
            cells = []
            for level in LEVELS:
                x = [float(r["mean_return"]) for r in mine if r["level"] == level]
                mark = "**" if min(x) > best[config][level] else ""
                cells.append(f"{mark}{np.mean(x):.2f}{mark} (worst {min(x):.2f})")
            wall = np.mean([float(r["wall_s"]) for r in mine]) / 60
            seeds = len({r["seed"] for r in mine})
            lines.append(f"| {config} | {variant} | {seeds} | " + " | ".join(cells)
                         + f" | {wall:.1f} |")  # fmt: skip
    return "\n".join(lines) + "\n"


def page() -> str:
    return f"""# Ablation: what each learning option buys

<!-- written by `python -m benchmarks.ablation` from docs/ablation.csv: do not edit -->

Each shipped v1 PPO config trained as shipped, with one option switched (off where it
ships on, `+` where it ships off), and with the other values it was raced against (what it
shipped with before, or what lost: the row named by them), each with its seeds, every final
model flown deterministically on {EPISODES} validation episodes (evaluation stream, seed
{SEED}: not the episodes docs/results.md scores on) at each level. A cell is the mean return
over seeds, and the worst seed's; in bold where every seed is above the best pilot there
(the best of the tuned, v0-tuned and hand-set pilots on the same episodes, in the config's
*best pilot* row). Wall time is the run's own clock, one core a run (one or two at a time
on a 2-core machine, beside other work: not a benchmark), the warm start's pilot flights
included.

{table()}"""


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--configs", nargs="+", choices=CONFIGS, default=list(CONFIGS))
    parser.add_argument("--seeds", type=int, default=2, help="training seeds per variant (2)")
    parser.add_argument("--workers", type=int, default=2, help="runs at a time (2)")
    parser.add_argument("--table", action="store_true", help="only the page, from the CSV")
    args = parser.parse_args(argv)
    if not args.table:
        new = [r for c in args.configs for r in rows(c, args.seeds, args.workers)]
        old = [r for r in (read_csv(CSV)[1] if CSV.is_file() else [])
               if r["config"] not in args.configs]  # fmt: skip
        every = [tuple(r[c] for c in COLUMNS) for r in old] + new
        every.sort(key=lambda r: CONFIGS.index(r[0]))  # the configs in CONFIGS' order
        write_csv(CSV, COLUMNS, every,
                  [f"validation episodes: {EPISODES} at each level, seed {SEED}"])  # fmt: skip
    PAGE.write_text(page())
    print(table())
    return 0


if __name__ == "__main__":
    sys.exit(main())
