"""Compile the physics kernels ahead, so that no env's first step waits for the compiler.

    python -m fluidsim_envs.warmup                    # every registered env (make setup runs it)
    python -m fluidsim_envs.warmup fluidsim/BoatOnStep-v0 --no-parallel

numba compiles a kernel at its first call and caches the machine code beside the package
(``cache=True``), so a fresh install, or a changed kernel, pays for it once: 19-37 s per env
for its first step on 2 cores (docs/bench_compile.csv, ``python -m benchmarks.bench_compile``),
and more for the threaded kernels of large batches. This pays it up front, one line per
env, for the kernels the env uses at a batch below and at or above the size from which the
Simulator steps environments on several threads.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable, Sequence

import gymnasium as gym
import numpy as np

from .physics.simulator import PARALLEL_MIN_BODIES
from .scenes import SCENES


def warm(
    env_ids: Sequence[str] | None = None,
    parallel: bool = True,
    say: Callable[[str], None] = print,
) -> dict[str, float]:
    """Reset and step each env (all of :data:`SCENES` by default) as a vector env of 2
    environments, and of the smallest batch that steps on threads if ``parallel``; returns
    the seconds each took (all but nothing once the cache is warm)."""
    ids = list(SCENES) if env_ids is None else list(env_ids)
    unknown = [i for i in ids if i not in SCENES]
    if unknown:
        raise ValueError(f"warmup: unknown env id(s) {unknown}; registered: {list(SCENES)}")
    sizes = (2, PARALLEL_MIN_BODIES) if parallel else (2,)
    took = {}
    for env_id in ids:
        say(f"compiling {env_id} (the first time takes minutes; cached afterwards) ...")
        t0 = time.perf_counter()
        for n in sizes:
            venv = gym.make_vec(env_id, num_envs=n, vectorization_mode="vector_entry_point")
            venv.reset(seed=0)
            venv.step(np.zeros(venv.action_space.shape, dtype=venv.action_space.dtype))
            venv.close()
        took[env_id] = time.perf_counter() - t0
        say(f"  {env_id}: ready in {took[env_id]:.1f} s")
    return took


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        prog="python -m fluidsim_envs.warmup", description=__doc__.splitlines()[0]
    )
    parser.add_argument("env_ids", nargs="*", help=f"env ids (default: all of {list(SCENES)})")
    parser.add_argument(
        "--no-parallel",
        dest="parallel",
        action="store_false",
        help=f"skip the threaded kernels (batches of {PARALLEL_MIN_BODIES} or more)",
    )
    args = parser.parse_args(argv)
    try:
        took = warm(args.env_ids or None, parallel=args.parallel)
    except ValueError as err:
        parser.error(str(err))
    print(f"physics kernels compiled and cached: {sum(took.values()):.0f} s in all")


if __name__ == "__main__":
    main(sys.argv[1:])
