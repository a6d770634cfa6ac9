"""fluidsim/PaperAirplane-v0: glide a paper dart to a target on the ground and land on it."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ...physics import Craft, Ground, Simulator, World
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
from .kernel import OBSERVATION, REWARD_TERMS
from .view import PaperAirplaneView


@dataclass(frozen=True)
class PaperAirplaneParams:
    """Parameters of PaperAirplane-v0 (``gym.make(id, **kwargs)`` overrides any of them).

    Ranges are (low, high) pairs drawn uniformly per episode. What each field may be is
    declared once, in ``RANGES`` (and ``dt`` at most the integrator's measured stability
    limit, ``scenes/limits.py``); docs/environments.md's parameter table is written from it.
    """

    # rk2 at 1/120 s: as cheap as symplectic Euler at 1/240 s (two force evaluations a step)
    # and about 90 times more accurate in flight (docs/study.md, Reading)
    dt: float = 1.0 / 120.0  # physics step (s)
    substeps: int = 4  # physics steps per action: 30 actions per second
    integrator: str = "rk2"
    dtype: str = "float64"  # physics precision; observations are float32
    max_episode_steps: int = 900  # 30 s
    launch_height_m: tuple = (4.0, 8.0)
    launch_speed_mps: tuple = (4.0, 8.0)
    launch_pitch_deg: tuple = (-10.0, 10.0)
    launch_roll_deg: tuple = (-15.0, 15.0)
    target_distance_ratio: tuple = (1.0, 3.0)  # target distance / launch height (glide ~4:1)
    target_bearing_deg: tuple = (-45.0, 45.0)  # target direction from the launch heading
    wind_speed_mps: tuple = (0.0, 1.0)  # horizontal wind from a uniformly random direction
    arena_radius_m: float = 60.0  # leaving this far from the launch point ends the episode
    ceiling_m: float = 30.0
    crash_sink_mps: float = 3.0  # touching down faster than this vertically is a crash
    crash_speed_mps: float = 12.0  # or this fast overall
    upright_min: float = 0.5  # body z must point up at least this much (cos 60 deg)
    success_radius_m: float = 2.0  # a landing this close to the target is a success
    accuracy_scale_m: float = 3.0
    w_progress: float = 1.0  # per metre closer to the target
    w_accuracy: float = 10.0  # landing on the target
    w_softness: float = 5.0  # landing with no sink
    w_crash: float = 10.0  # crash, leaving the arena or a diverged state
    w_effort: float = 0.01  # per step, times the mean squared action

    NAME: ClassVar[str] = "PaperAirplane-v0"  # what errors name
    RANGES: ClassVar[dict] = {
        "dt": Bound(1e-5, 0.1),  # and the integrator's limit (limits.DT_LIMIT_S)
        "substeps": SUBSTEPS,
        "max_episode_steps": EPISODE_STEPS,
        "launch_height_m": Span(0.5, 1000.0),
        # a hand throw is at most about 20 m/s, and a paper dart in more than a 15 m/s wind
        # (a strong breeze) is beyond its flight envelope: faster air stiffens its rate damping
        # past the default step's stability limit (docs/env_stability.csv, benchmarks/fuzz.py)
        "launch_speed_mps": Span(0.0, 20.0),
        "launch_pitch_deg": Span(-90.0, 90.0),
        "launch_roll_deg": Span(-180.0, 180.0),
        "target_distance_ratio": Span(0.0, 100.0),
        "target_bearing_deg": Span(-180.0, 180.0),
        "wind_speed_mps": Span(0.0, 15.0),
        "arena_radius_m": Bound(1e-6, 1e4),
        "ceiling_m": Bound(1e-6, 1e4),
        "crash_sink_mps": Bound(1e-6, 100.0),
        "crash_speed_mps": Bound(1e-6, 200.0),
        "upright_min": Bound(-1.0, 1.0),
        "success_radius_m": Bound(0.0, 1e3),
        "accuracy_scale_m": Bound(1e-6, 1e3),
        **dict.fromkeys(("w_progress", "w_accuracy", "w_softness", "w_crash", "w_effort"), WEIGHT),
    }

    def __post_init__(self) -> None:
        own = self.NAME
        check_params(self, own, self.RANGES)
        check_choice(own, "integrator", self.integrator, sorted(INTEGRATORS))
        check_step(own, self.dt, self.integrator, self.NAME)  # v1: its own, measured at hard
        check_choice(own, "dtype", self.dtype, ("float32", "float64"))
        if self.ceiling_m <= self.launch_height_m[1]:
            raise ValueError(
                f"{own}: ceiling_m ({self.ceiling_m}) must be above the highest launch "
                f"({self.launch_height_m[1]})"
            )


class PaperAirplaneVectorEnv(FluidVectorEnv):
    """PaperAirplane-v0 for N dart throws at once, stepped by one compiled call; the task,
    spaces and rewards are documented on :class:`PaperAirplaneEnv`.

    Examples:
        >>> import gymnasium as gym
        >>> import numpy as np
        >>> import fluidsim_envs
        >>> envs = gym.make_vec("fluidsim/PaperAirplane-v0", num_envs=4,
        ...                     vectorization_mode="vector_entry_point")
        >>> obs, info = envs.reset(seed=0)
        >>> obs.shape
        (4, 15)
        >>> obs, reward, terminated, truncated, info = envs.step(np.zeros((4, 3)))
        >>> sorted(info["reward_terms"])
        ['accuracy', 'crash', 'effort', 'progress', 'softness']
    """

    Params = PaperAirplaneParams
    View = PaperAirplaneView
    observation_layout = OBSERVATION  # (name, unit, description) per column
    obs_dim = len(OBSERVATION)
    reward_terms = REWARD_TERMS
    action_names = ("aileron", "elevator", "rudder")
    state_fields = (
        ("_v_prev", 0),
        ("target", 0),
        ("launch", 0),
        ("_distance", 0),
        ("_terms", 1),
        ("_flags", 1),
        ("_sink", 0),
    )

    def _build(self) -> None:
        p = self.params
        E = self.num_envs
        self.craft = Craft.load("paper_airplane")
        # a floor the dart lands on: it touches down on its collision box (contact.py)
        world = World(ground=Ground(restitution=0.5, friction=0.5))
        self.sim = Simulator(
            self.craft, world, num_envs=E, dt=p.dt, integrator=p.integrator, dtype=p.dtype
        )
        # points whose touching the ground is touchdown: the collision boxes' corners
        signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
        self._hull = np.concatenate(
            [
                np.asarray(b.center_m) + signs * np.asarray(b.half_extents_m)
                for b in self.craft.shapes
            ]
        )
        self._v_prev = np.zeros((E, 4))  # each dart's velocity and up-ness a step before
        self.target = np.zeros((E, 2))  # target on the ground (x, y), m
        self.launch = np.zeros((E, 2))  # launch point, the arena's center
        self._distance = np.zeros(E)
        self._cfg = np.array([getattr(p, name) for name in TK.CFG_FIELDS], dtype=np.float64)
        self._terms = np.zeros((len(REWARD_TERMS), E))
        self._flags = np.zeros((TK.NFLAGS, E), dtype=bool)
        self._sink = np.zeros(E)
        self.draws_per_episode = len(TK.DRAWS)
        self._spans = np.array(
            [(0.0, 2 * np.pi) if name in TK.ANGLES else getattr(p, name) for name in TK.DRAWS],
            dtype=np.float64,
        )
        self._task = TK.task_parallel if self.sim.parallel else TK.task_serial

    # ---- episode start --------------------------------------------------------------------

    def _draw_reset(self, ids, u) -> None:
        st, flow, diverged, warm = self.sim.start_arrays()
        TK.start(
            ids, u, self._spans, st, flow, diverged, warm, self._v_prev, self.target,
            self.launch, self._distance,
        )  # fmt: skip

    # ---- step -----------------------------------------------------------------------------

    def _advance(self, actions):
        self.sim.step(actions, steps=self.params.substeps)
        diverged = self.sim.diverged.copy()
        st, flow, body = self.sim.kernel_arrays()
        self._task(
            st, body, flow, diverged, self._hull, self.target, self.launch, self._distance,
            actions, self._cfg, self._terms, self._flags, self._sink, self._v_prev,
            self.sim.ground_impulse[:, 0], self._truth,
        )  # fmt: skip
        flags = self._flags.copy()
        info = {
            "distance_m": self._distance.copy(),
            "landed": flags[TK.F_LANDED],
            "crashed": flags[TK.F_CRASHED],
            "out_of_arena": flags[TK.F_OUT],
            "success": flags[TK.F_SUCCESS],
            "touchdown_sink_mps": self._sink.copy(),
        }
        terminated = flags[TK.F_TOUCHDOWN] | flags[TK.F_OUT]
        return terminated, diverged, self._terms.copy(), info

    # ---- observation ----------------------------------------------------------------------

    def _observe(self, out, ids) -> None:
        st, flow, body = self.sim.kernel_arrays()
        TK.observe(ids, self._keep_none, st, body, flow, self.target, out)

    # ---- what viewers read -----------------------------------------------------------------

    def target_xy(self, env_index: int) -> np.ndarray:
        """Sub-env ``env_index``'s target on the ground, (x, y) in m (a copy)."""
        return self.target[env_index].copy()


class PaperAirplaneEnv(FluidEnv):
    """A paper dart thrown from a height must glide to a target on the ground and land on it.

    ## Description

    The dart is the shipped craft ``paper_airplane`` (5 g, 0.016 m^2 of wing, 13 fluid
    samples; see ``fluidsim_envs/craft/paper_airplane.toml``). With zero controls it glides
    trimmed at about 6.7 m/s and 4:1; its ailerons, elevators and rudder are the actions.
    It is thrown from a random height, speed and attitude in a random horizontal wind; a
    target lies on the ground ahead, within gliding reach. Touching the ground ends the
    episode: a landing if right way up and slow enough, else a crash. The ground is solid:
    the dart's airframe (three thin collision boxes) lands on it and stops there (contact.py),
    so the terminal state is the dart on the floor, never more than a few millimetres into it.

    ## Action Space

    ``Box(-1, 1, (3,), float32)``: aileron (+ rolls right), elevator (+ pitches the nose up),
    rudder (+ yaws the nose right), scaled by the craft's deflection limits (20, 20 and 25
    degrees). Values beyond [-1, 1] saturate at the limit; NaN or a wrong shape is an error.

    ## Observation Space

    ``Box(-inf, inf, (15,), float32)``, SI units; the heading frame is the body's heading
    turned level (forward, left, up).

    | Index | Name | Unit | Description |
    |-------|------|------|-------------|
    | 0-2 | u, v, w | m/s | airspeed (velocity relative to the air) in the body frame |
    | 3-5 | p, q, r | rad/s | body rates: p + right wing down, q + nose down, r + nose left |
    | 6-8 | gx, gy, gz | 1 | unit gravity direction in the body frame |
    | 9 | height | m | height of the center of mass above the ground |
    | 10-11 | target_forward, target_left | m | target position in the heading frame |
    | 12-13 | ground_forward, ground_left | m/s | ground velocity in the heading frame |
    | 14 | climb | m/s | vertical velocity (+ up) |

    ## Rewards

    The reward is the sum of named terms, each reported per step in
    ``info["reward_terms"]`` and summed per episode in ``info["episode_terms"]`` at its end:

    - ``progress``: ``w_progress`` x metres the horizontal distance to the target shrank
      this step (sums to the distance closed over the episode);
    - ``accuracy``: on landing, ``w_accuracy * exp(-distance / accuracy_scale_m)``;
    - ``softness``: on landing, ``w_softness * exp(-(sink rate / 1 m/s)^2)``;
    - ``crash``: ``-w_crash`` on a crash, on leaving the arena and on a diverged state;
    - ``effort``: ``-w_effort`` x the mean squared action, every step.

    ## Starting State

    The dart starts above the origin at a height in ``launch_height_m``, heading in a
    uniformly random direction, at a speed in ``launch_speed_mps`` along its nose, pitched by
    ``launch_pitch_deg`` and rolled by ``launch_roll_deg``, without rotation. The target is on
    the ground at a bearing in ``target_bearing_deg`` from the launch heading and a distance of
    ``target_distance_ratio`` times the launch height. The wind is horizontal, uniform and
    steady, its speed in ``wind_speed_mps``, its direction uniformly random.

    ## Episode End

    Terminated: touchdown (the floor pushing on the airframe's collision boxes, or those
    within 2 mm of it;
    ``info["landed"]`` if the body is right way up, sank slower than ``crash_sink_mps`` and
    moved slower than ``crash_speed_mps`` at the step before, else ``info["crashed"]``);
    leaving the arena (``info["out_of_arena"]``: farther than ``arena_radius_m`` from the
    launch point or above ``ceiling_m``); a non-finite physics state
    (``info["physics_diverged"]``; the observation is then the last finite one).
    Truncated: ``max_episode_steps`` actions.
    ``info["success"]`` marks a landing within ``success_radius_m`` of the target.

    ## Arguments

    ``gym.make("fluidsim/PaperAirplane-v0", **kwargs)`` and
    ``gym.make_vec("fluidsim/PaperAirplane-v0", num_envs=N,
    vectorization_mode="vector_entry_point", **kwargs)`` accept ``render_mode``
    (``"rgb_array"``) and every field of :class:`PaperAirplaneParams` (physics ``dt``,
    ``substeps``, ``integrator``, ``dtype``, launch ranges, wind, limits, reward weights); an
    unknown key is an error listing the valid ones.

    ## Version History

    - v0: first version.

    Examples:
        >>> import gymnasium as gym
        >>> import fluidsim_envs
        >>> env = gym.make("fluidsim/PaperAirplane-v0")
        >>> obs, info = env.reset(seed=0)
        >>> obs.shape
        (15,)
        >>> obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    """

    vector_cls = PaperAirplaneVectorEnv


__all__ = ["OBSERVATION", "PaperAirplaneEnv", "PaperAirplaneParams", "PaperAirplaneVectorEnv"]
