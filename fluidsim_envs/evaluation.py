"""Roll a policy through one episode in every sub-env of a vector env, and summarize.

Used by the tests (the baseline pilot against doing nothing), the benchmarks and the
training CLI's evaluation. A policy maps observations [E, obs_dim] to actions [E, n]; it may
have a ``reset(mask)`` method, called with the sub-envs whose episode just ended.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .scenes.base import FluidVectorEnv


def first_episodes(
    venv: FluidVectorEnv, policy: Callable[[np.ndarray], np.ndarray], seed: int
) -> dict[str, np.ndarray]:
    """Each sub-env's first episode after ``reset(seed=seed)``: its return, length and the
    final info's scalar entries (e.g. landed, success, distance_m), arrays [E]."""
    E = venv.num_envs
    obs, _ = venv.reset(seed=seed)
    if hasattr(policy, "reset"):
        policy.reset()
    running = np.zeros(E)
    out: dict[str, np.ndarray] = {"return": np.zeros(E), "length": np.zeros(E, dtype=np.int64)}
    done = np.zeros(E, dtype=bool)
    while not done.all():
        obs, reward, terminated, truncated, info = venv.step(policy(obs))
        running += reward
        ended = terminated | truncated
        newly = ended & ~done
        if newly.any():
            final = info["final_info"]
            out["return"][newly] = running[newly]
            out["length"][newly] = final["episode_steps"][newly]
            out.setdefault("truncated", np.zeros(E, dtype=bool))[newly] = truncated[newly]
            for key, value in final.items():
                if key.startswith("_"):  # Gymnasium's masks, not results
                    continue
                if isinstance(value, np.ndarray) and value.shape == (E,):
                    out.setdefault(key, np.zeros(E, dtype=value.dtype))[newly] = value[newly]
            done |= newly
        running[ended] = 0.0
        if hasattr(policy, "reset") and ended.any():
            policy.reset(ended)
    return out


def zero_policy(venv: FluidVectorEnv) -> Callable[[np.ndarray], np.ndarray]:
    """Hold every control at 0."""
    shape = venv.action_space.shape
    return lambda obs: np.zeros(shape)


def random_policy(venv: FluidVectorEnv, seed: int) -> Callable[[np.ndarray], np.ndarray]:
    """Uniform random actions from a seeded generator."""
    rng = np.random.default_rng(seed)
    shape = venv.action_space.shape
    return lambda obs: rng.uniform(-1.0, 1.0, size=shape)
