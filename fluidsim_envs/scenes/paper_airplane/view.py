"""PaperAirplane-v0's frames: a chase view of the dart over the ground grid (1 m), with the
target (red ring and post) and the dart's height stalk."""

from __future__ import annotations

import numpy as np

from ...physics.kernels import quat_matrices
from ..drawing import CraftMesh, chase_camera, fill_ground
from ..render import Canvas

SKY, GROUND, GRID = (200, 222, 245), (186, 204, 170), (120, 150, 110)
TARGET, STALK = (210, 40, 40), (90, 90, 90)


class PaperAirplaneView:
    """Frames of a PaperAirplane-v0 vector env; keeps the dart's mesh."""

    def __init__(self, env) -> None:
        self.env = env
        self.mesh = CraftMesh(env.craft)

    def frame(self, e: int) -> np.ndarray:
        """Chase view of sub-env e: the dart, the ground grid, the target and its bearing."""
        env = self.env
        pos = np.array(env.sim.pos[e, 0], dtype=np.float64)
        rot = quat_matrices(np.ascontiguousarray(env.sim.quat[e], dtype=np.float64))[0]
        camera = chase_camera(pos, rot, back_m=0.7, up_m=0.25)
        canvas = Canvas(camera.width, camera.height, background=SKY)
        fill_ground(canvas, camera, GROUND)
        canvas.ground_grid(camera, pos[:2], 20.0, 1.0, GRID)
        tx, ty = env.target_xy(e)
        ring = np.linspace(0.0, 2.0 * np.pi, 25)
        circle = np.stack([tx + np.cos(ring), ty + np.sin(ring), 0 * ring], 1)
        canvas.lines(camera, circle[:-1], circle[1:], TARGET, thickness=2)
        canvas.lines(camera, [(tx, ty, 0.0)], [(tx, ty, 0.5)], TARGET, thickness=2)
        canvas.lines(camera, [(pos[0], pos[1], 0.0)], [pos], STALK)  # height stalk
        self.mesh.draw(canvas, camera, pos, rot)
        return canvas.image()
