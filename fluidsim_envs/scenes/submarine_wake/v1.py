"""fluidsim/SubmarineWake-v1: the station keeping of v0 with a UUV whose trim, hull and
thruster differ from dive to dive, real navigation instruments, fin servos and a thruster
that spools, at a difficulty level (``scenes/realism.py``)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import currents as CU
from .. import realism as RL
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
from .env import SubmarineWakeEnv, SubmarineWakeParams, SubmarineWakeVectorEnv
from .kernel import OBSERVATION

CONTROLS = ("thrust", "rudder", "dive_planes")  # the craft's channels (uuv.toml)

# A lateral line: the flow along the hull where each hull sample feels it (the lead's wake
# included), and the angle of attack at each fin and dive plane
PROBES = (
    *(Probe(s, (s,), ("flow_x", "flow_y", "flow_z"), s.replace("_", " "))
      for s in ("nose", "hull_fore", "hull_aft")),
    *(Probe(s, (s,), ("aoa",), s.replace("_", " "))
      for s in ("upper_fin", "lower_fin", "port_plane", "starboard_plane")),
)  # fmt: skip

# The navigation package of a small survey UUV. Noise per reading at the action rate
# (10 Hz), from the datasheets named.
SENSORS = (
    Sensor("dvl", ("u", "v", "w"), noise=0.01, bias=0.003, bias_time_s=300.0,
           hardware="Doppler velocity log (Teledyne RDI Pathfinder: +-0.4% +-0.2 cm/s)"),
    Sensor("gyro", ("p", "q", "r"), noise=0.0012, bias=0.0035, bias_time_s=100.0,
           quantum=1.33e-4,
           hardware="MEMS gyro (InvenSense MPU-6000: 0.005 deg/s/sqrt(Hz) over its 188 Hz "
                    "band, 16 bits over +-250 deg/s; 0.2 deg/s residual bias)"),
    Sensor("attitude", ("gx", "gy", "gz"), noise=0.002, bias=0.005, bias_time_s=30.0,
           hardware="AHRS attitude (VectorNav VN-100 class: pitch and roll 0.5 deg)"),
    Sensor("depth", ("depth",), noise=0.005, quantum=0.001,
           hardware="pressure depth sensor (Keller PA-33X: 0.01% of a 100 m span, 1 cm)"),
    Sensor("altimeter", ("altitude",), noise=0.02, quantum=0.01,
           hardware="DVL bottom range (about 1-2% of a few metres)"),
    Sensor("usbl", ("station_x", "station_y", "station_z"), noise=0.05, bias=0.05,
           bias_time_s=60.0,
           hardware="USBL acoustic positioning (Sonardyne Micro-Ranger 2 class: 0.5-1% of "
                    "slant range, 5 cm at 5-10 m)"),
    Sensor("usbl_rate", ("station_vx", "station_vy", "station_vz"), noise=0.05,
           hardware="USBL fixes differenced (the position noise over the fix interval)"),
    Sensor("flow", ("flow_x", "flow_y", "flow_z"), noise=0.01, bias=0.005, bias_time_s=300.0,
           hardware="acoustic Doppler velocimeter (Nortek Vector: +-0.5% +-1 mm/s)"),
    Sensor("heading", ("heading_sin", "heading_cos"), noise=0.005, bias=0.01,
           bias_time_s=60.0,
           hardware="AHRS heading against the lead's acoustic bearing (about 1 deg)"),
    Sensor("lateral_line", tuple(f"{p.name}_{r}" for p in PROBES[:3] for r in p.reads),
           noise=0.005, bias=0.005, bias_time_s=300.0,
           hardware="electromagnetic flow sensors on the hull (Valeport Model 802 class: "
                    "+-0.5% of reading +-5 mm/s)"),
    Sensor("plane_vanes", tuple(f"{p.name}_aoa" for p in PROBES[3:]), noise=0.0175,
           bias=0.009, bias_time_s=60.0,
           hardware="flow-angle vanes on angle encoders (about 1 deg per reading, 0.5 deg "
                    "alignment)"),
)  # fmt: skip


@dataclass(frozen=True)
class SubKnobs(Knobs):
    """The UUV's own knobs beside realism.Knobs': its moving water (scenes/currents.py)."""

    current_mps: float = 0.0  # the steady current's speed, drawn up to this per episode
    current_variation_mps: float = 0.0  # its slow wander, each horizontal component
    current_time_s: float = 120.0  # the wander's correlation time


KNOB_RANGES = {
    # where the UUV holds (docs/ranges.csv, reliability.md#knob-ranges-that-hold), at every
    # corner of them: its centre of mass within 10 cm (hard: 2 cm); its mass and the water's
    # density within a factor 1.25 (a UUV trimmed near neutral: a light one in dense water
    # is buoyant enough to leap), its inertia from 0.8 to 2, its areas from half to 1.5
    # times, its thrust up to twice
    "com_shift_m": Bound(0.0, 0.1),
    "mass_scale": Span(0.8, 1.25),
    "density_scale": Span(0.8, 1.25),
    "inertia_scale": Span(0.8, 2.0),
    "area_scale": Span(0.5, 1.5),
    "thrust_scale": Span(0.0, 2.0),
    "current_mps": Bound(0.0, 3.0),
    "current_variation_mps": Bound(0.0, 2.0),
    "current_time_s": Bound(1.0, 1e5),
}
KNOBS = SubKnobs  # what docs/environments.md's level table lists
PLAN = Plan(groups=("control_surfaces",), sensors=SENSORS, probes=PROBES)
OBSERVATION_V1 = OBSERVATION + PLAN.columns(CONTROLS)

LEVELS: dict[str, dict] = {
    "easy": {},
    "standard": {
        # ballast trimmed to within a percent; fins and hull fouled; sea water 1010-1030
        "mass_scale": (0.99, 1.01),
        "inertia_scale": (0.9, 1.1),
        "com_shift_m": 0.01,
        "area_scale": (0.9, 1.1),
        "efficiency_scale": (0.9, 1.0),
        "thrust_scale": (0.85, 1.05),
        "density_scale": (0.99, 1.01),
        "sensor_scale": 1.0,
        "sensor_latency_steps": 1,
        # fin servos and a thruster of a small UUV
        "actuators": True,
        "surface_time_constant_s": 0.1,
        "surface_rate_dps": 60.0,
        "thrust_time_constant_s": 0.3,
        "thrust_rate_per_s": 2.0,
        # a coastal current: up to 0.3 m/s, wandering 0.1 m/s over minutes
        "current_mps": 0.3,
        "current_variation_mps": 0.1,
    },
    "hard": {
        "mass_scale": (0.98, 1.02),
        "inertia_scale": (0.8, 1.2),
        "com_shift_m": 0.02,
        "area_scale": (0.8, 1.2),
        "efficiency_scale": (0.8, 1.0),
        "thrust_scale": (0.7, 1.05),
        "density_scale": (0.98, 1.02),
        "sensor_scale": 2.0,
        "sensor_latency_steps": 2,
        "actuators": True,
        "surface_time_constant_s": 0.2,
        "surface_rate_dps": 30.0,
        "thrust_time_constant_s": 0.6,
        "thrust_rate_per_s": 1.0,
        "current_mps": 0.6,  # a tidal stream
        "current_variation_mps": 0.2,
        "current_time_s": 60.0,
    },
}


@dataclass(frozen=True)
class SubmarineWakeV1Params(SubmarineWakeParams, KnobParams):
    """Parameters of SubmarineWake-v1: v0's, ``difficulty``, ``observe_samples`` and
    the knobs of :class:`~fluidsim_envs.scenes.realism.Knobs` (None: the level's value,
    ``LEVELS``)."""

    NAME: ClassVar[str] = "SubmarineWake-v1"
    KNOB_RANGES: ClassVar[dict] = {**RL.KNOB_RANGES, **KNOB_RANGES}
    current_mps: float | None = None
    current_variation_mps: float | None = None
    current_time_s: float | None = None

    def __post_init__(self) -> None:
        resolve(self, self.NAME, LEVELS, SubKnobs, self.KNOB_RANGES)
        super().__post_init__()


class SubmarineWakeV1VectorEnv(Version1, SubmarineWakeVectorEnv):
    """SubmarineWake-v1 for N vehicles at once; documented on :class:`SubmarineWakeV1Env`."""

    Params = SubmarineWakeV1Params
    observation_layout = OBSERVATION_V1
    obs_dim = len(OBSERVATION_V1)
    plan = PLAN
    state_fields = (
        SubmarineWakeVectorEnv.state_fields
        + V1_STATE
        + (
            ("_current_mean", 0),
            ("_current_wander", 0),
        )
    )

    def _observation_names(self):
        return (name for name, _, _ in OBSERVATION_V1)

    own_draws = 2  # the current's speed and direction

    def _build(self) -> None:
        super()._build()
        k = self.params.knobs
        self.moving_water = k.current_mps > 0.0 or k.current_variation_mps > 0.0
        self._current_mean = np.zeros((self.num_envs, 3))
        self._current_wander = np.zeros((self.num_envs, 2))

    def _start_own(self, ids, u) -> None:
        if not self.moving_water:
            return
        speed = self.params.knobs.current_mps * u[:, 0]
        way = 2.0 * np.pi * u[:, 1]
        self._current_mean[ids, 0] = speed * np.cos(way)
        self._current_mean[ids, 1] = speed * np.sin(way)
        self._flow(ids, start=True)

    def _flow(self, ids, start: bool) -> None:
        k, p = self.params.knobs, self.params
        _, flow, _, _ = self.sim.start_arrays()
        CU.current(ids, start, self.noise_keys, self._elapsed, self._current_mean,
                   self._current_wander, k.current_variation_mps, k.current_time_s,
                   p.dt * p.substeps, flow)  # fmt: skip

    def _advance(self, actions):
        if self.moving_water:
            self._flow(self._all, start=False)
        return super()._advance(actions)


class SubmarineWakeV1Env(FluidEnv):
    vector_cls = SubmarineWakeV1VectorEnv


SubmarineWakeV1Env.__doc__ = v1_doc(
    SubmarineWakeEnv.__doc__,
    """
    SubmarineWake-v0's task with a real vehicle: its trim, fins and thruster drawn anew
    each dive, navigated by real instruments, steered through fin servos.""",
    OBSERVATION_V1[len(OBSERVATION) :],
    replace={
        "Description": """
    As v0: hold the UUV on its station behind the submarine, in its wake. Each
    dive's vehicle is drawn anew (ballast: mass and centre of gravity; inertia; its control
    surfaces' areas and efficiencies; its thruster; the water's density, on buoyancy and
    forces alike), its navigation instruments are noisy, biased and late, its fins move
    through servos and its thruster spools, and the water moves: an ocean current, steady
    plus a slow wander (``scenes/currents.py``). ``difficulty`` picks a bundle of these
    knobs.""",
        "Action Space": """
    As v0: ``Box(-1, 1, (3,), float32)``, thrust, rudder, dive planes: now commands that
    the actuators follow with a first-order lag and a rate limit.""",
        "Arguments": """
    v0's, ``difficulty`` (``"easy"``, ``"standard"`` (default), ``"hard"``),
    ``observe_samples`` (default True: the probes' columns end the observation) and each
    knob of :class:`~fluidsim_envs.scenes.realism.Knobs` alone (given, it overrides its
    level's value; ``params.knobs`` holds them all). Levels (``LEVELS``):

    - ``easy``: v0's dynamics and exact readings (the actuator columns added);
    - ``standard``: mass and water density +-1% (trim off by up to 2% of the weight),
      inertia and fin areas +-10%, thrust -15% to +5%; the instruments of ``SENSORS``, one
      action late; fins at 0.1 s and 60 deg/s, the thruster at 0.3 s; a current of up to
      0.3 m/s wandering by 0.1 m/s over two minutes;
    - ``hard``: twice the spreads, instruments twice as noisy and two actions late, fins at
      30 deg/s, the thruster at 0.6 s; a tidal stream of up to 0.6 m/s wandering by 0.2 m/s.""",
        "Version History": """
    - v1: randomized vehicle, sensors, actuators, an ocean current, difficulty levels, and
      a lateral line in the observation (``observe_samples``); the lead changes speed and
      turn rate from one route segment to the next, as in v0.
    - v0: first version.

    Examples:
        >>> import gymnasium as gym
        >>> import fluidsim_envs
        >>> env = gym.make("fluidsim/SubmarineWake-v1", difficulty="hard")
        >>> obs, info = env.reset(seed=0)
        >>> obs.shape
        (38,)
        >>> float(info["randomized"]["mass_kg"]) > 0.0
        True""",
    },
    append={
        "Observation Space": """
    The task's columns as the instruments read them (``SENSORS`` in
    ``scenes/submarine_wake/v1.py``: DVL, gyro, AHRS, depth, altimeter, USBL, flow
    sensor), ``sensor_latency_steps`` late; the positions are exact. The last 13 columns
    (``observe_samples=True``, the default; without it the observation stops at the
    positions) are a lateral line (``PROBES``; ``scenes/probes.py``): the flow along the
    body's axes where the nose and the two hull cylinders meet it (the lead's wake and the
    current included), and the angle of attack at each fin and dive plane, read through
    the ``lateral_line`` and ``plane_vanes`` instruments.""",
        "Starting State": """
    Before the vehicle is placed, its physics is drawn from the level's ranges; what
    was drawn is ``info["randomized"]`` at every reset (and at a step where sub-envs restarted,
    masked by ``info["_randomized"]``): the mass (kg), the inertia factor, the centre of
    mass shift (m), each sample group's area and efficiency factors, the thrust and density
    factors. The actuators start centred.""",
        "Episode End": "As v0, judged on the true state, not on the readings.",
    },
)


__all__ = ["LEVELS", "OBSERVATION_V1", "PLAN", "SENSORS", "SubmarineWakeV1Env",
           "SubmarineWakeV1Params", "SubmarineWakeV1VectorEnv"]  # fmt: skip
