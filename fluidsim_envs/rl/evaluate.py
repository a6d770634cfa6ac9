"""Evaluate a trained run beside every baseline, or the baselines alone, on the same seeded
episodes, with 95% confidence intervals.

    fluidsim-evaluate RUN [--model final|best] [--episodes N] [--seed S] [--env KEY=VALUE ...]
                      [--planner-samples K] [--planner-horizon H] [--no-planner]
                      [--out DIR] [--rerun FILE.rrd] [--allow-pickle]
    fluidsim-evaluate --env-id ID --out DIR [--episodes N] [--seed S] [--env KEY=VALUE ...]
                      [--planner-samples K] [--planner-horizon H] [--no-planner]

(also ``python -m fluidsim_envs.rl.evaluate`` and ``python training/evaluate.py``). Each
policy flies the same N seeded episodes, one in each sub-env of one native vector env
(:func:`fluidsim_envs.evaluation.first_episodes`). The rows, in this order:

``trained PPO`` (or SAC; ``(best)`` for ``--model best``)
    the run's final model (``model.safetensors``) or the best evaluated one (``best/``),
    acting deterministically on observations normalized with the statistics saved beside it
    (numbers only, :mod:`.saved`: SB3's pickled files of an older run with
    ``--allow-pickle``)
``planner``
    the scene's sampling planner (``Scene.planner(venv, samples=K, horizon=H)``). It reads
    the true state of the env it flies, not the observations, but not the episode's noise
    to come: its rollouts draw turbulence, currents and sensor noise of their own (a gust
    or a route drawn at the episode's start it still reads: ``scenes/planner.py``). A
    reference for what a search of a few seconds ahead reaches, not a policy to deploy (nor a
    bound: a policy trained on whole episodes can do better). It costs minutes for 256 episodes;
    ``--no-planner`` skips it (``PlannerConfig.clairvoyant`` is the reference told that
    future too: ``benchmarks/results.py`` flies it beside this one)
``tuned pilot``
    the scene's scripted pilot with the gains tuned on the env's version (``Scene.pilot``)
``v0-tuned pilot``
    on a later version (v1), the same pilot with the gains tuned on its v0
``hand-set pilot``
    the same pilot with the gains set by hand (``Scene.hand_pilot``)
``random``
    uniform random actions from a generator seeded with ``--seed``

The table (the mean and std of the return, the success rate, and the mean of every scalar
entry of the episodes' final info) is printed and written to ``RUN/evaluation.csv``
(``evaluation_best.csv`` for ``--model best``; ``DIR/evaluation.csv`` with ``--out DIR``),
one row per policy, after ``#`` lines that say which command, run, env overrides and git
revision wrote it. Each mean column ``C`` has its 95% confidence interval beside it, ``C_lo``
and ``C_hi``: a BCa bootstrap over the episodes (:func:`mean_interval`, seeded, so a command
writes the same table each time). The interval is over these episodes' draws (launch, wind,
targets) for this one model, not over training seeds; the printed table shows
``mean [lo, hi]``.

``--env KEY=VALUE`` (repeatable) sets an env parameter on top of the run's (or, with
``--env-id``, the env's defaults), for out-of-distribution evaluation: the value is read as
YAML (``--env wind_speed_mps=[0,3] --env integrator=rk4 --env dt=0.005``); an unknown key or
a bad value is an error that names it. ``--env-id ID --out DIR`` without a run folder
evaluates the baselines alone. With ``--rerun``, the trained policy's episodes of the first
few sub-envs are logged to a Rerun recording.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import shlex
import sys
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .. import threads
from ..physics.jit import target_cpu
from . import files, saved
from .config import ConfigError, TrainConfig, load_config, load_yaml, parse_assignment
from .files import RunError
from .runs import MODEL, PICKLED, PICKLED_BEST, STATS, BestModel, read_run_meta
from .train import algorithm_class, build_policy, policy_obs_dim

#: the models a run folder holds: (model, its normalization statistics), by --model name
MODELS = {
    "final": (MODEL, STATS),
    "best": (f"best/{BestModel.MODEL}", f"best/{BestModel.STATS}"),
}
#: the same in SB3's pickled format (an older version's runs): read only with --allow-pickle
PICKLED_MODELS = {
    "final": (PICKLED[MODEL], PICKLED[STATS]),
    "best": (f"best/{PICKLED_BEST}", f"best/{PICKLED[STATS]}"),
}

RERUN_ENVS = 4  # sub-envs logged with --rerun

# the baselines' rows, in the table's order (after the trained model's)
PLANNER = "planner"  # knows the true state, not the episode's future noise
TUNED_PILOT = "tuned pilot"
V0_PILOT = "v0-tuned pilot"  # on a v1 env: the gains its v0 was tuned to
HAND_PILOT = "hand-set pilot"
RANDOM = "random"

CONFIDENCE = 0.95  # of the intervals
RESAMPLES = 9999  # bootstrap resamples per interval
# the bootstrap generator is seeded with (BOOTSTRAP_STREAM, --seed): a stream of its own,
# apart from the random policy's (seeded with --seed alone)
BOOTSTRAP_STREAM = 0xB007


# --------------------------------------------------------------------------------------------
# loading a run, with the checks that catch a mismatched or damaged folder


def model_files(run_dir: Path, which: str, allow_pickle: bool = False) -> tuple[Path, Path]:
    """The model and statistics files of ``which`` in ``run_dir``. The folder is only read:
    a trainer may be writing a new best beside this evaluation (``BestModel.committed``).
    Where only SB3's pickled files are there (an older version's run, a file from
    elsewhere): those with ``allow_pickle``, else an error that says what they are."""
    if which == "best":
        paths = BestModel(run_dir / "best").committed()
    else:
        paths = tuple(run_dir / name for name in MODELS[which])
    pickled = tuple(run_dir / name for name in PICKLED_MODELS[which])
    if paths[0].is_file() or not pickled[0].is_file():
        return paths
    if not allow_pickle:
        raise RunError(
            f"{pickled[0]}: an SB3 pickle, not a saved model of numbers (an older version "
            "wrote it, or it comes from elsewhere): loading it runs any code it carries. If "
            "you trust its source, pass --allow-pickle, or convert the folder once with "
            f"python -m fluidsim_envs.rl.convert {run_dir} --allow-pickle"
        )
    return pickled


def load_run(
    run_dir: Path, which: str = "final", allow_pickle: bool = False
) -> tuple[TrainConfig, Any]:
    """The run's config and policy (``which``: a key of :data:`MODELS`): the policy the config
    describes, with the saved weights loaded into it after checking that they belong together
    (the file is a saved model, of the config's algorithm, for the config's env). Nothing
    in the folder runs: see :mod:`.saved` (SB3's pickles only with ``allow_pickle``)."""
    import gymnasium as gym
    from gymnasium import spaces
    from gymnasium.envs.registration import load_env_creator

    if not run_dir.is_dir():
        what = "is a file, not a run folder" if run_dir.exists() else "run folder not found"
        raise RunError(f"{run_dir}: {what}")
    if not (run_dir / "config.yaml").is_file():
        raise RunError(f"{run_dir}: not a run folder (no config.yaml)")
    cfg = load_config(run_dir / "config.yaml")
    if which not in MODELS:
        raise RunError(f"--model must be one of {list(MODELS)}, got {which!r}")
    model_path, _ = model_files(run_dir, which, allow_pickle)
    if not model_path.is_file() and which == "best":
        raise RunError(
            f"{run_dir}: no {MODELS['best'][0]} (the run never evaluated: eval.freq was 0 or "
            "longer than the run); evaluate the final model with --model final"
        )
    if not model_path.is_file():
        raise RunError(
            f"{run_dir}: no {MODELS['final'][0]} (an unfinished run? continue it with "
            f"fluidsim-train --resume {run_dir})"
        )
    vector_cls = load_env_creator(gym.spec(cfg.env_id).vector_entry_point)
    probe = vector_cls(num_envs=1, **cfg.env_kwargs)  # its observation follows its params
    box, action_space = probe.single_observation_space, probe.single_action_space
    probe.close()
    obs_shape = (policy_obs_dim(cfg, box.shape[0]),)
    if model_path.suffix == ".zip":
        return cfg, _pickled_policy(cfg, model_path, obs_shape, action_space.shape)
    saved.check_model(model_path, cfg.algorithm.name, cfg.env_id, obs_shape, action_space.shape)
    policy = build_policy(cfg, spaces.Box(-np.inf, np.inf, obs_shape, box.dtype), action_space)
    saved.load_policy_weights(policy, model_path)
    return cfg, policy


def _pickled_policy(cfg: TrainConfig, path: Path, obs_shape: tuple, act_shape: tuple):
    """The policy of an SB3 model zip (``--allow-pickle``), checked as a saved model is."""
    algo_cls = algorithm_class(cfg.algorithm.name)
    try:
        model = saved.load_pickled_model(algo_cls, path)
    except Exception as e:  # whatever a damaged file raises (zip, JSON, pickle, torch)
        raise RunError(f"{path}: corrupt or not an SB3 model ({type(e).__name__}: {e})") from e
    if type(model) is not algo_cls:
        raise RunError(
            f"{path}: config.yaml says algorithm {cfg.algorithm.name!r} but the file holds a "
            f"{type(model).__name__} model"
        )
    shapes = (model.observation_space.shape, model.action_space.shape)
    if shapes != (obs_shape, act_shape):
        raise RunError(
            f"{path}: the model was trained on observations {shapes[0]} and actions "
            f"{shapes[1]}, but config.yaml's env {cfg.env_id} has {obs_shape} and {act_shape}: "
            "the model belongs to another env"
        )
    return model.policy


def model_policy(
    cfg: TrainConfig, model, run_dir: Path, venv, which: str = "final", allow_pickle: bool = False
) -> Callable:
    """A policy for :func:`first_episodes`: ``model.predict`` (deterministic: ``model`` is
    an SB3 policy or algorithm) on observations normalized with the statistics saved with
    that model (``MODELS[which]``; SB3's pickle with ``allow_pickle``)."""
    normalize: Callable[[np.ndarray], np.ndarray] = lambda obs: obs  # noqa: E731
    if cfg.normalize.enabled:
        from fluidsim_envs.wrappers.sb3 import SB3VecEnv

        _, stats = model_files(run_dir, which, allow_pickle)
        pickled = run_dir / PICKLED_MODELS[which][1]
        if not stats.is_file() and pickled.is_file() and allow_pickle:
            stats = pickled  # a folder half converted: its statistics still SB3's
        elif not stats.is_file() and pickled.is_file():
            raise RunError(
                f"{run_dir}: normalization is on and its statistics are still SB3's pickle "
                f"{pickled.name}: convert the folder (python -m fluidsim_envs.rl.convert "
                f"{run_dir} --allow-pickle) or pass --allow-pickle"
            )
        if not stats.is_file():
            raise RunError(f"{run_dir}: normalization is on but {stats.name} is missing")
        load = saved.load_pickled_statistics if stats.suffix == ".pkl" else saved.load_statistics
        shaped = venv
        if cfg.privileged_critic:  # the statistics cover the exact columns too
            from .privileged import WithTruth

            shaped = WithTruth(venv)
        try:
            # the statistics need a VecEnv to hang on: the adapter over the eval env
            vec_normalize = load(stats, SB3VecEnv(shaped))
        except Exception as e:  # damaged, or statistics of another env's shape
            raise RunError(f"{stats}: unusable normalization statistics ({e})") from e
        finally:
            if shaped is not venv:
                shaped.detach()
        vec_normalize.training = False
        normalize = vec_normalize.normalize_obs
    if cfg.privileged_critic:  # zeros where the critic read the exact observation
        from .privileged import pad

        unpadded = normalize
        normalize = lambda obs: unpadded(pad(obs))  # noqa: E731

    if cfg.frame_stack == 1:

        def policy(obs: np.ndarray) -> np.ndarray:
            actions, _ = model.predict(normalize(obs), deterministic=True)
            return actions

        return policy
    return StackedPolicy(model, normalize, cfg.frame_stack)


class StackedPolicy:
    """``model.predict`` (deterministic) on the last ``frames`` normalized observations side by
    side, oldest first, as SB3's ``VecFrameStack`` gave them in training: zeros before an
    episode's first observation. ``reset(mask)`` starts the sub-envs of ``mask`` (all when
    None) anew: their next observation is an episode's first."""

    def __init__(self, model, normalize: Callable[[np.ndarray], np.ndarray], frames: int):
        self.model, self.normalize, self.frames = model, normalize, frames
        self.stack: np.ndarray | None = None  # [E, frames * obs_dim]

    def reset(self, mask=None) -> None:
        if self.stack is not None:
            self.stack[slice(None) if mask is None else np.asarray(mask, dtype=bool)] = 0.0

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        obs = self.normalize(obs)
        if self.stack is None or len(self.stack) != len(obs):
            self.stack = np.zeros((len(obs), self.frames * obs.shape[1]), dtype=obs.dtype)
        self.stack = np.roll(self.stack, -obs.shape[1], axis=1)
        self.stack[:, -obs.shape[1] :] = obs
        actions, _ = self.model.predict(self.stack, deterministic=True)
        return actions


def scripted_pilot(env_id: str, venv) -> Callable:
    """The env's scripted baseline pilot (its scene's, in ``SCENES``), for ``venv.num_envs``
    sub-envs."""
    from fluidsim_envs.scenes import SCENES

    if env_id not in SCENES:
        raise RunError(f"no scripted pilot for {env_id} (not in SCENES: {sorted(SCENES)})")
    return SCENES[env_id].pilot(venv)


def find_scene(env_id: str):
    """The registered scene ``env_id`` (``fluidsim/`` may be left out)."""
    from fluidsim_envs.scenes import SCENES

    for key in (env_id, f"fluidsim/{env_id}"):
        if key in SCENES:
            return SCENES[key]
    raise RunError(f"unknown env id {env_id!r}; the registered ones: {', '.join(SCENES)}")


# --------------------------------------------------------------------------------------------
# env overrides (--env KEY=VALUE)


def parse_env_overrides(items: Sequence[str]) -> dict[str, Any]:
    """``KEY=VALUE`` strings as a dict, each value read as YAML (``[0, 3]`` a list, ``rk4`` a
    string, ``0.005`` and ``5e-3`` numbers: :func:`~.config.parse_assignment`).

    >>> parse_env_overrides(["wind_speed_mps=[0,3]", "integrator=rk4", "dt=5e-3"])
    {'wind_speed_mps': [0, 3], 'integrator': 'rk4', 'dt': 0.005}
    """
    return dict(parse_assignment(item, "--env") for item in items)


def env_kwargs_with(env_id: str, base: Mapping[str, Any], env: Mapping[str, Any]) -> dict:
    """``base`` (the run's env kwargs, or none: the defaults) with the overrides ``env`` on
    top, checked by the env's parameter class: an unknown key or a bad value is a
    :class:`ConfigError` that names it."""
    from fluidsim_envs.scenes.base import make_params

    kwargs = {**base, **env}
    if env:
        try:
            make_params(find_scene(env_id).vector_cls.Params, kwargs)
        except (TypeError, ValueError) as e:
            raise ConfigError(f"--env: {e}") from None
    return kwargs


def format_overrides(env: Mapping[str, Any]) -> list[str]:
    """``KEY=VALUE`` strings that :func:`parse_env_overrides` reads back as ``env``."""
    out = []
    for key, value in env.items():
        text = json.dumps(list(value) if isinstance(value, tuple) else value)
        if isinstance(value, str) and _reads_back(value):
            text = value
        out.append(f"{key}={text}")
    return out


def _reads_back(text: str) -> bool:
    """``text``, read as YAML (as ``--env`` reads a value), is ``text`` again."""
    try:
        return load_yaml(text, "--env") == text
    except ConfigError:
        return False


# --------------------------------------------------------------------------------------------
# evaluating


def mean_interval(values, seed: int, confidence: float = CONFIDENCE) -> tuple[float, float]:
    """The ``confidence`` bootstrap interval of the mean of ``values`` (BCa,
    ``scipy.stats.bootstrap``; percentile where BCa cannot be computed), resampled by a
    generator seeded with ``seed``: the same values and seed give the same interval. Every
    interval of one seed resamples the same episodes (paired across metrics and policies).
    All-equal values (or one, or a non-finite one) give ``(mean, mean)``.

    >>> mean_interval([1.0, 1.0, 1.0], seed=0)
    (1.0, 1.0)
    >>> lo, hi = mean_interval(np.arange(100.0), seed=0)
    >>> lo < 49.5 < hi
    True
    """
    from scipy import stats

    x = np.asarray(values, dtype=float)
    mean = float(np.mean(x))
    if x.size < 2 or not np.isfinite(x).all() or np.ptp(x) == 0.0:
        return mean, mean
    for method in ("BCa", "percentile"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # scipy's DegenerateDataWarning: NaN, handled below
            ci = stats.bootstrap(
                (x,),
                np.mean,
                n_resamples=RESAMPLES,
                confidence_level=confidence,
                method=method,
                rng=np.random.default_rng((BOOTSTRAP_STREAM, seed)),
            ).confidence_interval
        if np.isfinite(ci.low) and np.isfinite(ci.high):
            return float(ci.low), float(ci.high)
    return mean, mean


def summarize(name: str, results: dict[str, np.ndarray], seed: int = 0) -> dict[str, Any]:
    """One table row: return mean and std, success rate, the mean of every other entry; each
    mean column ``C`` with its interval ``C_lo``, ``C_hi`` (:func:`mean_interval`)."""
    row: dict[str, Any] = {"policy": name, "episodes": len(results["return"])}

    def mean(column: str, values) -> None:
        if values is None:
            row[column] = row[f"{column}_lo"] = row[f"{column}_hi"] = np.nan
            return
        row[column] = float(np.mean(values))
        row[f"{column}_lo"], row[f"{column}_hi"] = mean_interval(values, seed)

    mean("return_mean", results["return"])
    row["return_std"] = float(np.std(results["return"]))
    mean("success_rate", results.get("success"))
    for key, values in results.items():
        # episode_steps (= length) says nothing new
        if key not in ("return", "success", "episode_steps") and not key.startswith("_"):
            mean(f"{key}_mean", values)
    return row


def _fly(name: str, venv, make_policy: Callable[[], Callable], seed: int, say) -> dict:
    """``make_policy()``'s row over the first episode of each sub-env of ``venv``, with what
    it is doing and how long it took said."""
    from fluidsim_envs.evaluation import first_episodes

    say(f"{name}: {venv.num_envs} episodes ...")
    start = time.perf_counter()
    row = summarize(name, first_episodes(venv, make_policy(), seed=seed), seed)
    say(
        f"{name}: done in {time.perf_counter() - start:.1f} s (return {row['return_mean']:.4g}"
        f", success {row['success_rate']:.3g})"
    )
    return row


def baseline_rows(
    env_id: str,
    venv,
    seed: int,
    planner: bool = True,
    planner_kwargs: Mapping[str, int] | None = None,
    say: Callable[[str], None] = lambda text: None,
) -> tuple[list[dict[str, Any]], list[str]]:
    """The baselines' rows on ``venv`` (planner, tuned pilot, on v1 the v0-tuned pilot,
    hand-set pilot, random), and
    a line for each one skipped, saying why. The planner gets ``venv`` itself: it reads the
    state of the very env the episodes run in."""
    from fluidsim_envs.evaluation import random_policy

    scene = find_scene(env_id)
    rows, skipped = [], []
    if not planner:
        skipped.append(f"{PLANNER} (--no-planner)")
        say(f"skipped: {skipped[-1]}")
    else:
        kwargs = dict(planner_kwargs or {})

        def build_planner():
            try:
                return scene.planner(venv, **kwargs)
            except (TypeError, ValueError) as e:  # a budget it refuses (--planner-*)
                raise RunError(f"{PLANNER}: {e}") from None

        rows.append(_fly(PLANNER, venv, build_planner, seed, say))
    rows.append(_fly(TUNED_PILOT, venv, lambda: scene.pilot(venv), seed, say))
    if scene.version > 0:
        gains = sys.modules[scene.pilot.__module__].GAINS.tuned(version=0)
        rows.append(_fly(V0_PILOT, venv, lambda: scene.pilot(venv, gains), seed, say))
    rows.append(_fly(HAND_PILOT, venv, lambda: scene.hand_pilot(venv), seed, say))
    rows.append(_fly(RANDOM, venv, lambda: random_policy(venv, seed), seed, say))
    return rows, skipped


def _make_venv(env_id: str, episodes: int, env_kwargs: Mapping[str, Any]):
    """The env, one sub-env per episode."""
    import gymnasium as gym

    import fluidsim_envs  # noqa: F401  (registers the ids)

    return gym.make_vec(
        env_id, num_envs=episodes, vectorization_mode="vector_entry_point", **env_kwargs
    )


def _check_counts(
    episodes: int, planner_kwargs: Mapping[str, int] | None, seed: int, say=print
) -> None:
    from fluidsim_envs.evaluation import TUNING_SEEDS

    if episodes < 1:
        raise RunError(f"--episodes must be at least 1, got {episodes}")
    if not 0 <= seed < 2**63:
        raise RunError(f"--seed must be a non-negative integer, got {seed}")
    if seed in TUNING_SEEDS:  # allowed (a check of the tuning), but not an honest score
        say(f"warning: --seed {seed} is a tuning seed of the v0 pilots: their gains were "
            "tuned on these episodes (the v1 gains on the tuning stream, which no evaluation "
            "flies)")  # fmt: skip
    for key, value in (planner_kwargs or {}).items():
        if value < 1:
            raise RunError(f"--planner-{key} must be at least 1, got {value}")


@threads.on_owned_threads
def evaluate(
    run_dir: Path,
    episodes: int,
    seed: int,
    rerun: Path | None = None,
    which: str = "final",
    *,
    env: Mapping[str, Any] | None = None,
    planner: bool = True,
    planner_kwargs: Mapping[str, int] | None = None,
    out: Path | None = None,
    say: Callable[[str], None] = lambda text: None,
    allow_pickle: bool = False,
) -> list[dict[str, Any]]:
    """Evaluate the run's model (``which``: final or best; ``allow_pickle``: SB3's pickled
    files too, :mod:`.saved`) and the baselines
    (:func:`baseline_rows`) on the same ``episodes`` seeded episodes of the run's env, with
    the parameters ``env`` on top of the run's; write ``evaluation.csv`` (``which`` best:
    ``evaluation_best.csv``) into the run, or into ``out``, and return its rows. ``say``
    hears what is being evaluated and how long each policy took."""
    env = dict(env or {})
    _check_counts(episodes, planner_kwargs, seed, say)
    cfg, model = load_run(run_dir, which, allow_pickle)
    env_kwargs = env_kwargs_with(cfg.env_id, cfg.env_kwargs, env)
    label = f"trained {cfg.algorithm.name.upper()}" + (" (best)" if which == "best" else "")

    venv = _make_venv(cfg.env_id, episodes, env_kwargs)
    trained_env = venv
    if rerun is not None:
        rerun.parent.mkdir(parents=True, exist_ok=True)
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
    try:
        policy = model_policy(cfg, model, run_dir, venv, which, allow_pickle)
        rows = [_fly(label, trained_env, lambda: policy, seed, say)]
    finally:
        if trained_env is not venv:
            trained_env.close()  # closes the recording (and the env under it)
    if trained_env is not venv:  # the logger closed it: a fresh one for the baselines
        venv = _make_venv(cfg.env_id, episodes, env_kwargs)
    try:
        baselines, skipped = baseline_rows(cfg.env_id, venv, seed, planner, planner_kwargs, say)
    finally:
        venv.close()
    rows += baselines
    command = _command(
        [run_dir.name, "--model", which], episodes, seed, env, planner, planner_kwargs, out
    )
    comments = [
        *run_provenance(run_dir, which, command),
        _env_line(env, "the run's env_kwargs"),
        *_method_lines(rows, skipped),
    ]
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, (out or run_dir) / csv_name(which), seed, comments)
    return rows


@threads.on_owned_threads
def evaluate_baselines(
    env_id: str,
    episodes: int,
    seed: int,
    out: Path,
    *,
    env: Mapping[str, Any] | None = None,
    planner: bool = True,
    planner_kwargs: Mapping[str, int] | None = None,
    say: Callable[[str], None] = lambda text: None,
) -> list[dict[str, Any]]:
    """Evaluate the baselines alone (:func:`baseline_rows`) on ``episodes`` seeded episodes
    of ``env_id`` with the parameters ``env`` on top of its defaults; write
    ``out/evaluation.csv`` (the layout of a run's) and return its rows."""
    from .train import git_revision

    env = dict(env or {})
    _check_counts(episodes, planner_kwargs, seed, say)
    scene = find_scene(env_id)
    env_kwargs = env_kwargs_with(scene.id, {}, env)
    if out.exists() and not out.is_dir():
        raise RunError(f"--out {out}: not a folder")
    venv = _make_venv(scene.id, episodes, env_kwargs)
    try:
        rows, skipped = baseline_rows(scene.id, venv, seed, planner, planner_kwargs, say)
    finally:
        venv.close()
    git = git_revision() or {}
    dirty = " (dirty)" if git.get("dirty") else ""
    command = _command(["--env-id", scene.id], episodes, seed, env, planner, planner_kwargs, out)
    comments = [
        f"command: {command}",
        f"baselines only: {scene.id}, git {git.get('revision', '?')}{dirty}",
        _env_line(env, "the env's defaults"),
        *_method_lines(rows, skipped),
    ]
    out.mkdir(parents=True, exist_ok=True)
    write_csv(rows, out / csv_name("final"), seed, comments)
    return rows


def csv_name(which: str) -> str:
    """The table a run's evaluation of its ``which`` model writes."""
    return "evaluation.csv" if which == "final" else f"evaluation_{which}.csv"


def _command(
    head: list[str],
    episodes: int,
    seed: int,
    env: Mapping[str, Any],
    planner: bool,
    planner_kwargs: Mapping[str, int] | None,
    out: Path | None,
) -> str:
    """The command line that evaluates this again."""
    words = ["fluidsim-evaluate", *head, "--episodes", episodes, "--seed", seed]
    for item in format_overrides(env):
        words += ["--env", item]
    if not planner:
        words.append("--no-planner")
    for key, value in (planner_kwargs or {}).items():
        words += [f"--planner-{key}", value]
    if out is not None:
        words += ["--out", out]
    return shlex.join(map(str, words))


def _env_line(env: Mapping[str, Any], base: str) -> str:
    if not env:
        return f"env overrides: none ({base})"
    return f"env overrides: {' '.join(format_overrides(env))} (on {base})"


def _method_lines(rows: list[dict[str, Any]], skipped: list[str]) -> list[str]:
    lines = [
        f"rows: {', '.join(r['policy'] for r in rows)}"
        + (f"; skipped: {', '.join(skipped)}" if skipped else ""),
        f"intervals: each mean's {CONFIDENCE:.0%} bootstrap interval over the episodes "
        f"(_lo, _hi; scipy.stats.bootstrap, BCa, percentile where BCa fails; {RESAMPLES} "
        "resamples, seeded; all-equal values give [mean, mean])",
        f"cpu: {target_cpu()} (the kernels' target: on such a CPU these numbers again to the "
        "bit; another rounds the last bits differently)",
    ]
    return lines


def run_provenance(run_dir: Path, which: str, command: str) -> list[str]:
    """The ``#`` lines an evaluation table of a run starts with: the command that wrote it
    and the run and model it evaluated, so a copy of the table (in docs/) says where it came
    from."""
    try:
        meta = read_run_meta(run_dir)
    except (ConfigError, RunError):  # the table still says what it can
        meta = {}
    git = meta.get("git") or {}
    dirty = " (dirty)" if git.get("dirty") else ""
    return [
        f"command: {command}",
        f"run: {run_dir.name}, trained by: {meta.get('command_line', '?')}",
        f"model: {which} at {meta.get('num_timesteps', '?')} timesteps of "
        f"{meta.get('env_id', '?')}, git {git.get('revision', '?')}{dirty}",
    ]


def write_csv(rows: list[dict[str, Any]], path: Path, seed: int, comments: list[str] = ()) -> None:
    """The table (``#`` lines first: :func:`run_provenance`); readers skip lines starting
    ``#``."""
    columns = ["seed", *dict.fromkeys(k for row in rows for k in row)]
    f = io.StringIO(newline="")
    f.writelines(f"# {line}\n" for line in comments)
    writer = csv.DictWriter(f, columns)
    writer.writeheader()
    for row in rows:
        writer.writerow({"seed": seed, **row})
    files.write_text(path, f.getvalue())


def _number(value) -> str:
    return f"{value:d}" if isinstance(value, int) else f"{value:.4g}"


def format_table(rows: list[dict[str, Any]]) -> str:
    """Metrics down, policies across; a mean with an interval as ``mean [lo, hi]``."""
    keys = list(dict.fromkeys(k for row in rows for k in row))
    bounds = {f"{k}_{end}" for k in keys for end in ("lo", "hi") if f"{k}_lo" in keys}
    keys = [k for k in keys if k != "policy" and k not in bounds]
    cells = {}
    for row in rows:
        for key in keys:
            value = row.get(key, np.nan)
            text = _number(value)
            if f"{key}_lo" in row and np.isfinite(value):
                text += f" [{_number(row[f'{key}_lo'])}, {_number(row[f'{key}_hi'])}]"
            cells[row["policy"], key] = text
    width = max(len(k) for k in keys)
    col = max(12, *(len(row["policy"]) for row in rows), *(len(t) for t in cells.values()))
    lines = [" " * width + "".join(f"  {row['policy']:>{col}}" for row in rows)]
    for key in keys:
        lines.append(
            f"{key:<{width}}" + "".join(f"  {cells[row['policy'], key]:>{col}}" for row in rows)
        )
    return "\n".join(lines)


# --------------------------------------------------------------------------------------------
# the command line

USAGE = """%(prog)s RUN [--model final|best] [options]
       %(prog)s --env-id ID --out DIR [options]"""

DESCRIPTION = """\
Evaluate a training run beside the baselines (the planner, which knows the true state; the
tuned and the hand-set pilot; a random policy), or the baselines alone, on the same seeded
episodes, with 95% confidence intervals. It says which policy it is flying and how long each
took (the planner: minutes for 256 episodes)."""

EPILOG = """\
examples:
  {prog} runs/demo --model best --episodes 256 --rerun runs/demo/ep.rrd
  {prog} runs/demo --episodes 256 --env wind_speed_mps=[0,3] --out runs/demo/windy
  {prog} --env-id {example} --episodes 256 --out baselines/{short} --no-planner

The CSV holds one row per policy: the mean of the return, the success rate and each scalar
info entry, each with its {confidence:.0%} bootstrap interval over the episodes (columns
<mean>_lo, <mean>_hi; printed as mean [lo, hi]), and the return's std.
"""


def parse_args(argv: list[str] | None, prog: str) -> argparse.Namespace:
    from fluidsim_envs.evaluation import EVAL_SEED
    from fluidsim_envs.scenes import SCENES

    example = next(iter(SCENES))  # the help's example env: the first registered
    parser = argparse.ArgumentParser(
        prog=prog,
        usage=USAGE,
        description=DESCRIPTION,
        epilog=EPILOG.format(
            prog=prog, confidence=CONFIDENCE, example=example, short=example.split("/")[1]
        ),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    what = parser.add_argument_group("what to evaluate (a run folder, or --env-id and --out)")
    what.add_argument(
        "run", type=Path, nargs="?", help="the run folder (written by fluidsim-train)"
    )
    what.add_argument(
        "--env-id",
        metavar="ID",
        help=f"no run: evaluate the baselines alone on this env (e.g. {example})",
    )
    what.add_argument(
        "--model", choices=list(MODELS), help="which model of the run (default: final)"
    )
    what.add_argument(
        "--allow-pickle",
        action="store_true",
        help="load SB3's pickled model.zip and vecnormalize.pkl where the run has no "
        "safetensors files (an older version's run): unpickling runs any code the files "
        "carry, so only for files you trust",
    )
    episodes = parser.add_argument_group("the episodes")
    episodes.add_argument(
        "--episodes",
        type=int,
        default=100,
        metavar="N",
        help="seeded episodes per policy (default: 100)",
    )
    episodes.add_argument(
        "--seed",
        type=int,
        default=EVAL_SEED,
        metavar="S",
        help=f"seed of the episodes (default: {EVAL_SEED}, the docs' tables' seed)",
    )
    episodes.add_argument(
        "--env",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="set an env parameter on top of the run's (or the env's defaults), the value "
        "read as YAML; repeatable (e.g. --env wind_speed_mps=[0,3] --env integrator=rk4)",
    )
    planner = parser.add_argument_group("the planner (oracle: it reads the true state)")
    planner.add_argument(
        "--planner-samples",
        type=int,
        metavar="K",
        help="candidate plans per decision (default: its own)",
    )
    planner.add_argument(
        "--planner-horizon",
        type=int,
        metavar="H",
        help="the length of each plan (default: its own)",
    )
    planner.add_argument(
        "--no-planner", action="store_true", help="skip the planner (it takes minutes)"
    )
    output = parser.add_argument_group("output")
    output.add_argument(
        "--out",
        type=Path,
        metavar="DIR",
        help="write DIR/evaluation.csv (needed with --env-id; with a run, instead of the run "
        "folder: keeps an out-of-distribution table apart)",
    )
    output.add_argument("--rerun", type=Path, metavar="FILE.rrd", help="log to a Rerun file")
    return parser.parse_args(argv)


def _argument_error(args: argparse.Namespace) -> str | None:
    """What is wrong with the combination of arguments, or None."""
    if args.run is not None and args.env_id is not None:
        return (
            "pass a run folder or --env-id, not both (a run is evaluated on its own env: "
            "change its parameters with --env KEY=VALUE)"
        )
    if args.run is None and args.env_id is None:
        return (
            "pass a run folder (its model beside the baselines) or --env-id ID --out DIR "
            "(the baselines alone)"
        )
    if args.env_id is not None:
        if args.out is None:
            return "--env-id needs --out DIR (where evaluation.csv goes)"
        flags = {"--model": args.model, "--rerun": args.rerun, "--allow-pickle": args.allow_pickle}
        given = [f for f, v in flags.items() if v]
        if given:
            verb = "needs" if len(given) == 1 else "need"
            return f"{' and '.join(given)} {verb} a run folder (--env-id evaluates no model)"
    if args.no_planner and (args.planner_samples, args.planner_horizon) != (None, None):
        return "--planner-samples and --planner-horizon set the planner that --no-planner skips"
    return None


def check_output_paths(args: argparse.Namespace) -> None:
    """Where the evaluation will write (``--rerun``, ``--out``, else the run folder) can be
    written: checked before any episode is flown, a :class:`RunError` naming the path."""
    if args.rerun is not None:
        files.check_writable_file(args.rerun, "--rerun")
    if args.out is not None:
        files.check_writable_folder(args.out, "--out")
    elif args.run is not None and args.run.is_dir():
        files.check_writable_folder(args.run, "run folder")


def main(argv: list[str] | None = None, prog: str = "fluidsim-evaluate") -> int:
    args = parse_args(argv, prog)
    problem = _argument_error(args)
    if problem:
        print(f"{prog}: error: {problem}", file=sys.stderr)
        return 2
    planner_kwargs = {
        key: value
        for key, value in (("samples", args.planner_samples), ("horizon", args.planner_horizon))
        if value is not None
    }
    options = dict(
        planner=not args.no_planner,
        planner_kwargs=planner_kwargs,
        say=lambda text: print(text, flush=True),
    )
    which = args.model or "final"
    # evaluate() and evaluate_baselines() run on these (threads.on_owned_threads)
    print(threads.choose().describe(), flush=True)
    try:
        check_output_paths(args)
        env = parse_env_overrides(args.env)
        what = args.run if args.run is not None else args.env_id
        overrides = f", env overrides: {' '.join(format_overrides(env))}" if env else ""
        print(f"{what}: {args.episodes} episodes, seed {args.seed}{overrides}", flush=True)
        if args.run is not None:
            rows = evaluate(
                args.run, args.episodes, args.seed, args.rerun, which, env=env, out=args.out,
                allow_pickle=args.allow_pickle, **options,
            )  # fmt: skip
        else:
            rows = evaluate_baselines(
                args.env_id, args.episodes, args.seed, args.out, env=env, **options
            )
    except (ConfigError, RunError) as e:
        print(f"{prog}: error: {e}", file=sys.stderr)
        return 2
    print(f"means with their {CONFIDENCE:.0%} bootstrap intervals over the episodes:")
    print(format_table(rows))
    print(f"written: {(args.out or args.run) / csv_name(which)}")
    if args.rerun is not None:
        print(
            f"rerun recording: {args.rerun}  (view it: rerun {args.rerun}; on a machine "
            f"without a display: rerun --web-viewer {args.rerun})"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main(prog="python -m fluidsim_envs.rl.evaluate"))
