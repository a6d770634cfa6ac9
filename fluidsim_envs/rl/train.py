"""Train a pilot with Stable-Baselines3 from a YAML config, into a self-describing run folder.

    fluidsim-train paper_airplane_ppo [--set key=value ...] [--run-dir DIR] [--resume RUN]

(also ``python -m fluidsim_envs.rl.train`` and ``python training/train.py``). The config is a
YAML file or the name of a shipped one (``fluidsim_envs/configs/``). The run prints what it
will do, a line per evaluation, and at the end the commands that evaluate, replay and chart
it. The run folder holds everything needed to replay or continue the run:

========================  =====================================================================
``config.yaml``           the resolved config: defaults filled in, overrides applied, and
                          ``env_kwargs`` holding every env parameter (not only those changed)
``run.yaml``              the command line, git revision (and whether the tree was dirty),
                          seeds, package versions (fluidsim_envs included), timesteps done,
                          resumes, where the time went
``model.zip``             the final model; ``vecnormalize.pkl`` its normalization statistics
``checkpoints/``          periodic (and on Ctrl-C) model + statistics, for ``--resume``
``eval/``                 ``history.csv`` (one row per evaluation), SB3's ``evaluations.npz``
``best/``                 the best evaluated model, ``best_model.zip``, with the normalization
                          statistics it was evaluated with, ``vecnormalize.pkl``
``monitor.csv``           every training episode (return, length, success)
``learning_curve.png``    training and evaluation returns against timesteps
``tb/``                   TensorBoard logs (``rollout/success_rate`` included)
========================  =====================================================================
"""

from __future__ import annotations

import argparse
import csv
import datetime
import platform
import re
import shlex
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .extras import require

require("train", "fluidsim_envs.rl.train")

import yaml  # noqa: E402  (after the check that names the missing extra)

from .config import (  # noqa: E402
    ACTIVATIONS,
    ConfigError,
    TrainConfig,
    config_from_dict,
    dump_config,
    load_config,
    resolved,
)

CHECKPOINT_PREFIX = "model"
EVAL_HISTORY_COLUMNS = ("timesteps", "mean_return", "std_return", "mean_length", "success_rate")


class RunError(RuntimeError):
    """A run folder that cannot be used as asked (missing, or nothing to resume)."""


# --------------------------------------------------------------------------------------------
# building blocks


def algorithm_class(name: str) -> type:
    from stable_baselines3 import PPO, SAC

    return {"ppo": PPO, "sac": SAC}[name]


def policy_kwargs(cfg: TrainConfig) -> dict[str, Any]:
    """SB3 ``policy_kwargs`` from the structured policy section."""
    import torch.nn

    p = cfg.policy
    arch = p.net_arch
    kwargs: dict[str, Any] = {
        "net_arch": {k: list(v) for k, v in arch.items()} if isinstance(arch, dict) else list(arch),
        "activation_fn": getattr(torch.nn, ACTIVATIONS[p.activation_fn]),
    }
    if p.log_std_init is not None:
        kwargs["log_std_init"] = p.log_std_init
    if p.ortho_init is not None:
        kwargs["ortho_init"] = p.ortho_init
    return kwargs


def algorithm_kwargs(cfg: TrainConfig) -> dict[str, Any]:
    """The algorithm's keyword arguments (hyperparameters, learning-rate schedule)."""
    import dataclasses

    from stable_baselines3.common.utils import LinearSchedule

    a = cfg.algorithm
    kwargs = {f.name: getattr(a, f.name) for f in dataclasses.fields(a)}
    del kwargs["name"], kwargs["lr_schedule"]
    if a.lr_schedule == "linear":  # progress runs 1 -> 0 over the run, resumes included
        kwargs["learning_rate"] = LinearSchedule(a.learning_rate, 0.0, 1.0)
    return kwargs


def make_env(
    cfg: TrainConfig,
    n_envs: int,
    seed: int,
    *,
    evaluation: bool = False,
    stats: Path | None = None,
    monitor_file: Path | None = None,
    append: bool = False,
):
    """The SB3 vector env of a run: our native vector env through the adapter, its episodes
    recorded by ``VecMonitor`` (raw returns; into ``monitor_file``, appended to when
    ``append``), then ``VecNormalize`` when enabled (``stats``: a saved ``.pkl`` to load).

    ``evaluation``: frozen statistics and raw rewards. Success is reported as ``is_success``
    at each episode's end (SB3's ``rollout/success_rate`` and ``EvalCallback`` read it).
    """
    from stable_baselines3.common.monitor import ResultsWriter
    from stable_baselines3.common.vec_env import VecMonitor, VecNormalize

    from fluidsim_envs.wrappers.sb3 import make_sb3_vec_env

    venv = make_sb3_vec_env(
        cfg.env_id,
        n_envs,
        seed=seed,
        success_key="success",  # SB3 reads is_success: success rates in TensorBoard
        **cfg.env_kwargs,
    )
    venv = VecMonitor(venv, info_keywords=("success",))
    if monitor_file is not None:
        # VecMonitor opens its file for writing; a resumed run appends to the old rows
        venv.results_writer = ResultsWriter(
            str(monitor_file),
            header={"t_start": venv.t_start, "env_id": cfg.env_id},
            extra_keys=("success",),
            override_existing=not append,
        )
    n = cfg.normalize
    if not n.enabled:
        return venv
    if stats is not None:
        venv = VecNormalize.load(str(stats), venv)
    else:
        venv = VecNormalize(
            venv,
            norm_obs=n.norm_obs,
            norm_reward=n.norm_reward,
            clip_obs=n.clip_obs,
            clip_reward=n.clip_reward,
            gamma=cfg.algorithm.gamma,
            epsilon=n.epsilon,
        )
    if evaluation:
        venv.training = False
        venv.norm_reward = False
    return venv


def git_revision() -> dict[str, Any]:
    """The package's git revision and whether its tree has uncommitted changes (None
    outside a git checkout or without git)."""
    root = Path(__file__).resolve().parent
    try:
        rev = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True, timeout=10
        )
        status = subprocess.run(
            ["git", "status", "--porcelain"], cwd=root, capture_output=True, text=True, timeout=10
        )
    except (OSError, subprocess.SubprocessError):
        return {"revision": None, "dirty": None}
    if rev.returncode != 0:
        return {"revision": None, "dirty": None}
    return {"revision": rev.stdout.strip(), "dirty": bool(status.stdout.strip())}


def versions() -> dict[str, str]:
    import importlib.metadata

    import gymnasium
    import numba
    import numpy
    import stable_baselines3
    import torch

    try:
        ours = importlib.metadata.version("fluidsim-envs")
    except importlib.metadata.PackageNotFoundError:  # run from a checkout, not installed
        ours = "not installed"
    return {
        "fluidsim_envs": ours,
        "python": platform.python_version(),
        "numba": numba.__version__,
        "numpy": numpy.__version__,
        "gymnasium": gymnasium.__version__,
        "stable_baselines3": stable_baselines3.__version__,
        "torch": str(torch.__version__),
    }


def latest_checkpoint(run_dir: Path) -> tuple[int, Path] | None:
    """(timesteps, model path) of the newest checkpoint in ``run_dir/checkpoints``."""
    found = []
    for path in (run_dir / "checkpoints").glob(f"{CHECKPOINT_PREFIX}_*_steps.zip"):
        m = re.fullmatch(rf"{CHECKPOINT_PREFIX}_(\d+)_steps\.zip", path.name)
        if m:
            found.append((int(m.group(1)), path))
    return max(found) if found else None


@dataclass(frozen=True)
class Restart:
    """Where ``--resume`` continues from: a saved model, its statistics and replay buffer
    (either may be absent), and the timesteps it had done."""

    steps: int
    model: Path
    stats: Path
    replay: Path


def restart_point(run_dir: Path) -> Restart | None:
    """The newest saved state of a run: its newest checkpoint, or its final model when that
    went further (a finished run continued with a larger ``total_timesteps``)."""
    found = []
    checkpoint = latest_checkpoint(run_dir)
    if checkpoint is not None:
        steps, path = checkpoint
        replay = path.with_name(f"{CHECKPOINT_PREFIX}_replay_buffer_{steps}_steps.pkl")
        found.append(Restart(steps, path, checkpoint_stats(path), replay))
    meta = run_dir / "run.yaml"
    if (run_dir / "model.zip").is_file() and meta.is_file():
        steps = (yaml.safe_load(meta.read_text()) or {}).get("num_timesteps")
        if isinstance(steps, int):
            stats, replay = run_dir / "vecnormalize.pkl", run_dir / "replay_buffer.pkl"
            found.append(Restart(steps, run_dir / "model.zip", stats, replay))
    return max(found, key=lambda r: r.steps) if found else None


def trim_logs(run_dir: Path, restart: Restart) -> None:
    """Drop what a run logged after its restart point, so a resumed run's history does not
    hold the lost stretch twice: evaluations past its timesteps (``eval/history.csv``,
    ``eval/evaluations.npz``) and training episodes that ended after its model was saved
    (``monitor.csv``, by their wall time)."""
    import numpy as np

    history = run_dir / "eval" / "history.csv"
    if history.is_file():
        lines = history.read_text().splitlines(keepends=True)
        kept = [ln for ln in lines[1:] if int(float(ln.split(",", 1)[0])) <= restart.steps]
        history.write_text("".join(lines[:1] + kept))
    npz = run_dir / "eval" / "evaluations.npz"
    if npz.is_file():
        with np.load(npz) as data:
            keep = data["timesteps"] <= restart.steps
            arrays = {k: data[k][keep] for k in data.files}
        np.savez(npz, **arrays)
    monitor = run_dir / "monitor.csv"
    if monitor.is_file():
        lines = monitor.read_text().splitlines(keepends=True)
        t_start = float(re.search(r'"t_start": ([0-9.e+-]+)', lines[0]).group(1))
        saved = restart.model.stat().st_mtime - t_start
        rows = [ln for ln in lines[2:] if float(ln.split(",")[2]) <= saved]
        monitor.write_text("".join(lines[:2] + rows))


def checkpoint_stats(model_path: Path) -> Path:
    """The normalization statistics saved with a checkpoint (SB3's naming)."""
    steps = model_path.name[len(CHECKPOINT_PREFIX) + 1 :]
    return model_path.with_name(f"{CHECKPOINT_PREFIX}_vecnormalize_{steps}").with_suffix(".pkl")


def planned_timesteps(cfg: TrainConfig, remaining: int) -> int:
    """The timesteps that will really run for ``remaining`` asked: SB3 stops only between
    rollouts (PPO: ``n_steps`` x ``n_envs`` transitions; SAC: ``train_freq`` x ``n_envs``)."""
    a = cfg.algorithm
    chunk = cfg.n_envs * (a.n_steps if a.name == "ppo" else a.train_freq)
    return -(-remaining // chunk) * chunk


def _every(freq: int, n_envs: int) -> int:
    """SB3's callback period in vector steps for ``freq`` env steps (as ours is passed)."""
    return max(freq // n_envs, 1)


def schedule_warnings(cfg: TrainConfig, planned: int) -> list[str]:
    """What the run will never do: an evaluation or checkpoint interval beyond its length."""
    calls = planned // cfg.n_envs
    out = []
    if planned <= 0:  # nothing left to train: nothing to warn about
        return out
    for what, freq, key, left in (
        ("evaluation", cfg.eval.freq, "eval.freq", "best/ stays empty"),
        ("checkpoint", cfg.checkpoint.freq, "checkpoint.freq", "--resume will have nothing"),
    ):
        if freq > 0 and calls < _every(freq, cfg.n_envs):
            out.append(
                f"warning: no {what} will run: {key} is {freq:,} env steps but the run is "
                f"{planned:,} ({left}); lower it with --set {key}=N"
            )
    return out


def _eval_line(timesteps: int, returns, success, steps_per_s: float) -> str:
    import numpy as np

    rate = f"{100.0 * float(np.mean(success)):5.1f}%" if len(success) else "   n/a"
    return (
        f"eval @ {timesteps:>11,} steps: return {float(np.mean(returns)):9.3f} "
        f"+- {float(np.std(returns)):7.3f}   success {rate}   {steps_per_s:,.0f} env-steps/s"
    )


def _callbacks(cfg: TrainConfig, run_dir: Path, eval_env, say) -> list:
    from stable_baselines3.common.callbacks import BaseCallback, CheckpointCallback, EvalCallback

    started = time.perf_counter()
    news = []  # a new best model since the last evaluation line

    class EvalHistory(BaseCallback):
        """After each evaluation: a line on the terminal, its row in ``eval/history.csv``
        (kept across resumes); then reseed the eval env so the next evaluation flies the
        same episodes."""

        def _on_step(self) -> bool:
            import numpy as np

            parent = self.parent
            returns = parent.evaluations_results[-1]
            success = parent._is_success_buffer
            row = [
                parent.num_timesteps,
                float(np.mean(returns)),
                float(np.std(returns)),
                float(np.mean(parent.evaluations_length[-1])),
                float(np.mean(success)) if success else float("nan"),
            ]
            path = run_dir / "eval" / "history.csv"
            new = not path.exists()
            with path.open("a", newline="") as f:
                writer = csv.writer(f)
                if new:
                    writer.writerow(EVAL_HISTORY_COLUMNS)
                writer.writerow(row)
            steps = self.model.get_env().unwrapped.env_steps
            line = _eval_line(row[0], returns, success, steps / (time.perf_counter() - started))
            say(line + ("   new best" if news else ""))
            news.clear()
            eval_env.seed(cfg.eval.seed)
            return True

    class SaveBestStats(BaseCallback):
        """With each new best model: the normalization statistics it was evaluated with."""

        def _on_step(self) -> bool:
            stats = self.model.get_vec_normalize_env()
            if stats is not None:
                stats.save(str(run_dir / "best" / "vecnormalize.pkl"))
            news.append(self.num_timesteps)
            return True

    callbacks = []
    if cfg.checkpoint.freq > 0:
        callbacks.append(
            CheckpointCallback(
                save_freq=_every(cfg.checkpoint.freq, cfg.n_envs),
                save_path=str(run_dir / "checkpoints"),
                name_prefix=CHECKPOINT_PREFIX,
                save_replay_buffer=cfg.checkpoint.save_replay_buffer,
                save_vecnormalize=True,
            )
        )
    if cfg.eval.freq > 0:
        evaluation = EvalCallback(
            eval_env,
            callback_on_new_best=SaveBestStats(),
            callback_after_eval=EvalHistory(),
            n_eval_episodes=cfg.eval.n_episodes,
            eval_freq=_every(cfg.eval.freq, cfg.n_envs),
            log_path=str(run_dir / "eval"),
            best_model_save_path=str(run_dir / "best"),
            deterministic=True,
            verbose=0,
        )
        _continue_evaluations(evaluation, run_dir)
        callbacks.append(evaluation)
    return callbacks


def _continue_evaluations(evaluation, run_dir: Path) -> None:
    """A resumed run's EvalCallback starts from the run's earlier evaluations: its best score
    (so a worse model does not replace ``best/``) and the arrays it rewrites into
    ``evaluations.npz``. A new run has none."""
    import numpy as np

    npz = run_dir / "eval" / "evaluations.npz"
    if not npz.is_file():
        return
    with np.load(npz) as data:
        evaluation.evaluations_timesteps = [int(t) for t in data["timesteps"]]
        evaluation.evaluations_results = [list(r) for r in data["results"]]
        evaluation.evaluations_length = [list(n) for n in data["ep_lengths"]]
        if "successes" in data.files:
            evaluation.evaluations_successes = [list(x) for x in data["successes"]]
    if evaluation.evaluations_results:
        means = [float(np.mean(r)) for r in evaluation.evaluations_results]
        evaluation.best_mean_reward = max(means)


def _save(model, cfg: TrainConfig, where: Restart) -> None:
    """The model, its normalization statistics and (off-policy, when the config keeps it)
    its replay buffer, at the paths ``where`` names."""
    where.model.parent.mkdir(parents=True, exist_ok=True)
    model.save(where.model)
    vec_normalize = model.get_vec_normalize_env()
    if vec_normalize is not None:
        vec_normalize.save(str(where.stats))
    if cfg.checkpoint.save_replay_buffer and hasattr(model, "save_replay_buffer"):
        model.save_replay_buffer(where.replay)


def _timing(venv, eval_env, wall: float) -> dict[str, float]:
    """Where this session's training time went: the vector envs' reset and step (training and
    evaluation) against everything else (the policy's forward passes, the updates, SB3's
    bookkeeping); and the training env-steps per second of wall time."""
    train_env = venv.unwrapped
    eval_s = eval_env.unwrapped.env_seconds if eval_env is not None else 0.0
    return {
        "wall_s": round(wall, 1),
        "env_steps": int(train_env.env_steps),
        "env_steps_per_s": round(train_env.env_steps / max(wall, 1e-9), 1),
        "train_env_s": round(train_env.env_seconds, 1),
        "eval_env_s": round(eval_s, 1),
        "env_share": round((train_env.env_seconds + eval_s) / max(wall, 1e-9), 4),
    }


def plot_learning_curve(run_dir: Path) -> Path | None:
    """``learning_curve.png``: training episode returns (and their running mean) and the
    evaluations (mean +- std) against timesteps. None when there is nothing to plot yet."""
    try:
        import matplotlib
    except ImportError:  # an optional extra: the run itself is complete without the figure
        print("matplotlib is not installed: no learning_curve.png", file=sys.stderr)
        return None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, ax = plt.subplots(figsize=(7, 4), dpi=100)
    drew = False
    monitor = run_dir / "monitor.csv"
    if monitor.exists():
        rows = list(csv.DictReader(line for line in monitor.open() if not line.startswith("#")))
        if rows:
            r = np.array([float(row["r"]) for row in rows])
            steps = np.cumsum([int(row["l"]) for row in rows])
            ax.plot(steps, r, ".", ms=2, alpha=0.3, color="tab:blue", label="training episode")
            k = max(1, min(100, len(r) // 10))
            ax.plot(steps[k - 1 :], np.convolve(r, np.ones(k) / k, "valid"), color="tab:blue")
            drew = True
    history = run_dir / "eval" / "history.csv"
    if history.exists():
        rows = list(csv.DictReader(history.open()))
        if rows:
            t = np.array([float(row["timesteps"]) for row in rows])
            m = np.array([float(row["mean_return"]) for row in rows])
            s = np.array([float(row["std_return"]) for row in rows])
            ax.errorbar(t, m, yerr=s, fmt="o-", color="tab:red", capsize=3, label="evaluation")
            drew = True
    if not drew:
        plt.close(fig)
        return None
    ax.set_xlabel("timesteps")
    ax.set_ylabel("episode return")
    ax.set_title(run_dir.name)
    ax.grid(alpha=0.3)
    ax.legend(loc="best")
    fig.tight_layout()
    out = run_dir / "learning_curve.png"
    fig.savefig(out)
    plt.close(fig)
    return out


# --------------------------------------------------------------------------------------------
# the run


def train(
    cfg: TrainConfig,
    run_dir: Path,
    command: list[str],
    *,
    resume: bool = False,
    progress_bar: bool = True,
    say=print,
) -> Path:
    """Train ``cfg`` into ``run_dir`` (or, with ``resume``, continue the run there from its
    newest saved state) and return the final model's path. ``say`` gets the lines that tell
    the user what happens (the plan, each evaluation, what to do next)."""
    cfg = resolved(cfg)  # every env parameter written down: the run replays whatever changes
    run_dir.mkdir(parents=True, exist_ok=True)
    restart = _restart(run_dir, cfg) if resume else None
    meta = _meta(run_dir, cfg, command, restart)
    dump_config(cfg, run_dir / "config.yaml")
    # seeding, in one place: training env i gets SeedSequence(seed).spawn(n_envs)[i] at its
    # first reset (SB3VecEnv.seed, as the env's own reset(seed=...)); a resumed run reseeds
    # with seed + timesteps done, so it does not replay the episodes it began with; the eval
    # env is reseeded before every evaluation
    done_steps = restart.steps if restart else 0
    env_seed = cfg.seed + done_steps
    seeds = {
        "model": cfg.seed,
        "train_envs": f"SeedSequence({env_seed}).spawn({cfg.n_envs})[i] for env i",
        "eval_envs": f"SeedSequence({cfg.eval.seed}).spawn({cfg.eval.n_episodes})[i] for env i",
    }
    # said before the envs are built: a cold numba cache compiles there (and says so)
    remaining = cfg.total_timesteps - done_steps
    planned = planned_timesteps(cfg, remaining) if remaining > 0 else 0
    for line in (_plan(cfg, run_dir, remaining, planned), *schedule_warnings(cfg, planned)):
        say(line)
    stats = restart.stats if restart is not None and cfg.normalize.enabled else None
    venv = make_env(
        cfg, cfg.n_envs, env_seed, stats=stats, monitor_file=run_dir / "monitor.csv", append=resume
    )
    eval_env = None
    if cfg.eval.freq > 0:
        eval_env = make_env(cfg, cfg.eval.n_episodes, cfg.eval.seed, evaluation=True)
    model = _model(cfg, run_dir, venv, restart, env_seed)
    if restart is None:
        meta["seeds"] = seeds
    else:
        meta.setdefault("resumes", []).append(
            {
                "at": meta.pop("_now"),
                "command_line": shlex.join(command),
                "from": str(restart.model.relative_to(run_dir)),
                "timesteps": done_steps,
                "seeds": seeds,
            }
        )
    meta.pop("_now", None)
    meta["total_timesteps"] = cfg.total_timesteps
    (run_dir / "run.yaml").write_text(yaml.safe_dump(meta, sort_keys=False))

    start = time.perf_counter()
    try:
        if planned > 0:
            model.learn(
                total_timesteps=planned,
                callback=_callbacks(cfg, run_dir, eval_env, say),
                tb_log_name=cfg.algorithm.name.upper(),
                reset_num_timesteps=restart is None,
                progress_bar=progress_bar,
            )
    except KeyboardInterrupt:
        n = model.num_timesteps
        _save(model, cfg, _checkpoint_paths(run_dir, n))
        print(f"\ninterrupted at {n} timesteps; continue with --resume {run_dir}", file=sys.stderr)
        raise
    finally:
        venv.close()
        if eval_env is not None:
            eval_env.close()
    return _finish(
        model, cfg, run_dir, meta, _timing(venv, eval_env, time.perf_counter() - start), say
    )


def _restart(run_dir: Path, cfg: TrainConfig) -> Restart:
    """The state ``--resume`` continues from, checked, with the run's later logs dropped."""
    restart = restart_point(run_dir)
    if restart is None:
        raise RunError(
            f"{run_dir}: nothing saved to resume from (no checkpoints/ model, no model.zip)"
        )
    if cfg.normalize.enabled and not restart.stats.exists():
        raise RunError(f"{run_dir}: {restart.model.name} has no {restart.stats.name}")
    trim_logs(run_dir, restart)
    return restart


def _meta(run_dir: Path, cfg: TrainConfig, command: list[str], restart: Restart | None) -> dict:
    """``run.yaml``'s contents: read back on a resume, else what describes a new run."""
    now = datetime.datetime.now().isoformat(timespec="seconds")
    path = run_dir / "run.yaml"
    if restart is not None:
        meta = yaml.safe_load(path.read_text()) if path.exists() else {}
        return {**(meta or {}), "_now": now}
    return {
        "env_id": cfg.env_id,
        "env_version": int(cfg.env_id.rsplit("-v", 1)[1]),
        "algorithm": cfg.algorithm.name,
        "command": command,
        "command_line": shlex.join(command),
        "cwd": str(Path.cwd()),
        "git": git_revision(),
        "started": now,
        "versions": versions(),
    }


def _model(cfg: TrainConfig, run_dir: Path, venv, restart: Restart | None, env_seed: int):
    """A new model, or the saved one (with its replay buffer if kept) reseeded to go on."""
    algo_cls = algorithm_class(cfg.algorithm.name)
    if restart is None:
        return algo_cls(
            "MlpPolicy",
            venv,
            policy_kwargs=policy_kwargs(cfg),
            tensorboard_log=str(run_dir / "tb"),
            seed=cfg.seed,
            device=cfg.device,
            verbose=0,
            **algorithm_kwargs(cfg),
        )
    model = algo_cls.load(restart.model, env=venv, device=cfg.device)
    model.tensorboard_log = str(run_dir / "tb")
    model.set_random_seed(env_seed)  # torch, the action space and the envs (SeedSequence)
    if restart.replay.exists():
        model.load_replay_buffer(restart.replay)
    return model


def _checkpoint_paths(run_dir: Path, steps: int) -> Restart:
    """Where a checkpoint at ``steps`` goes (CheckpointCallback's naming)."""
    model = run_dir / "checkpoints" / f"{CHECKPOINT_PREFIX}_{steps}_steps.zip"
    replay = model.with_name(f"{CHECKPOINT_PREFIX}_replay_buffer_{steps}_steps.pkl")
    return Restart(steps, model, checkpoint_stats(model), replay)


def _finish(model, cfg: TrainConfig, run_dir: Path, meta: dict, timing: dict, say) -> Path:
    """Save the final model, close ``run.yaml``, chart the run and say what to do next."""
    steps = int(model.num_timesteps)
    final = Restart(
        steps, run_dir / "model.zip", run_dir / "vecnormalize.pkl", run_dir / "replay_buffer.pkl"
    )
    _save(model, cfg, final)
    meta.setdefault("timing", []).append(timing)
    meta["num_timesteps"] = steps
    meta["finished"] = datetime.datetime.now().isoformat(timespec="seconds")
    (run_dir / "run.yaml").write_text(yaml.safe_dump(meta, sort_keys=False))
    plot_learning_curve(run_dir)
    best = (run_dir / "best" / "best_model.zip").is_file()
    for line in _next_steps(run_dir, timing, best=best):
        say(line)
    return final.model


def _plan(cfg: TrainConfig, run_dir: Path, remaining: int, planned: int) -> str:
    """The line that opens a run: what it trains, how long, where it writes."""
    a = cfg.algorithm
    if remaining <= 0:
        return f"{run_dir}: already at {cfg.total_timesteps:,} timesteps; nothing to train"
    chunk = (
        f"rollouts of {a.n_steps} x {cfg.n_envs}"
        if a.name == "ppo"
        else f"collections of {a.train_freq} x {cfg.n_envs}"
    )
    rounded = f" ({remaining:,} asked, rounded up to whole {chunk})" if planned != remaining else ""
    evals = (
        f"evaluation every {cfg.eval.freq:,} steps on {cfg.eval.n_episodes} episodes"
        if cfg.eval.freq > 0
        else "no evaluation (eval.freq 0)"
    )
    return (
        f"training {a.name.upper()} on {cfg.env_id} with {cfg.n_envs} envs: {planned:,} env "
        f"steps{rounded}; {evals}; into {run_dir}"
    )


def _next_steps(run_dir: Path, timing: dict, best: bool) -> list[str]:
    """The lines that close a run: how it went and the commands that use it."""
    run = shlex.quote(str(run_dir))
    lines = [
        f"done: {timing['env_steps']:,} env steps in {timing['wall_s']:,.0f} s "
        f"({timing['env_steps_per_s']:,.0f} env-steps/s); final model {run_dir / 'model.zip'}",
        f"  evaluate:    fluidsim-evaluate {run}" + ("   (best model: --model best)" * best),
        f"  replay:      fluidsim-evaluate {run} --episodes 8 --rerun {run}/episodes.rrd"
        f"  then  rerun {run}/episodes.rrd",
        f"  curves:      {run}/learning_curve.png, or  tensorboard --logdir {run}/tb",
    ]
    return lines


# --------------------------------------------------------------------------------------------
# the command line


def parse_args(argv: list[str] | None, prog: str = "fluidsim-train") -> argparse.Namespace:
    from .config import shipped_configs

    shipped = list(shipped_configs())
    parser = argparse.ArgumentParser(
        prog=prog,
        description="Train a pilot with Stable-Baselines3 from a YAML config.",
        epilog=f"shipped configs: {', '.join(shipped)}. Example: {prog} {shipped[0]} "
        "--set total_timesteps=200000",
    )
    parser.add_argument(
        "config",
        nargs="?",
        help="a config YAML file, or a shipped config's name (omit with --resume)",
    )
    parser.add_argument(
        "--set",
        dest="overrides",
        metavar="KEY=VALUE",
        nargs="+",
        action="extend",
        default=[],
        help="override config keys (nested through dots, values read as YAML)",
    )
    parser.add_argument(
        "--run-dir", type=Path, help="run folder (default runs/<env>-<algo>-<time>)"
    )
    parser.add_argument("--resume", type=Path, metavar="RUN", help="continue this run folder")
    parser.add_argument("--no-progress-bar", action="store_true", help="hide the progress bar")
    return parser.parse_args(argv)


def _run_folder(args: argparse.Namespace) -> tuple[TrainConfig, Path]:
    """The config and run folder the arguments name (checked)."""
    if args.resume is not None:
        if args.config is not None or args.run_dir is not None:
            raise RunError("--resume RUN takes its config and folder from RUN")
        if not (args.resume / "config.yaml").is_file():
            raise RunError(f"{args.resume}: not a run folder (no config.yaml)")
        return load_config(args.resume / "config.yaml", args.overrides), args.resume
    if args.config is None:
        raise RunError(
            "a config is required (a file or a shipped config's name), or --resume RUN; see --help"
        )
    cfg = load_config(args.config, args.overrides)
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    run_dir = args.run_dir or Path("runs") / f"{cfg.env_name}-{cfg.algorithm.name}-{stamp}"
    if (run_dir / "config.yaml").exists():
        raise RunError(f"{run_dir} already holds a run (use --resume to continue it)")
    return cfg, run_dir


def main(argv: list[str] | None = None, prog: str = "fluidsim-train") -> int:
    args = parse_args(argv, prog)
    command = [prog, *(sys.argv[1:] if argv is None else argv)]
    try:
        cfg, run_dir = _run_folder(args)
        train(
            cfg,
            run_dir,
            command,
            resume=args.resume is not None,
            progress_bar=not args.no_progress_bar,
        )
    except (ConfigError, RunError) as e:
        print(f"{prog}: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    return 0


__all__ = ["config_from_dict", "main", "train"]

if __name__ == "__main__":
    sys.exit(main(prog="python -m fluidsim_envs.rl.train"))
