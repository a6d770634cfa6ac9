"""Multi-seed results on the v1 envs at each difficulty level: each algorithm trained with
several seeds, every run and every baseline flown on the same seeded episodes, and the
statistics of
Agarwal et al. (2021, "Deep RL at the edge of the statistical precipice") by their library,
``rliable``: interquartile mean (IQM) and mean over runs with 95% stratified bootstrap
intervals, performance profiles, learning curves with bands.

    python -m benchmarks.results --train            # train the missing seeds, then the docs
    python -m benchmarks.results                    # the docs from the published runs
    python -m benchmarks.results --configs boat_on_step_v1_ppo --train --max-new 2

Training: the seeds ``seed .. seed + --seeds - 1`` of each shipped v1 config (its own
``seed`` first) that are neither published nor trained here yet, through the real CLI,
``fluidsim-sweep CONFIG --seeds N --set seed=FIRST --sweep-dir
sweeps/results/CONFIG/DIGEST-training-seedsFIRST-LAST`` (in a subprocess; DIGEST names the config's
values, :func:`config_digest`; a folder that holds a sweep is resumed). ``--max-new K``
trains at most K of them now: the whole set is hours of compute on 2 cores, and a session's
machine (and its ``sweeps/``) does not outlive it.

Evaluation: each run's final model, acting deterministically, and the baselines (the
planner, an oracle of the present that reads the true state but draws its own future noise;
the scripted pilots of :data:`PILOTS`, the best of which is the bar; random actions) on the
same
:data:`EPISODES` episodes, seed :data:`EVAL_SEED` (disjoint from the pilots' tuning seeds and
from the runs' evaluation seed). A run's per-episode results are cached in its folder
(``results_eval.npz``). The baselines are flown once, each on its own: later runs read
their episodes back from ``docs/results_episodes.csv`` (the boat's planner alone takes more
than an hour), ``--fresh-baselines`` flies them again, as a change to a scene's physics,
pilot or planner needs, and ``--no-planner`` leaves out a planner not yet flown (the page
lists it, with its command); ``sweeps/results/baselines/`` keeps each until it is committed.

What it writes, and what survives the run folders (committed, merged: the rows of the runs
found here replace those of the same config and seed, the others are kept, so the seeds of
several sessions add up):

- ``docs/results_episodes.csv``: a row per policy, run (``seed N``) and episode; the
  statistics are computed from it alone;
- ``docs/results_history.csv``: each run's evaluations during training (the curves);
- ``docs/results_runs.csv``: a row per run: the revision that trained it, its steps, wall
  time and peak resident memory, its final evaluation return;
- ``docs/results.csv``: a row per env and policy: IQM and mean of the runs' mean returns with
  their intervals, the success rate, and the normalized score (0 random, 1 the best pilot);
- ``docs/results_curves.png``, ``docs/results_profiles.png`` (:func:`profile`: runs
  resampled whole), and ``docs/results.md`` (:func:`page`, checked by ``benchmarks.report``),
  whose table the README shows.
"""

from __future__ import annotations

import argparse
import hashlib
import subprocess
import sys
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np
import yaml

from benchmarks.common import DOCS, ROOT, read_csv, write_csv
from fluidsim_envs import threads
from fluidsim_envs.rl.runs import MODEL, PICKLED, read_history

#: what is trained: the shipped v1 configs, and their envs
CONFIGS = {
    "paper_airplane_v1_ppo": "fluidsim/PaperAirplane-v1",
    "submarine_wake_v1_ppo": "fluidsim/SubmarineWake-v1",
    "boat_on_step_v1_ppo": "fluidsim/BoatOnStep-v1",
    "paper_airplane_v1_sac": "fluidsim/PaperAirplane-v1",
}
#: configs whose seeds wait for something first (the page says what)
WAITING: dict[str, str] = {}  # config: why its runs are not trained yet (the page says)
SWEEPS = ROOT / "sweeps" / "results"
EVAL_SEED = 0  # the pilots were tuned on TUNING_SEEDS (evaluation.py): disjoint
EPISODES = 256
SEEDS = 5
#: the scripted pilots: gains tuned on the env's version (v1), tuned on its v0, set by hand;
#: the best of them on an env (by mean return) is the bar a trained policy is held to
PILOTS = ("tuned pilot", "v0-tuned pilot", "hand-set pilot")
BASELINES = ("planner", *PILOTS, "random")
PLANNERS = ("planner",)  # --no-planner leaves it out where not yet flown
#: every policy flies each level's episodes; the planner, the slowest baseline by far (an
#: hour on the boat at one level), flies ``standard``'s, where a policy is held to it
LEVELS = ("easy", "standard", "hard")
PLANNER_LEVELS = ("standard",)
#: baselines' names as earlier versions of this file wrote them: the planner before issue 44
#: kept the episode's noise keys (it flew the episode's own future gusts and sensor noise) and
#: flew offsets to the v0-tuned pilot; a reference now, not flown again
CLAIRVOYANT = "planner (clairvoyant, before issue 44)"
LEGACY = {"planner (oracle)": CLAIRVOYANT, "planner (clairvoyant)": CLAIRVOYANT}
EPISODES_CSV = DOCS / "results_episodes.csv"
HISTORY_CSV = DOCS / "results_history.csv"
RUNS_CSV = DOCS / "results_runs.csv"
CSV = DOCS / "results.csv"
PAGE = DOCS / "results.md"
EPISODE_COLUMNS = ("env", "level", "policy", "run", "episode", "return", "success")
HISTORY_COLUMNS = ("config", "seed", "timesteps", "wall_s", "mean_return", "success_rate")
RUN_COLUMNS = (
    "config", "seed", "config_digest", "revision", "train_stream", "timesteps", "wall_s",
    "peak_rss_mb", "final_eval_return", "results_return", "folder",
)  # fmt: skip
#: the seed stream a run's training episodes came from (fluidsim_envs.seeding): runs trained
#: before the streams were split (no ``train_stream`` in run.yaml, nor in their row) drew
#: them from the evaluation stream of their seed, so seed 0 began on these results'
#: episodes and seed 3 on the zoo's
SHARED = "evaluation"
COLUMNS = (
    "env", "level", "policy", "runs", "episodes",
    "iqm", "iqm_lo", "iqm_hi", "mean", "mean_lo", "mean_hi",
    "success", "success_lo", "success_hi", "normalized_iqm", "normalized_iqm_lo",
    "normalized_iqm_hi", "worst", "worst_run", "below_best_pilot",
)  # fmt: skip
REPS = 20_000  # bootstrap resamples
PROFILE_REPS = 2000
BOOTSTRAP_SEED = 2024


# --------------------------------------------------------------------------------------------
# training (configs -> run folders)


def base_seed(config: str) -> int:
    from fluidsim_envs.rl.config import load_config

    return int(load_config(config).seed)


def wanted_seeds(config: str, seeds: int) -> list[int]:
    first = base_seed(config)
    return list(range(first, first + seeds))


def config_digest(config: str | Path, overrides: Sequence[str] = ()) -> str:
    """What a run trains, as 12 hex digits: the config (a shipped name, or a run's
    config.yaml) with ``overrides`` (``key=value``) resolved, every env parameter filled
    in, without its seed and thread counts (fluidsim_envs.threads': they change no
    hyperparameter). A shipped config that changes (a new race's values, an env's new
    default) no longer matches its published runs: they are dropped and trained again."""
    from fluidsim_envs.rl.config import config_to_dict, load_config, resolved

    plain = config_to_dict(resolved(load_config(config, overrides)))
    for key in ("seed", "torch_threads", "numba_threads"):
        plain.pop(key, None)
    if not plain.get("curriculum"):
        plain.pop("curriculum", None)  # no curriculum: the digest runs had before there was one
    if not plain.get("privileged_critic"):
        plain.pop("privileged_critic", None)  # the critic reads the policy's input: as before
    if not plain.get("levels"):
        plain.pop("levels", None)  # one level: as runs were before the option
    if plain.get("frame_stack") == 1:
        plain.pop("frame_stack")  # the present only: as runs were before the option
    if not plain.get("warm_start", {}).get("steps"):
        plain.pop("warm_start", None)  # no warm start: as runs were before the option
    elif plain["warm_start"].get("teacher") == "pilot":
        plain["warm_start"].pop("teacher")  # the pilot: as runs were before the planner could
    return hashlib.sha256(yaml.safe_dump(plain, sort_keys=True).encode()).hexdigest()[:12]


def published_runs(config: str, digest: str) -> list[dict]:
    """The config's rows of docs/results_runs.csv trained with the config as it is now, on
    the training stream."""
    return [
        r
        for r in run_table()
        if r["config"] == config
        and r.get("config_digest") == digest
        and r["train_stream"] == "training"
    ]


def episode_table() -> list[dict]:
    """docs/results_episodes.csv's rows, the baselines under their names of now
    (:data:`LEGACY`); rows written before the ``level`` column flew ``standard``."""
    return [
        {**r, "policy": LEGACY.get(r["policy"], r["policy"]), "level": r.get("level") or "standard"}
        for r in published_rows(EPISODES_CSV)
    ]


def run_table() -> list[dict]:
    """docs/results_runs.csv's rows, each with its ``train_stream`` (:data:`SHARED` for the
    rows written before the column was)."""
    return [
        {**r, "train_stream": r.get("train_stream") or SHARED} for r in published_rows(RUNS_CSV)
    ]


def train_stream(run: Path) -> str:
    """The seed stream run folder ``run`` trained on (its run.yaml; :data:`SHARED` before the
    streams were split)."""
    return yaml.safe_load((run / "run.yaml").read_text())["seeds"].get("train_stream", SHARED)


def missing_seeds(config: str, seeds: int) -> list[int]:
    """The wanted seeds neither published (docs/results_runs.csv, trained with the config as
    it is now, on the training stream: a run of the shared stream is trained again, and its
    row replaced) nor finished here."""
    have = {int(r["seed"]) for r in published_runs(config, config_digest(config))}
    have |= set(local_runs(config))
    return [s for s in wanted_seeds(config, seeds) if s not in have]


def chunks(seeds: Sequence[int]) -> list[list[int]]:
    """Consecutive runs of sorted seeds: each is one ``--seeds N --set seed=FIRST`` sweep."""
    out: list[list[int]] = []
    for s in sorted(seeds):
        if out and s == out[-1][-1] + 1:
            out[-1].append(s)
        else:
            out.append([s])
    return out


def train(config: str, seeds: list[int]) -> None:
    for chunk in chunks(seeds):
        folder = SWEEPS / config / f"{config_digest(config)}-training-seeds{chunk[0]}-{chunk[-1]}"
        if (folder / "sweep.yaml").is_file():
            cmd = ["--resume", str(folder)]
        else:
            cmd = [config, "--seeds", str(len(chunk)), "--set", f"seed={chunk[0]}"]
            cmd += ["--sweep-dir", str(folder)]
        cmd = [sys.executable, "-m", "fluidsim_envs.rl.sweep", *cmd]
        print("$", " ".join(cmd), flush=True)
        subprocess.run(cmd, check=True, cwd=ROOT)


_SAID: set[Path] = set()  # the runs left out, said once


def local_runs(config: str) -> dict[int, Path]:
    """The config's runs finished here (a final model) with the config as it is now, on the
    training stream, by seed."""
    digest, out = config_digest(config), {}
    for run in sorted((SWEEPS / config).glob("*/runs/*")):
        if (run / MODEL).is_file() or (run / PICKLED[MODEL]).is_file():
            why = None
            if not (run / MODEL).is_file():
                why = f"its model is an SB3 pickle (python -m fluidsim_envs.rl.convert {run} "
                why += "--allow-pickle, once)"
            elif config_digest(run / "config.yaml") != digest:
                why = f"trained with another {config}"
            elif train_stream(run) != "training":
                why = f"trained on the {train_stream(run)} stream"
            if why:
                if run not in _SAID:
                    _SAID.add(run)
                    print(f"{run}: {why}: left out")
                continue
            out[int(yaml.safe_load((run / "config.yaml").read_text())["seed"])] = run
    return out


def policy_name(config: str) -> str:
    return config.rsplit("_", 1)[1].upper()


def run_label(seed: int) -> str:
    return f"seed {seed}"


# --------------------------------------------------------------------------------------------
# evaluation (run folders -> per-episode results)


def run_episodes(
    run: Path, episodes: int, seed: int, level: str = "standard"
) -> dict[str, np.ndarray]:
    """The run's final model on ``episodes`` seeded episodes at ``level`` (cached in the run
    folder)."""
    where = "" if level == "standard" else f"_{level}"
    cache = run / f"results_eval{where}{'' if seed == EVAL_SEED else f'_seed{seed}'}.npz"
    if cache.is_file():
        with np.load(cache) as data:
            if int(data["episodes"]) == episodes and int(data["seed"]) == seed:
                return {"return": data["return"], "success": data["success"]}
    from fluidsim_envs.evaluation import first_episodes
    from fluidsim_envs.rl.evaluate import _make_venv, load_run, model_policy

    print(f"{run.relative_to(ROOT)}: its final model on {episodes} episodes at {level} ...",
          flush=True)  # fmt: skip
    cfg, model = load_run(run, "final")
    venv = _make_venv(cfg.env_id, episodes, at_level(cfg.env_kwargs, level))
    try:
        out = first_episodes(venv, model_policy(cfg, model, run, venv), seed=seed)
    finally:
        venv.close()
    np.savez(cache, episodes=episodes, seed=seed, **{k: out[k] for k in ("return", "success")})
    return {k: out[k] for k in ("return", "success")}


def at_level(env_kwargs: dict, level: str) -> dict:
    """A run's env parameters at difficulty ``level`` (a knob a run set stays set)."""
    return {**{k: v for k, v in env_kwargs.items() if k != "difficulty"}, "difficulty": level}


def published_baselines(env: str, level: str, episodes: int) -> dict[str, dict[str, np.ndarray]]:
    """The baselines' episodes on ``env`` at ``level`` as docs/results_episodes.csv holds
    them (flown on :data:`EVAL_SEED`, its header says): those with all ``episodes`` of them."""
    got: dict[str, list[dict]] = {b: [] for b in BASELINES}
    for row in episode_table():
        if (
            (row["env"], row["level"]) == (env, level)
            and row["policy"] in got
            and row["run"] == "-"
        ):
            got[row["policy"]].append(row)
    return {
        b: {
            "return": np.array([float(r["return"]) for r in rows]),
            "success": np.array([int(r["success"]) for r in rows]),
        }
        for b, rows in got.items()
        if len(rows) == episodes
    }


def baseline_episodes(
    env_id: str, level: str, episodes: int, seed: int, fresh: bool = False, planner: bool = True
) -> dict[str, dict[str, np.ndarray]]:
    """The baselines on the same episodes at ``level`` (the planner at
    :data:`PLANNER_LEVELS` only), each the published one
    (:func:`published_baselines`, at the results' own seed), else the one cached in
    sweeps/results/baselines/, else flown now; ``fresh``: each flown now. ``planner`` False:
    the planner is left out unless published or cached (on the boat it takes hours of the
    machine's two cores; the page lists what is left out: :func:`missing_markdown`)."""
    env = env_id.split("/")[1]
    published = published_baselines(env, level, episodes) if seed == EVAL_SEED and not fresh else {}
    out = {}
    for name in BASELINES:
        if name in PLANNERS and level not in PLANNER_LEVELS:
            continue
        # "planner-fair": not the name the clairvoyant planner's cache had before issue 44
        slug = "planner-fair" if name == "planner" else "_".join(name.split())
        place = env if level == "standard" else f"{env}-{level}"
        cache = SWEEPS / "baselines" / f"{place}-{episodes}-{seed}-{slug}.npz"
        if name in published:
            out[name] = published[name]
        elif cache.is_file() and not fresh:
            with np.load(cache) as data:
                out[name] = {k: data[k] for k in ("return", "success")}
        elif planner or name not in PLANNERS:
            out[name] = fly_baseline(env_id, level, name, episodes, seed)
            cache.parent.mkdir(parents=True, exist_ok=True)
            np.savez(cache, **out[name])
    return out


def pilot_gains(scene, version: int):
    """The gains ``scene``'s pilot was tuned to on env ``version`` (its module's ``GAINS``)."""
    return sys.modules[scene.pilot.__module__].GAINS.tuned(version=version)


def fly_baseline(
    env_id: str, level: str, name: str, episodes: int, seed: int
) -> dict[str, np.ndarray]:
    """One baseline's ``return`` and ``success`` on the seeded episodes at ``level``."""
    from fluidsim_envs.evaluation import first_episodes, random_policy
    from fluidsim_envs.rl.evaluate import _make_venv, find_scene

    scene = find_scene(env_id)
    make = {
        "planner": lambda venv: scene.planner(venv),
        "tuned pilot": lambda venv: scene.pilot(venv),
        "v0-tuned pilot": lambda venv: scene.pilot(venv, pilot_gains(scene, version=0)),
        "hand-set pilot": lambda venv: scene.hand_pilot(venv),
        "random": lambda venv: random_policy(venv, seed),
    }
    venv = _make_venv(env_id, episodes, {"difficulty": level})
    try:
        print(f"{env_id} at {level}: {name} on {episodes} episodes ...", flush=True)
        got = first_episodes(venv, make[name](venv), seed=seed)
    finally:
        venv.close()
    return {k: got[k] for k in ("return", "success")}


def unplanned(configs: list[str], drop: bool) -> list[tuple[str, str, str, str]]:
    """With ``drop`` (``--fresh-baselines --no-planner``), the planners' published episodes
    on ``configs``' envs, as keys to drop: the planner flies offsets to the tuned pilot, and
    its episodes are not kept beside a pilot flown afresh (the page lists them to fly)."""
    envs = dict.fromkeys(CONFIGS[c].split("/")[1] for c in configs)
    keys = [(e, level, name, "-") for e in envs for level in PLANNER_LEVELS for name in PLANNERS]
    return keys if drop else []


def episode_rows(
    configs: list[str], episodes: int, seed: int, fresh: bool, planner: bool = True
) -> list[tuple]:
    """The baselines' episodes on each config's env and its local runs' episodes, as
    :data:`EPISODE_COLUMNS` rows (``planner``: see :func:`baseline_episodes`)."""
    rows: list[tuple] = []
    for env_id in dict.fromkeys(CONFIGS[c] for c in configs):
        env = env_id.split("/")[1]
        for level in LEVELS:
            flown = baseline_episodes(env_id, level, episodes, seed, fresh, planner)
            for name, d in flown.items():
                rows += _rows(env, level, name, "-", d)
    for config in configs:
        env = CONFIGS[config].split("/")[1]
        for s, run in local_runs(config).items():
            for level in LEVELS:
                d = run_episodes(run, episodes, seed, level)
                rows += _rows(env, level, policy_name(config), run_label(s), d)
    return rows


def _rows(env: str, level: str, policy: str, run: str, d: dict[str, np.ndarray]) -> list[tuple]:
    return [
        (env, level, policy, run, i, round(float(r), 4), int(s))
        for i, (r, s) in enumerate(zip(d["return"], d["success"], strict=True))
    ]


def history_rows(configs: list[str]) -> list[tuple]:
    """Each local run's evaluations during training, as :data:`HISTORY_COLUMNS` rows."""
    return [
        (config, s, int(h["timesteps"]), round(h["wall_s"], 1), round(h["mean_return"], 4),
         round(h["success_rate"], 4))
        for config in configs
        for s, run in local_runs(config).items()
        for h in read_history(run)
    ]  # fmt: skip


def run_rows(configs: list[str], episodes: int, seed: int) -> list[tuple]:
    """A row per local run: :data:`RUN_COLUMNS` (wall time: the run's clock at its last
    evaluation, across resumes; peak RSS: the largest of its sessions')."""
    out = []
    for config in configs:
        for s, run in local_runs(config).items():
            meta = yaml.safe_load((run / "run.yaml").read_text())
            last = read_history(run)[-1]
            rss = [t["peak_rss_mb"] for t in meta.get("timing", []) if "peak_rss_mb" in t]
            git = meta["git"]
            out.append((
                config, s, config_digest(config),
                git["revision"][:10] + ("+dirty" if git["dirty"] else ""), train_stream(run),
                int(meta["num_timesteps"]), round(last["wall_s"], 1),
                round(max(rss), 1) if rss else "", round(last["mean_return"], 4),
                round(float(np.mean(run_episodes(run, episodes, seed)["return"])), 4),
                str(run.relative_to(ROOT)),
            ))  # fmt: skip
    return out


def stale_runs(configs: list[str]) -> list[tuple[str, int]]:
    """The published runs of ``configs`` trained with another version of their config."""
    current = {c: config_digest(c) for c in configs}
    stale = [
        (r["config"], int(r["seed"]))
        for r in run_table()
        if r["config"] in current and r.get("config_digest") != current[r["config"]]
    ]
    for config, seed in stale:
        print(f"{config} seed {seed}: published, but trained with another {config}: dropped")
    return stale


def merge(path: Path, columns: Sequence[str], new: Iterable[Sequence], key: Sequence[str],
          comments: Sequence[str] = (), drop: Iterable[tuple] = ()) -> list[dict]:  # fmt: skip
    """Write ``new`` rows to the committed CSV at ``path``, keeping its rows whose ``key``
    (columns) no new row has, the rows of runs trained in other sessions, unless ``drop``
    names that key (runs of a config that has changed since)."""
    fresh = [dict(zip(columns, map(str, r), strict=True)) for r in new]
    keys = {tuple(r[k] for k in key) for r in fresh} | {tuple(map(str, k)) for k in drop}
    old = {RUNS_CSV: run_table, EPISODES_CSV: episode_table}.get(
        path, lambda: published_rows(path)
    )()
    kept = [r for r in old if tuple(r[k] for k in key) not in keys]
    rows = kept + fresh
    write_csv(path, columns, ([r[c] for c in columns] for r in rows), comments)
    return rows


def published_rows(path: Path) -> list[dict]:
    """The rows of the committed CSV at ``path`` (none where it does not exist yet)."""
    return read_csv(path)[1] if path.is_file() else []


# --------------------------------------------------------------------------------------------
# statistics (per-episode CSV -> summary CSV)


def score_matrices(rows: list[dict]) -> dict[tuple[str, str, str], dict[str, np.ndarray]]:
    """(env, level, policy) -> ``return`` and ``success`` as [runs, episodes] arrays, and
    ``runs``, the runs' labels in that order."""
    grouped: dict[tuple[str, str, str], dict[str, dict[int, tuple[float, float]]]] = {}
    for r in rows:
        runs_ = grouped.setdefault((r["env"], r.get("level") or "standard", r["policy"]), {})
        runs_.setdefault(r["run"], {})[int(r["episode"])] = (
            float(r["return"]),
            float(r["success"]),
        )
    out = {}
    for key, by_run in grouped.items():
        names = sorted(by_run)
        n = len(by_run[names[0]])
        ret = np.array([[by_run[k][i][0] for i in range(n)] for k in names])
        suc = np.array([[by_run[k][i][1] for i in range(n)] for k in names])
        out[key] = {"return": ret, "success": suc, "runs": names}
    return out


def interval_estimates(scores: np.ndarray) -> dict[str, tuple[float, float, float]]:
    """IQM and mean over runs of the runs' mean scores (``scores``: [runs, episodes]), each
    with its 95% stratified bootstrap interval over runs (rliable). A single run (a
    baseline: one policy, no training seeds) has no spread over runs: its IQM and mean are
    its mean, with the bootstrap interval of that mean over its episodes."""
    from rliable import library as rly
    from rliable import metrics

    def aggregate(x):
        return np.array([metrics.aggregate_iqm(x), metrics.aggregate_mean(x)])

    # rliable's StratifiedBootstrap draws from NumPy's global generator (its random_state
    # does not reach the resampling): seeded here, the same scores give the same intervals
    np.random.seed(BOOTSTRAP_SEED)  # noqa: NPY002  (the generator rliable uses)
    if scores.shape[0] > 1:
        point, ci = rly.get_interval_estimates(
            {"p": scores.mean(axis=1, keepdims=True)}, aggregate, reps=REPS
        )
        iqm, mean = point["p"]
        return {
            "iqm": (float(iqm), float(ci["p"][0, 0]), float(ci["p"][1, 0])),
            "mean": (float(mean), float(ci["p"][0, 1]), float(ci["p"][1, 1])),
        }
    point, ci = rly.get_interval_estimates(
        {"p": scores.reshape(-1, 1)}, metrics.aggregate_mean, reps=REPS
    )
    lo, hi = np.ravel(ci["p"])
    value = (float(np.ravel(point["p"])[0]), float(lo), float(hi))
    return {"iqm": value, "mean": value}


def best_pilot(matrices: dict, env: str, level: str = "standard") -> str:
    """The pilot of :data:`PILOTS` with the highest mean return on ``env`` at ``level``."""
    flown = [p for p in PILOTS if (env, level, p) in matrices]
    return max(flown, key=lambda p: matrices[(env, level, p)]["return"].mean())


def summary_rows(matrices: dict) -> list[dict]:
    """A :data:`COLUMNS` row per (env, level, policy): the envs in :data:`CONFIGS`' order,
    in each the levels in :data:`LEVELS`' order, in each the planner, the pilots, the trained
    policies, random."""
    envs = [e.split("/")[1] for e in dict.fromkeys(CONFIGS.values())]
    rank = {"planner": 0, CLAIRVOYANT: 0.5, "random": 3}
    rank.update({name: 1 + k / len(PILOTS) for k, name in enumerate(PILOTS)})

    def order(key):
        env, level, policy = key
        where = envs.index(env) if env in envs else len(envs)
        return (where, env, LEVELS.index(level), rank.get(policy, 2), policy)

    out = []
    for (env, level, policy), m in sorted(matrices.items(), key=lambda kv: order(kv[0])):
        ret = interval_estimates(m["return"])
        suc = interval_estimates(m["success"])
        pilot = matrices[(env, level, best_pilot(matrices, env, level))]["return"].mean()
        rand = matrices[(env, level, "random")]["return"].mean()
        per_run = m["return"].mean(axis=1)  # each run's mean return
        below = [run for run, x in zip(m["runs"], per_run, strict=True) if x < pilot]
        norm = interval_estimates((m["return"] - rand) / (pilot - rand))
        out.append({
            "env": env, "level": level, "policy": policy, "runs": m["return"].shape[0],
            "episodes": m["return"].shape[1],
            "iqm": ret["iqm"][0], "iqm_lo": ret["iqm"][1], "iqm_hi": ret["iqm"][2],
            "mean": ret["mean"][0], "mean_lo": ret["mean"][1], "mean_hi": ret["mean"][2],
            "success": suc["mean"][0], "success_lo": suc["mean"][1], "success_hi": suc["mean"][2],
            "normalized_iqm": norm["iqm"][0], "normalized_iqm_lo": norm["iqm"][1],
            "normalized_iqm_hi": norm["iqm"][2],
            "worst": float(per_run.min()), "worst_run": m["runs"][int(per_run.argmin())],
            "below_best_pilot": "; ".join(below) if policy not in BASELINES else "",
        })  # fmt: skip
    return out


# --------------------------------------------------------------------------------------------
# figures


def profile(returns: np.ndarray, taus: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The fraction of episodes whose return exceeds each tau (``returns``: [runs,
    episodes]), runs pooled, and its 95% bootstrap band: whole runs resampled (a run's
    episodes share its policy); a single run (a baseline) resampled over its episodes."""
    rng = np.random.default_rng(BOOTSTRAP_SEED)
    frac = (returns[:, :, None] > taus).mean(axis=1)  # [runs, taus]
    runs_, episodes_ = returns.shape
    if runs_ > 1:
        boots = frac[rng.integers(0, runs_, (PROFILE_REPS, runs_))].mean(axis=1)
    else:
        picks = returns[0][rng.integers(0, episodes_, (PROFILE_REPS, episodes_))]
        boots = (picks[:, :, None] > taus).mean(axis=1)
    return frac.mean(axis=0), np.percentile(boots, [2.5, 97.5], axis=0)


def plot_profiles(matrices: dict, path: Path) -> None:
    """Per env at ``standard``: each policy's performance profile (:func:`profile`), with
    its band."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    envs = sorted({env for env, level, _ in matrices if level == "standard"})
    fig, axes = plt.subplots(1, len(envs), figsize=(5 * len(envs), 3.6), squeeze=False)
    for ax, env in zip(axes[0], envs, strict=True):
        mats = {
            p: m["return"] for (e, lv, p), m in matrices.items() if (e, lv) == (env, "standard")
        }
        lo = min(m.min() for m in mats.values())
        hi = max(m.max() for m in mats.values())
        taus = np.linspace(lo, hi, 101)
        for policy, returns in mats.items():
            curve, band = profile(returns, taus)
            ax.plot(taus, curve, label=policy)
            ax.fill_between(taus, band[0], band[1], alpha=0.2)
        _label(ax, env, "episode return τ", "fraction of episodes > τ")
    _save(fig, path)


def plot_curves(history: list[dict], matrices: dict, path: Path) -> None:
    """Per config: its runs' evaluations during training (docs/results_history.csv) as the
    IQM over runs at each timestep, with a 95% stratified bootstrap band (rliable); the
    planner's and the best pilot's mean return on the results' episodes as lines (the
    evaluations during training fly other episodes: seed 1,000,000, 32 of them)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from rliable import library as rly
    from rliable import metrics

    configs = [c for c in CONFIGS if any(h["config"] == c for h in history)]
    cols = min(len(configs), 2)
    rows = -(-len(configs) // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(5 * cols, 3.6 * rows), squeeze=False)
    for ax in axes.flat[len(configs) :]:
        ax.set_visible(False)
    for ax, config in zip(axes.flat, configs, strict=False):
        curves: dict[str, dict[int, float]] = {}
        for h in history:
            if h["config"] == config:
                curves.setdefault(h["seed"], {})[int(h["timesteps"])] = float(h["mean_return"])
        steps = sorted(set.intersection(*(set(c) for c in curves.values())))
        scores = np.array([[c[t] for t in steps] for c in curves.values()])  # [runs, points]
        np.random.seed(BOOTSTRAP_SEED)  # noqa: NPY002  (rliable resamples with it)
        point, ci = rly.get_interval_estimates(
            {"r": scores},
            lambda x: np.array([metrics.aggregate_iqm(x[:, [j]]) for j in range(x.shape[1])]),
            reps=2000,
        )
        ax.plot(steps, point["r"], label=f"IQM of {len(curves)} runs")
        ax.fill_between(steps, ci["r"][0], ci["r"][1], alpha=0.25)
        env = CONFIGS[config].split("/")[1]
        flown = any((env, "standard", p) in matrices for p in PILOTS)
        best = best_pilot(matrices, env) if flown else None
        for name, style in (("planner", ":"), (best, "--")):
            if (env, "standard", name) in matrices:
                mean = matrices[(env, "standard", name)]["return"].mean()
                ax.axhline(mean, color="gray", linestyle=style, label=name)
        title = f"{CONFIGS[config].split('/')[1]}, {policy_name(config)}"
        _label(ax, title, "timesteps", "evaluation return")
    _save(fig, path)


def _label(ax, title: str, xlabel: str, ylabel: str) -> None:
    ax.set_title(title)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)


def _save(fig, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


# --------------------------------------------------------------------------------------------
# the docs' table (benchmarks.report)


def markdown() -> str:
    """docs/results.csv as a table: each env's levels, at each its policies; a trained
    policy's mean return against the best pilot's there (their intervals apart or not, and
    every run under the pilot's mean named) and, where the planner flew, its share of the
    planner's mean."""
    if not CSV.is_file():
        return "(no docs/results.csv yet: `python -m benchmarks.results --train`)\n"
    _, rows = read_csv(CSV)
    lines = [
        "| env | level | policy | runs | IQM return [95% CI] | mean return [95% CI] | success "
        "| normalized IQM [95% CI] | worst run | vs best pilot | of planner |",
        "|---|---|---|--:|---|---|---|---|---|---|--:|",
    ]
    words = ("env", "level", "policy", "worst_run", "below_best_pilot")
    for r in rows:  # rows written before the level column flew standard
        r["level"] = r.get("level") or "standard"
    for r in rows:
        f = {k: float(v) for k, v in r.items() if k not in words}
        versus, worst, share = "", "", ""
        if r["policy"] not in BASELINES and r["policy"] not in LEGACY.values():
            here = [
                p for p in rows if (p["env"], p.get("level", "standard")) == (r["env"], r["level"])
            ]
            pilot = max((p for p in here if p["policy"] in PILOTS), key=lambda p: float(p["mean"]))
            below = f["mean_hi"] < float(pilot["mean_lo"])  # the intervals apart
            above = f["mean_lo"] > float(pilot["mean_hi"])
            versus = "**below**" if below else ("above" if above else "overlaps")
            worst = f"{f['worst']:.2f} ({r['worst_run']})"
            if r["below_best_pilot"]:  # each run whose mean return is under the bar, named
                versus += f"; under its mean: {r['below_best_pilot']}"
            planner = [p for p in here if p["policy"] == "planner"]
            if planner:
                share = f"{100 * f['mean'] / float(planner[0]['mean']):.0f}%"
        lines.append(
            f"| {r['env']} | {r['level']} | {r['policy']} | {int(f['runs'])} | "
            f"{_ci(f, 'iqm', '.2f')} | {_ci(f, 'mean', '.2f')} | "
            f"{100 * f['success']:.0f}% [{100 * f['success_lo']:.0f}, "
            f"{100 * f['success_hi']:.0f}] | {_ci(f, 'normalized_iqm', '.2f')} | {worst} "
            f"| {versus} | {share} |"
        )
    return "\n".join(lines) + "\n"


def _ci(f: dict[str, float], key: str, form: str) -> str:
    return f"{f[key]:{form}} [{f[key + '_lo']:{form}}, {f[key + '_hi']:{form}}]"


def runs_markdown() -> str:
    """docs/results_runs.csv as a table: a row per run."""
    if not RUNS_CSV.is_file():
        return "(no runs published yet)\n"
    lines = [
        "| config | seed | digest | revision | training episodes | steps | wall (min) "
        "| peak RSS (MiB) | last evaluation during training | return on these episodes |",
        "|---|--:|---|---|---|--:|--:|--:|--:|--:|",
    ]
    for r in run_table():
        lines.append(
            f"| {r['config']} | {r['seed']} | `{r['config_digest']}` | `{r['revision']}` | "
            f"{r['train_stream']} | "
            f"{int(r['timesteps']):,} | "
            f"{float(r['wall_s']) / 60:.1f} | {r['peak_rss_mb'] or 'n/a'} | "
            f"{float(r['final_eval_return']):.2f} | {float(r['results_return']):.2f} |"
        )
    return "\n".join(lines) + "\n"


def missing_markdown() -> str:
    """The baselines not yet published on an env that has results, and the configs with
    fewer than :data:`SEEDS` published runs, each with the command that adds them."""
    flown = {(r["env"], r["level"], r["policy"]) for r in episode_table() if r["run"] == "-"}
    lines = []
    for env_id in dict.fromkeys(CONFIGS.values()):
        env = env_id.split("/")[1]
        config = next(c for c, e in CONFIGS.items() if e == env_id)
        if not any(e == env for e, _, _ in flown):
            continue  # no results on this env yet: its configs' lines say so
        lines += [
            f"- {env} at {level}: the {name}'s episodes "
            f"(`python -m benchmarks.results --configs {config}`)"
            for level in LEVELS
            for name in BASELINES
            if (env, level, name) not in flown and (name not in PLANNERS or level in PLANNER_LEVELS)
        ]
    have, shared = dict.fromkeys(CONFIGS, 0), dict.fromkeys(CONFIGS, 0)
    for r in run_table():
        have[r["config"]] += 1
        shared[r["config"]] += r["train_stream"] == SHARED
    lines += [
        f"- `{c}`: {n - shared[c]} of {SEEDS} runs on the training stream"
        + (f", {shared[c]} on the evaluation stream to train again" if shared[c] else "")
        + (f" ({WAITING[c]})" if c in WAITING else
           f" (`python -m benchmarks.results --configs {c} --train`)")
        for c, n in have.items()
        if n - shared[c] < SEEDS
    ]  # fmt: skip
    return "\n".join(lines) + "\n" if lines else "None: every config has its runs.\n"


def shared_sentence() -> str:
    """What the page says of the runs trained before the streams were split."""
    n = sum(r["train_stream"] == SHARED for r in run_table())
    if not n:
        return "Every run here did."
    return (
        f"{n} of the runs here did not (`evaluation` in the runs table): they were trained "
        "before the streams were split, on the evaluation stream of their seed, so that the run "
        f"seeded {EVAL_SEED} began on the episodes these results fly, and the one seeded 3 on "
        "the zoo's. They stand until trained again (the list below)."
    )


def page() -> str:
    """docs/results.md, whole, from the CSVs (``benchmarks.report --check`` compares it)."""
    return f"""# Results: trained policies over seeds, against the baselines

<!-- written by `python -m benchmarks.results` from docs/results*.csv: do not edit -->

Each shipped v1 config (`configs/<config>.yaml`) is trained with seeds 0 to
{SEEDS - 1}. Each run's final model, acting deterministically, and the baselines fly the same
{EPISODES} episodes (seed {EVAL_SEED}) at each difficulty level ({", ".join(LEVELS)}): three
scripted pilots (the scene's classical controller with its gains tuned on this v1 env at
`standard`, `tuned pilot`, by `python -m benchmarks.tune_pilots` on the tuning stream of
seeds 1 and 2; with the gains tuned on its v0, `v0-tuned pilot`; with the hand-set gains),
random actions, and at {", ".join(PLANNER_LEVELS)} the planner (an oracle of the present: it
reads the true state and plans over the env's own model, but its rollouts draw the noise to
come of their own, and what the episode drew at its start for later (the dart's gust not yet
begun, the lead submarine's route ahead) drawn again; it is flown where a policy is held to
it, and takes an hour a level on the boat). Where the table still shows `{CLAIRVOYANT}`, it
is the planner the table had before issue 44: it flew the episode's own future gusts and
sensor noise, offsets to the v0-tuned pilot, a reference no policy could match. The runs' own
evaluations during training use seed 1,000,000 at the config's level; the zoo publishes on
seed 3. All of these are the evaluation stream of their seed (`reset(seed=s)`); a run draws
its training episodes from the training stream of its seed (`fluidsim_envs.seeding`), which
no evaluation flies.
{shared_sentence()}

A run's score is its mean return over the episodes. The table gives the interquartile mean
(IQM: the mean of the middle half of the runs, scipy's 25% trimmed mean) and the mean over
runs, each with its 95% stratified bootstrap interval over runs (the `rliable` library of
Agarwal et al., 2021, {REPS:,} resamples). A baseline is one policy: its interval is over its
episodes. The best pilot of an env is the pilot with the highest mean return there. The
normalized IQM puts random at 0 and the best pilot at 1, at each level. *vs best pilot* says
**below** where the trained mean's interval lies wholly under the best pilot's at that level,
*above* where wholly over it, and *overlaps* otherwise, then names every run whose mean
return is under the best
pilot's; *worst run* is the lowest mean return of the runs, and which run. *of planner* is
the mean return over runs as a share of the planner's, where it flew.

{markdown()}
Still to fly and to train (each line is the command that adds the missing episodes or seeds;
runs of several sessions add up, the CSVs keep each run's revision; `--no-planner` leaves out
a planner not yet flown, the slowest baseline by far: it plans each action over the env's
own model):

{missing_markdown()}
## Learning curves

The IQM over runs of each evaluation during training (32 episodes each), with its 95%
bootstrap band:

![learning curves](results_curves.png)

## Performance profiles

The fraction of the {EPISODES} episodes whose return exceeds each value τ, with a 95% band
from resampling whole runs (a run's episodes share its policy):

![performance profiles](results_profiles.png)

## The runs

{runs_markdown()}
Wall time is the run's own clock at its last evaluation, two runs at a time on a 2-core
machine (one core each; a run alone, or beside other work such as the baselines'
evaluation, ran slower or faster: these are not benchmarks); peak RSS is the training
process's (torch, SB3 and the env; a Ray worker's where `fluidsim-sweep` trained it). The
revision is the commit the run was trained at (`+dirty`: with uncommitted changes in the
working tree); the digest names the config it trained with (resolved, without its seed: a
changed config's runs are dropped and trained again). A seed trains the same policy again,
to the bit, on the same CPU (the kernels compile for it; `run.yaml` names it): on another,
the kernels and torch round their last bits differently and training carries that into
another policy. Data: `docs/results_episodes.csv` (every episode of every policy),
`docs/results_history.csv` (the curves), `docs/results_runs.csv`, `docs/results.csv`.
"""


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--configs", nargs="+", choices=list(CONFIGS), default=list(CONFIGS))
    parser.add_argument("--seeds", type=int, default=SEEDS, help=f"runs per config ({SEEDS})")
    parser.add_argument("--train", action="store_true", help="train the missing seeds first")
    parser.add_argument("--max-new", type=int, help="train at most this many seeds a config")
    parser.add_argument(
        "--fresh-baselines",
        action="store_true",
        help="fly the planner, pilots and random again (after a change to a scene's physics, "
        "pilot or planner), not read from docs/results_episodes.csv; with --no-planner, the "
        "planner's episodes are dropped, to fly later",
    )
    parser.add_argument(
        "--no-planner",
        dest="planner",
        action="store_false",
        help="leave out the planner where it is not yet published (on the boat: hours); the "
        "page lists it as still to fly",
    )
    args = parser.parse_args(argv)
    threads.apply(threads.choose())  # the one owner's counts, as the CLIs run on
    if args.seeds < 1 or (args.max_new is not None and args.max_new < 1):
        parser.error(f"--seeds {args.seeds} --max-new {args.max_new}: each must be at least 1")
    if args.train:
        for config in args.configs:
            train(config, missing_seeds(config, args.seeds)[: args.max_new])
    stale = stale_runs(args.configs)
    note = [f"episodes: {EPISODES}, seed {EVAL_SEED}; each run's final model, deterministic"]
    rows = merge(
        EPISODES_CSV,
        EPISODE_COLUMNS,
        episode_rows(args.configs, EPISODES, EVAL_SEED, args.fresh_baselines, args.planner),
        ("env", "level", "policy", "run"),
        note,
        [
            (CONFIGS[c].split("/")[1], level, policy_name(c), run_label(s))
            for c, s in stale
            for level in LEVELS
        ]  # fmt: skip
        + unplanned(args.configs, args.fresh_baselines and not args.planner),
    )
    history = merge(
        HISTORY_CSV, HISTORY_COLUMNS, history_rows(args.configs), ("config", "seed"), drop=stale
    )
    merge(RUNS_CSV, RUN_COLUMNS, run_rows(args.configs, EPISODES, EVAL_SEED),
          ("config", "seed"), drop=stale)  # fmt: skip
    matrices = score_matrices(rows)
    summary = summary_rows(matrices)
    write_csv(CSV, COLUMNS, ([r[c] for c in COLUMNS] for r in summary), note)
    plot_profiles(matrices, DOCS / "results_profiles.png")
    if history:
        plot_curves(history, matrices, DOCS / "results_curves.png")
    PAGE.write_text(page())
    print(markdown())
    return 0


if __name__ == "__main__":
    sys.exit(main())
