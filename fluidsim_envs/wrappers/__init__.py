"""Adapters around the native vector envs.

- :class:`~fluidsim_envs.wrappers.sb3.SB3VecEnv` and
  :func:`~fluidsim_envs.wrappers.sb3.make_sb3_vec_env`: a native vector env as a
  Stable-Baselines3 ``VecEnv`` (in-process, same-step autoreset).
- :class:`~fluidsim_envs.wrappers.rerun_logger.RerunLogger`: logs chosen sub-envs to a Rerun
  recording.

The names are imported on first use, so ``import fluidsim_envs.wrappers`` pulls in neither
stable-baselines3 (and torch) nor rerun.
"""

from __future__ import annotations

import importlib
from typing import Any

_LAZY = {
    "SB3VecEnv": ".sb3",
    "make_sb3_vec_env": ".sb3",
    "RerunLogger": ".rerun_logger",
}

__all__ = sorted(_LAZY)


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name], __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
