"""Several difficulty levels of one v1 env in one vector env: a policy trained on the mixture
meets easy, standard and hard episodes side by side, where one trained at ``standard`` is a
specialist of it (docs/results.md).

A level's knobs are the whole vector env's (the sea, the turbulence, the instruments), so
:class:`LevelMix` holds one native vector env per level and steps them as one, its sub-envs
the parts' in order. Seeding keeps the meaning of a seed: sub-env i of the mixture draws from
the child i of the seed's sequence, as sub-env i of one vector env of that size would
(``reset(seed=s)``, any stream), whichever part it sits in.

    >>> from fluidsim_envs.wrappers.levels import LevelMix
    >>> venv = LevelMix("fluidsim/PaperAirplane-v1", ["easy", "hard"], num_envs=4)
    >>> venv.levels
    ('easy', 'easy', 'hard', 'hard')
    >>> obs, info = venv.reset(seed=0)
    >>> obs.shape
    (4, 31)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv

from .. import seeding as SD
from ..physics import checks as CK
from ..scenes.realism import LEVELS


def shares(levels: Sequence[str], num_envs: int, where: str = "levels") -> dict[str, int]:
    """Sub-envs per level: ``num_envs`` split over the entries of ``levels`` as evenly as
    whole sub-envs allow (entries differ by one at most, the earlier ones larger; a level
    named twice gets two shares), or a ValueError naming what cannot be split."""
    if isinstance(levels, str) or not isinstance(levels, Sequence) or not levels:
        raise ValueError(f"{where}: a list of difficulty levels {list(LEVELS)}, got {levels!r}")
    bad = [level for level in levels if level not in LEVELS]
    if bad:
        raise ValueError(f"{where}: unknown difficulty levels {bad}; levels are {list(LEVELS)}")
    if num_envs < len(levels):
        raise ValueError(
            f"{where}: {num_envs} sub-envs for the {len(levels)} entries of {list(levels)}; "
            f"each entry needs one at least"
        )
    each, extra = divmod(num_envs, len(levels))
    split: dict[str, int] = {}
    for i, level in enumerate(levels):
        split[level] = split.get(level, 0) + each + (i < extra)
    return split


class LevelMix(VectorEnv):
    """``num_envs`` sub-envs of the v1 env ``env_id``, split over ``levels`` (each
    entry a share: ``["standard", "hard", "hard"]`` gives hard two thirds), the parameters
    ``env_kwargs`` (any but ``difficulty``) at every level. Same-step autoreset, as each part.
    ``levels[i]`` names sub-env i's level; ``parts`` are the native vector envs."""

    metadata: dict[str, Any] = {"autoreset_mode": AutoresetMode.SAME_STEP}

    def __init__(
        self, env_id: str, levels: Sequence[str], num_envs: int, wrap=None, **env_kwargs: Any
    ):
        from .sb3 import make_vector_env

        if "difficulty" in env_kwargs:
            raise ValueError(
                f"LevelMix: the levels {list(levels)} set each part's difficulty; drop "
                f"difficulty={env_kwargs['difficulty']!r} from the env's parameters"
            )
        split = shares(levels, num_envs, "LevelMix levels")
        self.parts = [
            make_vector_env(env_id, n, difficulty=level, **env_kwargs).unwrapped
            for level, n in split.items()
        ]
        if wrap is not None:  # each part's observation made another way (rl/privileged.py)
            self.parts = [wrap(part) for part in self.parts]
        first = self.parts[0]
        for part in self.parts[1:]:
            if (part.single_observation_space, part.single_action_space) != (
                first.single_observation_space,
                first.single_action_space,
            ):
                raise ValueError(
                    f"LevelMix: {env_id} at {part.unwrapped.params.difficulty!r} has other "
                    f"spaces than at {first.unwrapped.params.difficulty!r}; a policy cannot "
                    "fly both"
                )
        self.levels = tuple(level for level, n in split.items() for _ in range(n))
        self.bounds = np.cumsum([0] + [p.num_envs for p in self.parts])
        self.num_envs = num_envs
        self.single_observation_space = first.single_observation_space
        self.single_action_space = first.single_action_space
        self.observation_space = first.observation_space.__class__(
            low=np.concatenate([p.observation_space.low for p in self.parts]),
            high=np.concatenate([p.observation_space.high for p in self.parts]),
            dtype=first.observation_space.dtype,
        )
        self.action_space = first.action_space.__class__(
            low=np.concatenate([p.action_space.low for p in self.parts]),
            high=np.concatenate([p.action_space.high for p in self.parts]),
            dtype=first.action_space.dtype,
        )
        self.spec = first.unwrapped.spec
        self.action_names = first.unwrapped.action_names
        self.version = getattr(first.unwrapped, "version", 0)

    def _slices(self):
        return [slice(lo, hi) for lo, hi in zip(self.bounds[:-1], self.bounds[1:], strict=True)]

    def reset(self, *, seed=None, options=None):
        """As a native vector env's ``reset``: ``seed`` None, an integer (sub-env i draws
        from child i of its stream's sequence) or one per sub-env; ``options`` with
        ``env_ids`` or ``reset_mask`` (mixture indices) and ``stream``."""
        options = dict(options or {})
        stream = SD.check_stream("LevelMix.reset", options.pop("stream", "evaluation"))
        if seed is None:
            seeds = [None] * len(self.parts)
        elif isinstance(seed, (list, tuple, np.ndarray)):
            if len(seed) != self.num_envs:
                raise ValueError(
                    f"LevelMix.reset: expected {self.num_envs} seeds, one per sub-env, "
                    f"got {len(seed)}"
                )
            seeds = [list(seed[s]) for s in self._slices()]
        else:
            seed = CK.seed("LevelMix.reset", "seed", seed)
            children = SD.root(seed, stream).spawn(self.num_envs)
            seeds = [children[s] for s in self._slices()]
        mask = self._mask(options)
        obs, infos = [], []
        for part, rows, part_seed in zip(self.parts, mask, seeds, strict=True):
            part_options = {"reset_mask": rows} if rows is not None else {}
            if part_seed is not None and stream != "evaluation" and not _sequences(part_seed):
                part_options["stream"] = stream
            o, info = part.reset(seed=part_seed, options=part_options or None)
            obs.append(o)
            infos.append(info)
        return np.concatenate(obs), concat_infos(infos, [p.num_envs for p in self.parts])

    def _mask(self, options: dict) -> list:
        """Each part's reset mask for the mixture's ``env_ids`` / ``reset_mask`` (None: all)."""
        if not options:
            return [None] * len(self.parts)
        if set(options) - {"env_ids", "reset_mask"} or len(options) > 1:
            raise ValueError(
                f"LevelMix.reset: unknown or conflicting options {sorted(options)}; valid "
                "options are one of 'env_ids', 'reset_mask', and 'stream'"
            )
        mask = np.zeros(self.num_envs, dtype=bool)
        if "reset_mask" in options:
            given = options["reset_mask"]
            if not (
                isinstance(given, np.ndarray)
                and given.dtype == np.bool_
                and given.shape == mask.shape
            ):
                raise ValueError(
                    f"LevelMix.reset: reset_mask must be a boolean array of shape "
                    f"({self.num_envs},), got {CK.show(given)}"
                )
            mask[:] = given
        else:
            mask[np.asarray(options["env_ids"], dtype=np.int64)] = True
        return [mask[s] for s in self._slices()]

    def step(self, actions):
        actions = np.asarray(actions)
        out = [part.step(actions[s]) for part, s in zip(self.parts, self._slices(), strict=True)]
        obs, reward, terminated, truncated, infos = zip(*out, strict=True)
        return (
            np.concatenate(obs),
            np.concatenate(reward),
            np.concatenate(terminated),
            np.concatenate(truncated),
            concat_infos(list(infos), [p.num_envs for p in self.parts]),
        )

    def split(self, make: Callable[[VectorEnv], Callable]) -> Callable:
        """A controller over the mixture from one per part (``make(part)``, e.g. a scene's
        pilot): each acts on its part's rows; ``reset(mask)`` is passed on in parts."""
        return _Split([make(p.unwrapped) for p in self.parts], self._slices())

    def close(self, **kwargs) -> None:
        for part in self.parts:
            part.close()


class _Split:
    """Controllers side by side, each on its rows of the mixture (:meth:`LevelMix.split`)."""

    def __init__(self, controllers: list, slices: list[slice]) -> None:
        self.controllers, self.slices = controllers, slices

    def __call__(self, obs):
        return np.concatenate(
            [np.asarray(c(obs[s])) for c, s in zip(self.controllers, self.slices, strict=True)]
        )

    def reset(self, mask=None) -> None:
        for c, s in zip(self.controllers, self.slices, strict=True):
            if hasattr(c, "reset"):
                c.reset(None if mask is None else np.asarray(mask)[s])


def _sequences(seeds) -> bool:
    return isinstance(seeds, list) and all(isinstance(s, np.random.SeedSequence) for s in seeds)


def concat_infos(infos: list[dict], sizes: list[int]) -> dict:
    """Batched info dicts of vector envs side by side (Gymnasium's layout: a value per
    sub-env and, where not every sub-env has one, a ``_key`` mask) as one batch's."""
    out: dict[str, Any] = {}
    keys = list(dict.fromkeys(k for info in infos for k in info if not k.startswith("_")))
    for key in keys:
        values = [info.get(key) for info in infos]
        present = [v is not None for v in values]
        if all(isinstance(v, dict) for v in values if v is not None):
            out[key] = concat_infos([v or {} for v in values], sizes)
        else:
            like = next(np.asarray(v) for v in values if v is not None)
            out[key] = np.concatenate(
                [
                    np.asarray(v) if v is not None else np.zeros((n, *like.shape[1:]), like.dtype)
                    for v, n in zip(values, sizes, strict=True)
                ]
            )
        masks = [info.get(f"_{key}") for info in infos]
        if not all(present) or any(m is not None for m in masks):
            out[f"_{key}"] = np.concatenate(
                [
                    np.asarray(m, dtype=bool) if m is not None else np.full(n, p)
                    for m, n, p in zip(masks, sizes, present, strict=True)
                ]
            )
    return out
