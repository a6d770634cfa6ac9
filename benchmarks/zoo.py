"""The zoo: the best trained policy of each env and algorithm, small enough for git, with the
evaluation that the README shows.

    python -m benchmarks.zoo                 # from benchmarks.results' runs: copy, evaluate, GIFs
    python -m benchmarks.zoo --check         # re-evaluate each entry: it must equal its row
    python -m benchmarks.zoo --gifs          # draw the entries' GIFs again
    python -m benchmarks.zoo --evaluate      # evaluate the entries again (a baseline changed)

For each config of :data:`benchmarks.results.CONFIGS`, the run with the best mean return on
the results' episodes (``docs/results_episodes.csv``, written by ``python -m
benchmarks.results``: the runs of every session; the run must be on this machine) is
copied to ``zoo/<Env-vN>-<algo>/``: ``config.yaml``, ``model.safetensors`` (the policy's
weights alone: :func:`save_policy`), ``vecnormalize.safetensors`` and ``run.yaml`` (how it
was trained: command, revision, seeds, versions); nothing in them runs as code when loaded.
Then ``fluidsim-evaluate zoo/<name> --episodes 256 --seed 3 --no-planner`` writes its
``evaluation.csv`` (the trained policy beside the tuned and hand-set pilots and random, on
the same episodes: fresh ones, not the seed-0 episodes the run was chosen on), whose trained
row the README's zoo table will show, and ``python -m fluidsim_envs.enjoy`` draws its GIF,
``docs/zoo_<Env-vN>-<algo>.gif``.

``--check`` runs the same evaluation again into a temporary folder and compares it with the
committed ``evaluation.csv``: on the CPU it was evaluated on (its ``# cpu:`` line: the
kernels' target) row by row, number by number (the kernels and torch compute the same bits);
on another, each policy's mean return and success rate to within what a CPU's rounding moves
them (:data:`OTHER_CPU_RETURN_REL`, :data:`OTHER_CPU_SUCCESS_EPISODES`).
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import yaml

from benchmarks.common import DOCS, ROOT, read_csv
from benchmarks.results import (
    CONFIGS,
    EPISODES_CSV,
    config_digest,
    local_runs,
    policy_name,
    published_rows,
)
from fluidsim_envs import threads
from fluidsim_envs.physics.jit import target_cpu
from fluidsim_envs.rl import saved
from fluidsim_envs.rl.runs import MODEL, STATS

#: the zoo's evaluation episodes: not the results' (seed 0), on which its runs were ranked,
#: so the published row is not the best of five on its own episodes
EVAL_SEED = 3  # and not the pilots' tuning seeds (1, 2: evaluation.TUNING_SEEDS)

ZOO = ROOT / "zoo"
FILES = ("config.yaml", MODEL, STATS, "run.yaml")
EPISODES = 256
MAX_BYTES = 2 * 1024 * 1024
#: each env's GIF: (every Nth frame, times real time), 320 px wide, a few dozen frames (25
#: to 50 kB each: the UUV's wake particles hardly compress): the dart's short glide at half
#: its frames in real time; the 60 s episodes of the UUV (10 Hz) and the boat (20 Hz) as 6 s
#: time-lapses at 5 frames a second
GIF_WIDTH = 320
GIF = {"PaperAirplane": (2, 1.0), "SubmarineWake": (20, 10.0), "BoatOnStep": (40, 10.0)}
#: how near an entry's evaluation comes again on a CPU other than its own: each policy's
#: mean return within this fraction, its success rate within this many episodes. Measured
#: between a rocketlake (AVX-512) and the CPU the PPO entries were first evaluated on, over
#: their 256 episodes: 3.2e-4 on the boat's trained return (the last bits carried as far as
#: one gate missed or not), under 1e-6 on the dart and the UUV; no success changed. The
#: boat's entry of today (seed 4, znver4) on a rocketlake: 2.2e-3 and one episode's success
#: (one run of gates flown otherwise), at the commit before and after issue 46's changes alike.
OTHER_CPU_RETURN_REL = 5e-3
OTHER_CPU_SUCCESS_EPISODES = 2


def entry_name(config: str) -> str:
    """``PaperAirplane-v1-ppo``: the env's name and version, and the algorithm."""
    return f"{CONFIGS[config].split('/')[1]}-{config.rsplit('_', 1)[1]}"


def best_seed(config: str) -> int | None:
    """The seed of the config's run with the best mean return on the results' episodes
    (docs/results_episodes.csv: the runs of every session)."""
    env, policy = CONFIGS[config].split("/")[1], policy_name(config)
    returns: dict[str, list[float]] = {}
    for r in published_rows(EPISODES_CSV):
        if r["env"] == env and r["policy"] == policy:
            returns.setdefault(r["run"], []).append(float(r["return"]))
    if not returns:
        return None
    best = max(returns, key=lambda run: np.mean(returns[run]))
    return int(best.removeprefix("seed "))


def entry_seed(folder: Path) -> int | None:
    """The training seed of the zoo entry in ``folder`` (None: no entry)."""
    path = folder / "config.yaml"
    if not (folder / MODEL).is_file() or not path.is_file():
        return None
    return int(yaml.safe_load(path.read_text())["seed"])


def holds(folder: Path, config: str, seed: int) -> bool:
    """Whether the entry holds the run of ``seed`` trained with ``config`` as it is now."""
    if entry_seed(folder) != seed:
        return False
    return config_digest(folder / "config.yaml") == config_digest(config)


def save_policy(run: Path, path: Path) -> None:
    """The run's final model without its optimizers' state (Adam's moments: as large again
    as the networks, needed to train on, not to act; SAC's would pass the 2 MiB)."""
    saved.copy_policy(run / MODEL, path)


def evaluate(folder: Path, out: Path) -> None:
    cmd = [sys.executable, "-m", "fluidsim_envs.rl.evaluate", str(folder), "--episodes"]
    cmd += [str(EPISODES), "--seed", str(EVAL_SEED), "--no-planner", "--out", str(out)]
    subprocess.run(cmd, check=True, cwd=ROOT, stdout=subprocess.DEVNULL)


def publish(config: str) -> None:
    """Copy the config's best run into the zoo, evaluate it and draw its GIF; an entry that
    already holds that run is left as it is."""
    seed = best_seed(config)
    folder = ZOO / entry_name(config)
    if seed is None:
        print(f"{config}: no published runs (python -m benchmarks.results --train first)")
        return
    if holds(folder, config, seed):
        print(f"{folder.name}: holds the best run (seed {seed}) already")
        return
    run = local_runs(config).get(seed)
    if run is None:
        print(f"{config}: the best run (seed {seed}) is not on this machine (trained in "
              f"another session); the zoo keeps seed {entry_seed(folder)}")  # fmt: skip
        return
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    for name in FILES:
        if name != MODEL:
            shutil.copy2(run / name, folder / name)
    save_policy(run, folder / MODEL)
    size = sum(p.stat().st_size for p in folder.iterdir())
    if size > MAX_BYTES:
        raise SystemExit(f"{folder}: {size / 2**20:.1f} MiB, over the zoo's 2 MiB")
    evaluate(folder, folder)
    gif = draw_gif(folder)
    print(f"{folder.name}: seed {seed} from {run.relative_to(ROOT)}, {size / 1024:.0f} KiB; "
          f"{gif.name} {gif.stat().st_size / 1024:.0f} KiB")  # fmt: skip


def draw_gif(folder: Path) -> Path:
    """docs/zoo_<entry>.gif: the entry's policy on one episode (seed :data:`EVAL_SEED`), a
    frame every :data:`GIF` stride (a GIF of every step of a minute's episode runs to
    megabytes); and docs/zoo_<entry>.mp4, the same episode at every control step in real
    time (the docs site plays it)."""
    gif = DOCS / f"zoo_{folder.name}.gif"
    cmd = [sys.executable, "-m", "fluidsim_envs.enjoy", str(folder), "--seed", str(EVAL_SEED)]
    cmd += ["--width", str(GIF_WIDTH)]
    stride, speed = GIF[folder.name.split("-")[0]]
    subprocess.run(
        [*cmd, "--video", str(gif), "--stride", str(stride), "--speed", str(speed)],
        check=True,
        cwd=ROOT,
    )
    subprocess.run([*cmd, "--video", str(gif.with_suffix(".mp4"))], check=True, cwd=ROOT)
    return gif


def check(folder: Path) -> list[str]:
    """The entry's evaluation run again: what differs from its evaluation.csv (nothing: it
    reproduces), by :func:`compare`."""
    with tempfile.TemporaryDirectory() as tmp:
        evaluate(folder, Path(tmp))
        _, again = read_csv(Path(tmp) / "evaluation.csv")
    comments, kept = read_csv(folder / "evaluation.csv")
    return compare(kept, again, evaluated_on(comments), target_cpu())


def evaluated_on(comments: list[str]) -> str | None:
    """The CPU an evaluation.csv's numbers were computed on (its ``# cpu:`` line; None: a
    table from before it said)."""
    return next((c.split()[1] for c in comments if c.startswith("cpu:")), None)


def compare(kept: list[dict], again: list[dict], kept_cpu: str | None, cpu: str) -> list[str]:
    """The rows of ``again`` (evaluated on ``cpu``) that differ from ``kept`` (on
    ``kept_cpu``): on the same CPU any number; on another, a mean return by more than
    :data:`OTHER_CPU_RETURN_REL` or a success rate by more than
    :data:`OTHER_CPU_SUCCESS_EPISODES` episodes."""
    if [a["policy"] for a in again] != [k["policy"] for k in kept]:
        return [f"policies {[a['policy'] for a in again]} != {[k['policy'] for k in kept]}"]
    if kept_cpu == cpu:
        return [f"{a['policy']}: {a} != {k}" for a, k in zip(again, kept, strict=True) if a != k]
    bad = []
    for a, k in zip(again, kept, strict=True):
        ret, ret_kept = float(a["return_mean"]), float(k["return_mean"])
        moved = abs(float(a["success_rate"]) - float(k["success_rate"])) * int(k["episodes"])
        if abs(ret - ret_kept) > OTHER_CPU_RETURN_REL * abs(ret_kept) or (
            round(moved) > OTHER_CPU_SUCCESS_EPISODES
        ):
            bad.append(
                f"{a['policy']} on {cpu} (evaluated on {kept_cpu or 'an unnamed CPU'}): "
                f"return {ret:.6g} vs {ret_kept:.6g}, success {a['success_rate']} vs "
                f"{k['success_rate']} of {k['episodes']} episodes"
            )
    return bad


def markdown() -> str:
    """The README's zoo table from each entry's evaluation.csv: the trained policy and the
    best of its scripted pilots (the highest mean return: the bar, as in the results) on the
    same episodes, each mean with its 95% interval."""
    entries = sorted(f for f in ZOO.glob("*") if (f / "evaluation.csv").is_file())
    if not entries:
        return "(no zoo entries yet: `python -m benchmarks.zoo`)\n"
    lines = [
        "| entry | trained return | trained success | best pilot | its return | its success "
        "| random return |",
        "|---|---|---|---|---|---|---|",
    ]
    for folder in entries:
        rows = read_csv(folder / "evaluation.csv")[1]
        by = {r["policy"]: r for r in rows}
        trained = next(r for r in rows if r["policy"].startswith("trained"))
        pilots = [r for r in rows if r["policy"].endswith("pilot")]
        pilot = max(pilots, key=lambda r: float(r["return_mean"]))
        cells = [_interval(trained, "return_mean", False), _interval(trained, "success_rate", True)]
        cells += [pilot["policy"], _interval(pilot, "return_mean", False)]
        cells += [_interval(pilot, "success_rate", True)]
        lines.append(
            f"| [`zoo/{folder.name}`](zoo/{folder.name}) (training seed {entry_seed(folder)}) | "
            + " | ".join(cells)
            + f" | {float(by['random']['return_mean']):.1f} |"
        )
    return "\n".join(lines) + "\n"


def gifs_markdown() -> str:
    """The README's pictures: each zoo entry's GIF (docs/zoo_<entry>.gif), in a row."""
    gifs = [ZOO.parent / "docs" / f"zoo_{f.name}.gif" for f in sorted(ZOO.glob("*"))]
    cells = [
        f'<img src="docs/{g.name}" width="{GIF_WIDTH}" alt="{g.stem[4:]}, flown by its zoo policy">'
        for g in gifs
        if g.is_file()
    ]
    if not cells:
        return "(no zoo GIFs yet: `python -m benchmarks.zoo`)\n"
    return "<p>\n" + "\n".join(cells) + "\n</p>\n"


def _interval(row: dict, key: str, percent: bool) -> str:
    scale, form, unit = (100.0, ".0f", "%") if percent else (1.0, ".1f", "")
    mean, lo, hi = (scale * float(row[key + t]) for t in ("", "_lo", "_hi"))
    return f"{mean:{form}}{unit} [{lo:{form}}, {hi:{form}}]"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--configs", nargs="+", choices=list(CONFIGS), default=list(CONFIGS))
    parser.add_argument("--check", action="store_true", help="re-evaluate the entries")
    parser.add_argument("--gifs", action="store_true", help="draw the entries' GIFs again")
    parser.add_argument(
        "--evaluate",
        action="store_true",
        help="write the entries' evaluation.csv again (after a change to a baseline: a pilot's "
        "gains, the env), the entries kept as they are",
    )
    args = parser.parse_args(argv)
    threads.apply(threads.choose())  # the one owner's counts, as the CLIs run on
    if args.gifs:
        for config in args.configs:
            folder = ZOO / entry_name(config)
            if (folder / MODEL).is_file():
                print(f"{draw_gif(folder).name} drawn")
        return 0
    if args.evaluate:
        for config in args.configs:
            folder = ZOO / entry_name(config)
            if (folder / MODEL).is_file():
                evaluate(folder, folder)
                print(f"{folder.name}: evaluated again")
        return 0
    if args.check:
        bad = [line for f in sorted(ZOO.glob("*")) if (f / MODEL).is_file() for line in check(f)]
        print("\n".join(bad) or "every zoo entry reproduces its evaluation.csv")
        return 1 if bad else 0
    for config in args.configs:
        publish(config)
    return 0


if __name__ == "__main__":
    sys.exit(main())
