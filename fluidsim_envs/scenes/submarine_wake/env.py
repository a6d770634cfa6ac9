"""fluidsim/SubmarineWake-v0: a small UUV holds station behind a cruising submarine, in its
wake."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ...physics import Craft, Simulator, WakeField, World
from ...physics import checks as CK
from ...physics.forces import thrust_control
from ...physics.kernels import INTEGRATORS
from ...physics.wake import MODELS as WAKE_MODELS
from ...physics.wake import NSRC as WAKE_SOURCE_ROWS
from ..base import FluidEnv, FluidVectorEnv, check_choice
from ..limits import (
    EPISODE_STEPS,
    SUBSTEPS,
    WEIGHT,
    Bound,
    Span,
    check_params,
    check_step,
)
from . import kernel as TK
from .kernel import OBSERVATION, REWARD_TERMS
from .view import SubmarineWakeView

LEAD_LENGTH_M, LEAD_RADIUS_M = 40.0, 3.0  # the submarine craft's hull (a prolate spheroid)
UUV_RADIUS_M = 0.16  # the uuv craft's hull radius
ROUTE_SEGMENTS = 8


@dataclass(frozen=True)
class SubmarineWakeParams:
    """Parameters of SubmarineWake-v0 (``gym.make(id, **kwargs)`` overrides any of them).

    Ranges are (low, high) pairs drawn uniformly per episode. What each field may be is
    declared once, in ``RANGES`` (and ``dt`` at most the integrator's measured stability
    limit, ``scenes/limits.py``); docs/environments.md's parameter table is written from it.
    Offsets are in the lead's frame (x forward from its center, y to port, z up); its hull
    spans x in [-20, 20] m.
    """

    # rk2 at 1/20 s: 0.8 times the force evaluations of symplectic Euler at 1/50 s and more
    # accurate (docs/study.md, Reading)
    dt: float = 1.0 / 20.0  # physics step (s)
    substeps: int = 2  # physics steps per action: 10 actions per second
    integrator: str = "rk2"
    dtype: str = "float64"  # physics precision; observations are float32
    max_episode_steps: int = 600  # 60 s
    # the lead submarine's scripted route
    lead_depth_m: tuple = (25.0, 40.0)
    lead_speed_mps: tuple = (1.2, 2.2)  # each route segment's cruising speed
    lead_turn_deg_s: tuple = (-1.5, 1.5)  # each segment's turn rate (+ left)
    straight_fraction: float = 0.4  # share of segments run straight
    segment_s: tuple = (10.0, 25.0)  # segment durations
    route_lag_s: float = 5.0  # time constant of the lead's speed and turn-rate changes
    floor_depth_m: float = 55.0  # the flat sea floor
    # the station point and the start
    station_behind_m: tuple = (-32.0, -24.0)  # station x (the stern is at -20)
    station_side_m: tuple = (1.0, 4.0)  # |station y|, to port or starboard at random
    station_up_m: tuple = (-2.0, 2.0)  # station z
    start_error_m: float = 4.0  # start this far from the station point at most, each axis
    start_heading_deg: float = 10.0  # and this far off the lead's heading at most
    # the wake
    wake: bool = True
    screws: int = 2
    circulation: float = 1.0  # vortex strength / (speed x hull radius)
    noise: float = 0.15  # turbulence amplitude / speed
    # dipoles carrying the hull's displacement flow: 8 are within 0.5% of the speed of the
    # exact flow from two hull radii out, where the station lies; 24 resolve it down to the
    # hull at three times the cost (tests/physics/test_wake.py)
    wake_dipoles: int = 8
    # how the wake is evaluated: "exact" (every closed form at every point; v0's default)
    # or "table" (WakeField(model="table"): the same flow to 3e-5 of the lead's speed (RMS)
    # where the UUV flies; the time the wake adds to a step 0.6-0.75 of the exact's;
    # docs/physics.md, "A cheaper wake")
    wake_model: str = "exact"
    # ending and scoring
    lost_distance_m: float = 30.0  # this far from the station point, the lead is lost
    success_radius_m: float = 3.0
    success_fraction: float = 0.8  # of the steps on station, for a successful episode
    station_scale_m: float = 3.0
    w_station: float = 1.0  # per step, times exp(-distance / station_scale_m)
    w_effort: float = 0.05  # per step, times the mean squared action
    w_crash: float = 100.0  # hitting the hull or the floor, losing the lead, diverging

    CHOICES: ClassVar[dict] = {"wake_model": WAKE_MODELS}  # the allowed strings
    NAME: ClassVar[str] = "SubmarineWake-v0"  # what errors name
    RANGES: ClassVar[dict] = {
        "dt": Bound(1e-5, 0.5),  # and the integrator's limit (limits.DT_LIMIT_S)
        "substeps": SUBSTEPS,
        "max_episode_steps": EPISODE_STEPS,
        "lead_depth_m": Span(5.0, 1000.0),
        "lead_speed_mps": Span(0.0, 5.0),
        "lead_turn_deg_s": Span(-10.0, 10.0),
        "straight_fraction": Bound(0.0, 1.0),
        "segment_s": Span(1.0, 1e4),
        "route_lag_s": Bound(1e-6, 1e4),
        "floor_depth_m": Bound(1e-6, 1e4),
        "station_behind_m": Span(-200.0, 200.0),
        "station_side_m": Span(0.0, 100.0),
        "station_up_m": Span(-100.0, 100.0),
        "start_error_m": Bound(0.0, 100.0),
        "start_heading_deg": Bound(0.0, 180.0),
        "screws": Bound(1, 2, integer=True),
        # a wake's vortices and turbulence stronger than these move the water faster than the
        # lead itself, which no submarine's wake does: beyond them the UUV's rate damping
        # stiffens past the default step's stability limit (benchmarks/env_stability.py).
        # Circulation stops at 2: beyond it (a fast lead, full turbulence) rk2 at the default
        # step carries the vortex's spin onto the UUV's light roll axis and runs away (the
        # witness at a quarter step shows it, the UUV's runaway rate flags it)
        "circulation": Bound(0.0, 2.0),
        "noise": Bound(0.0, 1.0),
        "wake_dipoles": Bound(1, 32, integer=True),
        "lost_distance_m": Bound(1e-6, 1e4),
        "success_radius_m": Bound(0.0, 1e3),
        "success_fraction": Bound(0.0, 1.0),
        "station_scale_m": Bound(1e-6, 1e3),
        **dict.fromkeys(("w_station", "w_effort", "w_crash"), WEIGHT),
    }

    def __post_init__(self) -> None:
        own = self.NAME
        check_params(self, own, self.RANGES)
        check_choice(own, "integrator", self.integrator, sorted(INTEGRATORS))
        check_step(own, self.dt, self.integrator, self.NAME)  # v1: its own, measured at hard
        check_choice(own, "dtype", self.dtype, ("float32", "float64"))
        for key, choices in self.CHOICES.items():
            check_choice(own, key, getattr(self, key), choices)
        CK.flag(own, "wake", self.wake)  # True or False: 1 is no switch
        if self.floor_depth_m <= self.lead_depth_m[1] + LEAD_RADIUS_M:
            raise ValueError(
                f"{own}: floor_depth_m ({self.floor_depth_m}) must be below the deepest lead "
                f"({self.lead_depth_m[1]} m) plus its radius ({LEAD_RADIUS_M} m)"
            )

    def wake_field(self) -> WakeField:
        """The lead's WakeField with these parameters."""
        return WakeField(
            length_m=LEAD_LENGTH_M,
            radius_m=LEAD_RADIUS_M,
            screws=int(self.screws),
            circulation=float(self.circulation),
            noise=float(self.noise),
            dipoles=int(self.wake_dipoles),
            model=self.wake_model,
        )


class SubmarineWakeVectorEnv(FluidVectorEnv):
    """SubmarineWake-v0 for N scenes at once, stepped by one compiled call; the task, spaces
    and rewards are documented on :class:`SubmarineWakeEnv`.

    Examples:
        >>> import gymnasium as gym
        >>> import numpy as np
        >>> import fluidsim_envs
        >>> envs = gym.make_vec("fluidsim/SubmarineWake-v0", num_envs=4,
        ...                     vectorization_mode="vector_entry_point")
        >>> obs, info = envs.reset(seed=0)
        >>> obs.shape
        (4, 22)
        >>> obs, reward, terminated, truncated, info = envs.step(np.zeros((4, 3)))
        >>> sorted(info["reward_terms"])
        ['crash', 'effort', 'station']
    """

    Params = SubmarineWakeParams
    View = SubmarineWakeView
    observation_layout = OBSERVATION  # (name, unit, description) per column
    obs_dim = len(OBSERVATION)
    reward_terms = REWARD_TERMS
    action_names = ("thrust", "rudder", "dive_planes")
    # _src is the Simulator's own with the wake (in its snapshot too: the same numbers)
    state_fields = (
        ("_ctrl", 0),
        ("lead", 1),
        ("route", 0),
        ("station", 0),
        ("noise_offset", 0),
        ("_src", 1),
        ("_terms", 1),
        ("_flags", 1),
        ("_distance", 0),
        ("_on_station", 0),
    )

    def _build(self) -> None:
        p = self.params
        E = self.num_envs
        self.craft = Craft.load("uuv")
        self.lead_craft = Craft.load("submarine")
        self.wake = p.wake_field()
        self.sim = Simulator(
            self.craft,
            World(water=True),
            num_envs=E,
            dt=p.dt,
            integrator=p.integrator,
            dtype=p.dtype,
            wake=self.wake if p.wake else None,
        )
        self._wprm = self.wake.params() if p.wake else np.zeros_like(self.wake.params())
        (prop,) = self.craft.thrusters
        self._thrust_range = (prop.min_thrust_n, prop.max_thrust_n)
        if self.sim.control_names != self.action_names or prop.control != self.action_names[0]:
            raise ValueError(  # _controls maps the actions onto the channels one to one
                f"SubmarineWake: the craft's control channels {self.sim.control_names} must be "
                f"the actions {self.action_names}, its thruster on {self.action_names[0]!r}"
            )
        self._ctrl = np.zeros((E, len(self.sim.control_names)))
        self.lead = np.zeros((TK.NLEAD, E))
        # segment end time, speed, turn rate; the route repeats after its last segment (a fixed
        # count, so that an episode's draws do not depend on the time limit)
        self.route = np.zeros((E, ROUTE_SEGMENTS, 3))
        self.station = np.zeros((E, 3))  # station offset in the lead's frame
        self.noise_offset = np.zeros((E, 3))
        # the wake's source rows: the Simulator's own when it has the wake, so the kernel
        # reads what lead_source writes
        self._src = self.sim.wake_source_rows() if p.wake else np.zeros((WAKE_SOURCE_ROWS, E))
        self._cfg = np.array([self._cfg_value(name) for name in TK.CFG_FIELDS], dtype=np.float64)
        self._terms = np.zeros((len(REWARD_TERMS), E))
        self._flags = np.zeros((TK.NFLAGS, E), dtype=bool)
        self._distance = np.zeros(E)
        self._on_station = np.zeros(E, dtype=np.int64)
        self.draws_per_episode = 14 + 4 * ROUTE_SEGMENTS
        self._task = TK.task_parallel if self.sim.parallel else TK.task_serial

    def _cfg_value(self, name: str) -> float:
        derived = {
            "hull_length_m": LEAD_LENGTH_M,
            "hull_radius_m": LEAD_RADIUS_M,
            "vehicle_half_length_m": max(abs(s.offset_m[0]) for s in self.craft.plates),
            "vehicle_radius_m": UUV_RADIUS_M,
            "sensor_x_m": max(s.offset_m[0] for s in self.craft.plates),
        }
        return derived[name] if name in derived else float(getattr(self.params, name))

    # ---- episode start --------------------------------------------------------------------

    def _draw_reset(self, ids, u) -> None:
        p = self.params
        S = self.route.shape[1]

        def span(x, lo_hi):
            return lo_hi[0] + x * (lo_hi[1] - lo_hi[0])

        heading = 2 * np.pi * u[:, 0]
        speed = span(u[:, 1], p.lead_speed_mps)
        depth = span(u[:, 2], p.lead_depth_m)
        side = np.where(u[:, 3] < 0.5, 1.0, -1.0) * span(u[:, 4], p.station_side_m)
        station = np.stack(
            [span(u[:, 5], p.station_behind_m), side, span(u[:, 6], p.station_up_m)], axis=1
        )
        # the route: segments of random duration, speed and turn (some straight)
        seg = u[:, 14:].reshape(len(ids), S, 4)
        ends = np.cumsum(span(seg[..., 0], p.segment_s), axis=1)
        turn = np.radians(span(seg[..., 2], p.lead_turn_deg_s))
        turn = np.where(seg[..., 3] < p.straight_fraction, 0.0, turn)
        self.route[ids] = np.stack([ends, span(seg[..., 1], p.lead_speed_mps), turn], axis=2)
        self.route[ids, 0, 1] = speed  # the first segment keeps the starting speed

        lead = self.lead
        lead[:, ids] = 0.0
        lead[TK.L_Z, ids] = -depth
        lead[TK.L_HEADING, ids] = heading
        lead[TK.L_SPEED, ids] = speed
        lead[TK.L_TURN, ids] = self.route[ids, 0, 2]
        self.station[ids] = station
        self.noise_offset[ids] = 1000.0 * u[:, 7:10]

        # the vehicle: near the station point, roughly on the lead's heading, at its speed
        err = 2 * u[:, 10:14] - 1
        c, s = np.cos(heading), np.sin(heading)
        ox, oy = station[:, 0], station[:, 1]
        spot = (
            np.stack([c * ox - s * oy, s * ox + c * oy, station[:, 2] - depth], axis=1)
            + p.start_error_m * err[:, :3]
        )
        yaw = heading + np.radians(p.start_heading_deg) * err[:, 3]
        quat = np.stack([np.cos(yaw / 2), 0 * yaw, 0 * yaw, np.sin(yaw / 2)], axis=1)
        vel = np.stack([speed * c, speed * s, 0 * speed], axis=1)
        self.sim.reset(pos=spot[:, None], quat=quat[:, None], lin_vel=vel[:, None], env_ids=ids)
        self._on_station[ids] = 0
        self._distance[ids] = np.linalg.norm(
            spot - np.stack([c * ox - s * oy, s * ox + c * oy, station[:, 2] - depth], 1), axis=1
        )
        TK.lead_source(ids, self.lead, self.noise_offset, self._src)

    def redraw_future(self, task, rng):
        """The lead's route from here on is drawn again: the segment it is on keeps its speed
        and turn (what it is doing now) and ends at a time uniform over what is left of the
        segment lengths it may have, the segments after it are drawn as at an episode's start.
        A route that has started over repeats segments already seen and is kept. The wake's
        turbulence is frozen in the water (``physics/wake.py``): the water's present, kept."""
        task = super().redraw_future(task, rng)
        p, route = self.params, task["route"].copy()
        time = task["lead"][:, TK.L_TIME]
        rows = np.flatnonzero(time < route[:, -1, 0])
        now, r = time[rows], route[rows]
        S = r.shape[1]

        def span(x, lo_hi):
            return lo_hi[0] + x * (lo_hi[1] - lo_hi[0])

        on = (r[:, :, 0] <= now[:, None]).sum(axis=1)  # the segment each lead is on
        begun = np.where(on > 0, r[np.arange(rows.size), np.maximum(on - 1, 0), 0], 0.0)
        u = rng.random((rows.size, S, 4))
        shortest = np.maximum(p.segment_s[0], now - begun)
        own_end = begun + span(u[:, 0, 0], (shortest, np.maximum(p.segment_s[1], shortest)))
        later = np.arange(S) > on[:, None]
        length = np.where(later, span(u[..., 0], p.segment_s), 0.0)
        turn = np.radians(span(u[..., 2], p.lead_turn_deg_s))
        turn = np.where(u[..., 3] < p.straight_fraction, 0.0, turn)
        r[:, :, 0] = np.where(later, own_end[:, None] + np.cumsum(length, axis=1), r[:, :, 0])
        r[np.arange(rows.size), on, 0] = own_end
        r[:, :, 1] = np.where(later, span(u[..., 1], p.lead_speed_mps), r[:, :, 1])
        r[:, :, 2] = np.where(later, turn, r[:, :, 2])
        route[rows] = r
        return {**task, "route": route}

    # ---- step -----------------------------------------------------------------------------

    def _controls(self, actions):
        """The craft's channels for the agent's actions: the thrust action maps linearly
        from full astern (-1) to full ahead (+1), as v0 always has (0: a third ahead); the
        craft's thrust channel gives no thrust at 0, so it gets that thrust's value."""
        lo, hi = self._thrust_range
        self._ctrl[:] = actions
        thrust = lo + 0.5 * (self._ctrl[:, 0] + 1.0) * (hi - lo)
        self._ctrl[:, 0] = thrust_control(thrust, lo, hi)
        return self._ctrl

    def _advance(self, actions):
        p = self.params
        # the physics moves the wake's source on in a straight line; the task kernel then
        # moves the lead along its route and puts the source back on it
        self.sim.step(self._controls(actions), steps=p.substeps)
        diverged = self.sim.diverged.copy()
        st, _, body = self.sim.kernel_arrays()
        self._task(
            st, body, diverged, self.lead, self.route, p.dt * p.substeps, p.route_lag_s,
            self.noise_offset, self._src, self.station, self._wprm, actions, self._cfg,
            self._terms, self._flags, self._distance, self._truth,
        )  # fmt: skip
        flags = self._flags.copy()
        self._on_station += flags[TK.F_ON_STATION]
        crashed = flags[TK.F_HULL] | flags[TK.F_FLOOR] | flags[TK.F_LOST]
        fraction = self._on_station / (self._elapsed + 1)
        info = {
            "station_distance_m": self._distance.copy(),
            "hit_hull": flags[TK.F_HULL],
            "hit_floor": flags[TK.F_FLOOR],
            "lost_lead": flags[TK.F_LOST],
            "on_station": flags[TK.F_ON_STATION],
            "on_station_fraction": fraction,
            # so far: at the episode's end (a crash, or either time limit) it is the verdict
            "success": ~crashed & ~diverged & (fraction >= p.success_fraction),
        }
        return crashed, diverged, self._terms.copy(), info

    # ---- observation ----------------------------------------------------------------------

    def _observe(self, out, ids) -> None:
        st, _, body = self.sim.kernel_arrays()
        TK.observe(
            ids, self._keep_none, st, body, self.lead, self.station, self._src, self._wprm,
            self._cfg, out,
        )  # fmt: skip

    # ---- what viewers read -----------------------------------------------------------------

    def lead_pose(self, env_index: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The lead submarine's position [3], quaternion [4] (w, x, y, z; level, turned to its
        heading) and velocity [3] in sub-env ``env_index`` (new arrays; the lead is
        scripted, not a simulated body)."""
        lead = self.lead[:, env_index]
        h, speed = float(lead[TK.L_HEADING]), float(lead[TK.L_SPEED])
        pos = np.array([lead[TK.L_X], lead[TK.L_Y], lead[TK.L_Z]])
        quat = np.array([math.cos(h / 2), 0.0, 0.0, math.sin(h / 2)])
        vel = np.array([speed * math.cos(h), speed * math.sin(h), 0.0])
        return pos, quat, vel

    def lead_heading(self, env_index: int) -> float:
        """The lead's heading in sub-env ``env_index`` (rad, from world x toward y)."""
        return float(self.lead[TK.L_HEADING, env_index])

    def station_point(self, env_index: int) -> np.ndarray:
        """The station point of sub-env ``env_index`` in the world [3] (m)."""
        pos, _, _ = self.lead_pose(env_index)
        h = self.lead_heading(env_index)
        c, s = math.cos(h), math.sin(h)
        sx, sy, sz = self.station[env_index]
        return pos + np.array([c * sx - s * sy, s * sx + c * sy, sz])


class SubmarineWakeEnv(FluidEnv):
    """A small UUV must hold station behind and beside a cruising submarine, in its wake.

    ## Description

    The lead is the shipped craft ``submarine`` (40 m, 773 t, twin screws), driven along a
    scripted route: level cruise at a constant depth above a flat sea floor, in segments of
    random length, each with its own speed and turn rate, changed smoothly. Its wake is a
    :class:`~fluidsim_envs.physics.WakeField`: water pushed aside by the hull, a
    counter-rotating vortex pair from the screws, and turbulence behind, all scaled with its
    speed. The agent flies the shipped ``uuv`` (2.4 m, 172 kg, slightly positive, a
    propeller, all-moving rudder and dive planes) whose fluid samples feel the wake at their
    own points: it is pushed, rolled and pitched by it. It must stay at a station point set
    behind and beside the lead without hitting the hull or the floor.

    ## Action Space

    ``Box(-1, 1, (3,), float32)``: thrust (-1: 60 N astern, +1: 120 N ahead; 0 gives 30 N),
    rudder (+ turns the nose right), dive planes (+ pitches the nose up), each fin up to 25
    degrees. Values beyond [-1, 1] saturate at the limit; NaN or a wrong shape is an error.

    ## Observation Space

    ``Box(-inf, inf, (22,), float32)``, SI units, body frame x forward, y left, z up:

    | Index | Name | Unit | Description |
    |-------|------|------|-------------|
    | 0-2 | u, v, w | m/s | velocity over the ground in the body frame |
    | 3-5 | p, q, r | rad/s | body rates: p + right side down, q + nose down, r + nose left |
    | 6-8 | gx, gy, gz | 1 | unit gravity direction in the body frame |
    | 9 | depth | m | depth of the center below the surface |
    | 10 | altitude | m | height of the center above the sea floor |
    | 11-13 | station_x, _y, _z | m | station point relative to the vehicle, body frame |
    | 14-16 | flow_x, _y, _z | m/s | water velocity (the wake) at the nose sensor, body frame |
    | 17-19 | station_vx, _vy, _vz | m/s | station point's velocity relative to the vehicle |
    | 20-21 | heading_sin, _cos | 1 | sine and cosine of the lead's heading minus the vehicle's |

    ## Rewards

    The reward is the sum of named terms, each reported per step in
    ``info["reward_terms"]`` and summed per episode in ``info["episode_terms"]`` at its end:

    - ``station``: ``w_station * exp(-distance / station_scale_m)`` every step (1 on the
      station point, 0.37 at 3 m);
    - ``effort``: ``-w_effort`` x the mean squared action, every step;
    - ``crash``: ``-w_crash`` on hitting the hull or the floor, losing the lead, or a
      diverged state.

    ## Starting State

    The lead starts at the origin's vertical at a depth in ``lead_depth_m``, heading in a
    uniformly random direction at a speed in ``lead_speed_mps``. The station point is at
    x in ``station_behind_m`` (the stern is at -20 m), 1-4 m to port or starboard
    (``station_side_m``) and z in ``station_up_m`` in the lead's frame. The vehicle starts
    within ``start_error_m`` of it on each axis, within ``start_heading_deg`` of the lead's
    heading, level, at the lead's velocity. The turbulence is shifted by a random offset.

    ## Episode End

    Terminated: the vehicle's nose, center or tail within its radius of the lead's hull
    (``info["hit_hull"]``) or of the floor (``info["hit_floor"]``); farther than
    ``lost_distance_m`` from the station point (``info["lost_lead"]``); a non-finite physics
    state (``info["physics_diverged"]``; the observation is then the last finite one).
    Truncated: ``max_episode_steps`` actions. ``info["success"]`` at the last step marks an
    episode that ended without a crash, having spent ``success_fraction`` of its steps within
    ``success_radius_m`` of the station point (``info["on_station_fraction"]``).

    ## Arguments

    ``gym.make("fluidsim/SubmarineWake-v0", **kwargs)`` and ``gym.make_vec(...,
    vectorization_mode="vector_entry_point", **kwargs)`` accept ``render_mode``
    (``"rgb_array"``) and every field of :class:`SubmarineWakeParams` (physics ``dt``,
    ``substeps``, ``integrator``, ``dtype``; the lead's route; the station; the wake:
    ``wake`` on or off, ``screws``, ``circulation``, ``noise``, ``wake_dipoles``,
    ``wake_model``: ``"exact"`` or the cheaper ``"table"``; limits and reward weights);
    an unknown key is an error listing the valid ones.

    ## Version History

    - v0: first version.

    Examples:
        >>> import gymnasium as gym
        >>> import fluidsim_envs
        >>> env = gym.make("fluidsim/SubmarineWake-v0")
        >>> obs, info = env.reset(seed=0)
        >>> obs.shape
        (22,)
        >>> obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    """

    vector_cls = SubmarineWakeVectorEnv


__all__ = ["OBSERVATION", "SubmarineWakeEnv", "SubmarineWakeParams", "SubmarineWakeVectorEnv"]
