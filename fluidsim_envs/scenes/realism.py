"""What a v1 env adds to its scene: difficulty levels, physics randomized per episode, sensors
and actuators. A scene's v1 module declares its knobs' bundles (``Level``), its sample
groups, its instruments (``sensors.Sensor``); :class:`Realism` runs them for one vector env.

**Knobs.** Every v1 parameter class has ``difficulty`` ("easy", "standard" or "hard") and
the fields of :class:`Knobs`, each None by default: a knob left None takes its level's value,
a knob given keeps it (``gym.make(id, difficulty="hard", sensor_scale=0.0)``). The resolved
values are ``params.knobs``. ``easy`` is the v0 task (with the v1 observation), ``standard``
the bundle a pilot is measured on, ``hard`` a craft and instruments a grade worse.

**Randomized physics.** Each episode start draws, from the sub-env's own generator, a mass
factor (inertia follows it: the same shape, heavier), an inertia factor on top, a centre of
mass shift per axis, an area factor and an efficiency factor per sample group the scene
names, a thrust factor, and a fluid density factor (on every sample's area: a fluid force
and a buoyancy are both proportional to density). What was drawn is ``info["randomized"]``
at every reset, and at a step where a sub-env restarted.

**Actuators.** Each control channel follows its command through a first-order lag and a
rate limit (``Simulator.set_actuators``; surfaces in deg/s over their deflection limit,
thrust channels a spool time), integrated at the physics step inside the kernel; the v1
observation has each channel's position after the scene's columns.

**Probes.** With ``observe_samples`` (on by default) the observation ends with what the
craft's fluid samples meet (``probes.py``: angles of attack and dynamic pressures, hull
pressures, flow along the hull), read through the scene's instruments like the rest.
"""

from __future__ import annotations

import dataclasses
import inspect
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from . import noise as NZ
from .limits import Bound, Span, check_params
from .probes import ProbeArray, probe_columns
from .sensors import MAX_LATENCY_STEPS, SensorModel

LEVELS = ("easy", "standard", "hard")


@dataclass(frozen=True)
class Knobs:
    """The knobs of every v1 env, at their v0 values (nothing randomized, perfect
    instruments, instant actuators). Spans are (low, high), drawn uniformly per episode."""

    mass_scale: tuple = (1.0, 1.0)  # times the craft's mass (its inertia follows)
    inertia_scale: tuple = (1.0, 1.0)  # times the inertia, on top
    com_shift_m: float = 0.0  # the centre of mass moves up to this far along each axis
    area_scale: tuple = (1.0, 1.0)  # per sample group: times its samples' areas
    efficiency_scale: tuple = (1.0, 1.0)  # per sample group: times its plates' efficiency
    thrust_scale: tuple = (1.0, 1.0)  # times every thruster's thrust
    density_scale: tuple = (1.0, 1.0)  # times the fluids' densities
    sensor_scale: float = 0.0  # times the instruments' noise and bias (0: exact readings)
    sensor_latency_steps: int = 0  # the pilot sees readings this many actions late
    actuators: bool = False  # control channels lag and are rate limited
    surface_time_constant_s: float = 0.05
    surface_rate_dps: float = 300.0
    thrust_time_constant_s: float = 0.5
    thrust_rate_per_s: float = 2.0  # control units per second (full range in a second)


KNOB_RANGES = {
    "mass_scale": Span(0.25, 4.0),
    "inertia_scale": Span(0.25, 4.0),
    "com_shift_m": Bound(0.0, 1.0),
    "area_scale": Span(0.25, 4.0),
    # a plate's efficiency is the share of its drag removed, at most 1: only less
    "efficiency_scale": Span(0.0, 1.0),
    "thrust_scale": Span(0.0, 4.0),
    "density_scale": Span(0.5, 2.0),
    "sensor_scale": Bound(0.0, 10.0),
    "sensor_latency_steps": Bound(0, MAX_LATENCY_STEPS, integer=True),
    "surface_time_constant_s": Bound(1e-4, 10.0),
    "surface_rate_dps": Bound(1e-3, 1e5),
    "thrust_time_constant_s": Bound(1e-4, 100.0),
    "thrust_rate_per_s": Bound(1e-4, 1e4),
}
KNOB_NAMES = tuple(f.name for f in dataclasses.fields(Knobs))


@dataclass(frozen=True)
class KnobParams:
    """The fields every v1 parameter class adds to its v0 one (inherit from both; the
    knobs' documentation is :class:`Knobs`'): ``difficulty`` and each knob, None for its
    level's value. The class's ``__post_init__`` calls :func:`resolve` first."""

    #: every knob's range, the shared :data:`KNOB_RANGES` with the scene's own over them (its
    #: knobs, and where its craft holds less: ``docs/ranges.csv``); a scene's class sets it
    KNOB_RANGES: ClassVar[dict] = KNOB_RANGES

    difficulty: str = "standard"
    observe_samples: bool = True  # the probes' columns (the plan's) end the observation
    mass_scale: tuple | None = None
    inertia_scale: tuple | None = None
    com_shift_m: float | None = None
    area_scale: tuple | None = None
    efficiency_scale: tuple | None = None
    thrust_scale: tuple | None = None
    density_scale: tuple | None = None
    sensor_scale: float | None = None
    sensor_latency_steps: int | None = None
    actuators: bool | None = None
    surface_time_constant_s: float | None = None
    surface_rate_dps: float | None = None
    thrust_time_constant_s: float | None = None
    thrust_rate_per_s: float | None = None


def resolve(params, own: str, levels: dict, knobs=Knobs, ranges=None, choices=None) -> None:
    """Check ``params.difficulty`` and the knobs the caller gave, and store every knob's
    value (given, else the level's, else the default of ``knobs``: :class:`Knobs` or a
    scene's subclass with its own knobs, whose numbers ``ranges`` bounds and whose words
    ``choices`` lists) as ``params.knobs``."""
    level = params.difficulty
    if not isinstance(level, str) or level not in LEVELS:
        raise ValueError(f"{own}: difficulty must be one of {list(LEVELS)}, got {level!r}")
    names = [f.name for f in dataclasses.fields(knobs)]
    unknown = sorted(set(levels[level]) - set(names))
    if unknown:  # a scene's table names a knob that does not exist: a programming error
        raise ValueError(f"{own}: difficulty {level!r} sets unknown knobs {unknown}")
    values = dict(dataclasses.asdict(knobs()), **levels[level])
    given = {k: getattr(params, k) for k in names if getattr(params, k) is not None}
    if "actuators" in given and not isinstance(given["actuators"], (bool, np.bool_)):
        raise ValueError(f"{own}: actuators must be True or False, got {given['actuators']!r}")
    if not isinstance(params.observe_samples, (bool, np.bool_)):
        raise ValueError(
            f"{own}: observe_samples must be True or False, got {params.observe_samples!r}"
        )
    for key, words in (choices or {}).items():
        if key in given and (not isinstance(given[key], str) or given[key] not in words):
            raise ValueError(f"{own}: {key} must be one of {list(words)}, got {given[key]!r}")
    values.update(given)
    out = knobs(**values)
    check_params(out, own, {**KNOB_RANGES, **(ranges or {})})  # spans stored as float tuples
    object.__setattr__(params, "knobs", out)


# --------------------------------------------------------------------------------------------
# one env's randomization, sensors and actuators


@dataclass(frozen=True)
class Plan:
    """What a scene randomizes and reads: the sample groups of its craft (body 0) drawn
    per episode, its instruments, and its probes of the craft's samples."""

    groups: tuple[str, ...]  # disjoint sample groups of the craft: area and efficiency
    sensors: tuple  # sensors.Sensor
    probes: tuple = ()  # probes.Probe: the columns that end the observation

    def columns(self, control_names) -> tuple[tuple[str, str, str], ...]:
        """The columns v1 adds to the scene's: each actuator's position, then the probes'."""
        return actuator_columns(control_names) + probe_columns(self.probes)


class Realism:
    """Randomized physics, sensors and actuators for one v1 vector env ``env`` (its ``sim``,
    ``params.knobs``, ``num_envs``), on ``plan``; the truth observation has ``names``."""

    # the episode's uniforms, in order: mass, inertia, 3 shifts, per group area then
    # efficiency, thrust, density, the noise key
    def __init__(self, env, plan: Plan, names) -> None:
        k, sim, E = env.params.knobs, env.sim, env.num_envs
        self.knobs, self.sim, self.plan = k, sim, plan
        craft = sim.crafts[0]
        self.mass_kg = craft.mass_kg
        self.thrusters = bool(craft.thrusters)
        G = len(plan.groups)
        self.draws = 5 + 2 * G + 3  # see start: the drawn columns, then the noise key
        # what each sub-env's episode drew, a column each (info["randomized"])
        self.drawn_names = (
            "mass_kg", "inertia_scale", "com_shift_x_m", "com_shift_y_m", "com_shift_z_m",
            *(f"{g}_{what}_scale" for g in plan.groups for what in ("area", "efficiency")),
            "thrust_scale", "density_scale",
        )  # fmt: skip
        lo_hi = np.array(
            [
                k.mass_scale, k.inertia_scale, (-k.com_shift_m, k.com_shift_m),
                (-k.com_shift_m, k.com_shift_m), (-k.com_shift_m, k.com_shift_m),
                *((k.area_scale, k.efficiency_scale) * G), k.thrust_scale, k.density_scale,
            ]
        )  # fmt: skip
        self.low, self.span = lo_hi[:, 0], lo_hi[:, 1] - lo_hi[:, 0]
        self.drawn = np.ones((E, len(self.drawn_names)))
        self.density_column = self.drawn_names.index("density_scale")  # the probes read it
        self.drawn[:, 0] = self.mass_kg
        self.drawn[:, 2:5] = 0.0
        self.randomizes = (
            any(
                _spread(getattr(k, n))
                for n in (
                    "mass_scale",
                    "inertia_scale",
                    "area_scale",
                    "efficiency_scale",
                    "thrust_scale",
                    "density_scale",
                )  # fmt: skip
            )
            or k.com_shift_m > 0.0
        )
        period = env.params.dt * env.params.substeps
        # without the probes' columns, the instruments that read only them are not fitted
        probed = {name for name, _, _ in probe_columns(plan.probes)} - set(names)
        sensors = [s for s in plan.sensors if not set(s.columns) <= probed]
        self.sensors = SensorModel(sensors, names, k.sensor_scale, period,
                                   k.sensor_latency_steps, E)  # fmt: skip
        self.keys = np.zeros(E, dtype=np.uint64)
        # each of plan.groups a group of the craft with plates (else a clear error)
        self.randomizer = sim.randomizer(plan.groups)
        if k.actuators:
            sim.set_actuators(*self.actuator_table(sim))

    def actuator_table(self, sim) -> tuple[np.ndarray, np.ndarray]:
        """Each control channel's time constant (s) and rate limit (control units per s):
        a thruster's channel spools, a surface's moves at ``surface_rate_dps`` over its
        deflection limit."""
        k = self.knobs
        tau, rate = [], []
        for craft in sim.crafts:
            thrust = {t.control for t in craft.thrusters}
            for ctl in craft.controls:
                if ctl.name in thrust:
                    tau.append(k.thrust_time_constant_s)
                    rate.append(k.thrust_rate_per_s)
                else:
                    tau.append(k.surface_time_constant_s)
                    rate.append(k.surface_rate_dps / max(ctl.max_deflection_deg, 1e-9))
        return np.asarray(tau), np.asarray(rate)

    def start(self, ids: np.ndarray, u: np.ndarray) -> None:
        """Draw sub-envs ``ids``' physics for their new episodes from their uniforms ``u``
        [len(ids), draws], before the scene places the craft (a reset's angular momentum
        needs the new inertia)."""
        G = len(self.plan.groups)
        self.keys[ids] = NZ.keys_from_uniforms(u[:, -1])
        if not self.randomizes:
            return
        # the drawn columns, in drawn_names order (the uniforms are in that order)
        x = self.low + u[:, : len(self.low)] * self.span
        G2 = slice(5, 5 + 2 * G)
        self.randomizer.set(
            ids, mass_scale=x[:, 0], inertia_scale=x[:, 1], com_shift_m=x[:, 2:5],
            density=x[:, -1], area=x[:, G2][:, 0::2], efficiency=x[:, G2][:, 1::2],
            thrust=x[:, -2] if self.thrusters else None,
        )  # fmt: skip
        if not self.thrusters:
            x[:, -2] = 1.0
        x[:, 0] *= self.mass_kg
        self.drawn[ids] = x

    def info(self) -> dict:
        """What each sub-env's current episode drew (copies)."""
        return {name: self.drawn[:, j].copy() for j, name in enumerate(self.drawn_names)}


def _spread(lo_hi) -> bool:
    return lo_hi[0] != 1.0 or lo_hi[1] != 1.0


def actuator_columns(control_names) -> tuple[tuple[str, str, str], ...]:
    """The observation columns v1 adds: each control channel's actuator position."""
    return tuple(
        (f"{name}_position", "1", f"where the {name} actuator is, in units of its command")
        for name in control_names
    )


class Version1:
    """A scene's v1 vector env: put it before the scene's v0 class
    (``class SceneV1VectorEnv(Version1, SceneVectorEnv)``) and set ``plan`` (what is
    randomized and read) and ``obs_dim`` (the v0 columns, then ``plan.columns``: with
    ``observe_samples=False`` an instance has fewer). It adds :class:`Realism` around the
    scene's hooks: the episode's physics drawn before the scene places the craft, the
    actuators' positions and the probes' readings after the scene's columns, the sensors
    between the truth and the pilot."""

    plan: Plan
    version = 1

    def _build(self) -> None:
        super()._build()
        names = tuple(self._observation_names())
        if len(names) != type(self).obs_dim:
            raise AssertionError(f"{type(self).__name__}: obs_dim is not its {len(names)} columns")
        n_probe = len(probe_columns(self.plan.probes))
        n_scene = len(names) - n_probe - len(self.sim.control_names)
        self._positions = slice(n_scene, n_scene + len(self.sim.control_names))
        self.probes = None
        if self.params.observe_samples and self.plan.probes:
            self.probes = ProbeArray(self.sim, self.plan.probes)
        else:
            self.obs_dim = len(names) - n_probe  # this instance's observation
            names = names[: self.obs_dim]
        self._probed = slice(self._positions.stop, self.obs_dim)
        self.realism = Realism(self, self.plan, names)
        self.sensors = None if self.realism.sensors.exact else self.realism.sensors
        self.noise_keys = self.realism.keys
        self._scene_draws = self.draws_per_episode
        self.draws_per_episode += self.realism.draws + self.own_draws
        self._drawn = self.realism.drawn  # snapshots: state_fields
        self._sensor_bias = self.realism.sensors.state
        self._sensor_history = self.realism.sensors.history
        self._sensor_head = self.realism.sensors.head

    def _observation_names(self):
        raise NotImplementedError

    def _read_by_instrument(self) -> np.ndarray:
        # every level's: at easy the instruments read exactly, and the space stays one for
        # all levels (a policy flies across them)
        return self.realism.sensors.read_by

    def _draw_reset(self, ids, u) -> None:
        # the episode's uniforms: the scene's start, then realism's, then the v1 scene's own
        s0, s1 = self._scene_draws, self._scene_draws + self.realism.draws
        self.realism.start(ids, u[:, s0:s1])
        self.sim.center_actuators(ids)
        super()._draw_reset(ids, np.ascontiguousarray(u[:, :s0]))
        self._start_own(ids, u[:, s1:])

    # uniforms each episode start draws for the v1 scene's own models (moving air, water)
    own_draws = 0

    def _start_own(self, ids, u) -> None:
        """Start the v1 scene's own models for sub-envs ``ids`` from ``u`` [len(ids),
        own_draws], after the scene placed the craft: nothing here."""

    def _advance(self, actions):
        out = super()._advance(actions)
        self._truth[:, self._positions] = self.sim.actuators
        if self.probes is not None:  # not where the physics diverged: no NaN observation
            ok = ~out[1]
            self._truth[ok, self._probed] = self._probe()[ok]
        return out

    def _observe(self, out, ids) -> None:
        super()._observe(out, ids)
        out[ids, self._positions] = self.sim.actuators[ids]
        if self.probes is not None:
            out[ids, self._probed] = self._probe(ids)

    def _probe(self, ids=None) -> np.ndarray:
        """The probes' columns of sub-envs ``ids`` (None: all), in the episode's fluid
        density."""
        scale = self.realism.drawn[:, self.realism.density_column]
        return self.probes.read(scale if ids is None else scale[ids], ids)

    def _info_after_reset(self) -> dict:
        return {**super()._info_after_reset(), "randomized": self.realism.info()}


V1_STATE = (
    ("_drawn", 0),
    ("noise_keys", 0),
    ("_sensor_bias", 0),
    ("_sensor_history", 0),
    ("_sensor_head", 0),
)


def v1_doc(v0_doc: str, summary: str, columns, replace: dict, append: dict) -> str:
    """A v1 env's docstring from its v0's (one source for what did not change): ``summary``
    first; each section named in ``replace`` rewritten, each in ``append`` extended; the
    observation table extended with ``columns`` ((name, unit, description) after v0's) and
    its size with them."""
    lines = inspect.cleandoc(v0_doc).split("\n")
    heads = [i for i, line in enumerate(lines) if line.startswith("## ")]
    sections = {
        lines[i][3:]: "\n".join(lines[i + 1 : j]).strip("\n")
        for i, j in zip(heads, heads[1:] + [len(lines)], strict=True)
    }
    unknown = sorted((set(replace) | set(append)) - set(sections))
    if unknown:
        raise AssertionError(f"v1_doc: no section {unknown} in v0's docstring")
    table = sections["Observation Space"].split("\n")
    last = max(i for i, line in enumerate(table) if line.startswith("| "))
    n0 = int(table[last].split("|")[1].split("-")[-1]) + 1  # v0's columns
    table[last + 1 : last + 1] = [
        f"| {n0 + k} | {name} | {unit} | {text} |" for k, (name, unit, text) in enumerate(columns)
    ]
    sections["Observation Space"] = "\n".join(table).replace(f"({n0},)", f"({n0 + len(columns)},)")
    for name, text in replace.items():
        sections[name] = inspect.cleandoc(text)
    for name, text in append.items():
        sections[name] += "\n\n" + inspect.cleandoc(text)
    body = "\n\n".join(f"## {name}\n\n{text}" for name, text in sections.items())
    return inspect.cleandoc(summary) + "\n\n" + body + "\n"


__all__ = [
    "v1_doc",
    "KNOB_NAMES",
    "actuator_columns",
    "KNOB_RANGES",
    "LEVELS",
    "Knobs",
    "Plan",
    "Realism",
    "resolve",
]
