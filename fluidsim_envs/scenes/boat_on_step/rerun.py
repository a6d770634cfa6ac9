"""BoatOnStep-v0 in a Rerun recording: each episode, the buoys, the gates and (calm water)
the water around the course; each step, speed, height, trim and heel (``state``), and with a
swell its surface around the boat (every ``SWELL_PERIOD_S``)."""

from __future__ import annotations

import numpy as np

from ..rerun import BUOY, WATER, grid_triangles, motion, patch, sheet

WATER_MARGIN_M = 30.0  # calm water drawn this far beyond the start and the buoys
SWELL_PERIOD_S = 0.5  # simulated time between logs of a moving (swell) water surface
SWELL_HALF_M, SWELL_CELLS = 40.0, 16  # that surface: a square around the boat, its cells


class BoatOnStepRerun:
    """The scene's Rerun hooks (see :class:`~fluidsim_envs.scenes.rerun.RerunHooks`)."""

    def __init__(self, logger) -> None:
        self.lg = logger
        self.env = logger.base

    def world(self, e: int) -> None:
        lg, rr, env = self.lg, self.lg.rr, self.env
        swell = bool(env.world.swell)  # a moving surface, or a flat patch each episode
        water = sheet(rr, WATER, grid_triangles(SWELL_CELLS)) if swell else sheet(rr, WATER)
        lg.log(e, "water", water, static=True)
        marks = rr.Points3D.from_fields(radii=env.params.buoy_radius_m, colors=BUOY)
        lg.log(e, "buoys", marks, static=True)
        lg.log(e, "gates", rr.LineStrips3D.from_fields(colors=BUOY), static=True)

    def episode(self, e: int) -> None:
        lg, env, rr = self.lg, self.env, self.lg.rr
        marks = np.concatenate([env.buoys[e], np.zeros((len(env.buoys[e]), 1))], axis=1)
        lg.record(e, "buoys", rr.Points3D, positions=marks)
        lg.record(e, "gates", rr.LineStrips3D, strips=np.stack([marks[0::2], marks[1::2]], 1))
        if not env.world.swell:
            course = np.concatenate([env.sim.pos[e, :1, :2], env.buoys[e]])
            lg.record(e, "water", rr.Mesh3D, vertex_positions=patch(course, 0.0, WATER_MARGIN_M))

    def step(self, e: int, info: dict | None) -> None:
        lg, env = self.lg, self.env
        lg.scalars(e, "state", motion(env, e, horizontal=True, angles=("trim_deg", "heel_deg")))
        if env.world.swell and lg.every(e, SWELL_PERIOD_S):
            n = SWELL_CELLS
            x0, y0 = (float(c) for c in env.sim.pos[e, 0, :2])
            u = np.linspace(-SWELL_HALF_M, SWELL_HALF_M, n + 1)
            x, y = np.meshgrid(x0 + u, y0 + u, indexing="ij")
            z = env.world.surface_height(x, y, env.sim.clock[e])
            vertices = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
            lg.record(e, "water", lg.rr.Mesh3D, vertex_positions=vertices)
