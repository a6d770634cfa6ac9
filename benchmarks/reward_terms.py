"""What each reward term gives the tuned pilot per episode, at each level of a v1 env.

A return says little about what pays for it: this flies the scene's tuned pilot (tuned on v0)
on ``--episodes`` seeded episodes at each level and prints the per-episode mean of each of
``info["episode_terms"]`` (the first episode of each sub-env), so a term that swamps the
others at some level shows at once (the boat's porpoising term in moving water, issue 23).

    python -m benchmarks.reward_terms fluidsim/BoatOnStep-v1 [--episodes 64] [--seed 0]
"""

from __future__ import annotations

import argparse
import sys

import gymnasium as gym
import numpy as np

import fluidsim_envs  # noqa: F401  (registers the ids)
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes.realism import LEVELS


def episode_terms(env_id: str, level: str, episodes: int, seed: int) -> dict[str, float]:
    """The mean of each reward term over the first episode of ``episodes`` sub-envs."""
    scene = SCENES[env_id]
    venv = gym.make_vec(env_id, num_envs=episodes, vectorization_mode="vector_entry_point",
                        difficulty=level)  # fmt: skip
    pilot = scene.pilot(venv.unwrapped)
    obs, _ = venv.reset(seed=seed)
    done = np.zeros(episodes, dtype=bool)
    sums = {name: np.zeros(episodes) for name in venv.unwrapped.reward_terms}
    while not done.all():
        obs, _, _, _, info = venv.step(pilot(obs))
        if "episode_terms" in info:
            first = info["_episode_terms"] & ~done
            for name, values in info["episode_terms"].items():
                sums[name][first] = values[first]
            done |= first
    venv.close()
    return {name: float(v.mean()) for name, v in sums.items()}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("env_id", choices=[i for i, s in SCENES.items() if s.version == 1])
    parser.add_argument("--episodes", type=int, default=64)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    if args.episodes < 1:
        parser.error(f"--episodes must be at least 1, got {args.episodes}")
    for level in LEVELS:
        terms = episode_terms(args.env_id, level, args.episodes, args.seed)
        print(f"{level:9s} " + "  ".join(f"{k} {v:8.1f}" for k, v in terms.items()), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
