"""Tune a scene's scripted pilot: Optuna's TPE over the gains its pilot module declares.

For each env: the pilot module (the module of the registry's pilot factory,
``SCENES[id].pilot``) names its gains dataclass ``GAINS`` (defaults: the hand-set gains) and
``SEARCH_SPACE`` (``{gain: (low, high)}``; ``fluidsim_envs/scenes/gains.py`` says what else a
tunable pilot module defines). Each trial flies the pilot with
``dataclasses.replace(GAINS(), **params)`` for one episode in each of ``--episodes`` sub-envs
per tuning seed (``reset(seed=s, options={"stream": "tuning"})`` for each ``s`` of
``--seed-base``, default ``fluidsim_envs.evaluation.TUNING_SEEDS``: the tuning stream, whose
episodes no evaluation flies at any seed, ``fluidsim_envs.seeding``; the v0 gains on record
were tuned on the evaluation stream of seeds 1 and 2, before the streams, apart from the
evaluation's seed ``EVAL_SEED``). Each env version is tuned on its own episodes (a v1 env at
its default level, ``standard``) and keeps its own gains. The
objective is the mean episode return over all of them: the RL objective, which PPO and the
planner maximize too; success is recorded beside it. Trial 0 is the hand-set gains
(``study.enqueue_trial``), so the best found is never worse than them on the tuning episodes.
The sampler is seeded (``--sampler-seed``) and the episodes are too, so a run repeats exactly.

With ``--write``: the best gains and how they were found go to ``tuned_gains.json`` (v0) or
``tuned_gains_v1.json`` (v1) beside the pilot (what ``GAINS.for_env`` and the registry's pilot
read; ``--gains-dir`` puts it elsewhere),
and each env tuned gets a row in ``docs/tune_pilots.csv`` (``--out``): hand-set against tuned
return and success on the tuning episodes, the trials, the seconds and the command. Without
it, nothing is written.

    python -m benchmarks.tune_pilots fluidsim/SubmarineWake-v0 --trials 200 --write
    python -m benchmarks.tune_pilots all --trials 200 --write  # every v0 with a SEARCH_SPACE
    python -m benchmarks.tune_pilots all-v1 --trials 200 --write  # every v1
    python -m benchmarks.tune_pilots BoatOnStep-v0 --trials 5 --episodes 16  # a look
"""

from __future__ import annotations

import argparse
import dataclasses
import inspect
import os
import platform
import shlex
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from benchmarks.common import DOCS, ROOT, command, load_average, read_csv, write_csv
from fluidsim_envs.evaluation import EVAL_SEED, TUNING_SEEDS, check_tuning_seeds, first_episodes
from fluidsim_envs.rl.extras import require
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes.gains import check_search_space, tuned_file, tuned_path, write_tuned

STREAM = "tuning"  # the seed stream of the tuning episodes (fluidsim_envs.seeding)

COLUMNS = (
    "env_id",
    "tuning_seeds",
    "tuning_stream",
    "episodes",
    "trials",
    "best_trial",
    "hand_return",
    "tuned_return",
    "hand_success",
    "tuned_success",
    "seconds",
    "command",
)
#: what a tunable pilot module defines (fluidsim_envs/scenes/gains.py)
NEEDS = ("GAINS", "SEARCH_SPACE", "make_pilot", "make_hand_pilot")


def env_id_of(name: str) -> str:
    """The registry's id for ``name`` (``fluidsim/`` may be left off)."""
    for env_id in (name, f"fluidsim/{name}"):
        if env_id in SCENES:
            return env_id
    raise ValueError(f"no scene {name!r}: one of {sorted(SCENES)}, 'all' or 'all-v1'")


def missing(module: ModuleType) -> list[str]:
    """What ``module`` lacks of a tunable pilot module (:data:`NEEDS`, a ``gains`` argument
    of ``make_pilot``, ``GAINS.tuned``)."""
    out = [name for name in NEEDS if not hasattr(module, name)]
    make = getattr(module, "make_pilot", None)
    if make is not None and "gains" not in inspect.signature(make).parameters:
        out.append("make_pilot(venv, gains=None)")
    if hasattr(module, "GAINS") and not hasattr(module.GAINS, "tuned"):
        out.append("GAINS.tuned (a subclass of fluidsim_envs.scenes.gains.TunableGains)")
    return out


def pilot_module(env_id: str) -> ModuleType:
    """The module of ``env_id``'s pilot factory, after checking that it can be tuned."""
    module = sys.modules[SCENES[env_id].pilot.__module__]
    if lacks := missing(module):
        raise ValueError(
            f"{env_id}: {module.__name__} cannot be tuned: it lacks {', '.join(lacks)} "
            "(fluidsim_envs/scenes/gains.py says what a tunable pilot module defines)"
        )
    return module


def tunable_ids(show: bool = True, version: int = 0) -> list[str]:
    """The registry's envs of ``version`` whose pilot modules can be tuned (what ``all`` and
    ``all-v1`` tune); the others are printed with what they lack, unless ``show`` is false."""
    out = []
    for env_id, scene in SCENES.items():
        if scene.version != version:
            continue
        module = sys.modules[scene.pilot.__module__]
        if lacks := missing(module):
            if show:
                print(f"{env_id}: skipped ({module.__name__} lacks {', '.join(lacks)})")
        else:
            out.append(env_id)
    return out


def git_revision() -> str:
    """``HEAD``'s hash, `` (dirty)`` after it when the tree has uncommitted changes."""
    try:
        rev = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True,
                             text=True, timeout=10)  # fmt: skip
        status = subprocess.run(["git", "status", "--porcelain"], cwd=ROOT, capture_output=True,
                                text=True, timeout=10)  # fmt: skip
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    if rev.returncode != 0:
        return "unknown"
    return rev.stdout.strip() + (" (dirty)" if status.stdout.strip() else "")


class Episodes:
    """The tuning episodes of one env: a vector env of ``episodes`` sub-envs per seed, each
    flown from ``reset(seed=s)`` in the tuning stream (the same episodes for every gains
    scored)."""

    def __init__(self, env_id: str, seeds: Sequence[int], episodes: int) -> None:
        self.scene = SCENES[env_id]
        self.seeds = tuple(seeds)
        self.venvs = [self.scene.vector_cls(num_envs=episodes) for _ in self.seeds]

    def score(self, gains) -> tuple[float, float]:
        """Mean return and success rate of the pilot with ``gains`` over every episode."""
        returns, success = [], []
        for venv, seed in zip(self.venvs, self.seeds, strict=True):
            r = first_episodes(venv, self.scene.pilot(venv, gains), seed=seed, stream=STREAM)
            returns.append(r["return"])
            success.append(r["success"])
        return float(np.mean(np.concatenate(returns))), float(np.mean(np.concatenate(success)))

    def close(self) -> None:
        for venv in self.venvs:
            venv.close()


def tune(
    env_id: str,
    trials: int,
    episodes: int,
    seeds: Sequence[int],
    sampler_seed: int = 0,
    log: Callable[[str], object] = lambda line: print(line, flush=True),
) -> dict[str, Any]:
    """Search the gains of ``env_id``'s pilot (``trials`` trials, trial 0 the hand-set gains)
    on ``episodes`` episodes from each of ``seeds``; the result: the best gains, the hand-set
    and best objective values and success rates, and the study's settings."""
    import optuna

    seeds = check_tuning_seeds(seeds)
    if trials < 1 or episodes < 1:
        raise ValueError(f"trials and episodes must be at least 1, got {trials} and {episodes}")
    module = pilot_module(env_id)
    hand = module.GAINS()
    space = dict(module.SEARCH_SPACE)
    check_search_space(hand, space)

    optuna.logging.set_verbosity(optuna.logging.WARNING)  # the progress lines below instead
    study = optuna.create_study(
        direction="maximize",
        sampler=optuna.samplers.TPESampler(seed=sampler_seed),
        study_name=env_id,
    )
    study.enqueue_trial({key: getattr(hand, key) for key in space})
    runs = Episodes(env_id, seeds, episodes)
    t_start = time.perf_counter()

    def objective(trial) -> float:
        params = {key: trial.suggest_float(key, low, high) for key, (low, high) in space.items()}
        value, success = runs.score(dataclasses.replace(hand, **params))
        trial.set_user_attr("success", success)
        return value

    def progress(study, trial) -> None:
        best = study.best_trial
        log(
            f"{env_id} trial {trial.number:3d}/{trials}: return {trial.value:9.3f}, success "
            f"{trial.user_attrs['success']:6.1%} | best {best.value:9.3f} (trial "
            f"{best.number}, success {best.user_attrs['success']:.1%}) "
            f"{time.perf_counter() - t_start:6.0f} s"
        )

    log(
        f"{env_id}: {trials} trials of {episodes} episodes x seeds {list(seeds)}, "
        f"{len(space)} gains of {type(hand).__name__} ({module.__name__})"
    )
    try:
        study.optimize(objective, n_trials=trials, callbacks=[progress])
    finally:
        runs.close()
    first, best = study.trials[0], study.best_trial
    return {
        "env_id": env_id,
        "gains": dataclasses.replace(hand, **best.params),
        "hand_gains": hand,
        "search_space": {key: list(bounds) for key, bounds in space.items()},
        "tuning_seeds": list(seeds),
        "tuning_stream": STREAM,
        "episodes_per_seed": episodes,
        "episodes": episodes * len(seeds),
        "trials": trials,
        "best_trial": best.number,
        "sampler": f"optuna TPESampler(seed={sampler_seed})",
        "objective": "mean episode return over the tuning episodes",
        "objective_value": best.value,
        "success": best.user_attrs["success"],
        "hand_objective_value": first.value,
        "hand_success": first.user_attrs["success"],
        "seconds": time.perf_counter() - t_start,
        "optuna_version": optuna.__version__,
    }


def write(result: dict[str, Any], gains_dir: Path | None, cmd: str) -> Path:
    """The tuned gains' file of ``result``'s env version (``gains.tuned_file``): beside the
    pilot, or in ``gains_dir/<scene>/``."""
    gains, version = result["gains"], SCENES[result["env_id"]].version
    path = tuned_path(type(gains), version)
    if gains_dir is not None:
        path = gains_dir / path.parent.name / tuned_file(version)
    provenance = {"env_id": result["env_id"], "command": cmd, "git_revision": git_revision()}
    skip = ("gains", "hand_gains", "seconds", *provenance)
    provenance.update((k, v) for k, v in result.items() if k not in skip)
    return write_tuned(path, gains, **provenance)


def csv_row(result: dict[str, Any], cmd: str) -> tuple:
    return (
        result["env_id"],
        " ".join(map(str, result["tuning_seeds"])),
        result["tuning_stream"],
        result["episodes"],
        result["trials"],
        result["best_trial"],
        result["hand_objective_value"],
        result["objective_value"],
        result["hand_success"],
        result["success"],
        round(result["seconds"]),
        cmd,
    )


def write_table(path: Path, rows: list[tuple]) -> Path:
    """``rows`` into the CSV at ``path``, replacing the rows of the same envs it holds (an env
    tuned alone keeps the others' rows), in the registry's order."""
    kept = []
    if path.is_file():
        new = {row[0] for row in rows}
        # rows from before the streams were split were tuned on the evaluation stream
        old = ({"tuning_stream": "evaluation", **r} for r in read_csv(path)[1])
        kept = [tuple(r[c] for c in COLUMNS) for r in old if r["env_id"] not in new]
    notes = [
        "one row per env, each from the command in its command column; return and success "
        "on the tuning episodes (the tuning stream, or before it the evaluation stream of "
        "other seeds than the evaluation's)",
        f"{platform.machine()}, os.cpu_count: {os.cpu_count()}, python {platform.python_version()}",
        load_average(),
    ]
    fmt = lambda x: f"{x:.6g}" if isinstance(x, float) else x  # noqa: E731
    order = list(SCENES)  # the registry's order
    table = sorted([tuple(map(fmt, r)) for r in rows] + kept, key=lambda r: order.index(r[0]))
    return write_csv(path, COLUMNS, table, notes)


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "env", help="env id (fluidsim/ may be left off), 'all' (every v0) or 'all-v1'"
    )
    parser.add_argument("--trials", type=int, default=200, help="trials (default %(default)s)")
    parser.add_argument(
        "--episodes", type=int, default=128, help="episodes per tuning seed (default %(default)s)"
    )
    parser.add_argument(
        "--seed-base", type=int, nargs="+", default=list(TUNING_SEEDS), metavar="S",
        help=f"the tuning seeds: reset(seed=S) for each (default {list(TUNING_SEEDS)}; never "
        f"the evaluation's {EVAL_SEED})",
    )  # fmt: skip
    parser.add_argument("--sampler-seed", type=int, default=0, help="TPE's seed (default 0)")
    parser.add_argument(
        "--write", action="store_true", help="write tuned_gains.json and the CSV row"
    )
    parser.add_argument(
        "--gains-dir", type=Path, default=None,
        help="write tuned_gains.json into DIR/<scene>/ (default: beside the pilot)",
    )  # fmt: skip
    parser.add_argument(
        "--out", type=Path, default=DOCS / "tune_pilots.csv", help="CSV (default %(default)s)"
    )
    args = parser.parse_args(argv)
    cmd = command() if argv is None else f"python -m benchmarks.tune_pilots {shlex.join(argv)}"
    try:
        require("tune", "benchmarks/tune_pilots.py")
        check_tuning_seeds(args.seed_base)
        every = {"all": 0, "all-v1": 1}
        env_ids = (
            tunable_ids(version=every[args.env]) if args.env in every else [env_id_of(args.env)]
        )
        for env_id in env_ids:
            pilot_module(env_id)
    except (ImportError, ValueError) as e:
        parser.error(str(e))
    print(load_average("start"), flush=True)
    rows = []
    for env_id in env_ids:
        result = tune(env_id, args.trials, args.episodes, args.seed_base, args.sampler_seed)
        hand, gains = result["hand_gains"], result["gains"]
        print(
            f"{env_id}: return {result['hand_objective_value']:.3f} -> "
            f"{result['objective_value']:.3f}, success {result['hand_success']:.1%} -> "
            f"{result['success']:.1%} (best trial {result['best_trial']}, "
            f"{result['seconds']:.0f} s)"
        )
        for key in result["search_space"]:
            print(f"    {key:>20} {getattr(hand, key):9.4g} -> {getattr(gains, key):9.4g}")
        if args.write:
            print(f"wrote {write(result, args.gains_dir, cmd)}")
        rows.append(csv_row(result, cmd))
    if args.write and rows:
        print(f"wrote {write_table(args.out, rows)}")


if __name__ == "__main__":
    main()
