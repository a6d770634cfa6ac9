"""The description of a scene that the registry (:data:`fluidsim_envs.scenes.SCENES`) holds:
everything generic code needs to register, evaluate, log, demo and test it without naming it."""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from .base import FluidEnv, FluidVectorEnv
from .keys import Axis
from .mesh import craft_meshes
from .planner import Planner, PlannerConfig


def nan_state(venv: FluidVectorEnv, env_index: int) -> None:
    """Make sub-env ``env_index``'s physics state NaN: a stand-in for a real blow-up."""
    st, _, _ = venv.sim.kernel_arrays()
    st[:, :, env_index] = np.nan


@dataclass(frozen=True)
class Scene:
    """One scene: its gym id, classes, layout, baseline pilot, viewers and test hooks.

    Checked on construction (a scene that does not hang together fails at import)."""

    id: str  # the gym id, "fluidsim/Name-vN"
    summary: str  # one line: the task
    # what info["success"] means, with the parameters it reads in braces (filled from a
    # params instance by success_text): one line for the docs' table of envs
    success: str
    env_cls: type[FluidEnv]  # the single env (the batch of one)
    vector_cls: type[FluidVectorEnv]  # the native vector env
    params_cls: type  # the frozen parameter dataclass (gym.make kwargs)
    observation: tuple[tuple[str, str, str], ...]  # the columns: (name, unit, description)
    # the scripted baseline for a vector env (or a wrapper of one): a policy obs -> actions,
    # with reset(mask) for the sub-envs whose episode ended
    pilot: Callable[[Any], Callable[[np.ndarray], np.ndarray]]
    # the same pilot with its hand-set gains (the tuned ones: benchmarks/tune_pilots.py)
    hand_pilot: Callable[[Any], Callable[[np.ndarray], np.ndarray]]
    view: type  # the rgb_array viewer: view(env).frame(env_index) -> [H, W, 3] uint8
    # the Rerun hooks: rerun(logger) -> RerunHooks (world, episode, step; see scenes/rerun.py)
    rerun: Callable[[Any], Any]
    # prints the pilot against random and idle controls (python -m fluidsim_envs.demo)
    demo: Callable[..., None]
    # parameters under which episodes end within tens of steps: contract tests, smoke runs
    short_episodes: Mapping[str, Any] = field(default_factory=dict)
    # forces a non-finite state in sub-env e of a vector env (the divergence contract test)
    diverge: Callable[[FluidVectorEnv, int], None] = nan_state
    # the render mesh of each body (scenes/mesh.py): what the frames and recordings draw
    meshes: Callable[[FluidVectorEnv], tuple[Any, ...]] = craft_meshes
    # the planner's default budget for this scene (docs/study_planner.csv): how far ahead
    # the reward tells plans apart sets the look-ahead
    planner_config: PlannerConfig = PlannerConfig()
    # the keyboard controls of python -m fluidsim_envs.play: an Axis per action, in order
    keys: tuple[Axis, ...] = ()

    def __post_init__(self) -> None:
        own = f"Scene {self.id!r}"
        if not re.fullmatch(r"fluidsim/[A-Z][A-Za-z0-9]*-v\d+", self.id):
            raise ValueError(f"{own}: the id must read 'fluidsim/Name-vN'")
        if getattr(self.env_cls, "vector_cls", None) is not self.vector_cls:
            raise ValueError(f"{own}: {self.env_cls.__name__}.vector_cls is not vector_cls")
        for attr, value in (("Params", self.params_cls), ("View", self.view)):
            if getattr(self.vector_cls, attr, None) is not value:
                raise ValueError(f"{own}: {self.vector_cls.__name__}.{attr} is not {value}")
        if self.vector_cls.obs_dim != len(self.observation):
            raise ValueError(
                f"{own}: obs_dim {self.vector_cls.obs_dim} != {len(self.observation)} columns"
            )
        if self.keys and tuple(a.action for a in self.keys) != tuple(self.vector_cls.action_names):
            raise ValueError(f"{own}: keys {self.keys} are not the actions, in order")
        try:
            self.success_text()
        except (KeyError, IndexError, ValueError) as e:
            raise ValueError(f"{own}: success names no parameter of the env: {e}") from None
        object.__setattr__(self, "observation", tuple(tuple(c) for c in self.observation))
        object.__setattr__(self, "short_episodes", MappingProxyType(dict(self.short_episodes)))

    def planner(self, venv, samples: int | None = None, horizon: int | None = None, **kwargs):
        """The sampling planner on the true physics (:class:`~.planner.Planner`, a privileged
        oracle) for every sub-env of ``venv``, at this scene's budget; ``samples``,
        ``horizon`` and any other :class:`~.planner.PlannerConfig` field override it."""
        budget = {k: v for k, v in (("samples", samples), ("horizon", horizon)) if v is not None}
        config = dataclasses.replace(self.planner_config, **budget, **kwargs)
        return Planner(venv, config, pilot=self.pilot)

    def success_text(self, params=None) -> str:
        """:attr:`success` with the numbers of ``params`` (default: the env's defaults)."""
        p = self.params_cls() if params is None else params
        return self.success.format(**{f: getattr(p, f) for f in p.__dataclass_fields__})

    @property
    def version(self) -> int:
        """The N of ``-vN``: v0 the first task, v1 the same with a real craft (realism.py)."""
        return int(self.id.rsplit("-v", 1)[1])

    @property
    def first_id(self) -> str:
        """The id of this scene's v0: the same craft and task, whose per-craft measurements
        (tuned pilot gains, pictures) a later version starts from; its step limits bound
        the later version's own (``scenes/limits.py``)."""
        return self.id.rsplit("-v", 1)[0] + "-v0"

    @property
    def obs_names(self) -> tuple[str, ...]:
        return tuple(name for name, _, _ in self.observation)

    @property
    def entry_point(self) -> str:
        return f"{self.env_cls.__module__}:{self.env_cls.__qualname__}"

    @property
    def vector_entry_point(self) -> str:
        return f"{self.vector_cls.__module__}:{self.vector_cls.__qualname__}"
