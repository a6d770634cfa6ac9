"""Roll a policy through one episode in every sub-env of a vector env, and summarize.

Used by the tests (the baseline pilot against doing nothing), the benchmarks and the
training CLI's evaluation. A policy maps observations [E, obs_dim] to actions [E, n]; it may
have a ``reset(mask)`` method, called with the sub-envs whose episode just ended.

Seeds: the published evaluation flies ``reset(seed=EVAL_SEED)`` (``fluidsim-evaluate``'s
default ``--seed``); the scripted pilots' gains are tuned on episodes from other seeds,
:data:`TUNING_SEEDS` (``benchmarks/tune_pilots.py``), checked by :func:`check_tuning_seeds`.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .scenes.base import FluidVectorEnv

#: the seed of the published evaluation: ``fluidsim-evaluate --seed``'s default, the seed of
#: the docs' tables
EVAL_SEED = 0

#: the seeds the scripted pilots' gains are tuned on. Apart from :data:`EVAL_SEED` because
#: ``reset(seed=s)`` draws sub-env i from ``SeedSequence(s).spawn(E)[i]``, and SeedSequences of
#: different base seeds (entropy) give independent streams for any number of sub-envs: unlike
#: ``seed + i`` schemes, no episode of one seed is an episode of another
TUNING_SEEDS = (1, 2)


def check_tuning_seeds(seeds, eval_seed: int = EVAL_SEED) -> tuple[int, ...]:
    """``seeds`` as a tuple of ints, after checking that none is ``eval_seed`` (tuning on the
    evaluation's episodes would grade the tuning on its own training set) and none repeats.

    >>> check_tuning_seeds([1, 2])
    (1, 2)
    >>> check_tuning_seeds([0, 1])
    Traceback (most recent call last):
    ...
    ValueError: tuning seeds [0, 1] include the evaluation seed 0: tune on other seeds
    """
    seeds = tuple(int(s) for s in seeds)
    if not seeds:
        raise ValueError("no tuning seeds")
    if int(eval_seed) in seeds:
        raise ValueError(
            f"tuning seeds {list(seeds)} include the evaluation seed {eval_seed}: "
            "tune on other seeds"
        )
    if len(set(seeds)) != len(seeds):
        raise ValueError(f"tuning seeds {list(seeds)} repeat a seed (its episodes twice)")
    return seeds


def first_episodes(
    venv: FluidVectorEnv,
    policy: Callable[[np.ndarray], np.ndarray],
    seed: int,
    stream: str = "evaluation",
) -> dict[str, np.ndarray]:
    """Each sub-env's first episode after ``reset(seed=seed)`` (in seed ``stream``,
    ``fluidsim_envs.seeding``): its return, length and the final info's scalar entries (e.g.
    landed, success, distance_m), arrays [E]."""
    E = venv.num_envs
    options = None if stream == "evaluation" else {"stream": stream}
    obs, _ = venv.reset(seed=seed, options=options)
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
                if key.startswith("_") or key == "is_success":  # masks; success's alias
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
