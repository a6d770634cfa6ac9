"""Train a pilot with Stable-Baselines3 from a YAML config, into a self-describing run folder.

    fluidsim-train paper_airplane_ppo [--set key=value ...] [--run-dir DIR] [--resume RUN]

(also ``python -m fluidsim_envs.rl.train`` and ``python training/train.py``). The config is a
YAML file or the name of a shipped one (``configs/``). The run prints what it
will do, a line per evaluation, and at the end the commands that evaluate, replay and chart
it. The run folder holds everything needed to replay or continue the run:

========================  =====================================================================
``config.yaml``           the resolved config: defaults filled in, overrides applied, and
                          ``env_kwargs`` holding every env parameter (not only those changed)
``run.yaml``              the command line, git revision (and whether the tree was dirty),
                          seeds, package versions (fluidsim_envs included), the device the
                          model ran on (``auto`` resolved), timesteps done, resumes, where the
                          time went
``model.safetensors``     the final model (numbers only, :mod:`.saved`);
                          ``vecnormalize.safetensors`` its normalization statistics
``checkpoints/``          periodic (and on Ctrl-C) model + statistics, for ``--resume``
``eval/``                 ``history.csv`` (one row per evaluation), SB3's ``evaluations.npz``
``best/``                 the best evaluated model, ``best_model.safetensors``, with the
                          statistics it was evaluated with, ``vecnormalize.safetensors``, and
                          its score, ``best.yaml`` (a resume reads it: only a better
                          evaluation replaces it)
``monitor.csv``           every training episode (return, length, time, success, and the run's
                          timesteps at its end)
``learning_curve.png``    training and evaluation returns against timesteps
``tb/``                   TensorBoard logs (``rollout/success_rate`` included)
========================  =====================================================================

A kill at any moment leaves the folder resumable (:mod:`.runs`, :mod:`.files`): every file is
written to a temporary name and then renamed; ``--resume`` continues from the newest saved
state that loads (saying which it skipped), drops the evaluations and episodes logged after
it, and goes on with the evaluation history, the best score and the time column.
``benchmarks/kill_resume.py`` kills a run again and again and checks all of that.
"""

from __future__ import annotations

import argparse
import csv
import datetime
import platform
import shlex
import shutil
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .extras import require

require("train", "fluidsim_envs.rl.train")

import numpy as np  # noqa: E402
import yaml  # noqa: E402  (after the check that names the missing extra)

from .. import seeding as SD  # noqa: E402
from .. import threads  # noqa: E402
from ..physics.jit import target_cpu  # noqa: E402
from . import files, memory, saved  # noqa: E402
from .config import (  # noqa: E402
    ACTIVATIONS,
    ConfigError,
    TrainConfig,
    add_overrides_argument,
    config_from_dict,
    dump_config,
    load_config,
    resolved,
    stage_starts,
)
from .files import RunError  # noqa: E402
from .runs import (  # noqa: E402, F401  (CHECKPOINT_PREFIX ... are this module's names too)
    CHECKPOINT_PREFIX,
    EVAL_HISTORY_COLUMNS,
    MODEL,
    BestModel,
    EvalLog,
    Restart,
    checkpoint_paths,
    checkpoint_stats,
    checkpoints,
    final_paths,
    pickled_states,
    read_run_meta,
    restart_point,
    save_state,
    saved_states,
    trim_logs,
)
from .warm_start import warm_start  # noqa: E402

# --------------------------------------------------------------------------------------------
# building blocks


def algorithm_class(name: str) -> type:
    from stable_baselines3 import PPO, SAC

    return {"ppo": PPO, "sac": SAC}[name]


def policy_spec(cfg: TrainConfig, observation_space) -> tuple[Any, dict[str, Any]]:
    """The policy (SB3's alias or our class) and its keyword arguments for observations of
    ``observation_space`` (the stacked frames, with the exact columns where privileged)."""
    kwargs = policy_kwargs(cfg)
    if not cfg.privileged_critic:
        return "MlpPolicy", kwargs
    from .privileged import PrivilegedCriticPolicy, actor_mask

    reading = observation_space.shape[0] // cfg.frame_stack // 2
    kwargs["actor_mask"] = actor_mask(reading, cfg.frame_stack)
    return PrivilegedCriticPolicy, kwargs


def build_policy(cfg: TrainConfig, observation_space, action_space):
    """The policy alone, as the algorithm builds it for ``cfg`` (weights to be loaded into
    it: :func:`.saved.load_policy_weights`), in evaluation mode."""
    algo_cls = algorithm_class(cfg.algorithm.name)
    policy, kwargs = policy_spec(cfg, observation_space)
    policy_cls = algo_cls.policy_aliases[policy] if isinstance(policy, str) else policy
    built = policy_cls(
        observation_space,
        action_space,
        lambda _: 0.0,  # no optimizer step is ever taken
        use_sde=cfg.algorithm.use_sde,
        **kwargs,
    )
    built.set_training_mode(False)
    return built


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
    start_timesteps: int = 0,
    time_offset_s: float = 0.0,
    env_kwargs: dict[str, Any] | None = None,
):
    """The SB3 vector env of a run (of ``env_kwargs``: a curriculum stage's; None: the
    run's own): our native vector env through the adapter, its episodes
    recorded by ``VecMonitor`` (raw returns; with ``monitor_file``, a :class:`RunMonitor`
    writing there, appended to when ``append``, its rows stamped with the run's timesteps from
    ``start_timesteps`` on and its times going on from ``time_offset_s``), then
    ``VecNormalize`` when enabled (``stats``: saved statistics to load, :mod:`.saved`), then
    ``VecFrameStack`` with ``cfg.frame_stack`` > 1.

    ``evaluation``: frozen statistics, raw rewards and the evaluation's seed stream (else the
    training stream, whose episodes no evaluation flies: ``fluidsim_envs.seeding``). Success
    is reported as ``is_success`` at each episode's end (SB3's ``rollout/success_rate`` and
    the evaluations read it).
    """
    from stable_baselines3.common.vec_env import VecMonitor, VecNormalize

    from fluidsim_envs.wrappers.sb3 import make_sb3_vec_env

    from .callbacks import RunMonitor

    venv = make_sb3_vec_env(
        cfg.env_id,
        n_envs,
        seed=seed,
        success_key="success",  # SB3 reads is_success: success rates in TensorBoard
        info_keys=("success",),  # all that training reads (VecMonitor, SB3's success rate)
        stream="evaluation" if evaluation else "training",  # fluidsim_envs.seeding
        levels=() if evaluation else cfg.levels,  # evaluations fly the run's own level
        truth=cfg.privileged_critic,  # the critic's exact columns (rl/privileged.py)
        **(cfg.env_kwargs if env_kwargs is None else env_kwargs),
    )
    if monitor_file is None:
        venv = VecMonitor(venv, info_keywords=("success",))
    else:
        venv = RunMonitor(
            venv,
            monitor_file,
            cfg.env_id,
            info_keywords=("success",),
            start_timesteps=start_timesteps,
            time_offset_s=time_offset_s,
            append=append,
        )
    n = cfg.normalize
    if not n.enabled:
        return _stacked(venv, cfg.frame_stack)
    if stats is not None:
        venv = saved.load_statistics(stats, venv)
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
    return _stacked(venv, cfg.frame_stack)


def _stacked(venv, frames: int):
    """``venv`` with its last ``frames`` observations side by side (``frame_stack``)."""
    from stable_baselines3.common.vec_env import VecFrameStack

    return venv if frames == 1 else VecFrameStack(venv, frames)


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


#: what ``train(on_eval=...)`` gets after each evaluation (:func:`eval_record`'s keys); False
#: back ends the training there (the run finishes as at its end: final model, run.yaml)
EvalHook = Callable[[dict[str, Any]], bool | None]


def eval_record(timesteps: int, returns, success, wall_s: float, best: float) -> dict[str, Any]:
    """One evaluation as plain numbers: what ``on_eval`` hooks (the sweep's reports) get."""
    return {
        "timesteps": int(timesteps),
        "eval_return": float(np.mean(returns)),
        "eval_return_std": float(np.std(returns)),
        "success_rate": float(np.mean(success)) if len(success) else float("nan"),
        "best_return": float(best),
        "wall_s": round(float(wall_s), 2),
        "peak_rss_mb": peak_rss_mb(),
    }


def _callbacks(
    cfg: TrainConfig,
    run_dir: Path,
    venv,
    eval_env,
    say,
    resumed: bool,
    time_offset_s: float = 0.0,
    on_eval: EvalHook | None = None,
) -> list:
    """The evaluations (first: see :class:`~.callbacks.Evaluations`) and the checkpoints. A
    resumed run goes on with its evaluation history and best score, and its clock from
    ``time_offset_s``; a new one starts them afresh, even in a folder that held such files."""
    from .callbacks import Checkpoints, Evaluations

    started = time.perf_counter()

    def clock() -> float:  # the run's wall-clock seconds, earlier sessions included
        return time_offset_s + time.perf_counter() - started

    callbacks: list = []
    if cfg.eval.freq > 0:
        log = EvalLog.load(run_dir / "eval") if resumed else EvalLog(run_dir / "eval")
        best = BestModel.open(run_dir / "best") if resumed else BestModel(run_dir / "best")

        def report(timesteps: int, returns, success, new_best: bool) -> bool | None:
            rate = venv.unwrapped.env_steps / (time.perf_counter() - started)
            say(_eval_line(timesteps, returns, success, rate) + ("   new best" * new_best))
            if on_eval is None:
                return None
            return on_eval(eval_record(timesteps, returns, success, log.wall_s[-1], best.score))

        period = _every(cfg.eval.freq, cfg.n_envs) * cfg.n_envs
        callbacks.append(
            Evaluations(
                eval_env, period, cfg.eval.n_episodes, cfg.eval.seed, log, best, report, clock
            )
        )
    if cfg.checkpoint.freq > 0:
        period = _every(cfg.checkpoint.freq, cfg.n_envs) * cfg.n_envs
        callbacks.append(Checkpoints(run_dir, period, cfg.checkpoint.save_replay_buffer))
    return callbacks


def _stage_at(cfg: TrainConfig, timesteps: int) -> dict[str, Any]:
    """The env parameters a run trains on at ``timesteps``: its curriculum's stage then."""
    return [kwargs for start, kwargs in stage_starts(cfg) if start <= timesteps][-1]


def _stage_label(cfg: TrainConfig, env_kwargs: dict[str, Any]) -> str:
    """What a stage changes of the run's own parameters, in a few words."""
    changed = [
        f"{k}: {v}" if len(repr(v)) < 40 else f"{k} (its own)"
        for k, v in env_kwargs.items()
        if cfg.env_kwargs.get(k) != v
    ]
    return f"episodes of {', '.join(changed)}" if changed else "the run's own episodes"


def _curriculum(cfg: TrainConfig, done_steps: int, say) -> list:
    """The callback that moves the training env to each stage still ahead (none without)."""
    from fluidsim_envs.wrappers.sb3 import make_vector_env

    from .callbacks import Curriculum

    ahead = [
        (start, kwargs, _stage_label(cfg, kwargs))
        for start, kwargs in stage_starts(cfg)
        if start > done_steps
    ]
    if not ahead:
        return []
    return [
        Curriculum(
            ahead,
            lambda kwargs: make_vector_env(cfg.env_id, cfg.n_envs, **kwargs),
            lambda timesteps: resumed_seed(cfg.seed, timesteps),
            say,
        )
    ]


def env_spaces(env_id: str, env_kwargs: dict[str, Any]) -> tuple:
    """The (observation, action) spaces of one sub-env of ``env_id`` with ``env_kwargs``."""
    from fluidsim_envs.wrappers.sb3 import make_vector_env

    env = make_vector_env(env_id, 1, **env_kwargs)
    try:
        return env.single_observation_space, env.single_action_space
    finally:
        env.close()


def policy_obs_dim(cfg: TrainConfig, reading_dim: int) -> int:
    """The width of what the policy reads: each stacked frame's reading, each with the exact
    observation after it where the critic is privileged (rl/privileged.py)."""
    return reading_dim * (2 if cfg.privileged_critic else 1) * cfg.frame_stack


def _check_memory(cfg: TrainConfig) -> None:
    """A run the machine's available memory cannot hold: an error with the estimate and the
    keys that set it (:mod:`.memory`), before any env is built."""
    obs, act = env_spaces(cfg.env_id, cfg.env_kwargs)
    obs_dim = policy_obs_dim(cfg, obs.shape[0])
    why = memory.problem(cfg, obs_dim, act.shape[0], memory.available_bytes())
    if why is not None:
        raise RunError(why)


def _check_stage_spaces(cfg: TrainConfig) -> None:
    """Every curriculum stage's env has the spaces of the run's own (the policy reads and
    acts on both): a mismatch is an error naming the stage before training, not at its
    start."""
    *stages, (_, own_kwargs) = stage_starts(cfg)
    own = env_spaces(cfg.env_id, own_kwargs)
    for i, (_, kwargs) in enumerate(stages):
        theirs = env_spaces(cfg.env_id, kwargs)
        if theirs != own:
            raise ConfigError(
                f"curriculum[{i}]: its env's (observation, action) spaces {theirs} differ "
                f"from those of the run's own env_kwargs {own}"
            )


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
        "peak_rss_mb": peak_rss_mb(),
    }


def peak_rss_mb() -> float:
    """This process's peak resident memory so far, in MiB (``getrusage``; Linux counts KiB)."""
    import resource

    kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return round(kib / (1024.0 if sys.platform != "darwin" else 1024.0**2), 1)


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
    files.write_with(out, fig.savefig)
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
    on_eval: EvalHook | None = None,
) -> Path:
    """Train ``cfg`` into ``run_dir`` (or, with ``resume``, continue the run there from its
    newest saved state that loads) and return the final model's path. ``say`` gets the lines
    that tell the user what happens (the plan, each evaluation, what to do next); ``on_eval``
    gets each evaluation as numbers (:func:`eval_record`: the sweep reports them to Ray Tune)
    and ends the training by returning False.

    Nothing is written before the config and the folder are checked, and a new folder whose
    envs or model cannot be built is removed again: a start that failed leaves nothing that
    blocks the next. The run's threads are :func:`fluidsim_envs.threads.choose`'s for the
    config's ``torch_threads`` and ``numba_threads`` (null: one torch thread, numba on every
    core), and the counts before it again afterwards."""
    plan = _threads(cfg)
    with threads.owned(plan):
        return _train(cfg, run_dir, command, resume, progress_bar, say, on_eval, plan)


def _threads(cfg: TrainConfig) -> threads.Threads:
    """The run's threads, or a :class:`ConfigError` naming the count that cannot be had."""
    try:
        return threads.choose(torch=cfg.torch_threads, numba=cfg.numba_threads)
    except threads.ThreadError as e:
        raise ConfigError(str(e)) from None


def _train(
    cfg: TrainConfig,
    run_dir: Path,
    command: list[str],
    resume: bool,
    progress_bar: bool,
    say,
    on_eval: EvalHook | None,
    plan: threads.Threads,
) -> Path:
    cfg = resolved(cfg)  # every env parameter written down: the run replays whatever changes
    files.check_writable_folder(run_dir, "--resume" if resume else "--run-dir")
    _check_memory(cfg)
    restart, time_offset = _restart(run_dir, cfg) if resume else (None, 0.0)
    # seeding, in one place: training env i gets seeding.root(seed, "training").spawn(n_envs)[i]
    # at its first reset (SB3VecEnv.seed, as the env's own reset(seed=..., options={"stream":
    # "training"}): never an evaluation's episodes at any seed); a resumed run reseeds
    # with seed + timesteps done (modulo 2**32, torch's and NumPy's seed range), so it does
    # not replay the episodes it began with; the eval env is reseeded before every evaluation
    done_steps = restart.steps if restart else 0
    env_seed = resumed_seed(cfg.seed, done_steps)
    # said before the envs are built: a cold numba cache compiles there (and says so)
    remaining = cfg.total_timesteps - done_steps
    planned = planned_timesteps(cfg, remaining) if remaining > 0 else 0
    opening = (_plan(cfg, run_dir, remaining, planned), plan.describe())
    for line in (*opening, *schedule_warnings(cfg, planned)):
        say(line)
    created = _first_missing(run_dir)
    run_dir.mkdir(parents=True, exist_ok=True)
    try:
        venv, eval_env, model = _build(cfg, run_dir, restart, env_seed, time_offset)
    except BaseException:
        if created is not None:
            shutil.rmtree(created, ignore_errors=True)
        raise
    meta = _meta(run_dir, cfg, command, restart, env_seed, str(model.device), plan)
    dump_config(cfg, run_dir / "config.yaml")
    files.write_text(run_dir / "run.yaml", yaml.safe_dump(meta, sort_keys=False))

    start = time.perf_counter()
    try:
        if restart is None and cfg.warm_start.steps:  # a resumed run has it behind it
            meta["warm_start"] = warm_start(cfg, model, say)
            files.write_text(run_dir / "run.yaml", yaml.safe_dump(meta, sort_keys=False))
            time_offset += meta["warm_start"]["seconds"]  # the run's clock counts it
        if planned > 0:
            callbacks = _callbacks(cfg, run_dir, venv, eval_env, say, resume, time_offset, on_eval)
            model.learn(
                total_timesteps=planned,
                callback=callbacks + _curriculum(cfg, done_steps, say),
                tb_log_name=cfg.algorithm.name.upper(),
                reset_num_timesteps=restart is None,
                progress_bar=progress_bar,
            )
    except KeyboardInterrupt:
        n = model.num_timesteps
        save_state(model, checkpoint_paths(run_dir, n), cfg.checkpoint.save_replay_buffer)
        print(f"\ninterrupted at {n} timesteps; continue with --resume {run_dir}", file=sys.stderr)
        raise
    finally:
        venv.close()
        if eval_env is not None:
            eval_env.close()
    return _finish(
        model, cfg, run_dir, meta, _timing(venv, eval_env, time.perf_counter() - start), say
    )


def _first_missing(path: Path) -> Path | None:
    """The outermost folder of ``path`` that does not exist yet (what ``mkdir -p`` creates
    and a failed start removes again), or None when ``path`` exists."""
    missing = None
    path = path.absolute()
    while not path.exists():
        missing, path = path, path.parent
    return missing


def _restart(run_dir: Path, cfg: TrainConfig) -> tuple[Restart, float]:
    """The state ``--resume`` continues from (the newest that loads), with the folder made
    whole again: temporary files of killed writes removed, a best model whose write a kill
    interrupted completed, the logs past the restart point dropped. Also returns the time
    ``monitor.csv`` had reached (its times go on from there)."""
    try:  # a zoo entry: nothing of it is touched
        zoo = saved.model_header(run_dir / MODEL).get("policy_only")
    except RunError:
        zoo = False
    if zoo and not checkpoints(run_dir):
        raise RunError(
            f"{run_dir}: a zoo entry (its model {saved.POLICY_ONLY}): zoo entries are "
            "read-only to --resume; train anew from its config.yaml with --run-dir"
        )
    files.remove_partials(run_dir)
    restart = restart_point(run_dir, cfg.normalize.enabled, cfg.checkpoint.save_replay_buffer)
    if restart is None and pickled_states(run_dir):
        raise RunError(
            f"{run_dir}: its saved states are SB3 pickles ({pickled_states(run_dir)[0].name}: "
            "an older version's format, and loading a pickle runs any code it carries); if "
            "you trust them, convert them once with python -m fluidsim_envs.rl.convert "
            f"{run_dir} --allow-pickle, then resume"
        )
    if restart is None:
        raise RunError(
            f"{run_dir}: nothing saved to resume from (no checkpoint in checkpoints/ nor "
            f"{MODEL} that loads with its normalization statistics); a run stopped before "
            "its first checkpoint starts again with another --run-dir, or after removing it"
        )
    # before the trim: a run of an older version takes its best score from the whole history
    BestModel.open(run_dir / "best", EvalLog.load(run_dir / "eval"))
    monitor_s = trim_logs(run_dir, restart)
    # the run's clock goes on from the later of the last kept episode's end and the last
    # kept evaluation's (an evaluation after the last episode: its wall_s must not go back)
    kept = [w for w in EvalLog.load(run_dir / "eval").wall_s if np.isfinite(w)]
    return restart, max([monitor_s, *kept[-1:]])


def resumed_seed(seed: int, done_steps: int) -> int:
    """The env seed of a run restarted after ``done_steps`` timesteps: ``seed`` for a fresh
    start, else a stream of its own derived from both (``seed + done_steps`` would give the
    runs seeded 0 and 1024 the same envs after a resume at 1024: STYLE's rule 7).

    >>> resumed_seed(7, 0)
    7
    >>> resumed_seed(0, 1024) != resumed_seed(1024, 0)
    True
    """
    if done_steps == 0:
        return seed
    return int(np.random.SeedSequence([seed, done_steps]).generate_state(1)[0])


def _build(cfg: TrainConfig, run_dir: Path, restart: Restart | None, env_seed: int, offset: float):
    """The training env, the eval env (None without evaluations) and the model."""
    stats = restart.stats if restart is not None and cfg.normalize.enabled else None
    steps = restart.steps if restart else 0
    venv = make_env(
        cfg,
        cfg.n_envs,
        env_seed,
        env_kwargs=_stage_at(cfg, steps),
        stats=stats,
        monitor_file=run_dir / "monitor.csv",
        # a resumed run goes on with monitor.csv, unless trim_logs found none worth keeping
        append=restart is not None and (run_dir / "monitor.csv").is_file(),
        start_timesteps=steps,
        time_offset_s=offset,
    )
    eval_env = None
    try:
        if cfg.curriculum:
            _check_stage_spaces(cfg)
        if cfg.eval.freq > 0:
            eval_env = make_env(cfg, cfg.eval.n_episodes, cfg.eval.seed, evaluation=True)
        return venv, eval_env, _model(cfg, run_dir, venv, restart, env_seed)
    except BaseException:
        for env in (venv, eval_env):
            if env is not None:
                env.close()
        raise


def _meta(
    run_dir: Path,
    cfg: TrainConfig,
    command: list[str],
    restart: Restart | None,
    env_seed: int,
    device: str,
    plan: threads.Threads,
) -> dict:
    """``run.yaml``'s contents: a new run's description, or the run's own with this resume
    added. ``device`` is where the model is (``auto`` resolved); ``plan`` its threads."""
    now = datetime.datetime.now().isoformat(timespec="seconds")
    seeds = {
        "model": cfg.seed,
        "train_envs": SD.describe(env_seed, cfg.n_envs, "training"),
        "train_stream": "training",  # fluidsim_envs.seeding
        "eval_envs": SD.describe(cfg.eval.seed, cfg.eval.n_episodes),
    }
    if restart is None:
        meta = {
            "env_id": cfg.env_id,
            "env_version": int(cfg.env_id.rsplit("-v", 1)[1]),
            "algorithm": cfg.algorithm.name,
            "command": command,
            "command_line": shlex.join(command),
            "cwd": str(Path.cwd()),
            "git": git_revision(),
            "started": now,
            "versions": versions(),
            # the CPU it trained on (the kernels' target): a seed trains the same policy again,
            # to the bit, on such a CPU only (the kernels and torch round differently on
            # another, and training carries it into another policy)
            "cpu": target_cpu(),
            "seeds": seeds,
        }
    else:
        meta = read_run_meta(run_dir)
        meta.setdefault("resumes", []).append(
            {
                "at": now,
                "command_line": shlex.join(command),
                "from": str(restart.model.relative_to(run_dir)),
                "timesteps": restart.steps,
                "seeds": seeds,
                "device": device,
                "threads": plan.as_dict(),
            }
        )
    meta["device"] = device
    meta["torch_threads"] = plan.torch  # the counts in force (nulls resolved)
    meta["threads"] = plan.as_dict()
    meta["total_timesteps"] = cfg.total_timesteps
    return meta


def _model(cfg: TrainConfig, run_dir: Path, venv, restart: Restart | None, env_seed: int):
    """A new model, or the saved one (with its replay buffer if kept) reseeded to go on."""
    policy, kwargs = policy_spec(cfg, venv.observation_space)
    model = algorithm_class(cfg.algorithm.name)(
        policy,
        venv,
        policy_kwargs=kwargs,
        tensorboard_log=str(run_dir / "tb"),
        seed=cfg.seed,
        device=cfg.device,
        verbose=0,
        **algorithm_kwargs(cfg),
    )
    if restart is None:
        return model
    saved.load_into(model, restart.model)  # weights, optimizers' states, timesteps
    model.set_random_seed(env_seed)  # torch, the action space and the envs (SeedSequence)
    if restart.replay.exists():
        saved.load_replay(model.replay_buffer, restart.replay)
    return model


def _finish(model, cfg: TrainConfig, run_dir: Path, meta: dict, timing: dict, say) -> Path:
    """Save the final model, close ``run.yaml``, chart the run and say what to do next."""
    steps = int(model.num_timesteps)
    final = final_paths(run_dir, steps)
    save_state(model, final, cfg.checkpoint.save_replay_buffer)
    meta.setdefault("timing", []).append(timing)
    meta["num_timesteps"] = steps
    meta["finished"] = datetime.datetime.now().isoformat(timespec="seconds")
    files.write_text(run_dir / "run.yaml", yaml.safe_dump(meta, sort_keys=False))
    plot_learning_curve(run_dir)
    best = (run_dir / "best" / BestModel.MODEL).is_file()
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
    stages = _stages_left(cfg, done=cfg.total_timesteps - remaining)
    if stages:  # the run's own episodes after the stages; evaluations fly those throughout
        stages = f" (a curriculum: {stages}, then the run's own)"
    return (
        f"training {a.name.upper()} on {cfg.env_id} with {cfg.n_envs} envs: {planned:,} env "
        f"steps{rounded}{stages}; {evals}; into {run_dir}"
    )


def _stages_left(cfg: TrainConfig, done: int) -> str:
    """The curriculum's stages not yet finished at ``done`` timesteps (a resumed run: the
    one under way with its steps left), as the plan line names them."""
    left = []
    for stage, (start, kwargs) in zip(cfg.curriculum, stage_starts(cfg), strict=False):
        steps = start + stage.timesteps - max(done, start)
        if steps > 0:
            more = " more" if done > start else ""
            left.append(f"{_stage_label(cfg, kwargs)} for {steps:,}{more} steps")
    return ", ".join(left)


def _next_steps(run_dir: Path, timing: dict, best: bool) -> list[str]:
    """The lines that close a run: how it went and the commands that use it."""
    run = shlex.quote(str(run_dir))
    lines = [
        f"done: {timing['env_steps']:,} env steps in {timing['wall_s']:,.0f} s "
        f"({timing['env_steps_per_s']:,.0f} env-steps/s); final model {run_dir / MODEL}",
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
    add_overrides_argument(
        parser, "override config keys (nested through dots, values read as YAML)"
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
        if not args.resume.is_dir():
            what = "not a folder" if args.resume.exists() else "run folder not found"
            raise RunError(f"--resume {args.resume}: {what}")
        if not (args.resume / "config.yaml").is_file():
            raise RunError(f"--resume {args.resume}: not a run folder (no config.yaml)")
        files.check_writable_folder(args.resume, "--resume")
        return load_config(args.resume / "config.yaml", args.overrides), args.resume
    if args.config is None:
        raise RunError(
            "a config is required (a file or a shipped config's name), or --resume RUN; see --help"
        )
    cfg = load_config(args.config, args.overrides)
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    run_dir = args.run_dir or Path("runs") / f"{cfg.env_name}-{cfg.algorithm.name}-{stamp}"
    files.check_writable_folder(run_dir, "--run-dir")
    if (run_dir / "config.yaml").exists():
        raise RunError(f"{run_dir} already holds a run (use --resume to continue it)")
    return cfg, run_dir


def main(argv: list[str] | None = None, prog: str = "fluidsim-train") -> int:
    args = parse_args(argv, prog)
    command = [prog, *(sys.argv[1:] if argv is None else argv)]
    run_dir = None
    try:
        cfg, run_dir = _run_folder(args)
        train(
            cfg,
            run_dir,
            command,
            resume=args.resume is not None,
            progress_bar=not args.no_progress_bar,
        )
    except KeyboardInterrupt:
        return 130
    except Exception as e:
        full = files.disk_full(e)  # the run's files say so (RunError); others are wrapped
        named = isinstance(e, ConfigError | RunError)
        if not (full or named):
            raise
        text = str(e) if named else f"no space left on the disk ({type(e).__name__}: {e})"
        if full and run_dir is not None and saved_states(run_dir):
            text += f"; free space, then continue the run: {prog} --resume {run_dir}"
        elif full:
            text += "; free space, then start the run again (it had saved nothing to resume)"
        print(f"{prog}: error: {text}", file=sys.stderr)
        return 2
    return 0


__all__ = ["config_from_dict", "main", "train"]

if __name__ == "__main__":
    sys.exit(main(prog="python -m fluidsim_envs.rl.train"))
