"""fluidsim/PaperAirplane-v1: the dart of v0 with a craft that differs from throw to throw,
real instruments and servos, at a difficulty level (``scenes/realism.py``)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import realism as RL
from .. import turbulence as TB
from ..base import FluidEnv
from ..limits import Bound, Span
from ..probes import Probe
from ..realism import (
    V1_STATE,
    KnobParams,
    Knobs,
    Plan,
    Version1,
    resolve,
    v1_doc,
)
from ..sensors import Sensor
from .env import PaperAirplaneEnv, PaperAirplaneParams, PaperAirplaneVectorEnv
from .kernel import OBSERVATION

CONTROLS = ("aileron", "elevator", "rudder")  # the craft's channels (paper_airplane.toml)

# What the dart's plates meet, like an array of flow-angle vanes and pitot tubes: the angle of
# attack and dynamic pressure at each wing, the tail and the fin, and the angle of attack at
# each control surface (its deflection included)
PROBES = (
    Probe("left_wing", ("left_wing",), ("aoa", "q"), "left wing"),
    Probe("right_wing", ("right_wing",), ("aoa", "q"), "right wing"),
    Probe("tail", ("left_stabilizer", "right_stabilizer"), ("aoa", "q"), "tail"),
    Probe("fin", ("fin",), ("aoa", "q"), "fin"),
    *(Probe(s, (s,), ("aoa",), s.replace("_", " "))
      for s in ("left_aileron", "right_aileron", "left_elevator", "right_elevator", "rudder")),
)  # fmt: skip

# The instruments of a small drone of the dart's size class. Noise per reading at the action
# rate (30 Hz), from the datasheets named; columns not listed are exact.
SENSORS = (
    Sensor("airspeed", ("u", "v", "w"), noise=0.1, bias=0.05, bias_time_s=60.0,
           hardware="pitot on a differential-pressure sensor with flow-angle vanes (Sensirion "
                    "SDP3x class: 0.2 Pa zero point; vanes about 1 deg: 0.1 m/s at 6 m/s)"),
    Sensor("gyro", ("p", "q", "r"), noise=0.0012, bias=0.0035, bias_time_s=100.0,
           quantum=1.33e-4,
           hardware="MEMS gyro (InvenSense MPU-6000: 0.005 deg/s/sqrt(Hz) over its 188 Hz "
                    "band, 16 bits over +-250 deg/s; 0.2 deg/s residual bias after "
                    "calibration)"),
    Sensor("attitude", ("gx", "gy", "gz"), noise=0.003, bias=0.01, bias_time_s=20.0,
           hardware="AHRS attitude (VectorNav VN-100 class: pitch and roll 0.5 deg static, "
                    "1 deg dynamic)"),
    Sensor("rangefinder", ("height",), noise=0.02, quantum=0.01,
           hardware="lidar rangefinder (Garmin LIDAR-Lite v3: +-2.5 cm, 1 cm resolution)"),
    Sensor("gnss_position", ("target_forward", "target_left"), noise=0.01, bias=0.02,
           bias_time_s=30.0,
           hardware="RTK GNSS (u-blox ZED-F9P: 0.01 m + 1 ppm CEP horizontal)"),
    Sensor("gnss_velocity", ("ground_forward", "ground_left", "climb"), noise=0.05,
           hardware="GNSS velocity (u-blox ZED-F9P: 0.05 m/s)"),
    Sensor("vanes", tuple(f"{p.name}_aoa" for p in PROBES), noise=0.0175, bias=0.009,
           bias_time_s=60.0,
           hardware="flow-angle vanes on angle encoders (about 1 deg per reading, 0.5 deg "
                    "alignment)"),
    Sensor("pitots", tuple(f"{p.name}_q" for p in PROBES if "q" in p.reads), noise=0.1,
           bias=0.2, bias_time_s=60.0, quantum=1.0 / 60.0,
           hardware="pitot tubes on differential-pressure sensors (Sensirion SDP31: 0.2 Pa "
                    "zero point, 1/60 Pa resolution)"),
)  # fmt: skip
PLAN = Plan(groups=("wings", "tail", "fuselage"), sensors=SENSORS, probes=PROBES)
OBSERVATION_V1 = OBSERVATION + PLAN.columns(CONTROLS)


@dataclass(frozen=True)
class DartKnobs(Knobs):
    """The dart's own knobs beside realism.Knobs': its moving air (scenes/turbulence.py)."""

    turbulence: str = "none"  # Dryden: none, wind (W20: the mean wind), light, moderate, severe
    gust_mps: float = 0.0  # one 1-cosine gust per episode of this peak (0: none)
    gust_duration_s: float = 1.0  # its length in time
    gust_within_s: float = 4.0  # it starts in the first this many seconds


KNOB_RANGES = {
    # where the dart holds (docs/ranges.csv, reliability.md#knob-ranges-that-hold), at every
    # corner of them: its centre of mass within 3 cm (a tenth of its length; hard moves it
    # 6 mm); mass, inertia and areas within a factor 1.5 of its own and the air's density
    # within 1.25 (a light dart of large area in dense air is stiffer than its step)
    "com_shift_m": Bound(0.0, 0.03),
    "mass_scale": Span(0.67, 1.5),
    "inertia_scale": Span(0.67, 1.5),
    "area_scale": Span(0.67, 1.5),
    "density_scale": Span(0.8, 1.25),
    "gust_mps": Bound(0.0, 20.0),
    "gust_duration_s": Bound(0.05, 10.0),
    "gust_within_s": Bound(0.01, 1000.0),
}
CHOICES = {"turbulence": TB.LEVELS}
KNOBS = DartKnobs  # what docs/environments.md's level table lists

# each level's knobs (realism.Knobs and DartKnobs; easy: v0's physics, exact readings)
LEVELS: dict[str, dict] = {
    "easy": {},
    "standard": {
        # paper of 80 to 100 g/m^2, folds a few mm off; air from sea level to 1 km, 0-30 C
        "mass_scale": (0.85, 1.15),
        "inertia_scale": (0.9, 1.1),
        "com_shift_m": 0.003,
        "area_scale": (0.9, 1.1),
        "efficiency_scale": (0.9, 1.0),
        "density_scale": (0.9, 1.05),
        "sensor_scale": 1.0,
        "sensor_latency_steps": 1,
        # a micro servo: 0.08 s per 60 deg (750 deg/s), about 30 ms to settle
        "actuators": True,
        "surface_time_constant_s": 0.03,
        "surface_rate_dps": 600.0,
        # turbulence of the episode's own breeze (MIL-HDBK-1797: sigma_w = 0.1 W20), a gust
        "turbulence": "wind",
        "gust_mps": 0.5,
    },
    "hard": {
        "mass_scale": (0.7, 1.3),
        "inertia_scale": (0.8, 1.2),
        "com_shift_m": 0.006,
        "area_scale": (0.8, 1.2),
        "efficiency_scale": (0.75, 1.0),
        "density_scale": (0.8, 1.1),
        "sensor_scale": 2.0,
        "sensor_latency_steps": 2,
        "actuators": True,
        "surface_time_constant_s": 0.06,
        "surface_rate_dps": 300.0,
        "turbulence": "light",  # W20 = 15 kt: 1.5 m/s along, 0.8 m/s up at 5 m
        "gust_mps": 1.5,
    },
}


@dataclass(frozen=True)
class PaperAirplaneV1Params(PaperAirplaneParams, KnobParams):
    """Parameters of PaperAirplane-v1: v0's, ``difficulty``, ``observe_samples`` and
    the knobs of :class:`~fluidsim_envs.scenes.realism.Knobs` (None: the level's value,
    ``LEVELS``)."""

    NAME: ClassVar[str] = "PaperAirplane-v1"
    KNOB_RANGES: ClassVar[dict] = {**RL.KNOB_RANGES, **KNOB_RANGES}
    turbulence: str | None = None
    gust_mps: float | None = None
    gust_duration_s: float | None = None
    gust_within_s: float | None = None

    def __post_init__(self) -> None:
        resolve(self, self.NAME, LEVELS, DartKnobs, self.KNOB_RANGES, CHOICES)
        super().__post_init__()


class PaperAirplaneV1VectorEnv(Version1, PaperAirplaneVectorEnv):
    """PaperAirplane-v1 for N darts at once; documented on :class:`PaperAirplaneV1Env`."""

    Params = PaperAirplaneV1Params
    observation_layout = OBSERVATION_V1
    obs_dim = len(OBSERVATION_V1)
    plan = PLAN
    state_fields = (
        PaperAirplaneVectorEnv.state_fields
        + V1_STATE
        + (
            ("_mean_wind", 0),
            ("_w20", 0),
            ("_gusts", 0),
            ("_air_state", 0),
        )
    )

    def _observation_names(self):
        return (name for name, _, _ in OBSERVATION_V1)

    own_draws = 3  # the gust's moment and direction

    def _build(self) -> None:
        super()._build()
        E, k = self.num_envs, self.params.knobs
        self.moving_air = k.turbulence != "none" or k.gust_mps > 0.0
        self._mean_wind = np.zeros((E, 3))  # each episode's steady wind (v0's)
        self._w20 = np.zeros(E)  # its turbulence's W20 (m/s)
        self._gusts = np.zeros((E, 6))  # start (s), duration (s), peak (m/s), direction
        self._air_state = np.zeros((E, TB.NSTATE))  # the Dryden filters'
        self._period_s = self.params.dt * self.params.substeps

    def _start_own(self, ids, u) -> None:
        if not self.moving_air:
            return
        k = self.params.knobs
        _, flow, _, _ = self.sim.start_arrays()
        self._mean_wind[ids] = flow[:3, ids].T
        w20 = TB.W20_MPS[k.turbulence]
        self._w20[ids] = np.linalg.norm(self._mean_wind[ids], axis=1) if math.isnan(w20) else w20
        n = len(ids)
        self._gusts[ids, :3] = np.stack(
            [u[:, 0] * k.gust_within_s, np.full(n, k.gust_duration_s), np.full(n, k.gust_mps)],
            axis=1,
        )
        self._gusts[ids, 3:] = _on_sphere(u[:, 1], u[:, 2])
        self._blow(ids, start=True)

    def redraw_future(self, task, rng):
        """A gust that has not begun is drawn again: its moment uniform between now and the
        last it could start at (what an episode that has seen no gust yet knows), its
        direction uniform on the sphere. A gust begun or over is the present and kept."""
        task = super().redraw_future(task, rng)
        if not self.moving_air:
            return task
        gusts = task["_gusts"].copy()
        now = task["_elapsed"] * self._period_s
        ahead = np.flatnonzero(now < gusts[:, 0])
        u = rng.random((ahead.size, 3))
        within = self.params.knobs.gust_within_s
        gusts[ahead, 0] = now[ahead] + u[:, 0] * (within - now[ahead])
        gusts[ahead, 3:] = _on_sphere(u[:, 1], u[:, 2])
        return {**task, "_gusts": gusts}

    def _blow(self, ids, start: bool) -> None:
        """The air of sub-envs ``ids`` over their next step (turbulence.air)."""
        st, flow, _, _ = self.sim.start_arrays()
        kernel = TB.air_parallel if ids.size >= 1024 else TB.air
        kernel(ids, start, self.noise_keys, self._elapsed, st, self._mean_wind, self._w20,
               self._gusts, self._period_s, self._air_state, flow)  # fmt: skip

    def _advance(self, actions):
        if self.moving_air:
            self._blow(self._all, start=False)
        return super()._advance(actions)


def _on_sphere(u1, u2) -> np.ndarray:
    """Unit vectors ``[n, 3]`` uniform on the sphere, from two uniforms each."""
    up = 2.0 * u1 - 1.0
    around = 2.0 * np.pi * u2
    flat = np.sqrt(1.0 - up * up)
    return np.stack([flat * np.cos(around), flat * np.sin(around), up], axis=1)


class PaperAirplaneV1Env(FluidEnv):
    vector_cls = PaperAirplaneV1VectorEnv


PaperAirplaneV1Env.__doc__ = v1_doc(
    PaperAirplaneEnv.__doc__,
    """
    PaperAirplane-v0's task with a real dart: drawn anew at each throw, read through
    real instruments, steered through servos.""",
    OBSERVATION_V1[len(OBSERVATION) :],
    replace={
        "Description": """
    As v0: a paper dart thrown from a height must glide to a target on the ground
    and land on it. Each throw's dart is drawn anew (mass, inertia, centre of mass, the
    wings', tail's and fuselage's areas and efficiencies, the air's density), its
    instruments are noisy, biased and late, its surfaces move through servos, and the air
    moves: Dryden turbulence and a 1-cosine gust on top of v0's steady wind
    (``scenes/turbulence.py``). ``difficulty`` picks a bundle of these knobs.""",
        "Action Space": """
    As v0: ``Box(-1, 1, (3,), float32)``, aileron, elevator, rudder: now the servos'
    commands, which each servo follows with a first-order lag and a rate limit
    (``surface_time_constant_s``, ``surface_rate_dps`` over the surface's deflection limit).""",
        "Arguments": """
    v0's, ``difficulty`` (``"easy"``, ``"standard"`` (default), ``"hard"``),
    ``observe_samples`` (default True: the probes' columns end the observation) and each
    knob of :class:`~fluidsim_envs.scenes.realism.Knobs` alone (given, it overrides its
    level's value; ``params.knobs`` holds them all). Levels (``LEVELS``):

    - ``easy``: v0's dynamics and exact readings (the actuator columns added);
    - ``standard``: mass +-15%, inertia +-10%, centre of mass +-3 mm, areas +-10%,
      efficiencies to -10%, air density -10% to +5%; the instruments of ``SENSORS``, one
      action late; servos of 30 ms and 600 deg/s; turbulence of the episode's own breeze
      (MIL-HDBK-1797's low-altitude Dryden model with W20 the mean wind) and a 0.5 m/s gust;
    - ``hard``: twice the spreads, instruments twice as noisy and two actions late, servos
      of 60 ms and 300 deg/s; light turbulence (W20 = 15 kt) and a 1.5 m/s gust.""",
        "Version History": """
    - v1: randomized dart, sensors, actuators, moving air, difficulty levels, and what its
      plates meet in the observation (``observe_samples``).
    - v0: first version.

    Examples:
        >>> import gymnasium as gym
        >>> import fluidsim_envs
        >>> env = gym.make("fluidsim/PaperAirplane-v1", difficulty="hard")
        >>> obs, info = env.reset(seed=0)
        >>> obs.shape
        (31,)
        >>> float(info["randomized"]["mass_kg"]) > 0.0
        True""",
    },
    append={
        "Observation Space": """
    Columns 0-14 as the instruments read them (``SENSORS`` in
    ``scenes/paper_airplane/v1.py``: airspeed, gyro, attitude, rangefinder, GNSS position and
    velocity; white noise, a wandering bias, resolution, ``sensor_latency_steps`` late);
    the positions are exact. The last 13 columns (``observe_samples=True``, the default;
    without it the observation stops at the positions) are what the dart's plates meet
    (``PROBES``; ``scenes/probes.py``), like flow-angle vanes and pitot tubes on each wing,
    the tail, the fin and each control surface, read through the ``vanes`` and ``pitots``
    instruments.""",
        "Starting State": """
    Before the dart is placed, its physics is drawn from the level's ranges; what
    was drawn is ``info["randomized"]`` at every reset (and at a step where sub-envs restarted,
    masked by ``info["_randomized"]``): the mass (kg), the inertia factor, the centre of
    mass shift (m), each sample group's area and efficiency factors, the thrust and density
    factors. The actuators start centred.""",
        "Episode End": "As v0, judged on the true state, not on the readings.",
    },
)


__all__ = [
    "LEVELS",
    "OBSERVATION_V1",
    "PLAN",
    "SENSORS",
    "PaperAirplaneV1Env",
    "PaperAirplaneV1Params",
    "PaperAirplaneV1VectorEnv",
]
