"""What the scenes' Rerun hooks share: the hooks' protocol, level planes and grids, the body's
motion scalars, colors. Rerun itself is not imported here: the hooks draw through the logger's
``rr`` (:class:`~fluidsim_envs.wrappers.rerun_logger.RerunLogger`), so this module imports
without it."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

if TYPE_CHECKING:
    import rerun

PLANE_HALF_M = 1000.0  # static planes (calm water, sea floor): far beyond any course
WATER, GROUND, FLOOR = (40, 110, 170, 120), (150, 180, 130), (150, 130, 90)
TARGET, BUOY = (210, 40, 40), (250, 140, 20)


class RerunHooks(Protocol):
    """A scene's part of a Rerun recording, made once per logger as ``hooks(logger)``; it
    reads the env (``logger.base``) through its public accessors and keeps its own state."""

    def world(self, e: int) -> None:
        """Static geometry of sub-env e, logged once."""

    def episode(self, e: int) -> None:
        """At the start of each episode of sub-env e (before that step's :meth:`step`)."""

    def step(self, e: int, info: dict[str, Any] | None) -> None:
        """After every reset (``info`` None) and step of sub-env e."""


def plane(rr: rerun, z: float, half: float, color):
    """A level square at height z, centered over the origin: a Mesh3D of two triangles."""
    corners = [[-half, -half, z], [half, -half, z], [half, half, z], [-half, half, z]]
    return rr.Mesh3D(
        vertex_positions=corners, triangle_indices=[[0, 1, 2], [0, 2, 3]], albedo_factor=color
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


def log_motion(lg, e: int, horizontal: bool = False, angles=("pitch_deg", "roll_deg")) -> None:
    """Speed (over the ground; horizontal only if asked), height and attitude of body 0
    (``angles``: the names of its pitch and roll)."""
    sim = lg.base.sim
    v = np.asarray(sim.lin_vel[e, 0], dtype=np.float64)
    lg.scalar(e, "state/speed_mps", np.linalg.norm(v[:2] if horizontal else v))
    lg.scalar(e, "state/altitude_m", sim.pos[e, 0, 2])
    pitch, roll = attitude_deg(sim.quat[e, 0])
    lg.scalar(e, f"state/{angles[0]}", pitch)
    lg.scalar(e, f"state/{angles[1]}", roll)
