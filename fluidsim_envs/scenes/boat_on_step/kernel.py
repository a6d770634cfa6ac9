"""BoatOnStep's layouts (observation, reward terms, flags, task state, course, task config)
and its per-step task logic in compiled calls: the engine's power curve, the observation, the
gates and buoys, porpoising and capsize detection and the reward terms, for all envs at once.

Each layout is declared once, as a tuple of names, and the constants the kernels use are looked
up by name from it. The layouts live in this module because numba's cache is keyed on this
file alone (a layout edited elsewhere would leave stale compiled indices behind)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ...physics.forces import thrust_control
from ...physics.kernels import body_state
from ...physics.rotation import env_inv_inertia, quat_to_matrix, to_body
from ...physics.state import B_COM_SHIFT, OQ, OV, OX
from ...physics.surface import surface_height
from ..layout import index

OBSERVATION = (
    # (name, unit, description): the columns of the observation, in order
    ("u", "m/s", "velocity along body x (forward)"),
    ("v", "m/s", "velocity along body y (left)"),
    ("w", "m/s", "velocity along body z (up)"),
    ("p", "rad/s", "roll rate (+ starboard side down)"),
    ("q", "rad/s", "pitch rate (+ bow down)"),
    ("r", "rad/s", "yaw rate (+ bow left)"),
    ("trim", "rad", "trim angle, bow up +"),
    ("heel", "rad", "heel angle, starboard side down +"),
    ("heave", "m", "center of gravity above the water surface under it, less that at rest"),
    ("speed_error", "m/s", "target speed minus speed over the ground"),
    ("gate_bearing_sin", "1", "sine of the bearing of the next gate's center from the bow"),
    ("gate_bearing_cos", "1", "cosine of that bearing"),
    ("gate_x", "m", "next gate's center relative to the boat, along its heading"),
    ("gate_y", "m", "next gate's center relative to the boat, to its left"),
    ("gate_heading_sin", "1", "sine of the gate's direction of travel minus the heading"),
    ("gate_heading_cos", "1", "cosine of that angle"),
    ("target_speed", "m/s", "the episode's target speed"),
    ("pitch_oscillation", "rad", "peak-to-peak trim oscillation (running estimate)"),
)
OBS_NAMES = tuple(name for name, _, _ in OBSERVATION)
OBS = index(OBS_NAMES)  # name -> column
O_U, O_V, O_W = OBS["u"], OBS["v"], OBS["w"]
O_P, O_Q, O_R = OBS["p"], OBS["q"], OBS["r"]
O_TRIM, O_HEEL, O_HEAVE = OBS["trim"], OBS["heel"], OBS["heave"]
O_SPEED_ERROR = OBS["speed_error"]
O_GATE_BEARING_SIN, O_GATE_BEARING_COS = OBS["gate_bearing_sin"], OBS["gate_bearing_cos"]
O_GATE_X, O_GATE_Y = OBS["gate_x"], OBS["gate_y"]
O_GATE_HEADING_SIN, O_GATE_HEADING_COS = OBS["gate_heading_sin"], OBS["gate_heading_cos"]
O_TARGET_SPEED = OBS["target_speed"]
O_PITCH_OSCILLATION = OBS["pitch_oscillation"]

# v0's terms; v1 adds the ride (seakeeping) term after them, so v0's rows are a prefix
REWARD_TERMS_V0 = ("speed", "progress", "gate", "buoy", "porpoise", "fuel", "crash")
REWARD_TERMS = REWARD_TERMS_V0 + ("ride",)
TERMS = index(REWARD_TERMS)
T_SPEED, T_PROGRESS, T_GATE = TERMS["speed"], TERMS["progress"], TERMS["gate"]
T_BUOY, T_PORPOISE = TERMS["buoy"], TERMS["porpoise"]
T_FUEL, T_CRASH, T_RIDE = TERMS["fuel"], TERMS["crash"], TERMS["ride"]
NTERMS = len(REWARD_TERMS)
FLAG_NAMES = (
    "capsized",
    "bow_stuffed",
    "left_course",
    "porpoising",
    "hit_buoy",
    "gate_passed",
    "gate_missed",
    "finished",
)
FLAGS = index(FLAG_NAMES)
F_CAPSIZE, F_STUFF, F_LEFT = FLAGS["capsized"], FLAGS["bow_stuffed"], FLAGS["left_course"]
F_PORPOISE, F_BUOY = FLAGS["porpoising"], FLAGS["hit_buoy"]
F_PASSED, F_MISSED, F_FINISHED = FLAGS["gate_passed"], FLAGS["gate_missed"], FLAGS["finished"]
NFLAGS = len(FLAG_NAMES)
# per-env task state rows task[K_*, E]
TASK_ROWS = (
    "gate",  # the next gate's index into the course (1-based: 0 is the start point)
    "target_speed",
    "trim_mean",
    "dev_mean",
    "pitch_var",
    "side",  # along-track position relative to the next gate's line (+ past it)
    "dist",  # distance to the next gate's center
    "passed",
    "missed",
    "porpoising",  # steps porpoising this episode
    "planed",  # the time the boat first planed, -1 until it does
    "time",
    "bow_vz",  # the stem's vertical velocity at the last step (m/s, world)
    "ride_var",  # running mean square of the stem's vertical acceleration (m^2/s^4)
)
TASK = index(TASK_ROWS)
K_GATE, K_TARGET, K_TRIM_MEAN = TASK["gate"], TASK["target_speed"], TASK["trim_mean"]
K_DEV_MEAN, K_PITCH_VAR, K_SIDE, K_DIST = (
    TASK["dev_mean"],
    TASK["pitch_var"],
    TASK["side"],
    TASK["dist"],
)
K_PASSED, K_MISSED, K_PORPOISING = TASK["passed"], TASK["missed"], TASK["porpoising"]
K_PLANED, K_TIME = TASK["planed"], TASK["time"]
K_BOW_VZ, K_RIDE_VAR = TASK["bow_vz"], TASK["ride_var"]
NTASK = len(TASK_ROWS)
# porpoising is a pitch-heave oscillation of 0.5-2 s period: the trim is high-passed twice with
# this time constant (a corner near 0.8 Hz) so that the slow trim changes of getting on plane
# or of a turn (ramps included) do not read as oscillation
HIGHPASS_S = 0.2
# course[E, G + 1, 3]: the start point, then each gate's center (x, y) and the heading of the
# leg that arrives at it, which is the direction of travel through the gate
COURSE_COLUMNS = ("x", "y", "heading")
COURSE = index(COURSE_COLUMNS)
G_X, G_Y, G_HEADING = COURSE["x"], COURSE["y"], COURSE["heading"]
# the task parameter vector: these fields (of BoatOnStepParams, or derived), in this order
CFG_FIELDS = (
    "w_speed",
    "w_progress",
    "w_gate",
    "w_buoy",
    "w_porpoise",
    "w_fuel",
    "w_crash",
    "speed_scale_mps",
    "gate_half_width_m",
    "buoy_radius_m",
    "course_half_width_m",
    "capsize_heel_deg",
    "porpoise_deg",
    "porpoise_min_speed_mps",
    "porpoise_window_s",
    "engine_power_w",
    "max_thrust_n",
    "min_thrust_n",
    "step_s",
    "rest_height_m",
    "bow_x_m",
    "bow_z_m",
    "hull_half_beam_m",
    "w_ride",
    "ride_limit_mps2",
    "ride_window_s",
)
CFG = index(CFG_FIELDS)  # field -> slot
C_W_SPEED, C_W_PROGRESS, C_W_GATE = CFG["w_speed"], CFG["w_progress"], CFG["w_gate"]
C_W_BUOY, C_W_PORPOISE, C_W_FUEL = CFG["w_buoy"], CFG["w_porpoise"], CFG["w_fuel"]
C_W_CRASH = CFG["w_crash"]
C_SPEED_SCALE = CFG["speed_scale_mps"]
C_GATE_HALF, C_BUOY_R = CFG["gate_half_width_m"], CFG["buoy_radius_m"]
C_COURSE_HALF, C_CAPSIZE = CFG["course_half_width_m"], CFG["capsize_heel_deg"]
C_PORPOISE, C_PORPOISE_SPEED = CFG["porpoise_deg"], CFG["porpoise_min_speed_mps"]
C_PORPOISE_WINDOW = CFG["porpoise_window_s"]
C_POWER = CFG["engine_power_w"]
C_MAX_THRUST, C_MIN_THRUST = CFG["max_thrust_n"], CFG["min_thrust_n"]
C_STEP, C_REST = CFG["step_s"], CFG["rest_height_m"]
C_BOW_X, C_BOW_Z, C_HALF_BEAM = CFG["bow_x_m"], CFG["bow_z_m"], CFG["hull_half_beam_m"]
C_W_RIDE, C_RIDE_WINDOW = CFG["w_ride"], CFG["ride_window_s"]
C_RIDE_LIMIT = CFG["ride_limit_mps2"]

_JIT = dict(cache=True, error_model="numpy")
TASK_BLOCK = 64  # sub-envs per call of a parallel task kernel (paper_airplane/kernel.py)


@njit(**_JIT)
def thrust_command(u, throttle, cfg):
    """Propeller thrust (N) for a throttle in [-1, 1] at forward speed u (m/s): 0 at idle,
    linear to full ahead (``max_thrust_n``) or full astern (``min_thrust_n``), and ahead never
    more than the engine's power allows, ``engine_power_w / u``: a fixed-pitch propeller's
    thrust falls with speed, which sets the boat's top speed."""
    if throttle >= 0.0:
        return throttle * min(cfg[C_MAX_THRUST], cfg[C_POWER] / max(u, 1.0))
    return -throttle * cfg[C_MIN_THRUST]


@njit(**_JIT)
def controls(st, actions, cfg, ctrl):
    """The craft's channel values ctrl[E, 3] (throttle, rudder, trim tabs, each in [-1, 1] of
    the craft's ranges) for the agent's actions [E, 3]."""
    lo, hi = cfg[C_MIN_THRUST], cfg[C_MAX_THRUST]
    for e in range(st.shape[2]):
        rot = quat_to_matrix(st[OQ, 0, e], st[OQ + 1, 0, e], st[OQ + 2, 0, e], st[OQ + 3, 0, e])
        u = rot[0] * st[OV, 0, e] + rot[3] * st[OV + 1, 0, e] + rot[6] * st[OV + 2, 0, e]
        thrust = thrust_command(u, actions[e, 0], cfg)
        ctrl[e, 0] = thrust_control(thrust, lo, hi)
        ctrl[e, 1] = actions[e, 1]
        ctrl[e, 2] = actions[e, 2]


@njit(**_JIT)
def attitude(rot):
    """Trim (bow up +) and heel (starboard side down +) in radians from the rotation matrix."""
    trim = math.asin(min(1.0, max(-1.0, rot[6])))
    heel = math.atan2(rot[7], rot[8])
    return trim, heel


@njit(**_JIT)
def _gate_frame(course, e, g, px, py):
    """Position relative to gate g of env e: along its heading (+ past it) and across (+ left)."""
    c, s = math.cos(course[e, g, G_HEADING]), math.sin(course[e, g, G_HEADING])
    dx, dy = px - course[e, g, G_X], py - course[e, g, G_Y]
    return c * dx + s * dy, -s * dx + c * dy


@njit(**_JIT)
def observe(ids, skip, st, body, course, task, swell, clock, cfg, out):
    """Observation rows out[ids, len(OBSERVATION)] (float32) from the boat's state
    st[13, 1, E], except where ``skip`` [E] is set (a diverged state keeps its last finite
    observation); heave is measured from the water surface under the boat (the swell at the
    env's clock)."""
    last = course.shape[1] - 1
    for e in ids:
        if skip[e]:
            continue
        (px, py, pz), (vx, vy, vz), rot, omega = body_state(st, 0, e, env_inv_inertia(body, e, 0))
        r0, r3 = rot[0], rot[3]
        out[e, O_U], out[e, O_V], out[e, O_W] = to_body(rot, vx, vy, vz)
        out[e, O_P], out[e, O_Q], out[e, O_R] = to_body(rot, omega[0], omega[1], omega[2])
        trim, heel = attitude(rot)
        out[e, O_TRIM] = trim
        out[e, O_HEEL] = heel
        out[e, O_HEAVE] = pz - surface_height(px, py, clock[e], swell) - cfg[C_REST]
        speed = math.sqrt(vx * vx + vy * vy)
        out[e, O_SPEED_ERROR] = task[K_TARGET, e] - speed
        heading = math.atan2(r3, r0)
        g = min(int(task[K_GATE, e]), last)
        dx, dy = course[e, g, G_X] - px, course[e, g, G_Y] - py
        err = math.atan2(dy, dx) - heading
        out[e, O_GATE_BEARING_SIN] = math.sin(err)
        out[e, O_GATE_BEARING_COS] = math.cos(err)
        c, s = math.cos(heading), math.sin(heading)
        out[e, O_GATE_X] = c * dx + s * dy
        out[e, O_GATE_Y] = -s * dx + c * dy
        gate_err = course[e, g, G_HEADING] - heading
        out[e, O_GATE_HEADING_SIN] = math.sin(gate_err)
        out[e, O_GATE_HEADING_COS] = math.cos(gate_err)
        out[e, O_TARGET_SPEED] = task[K_TARGET, e]
        out[e, O_PITCH_OSCILLATION] = 2.0 * math.sqrt(2.0 * task[K_PITCH_VAR, e])  # p-p


@njit(**_JIT)
def stem_offset(rot, body, e, cfg):
    """The stem's offset (m, world) from sub-env e's centre of mass: the craft's stem
    (``bow_x_m``, 0, ``bow_z_m`` from the craft's centre of mass) less the episode's
    centre-of-mass shift (v1's randomized physics; 0 in v0), rotated."""
    c = body[e, 0, B_COM_SHIFT], body[e, 0, B_COM_SHIFT + 1], body[e, 0, B_COM_SHIFT + 2]
    x, y, z = cfg[C_BOW_X] - c[0], -c[1], cfg[C_BOW_Z] - c[2]
    return (
        rot[0] * x + rot[1] * y + rot[2] * z,
        rot[3] * x + rot[4] * y + rot[5] * z,
        rot[6] * x + rot[7] * y + rot[8] * z,
    )


@njit(**_JIT)
def bow_vertical_velocity(st, body, e, cfg):
    """The stem's vertical velocity (m/s, world z) in sub-env e: the centre of mass's plus
    the rotation's, omega x r at the stem (:func:`stem_offset`)."""
    _, (_, _, vz), rot, w = body_state(st, 0, e, env_inv_inertia(body, e, 0))
    rx, ry, _ = stem_offset(rot, body, e, cfg)
    return vz + w[0] * ry - w[1] * rx


@njit(**_JIT)
def start(st, body, course, task, cfg, ids):
    """Task state of the envs ``ids`` at the start of an episode (target speed already set)."""
    for e in ids:
        task[K_BOW_VZ, e] = bow_vertical_velocity(st, body, e, cfg)
        task[K_RIDE_VAR, e] = 0.0
        task[K_GATE, e] = 1.0
        task[K_PASSED, e] = 0.0
        task[K_MISSED, e] = 0.0
        task[K_PORPOISING, e] = 0.0
        task[K_PLANED, e] = -1.0  # the time the boat first planed, -1 until it does
        task[K_TIME, e] = 0.0
        rot = quat_to_matrix(st[OQ, 0, e], st[OQ + 1, 0, e], st[OQ + 2, 0, e], st[OQ + 3, 0, e])
        task[K_TRIM_MEAN, e] = attitude(rot)[0]
        task[K_DEV_MEAN, e] = 0.0
        task[K_PITCH_VAR, e] = 0.0
        along, _ = _gate_frame(course, e, 1, st[OX, 0, e], st[OX + 1, 0, e])
        task[K_SIDE, e] = along
        task[K_DIST, e] = math.hypot(
            course[e, 1, G_X] - st[OX, 0, e], course[e, 1, G_Y] - st[OX + 1, 0, e]
        )


@njit(**_JIT)
def score(
    lo, hi, st, body, diverged, actions, course, buoys, hits, task, swell, clock, cfg, terms, flags
):
    """Gates, buoys, porpoising, capsize, bow stuffing and leaving the course, and the reward
    terms, of sub-envs ``lo`` to ``hi - 1`` after a step; writes ``terms`` [NTERMS, E] and
    ``flags`` [NFLAGS, E]. A buoy is touched where ``hits`` [E] says so (buoy bodies: the
    contact's impulse) or where the hull passes within reach of a marker in ``buoys``
    [E, n, 2] (n = 0 with buoy bodies).

    Porpoising is measured on the trim, high-passed twice (``HIGHPASS_S``): the running mean
    square of what passes, over ``porpoise_window_s``, is A^2 / 8 for a sustained sinusoid
    of peak-to-peak amplitude A (times the filter's gain, 0.82 at 1.6 Hz), so the estimate
    2 sqrt(2 var) reads A.

    The ride (v1) is judged at the stem, as a seakeeping criterion judges a craft in a seaway:
    its vertical acceleration, averaged over each step (the change of its vertical velocity,
    :func:`bow_vertical_velocity`), squared and averaged over ``ride_window_s``; above the
    limit ``ride_limit_mps2`` its root costs ``w_ride`` per step per multiple of the limit.
    It charges the sea's motion too, but unlike the trim's oscillation (measured only at
    planing speed) it grows with speed at every speed: a trade the helm makes.
    """
    last = course.shape[1] - 1  # the last gate's index (0 is the start point)
    k = 1.0 - math.exp(-cfg[C_STEP] / cfg[C_PORPOISE_WINDOW])
    hp = 1.0 - math.exp(-cfg[C_STEP] / HIGHPASS_S)
    k_ride = 1.0 - math.exp(-cfg[C_STEP] / cfg[C_RIDE_WINDOW])
    capsize = math.radians(cfg[C_CAPSIZE])
    for e in range(lo, hi):
        for j in range(NTERMS):
            terms[j, e] = 0.0
        for j in range(NFLAGS):
            flags[j, e] = False
        if diverged[e]:
            terms[T_CRASH, e] = -cfg[C_W_CRASH]
            continue
        px, py, pz = st[OX, 0, e], st[OX + 1, 0, e], st[OX + 2, 0, e]
        vx, vy = st[OV, 0, e], st[OV + 1, 0, e]
        rot = quat_to_matrix(st[OQ, 0, e], st[OQ + 1, 0, e], st[OQ + 2, 0, e], st[OQ + 3, 0, e])
        trim, heel = attitude(rot)
        speed = math.sqrt(vx * vx + vy * vy)

        # porpoising: the trim's oscillation about its running mean
        dev = trim - task[K_TRIM_MEAN, e]
        task[K_TRIM_MEAN, e] += hp * dev
        dev2 = dev - task[K_DEV_MEAN, e]
        task[K_DEV_MEAN, e] += hp * dev2
        if speed > cfg[C_PORPOISE_SPEED]:  # a planing instability: measured when planing
            task[K_PITCH_VAR, e] += k * (dev2 * dev2 - task[K_PITCH_VAR, e])
        else:
            task[K_PITCH_VAR, e] = 0.0
        amp = math.degrees(2.0 * math.sqrt(2.0 * task[K_PITCH_VAR, e]))
        task[K_TIME, e] += cfg[C_STEP]
        if task[K_PLANED, e] < 0.0 and speed > cfg[C_PORPOISE_SPEED]:
            task[K_PLANED, e] = task[K_TIME, e]
        if amp > cfg[C_PORPOISE]:
            flags[F_PORPOISE, e] = True
            task[K_PORPOISING, e] += 1.0
            terms[T_PORPOISE, e] = -cfg[C_W_PORPOISE] * (amp / cfg[C_PORPOISE] - 1.0)

        # the ride: the stem's vertical acceleration against the limit
        bow_vz = bow_vertical_velocity(st, body, e, cfg)
        acc = (bow_vz - task[K_BOW_VZ, e]) / cfg[C_STEP]
        task[K_BOW_VZ, e] = bow_vz
        task[K_RIDE_VAR, e] += k_ride * (acc * acc - task[K_RIDE_VAR, e])
        rough = math.sqrt(task[K_RIDE_VAR, e]) / cfg[C_RIDE_LIMIT]
        if rough > 1.0:
            terms[T_RIDE, e] = -cfg[C_W_RIDE] * (rough - 1.0)

        # speed and fuel
        err = task[K_TARGET, e] - speed
        terms[T_SPEED, e] = cfg[C_W_SPEED] * math.exp(-abs(err) / cfg[C_SPEED_SCALE])
        terms[T_FUEL, e] = -cfg[C_W_FUEL] * max(0.0, actions[e, 0])

        # gates: crossing the current gate's line, inside or outside its buoys; a gate is run
        # bow first (PPO on v1 learned to back the course stern first: the ride, measured at
        # the bow, and the fuel, charged for throttle ahead, then cost nothing)
        g = int(task[K_GATE, e])
        if g <= last:
            along, across = _gate_frame(course, e, g, px, py)
            dist = math.hypot(course[e, g, G_X] - px, course[e, g, G_Y] - py)
            terms[T_PROGRESS, e] = cfg[C_W_PROGRESS] * (task[K_DIST, e] - dist)
            if task[K_SIDE, e] < 0.0 <= along:
                gh = course[e, g, G_HEADING]
                bow_first = rot[0] * math.cos(gh) + rot[3] * math.sin(gh) > 0.0
                if abs(across) <= cfg[C_GATE_HALF] and bow_first:
                    flags[F_PASSED, e] = True
                    task[K_PASSED, e] += 1.0
                    terms[T_GATE, e] = cfg[C_W_GATE]
                else:
                    flags[F_MISSED, e] = True
                    task[K_MISSED, e] += 1.0
                    terms[T_GATE, e] = -cfg[C_W_GATE]
                g += 1
                task[K_GATE, e] = g
                if g > last:
                    flags[F_FINISHED, e] = True
                else:
                    along, _ = _gate_frame(course, e, g, px, py)
                    dist = math.hypot(course[e, g, G_X] - px, course[e, g, G_Y] - py)
            task[K_SIDE, e] = along
            task[K_DIST, e] = dist

        # buoys: the hull (a circle of its half beam) against each marker, no contact physics
        flags[F_BUOY, e] = hits[e]
        reach = cfg[C_BUOY_R] + cfg[C_HALF_BEAM]
        for b in range(buoys.shape[1]):
            bx, by = buoys[e, b, 0], buoys[e, b, 1]
            for f in (-0.5, 0.0, 1.0):  # stern, center, bow along the keel
                qx = px + rot[0] * f * cfg[C_BOW_X]
                qy = py + rot[3] * f * cfg[C_BOW_X]
                if (qx - bx) ** 2 + (qy - by) ** 2 < reach * reach:
                    flags[F_BUOY, e] = True
        if flags[F_BUOY, e]:
            terms[T_BUOY, e] = -cfg[C_W_BUOY]

        # capsize, bow stuffing (the stem under the surface while making way), off the course
        flags[F_CAPSIZE, e] = abs(heel) > capsize or rot[8] < 0.0
        bx = px + rot[0] * cfg[C_BOW_X] + rot[2] * cfg[C_BOW_Z]
        by = py + rot[3] * cfg[C_BOW_X] + rot[5] * cfg[C_BOW_Z]
        bz = pz + rot[6] * cfg[C_BOW_X] + rot[8] * cfg[C_BOW_Z]
        # less the episode's centre-of-mass shift (v1), subtracted apart: exact zeros in v0
        cx, cy, cz = (
            body[e, 0, B_COM_SHIFT],
            body[e, 0, B_COM_SHIFT + 1],
            body[e, 0, B_COM_SHIFT + 2],
        )
        bx -= rot[0] * cx + rot[1] * cy + rot[2] * cz
        by -= rot[3] * cx + rot[4] * cy + rot[5] * cz
        bz -= rot[6] * cx + rot[7] * cy + rot[8] * cz
        flags[F_STUFF, e] = bz < surface_height(bx, by, clock[e], swell) and speed > 3.0
        # off the course: farther than course_half_width_m from the leg to the current gate
        g = min(g, last)
        ax, ay = course[e, g - 1, G_X], course[e, g - 1, G_Y]
        lx, ly = course[e, g, G_X] - ax, course[e, g, G_Y] - ay
        t = min(1.0, max(0.0, ((px - ax) * lx + (py - ay) * ly) / (lx * lx + ly * ly)))
        off = math.hypot(px - ax - t * lx, py - ay - t * ly)
        flags[F_LEFT, e] = off > cfg[C_COURSE_HALF]
        if flags[F_CAPSIZE, e] or flags[F_STUFF, e] or flags[F_LEFT, e]:
            terms[T_CRASH, e] = -cfg[C_W_CRASH]


# fmt: off
@njit(**_JIT)
def task_range(
    lo, hi, st, body, diverged, actions, course, buoys, hits, task, swell, clock, cfg, terms,
    flags, out
):
    """Score and observe sub-envs ``lo`` to ``hi - 1`` after a physics step."""
    score(
        lo, hi, st, body, diverged, actions, course, buoys, hits, task, swell, clock, cfg, terms,
        flags
    )
    observe(np.arange(lo, hi), diverged, st, body, course, task, swell, clock, cfg, out)


@njit(**_JIT)
def task_serial(
    st, body, diverged, actions, course, buoys, hits, task, swell, clock, cfg, terms, flags, out
):
    """Every sub-env's score and observation after a physics step."""
    task_range(
        0, st.shape[2], st, body, diverged, actions, course, buoys, hits, task, swell, clock,
        cfg, terms, flags, out
    )


@njit(parallel=True, **_JIT)
def task_parallel(
    st, body, diverged, actions, course, buoys, hits, task, swell, clock, cfg, terms, flags, out
):
    """:func:`task_serial` on every thread, ``TASK_BLOCK`` sub-envs a call: each writes only
    its own slots, the same as serial, bit for bit (tests/scenes/test_contract.py)."""
    for b in prange((st.shape[2] + TASK_BLOCK - 1) // TASK_BLOCK):
        lo = b * TASK_BLOCK
        task_range(
            lo, min(st.shape[2], lo + TASK_BLOCK), st, body, diverged, actions, course, buoys,
            hits, task, swell, clock, cfg, terms, flags, out
        )
# fmt: on
