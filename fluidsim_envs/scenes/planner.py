"""A sampling model-predictive planner on the true physics: the reference a policy is measured
against (how well could one do at all?).

At each decision it copies the true state of every episode it flies (``get_state``: a
privileged oracle of the present, which knows the state and the episode's drawn physics, not
only the observation) into ``samples`` rollouts each of a private vector env of the same scene
and parameters, flies ``horizon`` actions of candidate plans there, and acts on the best plan.

It does not know the noise to come. An episode's turbulence, currents and sensor noise are
numbers of its noise key (``scenes/noise.py``), which a snapshot carries; the rollouts get
keys of their own instead (``noise.foreign_keys``: none is any episode's), a fresh one each
rollout and decision, so a plan is scored against noise like the episode's, not the
episode's own. What an episode draws at its start for later is drawn again where it is still
ahead (``FluidVectorEnv.redraw_future``): the dart's gust that has not begun, the lead
submarine's route from the segment it is on. ``PlannerConfig.clairvoyant`` keeps the episode's
keys and draws: a reference that sees the coming gusts and turns (the planner before issue
44), labelled so wherever it is flown.

The method is the cross-entropy method in the form of iCEM (Pinneri et al., 2020, "Sample-
efficient cross-entropy method for real-time planning"), chosen over MPPI because:

- the model is the env itself, bit for bit (``tests/scenes/test_snapshot.py``), so a rollout's
  return is exactly what flying that plan earns: acting on the best evaluated plan is exact,
  where MPPI acts on a weighted average of plans that nobody evaluated (and the average of a
  left turn and a right turn around a target is neither);
- the best plan of the last decision, one knot on, is a candidate again (iCEM's kept
  elite), so a good plan is not lost to sampling noise;
- time-correlated (coloured, 1/f^beta) noise gives smooth control-surface sequences at 20-30
  actions per second, where white noise mostly cancels out over a few actions.

The plan's score is the env's own reward summed over the horizon, up to the end of the
episode (no value estimate beyond it): the horizon must reach far enough for the reward to
tell plans apart.

Guided (``PlannerConfig.guided``, each scene's default): a plan is a sequence of offsets added
to the scene's tuned pilot, which flies closed loop in every rollout (from a copy of its
memory: the arrays its ``memory`` names, the episode first). The pilot alone, all offsets
zero, is then the first incumbent, so the planner starts from the pilot's plan and keeps it
unless a sampled plan earns more over the look-ahead; the pilot's feedback carries what a
look-ahead of seconds cannot see (a course of gates, a station held for a minute).
Unguided, plans are the actions themselves.
"""

from __future__ import annotations

import copy
import dataclasses
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from . import noise as NZ
from .base import FluidVectorEnv
from .snapshot import EnvState


@dataclass(frozen=True)
class PlannerConfig:
    """The planner's budget and sampling (per episode it flies; ``samples * horizon *
    iterations`` env-steps per decision)."""

    samples: int = 32  # candidate plans per iteration (K)
    horizon: int = 30  # knots per plan (H)
    # actions each knot of a plan holds, and the actions flown between two plans: a plan
    # sees horizon * hold actions ahead for the cost of horizon per action flown
    hold: int = 1
    iterations: int = 1  # CEM rounds per decision
    elites: int = 4  # the best plans a round refits the sampling distribution to
    noise_std: float = 0.5  # the first round's spread of each action (of [-1, 1])
    noise_beta: float = 2.0  # coloured noise: power spectrum ~ 1/f^beta along the plan
    momentum: float = 0.1  # share of the old mean and spread kept at each refit
    guided: bool = False  # plans are offsets to the scene's pilot flying closed loop
    # the rollouts keep the episode's noise keys: they fly its future gusts, currents and
    # sensor noise (a labelled reference); else each rollout draws keys of its own
    clairvoyant: bool = False
    seed: int = 0  # the planner's own generator (the episodes' are the env's)

    def __post_init__(self) -> None:
        for key in ("samples", "horizon", "hold", "iterations", "elites"):
            value = getattr(self, key)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
                raise ValueError(f"planner: {key} must be a positive integer, got {value!r}")
        if self.elites > self.samples:
            raise ValueError(
                f"planner: elites ({self.elites}) must not exceed samples ({self.samples})"
            )
        for key in ("guided", "clairvoyant"):
            if not isinstance(getattr(self, key), bool):
                raise ValueError(
                    f"planner: {key} must be True or False, got {getattr(self, key)!r}"
                )
        for key, lo, hi in (("noise_std", 0.0, 2.0), ("noise_beta", 0.0, 4.0), ("momentum", 0, 1)):
            value = getattr(self, key)
            number = isinstance(value, (int, float, np.floating)) and not isinstance(value, bool)
            if not (number and lo <= value <= hi):
                raise ValueError(f"planner: {key} must be in [{lo}, {hi}], got {value!r}")

    @property
    def budget(self) -> int:
        """Env-steps of rollouts per action flown, per episode."""
        return self.samples * self.horizon * self.iterations

    @property
    def lookahead(self) -> int:
        """Actions a plan reaches ahead."""
        return self.horizon * self.hold


def coloured_noise(rng: np.random.Generator, shape: tuple[int, ...], beta: float) -> np.ndarray:
    """Gaussian noise with unit variance whose power falls as 1/f^beta along axis -2 (the
    plan's time axis): beta 0 is white, 2 is smooth (iCEM's choice)."""
    steps = shape[-2]
    freqs = np.fft.rfftfreq(steps)
    freqs[0] = freqs[1] if steps > 1 else 1.0
    scale = freqs ** (-beta / 2.0)
    spectrum = rng.normal(size=(*shape[:-2], freqs.size, shape[-1], 2)) * scale[:, None, None]
    noise = np.fft.irfft(spectrum[..., 0] + 1j * spectrum[..., 1], n=steps, axis=-2)
    std = noise.std(axis=-2, keepdims=True)
    return noise / np.where(std > 0, std, 1.0)


class Planner:
    """iCEM over a private copy of ``venv``: a policy ``obs -> actions`` for all its sub-envs,
    with ``reset(mask)``, as the scripted pilots.

    Args:
        venv: the vector env the episodes run in (its ``unwrapped`` is read: get_state).
        config: the budget and sampling (:class:`PlannerConfig`).
        pilot: with ``config.guided``, the pilot factory (``pilot(venv) -> policy``, a
            scene's ``Scene.pilot``) whose actions the plans' offsets add to.

    Every ``config.hold`` actions it plans again for all sub-envs; and at once after
    ``reset(mask)`` (a sub-env started a new episode), so that no episode flies a plan made
    for another (the others' plans are scored again from where they are). A sub-env whose
    episode the caller no longer counts is planned for all the same: the batch is stepped
    whole. ``timing`` holds the seconds spent so far: ``total`` in calls, ``rollout``
    in the private env's steps, ``physics`` in its ``Simulator.step`` (the planner is bound
    by env speed); ``plans`` and ``decisions`` count plans made and actions returned.
    """

    def __init__(
        self, venv, config: PlannerConfig = PlannerConfig(), pilot: Callable | None = None
    ) -> None:
        env = venv.unwrapped
        if not isinstance(env, FluidVectorEnv):
            raise TypeError(f"planner: needs a fluidsim vector env, got {type(env).__name__}")
        if not isinstance(config, PlannerConfig):
            raise TypeError(f"planner: config must be a PlannerConfig, got {config!r}")
        self.env, self.config = env, config
        E, K, H = env.num_envs, config.samples, config.horizon
        self.num_actions = A = len(env.action_names)
        params = {f.name: getattr(env.params, f.name) for f in dataclasses.fields(env.params)}
        # autoreset on: a rollout whose episode ends steps on harmlessly (masked in _score)
        self.rollouts = type(env)(num_envs=E * K, **params)
        self.rng = np.random.default_rng(config.seed)
        self.mean = np.zeros((E, H, A))  # the sampling distribution's centre, in knots
        self.best = np.zeros((E, H, A))  # the plan being flown
        self.value = np.zeros(E)  # its return over the look-ahead, as the rollouts scored it
        self.flown = 0  # actions flown of the plan's first knot
        self.stale = True  # plan at the next call: the first, or after a reset
        if config.guided and pilot is None:
            raise ValueError("planner: guided plans need the pilot they add to (pilot=)")
        # the pilot of the episodes, and one for the rollouts (its memory copied at each plan)
        self.pilot = pilot(env) if config.guided else None
        self.rollout_pilot = pilot(self.rollouts) if config.guided else None
        if config.guided and not isinstance(getattr(self.pilot, "memory", None), tuple):
            raise TypeError(
                f"planner: guided plans need a pilot that names its per-episode memory "
                f"(a tuple 'memory' of array attributes), not {type(self.pilot).__name__}"
            )
        self.timing = {"total": 0.0, "rollout": 0.0, "physics": 0.0, "plans": 0, "decisions": 0}
        step = self.rollouts.sim.step

        def timed_step(*args, **kwargs):
            t0 = time.perf_counter()
            step(*args, **kwargs)
            self.timing["physics"] += time.perf_counter() - t0

        self.rollouts.sim.step = timed_step

    def reset(self, mask=None) -> None:
        """New episodes in the sub-envs of ``mask`` (all when None): forget their plans and
        plan again at the next call."""
        rows = slice(None) if mask is None else np.asarray(mask, dtype=bool)
        self.mean[rows] = 0.0
        self.best[rows] = 0.0
        if self.pilot is not None and hasattr(self.pilot, "reset"):
            self.pilot.reset(mask)
        if mask is None or np.any(mask):
            self.stale = True

    def __call__(self, obs) -> np.ndarray:
        """The actions for the env's current state (``obs`` is not read: the planner reads
        the true state, and its pilot the env's own observation)."""
        t0 = time.perf_counter()
        if self.flown >= self.config.hold or self.stale:
            # a plan made after a reset, mid-knot, keeps the knots as they are: the first
            # one then runs a whole knot from here
            self._plan(shift=self.flown >= self.config.hold)
            self.flown, self.stale = 0, False
        action = self.best[:, 0]
        if self.pilot is not None:  # the pilot's memory moves on with the episode's
            action = np.clip(self.pilot(self.env.observation) + action, -1.0, 1.0)
        self.flown += 1
        self.timing["decisions"] += 1
        self.timing["total"] += time.perf_counter() - t0
        return np.array(action)

    def _plan(self, shift: bool) -> None:
        cfg = self.config
        E, K, H, A = self.env.num_envs, cfg.samples, cfg.horizon, self.num_actions
        start = self._present(self.env.get_state().repeat(K))
        # warm start: the last plan and the distribution's centre, one knot on (the last
        # held) when the first knot was flown
        if shift:
            self.mean = np.concatenate([self.mean[:, 1:], self.mean[:, -1:]], axis=1)
            self.best = np.concatenate([self.best[:, 1:], self.best[:, -1:]], axis=1)
        best_plan = self.best
        best_value = np.full(E, -np.inf)
        std = np.full((E, H, A), cfg.noise_std)
        rows = np.arange(E)
        for _ in range(cfg.iterations):
            noise = coloured_noise(self.rng, (E, K, H, A), cfg.noise_beta)
            plans = np.clip(self.mean[:, None] + std[:, None] * noise, -1.0, 1.0)
            plans[:, 0] = best_plan  # the incumbent, scored again
            if K > 1:
                plans[:, 1] = np.clip(self.mean, -1.0, 1.0)  # the distribution's centre
            value = self._score(start, plans)
            top = np.argsort(-value, axis=1)[:, : cfg.elites]
            elite = np.take_along_axis(plans, top[:, :, None, None], axis=1)
            self.mean = cfg.momentum * self.mean + (1 - cfg.momentum) * elite.mean(axis=1)
            std = cfg.momentum * std + (1 - cfg.momentum) * elite.std(axis=1)
            better = value[rows, top[:, 0]] > best_value
            best_plan = np.where(better[:, None, None], elite[:, 0], best_plan)
            best_value = np.where(better, value[rows, top[:, 0]], best_value)
        self.best, self.value = best_plan, best_value
        self.timing["plans"] += 1

    def _present(self, start: EnvState) -> EnvState:
        """The rollouts' start: the episodes' snapshot, with noise keys of the planner's own
        unless it is clairvoyant (see the module's docstring)."""
        if self.config.clairvoyant:
            return start
        task = self.env.redraw_future(start.task, self.rng)
        if "noise_keys" in task:
            task = {**task, "noise_keys": NZ.foreign_keys(self.rng, len(start))}
        return dataclasses.replace(start, task=task)

    def _score(self, start, plans: np.ndarray) -> np.ndarray:
        """Each plan's return up to its look-ahead or its episode's end, ``[E, K]``."""
        E, K, H, A = plans.shape
        env, hold = self.rollouts, self.config.hold
        obs = env.set_state(start)
        pilot = None
        if self.pilot is not None:
            pilot = copy.copy(self.rollout_pilot)
            _copy_memory(self.pilot, pilot, K)
        t0 = time.perf_counter()
        value = np.zeros(E * K)
        alive = np.ones(E * K, dtype=bool)
        flat = plans.reshape(E * K, H, A)
        for t in range(H * hold):
            action = flat[:, t // hold]
            if pilot is not None:
                action = np.clip(pilot(obs) + action, -1.0, 1.0)
            obs, reward, terminated, truncated, _ = env.step(action)
            value += np.where(alive, reward, 0.0)
            alive &= ~(terminated | truncated)
            if not alive.any():
                break
        self.timing["rollout"] += time.perf_counter() - t0
        return value.reshape(E, K)


def _copy_memory(src, dst, k: int) -> None:
    """Give pilot ``dst`` (for ``k`` rollouts of each episode) ``src``'s per-episode memory:
    the arrays its class names in ``memory`` (the episode first), each row ``k`` times."""
    for name in src.memory:
        setattr(dst, name, np.repeat(getattr(src, name), k, axis=0))
