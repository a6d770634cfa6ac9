"""SubmarineWake-v0 in a Rerun recording: the surface, the floor and the lead's hull (once);
the lead's pose, the station point and the wake's tracers, with speed, height, attitude, depth
and the distance to the station (each step). The tracers are the hooks' own (seeded at each
episode's start, moved on one action period per step)."""

from __future__ import annotations

import math

import numpy as np

from ...physics.tracers import Tracers
from ..rerun import FLOOR, PLANE_HALF_M, WATER, log_motion, plane
from . import kernel as TK
from .env import LEAD_LENGTH_M, LEAD_RADIUS_M
from .view import advance_tracers, start_tracers


class SubmarineWakeRerun:
    """The scene's Rerun hooks (see :class:`~fluidsim_envs.scenes.rerun.RerunHooks`)."""

    def __init__(self, logger) -> None:
        self.lg = logger
        self.env = logger.base
        self.tracers: dict[int, Tracers] = {}  # sub-env -> its tracers, with the wake on
        self._fresh: set[int] = set()  # sub-envs whose tracers were seeded this step

    def world(self, e: int) -> None:
        lg, rr, p = self.lg, self.lg.rr, self.env.params
        lg.log(e, "water", plane(rr, 0.0, PLANE_HALF_M, WATER), static=True)
        lg.log(e, "floor", plane(rr, -p.floor_depth_m, PLANE_HALF_M, FLOOR), static=True)
        half = [0.5 * LEAD_LENGTH_M, LEAD_RADIUS_M, LEAD_RADIUS_M]
        hull = rr.Ellipsoids3D(half_sizes=[half], colors=(120, 125, 135), fill_mode="solid")
        lg.log(e, "lead/hull", hull, static=True)

    def episode(self, e: int) -> None:
        if self.env.params.wake:
            self.tracers[e] = start_tracers(self.env, e, self.tracers.get(e))
            self._fresh.add(e)

    def step(self, e: int, info: dict | None) -> None:
        lg, env, rr = self.lg, self.env, self.lg.rr
        log_motion(lg, e)
        lg.scalar(e, "state/depth_m", -env.sim.pos[e, 0, 2])
        if info is not None:
            lg.scalar(e, "state/station_distance_m", info["station_distance_m"][e])
        pos, _, _ = env.lead_pose(e)
        heading = env.lead_heading(e)
        turn = rr.Quaternion(xyzw=[0.0, 0.0, math.sin(heading / 2), math.cos(heading / 2)])
        lg.log(e, "lead", rr.Transform3D(translation=pos, quaternion=turn))
        lg.log(e, "station", rr.Points3D([env.station_point(e)], radii=0.3, colors=(90, 230, 120)))
        tracers = self.tracers.get(e)
        if tracers is None:
            return
        if e in self._fresh:
            self._fresh.discard(e)
        else:  # one step on since the last log
            advance_tracers(env, e, tracers, env.params.dt * env.params.substeps)
        speed = np.clip(tracers.speeds / max(env.lead[TK.L_SPEED, e], 0.1), 0.0, 1.0)
        colors = np.stack([70 + 180 * speed, 110 + 120 * speed, 160 + 90 * speed], 1)
        lg.log(
            e, "tracers", rr.Points3D(tracers.positions, radii=0.05, colors=colors.astype(np.uint8))
        )
