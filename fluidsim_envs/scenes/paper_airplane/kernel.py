"""PaperAirplane-v0's layouts (observation, reward terms, flags, task config) and its per-step
task logic (observation, touchdown, reward terms) for all envs in one compiled call: done in
numpy it costs tens of small array operations per step, which dominate the step at small batch
sizes.

Each layout is declared once, as a tuple of names; the row and column constants the kernels use
are looked up by name from it (numba freezes module-level ints as compile-time constants). The
layouts live in this module, not beside it: numba's cache is keyed on this file alone, so a
layout edited elsewhere would leave stale compiled indices behind."""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ...physics.kernels import body_state, quat_matrices
from ...physics.rotation import env_inv_inertia, quat_to_matrix, to_body
from ...physics.state import OL, OQ, OV, OX
from ..layout import index

OBSERVATION = (
    # (name, unit, description): the columns of the observation, in order
    ("u", "m/s", "airspeed along body x (forward)"),
    ("v", "m/s", "airspeed along body y (left)"),
    ("w", "m/s", "airspeed along body z (up)"),
    ("p", "rad/s", "roll rate (+ right wing down)"),
    ("q", "rad/s", "pitch rate (+ nose down)"),
    ("r", "rad/s", "yaw rate (+ nose left)"),
    ("gx", "1", "gravity direction in the body frame, x"),
    ("gy", "1", "gravity direction in the body frame, y"),
    ("gz", "1", "gravity direction in the body frame, z"),
    ("height", "m", "height of the center of mass above the ground"),
    ("target_forward", "m", "target position ahead, in the heading frame"),
    ("target_left", "m", "target position to the left, in the heading frame"),
    ("ground_forward", "m/s", "velocity over the ground ahead, in the heading frame"),
    ("ground_left", "m/s", "velocity over the ground to the left, in the heading frame"),
    ("climb", "m/s", "vertical velocity (+ up)"),
)
OBS_NAMES = tuple(name for name, _, _ in OBSERVATION)
OBS = index(OBS_NAMES)  # name -> column
O_U, O_V, O_W = OBS["u"], OBS["v"], OBS["w"]
O_P, O_Q, O_R = OBS["p"], OBS["q"], OBS["r"]
O_GX, O_GY, O_GZ = OBS["gx"], OBS["gy"], OBS["gz"]
O_HEIGHT = OBS["height"]
O_TARGET_FORWARD, O_TARGET_LEFT = OBS["target_forward"], OBS["target_left"]
O_GROUND_FORWARD, O_GROUND_LEFT = OBS["ground_forward"], OBS["ground_left"]
O_CLIMB = OBS["climb"]

# rows of the per-step outputs
REWARD_TERMS = ("progress", "accuracy", "softness", "crash", "effort")
TERMS = index(REWARD_TERMS)
T_PROGRESS, T_ACCURACY, T_SOFTNESS = TERMS["progress"], TERMS["accuracy"], TERMS["softness"]
T_CRASH, T_EFFORT = TERMS["crash"], TERMS["effort"]
NTERMS = len(REWARD_TERMS)
FLAG_NAMES = ("touchdown", "landed", "crashed", "out_of_arena", "success")
FLAGS = index(FLAG_NAMES)
F_TOUCHDOWN, F_LANDED, F_CRASHED = FLAGS["touchdown"], FLAGS["landed"], FLAGS["crashed"]
F_OUT, F_SUCCESS = FLAGS["out_of_arena"], FLAGS["success"]
NFLAGS = len(FLAG_NAMES)
# the task parameter vector: these PaperAirplaneParams fields, in this order
CFG_FIELDS = (
    "w_progress",
    "w_accuracy",
    "w_softness",
    "w_crash",
    "w_effort",
    "accuracy_scale_m",
    "crash_sink_mps",
    "crash_speed_mps",
    "upright_min",
    "arena_radius_m",
    "ceiling_m",
    "success_radius_m",
)
CFG = index(CFG_FIELDS)  # field -> slot
C_W_PROGRESS, C_W_ACCURACY, C_W_SOFTNESS = CFG["w_progress"], CFG["w_accuracy"], CFG["w_softness"]
C_W_CRASH, C_W_EFFORT = CFG["w_crash"], CFG["w_effort"]
C_ACC_SCALE = CFG["accuracy_scale_m"]
C_CRASH_SINK, C_CRASH_SPEED = CFG["crash_sink_mps"], CFG["crash_speed_mps"]
C_UPRIGHT = CFG["upright_min"]
C_ARENA, C_CEILING = CFG["arena_radius_m"], CFG["ceiling_m"]
C_SUCCESS = CFG["success_radius_m"]

TOUCH_M = 0.002  # the airframe this close to the floor is down (contact rests it within 1 mm)
_JIT = dict(cache=True, error_model="numpy")
# sub-envs per call of a parallel task kernel. Each kernel loops over sub-envs itself: a
# function of one sub-env, even inlined, counted its array arguments' references per sub-env,
# and cost 18 times the loop
TASK_BLOCK = 64  # sub-envs per call of a parallel task kernel


@njit(**_JIT)
def observe(ids, skip, st, body, flow, target, out):
    """Observation rows out[ids, len(OBSERVATION)] (float32) from the state st[13, 1, E],
    except where ``skip`` [E] is set (a diverged state keeps its last finite observation)."""
    for e in ids:
        if skip[e]:
            continue
        (px, py, pz), (vx, vy, vz), rot, omega = body_state(st, 0, e, env_inv_inertia(body, e, 0))
        r0, r1, r2, r3, r4, r5, r6, r7, r8 = rot
        # airspeed: R^T (v - wind)
        out[e, O_U], out[e, O_V], out[e, O_W] = to_body(
            rot, vx - flow[0, e], vy - flow[1, e], vz - flow[2, e]
        )
        out[e, O_P], out[e, O_Q], out[e, O_R] = to_body(rot, omega[0], omega[1], omega[2])
        out[e, O_GX], out[e, O_GY], out[e, O_GZ] = -r6, -r7, -r8  # R^T (0, 0, -1)
        out[e, O_HEIGHT] = pz
        heading = math.atan2(r3, r0)
        c, s = math.cos(heading), math.sin(heading)
        dx, dy = target[e, 0] - px, target[e, 1] - py
        out[e, O_TARGET_FORWARD] = c * dx + s * dy
        out[e, O_TARGET_LEFT] = -s * dx + c * dy
        out[e, O_GROUND_FORWARD] = c * vx + s * vy
        out[e, O_GROUND_LEFT] = -s * vx + c * vy
        out[e, O_CLIMB] = vz


@njit(**_JIT)
def score(
    lo,
    hi,
    st,
    diverged,
    hull,
    target,
    launch,
    distance,
    actions,
    cfg,
    terms,
    flags,
    sink,
    v_prev,
    touch,
):
    """Touchdown, landing, arena and reward terms of sub-envs ``lo`` to ``hi - 1`` after a step.

    ``distance`` [E] holds the horizontal distance to the target before the step and is
    updated (kept where the state diverged); ``terms`` [NTERMS, E], ``flags`` [NFLAGS, E] (bool) and
    ``sink`` [E] are written. Touchdown is the floor pushing on the dart during the step
    (``touch`` [E], the ground's impulse: the dart may touch and bounce clear within a
    step) or the airframe (``hull``: its collision boxes' corners) within ``TOUCH_M`` of
    it. The floor has already taken the touchdown's velocity away (and may have turned
    the dart) by then, so sink, speed and attitude are judged from ``v_prev`` [E, 4], the
    velocity and the body z axis's height at the step before (updated here)."""
    for e in range(lo, hi):
        for k in range(NTERMS):
            terms[k, e] = 0.0
        for k in range(NFLAGS):
            flags[k, e] = False
        sink[e] = 0.0
        effort = 0.0
        for k in range(actions.shape[1]):
            effort += actions[e, k] * actions[e, k]
        terms[T_EFFORT, e] = -cfg[C_W_EFFORT] * effort / actions.shape[1]
        if diverged[e]:
            terms[T_CRASH, e] = -cfg[C_W_CRASH]
            continue
        px, py, pz = st[OX, 0, e], st[OX + 1, 0, e], st[OX + 2, 0, e]
        vx, vy, vz = st[OV, 0, e], st[OV + 1, 0, e], st[OV + 2, 0, e]
        rot = quat_to_matrix(st[OQ, 0, e], st[OQ + 1, 0, e], st[OQ + 2, 0, e], st[OQ + 3, 0, e])
        lowest = np.inf
        for h in range(hull.shape[0]):
            z = rot[6] * hull[h, 0] + rot[7] * hull[h, 1] + rot[8] * hull[h, 2]
            lowest = min(lowest, z)
        d = math.hypot(target[e, 0] - px, target[e, 1] - py)
        terms[T_PROGRESS, e] = cfg[C_W_PROGRESS] * (distance[e] - d)
        distance[e] = d
        ux, uy, uz, up = v_prev[e, 0], v_prev[e, 1], v_prev[e, 2], v_prev[e, 3]
        v_prev[e, 0], v_prev[e, 1], v_prev[e, 2], v_prev[e, 3] = vx, vy, vz, rot[8]
        if touch[e] > 0.0 or pz + lowest <= TOUCH_M:
            flags[F_TOUCHDOWN, e] = True
            vz = min(vz, uz)  # the sink before the floor stopped it
            sink[e] = -vz
            speed = max(
                math.sqrt(vx * vx + vy * vy + vz * vz), math.sqrt(ux * ux + uy * uy + uz * uz)
            )
            landed = up >= cfg[C_UPRIGHT] and -vz < cfg[C_CRASH_SINK]
            landed = landed and speed < cfg[C_CRASH_SPEED]
            if landed:
                flags[F_LANDED, e] = True
                flags[F_SUCCESS, e] = d <= cfg[C_SUCCESS]
                terms[T_ACCURACY, e] = cfg[C_W_ACCURACY] * math.exp(-d / cfg[C_ACC_SCALE])
                terms[T_SOFTNESS, e] = cfg[C_W_SOFTNESS] * math.exp(-vz * vz)  # (sink / 1 m/s)^2
            else:
                flags[F_CRASHED, e] = True
                terms[T_CRASH, e] = -cfg[C_W_CRASH]
        elif math.hypot(px - launch[e, 0], py - launch[e, 1]) > cfg[C_ARENA] or pz > cfg[C_CEILING]:
            flags[F_OUT, e] = True
            terms[T_CRASH, e] = -cfg[C_W_CRASH]


# fmt: off
@njit(**_JIT)
def task_range(
    lo, hi, st, body, flow, diverged, hull, target, launch, distance, actions, cfg, terms,
    flags, sink, v_prev, touch, out
):
    """Score and observe sub-envs ``lo`` to ``hi - 1`` after a physics step."""
    score(
        lo, hi, st, diverged, hull, target, launch, distance, actions, cfg, terms, flags, sink,
        v_prev, touch
    )
    observe(np.arange(lo, hi), diverged, st, body, flow, target, out)


@njit(**_JIT)
def task_serial(
    st, body, flow, diverged, hull, target, launch, distance, actions, cfg, terms, flags, sink,
    v_prev, touch, out
):
    """Every sub-env's score and observation after a physics step."""
    task_range(
        0, st.shape[2], st, body, flow, diverged, hull, target, launch, distance, actions, cfg,
        terms, flags, sink, v_prev, touch, out
    )


@njit(parallel=True, **_JIT)
def task_parallel(
    st, body, flow, diverged, hull, target, launch, distance, actions, cfg, terms, flags, sink,
    v_prev, touch, out
):
    """:func:`task_serial` on every thread, ``TASK_BLOCK`` sub-envs a call: each writes only
    its own slots, the same as serial, bit for bit (tests/scenes/test_contract.py)."""
    for b in prange((st.shape[2] + TASK_BLOCK - 1) // TASK_BLOCK):
        lo = b * TASK_BLOCK
        task_range(
            lo, min(st.shape[2], lo + TASK_BLOCK), st, body, flow, diverged, hull, target,
            launch, distance, actions, cfg, terms, flags, sink, v_prev, touch, out
        )
# fmt: on


# the episode start's uniforms (``draws_per_episode``), in the order they are drawn; each
# scales to its [low, high] row of ``spans``: the PaperAirplaneParams range of that name, or
# (0, 2 pi) for the two directions
DRAWS = (
    "launch_height_m",
    "launch_speed_mps",
    "launch_pitch_deg",
    "launch_roll_deg",
    "yaw",
    "target_bearing_deg",
    "target_distance_ratio",
    "wind_speed_mps",
    "wind_direction",
)
ANGLES = ("yaw", "wind_direction")
U = index(DRAWS)
U_HEIGHT, U_SPEED, U_PITCH, U_ROLL = (U[n] for n in DRAWS[:4])
U_YAW, U_BEARING, U_DISTANCE, U_WIND, U_WIND_DIR = (U[n] for n in DRAWS[4:])


@njit(**_JIT)
def _span(w, spans, k):
    """Draw k of one start's uniforms ``w`` scaled to its range: lo + u (hi - lo)."""
    return spans[k, 0] + w[k] * (spans[k, 1] - spans[k, 0])


@njit(**_JIT)
def start(ids, u, spans, st, flow, diverged, warm, v_prev, target, launch, distance):
    """Throw the darts of sub-envs ``ids`` from their uniforms ``u`` [len(ids), len(DRAWS)]:
    the launch (height, speed along the nose, pitch, roll, heading), the target and the
    wind, written into the state ``st``, the air velocity ``flow[0:3]`` and the task's
    arrays (what ``Simulator.reset`` and ``set_wind`` would write: a normalized quaternion,
    no rotation, the diverged flag cleared, the floor contact's warm start forgotten)."""
    q = np.empty((1, 4))
    for i in range(ids.size):
        e, w = ids[i], u[i]
        height = _span(w, spans, U_HEIGHT)
        speed = _span(w, spans, U_SPEED)
        pitch = math.radians(_span(w, spans, U_PITCH))
        roll = math.radians(_span(w, spans, U_ROLL))
        yaw = _span(w, spans, U_YAW)
        bearing = yaw + math.radians(_span(w, spans, U_BEARING))
        dist = _span(w, spans, U_DISTANCE) * height
        wind_speed = _span(w, spans, U_WIND)
        wind_dir = _span(w, spans, U_WIND_DIR)
        # yaw, then nose-up pitch (about -y), then roll right (about +x): q = qz * qy * qx
        cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
        cp, sp = math.cos(-pitch / 2), math.sin(-pitch / 2)
        cr, sr = math.cos(roll / 2), math.sin(roll / 2)
        qw = cy * cp * cr + sy * sp * sr
        qx = cy * cp * sr - sy * sp * cr
        qy = cy * sp * cr + sy * cp * sr
        qz = sy * cp * cr - cy * sp * sr
        q[0, 0], q[0, 1], q[0, 2], q[0, 3] = qw, qx, qy, qz
        rot = quat_matrices(q)[0]  # the physics' rotation (its contracted arithmetic)
        nx, ny, nz = speed * rot[0, 0], speed * rot[1, 0], speed * rot[2, 0]  # the nose
        norm = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
        st[OX, 0, e], st[OX + 1, 0, e], st[OX + 2, 0, e] = 0.0, 0.0, height
        st[OQ, 0, e], st[OQ + 1, 0, e] = qw / norm, qx / norm
        st[OQ + 2, 0, e], st[OQ + 3, 0, e] = qy / norm, qz / norm
        st[OV, 0, e], st[OV + 1, 0, e], st[OV + 2, 0, e] = nx, ny, nz
        st[OL, 0, e], st[OL + 1, 0, e], st[OL + 2, 0, e] = 0.0, 0.0, 0.0
        diverged[e] = False
        if warm.shape[0]:
            warm[e] = 0.0
        v_prev[e, 0], v_prev[e, 1], v_prev[e, 2], v_prev[e, 3] = nx, ny, nz, rot[2, 2]
        flow[0, e], flow[1, e], flow[2, e] = (
            math.cos(wind_dir) * wind_speed,
            math.sin(wind_dir) * wind_speed,
            0.0,
        )
        launch[e, 0], launch[e, 1] = 0.0, 0.0
        target[e, 0], target[e, 1] = math.cos(bearing) * dist, math.sin(bearing) * dist
        distance[e] = dist
