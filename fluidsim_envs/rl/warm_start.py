"""A warm start for PPO: behaviour cloning of a teacher before RL.

Where RL stalls below a scripted pilot (the submarine and the boat at ``standard``: the
results), a policy that starts where its teacher is has the teacher's return to improve on
instead of a random one to climb from. The teacher (``warm_start.teacher``: the scene's tuned
pilot, or its planner, an oracle of the present that reads the true state and plans through
noise of its own) flies the run's own training envs for ``warm_start.steps`` env steps; the
policy's mean action is fitted to the teacher's actions (least squares) and its value
function to the discounted returns those actions earned, in the units PPO will train it in
(the rewards normalized by the run's ``VecNormalize``), so that PPO's first updates start from
a critic that knows what the teacher's states are worth rather than one whose errors would
unlearn the copied policy. The log std is left as the config sets it: exploration starts
where PPO's would.

The teacher steps the adapter beneath ``VecMonitor``: its episodes are not the run's (the
learning curve and ``monitor.csv`` are PPO's alone), and its steps are not the run's
timesteps (``run.yaml`` counts them under ``warm_start``). ``VecNormalize``'s statistics are
updated on the way as they are in training, so RL starts with them warm. The ``imitation``
library (the usual choice with SB3) pins gymnasium 0.29 and SB3 2.2, two majors behind ours.
"""

from __future__ import annotations

import itertools
import time
from typing import Any

import numpy as np

from .config import TrainConfig


def adapter_of(venv):
    """The :class:`~fluidsim_envs.wrappers.sb3.SB3VecEnv` at the bottom of a VecEnv chain."""
    from fluidsim_envs.wrappers.sb3 import SB3VecEnv

    while not isinstance(venv, SB3VecEnv):
        venv = venv.venv
    return venv


#: what run.yaml and the log call each teacher
TEACHER_NAMES = {"pilot": "tuned pilot", "planner": "planner"}


def teacher_factory(cfg: TrainConfig):
    """``make(venv) -> policy`` for ``cfg.warm_start.teacher``: the scene's pilot, or its
    planner at the scene's default budget with a generator of its own per vector env (one
    per level of a mixture), drawn from the run's seed."""
    from .evaluate import find_scene

    scene = find_scene(cfg.env_id)
    if cfg.warm_start.teacher == "pilot":
        return scene.pilot
    parts = itertools.count()

    def planner(venv):
        # its generator draws plans and rollout noise, never an episode: the rollouts' noise
        # keys are ones no episode start gives (scenes/noise.py foreign_keys) at any seed
        seed = np.random.SeedSequence([cfg.seed, next(parts)]).generate_state(1)[0]
        return scene.planner(venv, seed=int(seed))

    return planner


def fly_teacher(cfg: TrainConfig, model) -> dict[str, np.ndarray]:
    """The warm start's teacher on the run's training envs for ``cfg.warm_start.steps`` env
    steps: raw observations ``obs [T, E, D]``, its actions ``[T, E, A]``, rewards ``[T, E]``,
    episode ends ``dones [T, E]`` and which of them were time limits ``truncated [T, E]``
    (``VecNormalize``'s statistics updated as in training). The adapter's step counters are
    set back after it: the run's timing counts PPO's steps alone."""
    adapter, norm = adapter_of(model.get_env()), model.get_vec_normalize_env()
    make = teacher_factory(cfg)
    # a mixture of levels: a teacher per level's part (wrappers/levels.py)
    split = getattr(adapter.venv, "split", None)
    teacher = split(make) if split is not None else make(adapter.venv)
    E = adapter.num_envs
    T = -(-cfg.warm_start.steps // E)
    out = {"obs": [], "actions": [], "rewards": [], "dones": [], "truncated": []}
    returns = np.zeros(E)
    obs = adapter.reset()
    if hasattr(teacher, "reset"):
        teacher.reset()
    for _ in range(T):
        if norm is not None and norm.norm_obs:
            norm.obs_rms.update(obs)
        reading = obs[:, : obs.shape[1] // 2] if cfg.privileged_critic else obs
        actions = np.asarray(teacher(reading), dtype=np.float32)
        out["obs"].append(obs)
        out["actions"].append(actions)
        obs, rewards, dones, infos = adapter.step(actions)
        if norm is not None:  # VecNormalize's own reward statistics, step by step
            returns = returns * norm.gamma + rewards
            norm.ret_rms.update(returns)
            returns[dones] = 0.0
        out["rewards"].append(rewards)
        out["dones"].append(dones)
        out["truncated"].append([i.get("TimeLimit.truncated", False) for i in infos])
        if dones.any() and hasattr(teacher, "reset"):
            teacher.reset(dones)
    adapter.env_steps, adapter.env_seconds = 0, 0.0
    return {k: np.stack(v) for k, v in out.items()}


def policy_inputs(obs: np.ndarray, dones: np.ndarray, norm, frames: int) -> np.ndarray:
    """What the policy reads at each step ``[T, E, frames * D]``: the observations normalized
    with the final statistics, the last ``frames`` side by side (zeros before an episode's
    first, as ``VecFrameStack`` gives them)."""
    x = norm.normalize_obs(obs) if norm is not None and norm.norm_obs else obs
    if frames == 1:
        return x.astype(np.float32)
    T, E, D = x.shape
    stack = np.zeros((E, frames * D), dtype=np.float32)
    out = np.empty((T, E, frames * D), dtype=np.float32)
    for t in range(T):
        if t > 0:
            stack[dones[t - 1]] = 0.0  # a new episode starts here
        stack = np.roll(stack, -D, axis=1)
        stack[:, -D:] = x[t]
        out[t] = stack
    return out


def value_targets(rewards, dones, truncated, norm, gamma: float):
    """Discounted returns of the rewards PPO will see (normalized where ``norm`` is), each
    episode's own, and which of them to trust. A sum that an episode's end cuts is exact
    where the episode ended for good; where it was cut (a time limit, whose value PPO
    bootstraps, or the end of the flight) the steps fewer than ``3 / (1 - gamma)`` before the
    cut miss more than 5% of their weight, and are left out (``gamma`` < 1)."""
    r = norm.normalize_reward(rewards) if norm is not None and norm.norm_reward else rewards
    T, E = r.shape
    horizon = 3.0 / (1.0 - gamma)
    g = np.zeros((T, E), dtype=np.float64)
    valid = np.zeros((T, E), dtype=bool)
    running, known = np.zeros(E), np.zeros(E)  # known: the steps summed before a cut
    for t in range(T - 1, -1, -1):
        ended = dones[t].astype(bool)
        running = r[t] + gamma * np.where(ended, 0.0, running)
        after = np.where(truncated[t], 0.0, np.inf)  # a true end: nothing is missing
        known = 1.0 + np.where(ended, after, known)
        g[t], valid[t] = running, known >= horizon
    return g.astype(np.float32), valid


def warm_start(cfg: TrainConfig, model, say=print) -> dict[str, Any]:
    """Fly the teacher, then fit ``model``'s policy and value function to it (see the module's
    docstring); returns what run.yaml keeps of it."""
    import torch as th

    ws, t0 = cfg.warm_start, time.perf_counter()
    data = fly_teacher(cfg, model)
    norm = model.get_vec_normalize_env()
    x = policy_inputs(data["obs"], data["dones"], norm, cfg.frame_stack)
    g, valid = value_targets(
        data["rewards"], data["dones"], data["truncated"], norm, cfg.algorithm.gamma
    )
    policy = model.policy
    X = th.as_tensor(x.reshape(-1, x.shape[-1]), device=policy.device)
    A = th.as_tensor(data["actions"].reshape(-1, data["actions"].shape[-1]), device=policy.device)
    G = th.as_tensor(g.reshape(-1), device=policy.device)
    M = th.as_tensor(valid.reshape(-1), device=policy.device)

    def action_mse() -> float:
        with th.no_grad():
            return float(((policy.get_distribution(X).distribution.mean - A) ** 2).mean())

    before = action_mse()
    policy.set_training_mode(True)
    optimizer = th.optim.Adam(policy.parameters(), lr=ws.learning_rate)
    rng = np.random.default_rng(cfg.seed)
    for _ in range(ws.epochs):
        order = rng.permutation(len(X))
        for lo in range(0, len(X), ws.batch_size):
            idx = th.as_tensor(order[lo : lo + ws.batch_size])
            mean = policy.get_distribution(X[idx]).distribution.mean
            values = policy.predict_values(X[idx]).flatten()
            mask = M[idx]
            actor = ((mean - A[idx]) ** 2).mean()
            critic = ((values - G[idx]) ** 2)[mask].mean() if mask.any() else 0.0 * actor
            optimizer.zero_grad()
            (actor + critic).backward()
            th.nn.utils.clip_grad_norm_(policy.parameters(), cfg.algorithm.max_grad_norm)
            optimizer.step()
    policy.set_training_mode(False)
    stats = {
        "teacher": TEACHER_NAMES[ws.teacher],
        "env_steps": int(data["rewards"].size),
        "episodes_ended": int(data["dones"].sum()),
        # the policy's mean action against the teacher's, over every step flown
        "action_mse_before": round(before, 6),
        "action_mse": round(action_mse(), 6),
        "value_mse": round(critic.item(), 6),  # the last minibatch's
        "seconds": round(time.perf_counter() - t0, 1),
    }
    say(
        f"warm start: the {stats['teacher']} flew {stats['env_steps']:,} env steps "
        f"({stats['episodes_ended']} episodes ended); policy fitted over {ws.epochs} epochs "
        f"(action mse {stats['action_mse_before']:.3g} -> {stats['action_mse']:.3g}) in "
        f"{stats['seconds']:.0f} s"
    )
    return stats
