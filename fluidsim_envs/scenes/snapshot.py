"""A snapshot of sub-envs of a scene's vector env: everything that decides their future.

:meth:`FluidVectorEnv.get_state` takes one and :meth:`FluidVectorEnv.set_state` restores it;
restored sub-envs then step bit for bit as the ones it was taken from, whatever the batch
they sit in (the physics, the task's arrays, each sub-env's generator and clocks are all in
it). A planner copies one episode into many rollouts with :meth:`EnvState.repeat`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np


@dataclass(frozen=True)
class EnvState:
    """``n`` sub-envs of one scene with one set of parameters, picklable.

    Every array has the sub-env first (``[n, ...]``); ``rngs`` holds each sub-env's generator
    state (``bit_generator.state``; None before its first reset).
    """

    env: str  # the vector env's class, "module:qualname"
    params: Any  # the env's frozen parameter dataclass: the episodes' fixed physics
    physics: dict[str, np.ndarray]  # Simulator.get_state
    task: dict[str, np.ndarray]  # the scene's arrays (FluidVectorEnv.state_fields)
    rngs: tuple[dict | None, ...]

    def __len__(self) -> int:
        return len(self.rngs)

    def take(self, rows) -> EnvState:
        """The snapshot of sub-envs ``rows`` (indices into this one, repeats allowed)."""
        try:  # not asarray(rows, int64): that would read 0.5 as row 0
            idx = np.asarray(rows)
        except (TypeError, ValueError):  # a ragged list
            idx = None
        ok = idx is not None and idx.ndim == 1 and (idx.size == 0 or idx.dtype.kind in "iu")
        if not ok or (idx.size and (idx.min() < 0 or idx.max() >= len(self))):
            raise ValueError(
                f"EnvState.take: rows must be indices in [0, {len(self)}) (repeats allowed), "
                f"got {rows!r:.120}"
            )
        rows = idx.astype(np.int64)
        return replace(
            self,
            physics={k: v[rows] for k, v in self.physics.items()},
            task={k: v[rows] for k, v in self.task.items()},
            rngs=tuple(self.rngs[i] for i in rows),
        )

    def repeat(self, k: int) -> EnvState:
        """Each sub-env ``k`` times in a row (``a a a b b b``): ``k`` rollouts of each."""
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k < 1:
            raise ValueError(f"EnvState.repeat: k must be a positive integer, got {k!r}")
        return self.take(np.repeat(np.arange(len(self)), k))
