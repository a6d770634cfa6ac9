"""SubmarineWake-v0's frames: a plan (top view) over an elevation (side view), both in the
lead's heading frame and centered between the lead and the station point, with the wake's
tracers colored by the water's speed.

The view reads the env's public state (the vehicle's pose, ``lead_pose``, ``station_point``,
``lead``, ``wake``, ``noise_offset``, ``episode_steps``, ``episodes``) and owns the tracers of the
sub-envs it has drawn: it advances them by the steps taken since its last frame, and reseeds
them when the sub-env's episode restarts. Drawn every step, they move exactly as the water
does step by step."""

from __future__ import annotations

import math

import numpy as np

from ...physics.kernels import quat_matrices
from ...physics.tracers import Tracers
from ..render import Canvas, OrthoCamera
from . import kernel as TK

WIDTH, HEIGHT = 480, 240
SCALE = 6.0  # pixels per meter: 80 m across
TRACERS = 1500
WATER, FLOOR, HULL = (18, 52, 86), (150, 130, 90), (170, 175, 185)
VEHICLE, STATION = (250, 200, 40), (90, 230, 120)


def _heading_frame(env, e: int) -> np.ndarray:
    """The lead's heading frame (columns: forward, left, up) in sub-env e."""
    h = env.lead_heading(e)
    c, s = math.cos(h), math.sin(h)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def start_tracers(env, e: int, tracers: Tracers | None = None) -> Tracers:
    """(Re)seed the tracers of sub-env e around its lead; they only serve the picture, so
    their generator is fixed by e rather than drawn from the episode's."""
    pos, quat, vel = env.lead_pose(e)
    tr = Tracers(env.wake, count=TRACERS) if tracers is None else tracers
    tr.reset(pos, quat, vel, np.random.default_rng(e), env.noise_offset[e])
    return tr


def advance_tracers(env, e: int, tr: Tracers, dt: float) -> None:
    """Move sub-env e's tracers on by ``dt`` in the water around its lead as it is now."""
    pos, quat, vel = env.lead_pose(e)
    tr.advance(dt, pos, quat, vel, env.noise_offset[e])


class WatchedTracers:
    """The tracers of the sub-envs one viewer watches, kept in step with the env: reseeded
    when a sub-env's episode restarts, advanced by one action period per step taken since the
    last look."""

    def __init__(self, env) -> None:
        self.env = env
        self.tracers: dict[int, Tracers] = {}
        self._seen: dict[int, tuple[int, int]] = {}  # sub-env -> (episode, steps) at last look

    def update(self, e: int) -> Tracers:
        env = self.env
        now = int(env.episodes[e]), int(env.episode_steps[e])
        seen = self._seen.get(e)
        if seen is None or seen[0] != now[0]:
            self.tracers[e] = start_tracers(env, e, self.tracers.get(e))
        else:
            dt = env.params.dt * env.params.substeps
            for _ in range(now[1] - seen[1]):
                advance_tracers(env, e, self.tracers[e], dt)
        self._seen[e] = now
        return self.tracers[e]


def _ellipse(center, axis_u, axis_v, a, b, n=48):
    t = np.linspace(0.0, 2.0 * np.pi, n + 1)
    pts = center + np.outer(a * np.cos(t), axis_u) + np.outer(b * np.sin(t), axis_v)
    return pts[:-1], pts[1:]


class SubmarineWakeView:
    """Frames of a SubmarineWake-v0 vector env: plan over elevation in the lead's heading
    frame, the lead's hull (gray), the vehicle (yellow), the station point (green cross), the
    floor (brown) and the wake's tracers (brighter where the water moves faster)."""

    def __init__(self, env) -> None:
        self.env = env
        self.watched = WatchedTracers(env)

    def frame(self, e: int) -> np.ndarray:
        """The [2 * HEIGHT, WIDTH, 3] image of sub-env e."""
        tr = self.watched.update(e) if self.env.params.wake else None
        return frame(self.env, e, tr)


def frame(env, e: int, tr: Tracers | None) -> np.ndarray:
    """The [2 * HEIGHT, WIDTH, 3] image of sub-env e, with the tracers ``tr`` (or none)."""
    lead_pos, _, _ = env.lead_pose(e)
    rot = _heading_frame(env, e)
    fwd, left, up = rot[:, 0], rot[:, 1], rot[:, 2]
    st = env.station[e]
    station = lead_pos + rot @ st
    middle = lead_pos + 0.5 * (rot @ st)
    vpos = np.asarray(env.sim.pos[e, 0], dtype=np.float64)
    vrot = quat_matrices(np.ascontiguousarray(env.sim.quat[e], dtype=np.float64))[0]
    images = []
    # plan: looking down, the lead's heading to the right, port up
    # elevation: looking from starboard... i.e. along +left, heading to the right, up up
    for view_rot in (np.stack([fwd, -left, -up]), np.stack([fwd, -up, left])):
        cam = OrthoCamera(middle, view_rot, SCALE, WIDTH, HEIGHT)
        canvas = Canvas(WIDTH, HEIGHT, background=WATER)
        if view_rot[2] @ up == 0.0:  # the elevation shows the floor
            floor = -env.params.floor_depth_m
            a = middle + np.array([0.0, 0.0, floor - middle[2]]) - 60 * fwd
            canvas.lines(cam, [a], [a + 120 * fwd], FLOOR, thickness=4)
        if tr is not None:
            speed = np.clip(tr.speeds / max(env.lead[TK.L_SPEED, e], 0.1), 0.0, 1.0)
            colors = np.stack([70 + 180 * speed, 110 + 120 * speed, 160 + 90 * speed], 1)
            canvas.points(cam, tr.positions, colors.astype(np.uint8), radius=0)
        u, v = (fwd, left) if view_rot[2] @ up != 0.0 else (fwd, up)
        p0, p1 = _ellipse(lead_pos, u, v, 0.5 * 40.0, 3.0)
        canvas.lines(cam, p0, p1, HULL, thickness=2)
        nose, tail = vpos + 1.2 * vrot[:, 0], vpos - 1.2 * vrot[:, 0]
        canvas.lines(cam, [tail], [nose], VEHICLE, thickness=3)
        for d in (u, v):
            canvas.lines(cam, [station - d], [station + d], STATION, thickness=1)
        images.append(canvas.image())
    out = np.concatenate(images, axis=0)
    out[HEIGHT - 1 : HEIGHT + 1] = 230  # the divider
    return out
