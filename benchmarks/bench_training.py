"""Where training's wall time goes, per shipped v1 config, before and after issue 43 (threads
with one owner, lean infos, the wall-clock retune), on a quiet machine and beside busy
processes; and the grid of settings an earlier retune (of the v0 configs) was chosen from.

Each measurement trains one config for ``--steps`` env steps (seed 0; SAC ``--sac-steps``,
learning from its 1,000th step on, not its config's 10,000th, so that its updates are in the
window) through the trainer's own building blocks (the envs, ``VecMonitor``, ``VecNormalize``,
the model, the evaluation and checkpoint callbacks, TensorBoard logging:
:mod:`fluidsim_envs.rl.train`) into a temporary run folder, on the threads
:mod:`fluidsim_envs.threads` chooses, with timers around SB3's methods (not a sampling
profiler):

================  ============================================================================
``env``           the training ``VecEnv``'s ``step_wait``: the native vector env, the SB3
                  adapter, ``VecMonitor`` and ``VecNormalize``
``forward``       the policy in the rollout (PPO: ``policy.forward`` under no_grad; SAC:
                  ``_sample_action``)
``bookkeeping``   the rest of ``collect_rollouts``: tensors from and to NumPy, action clipping,
                  the rollout or replay buffer's adds, value bootstraps of truncated episodes,
                  GAE, the callbacks' per-step calls
``update``        ``PPO.train`` / ``SAC.train``: the gradient steps
``eval``          the periodic evaluations (``Evaluations._on_step``, eval env and saves);
                  when the budget is shorter than ``eval.freq``, one evaluation timed after
                  training, times the budget over ``eval.freq`` (added to the wall time)
``checkpoint``    the periodic checkpoints (``Checkpoints._on_step``)
``other``         the rest of ``learn``: its set-up, the logger's dumps
================  ============================================================================

``before`` is each config as it shipped before issue 43 (:data:`BEFORE`: its settings then,
torch's own default of a thread per core, and the SB3 adapter handing SB3 every info entry of
every sub-env); ``after`` is the shipped config as it is. Each is measured quiet and beside
``--busy`` busy processes (a Python loop each, started before the measurement and stopped
after it: a browser, a second run). Each measurement runs in a process of its own (thread
pools start there as in a user's run), subjects in turn, round after round
(``--repeats``), so that a change of load on the machine hits them alike; each row is its
fastest round, with the load average at its start and end.

    python -m benchmarks.bench_training              # docs/bench_training.csv, .png
    python -m benchmarks.bench_training --quick      # the dart alone, quiet, 2 rollouts each
    python -m benchmarks.bench_training --grid       # the v0 grid: docs/bench_training_grid.csv
    python -m benchmarks.bench_training --md-only    # the table and chart from the CSV
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import os
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

from benchmarks.common import DOCS, ROOT, arguments, describe, load_average, read_csv, write_csv

CONFIGS = ("paper_airplane_v1_ppo", "submarine_wake_v1_ppo", "boat_on_step_v1_ppo",
           "paper_airplane_v1_sac")  # fmt: skip
#: what each config shipped with before issue 43, as ``--set`` overrides on the config as it
#: ships now (``torch_threads`` and the adapter's full infos are the ``before`` variant's own)
BEFORE: dict[str, tuple[str, ...]] = {
    "paper_airplane_v1_ppo": ("algorithm.n_epochs=10", "algorithm.learning_rate=3.0e-4"),
    "submarine_wake_v1_ppo": (),
    "boat_on_step_v1_ppo": (),
    "paper_airplane_v1_sac": (),
}
#: SAC's first update at this step in every measurement (its configs: 10,000)
SAC_LEARNING_STARTS = 1_000
#: the v0 configs and the settings they shipped with before their retune (issue 21): the
#: grid (``--grid``) and ``benchmarks.train_wallclock`` start from them
V0_CONFIGS = ("paper_airplane_ppo", "boat_on_step_ppo", "submarine_wake_ppo")
V0_BEFORE = (
    "n_envs=64",
    "algorithm.n_steps=256",
    "algorithm.batch_size=2048",
    "algorithm.n_epochs=10",
)
PHASES = ("env", "forward", "bookkeeping", "update", "eval", "checkpoint", "other")
COLUMNS = (
    "config", "variant", "busy", "overrides", "n_envs", "n_steps", "batch_size", "n_epochs",
    "torch_threads", "numba_threads", "env_steps", "wall_s", "env_steps_per_s",
    *(f"{p}_s" for p in PHASES), "load_start", "load_end",
)  # fmt: skip
#: the grid (``--grid``): label -> overrides on top of V0_BEFORE, measured on each --configs
GRID = {
    "before": ("torch_threads=2",),
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
GRID_CSV = DOCS / "bench_training_grid.csv"


# ---- the timers ------------------------------------------------------------------------------


@contextlib.contextmanager
def timers(train_env):
    """Seconds per phase (inclusive: ``rollout`` holds env, forward, eval, checkpoint), from
    SB3's and our classes' methods wrapped for the duration: at class level, so that a model
    saved meanwhile pickles nothing of this. Only the training env's ``step_wait`` counts as
    ``env`` (the eval env is inside ``eval``)."""
    from stable_baselines3 import PPO, SAC
    from stable_baselines3.common.off_policy_algorithm import OffPolicyAlgorithm
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
    wrap(OffPolicyAlgorithm, "collect_rollouts", "rollout")
    wrap(PPO, "train", "update")
    wrap(SAC, "train", "update")
    wrap(ActorCriticPolicy, "forward", "forward")
    wrap(OffPolicyAlgorithm, "_sample_action", "forward")
    wrap(type(train_env), "step_wait", "env", only=train_env)
    wrap(Evaluations, "_on_step", "eval")
    wrap(Checkpoints, "_on_step", "checkpoint")
    try:
        yield seconds
    finally:
        for cls, name, original in reversed(patched):
            setattr(cls, name, original)


@contextlib.contextmanager
def busy_processes(n: int):
    """``n`` processes, each a Python loop that keeps a core busy, for the block."""
    procs = [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(n)]
    try:
        if procs:
            time.sleep(1.0)  # scheduled before the clock starts
        yield
    finally:
        for p in procs:
            p.kill()
            p.wait()


@contextlib.contextmanager
def old_threads(plan):
    """The threads before issue 43: torch's set (its default, a thread per core), numba's
    left alone, so that its pool starts only if a kernel runs in parallel (setting its count,
    as the owner does, starts it; beside torch's pool of two it is what collapses)."""
    import torch

    before = torch.get_num_threads()
    torch.set_num_threads(plan.torch)
    try:
        yield
    finally:
        torch.set_num_threads(before)


@contextlib.contextmanager
def full_infos(on: bool):
    """With ``on``, the SB3 adapter as it was before issue 43: every info entry of every
    sub-env handed to SB3 (``info_keys=None``), not only those training reads."""
    from fluidsim_envs.wrappers import sb3

    original = sb3.make_sb3_vec_env
    if on:
        sb3.make_sb3_vec_env = lambda *a, **k: original(*a, **{**k, "info_keys": None})
    try:
        yield
    finally:
        sb3.make_sb3_vec_env = original


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


@dataclasses.dataclass(frozen=True)
class Subject:
    """One measurement's settings: a config with ``--set`` overrides, ``old`` (torch's own
    thread default and the adapter's full infos, as before issue 43), beside ``busy``
    processes."""

    config: str
    variant: str
    overrides: tuple[str, ...] = ()
    old: bool = False
    busy: int = 0


def measure(subject: Subject, steps: int) -> dict:
    """Train ``subject`` for ``steps`` env steps (rounded up to whole rollouts) and return a
    CSV row: the settings, the rate and the seconds per phase."""
    from fluidsim_envs import threads
    from fluidsim_envs.rl import train as T
    from fluidsim_envs.rl.config import load_config, resolved

    overrides = list(subject.overrides)
    if subject.config.endswith("_sac"):
        overrides.append(f"algorithm.learning_starts={SAC_LEARNING_STARTS}")
    cfg = resolved(load_config(subject.config, overrides))
    plan = T._threads(cfg)
    if subject.old:  # torch's own default then, a thread per core, and numba's untouched
        plan = dataclasses.replace(plan, torch=plan.cores)
    planned = T.planned_timesteps(cfg, steps)
    with (
        tempfile.TemporaryDirectory(prefix="bench_training_") as tmp,
        old_threads(plan) if subject.old else threads.owned(plan),
        full_infos(subject.old),
    ):
        run_dir = Path(tmp)
        venv, eval_env, model = T._build(cfg, run_dir, None, cfg.seed, 0.0)
        warm_up(venv, eval_env)
        callbacks = T._callbacks(cfg, run_dir, venv, eval_env, lambda line: None, resumed=False)
        with busy_processes(subject.busy):
            load_start = os.getloadavg()[0]
            with timers(venv) as s:
                t0 = time.perf_counter()
                model.learn(total_timesteps=planned, callback=callbacks, progress_bar=False)
                wall = time.perf_counter() - t0
            from fluidsim_envs.rl.callbacks import Evaluations

            evaluations = next((c for c in callbacks if isinstance(c, Evaluations)), None)
            if evaluations is not None and not len(evaluations.log.timesteps):
                # a budget shorter than eval.freq: one evaluation timed now, counted as the
                # share of one that these steps bring in a real run (one per eval.freq steps)
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
        "config": subject.config,
        "variant": subject.variant,
        "busy": subject.busy,
        "overrides": " ".join(subject.overrides),
        "n_envs": cfg.n_envs,
        "n_steps": getattr(a, "n_steps", ""),
        "batch_size": a.batch_size,
        "n_epochs": getattr(a, "n_epochs", ""),
        "torch_threads": plan.torch,
        "numba_threads": plan.numba,
        "env_steps": int(model.num_timesteps),
        "wall_s": round(wall, 3),
        "env_steps_per_s": round(model.num_timesteps / wall, 1),
        **{f"{p}_s": round(v, 3) for p, v in phases.items()},
        "load_start": round(load_start, 2),
        "load_end": round(load_end, 2),
    }


def measure_apart(subject: Subject, steps: int) -> dict:
    """:func:`measure` in a process of its own, as a user's ``fluidsim-train`` runs: numba's
    and torch's thread pools start there only if the run starts them (this one's numba pool
    is started by :func:`describe`, and a pool left beside torch's changes what is measured)."""
    args = json.dumps({**dataclasses.asdict(subject), "steps": steps})
    done = subprocess.run(
        [sys.executable, "-m", "benchmarks.bench_training", "--child", args],
        capture_output=True, text=True, cwd=ROOT,
    )  # fmt: skip
    if done.returncode != 0:
        raise SystemExit(f"measuring {subject} failed:\n{done.stderr[-4000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def interleaved(subjects: list[Subject], steps: dict[str, int], repeats: int) -> list[dict]:
    """Every subject measured once per round, each in a process of its own, in turn (the
    order reversed every other round); each subject's fastest round. ``steps``: the budget
    per config."""
    best: dict[Subject, dict] = {}
    for r in range(repeats):
        for subject in subjects if r % 2 == 0 else subjects[::-1]:
            row = measure_apart(subject, steps[subject.config])
            print(_line(row), flush=True)
            if subject not in best or row["wall_s"] < best[subject]["wall_s"]:
                best[subject] = row
    return [best[s] for s in subjects]


def _line(r: dict) -> str:
    split = " ".join(f"{p} {float(r[f'{p}_s']):6.1f}" for p in PHASES)
    return (
        f"{r['config']:<22} {r['variant']:<8} busy {r['busy']} "
        f"{float(r['env_steps_per_s']):>9,.0f} env-steps/s  torch {r['torch_threads']}  "
        f"{split}  (s; load {r['load_start']})"
    )


# ---- the table and the chart -----------------------------------------------------------------


def markdown(path: Path = CSV) -> str:
    """docs/bench_training.csv as a table: per config, variant and load, the settings, the
    rate, what it kept of its quiet rate, and each phase's share of the wall time."""
    if not path.is_file():
        return "(no docs/bench_training.csv yet: run python -m benchmarks.bench_training)"
    comments, rows = read_csv(path)
    rate = {(r["config"], r["variant"], r["busy"]): float(r["env_steps_per_s"]) for r in rows}
    lines = [
        "| config | variant | beside busy processes | n_envs x n_steps, batch, epochs | "
        "torch threads | env-steps/s | of its quiet rate | " + " | ".join(PHASES) + " |",
        "|---|---|---:|---|---:|---:|---:|" + "---:|" * len(PHASES),
    ]
    for r in rows:
        wall = float(r["wall_s"])
        shares = " | ".join(f"{100 * float(r[f'{p}_s']) / wall:.0f}%" for p in PHASES)
        quiet = rate.get((r["config"], r["variant"], "0"))
        kept = f"{float(r['env_steps_per_s']) / quiet:.2f}" if quiet else ""
        shape = (
            f"{r['n_envs']} x {r['n_steps'] or 'n/a'}, {r['batch_size']}, {r['n_epochs'] or 'n/a'}"
        )
        lines.append(
            f"| {r['config']} | {r['variant']} | {r['busy']} | {shape} | {r['torch_threads']} | "
            f"{float(r['env_steps_per_s']):,.0f} | {kept} | {shares} |"
        )
    lines.append("")
    for config in dict.fromkeys(r["config"] for r in rows):
        said = []
        for busy in sorted({r["busy"] for r in rows if r["config"] == config}, key=int):
            after, before = rate.get((config, "after", busy)), rate.get((config, "before", busy))
            if after and before:
                where = "quiet" if busy == "0" else f"beside {busy} busy processes"
                said.append(f"{after / before:.1f}x {where}")
        if said:
            lines.append(f"- {config}, after over before: {', '.join(said)}.")
    for r in rows:
        if r["variant"] == "after" and r["busy"] == "0":
            wall = float(r["wall_s"])
            top = sorted(PHASES, key=lambda p: -float(r[f"{p}_s"]))[:3]
            shares = ", ".join(f"{p} {100 * float(r[f'{p}_s']) / wall:.0f}%" for p in top)
            lines.append(f"- After, quiet, {r['config']} spends the most in: {shares}.")
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
    """Stacked bars: seconds per million env steps in each phase, per config, variant and
    load, the rate above each bar."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    _, rows = read_csv(path)
    png = png or path.with_suffix(".png")
    fig, ax = plt.subplots(figsize=(10, 4.6), dpi=100)
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
                va="bottom", fontsize=7)  # fmt: skip
        load = "quiet" if r["busy"] == "0" else f"{r['busy']} busy"
        labels.append(f"{r['config'].removesuffix('_ppo')}\n{r['variant']}, {load}")
    ax.set_xticks(range(len(rows)), labels, fontsize=6, rotation=90)
    ax.set_ylabel("seconds per million env steps")
    ax.set_yscale("log")
    ax.set_title("Training's wall time by phase, before and after, quiet and beside busy processes")
    ax.set_ylim(top=3 * top)
    ax.legend(fontsize=7, ncol=len(PHASES), loc="upper center")
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(png)
    plt.close(fig)
    return png


# ---- main ------------------------------------------------------------------------------------


def main(argv: list[str] | None = None) -> int:
    parser = arguments(__doc__, "the dart alone, quiet, two rollouts each", "bench_training.csv")
    parser.add_argument("--steps", type=int, default=131_072, help="PPO env steps per measurement")
    parser.add_argument("--sac-steps", type=int, default=12_000, help="SAC env steps (likewise)")
    parser.add_argument("--repeats", type=int, default=2, help="rounds (each row: its best)")
    parser.add_argument(
        "--busy", type=int, nargs="+", default=[0, 2], help="busy processes beside each (0 2)"
    )
    parser.add_argument("--configs", nargs="+", default=None, choices=CONFIGS + V0_CONFIGS)
    parser.add_argument("--grid", action="store_true", help=f"the v0 grid into {GRID_CSV.name}")
    parser.add_argument("--variants", nargs="+", choices=list(GRID), help="--grid: only these")
    parser.add_argument("--md-only", action="store_true", help="table and chart from the CSV")
    parser.add_argument("--child", help=argparse.SUPPRESS)  # measure_apart's subject, as JSON
    parser.add_argument(
        "--merge",
        action="store_true",
        help="keep the CSV's rows of the configs not measured now (and their # lines)",
    )
    args = parser.parse_args(argv)
    if args.child:
        given = json.loads(args.child)
        steps = given.pop("steps")
        given["overrides"] = tuple(given["overrides"])
        print(json.dumps(measure(Subject(**given), steps)))
        return 0
    if args.md_only:
        print(markdown(args.out))
        print(f"written: {plot(args.out)}")
        return 0
    configs = args.configs or list(V0_CONFIGS if args.grid else CONFIGS)
    steps = {c: args.sac_steps if c.endswith("_sac") else args.steps for c in configs}
    repeats, busy = args.repeats, args.busy
    if args.quick:
        configs, repeats, busy = ["paper_airplane_v1_ppo"], 1, [0]
        steps = {configs[0]: 2 * 16_384}
    machine = describe()
    if args.grid:
        subjects = [
            Subject(c, label, (*V0_BEFORE, *GRID[label]))
            for c in configs
            for label in (args.variants or GRID)
        ]
    else:
        subjects = [
            Subject(c, variant, BEFORE[c] if old else (), old=old, busy=b)
            for c in configs
            for b in busy
            for variant, old in (("before", True), ("after", False))
        ]
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
        f"each row: the fastest of {repeats} rounds of {args.steps:,} env steps (SAC "
        f"{args.sac_steps:,}, learning from step {SAC_LEARNING_STARTS:,}; whole rollouts), "
        "subjects in turn; seconds per phase (see benchmarks/bench_training.py)",
        "before: each config's settings before issue 43 (BEFORE), torch on a thread per core, "
        "every info entry handed to SB3",
    ]
    comments = [*machine, load_average(), *notes]
    if args.merge and out.is_file():  # the rows of the other configs, and where they came from
        kept_comments, kept = read_csv(out)
        rows = [r for r in kept if r["config"] not in configs] + rows
        order = {c: i for i, c in enumerate(CONFIGS + V0_CONFIGS)}
        rows.sort(key=lambda r: order[r["config"]])
        comments += [f"rows of {', '.join(sorted({r['config'] for r in kept} - set(configs)))}"
                     " from:", *(f"  {c}" for c in kept_comments)]  # fmt: skip
    columns = COLUMNS if not args.grid else tuple(c for c in COLUMNS if c != "busy")
    write_csv(out, columns, ([r[c] for c in columns] for r in rows), comments)
    print(f"written: {out}")
    if not args.grid:
        print(markdown(out))
        print(f"written: {plot(out, out.with_suffix('.png'))}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
