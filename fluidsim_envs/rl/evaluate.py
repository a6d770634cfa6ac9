"""Evaluate a trained run beside the scripted pilot and a random policy.

    fluidsim-evaluate RUN [--model final|best] [--episodes N] [--seed S] [--rerun FILE.rrd]

(also ``python -m fluidsim_envs.rl.evaluate`` and ``python training/evaluate.py``). ``--model``
picks the run's final model (``model.zip``) or the best evaluated one (``best/``), each with
the normalization statistics saved beside it. Each policy flies the same N seeded episodes,
one in each sub-env of one native vector env
(:func:`fluidsim_envs.evaluation.first_episodes`); the trained model acts deterministically on
observations normalized with the run's saved statistics. The table (mean and std of the
return, success rate, and the mean of every scalar entry of the episodes' final info) is
printed and written to ``RUN/evaluation.csv``. With ``--rerun``, the trained policy's episodes
of the first few sub-envs are logged to a Rerun recording.
"""

from __future__ import annotations

import argparse
import csv
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .config import ConfigError, TrainConfig, load_config
from .train import RunError, algorithm_class

#: the models a run folder holds: (model, its normalization statistics), by --model name
MODELS = {
    "final": ("model.zip", "vecnormalize.pkl"),
    "best": ("best/best_model.zip", "best/vecnormalize.pkl"),
}

RERUN_ENVS = 4  # sub-envs logged with --rerun


# --------------------------------------------------------------------------------------------
# loading a run, with the checks that catch a mismatched or damaged folder


def _expected_policy(algo: str) -> type:
    from stable_baselines3.common.policies import ActorCriticPolicy
    from stable_baselines3.sac.policies import SACPolicy

    return {"ppo": ActorCriticPolicy, "sac": SACPolicy}[algo]


def load_run(run_dir: Path, which: str = "final") -> tuple[TrainConfig, Any]:
    """The run's config and model (``which``: a key of :data:`MODELS`), after checking that
    they belong together: the model file is a readable SB3 model, of the config's algorithm,
    for the config's env."""
    import gymnasium as gym
    from gymnasium.envs.registration import load_env_creator
    from stable_baselines3.common.save_util import load_from_zip_file

    if not run_dir.is_dir():
        raise RunError(f"run folder not found: {run_dir}")
    if not (run_dir / "config.yaml").is_file():
        raise RunError(f"{run_dir}: not a run folder (no config.yaml)")
    cfg = load_config(run_dir / "config.yaml")
    if which not in MODELS:
        raise RunError(f"--model must be one of {list(MODELS)}, got {which!r}")
    model_path = run_dir / MODELS[which][0]
    if not model_path.is_file() and which == "best":
        raise RunError(
            f"{run_dir}: no {MODELS['best'][0]} (the run never evaluated: eval.freq was 0 or "
            "longer than the run); evaluate the final model with --model final"
        )
    if not model_path.is_file():
        raise RunError(
            f"{run_dir}: no model.zip (an unfinished run? continue it with "
            f"fluidsim-train --resume {run_dir})"
        )
    try:
        data, _, _ = load_from_zip_file(model_path, device="cpu")
    except Exception as e:  # whatever a damaged file raises (zip, JSON, pickle, torch)
        raise RunError(
            f"{model_path}: corrupt or not an SB3 model ({type(e).__name__}: {e})"
        ) from e
    if not data or "policy_class" not in data or "observation_space" not in data:
        raise RunError(f"{model_path}: corrupt or not an SB3 model (no model data)")

    policy_class = data["policy_class"]
    expected = _expected_policy(cfg.algorithm.name)
    if not (isinstance(policy_class, type) and issubclass(policy_class, expected)):
        found = getattr(policy_class, "__module__", repr(policy_class))
        kind = next(
            (
                a
                for a in ("ppo", "sac")
                if isinstance(policy_class, type) and issubclass(policy_class, _expected_policy(a))
            ),
            f"unknown ({found})",
        )
        raise RunError(
            f"{run_dir}: config.yaml says algorithm {cfg.algorithm.name!r} but model.zip "
            f"holds a {kind} model (policy {getattr(policy_class, '__name__', policy_class)})"
        )

    vector_cls = load_env_creator(gym.spec(cfg.env_id).vector_entry_point)
    obs_shape = (vector_cls.obs_dim,)
    act_shape = (len(vector_cls.action_names),)
    model_obs = getattr(data["observation_space"], "shape", None)
    model_act = getattr(data.get("action_space"), "shape", None)
    if model_obs != obs_shape or model_act != act_shape:
        raise RunError(
            f"{run_dir}: model.zip was trained on observations {model_obs} and actions "
            f"{model_act}, but config.yaml's env {cfg.env_id} has {obs_shape} and {act_shape}: "
            "the model belongs to another env"
        )
    model = algorithm_class(cfg.algorithm.name).load(model_path, device="cpu")
    return cfg, model


def model_policy(cfg: TrainConfig, model, run_dir: Path, venv, which: str = "final") -> Callable:
    """A policy for :func:`first_episodes`: ``model.predict`` (deterministic) on observations
    normalized with the statistics saved with that model (``MODELS[which]``)."""
    normalize: Callable[[np.ndarray], np.ndarray] = lambda obs: obs  # noqa: E731
    if cfg.normalize.enabled:
        from stable_baselines3.common.vec_env import VecNormalize

        from fluidsim_envs.wrappers.sb3 import SB3VecEnv

        stats = run_dir / MODELS[which][1]
        if not stats.is_file():
            raise RunError(f"{run_dir}: normalization is on but {MODELS[which][1]} is missing")
        try:
            # VecNormalize.load needs a VecEnv to hang on: the adapter over the eval env
            vec_normalize = VecNormalize.load(str(stats), SB3VecEnv(venv))
        except Exception as e:  # a damaged pickle, or statistics of another env's shape
            raise RunError(f"{stats}: unusable normalization statistics ({e})") from e
        vec_normalize.training = False
        normalize = vec_normalize.normalize_obs

    def policy(obs: np.ndarray) -> np.ndarray:
        actions, _ = model.predict(normalize(obs), deterministic=True)
        return actions

    return policy


def scripted_pilot(env_id: str, venv) -> Callable:
    """The env's scripted baseline pilot (its scene's, in ``SCENES``), for ``venv.num_envs``
    sub-envs."""
    from fluidsim_envs.scenes import SCENES

    if env_id not in SCENES:
        raise RunError(f"no scripted pilot for {env_id} (not in SCENES: {sorted(SCENES)})")
    return SCENES[env_id].pilot(venv)


# --------------------------------------------------------------------------------------------
# evaluating


def summarize(name: str, results: dict[str, np.ndarray]) -> dict[str, Any]:
    """One table row: return mean and std, success rate, the mean of every other entry."""
    row: dict[str, Any] = {
        "policy": name,
        "episodes": len(results["return"]),
        "return_mean": float(np.mean(results["return"])),
        "return_std": float(np.std(results["return"])),
        "success_rate": float(np.mean(results["success"])) if "success" in results else np.nan,
    }
    for key, values in results.items():
        # episode_steps (= length) says nothing new
        if key not in ("return", "success", "episode_steps") and not key.startswith("_"):
            row[f"{key}_mean"] = float(np.mean(values))
    return row


def evaluate(
    run_dir: Path, episodes: int, seed: int, rerun: Path | None = None, which: str = "final"
) -> list[dict[str, Any]]:
    """Evaluate the run's model (``which``: final or best), the scripted pilot and a random
    policy on the same ``episodes`` seeded episodes; write ``evaluation.csv`` (``which`` best:
    ``evaluation_best.csv``) into the run and return its rows."""
    import gymnasium as gym

    import fluidsim_envs  # noqa: F401  (registers the ids)
    from fluidsim_envs.evaluation import first_episodes, random_policy

    if episodes < 1:
        raise RunError(f"--episodes must be at least 1, got {episodes}")
    cfg, model = load_run(run_dir, which)

    def make():  # the run's env, one sub-env per episode
        return gym.make_vec(
            cfg.env_id, num_envs=episodes, vectorization_mode="vector_entry_point", **cfg.env_kwargs
        )

    venv = make()
    trained_env = venv
    if rerun is not None:
        try:
            from fluidsim_envs.wrappers.rerun_logger import RerunLogger

            trained_env = RerunLogger(
                venv,
                path=str(rerun),
                env_ids=list(range(min(episodes, RERUN_ENVS))),
                episodes_per_env=1,  # whole episodes: each logged sub-env's first
                name=f"{run_dir.name}, trained {cfg.algorithm.name.upper()}, seed {seed}",
            )
        except ImportError as e:
            raise RunError(f"--rerun needs the Rerun logger and rerun-sdk: {e}") from e
    rows = []
    try:
        trained = model_policy(cfg, model, run_dir, venv, which)
        results = first_episodes(trained_env, trained, seed=seed)
        label = f"trained {cfg.algorithm.name.upper()}" + (" (best)" if which == "best" else "")
        rows.append(summarize(label, results))
    finally:
        if trained_env is not venv:
            trained_env.close()  # closes the recording (and the env under it)
    if trained_env is not venv:  # the logger closed it: a fresh one for the baselines
        venv = make()
    for name, policy in (
        ("scripted pilot", scripted_pilot(cfg.env_id, venv)),
        ("random", random_policy(venv, seed)),
    ):
        rows.append(summarize(name, first_episodes(venv, policy, seed=seed)))
    venv.close()
    comments = provenance(run_dir, which, episodes, seed)
    write_csv(rows, run_dir / csv_name(which), seed, comments)
    return rows


def csv_name(which: str) -> str:
    """The table a run's evaluation of its ``which`` model writes."""
    return "evaluation.csv" if which == "final" else f"evaluation_{which}.csv"


def provenance(run_dir: Path, which: str, episodes: int, seed: int) -> list[str]:
    """The ``#`` lines an evaluation table starts with: the command that wrote it and the run
    and model it evaluated, so a copy of the table (in docs/) says where it came from."""
    import yaml

    path = run_dir / "run.yaml"
    meta = (yaml.safe_load(path.read_text()) if path.is_file() else None) or {}
    git = meta.get("git") or {}
    dirty = " (dirty)" if git.get("dirty") else ""
    return [
        f"command: fluidsim-evaluate {run_dir.name} --model {which} --episodes {episodes} "
        f"--seed {seed}",
        f"run: {run_dir.name}, trained by: {meta.get('command_line', '?')}",
        f"model: {which} at {meta.get('num_timesteps', '?')} timesteps of "
        f"{meta.get('env_id', '?')}, git {git.get('revision', '?')}{dirty}",
    ]


def write_csv(rows: list[dict[str, Any]], path: Path, seed: int, comments: list[str] = ()) -> None:
    """The table (``#`` lines first: :func:`provenance`); readers skip lines starting ``#``."""
    columns = ["seed", *dict.fromkeys(k for row in rows for k in row)]
    with path.open("w", newline="") as f:
        f.writelines(f"# {line}\n" for line in comments)
        writer = csv.DictWriter(f, columns)
        writer.writeheader()
        for row in rows:
            writer.writerow({"seed": seed, **row})


def format_table(rows: list[dict[str, Any]]) -> str:
    """Metrics down, policies across."""
    keys = [k for k in dict.fromkeys(k for row in rows for k in row) if k != "policy"]
    width = max(len(k) for k in keys)
    col = max(12, *(len(row["policy"]) for row in rows))
    lines = [" " * width + "".join(f"  {row['policy']:>{col}}" for row in rows)]
    for key in keys:
        cells = []
        for row in rows:
            value = row.get(key, np.nan)
            text = f"{value:d}" if isinstance(value, int) else f"{value:.4g}"
            cells.append(f"  {text:>{col}}")
        lines.append(f"{key:<{width}}" + "".join(cells))
    return "\n".join(lines)


# --------------------------------------------------------------------------------------------
# the command line


def main(argv: list[str] | None = None, prog: str = "fluidsim-evaluate") -> int:
    parser = argparse.ArgumentParser(
        prog=prog,
        description="Evaluate a training run beside the scripted pilot and a random policy.",
        epilog=f"Example: {prog} runs/demo --model best --episodes 256 --rerun runs/demo/ep.rrd",
    )
    parser.add_argument("run", type=Path, help="the run folder (written by fluidsim-train)")
    parser.add_argument(
        "--model", choices=list(MODELS), default="final", help="which model (default: final)"
    )
    parser.add_argument("--episodes", type=int, default=100, help="seeded episodes per policy")
    parser.add_argument("--seed", type=int, default=0, help="seed of the episodes")
    parser.add_argument("--rerun", type=Path, metavar="FILE.rrd", help="log to a Rerun file")
    args = parser.parse_args(argv)
    try:
        rows = evaluate(args.run, args.episodes, args.seed, args.rerun, args.model)
    except (ConfigError, RunError) as e:
        print(f"{prog}: error: {e}", file=sys.stderr)
        return 2
    print(f"{args.run}: {args.episodes} episodes, seed {args.seed}")
    print(format_table(rows))
    print(f"written: {args.run / csv_name(args.model)}")
    if args.rerun is not None:
        print(
            f"rerun recording: {args.rerun}  (view it: rerun {args.rerun}; on a machine "
            f"without a display: rerun --web-viewer {args.rerun})"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main(prog="python -m fluidsim_envs.rl.evaluate"))
