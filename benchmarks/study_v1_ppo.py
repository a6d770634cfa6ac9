"""PPO on the v1 envs at ``standard``, with and without the probes, beside the tuned pilot.

For each shipped PPO config and variant, one seed (one seed says what one run did, not what
PPO does: the multi-seed statistics are issue 24's):

- ``probes``: the config with ``env_id`` its scene's v1 (``difficulty="standard"``, the
  default, and ``observe_samples=True``, the default: the probes' columns end the
  observation);
- ``no probes``: the same with ``env_kwargs.observe_samples=false``;
- ``probes, no floor`` (on request, ``--variants``): ``probes`` with VecNormalize's
  variance floor at SB3's default, for a config that :data:`SETS` raises it for (the boat:
  why there).

``--difficulty`` trains at another level (run folders ``runs/v1_LEVEL``, the CSV
``docs/study_v1_ppo_LEVEL.csv``).

Each run is ``fluidsim-train CONFIG --set env_id=... seed=S ... --run-dir RUNS/...`` (the real
CLI, in a subprocess; a run whose final model exists is kept), its final model evaluated by
the project's evaluator on ``--episodes`` seeded episodes (seed 0) beside the tuned pilot
(tuned on v0, never shown a level) and random actions, on the same episodes. Writes
``docs/study_v1_ppo.csv`` (a row per run and policy), ``docs/study_v1_ppo_curves.csv`` (each
run's evaluations during training) and ``docs/study_v1_ppo.png`` (the learning curves).

    python -m benchmarks.study_v1_ppo                 # trains what is missing (about an hour)
    python -m benchmarks.study_v1_ppo --csv-only      # the CSVs and chart from the run folders
    python -m benchmarks.study_v1_ppo --configs boat_on_step_ppo --difficulty easy --seed 1 \
        --total-timesteps 3000000 --variants probes "no probes" "probes, no floor"

The table in docs/environments.md comes from the CSV, the boat's at easy in
docs/training.md (``python -m benchmarks.report``).
"""

from __future__ import annotations

import argparse
import csv
import re
import sys
from pathlib import Path

import yaml

from benchmarks.common import DOCS, ROOT, read_csv, write_csv
from benchmarks.train_wallclock import evaluate, run_dir, train
from fluidsim_envs import threads

CSV = DOCS / "study_v1_ppo.csv"
CURVES = DOCS / "study_v1_ppo_curves.csv"
RUNS = ROOT / "runs" / "v1"
CONFIGS = {  # the shipped PPO configs and their scenes' v1
    "paper_airplane_ppo": "fluidsim/PaperAirplane-v1",
    "submarine_wake_ppo": "fluidsim/SubmarineWake-v1",
    "boat_on_step_ppo": "fluidsim/BoatOnStep-v1",
}
# What a v1 run sets beside the shipped config. The boat: VecNormalize's variance floor,
# epsilon, from 1e-8 (a guard against division by zero) to 1e-3 (a standard deviation of at
# least 0.03 in the column's SI unit). Its hull taps' wetted fractions, like the trim's
# oscillation, hardly vary while the hull pushes through the water (the policy's first
# million steps); normalized by that spread they leave the clip at +-10 as soon as the hull
# lifts, so the states of a planing hull look to the policy like nothing it has seen
# (docs/training.md, "Columns that barely vary").
SETS = {"boat_on_step_ppo": ("normalize.epsilon=1e-3",)}
VARIANTS = {
    "probes": (),
    "no probes": ("env_kwargs.observe_samples=false",),
    # the boat's runs with SB3's own floor (what SETS changes): why SETS has it
    "probes, no floor": ("normalize.epsilon=1e-8",),
}
DEFAULT_VARIANTS = ("probes", "no probes")
LEVELS = ("easy", "standard", "hard")
POLICIES = {"trained": "PPO", "tuned pilot": "tuned pilot", "random": "random"}
COLUMNS = (
    "env", "variant", "seed", "policy", "env_steps", "wall_s", "episodes",
    "success_rate", "success_rate_lo", "success_rate_hi",
    "return_mean", "return_mean_lo", "return_mean_hi",
)  # fmt: skip
CURVE_COLUMNS = ("env", "variant", "seed", "timesteps", "mean_return", "success_rate")


def _sets(config: str, variant: str, level: str = "standard") -> list[str]:
    at = [f"env_kwargs.difficulty={level}"] if level != "standard" else []
    return [f"env_id={CONFIGS[config]}", *at, *SETS.get(config, ()), *VARIANTS[variant]]


def _folder(variant: str) -> str:
    """A variant's part of a run folder's name: "no probes" -> no_probes."""
    return "_".join(re.findall(r"[a-z0-9]+", variant))


def level_csv(level: str) -> Path:
    """The runs' CSV at ``level`` (standard's is :data:`CSV`)."""
    return CSV if level == "standard" else CSV.with_name(f"study_v1_ppo_{level}.csv")


def rows(out: Path, config: str, variant: str, seed: int) -> list[dict]:
    """The CSV rows of one run: its trained policy, the tuned pilot and random actions on the
    same episodes, from its ``evaluation.csv``."""
    meta = yaml.safe_load((out / "run.yaml").read_text())
    timing = meta["timing"][-1]
    with (out / "evaluation.csv").open() as f:
        table = list(csv.DictReader(ln for ln in f if not ln.startswith("#")))
    found = []
    for r in table:
        name = next((v for k, v in POLICIES.items() if r["policy"].startswith(k)), None)
        if name is None:
            continue
        found.append({
            "env": CONFIGS[config].split("/")[1], "variant": variant, "seed": seed,
            "policy": name, "env_steps": timing["env_steps"], "wall_s": timing["wall_s"],
            **{c: r[c] for c in COLUMNS[6:]},
        })  # fmt: skip
    return found


def curve(out: Path, config: str, variant: str, seed: int) -> list[dict]:
    """The run's evaluations during training (``eval/history.csv``; none in a short run)."""
    path = out / "eval" / "history.csv"
    if not path.is_file():
        return []
    with path.open() as f:
        return [
            {"env": CONFIGS[config].split("/")[1], "variant": variant, "seed": seed,
             "timesteps": r["timesteps"], "mean_return": r["mean_return"],
             "success_rate": r["success_rate"]}
            for r in csv.DictReader(f)
        ]  # fmt: skip


def plot(
    path: Path = CURVES, png: Path | None = None, final: Path = CSV, level: str = "standard"
) -> Path:
    """Success during training of each variant, per env; the pilot's line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    _, points = read_csv(path)
    _, final = read_csv(final)
    envs = list(dict.fromkeys(r["env"] for r in points))
    fig, axes = plt.subplots(1, len(envs), figsize=(4.4 * len(envs), 3.6), squeeze=False)
    for ax, env in zip(axes[0], envs, strict=True):
        for variant, color in zip(VARIANTS, ("tab:blue", "tab:orange", "tab:red"), strict=True):
            mine = [r for r in points if r["env"] == env and r["variant"] == variant]
            if not mine:
                continue
            t = [float(r["timesteps"]) / 1e6 for r in mine]
            ax.plot(t, [100 * float(r["success_rate"]) for r in mine], "o-", ms=3,
                    color=color, label=f"PPO, {variant}")  # fmt: skip
        pilot = [r for r in final if r["env"] == env and r["policy"] == "tuned pilot"]
        if pilot:
            ax.axhline(100 * float(pilot[0]["success_rate"]), color="k", ls="--", lw=1,
                       label="tuned pilot")  # fmt: skip
        ax.set_title(f"{env} ({level})", fontsize=10)
        ax.set_xlabel("env steps (millions)")
        ax.set_ylabel("success in evaluation (%)")
        ax.set_ylim(-2, 102)
        ax.grid(alpha=0.3)
    axes[0][0].legend(loc="best", fontsize=8)
    fig.tight_layout()
    png = png or path.with_name(path.stem.removesuffix("_curves") + ".png")
    fig.savefig(png, dpi=90)
    plt.close(fig)
    return png


def markdown(path: Path = CSV) -> str:
    """docs/environments.md's table: each run's final success and return beside the pilot's
    and random actions' on the same episodes."""
    _, table = read_csv(path)

    def ci(r, key, pct):
        f = (lambda x: f"{100 * float(x):.0f}%") if pct else (lambda x: f"{float(x):.1f}")
        return f"{f(r[key])} [{f(r[key + '_lo'])}, {f(r[key + '_hi'])}]"

    lines = [
        "| env | observation | policy | env steps | success [95%] | return [95%] |",
        "|---|---|---|---:|---:|---:|",
    ]
    seen = set()
    envs = list(dict.fromkeys(r["env"] for r in table))
    order = {"PPO": 0, "tuned pilot": 1, "random": 2}
    table.sort(key=lambda r: (envs.index(r["env"]), order[r["policy"]]))  # stable: variants
    for r in table:
        if r["policy"] != "PPO" and (r["env"], r["policy"]) in seen:
            continue  # the baselines' rows are the same in both variants: once
        seen.add((r["env"], r["policy"]))
        what = r["variant"] if r["policy"] == "PPO" else "-"
        steps = f"{int(float(r['env_steps'])):,}" if r["policy"] == "PPO" else "-"
        score = f"{ci(r, 'success_rate', True)} | {ci(r, 'return_mean', False)}"
        lines.append(f"| {r['env']} | {what} | {r['policy']} | {steps} | {score} |")
    episodes = table[0]["episodes"] if table else "?"
    lines.append("")
    lines.append(f"One training seed per row; {episodes} evaluation episodes (seed 0), the same "
                 "episodes for every policy of an env.")  # fmt: skip
    return "\n".join(lines)


def easy_markdown() -> str:
    """docs/training.md's table: the boat at easy, with and without the variance floor."""
    return markdown(level_csv("easy"))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--configs", nargs="+", default=list(CONFIGS), choices=list(CONFIGS))
    parser.add_argument("--episodes", type=int, default=256)
    parser.add_argument("--difficulty", choices=LEVELS, default="standard")
    parser.add_argument("--variants", nargs="+", choices=list(VARIANTS),
                        default=list(DEFAULT_VARIANTS))  # fmt: skip
    parser.add_argument("--runs", type=Path, default=None,
                        help="run folders (default runs/v1, runs/v1_LEVEL)")  # fmt: skip
    parser.add_argument("--csv-only", action="store_true", help="train nothing, evaluate nothing")
    parser.add_argument("--total-timesteps", type=int, default=None,
                        help="a budget other than each config's (a smoke run: with --runs and "
                             "--out elsewhere)")  # fmt: skip
    parser.add_argument("--out", type=Path, default=None,
                        help="the runs' CSV, curves beside (default docs/study_v1_ppo.csv, "
                             "docs/study_v1_ppo_LEVEL.csv)")  # fmt: skip
    args = parser.parse_args(argv)
    threads.apply(threads.choose())  # the one owner's counts, as the CLIs run on
    level = args.difficulty
    runs = args.runs or (RUNS if level == "standard" else RUNS.with_name(f"v1_{level}"))
    args.out = args.out or level_csv(level)
    table, points = [], []
    for config in args.configs:
        for variant in args.variants:
            name = _folder(variant)
            steps = args.total_timesteps
            out = run_dir(runs, config, name, args.seed, steps)
            if not args.csv_only:
                sets = _sets(config, variant, level)
                train(runs, config, name, args.seed, steps, sets=sets)
                evaluate(out, args.episodes)
            if not (out / "evaluation.csv").is_file():
                print(f"missing: {out} (not trained or not evaluated)")
                continue
            table += rows(out, config, variant, args.seed)
            points += curve(out, config, variant, args.seed)
    notes = [f"difficulty: {level}"]
    notes += [f"{v}: {' '.join(VARIANTS[v]) or '(the defaults)'}" for v in args.variants]
    notes += [f"{config}: also {' '.join(sets)}" for config, sets in SETS.items()]
    curves = args.out.with_name(args.out.stem + "_curves.csv")
    write_csv(args.out, COLUMNS, ([r[c] for c in COLUMNS] for r in table), notes)
    write_csv(curves, CURVE_COLUMNS, ([r[c] for c in CURVE_COLUMNS] for r in points))
    print(markdown(args.out))
    print(f"written: {args.out}, {curves}, {plot(curves, final=args.out, level=level)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
