"""Where PPO's wall time goes, per shipped PPO config, before and after the wall-clock retune;
and the grid of settings the retune was chosen from.

Each measurement trains one config for ``--steps`` env steps (seed 0) through the trainer's
own building blocks (the envs, ``VecMonitor``, ``VecNormalize``, the model, the evaluation and
checkpoint callbacks, TensorBoard logging: :mod:`fluidsim_envs.rl.train`) into a temporary run
folder, with timers around SB3's methods (not a sampling profiler):

================  ============================================================================
``env``           the training ``VecEnv``'s ``step_wait``: the native vector env, the SB3
                  adapter, ``VecMonitor`` and ``VecNormalize``
``forward``       the policy's forward pass in the rollout (``policy.forward`` under no_grad)
``bookkeeping``   the rest of ``collect_rollouts``: tensors from and to NumPy, action clipping,
                  the rollout buffer's adds, value bootstraps of truncated episodes, GAE, the
                  callbacks' per-step calls
``update``        ``PPO.train``: the epochs of minibatch gradient steps
``eval``          the periodic evaluations (``Evaluations._on_step``, eval env and saves);
                  when the budget is shorter than ``eval.freq``, one evaluation timed after
                  training, times the budget over ``eval.freq`` (added to the wall time)
``checkpoint``    the periodic checkpoints (``Checkpoints._on_step``)
``other``         the rest of ``learn``: its set-up, the logger's dumps
================  ============================================================================

``before`` is each config with the settings it shipped with before the retune
(:data:`BEFORE`); ``after`` is the shipped config as it is. Both are measured in turn, round
after round (``--repeats``), so that a change of load on the machine hits them alike; each
row is its fastest round. torch's and numba's thread counts and the load average are written
with every row.

    python -m benchmarks.bench_training              # docs/bench_training.csv, .png
    python -m benchmarks.bench_training --quick      # the dart alone, 2 rollouts each: < 1 min
    python -m benchmarks.bench_training --grid       # docs/bench_training_grid.csv
    python -m benchmarks.bench_training --md-only    # the table and chart from the CSV
"""

from __future__ import annotations

import contextlib
import os
import tempfile
import time
from collections import defaultdict
from pathlib import Path

import numba

from benchmarks.common import DOCS, arguments, describe, load_average, read_csv, write_csv

CONFIGS = ("paper_airplane_ppo", "boat_on_step_ppo", "submarine_wake_ppo")
#: the wall-clock settings every shipped PPO config had before the retune (issue 21): a
#: variant is a list of ``--set`` overrides on top of the shipped config
BEFORE = (
    "n_envs=64",
    "algorithm.n_steps=256",
    "algorithm.batch_size=2048",
    "algorithm.n_epochs=10",
    "torch_threads=null",
)
PHASES = ("env", "forward", "bookkeeping", "update", "eval", "checkpoint", "other")
COLUMNS = (
    "config", "variant", "overrides", "n_envs", "n_steps", "batch_size", "n_epochs",
    "torch_threads", "numba_threads", "env_steps", "wall_s", "env_steps_per_s",
    *(f"{p}_s" for p in PHASES), "load_start", "load_end",
)  # fmt: skip
#: the grid (``--grid``): label -> overrides on top of BEFORE, measured on each --configs
GRID = {
    "before": (),
    "threads 1": ("torch_threads=1",),
    **{
        f"threads 1, {label}": ("torch_threads=1", *sets)
        for label, sets in {
            "batch 4096": ("algorithm.batch_size=4096",),
            "batch 8192": ("algorithm.batch_size=8192",),
            "epochs 5": ("algorithm.n_epochs=5",),
            "256 envs x 64": ("n_envs=256", "algorithm.n_steps=64"),
            "512 envs x 32": ("n_envs=512", "algorithm.n_steps=32"),
            "256 x 64, batch 4096": (
                "n_envs=256",
                "algorithm.n_steps=64",
                "algorithm.batch_size=4096",
            ),
            "256 x 64, batch 8192": (
                "n_envs=256",
                "algorithm.n_steps=64",
                "algorithm.batch_size=8192",
            ),
        }.items()
    },
    "256 x 64, threads 2": ("n_envs=256", "algorithm.n_steps=64", "torch_threads=2"),
}
CSV = DOCS / "bench_training.csv"
TORCH_DEFAULT_THREADS = 0  # torch's thread count before any measurement set it (main)
GRID_CSV = DOCS / "bench_training_grid.csv"


# ---- the timers ------------------------------------------------------------------------------


@contextlib.contextmanager
def timers(train_env):
    """Seconds per phase (inclusive: ``rollout`` holds env, forward, eval, checkpoint), from
    SB3's and our classes' methods wrapped for the duration: at class level, so that a model
    saved meanwhile pickles nothing of this. Only the training env's ``step_wait`` counts as
    ``env`` (the eval env is inside ``eval``)."""
    from stable_baselines3 import PPO
    from stable_baselines3.common.on_policy_algorithm import OnPolicyAlgorithm
    from stable_baselines3.common.policies import ActorCriticPolicy

    from fluidsim_envs.rl.callbacks import Checkpoints, Evaluations

    seconds: dict[str, float] = defaultdict(float)
    patched = []

    def wrap(cls, name: str, key: str, only=None) -> None:
        original = cls.__dict__[name]

        def timed(self, *args, **kwargs):
            if only is not None and self is not only:
                return original(self, *args, **kwargs)
            t0 = time.perf_counter()
            try:
                return original(self, *args, **kwargs)
            finally:
                seconds[key] += time.perf_counter() - t0

        setattr(cls, name, timed)
        patched.append((cls, name, original))

    wrap(OnPolicyAlgorithm, "collect_rollouts", "rollout")
    wrap(PPO, "train", "update")
    wrap(ActorCriticPolicy, "forward", "forward")
    wrap(type(train_env), "step_wait", "env", only=train_env)
    wrap(Evaluations, "_on_step", "eval")
    wrap(Checkpoints, "_on_step", "checkpoint")
    try:
        yield seconds
    finally:
        for cls, name, original in reversed(patched):
            setattr(cls, name, original)


def warm_up(*venvs) -> None:
    """Each SB3 env's native vector env reset and stepped once before anything is timed: an
    env instance compiles (or loads) its step kernel on its first step, seconds that belong
    to no phase. ``learn`` (and each evaluation) resets with its own seed afterwards."""
    import numpy as np

    for venv in venvs:
        if venv is None:
            continue
        native = venv.unwrapped.venv
        native.reset(seed=0)
        native.step(np.zeros(native.action_space.shape, dtype=np.float32))


def measure(config: str, overrides: tuple[str, ...], steps: int) -> dict:
    """Train ``config`` with ``overrides`` for ``steps`` env steps (rounded up to whole
    rollouts) and return a CSV row: the settings, the rate and the seconds per phase."""
    from fluidsim_envs.rl import train as T
    from fluidsim_envs.rl.config import load_config, resolved

    cfg = resolved(load_config(config, [*overrides]))
    # null: torch's default, as a fresh process has it (an earlier measurement set others)
    threads = T.set_torch_threads(cfg.torch_threads or TORCH_DEFAULT_THREADS)
    planned = T.planned_timesteps(cfg, steps)
    with tempfile.TemporaryDirectory(prefix="bench_training_") as tmp:
        run_dir = Path(tmp)
        venv, eval_env, model = T._build(cfg, run_dir, None, cfg.seed, 0.0)
        warm_up(venv, eval_env)
        callbacks = T._callbacks(cfg, run_dir, venv, eval_env, lambda line: None, resumed=False)
        load_start = os.getloadavg()[0]
        with timers(venv) as s:
            t0 = time.perf_counter()
            model.learn(total_timesteps=planned, callback=callbacks, progress_bar=False)
            wall = time.perf_counter() - t0
        from fluidsim_envs.rl.callbacks import Evaluations

        evaluations = next((c for c in callbacks if isinstance(c, Evaluations)), None)
        if evaluations is not None and not len(evaluations.log.timesteps):
            # a budget shorter than eval.freq: one evaluation timed now, counted as the share
            # of one that these steps bring in a real run (one per eval.freq steps)
            t0 = time.perf_counter()
            evaluations._episodes()
            s["eval"] = (time.perf_counter() - t0) * model.num_timesteps / evaluations.period
            s["rollout"] += s["eval"]
            wall += s["eval"]
        load_end = os.getloadavg()[0]
        venv.close()
        if eval_env is not None:
            eval_env.close()
    a = cfg.algorithm
    phases = {
        "env": s["env"],
        "forward": s["forward"],
        "bookkeeping": s["rollout"] - s["env"] - s["forward"] - s["eval"] - s["checkpoint"],
        "update": s["update"],
        "eval": s["eval"],
        "checkpoint": s["checkpoint"],
        "other": wall - s["rollout"] - s["update"],
    }
    return {
        "config": config,
        "overrides": " ".join(overrides),
        "n_envs": cfg.n_envs,
        "n_steps": a.n_steps,
        "batch_size": a.batch_size,
        "n_epochs": a.n_epochs,
        "torch_threads": threads,
        "numba_threads": numba.get_num_threads(),
        "env_steps": int(model.num_timesteps),
        "wall_s": round(wall, 3),
        "env_steps_per_s": round(model.num_timesteps / wall, 1),
        **{f"{p}_s": round(v, 3) for p, v in phases.items()},
        "load_start": round(load_start, 2),
        "load_end": round(load_end, 2),
    }


def interleaved(subjects: dict[tuple[str, str], tuple[str, ...]], steps: int, repeats: int):
    """Every subject ``(config, variant) -> overrides`` measured once per round, in turn (the
    order reversed every other round); each subject's fastest round."""
    best: dict[tuple[str, str], dict] = {}
    keys = list(subjects)
    for r in range(repeats):
        for key in keys if r % 2 == 0 else keys[::-1]:
            row = {**measure(key[0], subjects[key], steps), "variant": key[1]}
            print(_line(row), flush=True)
            if key not in best or row["wall_s"] < best[key]["wall_s"]:
                best[key] = row
    return [best[k] for k in keys]


def _line(r: dict) -> str:
    split = " ".join(f"{p} {float(r[f'{p}_s']):6.1f}" for p in PHASES)
    return (
        f"{r['config']:<20} {r['variant']:<32} {float(r['env_steps_per_s']):>9,.0f} env-steps/s  "
        f"torch {r['torch_threads']}  {split}  (s; load {r['load_start']})"
    )


# ---- the table and the chart -----------------------------------------------------------------


def markdown(path: Path = CSV) -> str:
    """docs/bench_training.csv as a table: per config and variant, the settings, the rate and
    each phase's share of the wall time."""
    if not path.is_file():
        return "(no docs/bench_training.csv yet: run python -m benchmarks.bench_training)"
    comments, rows = read_csv(path)
    lines = [
        "| config | variant | n_envs x n_steps | batch | epochs | torch threads | env-steps/s | "
        + " | ".join(PHASES)
        + " |",
        "|---|---|---:|---:|---:|---:|---:|" + "---:|" * len(PHASES),
    ]
    for r in rows:
        wall = float(r["wall_s"])
        shares = " | ".join(f"{100 * float(r[f'{p}_s']) / wall:.0f}%" for p in PHASES)
        lines.append(
            f"| {r['config']} | {r['variant']} | {r['n_envs']} x {r['n_steps']} | "
            f"{r['batch_size']} | {r['n_epochs']} | {r['torch_threads']} | "
            f"{float(r['env_steps_per_s']):,.0f} | {shares} |"
        )
    rate = {(r["config"], r["variant"]): float(r["env_steps_per_s"]) for r in rows}
    gains = [
        f"{c} {rate[(c, 'after')] / rate[(c, 'before')]:.1f}x"
        for c in dict.fromkeys(r["config"] for r in rows)
        if (c, "before") in rate and (c, "after") in rate
    ]
    lines += ["", f"- After over before, env-steps/s: {', '.join(gains)}."]
    for r in rows:
        if r["variant"] == "after":
            wall = float(r["wall_s"])
            top = sorted(PHASES, key=lambda p: -float(r[f"{p}_s"]))[:3]
            shares = ", ".join(f"{p} {100 * float(r[f'{p}_s']) / wall:.0f}%" for p in top)
            lines.append(f"- After, {r['config']} spends the most in: {shares}.")
    lines += _provenance(comments)
    return "\n".join(lines)


def _provenance(comments: list[str]) -> list[str]:
    """The command, machine, load and revision lines of a CSV, as a Markdown paragraph."""
    command = next((c[len("command: ") :] for c in comments if c.startswith("command: ")), "")
    machine = next((c[len("cpu: ") :] for c in comments if c.startswith("cpu: ")), "")
    load = [c.split(": ", 1)[1].split(", ")[0] for c in comments if c.startswith("load average")]
    git = next((c for c in comments if c.startswith("git ")), "")
    revision = f"; {git[:14]}" + (" (dirty)" if "dirty" in git else "") if git else ""
    merged = [
        f" The rows of {c[len('rows of ') : -len(' from:')]} come from `{nxt.strip()[9:]}`."
        for c, nxt in zip(comments, comments[1:], strict=False)
        if c.startswith("rows of ") and nxt.strip().startswith("command: ")
    ]
    return [
        "",
        f"`{command}`; {machine}, load average (1 min) {' then '.join(load)}{revision}."
        + "".join(merged),
    ]


def grid_markdown(path: Path = GRID_CSV) -> str:
    """docs/bench_training_grid.csv as a table: each setting tried, its rate against the
    grid's ``before`` row, and the seconds of each phase."""
    if not path.is_file():
        return (
            "(no docs/bench_training_grid.csv yet: run python -m benchmarks.bench_training --grid)"
        )
    comments, rows = read_csv(path)
    base = {r["config"]: float(r["env_steps_per_s"]) for r in rows if r["variant"] == "before"}
    lines = [
        "| config | setting (on top of before) | env-steps/s | against before | "
        + " | ".join(f"{p} (s)" for p in PHASES[:4])
        + " |",
        "|---|---|---:|---:|" + "---:|" * 4,
    ]
    for r in rows:
        rate = float(r["env_steps_per_s"])
        ratio = f"{rate / base[r['config']]:.2f}x" if r["config"] in base else ""
        secs = " | ".join(f"{float(r[f'{p}_s']):.1f}" for p in PHASES[:4])
        lines.append(f"| {r['config']} | {r['variant']} | {rate:,.0f} | {ratio} | {secs} |")
    return "\n".join([*lines, *_provenance(comments)])


def plot(path: Path = CSV, png: Path | None = None) -> Path:
    """Stacked bars: seconds per million env steps in each phase, before and after, per
    config."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    _, rows = read_csv(path)
    png = png or path.with_suffix(".png")
    fig, ax = plt.subplots(figsize=(8, 4.2), dpi=100)
    colors = dict(zip(PHASES, plt.get_cmap("tab10").colors, strict=False))
    labels, top = [], 0.0
    for i, r in enumerate(rows):
        per_m = 1e6 / float(r["env_steps"])
        bottom = 0.0
        for p in PHASES:
            h = float(r[f"{p}_s"]) * per_m
            ax.bar(i, h, bottom=bottom, color=colors[p], label=p if i == 0 else None)
            bottom += h
        top = max(top, bottom)
        ax.text(i, bottom, f"{float(r['env_steps_per_s']) / 1e3:.1f}k/s", ha="center",
                va="bottom", fontsize=8)  # fmt: skip
        labels.append(f"{r['config'].removesuffix('_ppo')}\n{r['variant']}")
    ax.set_xticks(range(len(rows)), labels, fontsize=7)
    ax.set_ylabel("seconds per million env steps")
    ax.set_title("PPO's wall time by phase, before and after, measured in turn (2 shared cores)")
    ax.set_ylim(0, 1.3 * top)
    ax.legend(fontsize=7, ncol=len(PHASES), loc="upper center")
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)
    return png


# ---- main ------------------------------------------------------------------------------------


def main(argv: list[str] | None = None) -> int:
    parser = arguments(__doc__, "the dart alone, two rollouts each (< 1 min)", "bench_training.csv")
    parser.add_argument("--steps", type=int, default=500_000, help="env steps per measurement")
    parser.add_argument("--repeats", type=int, default=2, help="rounds (each row: its best)")
    parser.add_argument("--configs", nargs="+", default=list(CONFIGS), choices=CONFIGS)
    parser.add_argument("--grid", action="store_true", help=f"the grid into {GRID_CSV.name}")
    parser.add_argument("--variants", nargs="+", choices=list(GRID), help="--grid: only these")
    parser.add_argument("--md-only", action="store_true", help="table and chart from the CSV")
    parser.add_argument(
        "--merge",
        action="store_true",
        help="keep the CSV's rows of the configs not measured now (and their # lines)",
    )
    args = parser.parse_args(argv)
    if args.md_only:
        print(markdown(args.out))
        print(f"written: {plot(args.out)}")
        return 0
    import torch

    global TORCH_DEFAULT_THREADS
    TORCH_DEFAULT_THREADS = torch.get_num_threads()
    steps, repeats, configs = args.steps, args.repeats, args.configs
    if args.quick:
        steps, repeats, configs = 2 * 16_384, 1, ["paper_airplane_ppo"]
    machine = describe()
    if args.grid:
        subjects = {
            (c, label): (*BEFORE, *GRID[label])
            for c in configs
            for label in (args.variants or GRID)
        }
    else:
        subjects = {}
        for c in configs:
            subjects[(c, "before")] = BEFORE
            subjects[(c, "after")] = ()
    rows = interleaved(subjects, steps, repeats)
    out = args.out
    if args.grid and out == CSV:
        out = GRID_CSV
    if args.quick and out in (CSV, GRID_CSV):
        out = DOCS.parent / "build" / out.name
    from fluidsim_envs.rl.train import git_revision

    git = git_revision()
    notes = [
        f"git {git['revision']}" + (" (dirty)" if git["dirty"] else ""),
        f"each row: the fastest of {repeats} rounds of {steps:,} env steps (whole rollouts), "
        "subjects in turn; seconds per phase (see benchmarks/bench_training.py)",
        f"before: {' '.join(BEFORE)}",
    ]
    comments = [*machine, load_average(), *notes]
    if args.merge and out.is_file():  # the rows of the other configs, and where they came from
        kept_comments, kept = read_csv(out)
        rows = [r for r in kept if r["config"] not in configs] + rows
        order = {c: i for i, c in enumerate(CONFIGS)}
        rows.sort(key=lambda r: order[r["config"]])
        comments += [f"rows of {', '.join(sorted({r['config'] for r in kept} - set(configs)))}"
                     " from:", *(f"  {c}" for c in kept_comments)]  # fmt: skip
    write_csv(out, COLUMNS, ([r[c] for c in COLUMNS] for r in rows), comments)
    print(f"written: {out}")
    if not args.grid:
        print(markdown(out))
        print(f"written: {plot(out, out.with_suffix('.png'))}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
