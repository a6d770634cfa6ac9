"""SubmarineWake-v0's frames: a plan (top view) over an elevation (side view), both in the
lead's heading frame and centered between the lead and the station point, with the wake's
tracers colored by the water's speed."""

from __future__ import annotations

import math

import numpy as np

from ..physics.kernels import quat_matrices
from ..physics.tracers import Tracers
from . import submarine_wake_kernel as TK
from .render import Canvas, OrthoCamera

WIDTH, HEIGHT = 480, 240
SCALE = 6.0  # pixels per meter: 80 m across
TRACERS = 1500
WATER, FLOOR, HULL = (18, 52, 86), (150, 130, 90), (170, 175, 185)
VEHICLE, STATION = (250, 200, 40), (90, 230, 120)


def _lead_pose(env, e):
    lead = env.lead[:, e]
    h = lead[TK.L_HEADING]
    c, s = math.cos(h), math.sin(h)
    pos = lead[[TK.L_X, TK.L_Y, TK.L_Z]].copy()
    quat = np.array([math.cos(h / 2), 0.0, 0.0, math.sin(h / 2)])
    vel = np.array([lead[TK.L_SPEED] * c, lead[TK.L_SPEED] * s, 0.0])
    return pos, quat, vel, np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def start_tracers(env, e: int, tracers: Tracers | None = None) -> Tracers:
    """(Re)seed the tracers of sub-env e around its lead; they only serve the picture, so
    their generator is fixed by e rather than drawn from the episode's."""
    pos, quat, vel, _ = _lead_pose(env, e)
    tr = Tracers(env.wake, count=TRACERS) if tracers is None else tracers
    tr.reset(pos, quat, vel, np.random.default_rng(e), env.noise_offset[e])
    return tr


def advance_tracers(env, e: int, tr: Tracers, dt: float) -> None:
    pos, quat, vel, _ = _lead_pose(env, e)
    tr.advance(dt, pos, quat, vel, env.noise_offset[e])


def _ellipse(center, axis_u, axis_v, a, b, n=48):
    t = np.linspace(0.0, 2.0 * np.pi, n + 1)
    pts = center + np.outer(a * np.cos(t), axis_u) + np.outer(b * np.sin(t), axis_v)
    return pts[:-1], pts[1:]


def frame(env, e: int) -> np.ndarray:
    """The [2 * HEIGHT, WIDTH, 3] image of sub-env e."""
    lead_pos, _, _, rot = _lead_pose(env, e)
    fwd, left, up = rot[:, 0], rot[:, 1], rot[:, 2]
    st = env.station[e]
    station = lead_pos + rot @ st
    middle = lead_pos + 0.5 * (rot @ st)
    vpos = np.asarray(env.sim.pos[e, 0], dtype=np.float64)
    vrot = quat_matrices(np.ascontiguousarray(env.sim.quat[e], dtype=np.float64))[0]
    tr = env._tracers.get(e) if env.params.wake else None
    if tr is None and env.params.wake:  # first look at this env: start showing its wake
        tr = env._tracers[e] = start_tracers(env, e)
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
