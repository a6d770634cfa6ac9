"""The zoo: the trained policies that ship with the package, one entry per env and algorithm.

    >>> from fluidsim_envs import zoo
    >>> zoo.list()
    ['BoatOnStep-v1-ppo', 'PaperAirplane-v1-ppo', 'PaperAirplane-v1-sac', 'SubmarineWake-v1-ppo']

An entry is a folder (the repository's ``zoo/<Env-vN>-<algo>/``, in the wheel
``fluidsim_envs/zoo/entries/``) of numbers and plain text: ``config.yaml`` (how it was
trained: the env's parameters and the policy's shape), ``model.safetensors`` (the policy's
weights), ``vecnormalize.safetensors`` (the observation statistics it was trained on),
``evaluation.csv`` (its published evaluation, beside the scripted pilots on the same
episodes) and ``run.yaml``. Loading one runs no code from it (:mod:`fluidsim_envs.rl.saved`).

:func:`load` gives the policy with what it needs to act, in SB3's ``predict`` form, so that
SB3's own tools fly it::

    import gymnasium as gym
    from stable_baselines3.common.evaluation import evaluate_policy
    from stable_baselines3.common.vec_env import DummyVecEnv

    entry = zoo.load("PaperAirplane-v1-ppo")
    venv = DummyVecEnv([lambda: gym.make(entry.env_id, **entry.env_kwargs)] * 8)
    mean, std = evaluate_policy(entry, venv, n_eval_episodes=64)

Loading needs the ``train`` extra (SB3 and torch build the policy).
"""

from __future__ import annotations

import csv
import dataclasses
from collections.abc import Callable
from pathlib import Path
from typing import Any

#: where the entries are: the repository's zoo/ (a link in a checkout, a copy in the wheel)
ENTRIES = Path(__file__).resolve().parent / "entries"
#: the files an entry holds
FILES = ("config.yaml", "model.safetensors", "vecnormalize.safetensors", "evaluation.csv")


class ZooError(LookupError):
    """No such entry, or a folder that is not one; the message names it."""


def names() -> list[str]:
    """The entries' names, sorted (:func:`list` too)."""
    if not ENTRIES.is_dir():  # a checkout without symbolic links: the link is a text file
        raise ZooError(f"{ENTRIES} is not a folder of entries (a checkout needs its links)")
    return sorted(p.name for p in ENTRIES.iterdir() if (p / "config.yaml").is_file())


def path(name: str | Path) -> Path:
    """The folder of entry ``name`` (``"PaperAirplane-v1-ppo"``, or ``zoo/<name>``), or
    ``name`` itself where it is a folder holding an entry's files (a run folder too)."""
    folder = Path(name)
    if folder.is_dir() and (folder / "config.yaml").is_file():
        return folder
    known = names()
    if folder.name in known and folder.parent in (Path("."), Path("zoo")):
        return ENTRIES / folder.name
    raise ZooError(
        f"{str(name)!r} is neither a zoo entry ({', '.join(known)}) nor a folder with a config.yaml"
    )


list = names  # noqa: A001  (the zoo's word for it: zoo.list())


@dataclasses.dataclass(frozen=True, eq=False)
class Entry:
    """A loaded entry: its config, its policy and its published evaluation.

    Call it on a batch of raw observations ``[E, D]`` for actions ``[E, A]``, or use
    :meth:`predict` as SB3's tools do; either normalizes the observations with the entry's
    statistics and acts deterministically."""

    name: str
    folder: Path
    config: Any  # fluidsim_envs.rl.config.TrainConfig
    act: Callable  # raw observations [E, D] -> actions [E, A]
    evaluation: tuple[dict[str, str], ...]  # evaluation.csv's rows

    @property
    def env_id(self) -> str:
        return self.config.env_id

    @property
    def env_kwargs(self) -> dict[str, Any]:
        """The parameters it was trained with: ``gym.make(entry.env_id, **entry.env_kwargs)``."""
        return dict(self.config.env_kwargs)

    def __call__(self, observations):
        import numpy as np

        obs = np.asarray(observations)
        return self.act(obs.reshape(1, -1) if obs.ndim == 1 else obs).reshape(
            (-1,) if obs.ndim == 1 else (len(obs), -1)
        )

    def predict(self, observation, state=None, episode_start=None, deterministic=True):
        """SB3's ``predict``: ``(actions, None)``. Only deterministic, as it was evaluated."""
        if not deterministic:
            raise ValueError(f"{self.name}: the zoo's policies act deterministically")
        if episode_start is not None and hasattr(self.act, "reset"):  # stacked frames
            self.act.reset(episode_start)
        return self(observation), None

    def agrees(self, returns, policy: str | None = None) -> bool:
        """Whether episode ``returns`` of other episodes score what :meth:`published` says,
        to within sampling: their mean differs from the published mean by at most 1.96
        standard errors of a difference of two means (the published one's from its 95%
        interval)."""
        import numpy as np

        r, row = np.asarray(returns, dtype=float), self.published(policy)
        if r.size < 2:
            raise ValueError(f"{self.name}: agrees() needs two returns or more, got {r.size}")
        se_published = (float(row["return_mean_hi"]) - float(row["return_mean_lo"])) / 3.92
        se_here = r.std(ddof=1) / np.sqrt(r.size)
        gap = abs(r.mean() - float(row["return_mean"]))
        return bool(gap <= 1.96 * np.hypot(se_published, se_here))

    def published(self, policy: str | None = None) -> dict[str, str]:
        """The evaluation.csv row of ``policy`` (default: the trained one, the first row)."""
        for row in self.evaluation:
            if policy is None or row["policy"] == policy:
                return row
        raise ZooError(f"{self.name}: no evaluation row {policy!r}")


def load(name: str | Path, allow_pickle: bool = False) -> Entry:
    """Entry ``name`` (see :func:`path`) with its policy loaded: weights and statistics
    checked against its config (SB3's pickled files only with ``allow_pickle``, which runs
    any code they carry)."""
    import gymnasium as gym

    import fluidsim_envs  # noqa: F401  (registers the ids)
    from fluidsim_envs.enjoy import load_policy
    from fluidsim_envs.rl.config import load_config

    folder = path(name)
    cfg = load_config(folder / "config.yaml")
    # the statistics hang on a VecEnv of the env's shape: one sub-env, closed at once
    venv = gym.make_vec(cfg.env_id, 1, vectorization_mode="vector_entry_point", **cfg.env_kwargs)
    try:
        _, act = load_policy(folder, venv.unwrapped, allow_pickle)
    finally:
        venv.close()
    rows: tuple[dict[str, str], ...] = ()
    if (folder / "evaluation.csv").is_file():
        with open(folder / "evaluation.csv", newline="") as f:
            rows = tuple(csv.DictReader(line for line in f if not line.startswith("#")))
    return Entry(folder.name, folder, cfg, act, rows)
