"""BoatOnStep-v0 in a Rerun recording: calm water (once) or the swell's surface around the boat
(every ``SWELL_EVERY`` steps), the buoys and gates (each episode), speed, height, trim and heel
(each step)."""

from __future__ import annotations

import numpy as np

from ..rerun import BUOY, PLANE_HALF_M, WATER, grid_triangles, log_motion, plane

SWELL_EVERY = 5  # steps between re-logs of a moving (swell) water surface
SWELL_HALF_M, SWELL_CELLS = 40.0, 32  # that surface: a square around the boat, its cells


class BoatOnStepRerun:
    """The scene's Rerun hooks (see :class:`~fluidsim_envs.scenes.rerun.RerunHooks`)."""

    def __init__(self, logger) -> None:
        self.lg = logger
        self.env = logger.base

    def world(self, e: int) -> None:
        if not self.env.world.swell:  # calm: one flat sheet; a swell is logged as it moves
            self.lg.log(e, "water", plane(self.lg.rr, 0.0, PLANE_HALF_M, WATER), static=True)

    def episode(self, e: int) -> None:
        lg, env, rr = self.lg, self.env, self.lg.rr
        marks = np.concatenate([env.buoys[e], np.zeros((len(env.buoys[e]), 1))], axis=1)
        lg.log(e, "buoys", rr.Points3D(marks, radii=env.params.buoy_radius_m, colors=BUOY))
        lg.log(e, "gates", rr.LineStrips3D(np.stack([marks[0::2], marks[1::2]], 1), colors=BUOY))

    def step(self, e: int, info: dict | None) -> None:
        lg, env = self.lg, self.env
        log_motion(lg, e, horizontal=True, angles=("trim_deg", "heel_deg"))
        if env.world.swell and lg.step_index % SWELL_EVERY == 0:
            n = SWELL_CELLS
            x0, y0 = (float(c) for c in env.sim.pos[e, 0, :2])
            u = np.linspace(-SWELL_HALF_M, SWELL_HALF_M, n + 1)
            x, y = np.meshgrid(x0 + u, y0 + u, indexing="ij")
            z = env.world.surface_height(x, y, env.sim.clock[e])
            vertices = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
            lg.log(
                e,
                "water",
                lg.rr.Mesh3D(
                    vertex_positions=vertices,
                    triangle_indices=grid_triangles(n),
                    albedo_factor=WATER,
                ),
            )
