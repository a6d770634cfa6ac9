"""SubmarineWake-v0's frames (480 x 480): a plan (top view) over an elevation (side view, from
starboard), both in the lead's heading frame (its bow to the right) and centered between the
lead and the station point, 6 px/m (80 m across).

- The lead submarine and the UUV are their render meshes (:mod:`.mesh`), shaded by the sun;
  the UUV's rudder and dive planes turn with the commands the physics last used.
- The water is colored by its speed (the wake field's, as a share of the lead's speed; scale
  bottom left of the elevation) in the plane through the UUV: horizontal in the plan, along
  the lead's heading in the elevation. Still water stays dark blue; the displacement flow
  around the hull, the screw vortices behind it and the turbulence glow cyan to yellow. The
  tracers are white dots that drift with the water.
- The station point is a magenta cross; the floor a sand band in the elevation.
- An inset (bottom right of each panel, 5 times larger) follows the UUV, so that its fins
  can be seen; the readout (top left) gives the time, the distance to the station, the depth,
  the speeds and the three commands.

The view reads the env's public state (the vehicle's pose, ``lead_pose``, ``station``,
``lead``, ``wake``, ``noise_offset``, ``episode_steps``, ``episodes``) and owns the tracers of the
sub-envs it has drawn: it advances them by the steps taken since its last frame, and reseeds
them when the sub-env's episode restarts. Drawn every step, they move exactly as the water
does step by step."""

from __future__ import annotations

import math

import numpy as np

from ...physics.kernels import quat_matrices
from ...physics.tracers import Tracers
from ..drawing import draw_mesh, number, readout, signed
from ..mesh import RenderMesh
from ..render import Canvas, OrthoCamera
from . import kernel as TK
from .mesh import lead_mesh, meshes

WIDTH, HEIGHT = 480, 240
SCALE = 6.0  # pixels per meter: 80 m across
TRACERS = 1500
WATER, FLOOR, SAND = (18, 52, 86), (150, 130, 90), (112, 98, 70)
STATION, FRAME, LABEL = (255, 80, 220), (200, 205, 215), (200, 210, 225)
TRACER = (200, 215, 235)
SLICE_STEP = 4  # pixels between the wake field's samples in a slice (interpolated between)
INSET_W, INSET_H, INSET_SCALE = 150, 96, 30.0  # the UUV's inset: 5 m x 3.2 m
# water colors from still (0) to SPEED_TOP times the lead's speed (and beyond), on a square
# root scale: the far wake and the turbulence move a few percent of the lead's speed, the flow
# past the hull and the vortex cores tens of percent, and both should read
SPEED_TOP = 0.5
RAMP = np.array([WATER, (30, 104, 160), (50, 180, 205), (230, 220, 100), (255, 245, 225)])


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


def speed_colors(speed: np.ndarray, lead_speed: float) -> np.ndarray:
    """``[..., 3]`` uint8: colors along ``RAMP`` for water speeds ``[...]`` from 0 to
    ``SPEED_TOP`` times the lead's speed, square-root scaled (clipped beyond; NaN as still
    water)."""
    return _LUT[(255.0 * _scaled(speed, lead_speed)).astype(np.uint8)]


def _scaled(speed: np.ndarray, lead_speed: float) -> np.ndarray:
    """Speeds on the color scale: 0 (still) to 1 (``SPEED_TOP`` of the lead's speed)."""
    s = np.nan_to_num(np.asarray(speed, dtype=np.float64) / (SPEED_TOP * max(lead_speed, 0.1)))
    return np.sqrt(np.clip(s, 0.0, 1.0))


def _lut() -> np.ndarray:
    """``RAMP`` interpolated into 256 colors (a lookup is ~10x faster than interpolating each
    pixel of a slice)."""
    u = np.linspace(0.0, len(RAMP) - 1, 256)
    k = np.minimum(u.astype(np.intp), len(RAMP) - 2)
    f = (u - k)[:, None]
    return ((1.0 - f) * RAMP[k] + f * RAMP[k + 1]).round().astype(np.uint8)


_LUT = _lut()


def wake_slice(env, e: int, cam: OrthoCamera, through, lead_speed: float) -> np.ndarray:
    """``[H, W, 3]`` uint8: sub-env e's water colored by its speed (:func:`speed_colors`) in
    the plane through the point ``through`` facing the camera ``cam``, one color per pixel.
    The wake field is sampled every ``SLICE_STEP`` pixels (it varies over meters) and its
    colors interpolated (bilinear) between, in the scale's coordinate."""
    h, w = -(-cam.height // SLICE_STEP) + 1, -(-cam.width // SLICE_STEP) + 1
    right, down, ahead = cam.rotation
    base = cam.eye + ((np.asarray(through) - cam.eye) @ ahead) * ahead
    u = (np.arange(w) * SLICE_STEP - 0.5 * cam.width) / cam.scale
    v = (np.arange(h) * SLICE_STEP - 0.5 * cam.height) / cam.scale
    pts = (base + u[None, :, None] * right + v[:, None, None] * down).reshape(-1, 3)
    pos, quat, vel = env.lead_pose(e)
    if not np.isfinite(pts).all():
        return np.broadcast_to(_LUT[0], (cam.height, cam.width, 3))
    flow = env.wake.velocity(pts, pos, quat, vel, env.noise_offset[e])
    scaled = _scaled(np.linalg.norm(flow, axis=1), lead_speed).astype(np.float32)
    fine = _resample(scaled.reshape(h, w), cam.height, cam.width)
    return _LUT[(255.0 * fine).astype(np.uint8)]


def _resample(coarse: np.ndarray, rows: int, cols: int) -> np.ndarray:
    """Bilinear interpolation of samples ``SLICE_STEP`` pixels apart (the first at pixel
    corner 0) onto the pixel centers of a ``[rows, cols]`` image."""

    def at(n: int, m: int) -> tuple[np.ndarray, np.ndarray]:  # coarse index, weight of next
        t = (np.arange(n) + 0.5) / SLICE_STEP
        k = np.minimum(t.astype(np.intp), m - 2)
        return k, (t - k).astype(coarse.dtype)

    kr, fr = at(rows, coarse.shape[0])
    kc, fc = at(cols, coarse.shape[1])
    c = coarse[kr] * (1.0 - fr[:, None]) + coarse[kr + 1] * fr[:, None]  # [rows, m]
    return c[:, kc] * (1.0 - fc) + c[:, kc + 1] * fc


class SubmarineWakeView:
    """Frames of a SubmarineWake-v0 vector env (see the module docstring); keeps the meshes
    and the watched tracers."""

    def __init__(self, env) -> None:
        self.env = env
        self.watched = WatchedTracers(env)
        (self.uuv,) = meshes(env)
        self.lead = lead_mesh(env.lead_craft, env.wake)

    def frame(self, e: int) -> np.ndarray:
        """The [2 * HEIGHT, WIDTH, 3] image of sub-env e."""
        tr = self.watched.update(e) if self.env.params.wake else None
        return frame(self.env, e, tr, self.uuv, self.lead)


def frame(env, e: int, tr: Tracers | None, uuv: RenderMesh, lead: RenderMesh) -> np.ndarray:
    """The [2 * HEIGHT, WIDTH, 3] image of sub-env e, with the tracers ``tr`` (or none)."""
    lead_pos, _, _ = env.lead_pose(e)
    rot = _heading_frame(env, e)  # also the lead's attitude: level, turned to its heading
    fwd, left, up = rot[:, 0], rot[:, 1], rot[:, 2]
    station = lead_pos + rot @ env.station[e]
    middle = lead_pos + 0.5 * (rot @ env.station[e])
    vpos = np.asarray(env.sim.pos[e, 0], dtype=np.float64)
    vrot = quat_matrices(np.ascontiguousarray(env.sim.quat[e], dtype=np.float64))[0]
    commands = np.asarray(env.sim.controls[e], dtype=np.float64)
    lead_speed = float(env.lead[TK.L_SPEED, e])
    through = vpos if np.isfinite(vpos).all() else station

    def scene(canvas: Canvas, cam: OrthoCamera, plan: bool, radius: int) -> None:
        if env.params.wake:
            canvas.blit(0, 0, wake_slice(env, e, cam, through, lead_speed))
        if not plan:  # the floor: sand below its line
            floor = np.array([middle[0], middle[1], -env.params.floor_depth_m])
            canvas.fill_rows(cam.project(floor[None])[0][0, 1], cam.height, SAND)
        draw_mesh(canvas, cam, lead, None, lead_pos, rot)
        draw_mesh(canvas, cam, uuv, commands, vpos, vrot)
        if tr is not None:
            canvas.points(cam, tr.positions, TRACER, radius=radius, depth_test=True)
        u, v = (fwd, left) if plan else (fwd, up)
        for d in (u, v):
            canvas.lines(cam, [station - d], [station + d], STATION)

    images = []
    # plan: looking down, the lead's heading to the right, port up;
    # elevation: looking from starboard (along +left), heading to the right, up up
    for plan, view_rot in (
        (True, np.stack([fwd, -left, -up])),
        (False, np.stack([fwd, -up, left])),
    ):
        cam = OrthoCamera(middle, view_rot, SCALE, WIDTH, HEIGHT)
        canvas = Canvas(WIDTH, HEIGHT, background=WATER)
        scene(canvas, cam, plan, radius=0)
        if plan:
            readout(canvas, _lines(env, e, vpos, station, lead_speed, commands))
        else:
            _speed_scale(canvas)
        img = canvas.image()
        zoom = OrthoCamera(through, view_rot, INSET_SCALE, INSET_W, INSET_H)
        inset = Canvas(INSET_W, INSET_H, background=WATER)
        scene(inset, zoom, plan, radius=1)
        readout(inset, [f"UUV x{INSET_SCALE / SCALE:g}"], x=2, y=2)
        _paste(img, inset.image())
        images.append(img)
    out = np.concatenate(images, axis=0)
    out[HEIGHT - 1 : HEIGHT + 1] = 230  # the divider
    return out


def _paste(img: np.ndarray, inset: np.ndarray) -> None:
    """Put ``inset`` in the bottom-right corner of ``img``, framed."""
    h, w, _ = inset.shape
    y0, x0 = img.shape[0] - h - 6, img.shape[1] - w - 6
    img[y0 - 1 : y0 + h + 1, x0 - 1 : x0 + w + 1] = FRAME
    img[y0 : y0 + h, x0 : x0 + w] = inset


def _speed_scale(canvas: Canvas) -> None:
    """The water's color scale, bottom left: 0 to SPEED_TOP of the lead's speed."""
    x0, y0, w = 8, canvas.height - 24, 96
    canvas.rect(x0 - 3, y0 - 3, x0 + w + 74, y0 + 19, (10, 20, 30), alpha=0.6)
    ramp = speed_colors(np.linspace(0.0, SPEED_TOP, w), 1.0)
    canvas.blit(x0, y0, np.broadcast_to(ramp, (6, w, 3)))
    canvas.text(x0, y0 + 9, "0", LABEL)
    canvas.text(x0 + w - 54, y0 + 9, f"{SPEED_TOP:g}x lead", LABEL)
    canvas.text(x0 + w + 6, y0, "water speed", LABEL)


def _lines(env, e, vpos, station, lead_speed, commands) -> list[str]:
    p = env.params
    t = float(env.episode_steps[e]) * p.dt * p.substeps
    speed = float(np.linalg.norm(env.sim.lin_vel[e, 0]))
    cmd = dict(zip(env.sim.control_names, commands.tolist(), strict=True))
    return [
        f"t {t:4.1f} s  station {number(float(np.linalg.norm(vpos - station)))} m"
        f"  depth {number(-float(vpos[2]))} m",
        f"uuv {number(speed, 2)} m/s  lead {lead_speed:.2f} m/s"
        f"  return {number(float(env.episode_return[e]), 1)}",
        f"thrust {signed(cmd['thrust'])} rudder {signed(cmd['rudder'])}"
        f" planes {signed(cmd['dive_planes'])}",
    ]
