"""The zoo: the best trained policy of each env and algorithm, small enough for git, with the
evaluation that the README shows.

    python -m benchmarks.zoo                 # from benchmarks.results' runs: copy, evaluate, GIFs
    python -m benchmarks.zoo --check         # re-evaluate each entry: it must equal its row

For each config of :data:`benchmarks.results.CONFIGS`, the run with the best mean return on
the results' episodes (``results_eval.npz``, written by ``python -m benchmarks.results``) is
copied to ``zoo/<Env-vN>-<algo>/``: ``config.yaml``, ``model.zip``, ``vecnormalize.pkl`` and
``run.yaml`` (how it was trained: command, revision, seeds, versions). Then ``fluidsim-evaluate
zoo/<name> --episodes 256 --seed 3 --no-planner`` writes its ``evaluation.csv`` (the trained
policy beside the tuned and hand-set pilots and random, on the same episodes: fresh ones,
not the seed-0 episodes the run was chosen on), whose trained row the README's zoo table
will show, and ``python -m fluidsim_envs.enjoy`` draws its GIF,
``docs/zoo_<Env-vN>-<algo>.gif``.

``--check`` runs the same evaluation again into a temporary folder and compares it with the
committed ``evaluation.csv`` row by row, number by number (same machine kind: the kernels and
torch compute the same bits).
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from benchmarks.common import DOCS, ROOT, read_csv
from benchmarks.results import CONFIGS, runs

#: the zoo's evaluation episodes: not the results' (seed 0), on which its runs were ranked,
#: so the published row is not the best of five on its own episodes
EVAL_SEED = 3  # and not the pilots' tuning seeds (1, 2: evaluation.TUNING_SEEDS)

ZOO = ROOT / "zoo"
FILES = ("config.yaml", "model.zip", "vecnormalize.pkl", "run.yaml")
EPISODES = 256
MAX_BYTES = 2 * 1024 * 1024
GIF = {"stride": 2, "width": 320}  # every other frame, 320 px wide: a few hundred kB


def entry_name(config: str) -> str:
    """``PaperAirplane-v1-ppo``: the env's name and version, and the algorithm."""
    return f"{CONFIGS[config].split('/')[1]}-{config.rsplit('_', 1)[1]}"


def best_run(config: str) -> Path | None:
    """The config's run with the best mean return on the results' episodes."""
    scored = []
    for run in runs(config):
        cache = run / "results_eval.npz"
        if cache.is_file():
            with np.load(cache) as data:
                scored.append((float(np.mean(data["return"])), run))
    return max(scored)[1] if scored else None


def evaluate(folder: Path, out: Path) -> None:
    cmd = [sys.executable, "-m", "fluidsim_envs.rl.evaluate", str(folder), "--episodes"]
    cmd += [str(EPISODES), "--seed", str(EVAL_SEED), "--no-planner", "--out", str(out)]
    subprocess.run(cmd, check=True, cwd=ROOT, stdout=subprocess.DEVNULL)


def publish(config: str) -> None:
    run = best_run(config)
    if run is None:
        print(f"{config}: no evaluated runs (python -m benchmarks.results first)")
        return
    folder = ZOO / entry_name(config)
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    for name in FILES:
        shutil.copy2(run / name, folder / name)
    size = sum(p.stat().st_size for p in folder.iterdir())
    if size > MAX_BYTES:
        raise SystemExit(f"{folder}: {size / 2**20:.1f} MiB, over the zoo's 2 MiB")
    evaluate(folder, folder)
    gif = DOCS / f"zoo_{folder.name}.gif"
    cmd = [sys.executable, "-m", "fluidsim_envs.enjoy", str(folder), "--seed", str(EVAL_SEED)]
    cmd += ["--video", str(gif), "--stride", str(GIF["stride"]), "--width", str(GIF["width"])]
    subprocess.run(cmd, check=True, cwd=ROOT)
    print(f"{folder.name}: from {run.relative_to(ROOT)}, {size / 1024:.0f} KiB; {gif.name}")


def check(folder: Path) -> list[str]:
    """The entry's evaluation run again: the rows that differ (none: it reproduces)."""
    with tempfile.TemporaryDirectory() as tmp:
        evaluate(folder, Path(tmp))
        _, again = read_csv(Path(tmp) / "evaluation.csv")
    _, kept = read_csv(folder / "evaluation.csv")
    return [f"{a['policy']}: {a} != {k}" for a, k in zip(again, kept, strict=True) if a != k]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--configs", nargs="+", choices=list(CONFIGS), default=list(CONFIGS))
    parser.add_argument("--check", action="store_true", help="re-evaluate the entries")
    args = parser.parse_args(argv)
    if args.check:
        bad = [
            line for f in sorted(ZOO.glob("*")) if (f / "model.zip").is_file() for line in check(f)
        ]
        print("\n".join(bad) or "every zoo entry reproduces its evaluation.csv")
        return 1 if bad else 0
    for config in args.configs:
        publish(config)
    return 0


if __name__ == "__main__":
    sys.exit(main())
