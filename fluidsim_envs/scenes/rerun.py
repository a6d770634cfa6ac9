"""What the scenes' Rerun hooks share: the hooks' protocol, level patches and grids, the body's
motion scalars, colors. Rerun itself is not imported here: the hooks draw through the logger's
``rr`` (:class:`~fluidsim_envs.wrappers.rerun_logger.RerunLogger`), so this module imports
without it.

A hook logs through the logger: ``lg.log(e, path, archetype, static=...)`` for what is drawn
once or once per episode, ``lg.record(e, path, Archetype, **columns)`` for a row held and sent
with the episode (what changes every step), ``lg.scalars(e, path, {name: value})`` for a row of
named series, and ``lg.every(e, period_s)`` to draw heavy things less often than every step.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

if TYPE_CHECKING:
    import rerun

WATER, GROUND, FLOOR = (40, 110, 170, 120), (150, 180, 130), (150, 130, 90)
TARGET, BUOY = (210, 40, 40), (250, 140, 20)


class RerunHooks(Protocol):
    """A scene's part of a Rerun recording, made once per logger as ``hooks(logger)``; it
    reads the env (``logger.base``) through its public accessors and keeps its own state."""

    def world(self, e: int) -> None:
        """Static geometry of sub-env e, logged once."""

    def episode(self, e: int) -> None:
        """At the start of each episode of sub-env e (before that row's :meth:`step`)."""

    def step(self, e: int, info: dict[str, Any] | None) -> None:
        """Every logged row of sub-env e: an episode's first state (``info`` None), each step
        and an episode's last state (before the autoreset)."""


def patch(points_xy, z: float, margin_m: float) -> np.ndarray:
    """The corners ``[4, 3]`` of a level rectangle at height z around ``points_xy [n, 2]``,
    ``margin_m`` beyond them: the ground or water under a course (drawn with
    :func:`sheet`'s two triangles), not a plane to the horizon that would frame the views."""
    xy = np.asarray(points_xy, dtype=np.float64).reshape(-1, 2)
    (x0, y0), (x1, y1) = xy.min(axis=0) - margin_m, xy.max(axis=0) + margin_m
    return np.array([[x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z]])


def sheet(rr: rerun, color, triangles=((0, 1, 2), (0, 2, 3))):
    """What a surface's rows share, logged once (static): its triangles and its color; its
    vertices come per row (a :func:`patch` each episode, a swell's surface every so often)."""
    return rr.Mesh3D.from_fields(
        triangle_indices=np.asarray(triangles, dtype=np.uint32), albedo_factor=color
    )


def mesh3d(rr: rerun, vertices, triangles, colors, positions: bool = True):
    """A render mesh's triangles ``[T, 3]`` over ``vertices [V, 3]``, one color per triangle
    (``[T, 3]`` uint8: each vertex takes its triangles' color), as a double-sided Mesh3D with
    area-weighted vertex normals; without its vertex positions unless ``positions`` (a mesh
    whose vertices are logged per row)."""
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.uint32).reshape(-1, 3)
    vertex_colors = np.zeros((len(v), 3), dtype=np.uint8)
    for k in range(3):
        vertex_colors[t[:, k]] = colors
    a, b, c = (v[t[:, k]] for k in range(3))
    normals = np.zeros_like(v)
    for k in range(3):
        np.add.at(normals, t[:, k], np.cross(b - a, c - a))
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.where(length > 1e-12, normals / np.maximum(length, 1e-12), [0.0, 0.0, 1.0])
    return rr.Mesh3D.from_fields(
        vertex_positions=v if positions else None,
        triangle_indices=t,
        vertex_colors=vertex_colors,
        vertex_normals=normals,
        face_rendering=rr.components.MeshFaceRendering.DoubleSided,
    )


def grid_triangles(n: int) -> np.ndarray:
    """Triangle indices of an (n + 1) x (n + 1) vertex grid, row-major."""
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    a = (i * (n + 1) + j).ravel()
    b, c, d = a + 1, a + n + 1, a + n + 2
    return np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)]).astype(np.uint32)


def attitude_deg(quat) -> tuple[float, float]:
    """(pitch, roll) in degrees: nose (body x) up +, right side (-y) down +."""
    w, x, y, z = (float(v) for v in quat)
    nose_z = 2.0 * (x * z - w * y)  # the world z of body x
    left_z = 2.0 * (y * z + w * x)  # of body y
    up_z = 1.0 - 2.0 * (x * x + y * y)  # of body z
    return math.degrees(math.asin(max(-1.0, min(1.0, nose_z)))), math.degrees(
        math.atan2(left_z, up_z)
    )


def motion(env, e: int, horizontal: bool = False, angles=("pitch_deg", "roll_deg")) -> dict:
    """Speed (over the ground; horizontal only if asked), height and attitude of body 0 of
    sub-env e (``angles``: the names of its pitch and roll), by series name."""
    sim = env.sim
    v = np.asarray(sim.lin_vel[e, 0], dtype=np.float64)
    pitch, roll = attitude_deg(sim.quat[e, 0])
    return {
        "speed_mps": float(np.linalg.norm(v[:2] if horizontal else v)),
        "altitude_m": float(sim.pos[e, 0, 2]),
        angles[0]: pitch,
        angles[1]: roll,
    }
