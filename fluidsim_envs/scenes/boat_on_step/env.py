"""fluidsim/BoatOnStep-v0: a planing speedboat must get up on step, hold a target speed and
run a course of gates."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ...craft.buoy import MarkerBuoy
from ...physics import Craft, Simulator, World
from ...physics import checks as CK
from ...physics.hydrostatics import static_float
from ...physics.kernels import INTEGRATORS
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
from .kernel import OBSERVATION, REWARD_TERMS_V0
from .view import BoatOnStepView

REWARD_TERMS = REWARD_TERMS_V0  # this version's terms (envs/boat_on_step.py re-exports it)
GATES = 6  # per course (a fixed count, so that an episode's draws never depend on a limit)


@dataclass(frozen=True)
class BoatOnStepParams:
    """Parameters of BoatOnStep-v0 (``gym.make(id, **kwargs)`` overrides any of them).

    Ranges are (low, high) pairs drawn uniformly per episode. What each field may be is
    declared once, in ``RANGES`` (and ``dt`` at most the integrator's measured stability
    limit, ``scenes/limits.py``); docs/environments.md's parameter table is written from it.
    """

    # rk2 at 1/100 s: as cheap as symplectic Euler at 1/200 s (two force evaluations a step)
    # and 150 times more accurate over a second (docs/study.md, Reading)
    dt: float = 1.0 / 100.0  # physics step (s)
    substeps: int = 5  # physics steps per action: 20 actions per second
    integrator: str = "rk2"
    dtype: str = "float64"  # physics precision; observations are float32
    max_episode_steps: int = 1200  # 60 s
    # the engine: thrust up to the craft's static thrust, and never above power / speed
    engine_power_w: float = 80_000.0  # delivered thrust power (about 180 hp at the shaft)
    # the water: calm, or swell (world frame; the course's heading is random, so the swell
    # meets it from any direction), each wave (amplitude_m, wavelength_m, direction_deg) or
    # a SwellWave; each episode starts at a random moment of the swell
    swell: tuple = ()
    # the course
    target_speed_mps: tuple = (13.0, 19.0)  # planing: volumetric Froude number 4-6
    first_leg_m: tuple = (120.0, 180.0)  # straight run to the first gate (getting on plane)
    leg_m: tuple = (70.0, 110.0)  # between gates
    turn_deg: tuple = (-40.0, 40.0)  # course change at each gate
    start_heading_deg: float = 20.0  # the bow starts this far off the first leg at most
    gate_half_width_m: float = 8.0  # center to each buoy
    buoy_radius_m: float = 0.4
    # the buoys as floating bodies (a MarkerBuoy of buoy_radius_m each, moored at its mark,
    # that the hull hits and pushes aside: contact.py), or markers the hull passes through
    buoy_bodies: bool = False
    course_half_width_m: float = 60.0  # farther from the leg than this leaves the course
    # detection
    capsize_heel_deg: float = 70.0
    porpoise_deg: float = 1.0  # peak-to-peak trim oscillation that counts as porpoising
    # planing speed (Cv 2.4): porpoising is measured above it (the hump is not porpoising),
    # and info["time_to_plane_s"] is the time to reach it
    porpoise_min_speed_mps: float = 10.0
    porpoise_window_s: float = 1.0  # averaging time of the oscillation estimate
    # rewards
    speed_scale_mps: float = 2.0
    w_speed: float = 0.05  # per step, times exp(-|speed error| / speed_scale_mps)
    w_progress: float = 0.02  # per meter closed on the next gate
    w_gate: float = 5.0  # per gate passed (and minus per gate missed)
    w_buoy: float = 1.0  # per step touching a buoy
    w_porpoise: float = 0.05  # per step, times the oscillation over porpoise_deg, minus 1
    w_fuel: float = 0.01  # per step, times the throttle ahead
    w_crash: float = 20.0  # capsize, bow stuffed, off the course, diverged

    NAME: ClassVar[str] = "BoatOnStep-v0"  # what errors name
    RANGES: ClassVar[dict] = {
        "dt": Bound(1e-5, 0.05),  # and the integrator's limit (limits.DT_LIMIT_S)
        "substeps": SUBSTEPS,
        "max_episode_steps": EPISODE_STEPS,
        "engine_power_w": Bound(1.0, 1e7),
        "target_speed_mps": Span(0.0, 40.0),
        "first_leg_m": Span(10.0, 1e4),
        "leg_m": Span(10.0, 1e4),
        "turn_deg": Span(-120.0, 120.0),
        "start_heading_deg": Bound(0.0, 180.0),
        "gate_half_width_m": Bound(1.0, 100.0),
        "buoy_radius_m": Bound(0.0, 10.0),
        "course_half_width_m": Bound(5.0, 1e4),
        "capsize_heel_deg": Bound(10.0, 180.0),
        "porpoise_deg": Bound(1e-3, 90.0),
        "porpoise_min_speed_mps": Bound(0.0, 40.0),
        "porpoise_window_s": Bound(0.05, 60.0),
        "speed_scale_mps": Bound(1e-3, 100.0),
        **dict.fromkeys(
            ("w_speed", "w_progress", "w_gate", "w_buoy", "w_porpoise", "w_fuel", "w_crash"),
            WEIGHT,
        ),
    }

    def __post_init__(self) -> None:
        own = self.NAME
        check_params(self, own, self.RANGES)
        check_choice(own, "integrator", self.integrator, sorted(INTEGRATORS))
        check_step(own, self.dt, self.integrator, self.NAME)  # v1: its own, measured at hard
        check_choice(own, "dtype", self.dtype, ("float32", "float64"))
        CK.flag(own, "buoy_bodies", self.buoy_bodies)
        try:
            swell = World(water=True, swell=self.swell).swell
        except ValueError as err:
            raise ValueError(f"{own}: swell: {err}") from None
        object.__setattr__(self, "swell", swell)
        if self.buoy_radius_m >= self.gate_half_width_m:
            raise ValueError(
                f"{own}: buoy_radius_m ({self.buoy_radius_m}) must be smaller than "
                f"gate_half_width_m ({self.gate_half_width_m})"
            )


class BoatOnStepVectorEnv(FluidVectorEnv):
    """BoatOnStep-v0 for N scenes at once, stepped by one compiled call; the task, spaces and
    rewards are documented on :class:`BoatOnStepEnv`.

    Examples:
        >>> import gymnasium as gym
        >>> import numpy as np
        >>> import fluidsim_envs
        >>> envs = gym.make_vec("fluidsim/BoatOnStep-v0", num_envs=4,
        ...                     vectorization_mode="vector_entry_point")
        >>> obs, info = envs.reset(seed=0)
        >>> obs.shape
        (4, 18)
        >>> obs, reward, terminated, truncated, info = envs.step(np.zeros((4, 3)))
        >>> sorted(info["reward_terms"])
        ['buoy', 'crash', 'fuel', 'gate', 'porpoise', 'progress', 'speed']
    """

    Params = BoatOnStepParams
    View = BoatOnStepView
    observation_layout = OBSERVATION  # (name, unit, description) per column
    obs_dim = len(OBSERVATION)
    reward_terms = REWARD_TERMS
    action_names = ("throttle", "rudder", "trim_tabs")
    state_fields = (
        ("_mooring", 0),
        ("_hits", 0),
        ("course", 0),
        ("buoys", 0),
        ("task", 1),
        ("_ctrl", 0),
        ("_terms", 1),
        ("_flags", 1),
    )

    def _build(self) -> None:
        p = self.params
        E = self.num_envs
        self.craft = Craft.load("speedboat")
        self.world = self._world()
        crafts = [self.craft]
        if p.buoy_bodies:
            self.marker = MarkerBuoy.scaled(p.buoy_radius_m)
            crafts += [Craft.from_dict(self.marker.samples())] * (2 * GATES)
        self.sim = Simulator(
            crafts, self.world, num_envs=E, dt=p.dt, integrator=p.integrator, dtype=p.dtype
        )
        # with buoy bodies: each one's mooring force [E, 1 + 2 GATES, 3] (the boat's row 0)
        self._mooring = np.zeros((E, len(crafts), 3))
        self._hits = np.zeros(E, dtype=bool)  # the hull touched a buoy body this step
        self.rest_height_m, self.rest_trim_rad = static_float(
            self.craft, self.world.water_density_kgm3, self.world.gravity_mps2
        )
        self.course = np.zeros((E, GATES + 1, 3))  # start point, then the gates
        self.buoys = np.zeros((E, 2 * GATES, 2))  # left and right buoy of each gate
        self.task = np.zeros((TK.NTASK, E))
        self._cfg = np.array([self._cfg_value(name) for name in TK.CFG_FIELDS], dtype=np.float64)
        self.draws_per_episode = 4 + 2 * GATES
        self._task = TK.task_parallel if self.sim.parallel else TK.task_serial
        self._ctrl = np.zeros((E, 3))
        self._terms = np.zeros((TK.NTERMS, E))  # every version's; reward_terms' rows first
        self._flags = np.zeros((TK.NFLAGS, E), dtype=bool)

    def _world(self) -> World:
        """The water and its swell (v1 moves the water with it)."""
        return World(water=True, swell=self.params.swell)

    def _cfg_value(self, name: str) -> float:
        (prop,) = self.craft.thrusters
        (stem,) = [s for s in self.craft.plates if s.name == "stem"]
        derived = {
            "max_thrust_n": prop.max_thrust_n,
            "min_thrust_n": prop.min_thrust_n,
            "step_s": self.params.dt * self.params.substeps,
            "rest_height_m": self.rest_height_m,
            "bow_x_m": stem.offset_m[0],
            "bow_z_m": stem.offset_m[2],
            "hull_half_beam_m": max(abs(s.offset_m[1]) for s in self.craft.plates),
        }
        if hasattr(self.params, "ride_limit_g"):  # v1 judges the ride
            derived["ride_limit_mps2"] = self.params.ride_limit_g * self.world.gravity_mps2
        else:  # v0 does not: the kernel computes the term, weighs it 0 and drops its row
            derived.update(w_ride=0.0, ride_limit_mps2=1.0, ride_window_s=1.0)
        return derived[name] if name in derived else float(getattr(self.params, name))

    # ---- episode start --------------------------------------------------------------------

    def _draw_reset(self, ids, u) -> None:
        p = self.params

        def span(x, lo_hi):
            return lo_hi[0] + x * (lo_hi[1] - lo_hi[0])

        course_heading = 2 * np.pi * u[:, 0]
        self.task[TK.K_TARGET, ids] = span(u[:, 1], p.target_speed_mps)
        # the course: a first leg, then legs turning at each gate
        legs = np.concatenate(
            [span(u[:, 2:3], p.first_leg_m), span(u[:, 4 : 3 + GATES], p.leg_m)], axis=1
        )
        turns = np.radians(span(u[:, 3 + GATES : 3 + 2 * GATES], p.turn_deg))
        turns[:, 0] = 0.0
        heading = course_heading[:, None] + np.cumsum(turns, axis=1)
        steps = legs[..., None] * np.stack([np.cos(heading), np.sin(heading)], axis=2)
        course = self.course
        course[ids] = 0.0
        course[ids, 1:, :2] = np.cumsum(steps, axis=1)
        course[ids, 1:, TK.G_HEADING] = heading
        course[ids, 0, TK.G_HEADING] = course_heading
        across = np.stack([-np.sin(heading), np.cos(heading)], axis=2) * p.gate_half_width_m
        self.buoys[ids, 0::2] = course[ids, 1:, :2] + across
        self.buoys[ids, 1::2] = course[ids, 1:, :2] - across

        # the boat: at rest at its floating height and trim, bow off the first leg a little
        yaw = course_heading + np.radians(p.start_heading_deg) * (2 * u[:, 3] - 1)
        t = self.rest_trim_rad
        # yaw about z, then trim about the body's y (bow up: a negative rotation about y)
        quat = np.stack(
            [
                np.cos(yaw / 2) * np.cos(t / 2),
                np.sin(yaw / 2) * np.sin(t / 2),
                -np.cos(yaw / 2) * np.sin(t / 2),
                np.sin(yaw / 2) * np.cos(t / 2),
            ],
            axis=1,
        )
        # a random moment of the swell (a day of it), the boat floating on its surface
        clock = 86400.0 * u[:, 3 + 2 * GATES]
        self.sim.set_clock(clock, env_ids=ids)
        surface = self.world.surface_height(0.0, 0.0, clock)
        pos = np.stack([0 * clock, 0 * clock, self.rest_height_m + surface], axis=1)
        if p.buoy_bodies:  # each buoy afloat at its mark, upright, at rest
            marks = self.buoys[ids]
            z = self.world.surface_height(marks[..., 0], marks[..., 1], clock[:, None])
            buoys = np.concatenate([marks, (z - self.marker.waterline_m)[..., None]], axis=2)
            pos = np.concatenate([pos[:, None], buoys], axis=1)
            upright = np.tile((1.0, 0.0, 0.0, 0.0), (len(ids), 2 * GATES, 1))
            quat = np.concatenate([quat[:, None], upright], axis=1)
            self.sim.reset(pos=pos, quat=quat, env_ids=ids)
        else:
            self.sim.reset(pos=pos[:, None], quat=quat[:, None], env_ids=ids)
        st, _, body = self.sim.kernel_arrays()
        TK.start(st, body, self.course, self.task, self._cfg, np.asarray(ids, dtype=np.int64))

    # ---- step -----------------------------------------------------------------------------

    def _advance(self, actions):
        p = self.params
        st, _, _ = self.sim.kernel_arrays()
        TK.controls(st, actions, self._cfg, self._ctrl)
        if p.buoy_bodies:  # the chains pull each buoy back toward its mark
            self._mooring[:, 1:, :2] = -self.marker.mooring_stiffness_npm * (
                self.sim.pos[:, 1:, :2] - self.buoys
            )
            self.sim.set_external_force(self._mooring)
        self.sim.step(self._ctrl, steps=p.substeps)
        diverged = self.sim.diverged.copy()
        swell, clock = self.sim.surface_arrays()
        if p.buoy_bodies:  # pairs (0, 1) ... (0, 2 GATES) come first: the hull and each buoy
            np.greater(self.sim.pair_impulse[:, : 2 * GATES].max(axis=1), 0.0, out=self._hits)
        _, _, body = self.sim.kernel_arrays()
        self._task(
            st, body, diverged, actions, self.course,
            self.buoys[:, :0] if p.buoy_bodies else self.buoys,
            self._hits, self.task, swell, clock, self._cfg, self._terms, self._flags, self._truth,
        )  # fmt: skip
        f = self._flags.copy()
        crashed = f[TK.F_CAPSIZE] | f[TK.F_STUFF] | f[TK.F_LEFT]
        info = {
            "capsized": f[TK.F_CAPSIZE],
            "bow_stuffed": f[TK.F_STUFF],
            "left_course": f[TK.F_LEFT],
            "porpoising": f[TK.F_PORPOISE],
            "hit_buoy": f[TK.F_BUOY],
            "gate_passed": f[TK.F_PASSED],
            "gate_missed": f[TK.F_MISSED],
            "gates_passed": self.task[TK.K_PASSED].astype(np.int64),
            "gates_missed": self.task[TK.K_MISSED].astype(np.int64),
            # of this episode's steps so far
            "porpoising_fraction": self.task[TK.K_PORPOISING] / (self._elapsed + 1),
            # seconds from the start to planing speed (porpoise_min_speed_mps); -1: not yet
            "time_to_plane_s": self.task[TK.K_PLANED].copy(),
            # the course run through, every gate passed, nothing crashed
            "success": f[TK.F_FINISHED] & (self.task[TK.K_MISSED] == 0) & ~crashed & ~diverged,
        }
        terms = self._terms[: len(self.reward_terms)].copy()
        return crashed | f[TK.F_FINISHED], diverged, terms, info

    def buoy_xy(self, env_index: int) -> np.ndarray:
        """Where sub-env ``env_index``'s buoys are, [2 GATES, 2] (m, world): the bodies'
        positions with ``buoy_bodies``, else their marks (``self.buoys``, which also define
        the gates either way)."""
        if self.params.buoy_bodies:
            return np.asarray(self.sim.pos[env_index, 1:, :2], dtype=np.float64)
        return self.buoys[env_index]

    # ---- observation ----------------------------------------------------------------------

    def _observe(self, out, ids) -> None:
        st, _, body = self.sim.kernel_arrays()
        swell, clock = self.sim.surface_arrays()
        TK.observe(
            ids, self._keep_none, st, body, self.course, self.task, swell, clock, self._cfg, out
        )

    # ---- what viewers read -----------------------------------------------------------------

    @property
    def next_gate(self) -> np.ndarray:
        """Each sub-env's next gate [E], an index into ``course`` (1 is the first gate; past
        the last one when the course is run through)."""
        return self.task[TK.K_GATE].astype(np.int64)

    @property
    def target_speed(self) -> np.ndarray:
        """Each sub-env's target speed this episode [E] (m/s, a copy)."""
        return self.task[TK.K_TARGET].copy()


class BoatOnStepEnv(FluidEnv):
    """A planing speedboat must get up on step, hold a target speed and run a course of gates.

    ## Description

    The boat is the shipped craft ``speedboat``: a 5 m, 1 t V-bottom runabout whose hull is
    made of fluid samples (bottom plates at the deadrise angle along eight stations,
    buoyancy columns under them, skin friction, topsides, skeg, rudder, trim tabs and an
    outboard propeller). Nothing in the scene knows about planing: the lift that raises the
    hull onto the surface is the plates' force as they meet the water. Starting at rest, the
    boat must climb over the resistance hump onto the plane, then hold the episode's target
    speed through six gates (pairs of buoys) on legs that change heading, without
    porpoising, stuffing the bow, capsizing or burning fuel it does not need.

    ## Action Space

    ``Box(-1, 1, (3,), float32)``: throttle (0 idle, +1 full ahead: 4.5 kN static thrust,
    falling above 18 m/s as the engine's power allows; -1 full astern, 1.5 kN), rudder
    (+ turns the bow to starboard; 35 degrees), trim tabs (-1 flush, +1 fully down at 15
    degrees: bow down). Values beyond [-1, 1] saturate; NaN or a wrong shape is an error.

    ## Observation Space

    ``Box(-inf, inf, (18,), float32)``, SI units, body frame x forward, y left, z up:

    | Index | Name | Unit | Description |
    |-------|------|------|-------------|
    | 0-2 | u, v, w | m/s | velocity in the body frame |
    | 3-5 | p, q, r | rad/s | body rates: p + starboard down, q + bow down, r + bow left |
    | 6 | trim | rad | bow up + |
    | 7 | heel | rad | starboard side down + |
    | 8 | heave | m | center of gravity above the surface under it, less its height at rest |
    | 9 | speed_error | m/s | target speed minus speed over the ground |
    | 10-11 | gate_bearing_sin, _cos | 1 | bearing of the next gate's center from the bow |
    | 12-13 | gate_x, gate_y | m | next gate's center in the boat's heading frame |
    | 14-15 | gate_heading_sin, _cos | 1 | gate's direction of travel minus the heading |
    | 16 | target_speed | m/s | the episode's target speed |
    | 17 | pitch_oscillation | rad | running peak-to-peak trim oscillation |

    ## Rewards

    The reward is the sum of named terms, each reported per step in
    ``info["reward_terms"]`` and summed per episode in ``info["episode_terms"]`` at its end:

    - ``speed``: ``w_speed * exp(-|speed error| / speed_scale_mps)`` every step;
    - ``progress``: ``w_progress`` per meter closed on the next gate's center;
    - ``gate``: ``+w_gate`` for a gate passed bow first between its buoys, ``-w_gate`` for
      one missed (outside its buoys, or run stern first);
    - ``buoy``: ``-w_buoy`` every step the hull touches a buoy;
    - ``porpoise``: ``-w_porpoise * (oscillation / porpoise_deg - 1)`` while porpoising;
    - ``fuel``: ``-w_fuel`` x the throttle ahead, every step;
    - ``crash``: ``-w_crash`` on capsizing, stuffing the bow, leaving the course, or a
      diverged state.

    ## Starting State

    At rest, floating at the height and trim its buoyancy gives (in calm water; on the
    surface under it in swell, at a random moment of the swell), at the first leg's start,
    the bow within ``start_heading_deg`` of the leg's heading (uniform in every
    direction). The course: a first leg of ``first_leg_m``, then five legs of ``leg_m``, each
    turning by ``turn_deg`` at its gate; the target speed is drawn from ``target_speed_mps``.

    ## Episode End

    Terminated: every gate run through (``info["success"]`` when none was missed and nothing
    crashed); capsized (heel beyond ``capsize_heel_deg``, ``info["capsized"]``); bow stuffed
    (the stem under water while making way, ``info["bow_stuffed"]``); farther than
    ``course_half_width_m`` from the current leg (``info["left_course"]``); a non-finite
    physics state (``info["physics_diverged"]``; the observation is then the last finite
    one). Truncated: ``max_episode_steps`` actions. ``info["porpoising"]`` flags the steps
    with a trim oscillation above ``porpoise_deg`` at speed (``porpoising_fraction``: the
    episode's share of them); ``time_to_plane_s`` is the time it took to reach planing speed
    (``porpoise_min_speed_mps``). ``info["hit_buoy"]`` flags the steps the hull touches a
    buoy. By default the buoys are markers the hull passes through; with
    ``buoy_bodies=True`` each is a floating body (the shipped craft ``buoy``: a 0.8 m,
    40 kg ballasted sphere, scaled to ``buoy_radius_m``) moored at its mark by a chain
    (a horizontal spring, 6 s sway period), and a hit pushes it aside and slows the boat
    (contact with restitution 0.3). The gates stay where the marks are.

    ## Arguments

    ``gym.make("fluidsim/BoatOnStep-v0", **kwargs)`` and ``gym.make_vec(...,
    vectorization_mode="vector_entry_point", **kwargs)`` accept ``render_mode``
    (``"rgb_array"``) and every field of :class:`BoatOnStepParams` (physics ``dt``,
    ``substeps``, ``integrator``, ``dtype``; the engine; ``swell``, e.g.
    ``swell=[(0.3, 30.0, 45.0)]`` for 0.3 m waves 30 m long travelling north-east (up to
    four, each ``(amplitude_m, wavelength_m, direction_deg)``; calm by default); the course;
    detection thresholds and reward weights); an unknown key is an error listing the valid
    ones.

    ## Version History

    - v0: first version.

    Examples:
        >>> import gymnasium as gym
        >>> import fluidsim_envs
        >>> env = gym.make("fluidsim/BoatOnStep-v0")
        >>> obs, info = env.reset(seed=0)
        >>> obs.shape
        (18,)
        >>> obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    """

    vector_cls = BoatOnStepVectorEnv


__all__ = ["OBSERVATION", "BoatOnStepEnv", "BoatOnStepParams", "BoatOnStepVectorEnv"]
