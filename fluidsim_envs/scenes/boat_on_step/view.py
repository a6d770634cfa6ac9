"""BoatOnStep-v0's frames: a plan (top view) over an elevation (side view), 480 x 480 px.

- Plan, 480 x 300 px: north-up world frame (world x, east, to the right; world y, north, up),
  centered on the boat, 3 px/m (160 m across, 100 m high; a 10 m grid that stays put in the
  world): the course legs from the start point through the gates, each gate's buoys (port
  buoy red, starboard green; the next gate larger and joined by a yellow line, gates behind
  the boat dimmed, with their legs), the wake (the boat's last 2.5 s of track, fading with
  age) and the hull's planform turned to the boat's attitude. The readout (top left): the
  episode's time, the next gate, the speed against the target and the three commands.
- Elevation, 480 x 180 px: seen from starboard, the boat's heading to the right, 52 px/m
  (about 9 m across), the hull's profile (keel, chine and sheer lines) turned by its trim and
  heel and raised by its heave over the water surface line (calm water at z = 0, or the
  swell along the view at the sub-env's clock),
  the outboard's leg and propeller, the skeg and rudder, the windscreen and the trim tab at
  its deflection (the last action's; flush at -1, fully down at +1). Along the bottom, a
  speed bar: speed over the ground from 0 (left) to 1.5 times the highest target speed,
  green within ``speed_scale_mps`` of the target and amber outside, with a white tick at the
  episode's target and small ticks every 5 m/s.

The hull's shapes come from the craft's samples (:class:`HullShape`): no boat dimension is
written here. The view reads the env's public state (poses, ``course``, ``buoy_xy``,
``next_gate``, ``target_speed``, ``last_action``, ``episode_steps``, ``episodes``) and keeps
its own: the wake of each rendered sub-env (:attr:`BoatOnStepView.tracks`), which restarts
when that sub-env's episode does.
"""

from __future__ import annotations

import math

import numpy as np

from ...physics import Craft
from ...physics.kernels import quat_matrices
from ..drawing import EDGE_COLOR, PLATE_COLOR, number, readout, signed
from ..render import Canvas, OrthoCamera

WIDTH, PLAN_H, SIDE_H = 480, 300, 180
PLAN_SCALE = 3.0  # px/m: 160 m across
SIDE_SCALE = 52.0  # px/m: 9.2 m across
SIDE_CENTER_Z = 0.1  # m: the elevation's center height while the boat is near the surface
GRID_M = 10.0
TRACK_LEN = 50  # positions kept for the wake: 2.5 s at 20 actions per second
PROP_RADIUS_M = 0.17  # drawn size of the propeller (a 13-14 inch outboard propeller)
SCREEN_RAKE = 0.4  # drawn windscreen: aft per unit of height
COWL_M = 0.35  # drawn size of the outboard's cowl, over the sheer

WATER, GRID = (38, 86, 128), (50, 100, 144)
SKY, SURFACE = (200, 225, 245), (235, 245, 252)
COURSE, DIM = (150, 182, 210), (92, 112, 132)
PORT, STARBOARD, NEXT_GATE = (225, 60, 50), (60, 200, 95), (250, 210, 40)
HULL, EDGE = PLATE_COLOR, EDGE_COLOR
WAKE = (222, 236, 248)
GEAR, GLASS, TAB = (72, 72, 84), (120, 165, 200), (250, 150, 30)
BAR_BG, BAR_OK, BAR_OFF, TICK = (22, 50, 78), (90, 210, 110), (240, 170, 50), (255, 255, 255)
READOUT = (255, 235, 160)  # apart from the wake's and the hull's colors

# plan: camera right = world x, down = world -y, looking down (-z)
PLAN_ROT = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])


class HullShape:
    """The hull's outlines in the body frame (m; x forward, y left, z up), from the craft.

    Stations are the bottom plates' x positions; at each, the keel and chine follow from the
    line through the port plates' centers (the V bottom at its deadrise) and the chine
    half-beam is the outer plus the inner plate's offset (strips of equal width). The transom
    and stem lie half a station beyond the first and last; the planform is pointed at the stem.
    The sheer is the topsides' top edge: their centers are halfway up from the chine at the
    transom (the topsides are a band of constant height over the prismatic run's chine).
    """

    def __init__(self, craft: Craft) -> None:
        plates = {p.name: p for p in craft.plates}
        bottom = np.array([p.offset_m for p in craft.plates if p.name.startswith("bottom")])
        xs = np.unique(bottom[:, 0])
        keel, chine_z, half = [], [], []
        for x in xs:
            st = bottom[(bottom[:, 0] == x) & (bottom[:, 1] > 0.0)]
            st = st[np.argsort(st[:, 1])]
            (y0, z0), (y1, z1) = st[0, 1:], st[-1, 1:]
            slope = (z1 - z0) / (y1 - y0) if y1 > y0 else 0.0
            half.append(y0 + y1 if y1 > y0 else 2.0 * y0)
            keel.append(z0 - slope * y0)
            chine_z.append(z0 + slope * (half[-1] - y0))
        ds = float(np.diff(xs).mean()) if len(xs) > 1 else 0.5
        self.transom_x, self.stem_x = xs[0] - 0.5 * ds, xs[-1] + 0.5 * ds

        def ends(v):  # flat to the transom, straight on to the stem
            rise = (v[-1] - v[-2]) / ds if len(v) > 1 else 0.0
            return np.array([v[0], *v, v[-1] + 0.5 * ds * rise])

        self.x = np.array([self.transom_x, *xs, self.stem_x])
        self.chine_z = ends(chine_z)
        sides = [p for p in craft.plates if p.name.startswith("topside")]
        if sides:
            self.sheer_z = float(np.mean([2 * p.offset_m[2] - chine_z[0] for p in sides]))
        else:
            self.sheer_z = float(max(chine_z)) + 0.3
        self.keel_z = np.minimum(ends(keel), self.sheer_z)
        self.chine_z = np.minimum(self.chine_z, self.sheer_z)
        self.half_beam = np.array([half[0], *half, 0.0])
        # the profile (y = 0) and the planform (z = chine) as body-frame triangles
        n = len(self.x)
        self.profile = _strip(
            np.stack([self.x, np.zeros(n), self.keel_z], 1),
            np.stack([self.x, np.zeros(n), np.full(n, self.sheer_z)], 1),
        )
        self.profile_outline = np.array(
            [
                *np.stack([self.x, np.zeros(n), self.keel_z], 1),
                [self.stem_x, 0.0, self.sheer_z],
                [self.transom_x, 0.0, self.sheer_z],
            ]
        )
        self.chine = np.stack([self.x, np.zeros(n), self.chine_z], 1)
        self.planform = _strip(
            np.stack([self.x, -self.half_beam, self.chine_z], 1),
            np.stack([self.x, self.half_beam, self.chine_z], 1),
        )
        # fins seen from the side (plates facing y on the centerline): skeg, rudder
        fins = [p for p in craft.plates if abs(p.normal[1]) > 0.9 and p.offset_m[1] == 0.0]
        self.fins = np.array(
            [_rect_xz(p.offset_m, math.sqrt(p.area_m2), math.sqrt(p.area_m2)) for p in fins]
        ).reshape(-1, 3, 3)
        # the windscreen: from the sheer up to its sample's height, raked aft
        screens = []
        for p in craft.plates:
            if p.name.startswith("windscreen"):
                (x, _, z), rise = p.offset_m, p.offset_m[2] - self.sheer_z
                screens.append([(x, 0.0, self.sheer_z), (x - SCREEN_RAKE * rise, 0.0, z)])
        self.screens = np.array(screens).reshape(-1, 2, 3)
        # the outboards: a cowl over the transom, a leg down to the propeller, the propeller
        props = np.array([t.offset_m for t in craft.thrusters]).reshape(-1, 3)
        self.legs = np.stack([props, props], 1)
        self.legs[:, 0, 2] = self.sheer_z
        self.cowls = np.array(
            [_rect_xz((x, 0.0, self.sheer_z + 0.5 * COWL_M), COWL_M, COWL_M) for x in props[:, 0]]
        ).reshape(-1, 3, 3)
        self.props = np.stack([props - [0.0, 0.0, PROP_RADIUS_M], props + [0, 0, PROP_RADIUS_M]], 1)
        # trim tabs: hinged at the transom, the base normal at the middle of their travel
        (tabs,) = [c for c in craft.controls if c.name == "trim_tabs"] or [None]
        self.tabs = []  # (hinge [3], chord m, base deflection rad)
        self.tab_range_rad = math.radians(tabs.max_deflection_deg) if tabs else 0.0
        for s in tabs.surfaces if tabs else ():
            p = plates[s.sample]
            base = math.atan2(p.normal[0], -p.normal[2])  # trailing edge down +
            chord = 2.0 * (self.transom_x - p.offset_m[0])
            if not chord > 0.0:
                chord = math.sqrt(p.area_m2)
            aft = np.array([-math.cos(base), 0.0, -math.sin(base)])
            hinge = np.asarray(p.offset_m, dtype=np.float64) - 0.5 * chord * aft
            self.tabs.append((hinge, chord, base))

    def tab_segments(self, action: float) -> np.ndarray:
        """Body-frame segments [n, 2, 3] of the tabs at channel value ``action`` in [-1, 1]."""
        out = []
        for hinge, chord, base in self.tabs:
            d = base + self.tab_range_rad * action
            out.append((hinge, hinge + chord * np.array([-math.cos(d), 0.0, -math.sin(d)])))
        return np.array(out).reshape(-1, 2, 3)


def _strip(lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Triangles [2 (n - 1), 3, 3] filling between two polylines [n, 3] (an x-monotone shape,
    convex or not)."""
    a, b, c, d = lower[:-1], lower[1:], upper[1:], upper[:-1]
    return np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def _rect_xz(center, length: float, height: float) -> np.ndarray:
    """Two triangles [2, 3, 3]: a rectangle in the x-z plane around ``center``."""
    c = np.asarray(center, dtype=np.float64)
    a, b, d, e = (
        c + [0.5 * sx * length, 0.0, 0.5 * sz * height]
        for sx, sz in ((-1, -1), (1, -1), (1, 1), (-1, 1))
    )
    return np.array([(a, b, d), (a, d, e)])


# ---- the wake ------------------------------------------------------------------------------


class Track:
    """The last ``TRACK_LEN`` horizontal positions of one rendered sub-env (a ring buffer)."""

    def __init__(self, elapsed: int, episode: int = 0) -> None:
        self.elapsed = elapsed
        self.episode = episode
        self.n = 0
        self._xy = np.empty((TRACK_LEN, 2))

    def push(self, xy) -> None:
        self._xy[self.n % TRACK_LEN] = xy
        self.n += 1

    def last(self) -> np.ndarray:
        return self._xy[(self.n - 1) % TRACK_LEN]

    def points(self) -> np.ndarray:
        """The kept positions [min(n, TRACK_LEN), 2], oldest first."""
        if self.n <= TRACK_LEN:
            return self._xy[: self.n].copy()
        i = self.n % TRACK_LEN
        return np.concatenate([self._xy[i:], self._xy[:i]])


# ---- the frame -----------------------------------------------------------------------------


class BoatOnStepView:
    """Frames of a BoatOnStep-v0 vector env. Keeps the hull's outlines and, for each rendered
    sub-env, its wake (``tracks``: sub-env -> :class:`Track`)."""

    def __init__(self, env) -> None:
        self.env = env
        self.shape = HullShape(env.craft)
        self.tracks: dict[int, Track] = {}

    def update_track(self, e: int) -> Track:
        """Sub-env e's track with its current position added (once per step); a new track
        when its episode has restarted."""
        env = self.env
        elapsed, episode = int(env.episode_steps[e]), int(env.episodes[e])
        tr = self.tracks.get(e)
        if tr is not None and tr.episode == episode and tr.elapsed == elapsed:
            return tr  # the same step again
        if tr is None or tr.episode != episode:
            tr = self.tracks[e] = Track(elapsed, episode)
        tr.elapsed = elapsed
        tr.push(np.asarray(env.sim.pos[e, 0, :2], dtype=np.float64))
        return tr

    def frame(self, e: int) -> np.ndarray:
        """The [PLAN_H + SIDE_H, WIDTH, 3] uint8 image of sub-env e: the plan over the
        elevation."""
        env = self.env
        track = self.update_track(e)
        pos = np.asarray(env.sim.pos[e, 0], dtype=np.float64)
        rot = quat_matrices(np.ascontiguousarray(env.sim.quat[e], dtype=np.float64))[0]
        out = np.concatenate(
            [_plan(env, e, self.shape, pos, rot, track), _elevation(env, e, self.shape, pos, rot)],
            axis=0,
        )
        out[PLAN_H - 1 : PLAN_H + 1] = 230  # the divider
        return out


def _place(points: np.ndarray, pos: np.ndarray, rot: np.ndarray) -> np.ndarray:
    return points @ rot.T + pos


def _plan(env, e: int, shape: HullShape, pos, rot, track: Track) -> np.ndarray:
    canvas = Canvas(WIDTH, PLAN_H, background=WATER)
    center = np.array([pos[0], pos[1], 0.0])
    if not np.isfinite(center).all():
        center = np.zeros(3)
    cam = OrthoCamera(center, PLAN_ROT, PLAN_SCALE, WIDTH, PLAN_H)
    canvas.ground_grid(cam, center[:2], 0.5 * WIDTH / PLAN_SCALE + GRID_M, GRID_M, GRID)

    gates = env.course.shape[1] - 1
    k = int(env.next_gate[e])  # the next gate, 1-based into the course
    course = np.zeros((gates + 1, 3))
    course[:, :2] = env.course[e, :, :2]
    behind = np.arange(1, gates + 1) < k  # legs and gates already run through
    canvas.lines(cam, course[:-1], course[1:], np.where(behind[:, None], DIM, COURSE))

    buoys = np.zeros((2 * gates, 3))
    buoys[:, :2] = env.buoy_xy(e)
    colors = np.tile([PORT, STARBOARD], (gates, 1))
    colors[np.repeat(behind, 2)] = DIM
    radius = max(round(env.params.buoy_radius_m * PLAN_SCALE), 2)
    canvas.points(cam, buoys, colors, radius=radius)
    if 1 <= k <= gates:
        pair = buoys[2 * (k - 1) : 2 * k]
        canvas.lines(cam, pair[:1], pair[1:], NEXT_GATE)
        canvas.points(cam, pair, [PORT, STARBOARD], radius=radius + 2)

    pts = track.points()
    if len(pts) > 1:
        wake = np.zeros((len(pts), 3))
        wake[:, :2] = pts
        age = np.linspace(1.0, 0.0, len(pts) - 1)[:, None]  # oldest segment first
        colors = (1 - age) * np.array(WAKE) + age * np.array(WATER)
        canvas.lines(cam, wake[:-1], wake[1:], colors, thickness=2)

    canvas.triangles(cam, _place(shape.planform, pos, rot), HULL, depth_test=False)
    readout(canvas, _lines(env, e, k, gates), color=READOUT)
    return canvas.image()


def _lines(env, e: int, gate: int, gates: int) -> list[str]:
    p = env.params
    t = float(env.episode_steps[e]) * p.dt * p.substeps
    speed = math.hypot(*np.asarray(env.sim.lin_vel[e, 0, :2], dtype=np.float64))
    act = dict(zip(env.action_names, env.last_action[e].tolist(), strict=True))
    where = f"gate {gate}/{gates}" if gate <= gates else "course run"
    return [
        f"t {t:4.1f} s  {where}  return {number(float(env.episode_return[e]), 2)}",
        f"speed {number(speed)} m/s  target {float(env.target_speed[e]):.1f} m/s",
        f"throttle {signed(act['throttle'])} rudder {signed(act['rudder'])}"
        f" tabs {signed(act['trim_tabs'])}",
    ]


def _elevation(env, e: int, shape: HullShape, pos, rot) -> np.ndarray:
    canvas = Canvas(WIDTH, SIDE_H, background=SKY)
    fwd = np.array([rot[0, 0], rot[1, 0], 0.0])
    norm = math.hypot(fwd[0], fwd[1])
    fwd = fwd / norm if norm > 1e-6 else np.array([1.0, 0.0, 0.0])
    left = np.array([-fwd[1], fwd[0], 0.0])
    z = float(pos[2])
    zc = SIDE_CENTER_Z + min(0.0, z + 0.9) + max(0.0, z - 0.9)  # follow only when far off
    center = np.array([pos[0], pos[1], zc])
    if not np.isfinite(center).all():
        center = np.array([0.0, 0.0, SIDE_CENTER_Z])
    cam = OrthoCamera(center, np.stack([fwd, [0.0, 0.0, -1.0], left]), SIDE_SCALE, WIDTH, SIDE_H)

    # the water: calm, or the swell at this sub-env's clock
    half = 0.5 * WIDTH / SIDE_SCALE + 0.5
    calm = not env.world.swell
    s = np.linspace(-half, half, 2 if calm else 49)
    line = center + s[:, None] * fwd
    if calm:
        line[:, 2] = 0.0
        row = cam.project(line[:1])[0][0, 1]
        canvas.fill_rows(row, SIDE_H, WATER)
    else:
        line[:, 2] = env.world.surface_height(line[:, 0], line[:, 1], env.sim.clock[e])
        deep = line.copy()
        deep[:, 2] = zc - SIDE_H / SIDE_SCALE
        canvas.triangles(cam, _strip(deep, line), WATER, depth_test=False)

    # the boat
    act = env.last_action[e]
    canvas.lines(cam, *_place(shape.legs, pos, rot).transpose(1, 0, 2), GEAR, thickness=4)
    canvas.lines(cam, *_place(shape.props, pos, rot).transpose(1, 0, 2), GEAR, thickness=3)
    if len(shape.cowls):
        canvas.triangles(cam, _place(shape.cowls, pos, rot), GEAR, depth_test=False)
    if len(shape.fins):
        canvas.triangles(cam, _place(shape.fins, pos, rot), GEAR, depth_test=False)
    canvas.triangles(cam, _place(shape.profile, pos, rot), HULL, depth_test=False)
    outline = _place(shape.profile_outline, pos, rot)
    canvas.lines(cam, outline, np.roll(outline, -1, axis=0), EDGE)
    chine = _place(shape.chine, pos, rot)
    canvas.lines(cam, chine[:-1], chine[1:], EDGE)
    if len(shape.screens):
        canvas.lines(cam, *_place(shape.screens, pos, rot).transpose(1, 0, 2), GLASS, 3)
    tabs = shape.tab_segments(float(act[2]))
    if len(tabs):
        canvas.lines(cam, *_place(tabs, pos, rot).transpose(1, 0, 2), TAB, thickness=3)
    canvas.lines(cam, line[:-1], line[1:], SURFACE)  # the waterline across the hull

    img = canvas.image()
    vel = np.asarray(env.sim.lin_vel[e, 0], dtype=np.float64)
    speed = math.hypot(vel[0], vel[1])
    target = float(env.target_speed[e])
    vmax = 1.5 * max(env.params.target_speed_mps)
    _speed_bar(img, speed, target, vmax, env.params.speed_scale_mps)
    return img


def _speed_bar(img: np.ndarray, speed: float, target: float, vmax: float, tol: float) -> None:
    """A horizontal bar along the bottom of ``img``: speed from 0 to ``vmax``, a tick at the
    target, small ticks every 5 m/s."""
    h = img.shape[0]
    x0, x1, y0, y1 = 12, img.shape[1] - 12, h - 14, h - 6

    def col(v: float) -> int:
        return x0 + round((x1 - x0) * min(max(v / vmax, 0.0), 1.0)) if math.isfinite(v) else x0

    img[y0:y1, x0:x1] = BAR_BG
    ok = math.isfinite(speed) and abs(speed - target) <= tol
    img[y0:y1, x0 : col(speed)] = BAR_OK if ok else BAR_OFF
    for v in np.arange(5.0, vmax, 5.0):
        img[y1 : y1 + 2, col(v)] = BAR_BG
    t = col(target)
    img[y0 - 3 : y1 + 3, t - 1 : t + 1] = TICK
