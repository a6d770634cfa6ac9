"""The scenes: one package per task (env, task kernel and layouts, view, Rerun hooks, scripted
pilot) on the shared base, and :data:`SCENES`, the one registry (env id -> :class:`Scene`)
that registration, evaluation, the Rerun logger, the demo and the contract tests read.

Adding a scene: a package ``scenes/<scene>/`` that defines ``SCENE = Scene(...)``, and one
entry below.
"""

from __future__ import annotations

from types import MappingProxyType

from . import boat_on_step, paper_airplane, submarine_wake
from .scene import Scene, nan_state

SCENES: MappingProxyType[str, Scene] = MappingProxyType(
    {s.id: s for m in (paper_airplane, submarine_wake, boat_on_step) for s in (m.SCENE, m.SCENE_V1)}
)

# each scene's first version: what is measured per craft (tuned pilots, pictures; a later
# version's step limits are its own, at most its v0's)
V0_SCENES: MappingProxyType[str, Scene] = MappingProxyType(
    {i: s for i, s in SCENES.items() if s.version == 0}
)

__all__ = ["SCENES", "V0_SCENES", "Scene", "nan_state"]
