"""The scenes: one package per task (env, task kernel and layouts, view, Rerun hooks, scripted
pilot) on the shared base, and :data:`SCENES`, the one registry (env id -> :class:`Scene`)
that registration, evaluation, the Rerun logger, the demo and the contract tests read.

Adding a scene: a package ``scenes/<scene>/`` that defines ``SCENE = Scene(...)``, and one
entry below.
"""

from __future__ import annotations

from types import MappingProxyType

from .boat_on_step import SCENE as _BOAT_ON_STEP
from .paper_airplane import SCENE as _PAPER_AIRPLANE
from .scene import Scene, nan_state
from .submarine_wake import SCENE as _SUBMARINE_WAKE

SCENES: MappingProxyType[str, Scene] = MappingProxyType(
    {s.id: s for s in (_PAPER_AIRPLANE, _SUBMARINE_WAKE, _BOAT_ON_STEP)}
)

__all__ = ["SCENES", "Scene", "nan_state"]
