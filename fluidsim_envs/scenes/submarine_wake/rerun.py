"""SubmarineWake-v0 in a Rerun recording: the lead submarine's render mesh (once); each
episode, the surface and the floor around the reach of its course; each step, the lead's
pose, the station point, speed, height, attitude and depth (``state``) and the distance to
the station (``state/task``); every ``TRACER_PERIOD_S``, ``TRACERS_LOGGED`` of the wake's
tracers. The tracers are the hooks' own (seeded at each episode's start, moved on one action
period per step)."""

from __future__ import annotations

import math

import numpy as np

from ...physics.tracers import Tracers
from ..rerun import FLOOR, WATER, mesh3d, motion, patch, sheet
from . import kernel as TK
from .mesh import lead_mesh
from .view import TRACERS, advance_tracers, start_tracers

TRACER_PERIOD_S = 0.5  # simulated time between logs of the tracers
TRACERS_LOGGED = 250  # of the TRACERS advected (every TRACERS // TRACERS_LOGGED-th)
STATION = (90, 230, 120)


class SubmarineWakeRerun:
    """The scene's Rerun hooks (see :class:`~fluidsim_envs.scenes.rerun.RerunHooks`)."""

    def __init__(self, logger) -> None:
        self.lg = logger
        self.env = logger.base
        self.tracers: dict[int, Tracers] = {}  # sub-env -> its tracers, with the wake on
        self._fresh: set[int] = set()  # sub-envs whose tracers were seeded this step
        self.lead = lead_mesh(self.env.lead_craft, self.env.wake)

    def world(self, e: int) -> None:
        lg, rr = self.lg, self.lg.rr
        lead = mesh3d(rr, self.lead.posed(None), self.lead.triangles, self.lead.colors)
        lg.log(e, "lead/mesh", lead, static=True)
        lg.log(e, "station", rr.Points3D.from_fields(radii=0.3, colors=STATION), static=True)
        lg.log(e, "tracers", rr.Points3D.from_fields(radii=0.05), static=True)
        lg.log(e, "water", sheet(rr, WATER), static=True)
        lg.log(e, "floor", sheet(rr, FLOOR), static=True)

    def episode(self, e: int) -> None:
        lg, rr, p = self.lg, self.lg.rr, self.env.params
        # the lead's reach in an episode, around where it starts
        reach = max(p.lead_speed_mps) * p.max_episode_steps * p.dt * p.substeps
        start = self.env.lead_pose(e)[0][:2]
        lg.record(e, "water", rr.Mesh3D, vertex_positions=patch([start], 0.0, reach))
        floor = patch([start], -p.floor_depth_m, reach)
        lg.record(e, "floor", rr.Mesh3D, vertex_positions=floor)
        if p.wake:
            self.tracers[e] = start_tracers(self.env, e, self.tracers.get(e))
            self._fresh.add(e)

    def step(self, e: int, info: dict | None) -> None:
        lg, env, rr = self.lg, self.env, self.lg.rr
        lg.scalars(e, "state", {**motion(env, e), "depth_m": -float(env.sim.pos[e, 0, 2])})
        if info is not None:
            lg.scalars(e, "state/task", {"station_distance_m": info["station_distance_m"][e]})
        pos, _, _ = env.lead_pose(e)
        h = env.lead_heading(e)
        turn = [[0.0, 0.0, math.sin(h / 2), math.cos(h / 2)]]
        lg.record(e, "lead", rr.Transform3D, translation=[pos], quaternion=turn)
        lg.record(e, "station", rr.Points3D, positions=[env.station_point(e)])
        self._tracers(e)

    def _tracers(self, e: int) -> None:
        lg, env = self.lg, self.env
        tracers = self.tracers.get(e)
        if tracers is None:
            return
        if e in self._fresh:
            self._fresh.discard(e)
        else:  # one step on since the last row
            advance_tracers(env, e, tracers, env.params.dt * env.params.substeps)
        if lg.every(e, TRACER_PERIOD_S):
            shown = slice(None, None, max(1, TRACERS // TRACERS_LOGGED))
            speed = np.clip(tracers.speeds[shown] / max(env.lead[TK.L_SPEED, e], 0.1), 0.0, 1.0)
            colors = np.stack([70 + 180 * speed, 110 + 120 * speed, 160 + 90 * speed], 1)
            positions = tracers.positions[shown]
            lg.record(
                e, "tracers", lg.rr.Points3D, positions=positions, colors=colors.astype(np.uint8)
            )
