"""PaperAirplane-v0 in a Rerun recording: each episode, the ground around its course (the
launch point and the target), the target and its success ring; each step, speed, height,
attitude (``state``) and the distance to the target (``state/task``)."""

from __future__ import annotations

import numpy as np

from ..rerun import GROUND, TARGET, motion, patch, sheet

GROUND_MARGIN_M = 10.0  # the ground drawn this far beyond the launch point and the target
GRID_CLEARANCE_M = 0.005  # the ground drawn this far below z = 0, so the view's grid shows


class PaperAirplaneRerun:
    """The scene's Rerun hooks (see :class:`~fluidsim_envs.scenes.rerun.RerunHooks`)."""

    def __init__(self, logger) -> None:
        self.lg = logger
        self.env = logger.base

    def world(self, e: int) -> None:
        lg, rr = self.lg, self.lg.rr
        lg.log(e, "ground", sheet(rr, GROUND), static=True)
        lg.log(e, "target", rr.Points3D.from_fields(radii=0.1, colors=TARGET), static=True)
        lg.log(e, "target/ring", rr.LineStrips3D.from_fields(colors=TARGET), static=True)

    def episode(self, e: int) -> None:
        lg, env, rr = self.lg, self.env, self.lg.rr
        tx, ty = env.target_xy(e)
        ground = patch([env.sim.pos[e, 0, :2], (tx, ty)], -GRID_CLEARANCE_M, GROUND_MARGIN_M)
        lg.record(e, "ground", rr.Mesh3D, vertex_positions=ground)
        ring = np.linspace(0.0, 2.0 * np.pi, 49)
        r = env.params.success_radius_m
        circle = np.stack([tx + r * np.cos(ring), ty + r * np.sin(ring), 0.0 * ring], axis=1)
        lg.record(e, "target", rr.Points3D, positions=[[tx, ty, 0.0]])
        lg.record(e, "target/ring", rr.LineStrips3D, strips=circle[None])

    def step(self, e: int, info: dict | None) -> None:
        self.lg.scalars(e, "state", motion(self.env, e))
        if info is not None:
            self.lg.scalars(e, "state/task", {"distance_to_target_m": info["distance_m"][e]})
