"""PaperAirplane-v0 in a Rerun recording: the ground (once), the target and its success ring
(each episode), speed, height, attitude and the distance to the target (each step)."""

from __future__ import annotations

import numpy as np

from ..rerun import GROUND, TARGET, log_motion, plane


class PaperAirplaneRerun:
    """The scene's Rerun hooks (see :class:`~fluidsim_envs.scenes.rerun.RerunHooks`)."""

    def __init__(self, logger) -> None:
        self.lg = logger
        self.env = logger.base

    def world(self, e: int) -> None:
        half = self.env.params.arena_radius_m
        self.lg.log(e, "ground", plane(self.lg.rr, 0.0, half, GROUND), static=True)

    def episode(self, e: int) -> None:
        lg, env, rr = self.lg, self.env, self.lg.rr
        tx, ty = env.target_xy(e)
        ring = np.linspace(0.0, 2.0 * np.pi, 49)
        r = env.params.success_radius_m
        circle = np.stack([tx + r * np.cos(ring), ty + r * np.sin(ring), 0.0 * ring], axis=1)
        lg.log(e, "target", rr.Points3D([[tx, ty, 0.0]], radii=0.1, colors=TARGET))
        lg.log(e, "target/ring", rr.LineStrips3D([circle], colors=TARGET))

    def step(self, e: int, info: dict | None) -> None:
        log_motion(self.lg, e)
        if info is not None:
            self.lg.scalar(e, "state/distance_to_target_m", info["distance_m"][e])
