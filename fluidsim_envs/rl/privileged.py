"""An asymmetric actor-critic (``privileged_critic: true``, PPO on a v1 env): the value
function reads the exact observation the env computes before its instruments (``_truth``:
no noise, bias or latency) beside the sensors' reading, the policy the reading alone.

A critic that sees the state judges each step's advantage with less noise than one that must
infer it from lagging, noisy readings, and nothing of it is needed to fly: the trained policy
acts on its instruments, as a pilot would (Pinto et al., 2018, "Asymmetric actor critic for
image-based robot learning").

How: :class:`WithTruth` appends the exact observation to each sub-env's reading (the ended
episode's too, in ``final_obs``, for SB3's bootstrap at a time limit), so VecNormalize, frame
stacking and the rollout buffer handle one flat observation; :class:`PrivilegedCriticPolicy`
is SB3's actor-critic with its two feature extractors apart, the actor's zeroing the exact
columns (:func:`actor_mask`). The policy's output does not depend on them: an evaluation
feeds zeros there (:func:`pad`).
"""

from __future__ import annotations

import numpy as np
import torch as th
from gymnasium import spaces
from gymnasium.vector import VectorWrapper
from stable_baselines3.common.policies import ActorCriticPolicy
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor


class WithTruth(VectorWrapper):
    """A fluidsim vector env whose observation is its reading then its exact observation,
    ``[E, 2 D]``; ``final_obs`` likewise, with the ended episode's exact last one."""

    def __init__(self, env) -> None:
        super().__init__(env)
        # at a level without instrument errors (v1's easy) the two halves are equal
        self.base = base = env.unwrapped
        box = env.single_observation_space
        self.single_observation_space = spaces.Box(
            np.concatenate([box.low, box.low]), np.concatenate([box.high, box.high]),
            dtype=box.dtype,
        )  # fmt: skip
        self.observation_space = spaces.Box(
            np.tile(self.single_observation_space.low, (env.num_envs, 1)),
            np.tile(self.single_observation_space.high, (env.num_envs, 1)),
            dtype=box.dtype,
        )
        self._final_truth = np.zeros_like(base._truth)
        base.before_autoreset.append(self._keep_final_truth)

    def _keep_final_truth(self, ended: np.ndarray, info: dict, reward: np.ndarray) -> None:
        self._final_truth[ended] = self.base._truth[ended]

    def _with_truth(self, obs: np.ndarray, truth: np.ndarray) -> np.ndarray:
        return np.concatenate([obs, truth.astype(obs.dtype)], axis=1)

    def reset(self, *, seed=None, options=None):
        obs, info = self.env.reset(seed=seed, options=options)
        return self._with_truth(obs, self.base._truth), info

    def step(self, actions):
        obs, reward, terminated, truncated, info = self.env.step(actions)
        if "final_obs" in info:
            info = {**info, "final_obs": self._with_truth(info["final_obs"], self._final_truth)}
        return self._with_truth(obs, self.base._truth), reward, terminated, truncated, info

    def detach(self) -> None:
        """Stop keeping the env's last exact observations (the env goes on, unwrapped)."""
        if self._keep_final_truth in self.base.before_autoreset:
            self.base.before_autoreset.remove(self._keep_final_truth)

    def close(self, **kwargs) -> None:
        self.detach()
        super().close(**kwargs)


def actor_mask(obs_dim: int, frames: int = 1) -> list[bool]:
    """Which columns of the policy's input the actor reads: each frame's reading (its first
    ``obs_dim`` columns), never the exact observation after it."""
    return ([True] * obs_dim + [False] * obs_dim) * frames


def pad(obs: np.ndarray) -> np.ndarray:
    """Readings ``[E, D]`` as a privileged policy's input ``[E, 2 D]``, zeros where the exact
    observation goes (its actor does not read them)."""
    return np.concatenate([obs, np.zeros_like(obs)], axis=1)


class Masked(BaseFeaturesExtractor):
    """The flat observation with the columns outside ``mask`` set to zero (the same width,
    so that SB3's networks take either extractor's features)."""

    def __init__(self, observation_space: spaces.Box, mask: list[bool]) -> None:
        super().__init__(observation_space, features_dim=len(mask))
        self.register_buffer("mask", th.tensor(mask, dtype=th.float32))

    def forward(self, observations: th.Tensor) -> th.Tensor:
        return observations.flatten(1) * self.mask


class PrivilegedCriticPolicy(ActorCriticPolicy):
    """SB3's actor-critic whose actor reads only the columns of ``actor_mask``; the critic
    reads every column. The feature extractors are apart (``share_features_extractor``
    False)."""

    def __init__(self, *args, actor_mask: list[bool], **kwargs) -> None:
        kwargs["share_features_extractor"] = False
        super().__init__(*args, **kwargs)
        width = int(np.prod(self.observation_space.shape))
        if len(actor_mask) != width:
            raise ValueError(
                f"PrivilegedCriticPolicy: actor_mask has {len(actor_mask)} columns, the "
                f"observation {width}"
            )
        self.actor_mask = list(actor_mask)
        # no weights in either extractor: the optimizer built above holds every parameter
        self.pi_features_extractor = Masked(self.observation_space, self.actor_mask)
        self.features_extractor = self.pi_features_extractor

    def _get_constructor_parameters(self) -> dict:
        return {**super()._get_constructor_parameters(), "actor_mask": self.actor_mask}
