"""Multi-seed results on the v1 envs at ``standard``: each algorithm trained with several
seeds, every run and every baseline flown on the same seeded episodes, and the statistics of
Agarwal et al. (2021, "Deep RL at the edge of the statistical precipice") by their library,
``rliable``: interquartile mean (IQM) and mean over runs with 95% stratified bootstrap
intervals, performance profiles, learning curves with bands.

    python -m benchmarks.results --train            # train what is missing, then the docs
    python -m benchmarks.results                    # the docs from the runs as they are
    python -m benchmarks.results --configs paper_airplane_v1_ppo --seeds 5 --train

Training: ``fluidsim-sweep CONFIG --seeds N --sweep-dir sweeps/results/CONFIG [--set ...]``
for each shipped v1 config (a folder that holds a sweep is resumed; the real CLI, in a
subprocess). Evaluation: each run's final model, acting deterministically, and the
baselines (the planner, an oracle that reads the true state; the tuned pilot; random
actions) on the same ``--episodes`` episodes, seed :data:`EVAL_SEED` (disjoint from the
pilots' tuning seeds); each run's per-episode results are kept in its folder
(``results_eval.npz``), the baselines' in ``sweeps/results/baselines/``.

Writes ``docs/results_episodes.csv`` (a row per policy, run and episode: everything else is
computed from it) and ``docs/results.csv`` (a row per env and policy: IQM and mean of the
runs' mean returns with their intervals, the success rate, and the normalized score, 0 for
random and 1 for the tuned pilot), ``docs/results_curves.png`` and
``docs/results_profiles.png`` (:func:`profile`: runs resampled whole). :func:`markdown`
renders ``docs/results.csv`` as the table that docs/results.md and the README will show
once the runs exist (a ``benchmarks.report`` block, wired with the first results).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

import numpy as np

from benchmarks.common import DOCS, ROOT, read_csv, write_csv
from fluidsim_envs.rl.runs import read_history

#: what is trained: the shipped v1 configs, and their envs
CONFIGS = {
    "paper_airplane_v1_ppo": "fluidsim/PaperAirplane-v1",
    "submarine_wake_v1_ppo": "fluidsim/SubmarineWake-v1",
    "boat_on_step_v1_ppo": "fluidsim/BoatOnStep-v1",
    "paper_airplane_v1_sac": "fluidsim/PaperAirplane-v1",
}
SWEEPS = ROOT / "sweeps" / "results"
EVAL_SEED = 0  # the pilots were tuned on TUNING_SEEDS (evaluation.py): disjoint
EPISODES = 256
BASELINES = ("planner (oracle)", "tuned pilot", "random")
EPISODES_CSV = DOCS / "results_episodes.csv"
CSV = DOCS / "results.csv"
EPISODE_COLUMNS = ("env", "policy", "run", "episode", "return", "success")
COLUMNS = (
    "env", "policy", "runs", "episodes",
    "iqm", "iqm_lo", "iqm_hi", "mean", "mean_lo", "mean_hi",
    "success", "success_lo", "success_hi", "normalized_iqm", "normalized_iqm_lo",
    "normalized_iqm_hi",
)  # fmt: skip
REPS = 20_000  # bootstrap resamples
PROFILE_REPS = 2000
BOOTSTRAP_SEED = 2024


# --------------------------------------------------------------------------------------------
# training and evaluation (run folders -> per-episode results)


def train(config: str, seeds: int, sets: list[str]) -> None:
    folder = SWEEPS / config
    if (folder / "sweep.yaml").is_file():
        cmd = ["--resume", str(folder)]
    else:
        cmd = [config, "--seeds", str(seeds), "--sweep-dir", str(folder)]
        cmd += ["--set", *sets] if sets else []
    cmd = [sys.executable, "-m", "fluidsim_envs.rl.sweep", *cmd]
    print("$", " ".join(cmd), flush=True)
    subprocess.run(cmd, check=True, cwd=ROOT)


def runs(config: str) -> list[Path]:
    """The config's finished runs (a final model), by trial."""
    folder = SWEEPS / config / "runs"
    return sorted(p for p in folder.glob("*") if (p / "model.zip").is_file())


def policy_name(config: str) -> str:
    return config.rsplit("_", 1)[1].upper()


def run_episodes(run: Path, episodes: int, seed: int) -> dict[str, np.ndarray]:
    """The run's final model on ``episodes`` seeded episodes (cached in the run folder)."""
    cache = run / "results_eval.npz"
    if cache.is_file():
        with np.load(cache) as data:
            if int(data["episodes"]) == episodes and int(data["seed"]) == seed:
                return {"return": data["return"], "success": data["success"]}
    from fluidsim_envs.evaluation import first_episodes
    from fluidsim_envs.rl.evaluate import _make_venv, load_run, model_policy

    cfg, model = load_run(run, "final")
    venv = _make_venv(cfg.env_id, episodes, cfg.env_kwargs)
    try:
        out = first_episodes(venv, model_policy(cfg, model, run, venv), seed=seed)
    finally:
        venv.close()
    np.savez(cache, episodes=episodes, seed=seed, **{k: out[k] for k in ("return", "success")})
    return {k: out[k] for k in ("return", "success")}


def baseline_episodes(env_id: str, episodes: int, seed: int) -> dict[str, dict[str, np.ndarray]]:
    """The baselines on the same episodes (cached per env in sweeps/results/baselines/)."""
    cache = SWEEPS / "baselines" / f"{env_id.split('/')[1]}-{episodes}-{seed}.npz"
    if cache.is_file():
        with np.load(cache) as data:
            return {b: {k: data[f"{b}/{k}"] for k in ("return", "success")} for b in BASELINES}
    from fluidsim_envs.evaluation import first_episodes, random_policy
    from fluidsim_envs.rl.evaluate import _make_venv, find_scene

    scene = find_scene(env_id)
    make = {
        "planner (oracle)": lambda venv: scene.planner(venv),
        "tuned pilot": lambda venv: scene.pilot(venv),
        "random": lambda venv: random_policy(venv, seed),
    }
    out = {}
    for name in BASELINES:
        venv = _make_venv(env_id, episodes, {})
        try:
            print(f"{env_id}: {name} on {episodes} episodes ...", flush=True)
            got = first_episodes(venv, make[name](venv), seed=seed)
        finally:
            venv.close()
        out[name] = {k: got[k] for k in ("return", "success")}
    cache.parent.mkdir(parents=True, exist_ok=True)
    np.savez(cache, **{f"{b}/{k}": v for b, d in out.items() for k, v in d.items()})
    return out


def episode_rows(configs: list[str], episodes: int, seed: int) -> list[tuple]:
    """Every policy's episodes, as :data:`EPISODE_COLUMNS` rows."""
    rows: list[tuple] = []
    envs_done: set[str] = set()
    for config in configs:
        env = CONFIGS[config].split("/")[1]
        if env not in envs_done:
            envs_done.add(env)
            for name, d in baseline_episodes(CONFIGS[config], episodes, seed).items():
                rows += _rows(env, name, "-", d)
        for run in runs(config):
            rows += _rows(env, policy_name(config), run.name, run_episodes(run, episodes, seed))
    return rows


def _rows(env: str, policy: str, run: str, d: dict[str, np.ndarray]) -> list[tuple]:
    return [
        (env, policy, run, i, round(float(r), 4), int(s))
        for i, (r, s) in enumerate(zip(d["return"], d["success"], strict=True))
    ]


# --------------------------------------------------------------------------------------------
# statistics (per-episode CSV -> summary CSV)


def score_matrices(rows: list[dict]) -> dict[tuple[str, str], dict[str, np.ndarray]]:
    """(env, policy) -> ``return`` and ``success`` as [runs, episodes] arrays."""
    grouped: dict[tuple[str, str], dict[str, dict[int, tuple[float, float]]]] = {}
    for r in rows:
        runs_ = grouped.setdefault((r["env"], r["policy"]), {})
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
        out[key] = {"return": ret, "success": suc}
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


def summary_rows(matrices: dict) -> list[dict]:
    out = []
    for (env, policy), m in matrices.items():
        ret = interval_estimates(m["return"])
        suc = interval_estimates(m["success"])
        pilot = matrices[(env, "tuned pilot")]["return"].mean()
        rand = matrices[(env, "random")]["return"].mean()
        norm = interval_estimates((m["return"] - rand) / (pilot - rand))
        out.append({
            "env": env, "policy": policy, "runs": m["return"].shape[0],
            "episodes": m["return"].shape[1],
            "iqm": ret["iqm"][0], "iqm_lo": ret["iqm"][1], "iqm_hi": ret["iqm"][2],
            "mean": ret["mean"][0], "mean_lo": ret["mean"][1], "mean_hi": ret["mean"][2],
            "success": suc["mean"][0], "success_lo": suc["mean"][1], "success_hi": suc["mean"][2],
            "normalized_iqm": norm["iqm"][0], "normalized_iqm_lo": norm["iqm"][1],
            "normalized_iqm_hi": norm["iqm"][2],
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
    """Per env: each policy's performance profile (:func:`profile`), with its band."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    envs = sorted({env for env, _ in matrices})
    fig, axes = plt.subplots(1, len(envs), figsize=(5 * len(envs), 3.6), squeeze=False)
    for ax, env in zip(axes[0], envs, strict=True):
        mats = {p: m["return"] for (e, p), m in matrices.items() if e == env}
        lo = min(m.min() for m in mats.values())
        hi = max(m.max() for m in mats.values())
        taus = np.linspace(lo, hi, 101)
        for policy, returns in mats.items():
            curve, band = profile(returns, taus)
            ax.plot(taus, curve, label=policy)
            ax.fill_between(taus, band[0], band[1], alpha=0.2)
        _label(ax, env, "episode return τ", "fraction of episodes > τ")
    _save(fig, path)


def plot_curves(configs: list[str], path: Path) -> None:
    """Per config: each run's evaluations during training (eval/history.csv) as the IQM over
    runs at each timestep, with a 95% stratified bootstrap band (rliable)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from rliable import library as rly
    from rliable import metrics

    fig, axes = plt.subplots(1, len(configs), figsize=(5 * len(configs), 3.6), squeeze=False)
    for ax, config in zip(axes[0], configs, strict=True):
        curves = [
            {int(h["timesteps"]): h["mean_return"] for h in read_history(run)}
            for run in runs(config)
        ]
        curves = [c for c in curves if c]
        if not curves:
            ax.set_title(f"{config}: no runs")
            continue
        steps = sorted(set.intersection(*(set(c) for c in curves)))
        scores = np.array([[c[t] for t in steps] for c in curves])  # [runs, points]
        np.random.seed(BOOTSTRAP_SEED)  # noqa: NPY002  (rliable resamples with it)
        point, ci = rly.get_interval_estimates(
            {"r": scores},
            lambda x: np.array([metrics.aggregate_iqm(x[:, [j]]) for j in range(x.shape[1])]),
            reps=2000,
        )
        ax.plot(steps, point["r"], label=f"IQM of {len(curves)} runs")
        ax.fill_between(steps, ci["r"][0], ci["r"][1], alpha=0.25)
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
    """docs/results.csv as a table: each env's policies; a trained policy's IQM interval
    entirely below the tuned pilot's interval is said so in bold."""
    if not CSV.is_file():
        return "(no docs/results.csv yet: `python -m benchmarks.results --train`)\n"
    _, rows = read_csv(CSV)
    lines = [
        "| env | policy | runs | IQM return [95% CI] | mean return [95% CI] | success "
        "| IQM vs tuned pilot |",
        "|---|---|--:|---|---|---|---|",
    ]
    for r in rows:
        f = {k: float(v) for k, v in r.items() if k not in ("env", "policy")}
        versus = ""
        if r["policy"] not in BASELINES:
            pilot = next(p for p in rows if p["env"] == r["env"] and p["policy"] == "tuned pilot")
            below = f["iqm_hi"] < float(pilot["mean_lo"])  # the intervals apart
            above = f["iqm_lo"] > float(pilot["mean_hi"])
            versus = "**below**" if below else ("above" if above else "overlaps")
        lines.append(
            f"| {r['env']} | {r['policy']} | {int(f['runs'])} | "
            f"{f['iqm']:.2f} [{f['iqm_lo']:.2f}, {f['iqm_hi']:.2f}] | "
            f"{f['mean']:.2f} [{f['mean_lo']:.2f}, {f['mean_hi']:.2f}] | "
            f"{100 * f['success']:.0f}% [{100 * f['success_lo']:.0f}, {100 * f['success_hi']:.0f}] "
            f"| {versus} |"
        )
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--configs", nargs="+", choices=list(CONFIGS), default=list(CONFIGS))
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--episodes", type=int, default=EPISODES)
    parser.add_argument("--train", action="store_true", help="train the missing runs first")
    parser.add_argument("--set", nargs="+", default=[], help="config overrides for training")
    args = parser.parse_args(argv)
    if args.train:
        for config in args.configs:
            train(config, args.seeds, args.set)
    rows = episode_rows(args.configs, args.episodes, EVAL_SEED)
    write_csv(EPISODES_CSV, EPISODE_COLUMNS, rows, [f"episodes: seed {EVAL_SEED}"])
    _, episodes = read_csv(EPISODES_CSV)
    matrices = score_matrices(episodes)
    summary = summary_rows(matrices)
    write_csv(CSV, COLUMNS, ([r[c] for c in COLUMNS] for r in summary))
    plot_profiles(matrices, DOCS / "results_profiles.png")
    plot_curves(args.configs, DOCS / "results_curves.png")
    print(markdown())
    return 0


if __name__ == "__main__":
    sys.exit(main())
