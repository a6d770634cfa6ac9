"""The Stable-Baselines3 parts of a run that write into its folder, written so that a kill at
any moment leaves it resumable (see :mod:`.runs`):

- :class:`Checkpoints`: SB3's ``CheckpointCallback`` with atomic writes, the model last;
- :class:`Evaluations`: SB3's ``EvalCallback`` with atomic writes, the best model replaced
  only by a better score than the run's best so far (kept in ``best/best.yaml`` across
  resumes), and the evaluation history continued;
- :class:`RunMonitor`: SB3's ``VecMonitor`` whose ``monitor.csv`` rows carry the run's
  timesteps and whose time column goes on across resumes.

Both callbacks act when the run's timesteps reach a multiple of their period, not every so
many calls of this session: a resumed run keeps the schedule it began with.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from stable_baselines3.common.callbacks import BaseCallback
from stable_baselines3.common.evaluation import evaluate_policy
from stable_baselines3.common.monitor import ResultsWriter
from stable_baselines3.common.vec_env import VecMonitor, sync_envs_normalization

from .runs import MONITOR_STEPS, BestModel, EvalLog, checkpoint_paths, save_state


class Checkpoints(BaseCallback):
    """Every ``period`` timesteps: the model, its normalization statistics and (``replay``)
    its replay buffer into ``run_dir/checkpoints`` (:func:`~.runs.save_state`)."""

    def __init__(self, run_dir: Path, period: int, replay: bool) -> None:
        super().__init__()
        self.run_dir, self.period, self.replay = run_dir, period, replay

    def _on_step(self) -> bool:
        if self.num_timesteps % self.period == 0:
            save_state(self.model, checkpoint_paths(self.run_dir, self.num_timesteps), self.replay)
        return True


#: what :class:`Evaluations` tells after each evaluation: timesteps, the episodes' returns,
#: their successes, whether the model became the new best; False back ends the training (as
#: an SB3 callback's False does: the run then finishes as at its end)
Report = Callable[[int, Sequence[float], Sequence[float], bool], bool | None]


class Evaluations(BaseCallback):
    """Every ``period`` timesteps: ``n_episodes`` deterministic episodes on ``eval_env``
    (reseeded with ``seed`` first, so each evaluation flies the same ones; normalized with the
    training env's statistics of the moment). Then, in this order: the best model when the
    mean return beats ``best``'s score, the evaluation into ``log`` (saved, with the run's
    wall-clock seconds that ``clock`` tells), TensorBoard's ``eval/`` scalars, and ``report``.

    Put it before :class:`Checkpoints` in the callback list: a checkpoint at the same step
    then comes after the evaluation is saved, so a resume from it never lacks it, and a kill
    during it leaves the previous checkpoint, from which the evaluation runs again."""

    def __init__(
        self,
        eval_env,
        period: int,
        n_episodes: int,
        seed: int,
        log: EvalLog,
        best: BestModel,
        report: Report,
        clock: Callable[[], float] = lambda: float("nan"),
    ) -> None:
        super().__init__()
        self.eval_env, self.period, self.n_episodes, self.seed = eval_env, period, n_episodes, seed
        self.log, self.best, self.report, self.clock = log, best, report, clock

    def _on_training_start(self) -> None:
        # Ctrl-C during the evaluation at step S saves the interrupt checkpoint at S without
        # that evaluation: a run resumed from there evaluates first, so its history keeps
        # every period
        n = self.num_timesteps
        if n and n % self.period == 0 and n not in self.log.timesteps:
            self._evaluate()

    def _on_step(self) -> bool:
        if self.num_timesteps % self.period == 0:
            return self._evaluate() is not False
        return True

    def _evaluate(self) -> bool | None:
        returns, lengths, successes = self._episodes()
        mean = float(np.mean(returns))
        new_best = mean > self.best.score
        if new_best:
            self.best.save(self.model, self._record(returns, successes))
        self.log.add(self.num_timesteps, returns, lengths, successes, self.clock())
        self.log.save()
        self._to_logger(returns, lengths, successes)
        return self.report(self.num_timesteps, returns, successes, new_best)

    def _episodes(self) -> tuple[list[float], list[int], list[float]]:
        """Returns, lengths and (where the env reports ``is_success``) successes."""
        if self.model.get_vec_normalize_env() is not None:
            sync_envs_normalization(self.training_env, self.eval_env)
        self.eval_env.seed(self.seed)
        successes: list[float] = []

        def on_step(local_vars: dict, _globals: dict) -> None:
            flag = local_vars["info"].get("is_success") if local_vars["done"] else None
            if flag is not None:
                successes.append(float(flag))

        returns, lengths = evaluate_policy(
            self.model,
            self.eval_env,
            n_eval_episodes=self.n_episodes,
            deterministic=True,
            return_episode_rewards=True,
            callback=on_step,
        )
        return list(returns), list(lengths), successes

    def _record(self, returns, successes) -> dict:
        return {
            "mean_return": float(np.mean(returns)),
            "std_return": float(np.std(returns)),
            "success_rate": float(np.mean(successes)) if successes else None,
            "timesteps": int(self.num_timesteps),
            "evaluated": time.strftime("%Y-%m-%dT%H:%M:%S"),
        }

    def _to_logger(self, returns, lengths, successes) -> None:
        """TensorBoard's ``eval/`` scalars, written at this step (as SB3's EvalCallback)."""
        self.logger.record("eval/mean_reward", float(np.mean(returns)))
        self.logger.record("eval/mean_ep_length", float(np.mean(lengths)))
        if successes:
            self.logger.record("eval/success_rate", float(np.mean(successes)))
        self.logger.record("time/total_timesteps", self.num_timesteps, exclude="tensorboard")
        self.logger.dump(self.num_timesteps)


class _StampedWriter(ResultsWriter):
    """``monitor.csv``'s writer: each row gets the run's timesteps when it is written."""

    def __init__(self, monitor: RunMonitor, *args, **kwargs) -> None:
        self.monitor = monitor
        super().__init__(*args, **kwargs)

    def write_row(self, epinfo: dict) -> None:
        super().write_row({**epinfo, MONITOR_STEPS: self.monitor.timesteps})


class RunMonitor(VecMonitor):
    """``VecMonitor`` writing ``path`` (``monitor.csv``; appended to with ``append``) whose
    rows carry, besides SB3's ``r, l, t`` and ``info_keywords``, the run's timesteps when the
    episode ended (``start_timesteps`` plus ``num_envs`` per step, as SB3 counts its
    ``num_timesteps``). Its time column goes on from ``time_offset_s`` (a resumed run: the
    time its rows had reached), so it never steps back."""

    def __init__(
        self,
        venv,
        path: Path,
        env_id: str,
        info_keywords: tuple[str, ...] = (),
        *,
        start_timesteps: int = 0,
        time_offset_s: float = 0.0,
        append: bool = False,
    ) -> None:
        super().__init__(venv, info_keywords=info_keywords)
        self.timesteps = start_timesteps
        self.t_start -= time_offset_s  # VecMonitor's t is time.time() - t_start
        self.results_writer = _StampedWriter(
            self,
            str(path),
            header={"t_start": self.t_start, "env_id": env_id},
            extra_keys=(*info_keywords, MONITOR_STEPS),
            override_existing=not append,
        )

    def step_wait(self):
        self.timesteps += self.num_envs
        return super().step_wait()


class Curriculum(BaseCallback):
    """At the first rollout's end at or past each of ``starts``' timesteps (timestep, env
    parameters, a label that says them), the training env steps episodes of that stage's
    parameters: ``make(env_kwargs)`` builds its native vector
    env, which replaces the adapter's (:meth:`~fluidsim_envs.wrappers.sb3.SB3VecEnv.replace`),
    seeded with ``seed_at(timestep)``; then every env starts afresh (the episodes in flight
    are dropped, not recorded). Between rollouts, so no rollout mixes two stages; the
    normalization statistics go on. ``say`` tells the switch."""

    def __init__(
        self,
        starts: Sequence[tuple[int, dict, str]],
        make: Callable[[dict], object],
        seed_at: Callable[[int], int],
        say: Callable[[str], None],
    ) -> None:
        super().__init__()
        self.starts, self.make, self.seed_at, self.say = list(starts), make, seed_at, say

    def _on_step(self) -> bool:
        return True

    def _on_rollout_end(self) -> None:
        if not self.starts or self.num_timesteps < self.starts[0][0]:
            return
        _, env_kwargs, label = self.starts.pop(0)
        while self.starts and self.num_timesteps >= self.starts[0][0]:
            _, env_kwargs, label = self.starts.pop(0)  # a stage shorter than a rollout: skipped
        adapter = self.training_env.unwrapped
        adapter.replace(self.make(env_kwargs))
        adapter.seed(self.seed_at(self.num_timesteps))
        model = self.model
        model._last_obs = self.training_env.reset()
        model._last_episode_starts = np.ones(self.training_env.num_envs, dtype=bool)
        if hasattr(model, "_last_original_obs") and model.get_vec_normalize_env() is not None:
            # off-policy: the replay buffer stores the unnormalized observation (without
            # VecNormalize, SB3 sets it from _last_obs at the next step)
            model._last_original_obs = model.get_vec_normalize_env().get_original_obs()
        self.say(f"curriculum: from {self.num_timesteps:,} timesteps on, {label}")


__all__ = ["Checkpoints", "Curriculum", "Evaluations", "RunMonitor"]
