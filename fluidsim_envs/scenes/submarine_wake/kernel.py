"""SubmarineWake-v0's layouts (observation, reward terms, flags, the lead's state, task config)
and its per-step task logic in compiled calls: the lead submarine's scripted route, the station
point, the observation (with the flow sensor reading the WakeField) and the reward terms, for
all envs at once.

Each layout is declared once, as a tuple of names, and the constants the kernels use are looked
up by name from it. The layouts live in this module because numba's cache is keyed on this
file alone (a layout edited elsewhere would leave stale compiled indices behind)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ...physics.kernels import body_state
from ...physics.rotation import env_inv_inertia, quat_to_matrix, to_body
from ...physics.state import OQ, OX
from ...physics.wake import source_tuple, wake_at
from ..layout import index

OBSERVATION = (
    # (name, unit, description): the columns of the observation, in order
    ("u", "m/s", "velocity along body x (forward), over the ground"),
    ("v", "m/s", "velocity along body y (left)"),
    ("w", "m/s", "velocity along body z (up)"),
    ("p", "rad/s", "roll rate (+ right side down)"),
    ("q", "rad/s", "pitch rate (+ nose down)"),
    ("r", "rad/s", "yaw rate (+ nose left)"),
    ("gx", "1", "gravity direction in the body frame, x"),
    ("gy", "1", "gravity direction in the body frame, y"),
    ("gz", "1", "gravity direction in the body frame, z"),
    ("depth", "m", "depth of the center below the surface"),
    ("altitude", "m", "height of the center above the sea floor"),
    ("station_x", "m", "station point relative to the vehicle, body x"),
    ("station_y", "m", "station point relative to the vehicle, body y"),
    ("station_z", "m", "station point relative to the vehicle, body z"),
    ("flow_x", "m/s", "water velocity at the nose sensor, body x"),
    ("flow_y", "m/s", "water velocity at the nose sensor, body y"),
    ("flow_z", "m/s", "water velocity at the nose sensor, body z"),
    ("station_vx", "m/s", "station point's velocity relative to the vehicle, body x"),
    ("station_vy", "m/s", "station point's velocity relative to the vehicle, body y"),
    ("station_vz", "m/s", "station point's velocity relative to the vehicle, body z"),
    ("heading_sin", "1", "sine of the lead's heading minus the vehicle's"),
    ("heading_cos", "1", "cosine of the lead's heading minus the vehicle's"),
)
OBS_NAMES = tuple(name for name, _, _ in OBSERVATION)
OBS = index(OBS_NAMES)  # name -> column
O_U, O_V, O_W = OBS["u"], OBS["v"], OBS["w"]
O_P, O_Q, O_R = OBS["p"], OBS["q"], OBS["r"]
O_GX, O_GY, O_GZ = OBS["gx"], OBS["gy"], OBS["gz"]
O_DEPTH, O_ALTITUDE = OBS["depth"], OBS["altitude"]
O_STATION_X, O_STATION_Y, O_STATION_Z = OBS["station_x"], OBS["station_y"], OBS["station_z"]
O_FLOW_X, O_FLOW_Y, O_FLOW_Z = OBS["flow_x"], OBS["flow_y"], OBS["flow_z"]
O_STATION_VX, O_STATION_VY, O_STATION_VZ = (
    OBS["station_vx"],
    OBS["station_vy"],
    OBS["station_vz"],
)
O_HEADING_SIN, O_HEADING_COS = OBS["heading_sin"], OBS["heading_cos"]

REWARD_TERMS = ("station", "effort", "crash")
TERMS = index(REWARD_TERMS)
T_STATION, T_EFFORT, T_CRASH = TERMS["station"], TERMS["effort"], TERMS["crash"]
NTERMS = len(REWARD_TERMS)
FLAG_NAMES = ("hit_hull", "hit_floor", "lost_lead", "on_station")
FLAGS = index(FLAG_NAMES)
F_HULL, F_FLOOR, F_LOST = FLAGS["hit_hull"], FLAGS["hit_floor"], FLAGS["lost_lead"]
F_ON_STATION = FLAGS["on_station"]
NFLAGS = len(FLAG_NAMES)
# the lead's state rows lead[L_*, E]
LEAD_ROWS = ("x", "y", "z", "heading", "speed", "turn", "time")
LEAD = index(LEAD_ROWS)
L_X, L_Y, L_Z = LEAD["x"], LEAD["y"], LEAD["z"]
L_HEADING, L_SPEED, L_TURN, L_TIME = LEAD["heading"], LEAD["speed"], LEAD["turn"], LEAD["time"]
NLEAD = len(LEAD_ROWS)
# the task parameter vector: these fields (of SubmarineWakeParams, or derived), in this order
CFG_FIELDS = (
    "w_station",
    "w_effort",
    "w_crash",
    "station_scale_m",
    "success_radius_m",
    "lost_distance_m",
    "floor_depth_m",
    "route_lag_s",
    "hull_length_m",
    "hull_radius_m",
    "vehicle_half_length_m",
    "vehicle_radius_m",
    "sensor_x_m",
)
CFG = index(CFG_FIELDS)  # field -> slot
C_W_STATION, C_W_EFFORT, C_W_CRASH = CFG["w_station"], CFG["w_effort"], CFG["w_crash"]
C_STATION_SCALE, C_SUCCESS = CFG["station_scale_m"], CFG["success_radius_m"]
C_LOST, C_FLOOR, C_LAG = CFG["lost_distance_m"], CFG["floor_depth_m"], CFG["route_lag_s"]
C_HULL_L, C_HULL_R = CFG["hull_length_m"], CFG["hull_radius_m"]
C_HALF, C_RADIUS = CFG["vehicle_half_length_m"], CFG["vehicle_radius_m"]
C_SENSOR = CFG["sensor_x_m"]

_JIT = dict(cache=True, error_model="numpy")
TASK_BLOCK = 64  # sub-envs per call of a parallel task kernel (paper_airplane/kernel.py)


@njit(**_JIT)
def advance_lead(lo, hi, lead, route, dt, lag):
    """Move the leads of sub-envs ``lo`` to ``hi - 1`` along their routes by dt: speed and
    turn rate follow the current segment's targets with a first-order lag, the heading
    integrates the turn rate and the position moves along the mean heading of the step
    (level cruise).

    ``route[E, S, 3]`` holds each segment's (end time, speed, turn rate); after the last
    segment the route starts over."""
    k = 1.0 - math.exp(-dt / lag)
    for e in range(lo, hi):
        t = lead[L_TIME, e] % route[e, route.shape[1] - 1, 0]
        s = 0
        while s < route.shape[1] - 1 and route[e, s, 0] <= t:
            s += 1
        speed0, heading0 = lead[L_SPEED, e], lead[L_HEADING, e]
        lead[L_SPEED, e] = speed0 + k * (route[e, s, 1] - speed0)
        lead[L_TURN, e] += k * (route[e, s, 2] - lead[L_TURN, e])
        lead[L_HEADING, e] = heading0 + dt * lead[L_TURN, e]
        mid = 0.5 * (heading0 + lead[L_HEADING, e])
        step = 0.5 * (speed0 + lead[L_SPEED, e]) * dt
        lead[L_X, e] += step * math.cos(mid)
        lead[L_Y, e] += step * math.sin(mid)
        lead[L_TIME, e] += dt


@njit(**_JIT)
def lead_source(ids, lead, offset, src):
    """The wake source rows src[18, ids] (position, rotation, velocity, noise offset) of the
    leads of sub-envs ``ids`` (see physics.wake.source_row)."""
    for e in ids:
        c, s = math.cos(lead[L_HEADING, e]), math.sin(lead[L_HEADING, e])
        src[0, e], src[1, e], src[2, e] = lead[L_X, e], lead[L_Y, e], lead[L_Z, e]
        src[3, e], src[4, e], src[5, e] = c, -s, 0.0
        src[6, e], src[7, e], src[8, e] = s, c, 0.0
        src[9, e], src[10, e], src[11, e] = 0.0, 0.0, 1.0
        src[12, e], src[13, e], src[14, e] = lead[L_SPEED, e] * c, lead[L_SPEED, e] * s, 0.0
        src[15, e], src[16, e], src[17, e] = offset[e, 0], offset[e, 1], offset[e, 2]


@njit(**_JIT)
def _station(lead, station, e):
    """World position and velocity of env e's station point (offset in the lead's frame)."""
    c, s = math.cos(lead[L_HEADING, e]), math.sin(lead[L_HEADING, e])
    ox, oy, oz = station[e, 0], station[e, 1], station[e, 2]
    wx, wy = c * ox - s * oy, s * ox + c * oy
    u, r = lead[L_SPEED, e], lead[L_TURN, e]
    # velocity: the lead's plus its turn rate crossed with the offset
    return (
        lead[L_X, e] + wx,
        lead[L_Y, e] + wy,
        lead[L_Z, e] + oz,
        u * c - r * wy,
        u * s + r * wx,
        0.0,
    )


@njit(**_JIT)
def observe(ids, skip, st, body, lead, station, src, wprm, cfg, out):
    """Observation rows out[ids, len(OBSERVATION)] (float32) from the vehicle's state
    st[13, 1, E], except where ``skip`` [E] is set (a diverged state keeps its last finite
    observation)."""
    for e in ids:
        if skip[e]:
            continue
        (px, py, pz), (vx, vy, vz), rot, omega = body_state(st, 0, e, env_inv_inertia(body, e, 0))
        r0, r1, r2, r3, r4, r5, r6, r7, r8 = rot
        out[e, O_U], out[e, O_V], out[e, O_W] = to_body(rot, vx, vy, vz)
        out[e, O_P], out[e, O_Q], out[e, O_R] = to_body(rot, omega[0], omega[1], omega[2])
        out[e, O_GX], out[e, O_GY], out[e, O_GZ] = -r6, -r7, -r8  # R^T (0, 0, -1)
        out[e, O_DEPTH] = -pz
        out[e, O_ALTITUDE] = pz + cfg[C_FLOOR]
        sx, sy, sz, svx, svy, svz = _station(lead, station, e)
        dx, dy, dz = sx - px, sy - py, sz - pz
        out[e, O_STATION_X] = r0 * dx + r3 * dy + r6 * dz
        out[e, O_STATION_Y] = r1 * dx + r4 * dy + r7 * dz
        out[e, O_STATION_Z] = r2 * dx + r5 * dy + r8 * dz
        # the flow sensor in the nose reads the water's velocity there
        n = cfg[C_SENSOR]
        fx, fy, fz = wake_at(px + r0 * n, py + r3 * n, pz + r6 * n, source_tuple(src[:, e]), wprm)
        out[e, O_FLOW_X] = r0 * fx + r3 * fy + r6 * fz
        out[e, O_FLOW_Y] = r1 * fx + r4 * fy + r7 * fz
        out[e, O_FLOW_Z] = r2 * fx + r5 * fy + r8 * fz
        dvx, dvy, dvz = svx - vx, svy - vy, svz - vz
        out[e, O_STATION_VX] = r0 * dvx + r3 * dvy + r6 * dvz
        out[e, O_STATION_VY] = r1 * dvx + r4 * dvy + r7 * dvz
        out[e, O_STATION_VZ] = r2 * dvx + r5 * dvy + r8 * dvz
        err = lead[L_HEADING, e] - math.atan2(r3, r0)
        out[e, O_HEADING_SIN] = math.sin(err)
        out[e, O_HEADING_COS] = math.cos(err)


@njit(**_JIT)
def score(lo, hi, st, diverged, lead, station, actions, cfg, terms, flags, distance):
    """Collisions, losing the lead and the reward terms of sub-envs ``lo`` to
    ``hi - 1`` after a step; writes
    ``terms`` [NTERMS, E], ``flags`` [NFLAGS, E] (bool) and ``distance`` [E] (to the station point;
    kept where the state diverged)."""
    a = 0.5 * cfg[C_HULL_L] + cfg[C_RADIUS]
    b = cfg[C_HULL_R] + cfg[C_RADIUS]
    half = cfg[C_HALF]
    for e in range(lo, hi):
        for k in range(NTERMS):
            terms[k, e] = 0.0
        for k in range(NFLAGS):
            flags[k, e] = False
        effort = 0.0
        for k in range(actions.shape[1]):
            effort += actions[e, k] * actions[e, k]
        terms[T_EFFORT, e] = -cfg[C_W_EFFORT] * effort / actions.shape[1]
        if diverged[e]:
            terms[T_CRASH, e] = -cfg[C_W_CRASH]
            continue
        px, py, pz = st[OX, 0, e], st[OX + 1, 0, e], st[OX + 2, 0, e]
        rot = quat_to_matrix(st[OQ, 0, e], st[OQ + 1, 0, e], st[OQ + 2, 0, e], st[OQ + 3, 0, e])
        c, s = math.cos(lead[L_HEADING, e]), math.sin(lead[L_HEADING, e])
        for j in range(3):  # nose, center, tail against the lead's hull and the floor
            f = half * (1 - j)
            qx, qy, qz = px + rot[0] * f, py + rot[3] * f, pz + rot[6] * f
            dx, dy, dz = qx - lead[L_X, e], qy - lead[L_Y, e], qz - lead[L_Z, e]
            hx, hy = c * dx + s * dy, -s * dx + c * dy  # in the lead's frame
            if (hx / a) ** 2 + (hy / b) ** 2 + (dz / b) ** 2 <= 1.0:
                flags[F_HULL, e] = True
            if qz - cfg[C_RADIUS] <= -cfg[C_FLOOR]:
                flags[F_FLOOR, e] = True
        sx, sy, sz, _, _, _ = _station(lead, station, e)
        d = math.sqrt((sx - px) ** 2 + (sy - py) ** 2 + (sz - pz) ** 2)
        distance[e] = d
        flags[F_LOST, e] = d > cfg[C_LOST]
        flags[F_ON_STATION, e] = d <= cfg[C_SUCCESS]
        terms[T_STATION, e] = cfg[C_W_STATION] * math.exp(-d / cfg[C_STATION_SCALE])
        if flags[F_HULL, e] or flags[F_FLOOR, e] or flags[F_LOST, e]:
            terms[T_CRASH, e] = -cfg[C_W_CRASH]


# fmt: off
@njit(**_JIT)
def task_range(
    lo, hi, st, body, diverged, lead, route, dt, lag, offset, src, station, wprm, actions, cfg,
    terms, flags, distance, out
):
    """After a physics step of ``dt``: the leads of sub-envs ``lo`` to ``hi - 1`` moved on
    along their routes (and their wakes' sources with them), then their score and
    observation."""
    ids = np.arange(lo, hi)
    advance_lead(lo, hi, lead, route, dt, lag)
    lead_source(ids, lead, offset, src)
    score(lo, hi, st, diverged, lead, station, actions, cfg, terms, flags, distance)
    observe(ids, diverged, st, body, lead, station, src, wprm, cfg, out)


@njit(**_JIT)
def task_serial(
    st, body, diverged, lead, route, dt, lag, offset, src, station, wprm, actions, cfg, terms,
    flags, distance, out
):
    """:func:`task_range` of every sub-env."""
    task_range(
        0, st.shape[2], st, body, diverged, lead, route, dt, lag, offset, src, station, wprm,
        actions, cfg, terms, flags, distance, out
    )


@njit(parallel=True, **_JIT)
def task_parallel(
    st, body, diverged, lead, route, dt, lag, offset, src, station, wprm, actions, cfg, terms,
    flags, distance, out
):
    """:func:`task_serial` on every thread, ``TASK_BLOCK`` sub-envs a call: each writes only
    its own slots, the same as serial, bit for bit (tests/scenes/test_contract.py)."""
    for b in prange((st.shape[2] + TASK_BLOCK - 1) // TASK_BLOCK):
        lo = b * TASK_BLOCK
        task_range(
            lo, min(st.shape[2], lo + TASK_BLOCK), st, body, diverged, lead, route, dt, lag,
            offset, src, station, wprm, actions, cfg, terms, flags, distance, out
        )
# fmt: on
