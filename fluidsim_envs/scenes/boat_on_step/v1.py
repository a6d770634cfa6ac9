"""fluidsim/BoatOnStep-v1: the course of v0 with a boat whose load, hull and engine differ from
run to run, real instruments, hydraulic steering and trim tabs and an engine that spools, at
a difficulty level (``scenes/realism.py``)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ...craft.hull import HULLS
from ...physics import World
from ...physics.surface import MAX_STEEPNESS, irregular_sea
from .. import realism as RL
from ..base import FluidEnv
from ..limits import WEIGHT, Bound, Span
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
from . import kernel as TK
from .env import BoatOnStepEnv, BoatOnStepParams, BoatOnStepVectorEnv
from .kernel import OBSERVATION, REWARD_TERMS

CONTROLS = ("throttle", "rudder", "trim_tabs")  # the craft's channels (speedboat.toml)

# A hull pressure-tap array: at each of the hull's stations (from the transom), the wetted
# fraction and the mean pressure of its bottom plates (the hull that speedboat.toml is
# generated from: craft/hull.py names them bottom_{station}_{side}_{strip})
HULL = HULLS["speedboat"]
PROBES = tuple(
    Probe(f"station_{k}", tuple(f"bottom_{k}_{side}_{j}" for side in ("port", "starboard")
                                for j in range(HULL.strips)),
          ("wetted", "pressure"), f"hull station {k} from the transom")
    for k in range(HULL.stations)
)  # fmt: skip

# The instruments of a small sport boat with a navigation and motion package. Noise per
# reading at the action rate (20 Hz), from the datasheets named; the task's own columns
# (target speed, the trim oscillation and ride estimates) are exact.
SENSORS = (
    Sensor("gnss_velocity", ("u", "v", "w", "speed_error"), noise=0.05,
           hardware="GNSS velocity (u-blox ZED-F9P: 0.05 m/s)"),
    Sensor("gyro", ("p", "q", "r"), noise=0.0012, bias=0.0035, bias_time_s=100.0,
           quantum=1.33e-4,
           hardware="MEMS gyro (InvenSense MPU-6000: 0.005 deg/s/sqrt(Hz) over its 188 Hz "
                    "band, 16 bits over +-250 deg/s; 0.2 deg/s residual bias)"),
    Sensor("attitude", ("trim", "heel"), noise=0.003, bias=0.009, bias_time_s=20.0,
           hardware="motion reference unit (Kongsberg MRU class: roll and pitch 0.5 deg "
                    "dynamic for a low-cost unit)"),
    Sensor("heave", ("heave",), noise=0.02, bias=0.03, bias_time_s=10.0,
           hardware="MRU heave (Kongsberg MRU 5: 5 cm or 5%)"),
    Sensor("gnss_position", ("gate_x", "gate_y"), noise=0.01, bias=0.02, bias_time_s=30.0,
           hardware="RTK GNSS (u-blox ZED-F9P: 0.01 m + 1 ppm CEP horizontal)"),
    Sensor("gnss_heading",
           ("gate_bearing_sin", "gate_bearing_cos", "gate_heading_sin", "gate_heading_cos"),
           noise=0.004, bias=0.005, bias_time_s=60.0,
           hardware="dual-antenna GNSS heading (u-blox ZED-F9P moving base: about 0.4 deg "
                    "on a 1 m baseline)"),
    Sensor("hull_taps", tuple(f"{p.name}_pressure" for p in PROBES), noise=0.2, bias=0.35,
           bias_time_s=60.0,
           hardware="flush piezoresistive hull pressure transducers (0-350 kPa at 0.1% of "
                    "full scale: Kulite XTL-190 class)"),
    Sensor("wetness", tuple(f"{p.name}_wetted" for p in PROBES), noise=0.02,
           hardware="conductivity wetness taps, one per bottom plate, averaged per station"),
)  # fmt: skip


@dataclass(frozen=True)
class BoatKnobs(Knobs):
    """The boat's own knobs beside realism.Knobs': its moving air and water."""

    wind_mps: float = 0.0  # a steady wind on the topsides, drawn up to this per episode
    sea_hs_m: float = 0.0  # an irregular sea (JONSWAP) of this significant height (0: v0's)
    sea_tp_s: float = 3.0  # its peak period
    sea_gamma: float = 3.3  # its peak enhancement (1: Pierson-Moskowitz)


KNOB_RANGES = {
    "wind_mps": Bound(0.0, 30.0),
    # where the boat holds (docs/ranges.csv, reliability.md#knob-ranges-that-hold), at every
    # corner of them: its centre of mass within 50 cm (hard: 20 cm); its mass, inertia,
    # areas, the water's density and its thrust within a factor 1.5 (a light hull with large
    # planing areas at full power porpoises into a runaway)
    "com_shift_m": Bound(0.0, 0.5),
    "mass_scale": Span(0.67, 1.5),
    "inertia_scale": Span(0.67, 1.5),
    "area_scale": Span(0.67, 1.5),
    "density_scale": Span(0.67, 1.5),
    "thrust_scale": Span(0.0, 1.5),
    # each end a sea linear wave theory holds with the other at hard's (hs 0.4 m, tp 3 s):
    # steeper seas are refused, naming both knobs (_check_sea)
    "sea_hs_m": Bound(0.0, 1.2),
    "sea_tp_s": Bound(1.7, 20.0),
    "sea_gamma": Bound(1.0, 10.0),
}
KNOBS = BoatKnobs  # what docs/environments.md's level table lists
PLAN = Plan(groups=("bottom", "friction", "topsides"), sensors=SENSORS, probes=PROBES)
# v1 judges the ride (kernel.score), so its running estimate is observed beside v0's columns
RIDE_COLUMN = (
    ("bow_acceleration_rms", "m/s^2",
     "the stem's vertical acceleration, root mean square over ride_window_s (running)"),
)  # fmt: skip
O_RIDE = len(OBSERVATION)
OBSERVATION_V1 = OBSERVATION + RIDE_COLUMN + PLAN.columns(CONTROLS)

LEVELS: dict[str, dict] = {
    "easy": {},
    "standard": {
        # one to three people and the fuel between empty and full; fouling; an engine off
        # its best; fresh to salt water
        "mass_scale": (0.85, 1.2),
        "inertia_scale": (0.9, 1.1),
        "com_shift_m": 0.1,
        "area_scale": (0.95, 1.05),
        "efficiency_scale": (0.9, 1.0),
        "thrust_scale": (0.85, 1.05),
        "density_scale": (0.975, 1.0),
        "sensor_scale": 1.0,
        "sensor_latency_steps": 1,
        # hydraulic steering and trim tabs; the engine's torque builds over about a second
        "actuators": True,
        "surface_time_constant_s": 0.2,
        "surface_rate_dps": 40.0,
        "thrust_time_constant_s": 1.0,
        "thrust_rate_per_s": 1.0,
        # a fresh breeze and a light chop that moves the water (orbital velocities)
        "wind_mps": 5.0,
        "sea_hs_m": 0.2,
        "sea_tp_s": 2.5,
    },
    "hard": {
        "mass_scale": (0.75, 1.35),
        "inertia_scale": (0.8, 1.2),
        "com_shift_m": 0.2,
        "area_scale": (0.9, 1.1),
        "efficiency_scale": (0.8, 1.0),
        "thrust_scale": (0.7, 1.05),
        "density_scale": (0.975, 1.0),
        "sensor_scale": 2.0,
        "sensor_latency_steps": 2,
        "actuators": True,
        "surface_time_constant_s": 0.3,
        "surface_rate_dps": 25.0,
        "thrust_time_constant_s": 1.5,
        "thrust_rate_per_s": 0.7,
        "wind_mps": 10.0,
        "sea_hs_m": 0.4,
        "sea_tp_s": 3.0,
    },
}


@dataclass(frozen=True)
class BoatOnStepV1Params(BoatOnStepParams, KnobParams):
    """Parameters of BoatOnStep-v1: v0's, ``difficulty``, ``observe_samples`` and
    the knobs of :class:`~fluidsim_envs.scenes.realism.Knobs` (None: the level's value,
    ``LEVELS``)."""

    NAME: ClassVar[str] = "BoatOnStep-v1"
    KNOB_RANGES: ClassVar[dict] = {**RL.KNOB_RANGES, **KNOB_RANGES}
    RANGES: ClassVar[dict] = {
        **BoatOnStepParams.RANGES,
        "ride_limit_g": Bound(1e-3, 10.0),
        "ride_window_s": Bound(0.05, 60.0),
        "w_ride": WEIGHT,
    }
    # the ride, judged as a seakeeping criterion judges a craft in a seaway: the root mean
    # square vertical acceleration at the bow against NORDFORSK's limit for craft under 100 m
    # at the forward perpendicular (NORDFORSK 1987, "Assessment of ship performance in a
    # seaway": 0.275 g). It replaces v0's porpoising term (w_porpoise 0, still reported in
    # info): the trim's oscillation counts the sea's pitching as the helm's, a rough ride is
    # what the helm can ease (by speed and trim), and a porpoising hull rides roughly too.
    ride_limit_g: float = 0.275
    ride_window_s: float = 2.0  # averaging time of the estimate (a few wave encounters)
    w_ride: float = 0.01  # per step, times the rms acceleration over the limit, minus 1
    w_porpoise: float = 0.0
    wind_mps: float | None = None
    sea_hs_m: float | None = None
    sea_tp_s: float | None = None
    sea_gamma: float | None = None

    def __post_init__(self) -> None:
        resolve(self, self.NAME, LEVELS, BoatKnobs, self.KNOB_RANGES)
        super().__post_init__()
        if self.knobs.sea_hs_m > 0.0 and self.swell:
            raise ValueError(
                f"{self.NAME}: give swell or sea_hs_m, not both (swell={self.swell!r}, "
                f"sea_hs_m={self.knobs.sea_hs_m!r})"
            )


class BoatOnStepV1VectorEnv(Version1, BoatOnStepVectorEnv):
    """BoatOnStep-v1 for N boats at once; documented on :class:`BoatOnStepV1Env`."""

    Params = BoatOnStepV1Params
    reward_terms = REWARD_TERMS
    observation_layout = OBSERVATION_V1
    obs_dim = len(OBSERVATION_V1)
    plan = PLAN
    state_fields = BoatOnStepVectorEnv.state_fields + V1_STATE

    def _observation_names(self):
        return (name for name, _, _ in OBSERVATION_V1)

    def _world(self) -> World:
        """v0's water, with an irregular sea where ``sea_hs_m`` is set, and the water moving
        with every wave (orbital velocities: the boat rides the swell, not only its shape)."""
        k = self.params.knobs
        swell = self.params.swell
        if k.sea_hs_m > 0.0:  # the components straddle the peak: a fixed sea, a random moment
            _check_sea(k.sea_hs_m, k.sea_tp_s, k.sea_gamma)
            swell = irregular_sea(k.sea_hs_m, k.sea_tp_s, k.sea_gamma, spread_deg=30.0)
        return World(water=True, swell=swell, wave_orbital_velocity=True)

    def _advance(self, actions):
        out = super()._advance(actions)
        self._truth[:, O_RIDE] = np.sqrt(self.task[TK.K_RIDE_VAR])
        return out

    def _observe(self, out, ids) -> None:
        super()._observe(out, ids)
        out[ids, O_RIDE] = np.sqrt(self.task[TK.K_RIDE_VAR, ids])

    own_draws = 2  # the wind's speed and direction

    def _start_own(self, ids, u) -> None:
        speed = self.params.knobs.wind_mps * u[:, 0]
        if not speed.any():
            return
        way = 2.0 * np.pi * u[:, 1]
        wind = np.stack([speed * np.cos(way), speed * np.sin(way), 0.0 * speed], axis=1)
        self.sim.set_wind(wind, env_ids=ids)


class BoatOnStepV1Env(FluidEnv):
    vector_cls = BoatOnStepV1VectorEnv


BoatOnStepV1Env.__doc__ = v1_doc(
    BoatOnStepEnv.__doc__,
    """
    BoatOnStep-v0's task with a real boat: its load, hull and engine drawn anew each run,
    read through real instruments, steered through hydraulics, driven by an engine that
    spools.""",
    OBSERVATION_V1[len(OBSERVATION) :],
    replace={
        "Rewards": """
    v0's terms, with the hull's motion judged differently: ``porpoise`` weighs nothing
    (``w_porpoise`` 0; ``info["porpoising"]`` still flags it) and a ``ride`` term takes its
    place, a seakeeping criterion: ``-w_ride * (rms / limit - 1)`` every step the stem's
    vertical acceleration, root mean square over ``ride_window_s`` (2 s; observed as
    ``bow_acceleration_rms``), passes ``ride_limit_g`` (0.275 g: NORDFORSK 1987, at the
    bow of craft under 100 m). v0's trim oscillation reads the sea's own pitching as
    porpoising and is measured only at planing speed, so in moving water it paid more for
    crawling the course below planing speed than for running it
    (``python -m benchmarks.reward_terms``, docs/environments.md). The ride charges the
    sea's motion too (at standard the stem passes the limit at any planing speed), but it
    grows with speed at every speed, so it is a trade the helm makes, and a porpoising hull
    in calm water fails it as well (tests/scenes/test_boat_ride.py). The other terms are
    v0's:

    - ``speed``: ``w_speed * exp(-|speed error| / speed_scale_mps)`` every step;
    - ``progress``: ``w_progress`` per meter closed on the next gate's center;
    - ``gate``: ``+w_gate`` for a gate passed bow first between its buoys, ``-w_gate`` for
      one missed (outside its buoys, or run stern first);
    - ``buoy``: ``-w_buoy`` every step the hull touches a buoy;
    - ``fuel``: ``-w_fuel`` x the throttle ahead, every step;
    - ``crash``: ``-w_crash`` on capsizing, stuffing the bow, leaving the course, or a
      diverged state.""",
        "Description": """
    As v0: get the speedboat up on step and run the course of gates. Each run's boat
    is drawn anew (load: mass, inertia, centre of gravity; the bottom's, friction strips'
    and topsides' areas and efficiencies; the engine's thrust; the water's density), its
    instruments are noisy, biased and late, its rudder and trim tabs move hydraulically
    and its engine spools; the wind blows on its topsides and, in v1, the water moves with
    the waves (linear orbital velocities at every sample) in an irregular JONSWAP sea
    (``sea_hs_m``, ``sea_tp_s``). ``difficulty`` picks a bundle of these knobs.""",
        "Action Space": """
    As v0: ``Box(-1, 1, (3,), float32)``, throttle, rudder, trim tabs: now commands
    that the actuators follow with a first-order lag and a rate limit
    (``surface_time_constant_s``, ``surface_rate_dps``; the throttle:
    ``thrust_time_constant_s``, ``thrust_rate_per_s``).""",
        "Arguments": """
    v0's, the ride's (``ride_limit_g``, ``ride_window_s``, ``w_ride``; ``w_porpoise``
    defaults to 0), ``difficulty`` (``"easy"``, ``"standard"`` (default), ``"hard"``),
    ``observe_samples`` (default True: the probes' columns end the observation) and each
    knob of :class:`~fluidsim_envs.scenes.realism.Knobs` alone (given, it overrides its
    level's value; ``params.knobs`` holds them all). Levels (``LEVELS``):

    - ``easy``: v0's dynamics and exact readings (the actuator columns added);
    - ``standard``: mass -15% to +20%, centre of gravity +-10 cm, thrust -15% to +5%, fresh
      to salt water; the instruments of ``SENSORS``, one action late; steering and tabs at
      0.2 s and 40 deg/s, the engine at 1 s; a wind of up to 5 m/s and a 0.2 m sea of 2.5 s;
    - ``hard``: wider spreads, instruments twice as noisy and two actions late, slower
      steering (25 deg/s) and engine (1.5 s), a wind of up to 10 m/s and a 0.4 m sea of 3 s.""",
        "Version History": """
    - v1: randomized boat, sensors, actuators, wind, an irregular sea whose water moves,
      difficulty levels, a hull pressure-tap array in the observation
      (``observe_samples``), and the ride (a seakeeping criterion at the bow) in place of
      the porpoising term.
    - v0: first version.

    Examples:
        >>> import gymnasium as gym
        >>> import fluidsim_envs
        >>> env = gym.make("fluidsim/BoatOnStep-v1", difficulty="hard")
        >>> obs, info = env.reset(seed=0)
        >>> obs.shape
        (38,)
        >>> float(info["randomized"]["mass_kg"]) > 0.0
        True""",
    },
    append={
        "Observation Space": """
    The task's columns as the instruments read them (``SENSORS`` in
    ``scenes/boat_on_step/v1.py``: GNSS velocity, position and heading, gyro, motion
    reference unit; ``target_speed``, ``pitch_oscillation`` and ``bow_acceleration_rms``,
    the task's own, exact), ``sensor_latency_steps`` late; the positions are exact. The
    last 16 columns (``observe_samples=True``, the default; without it the observation
    stops at the positions) are a hull pressure-tap array (``PROBES``;
    ``scenes/probes.py``): at each of the 8 stations from the transom the wetted fraction
    and the mean gauge pressure of its four bottom plates, read through the ``wetness``
    and ``hull_taps`` instruments.""",
        "Starting State": """
    Before the boat is placed, its physics is drawn from the level's ranges; what
    was drawn is ``info["randomized"]`` at every reset (and at a step where sub-envs restarted,
    masked by ``info["_randomized"]``): the mass (kg), the inertia factor, the centre of
    mass shift (m), each sample group's area and efficiency factors, the thrust and density
    factors. The actuators start centred.""",
        "Episode End": "As v0, judged on the true state, not on the readings.",
    },
)


__all__ = ["LEVELS", "OBSERVATION_V1", "PLAN", "SENSORS", "BoatOnStepV1Env",
           "BoatOnStepV1Params", "BoatOnStepV1VectorEnv"]  # fmt: skip


def _check_sea(hs_m: float, tp_s: float, gamma: float) -> None:
    """A ValueError naming the knobs where ``sea_hs_m`` and ``sea_tp_s`` make a sea whose
    steepest component is past what linear wave theory holds (``surface.MAX_STEEPNESS``),
    with the largest height and the shortest period that would do."""
    # a component's steepness 2 pi a / wavelength grows with the height and falls with the
    # period squared (deep water): measured on a low sea of the same shape, then scaled
    low = irregular_sea(1e-3, tp_s, gamma, spread_deg=30.0)
    steepness = max(w.steepness for w in low) * hs_m / 1e-3
    if steepness <= MAX_STEEPNESS:
        return
    raise ValueError(
        f"sea_hs_m={hs_m:g} with sea_tp_s={tp_s:g} (sea_gamma={gamma:g}) makes waves of "
        f"steepness {steepness:.3g}, past the {MAX_STEEPNESS:g} that linear wave theory "
        f"holds: a sea of that height needs sea_tp_s >= "
        f"{tp_s * math.sqrt(steepness / MAX_STEEPNESS):.3g} s, or at that period "
        f"sea_hs_m <= {hs_m * MAX_STEEPNESS / steepness:.3g} m"
    )
