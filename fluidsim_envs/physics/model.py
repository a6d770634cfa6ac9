"""The kernels' data, by name: ``Model`` (what the crafts and the world are) and ``Data`` (what
changes as they move), numba-typed named tuples built once by :class:`Simulator`.

Like MuJoCo's model and data, or Brax's ``System`` and ``State``: a kernel takes ``(model,
samples, data)`` and reads ``samples.plate``, ``data.st``, never a slot number. Every field is
an array; row layouts are named here (the
samples' ``S_*`` rows), in ``state.py`` (the state, the body constants, the scratch) and in
``contact/tables.py`` (``SH_*``, ``CB_*``, ``C_*``).

Per environment. What ``Simulator.set_mass_properties`` and ``Simulator.set_sample_scale`` can
change is stored per environment, environments innermost, so that the force loops read it
as they read the state: ``body`` (mass, inertia, the center of mass's shift, which every
sample's offset is taken from), and one factor per sample on its area, its efficiency and
its thrust (``Samples.factor``, rows shared by the samples that have the same factors in
every environment: :mod:`factors`). The craft's own numbers (offsets, sizes, normals, axes,
control wiring) are stored once per sample: a batch reads a few kilobytes of them however
many environments it has. An environment left at the craft's values has factors of exactly
1 and a shift of exactly 0, so it steps bit-identically to a batch built from that craft.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from . import contact as CT
from .craft import Craft
from .state import BODY_FIELDS, NBODY


class Glyph(NamedTuple):
    """How a viewer draws one sample, in the body frame and without naming a renderer.

    ``form`` is one of :data:`GLYPH_FORMS`: a ``square`` (a flat plate: side ``size`` m,
    normal ``axis``), a ``rod`` (length ``size`` m along ``axis``, centered), a ``ball``
    (radius ``size`` m) or an ``arrow`` (a force of ``size`` N along ``axis``, from
    ``center_m``, drawn at the viewer's force scale). A glyph shows where a sample acts and how
    big it is, not the craft's shape: a cylinder's rod is as long as the square root of its
    area.
    """

    form: str
    center_m: tuple[float, float, float]
    axis: tuple[float, float, float]
    size: float


GLYPH_FORMS = ("square", "rod", "ball", "arrow")
UP = (0.0, 0.0, 1.0)


def _ball_radius(volume_m3: float) -> float:
    return (3.0 * volume_m3 / (4.0 * math.pi)) ** (1.0 / 3.0)


@dataclass(frozen=True)
class SampleKind:
    """A kind of sample, as the kernels' tables hold it.

    Attributes:
        name: the prefix of its :class:`Samples` fields: ``<name>`` (the rows ``[width, n]``),
            ``<name>_at`` (each body's range) and ``<name>_<suffix>`` for each geometry table.
        of: the craft's samples of this kind, in the craft's order.
        sizes: the rows after the offset (rows 0-2): the sample's attributes (None reads as
            0).
        geometry: ``(suffix, attribute)`` of each shared ``[3, n]`` table (a unit vector).
        area: the sizes that ``set_sample_scale(area=)`` multiplies.
        efficiency: the sizes that ``set_sample_scale(efficiency=)`` multiplies.
        thrust: the sizes that ``set_thrust_scale`` multiplies. (``Simulator`` reads these
            three to know which samples take which factor; the kind's loop in
            ``kernels._evaluate`` must multiply the same sizes.)
        glyph: how a viewer draws one sample of this kind (:class:`Glyph`).
    """

    name: str
    of: Callable[[Craft], list]
    sizes: tuple[str, ...]
    glyph: Callable[[object], Glyph]
    geometry: tuple[tuple[str, str], ...] = ()
    area: tuple[str, ...] = ()
    efficiency: tuple[str, ...] = ()
    thrust: tuple[str, ...] = ()

    @property
    def width(self) -> int:
        return 3 + len(self.sizes)

    def row(self, size: str) -> int:
        """The per-environment row of one of :attr:`sizes`."""
        return 3 + self.sizes.index(size)

    def rows(self, craft: Craft) -> list[tuple]:
        """The rows of the craft's samples of this kind (float64 values)."""
        return [(*s.offset_m, *(getattr(s, a) or 0.0 for a in self.sizes)) for s in self.of(craft)]


def is_flap(craft: Craft) -> set[str]:
    """The names of a craft's plates that a control channel drives."""
    return {s.sample for ctl in craft.controls for s in ctl.surfaces}


# a plate's rows after the offset, control surfaces' too (craft.Plate): pressure (area,
# efficiency, one-sided 0/1), then skin friction (forces.friction_force: its area, 0 for a
# plate without; C_f or the roughness allowance; the ITTC-1957 line 0/1; its length)
PLATE_SIZES = (
    "area_m2",
    "efficiency",
    "one_sided",
    "skin_area_m2",
    "friction_coefficient",
    "friction_ittc",
    "friction_length_m",
)

# The kinds, in the order their samples are numbered everywhere (``sample_forces``, the
# kernel's loops). A new kind: a row here (with its glyph: a new form needs a drawing in
# wrappers/rerun_logger.py, which tests/wrappers checks), its Samples fields
# (tests/physics/test_model.py checks them), its loop in ``kernels._evaluate`` (kernels.py
# refuses to import until it has one), its part and schema in craft.py.
KINDS = (
    SampleKind(
        "plate",  # plates without a control channel
        lambda c: [p for p in c.plates if p.name not in is_flap(c)],
        sizes=PLATE_SIZES,
        glyph=lambda p: Glyph("square", p.offset_m, p.normal, math.sqrt(p.area_m2)),
        geometry=(("normal", "normal"),),
        area=("area_m2", "skin_area_m2"),
        efficiency=("efficiency",),
    ),
    SampleKind(
        "flap",  # control surfaces: normals turned about a hinge by the controls
        lambda c: [p for p in c.plates if p.name in is_flap(c)],
        sizes=PLATE_SIZES,
        glyph=lambda p: Glyph("square", p.offset_m, p.normal, math.sqrt(p.area_m2)),
        geometry=(("normal", "normal"), ("hinge", "hinge_axis")),
        area=("area_m2", "skin_area_m2"),
        efficiency=("efficiency",),
    ),
    SampleKind(
        "cyl",
        lambda c: list(c.cylinders),
        sizes=("area_m2",),
        glyph=lambda c: Glyph("rod", c.offset_m, c.axis, math.sqrt(c.area_m2)),
        geometry=(("axis", "axis"),),
        area=("area_m2",),
    ),
    SampleKind(
        "buoy",
        lambda c: list(c.buoyancy),
        sizes=("volume_m3", "area_m2"),  # one of them 0, by the sample's kind
        glyph=lambda b: (
            Glyph("ball", b.offset_m, UP, _ball_radius(b.volume_m3))
            if b.kind == "volume"
            else Glyph("square", b.offset_m, UP, math.sqrt(b.area_m2))
        ),
        area=("volume_m3", "area_m2"),
    ),
    SampleKind(
        "thr",
        lambda c: list(c.thrusters),
        sizes=("min_thrust_n", "max_thrust_n"),
        glyph=lambda t: Glyph("arrow", t.offset_m, t.direction, t.max_thrust_n),
        geometry=(("dir", "direction"),),
        thrust=("min_thrust_n", "max_thrust_n"),
    ),
)
KIND = {k.name: k for k in KINDS}

# the kernels' row numbers, from the kinds' declarations
S_OFFSET = 0  # rows 0-2 of every kind: the offset from the center of mass (body frame, m)
S_AREA = KIND["plate"].row("area_m2")  # plates and control surfaces: area (m^2)
S_EFFICIENCY = KIND["plate"].row("efficiency")
S_ONE_SIDED = KIND["plate"].row("one_sided")  # 1: only the face n points out of acts
S_SKIN_AREA = KIND["plate"].row("skin_area_m2")  # skin friction's area (m^2); 0: none
S_FRICTION_CF = KIND["plate"].row("friction_coefficient")  # C_f, or the ITTC line's allowance
S_FRICTION_ITTC = KIND["plate"].row("friction_ittc")  # 1: C_f from the ITTC-1957 line
S_FRICTION_LENGTH = KIND["plate"].row("friction_length_m")  # the Reynolds number's length (m)
S_CYL_AREA = KIND["cyl"].row("area_m2")  # side area times drag coefficient (m^2)
S_VOLUME, S_BUOY_AREA = KIND["buoy"].row("volume_m3"), KIND["buoy"].row("area_m2")
S_THRUST_MIN, S_THRUST_MAX = KIND["thr"].row("min_thrust_n"), KIND["thr"].row("max_thrust_n")
assert KIND["flap"].sizes == KIND["plate"].sizes  # the kernel reads both with S_AREA, ...
# the rows of Samples.factor_row: which row of Samples.factor holds a sample's factor on its
# area, efficiency, thrust (SampleKind.area, .efficiency, .thrust say what each multiplies)
FACTORS = ("area", "efficiency", "thrust")
F_AREA, F_EFFICIENCY, F_THRUST = range(len(FACTORS))


class Samples(NamedTuple):
    """The crafts' samples, as a force evaluation reads them.

    Samples are numbered per kind (:data:`KINDS`), all bodies' in a row, and
    ``<kind>_at[b]:<kind>_at[b + 1]`` are body b's. A bundle of its own, beside
    :class:`Model`, because a force evaluation takes it and not the rest: every array a
    compiled call takes costs it time, which shows in the one-environment step (and numba's
    parallel loops take no named tuple nested in another).
    """

    plate: np.ndarray  # [width, n] offset, model.PLATE_SIZES
    plate_normal: np.ndarray  # [3, n] body frame
    plate_at: np.ndarray  # [B + 1] int64
    flap: np.ndarray  # [width, n] offset, model.PLATE_SIZES
    flap_normal: np.ndarray  # [3, n] undeflected
    flap_hinge: np.ndarray  # [3, n] the axis the normal turns about
    flap_mix: np.ndarray  # [n, C] deflection (rad) per unit of each control channel
    flap_at: np.ndarray  # [B + 1]
    cyl: np.ndarray  # [width, n] offset, area
    cyl_axis: np.ndarray  # [3, n]
    cyl_at: np.ndarray  # [B + 1]
    buoy: np.ndarray  # [width, n] offset, volume, area
    buoy_at: np.ndarray  # [B + 1]
    thr: np.ndarray  # [width, n] offset, thrust at -1 and +1
    thr_dir: np.ndarray  # [3, n] unit direction
    thr_channel: np.ndarray  # [n] int64 control channel (-1: none, full thrust)
    thr_at: np.ndarray  # [B + 1]
    # each sample's factors: sample j (all bodies' samples in _evaluate's order) has its
    # area times factor[factor_row[F_AREA, j], e] in environment e, and so on
    factor_row: np.ndarray  # [len(FACTORS), N] int64
    factor: np.ndarray  # [rows, E]; row 0 is all ones


class Model(NamedTuple):
    """What the kernels know of the crafts and the world (read-only during a step), for E
    environments of B bodies."""

    prm: np.ndarray  # [NPRM] world and step parameters (kernels.P_*), simulation dtype
    wprm: np.ndarray  # [NWPRM] the wake's parameters (wake.W_*; W_ON = 0: no wake)
    swell: np.ndarray  # [n_waves, 5] float64 (a, kx, ky, omega, phase); empty: calm water
    body: np.ndarray  # [E, B, NBODY] mass, inertia, CoM shift (state.BODY_FIELDS)
    shape: np.ndarray  # [E, NSHAPE, n] collision shapes (contact.SH_*), per environment
    shape_at: np.ndarray  # [B + 1]
    contact_body: np.ndarray  # [E, B, NCBODY] restitution, friction, reach (contact.CB_*)
    cprm: np.ndarray  # [NCPRM] contact parameters (contact.C_*)
    grid: np.ndarray  # the ground's height grid ([1, 1] for a plane)
    # the control channels' actuators (Simulator.set_actuators): per channel, the first-order
    # lag's share of the gap closed per step, 1 - exp(-dt / tau), and the most a channel
    # moves in a step (rate limit x dt, in control units); [0, 2]: instant actuators
    actuator: np.ndarray


class Data(NamedTuple):
    """What a step reads and writes, besides :class:`Model`; buffers allocated once."""

    st: np.ndarray  # [NSTATE, B, E] the state (state.STATE_FIELDS)
    flow: np.ndarray  # [6, E] air velocity, then water velocity
    src: np.ndarray  # [NSRC, E] the wake source of each environment (wake.source_row)
    clock: np.ndarray  # [E] float64 time (s)
    ctrl: np.ndarray  # [C, E] control channels in [-1, 1]: where the actuators are
    command: np.ndarray  # [C, E] where the controls are told to go (with actuators)
    flap_now: np.ndarray  # [3, n_flaps, E] deflected control-surface normals, body frame
    external: np.ndarray  # [E, B, 6] held world force and torque (set_external_force)
    warm: np.ndarray  # [E or 0, pairs, NWARM] contact warm starts
    touch: np.ndarray  # [E or 0, pairs] each pair's normal impulse over the last call
    scr: np.ndarray  # [blocks, B, ROWS * BLOCK] the blocks' scratch (state.SCRATCH_FIELDS)
    diverged: np.ndarray  # [E] bool
    # a carrying integrator's memory (state.MEMORY_FIELDS; integrators.Integrator.carries),
    # [NMEMORY, B, E]; [0, B, E] for the others
    memory: np.ndarray
    iterations: np.ndarray  # [E] implicit_midpoint: the most iterations of a step; [0] else


# --------------------------------------------------------------------------------------------
# packing a craft


def body_rows(
    mass_kg: np.ndarray, inertia: np.ndarray, com_shift_m=None, runaway=None
) -> np.ndarray:
    """``BODY_FIELDS`` rows ``[n, NBODY]`` (float64) of masses ``[n]``, body inertia tensors
    ``[n, 3, 3]``, center-of-mass shifts ``[n, 3]`` (None: none) and runaway limits
    ``[n, 2]`` (speed m/s, rate rad/s; None: none): mass, inverse inertia, second moment,
    shift, limits."""
    inertia = np.asarray(inertia, dtype=np.float64)
    inv = np.linalg.inv(inertia)
    trace = inertia[:, 0, 0] + inertia[:, 1, 1] + inertia[:, 2, 2]
    sec = 0.5 * trace[:, None, None] * np.eye(3) - inertia  # reference/tetra.py
    i, j = np.array([0, 1, 2, 0, 0, 1]), np.array([0, 1, 2, 1, 2, 2])  # xx yy zz xy xz yz
    mass = np.asarray(mass_kg, float)[:, None]
    shift = np.zeros((len(mass), 3)) if com_shift_m is None else com_shift_m
    limits = np.full((len(mass), 2), np.inf) if runaway is None else runaway
    rows = np.concatenate([mass, inv[:, i, j], sec[:, i, j], shift, limits], 1)
    assert rows.shape[1] == NBODY == sum(w for _, w in BODY_FIELDS)
    return rows


def sample_rows(craft: Craft) -> dict[str, list[tuple]]:
    """A craft's sample rows by kind (float64)."""
    return {k.name: k.rows(craft) for k in KINDS}


def glyphs(craft: Craft) -> list[Glyph]:
    """Every sample's glyph, in the kernels' order (``Simulator.sample_forces``')."""
    return [kind.glyph(s) for kind in KINDS for s in kind.of(craft)]


def sample_names(craft: Craft) -> dict[str, list[str]]:
    """A craft's sample names by kind, in :func:`sample_rows`' order."""
    return {k.name: [s.name for s in k.of(craft)] for k in KINDS}


def control_names(crafts: Sequence[Craft]) -> list[str]:
    """The simulator's control channels: each craft's, prefixed by its name if several."""
    if len(crafts) == 1:
        return list(crafts[0].control_names)
    return [f"{c.name}.{n}" for c in crafts for n in c.control_names]


def surface_mix(craft: Craft) -> dict[str, np.ndarray]:
    """Each control surface's deflection (rad) per unit of each of ``craft``'s channels: the
    sum over its controls of ``gain * max_deflection_deg`` (the kernels' ``flap_mix`` rows,
    and what a render mesh turns a surface by)."""
    drive: dict[str, np.ndarray] = {}
    for j, ctl in enumerate(craft.controls):
        for s in ctl.surfaces:
            row = drive.setdefault(s.sample, np.zeros(len(craft.controls)))
            row[j] += s.gain * math.radians(ctl.max_deflection_deg)
    return drive


def _once(rows: list[tuple], width: int, dtype) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(rows, dtype=np.float64).reshape(-1, width).T, dtype)


def _ranges(counts: list[int]) -> np.ndarray:
    return np.asarray(np.concatenate([[0], np.cumsum(counts)]), dtype=np.int64)


def pack(
    crafts: Sequence[Craft],
    num_envs: int,
    dtype,
    prm: np.ndarray,
    wprm: np.ndarray,
    swell: np.ndarray,
    cprm: np.ndarray,
    grid: np.ndarray,
) -> tuple[Model, Samples]:
    """The :class:`Model` and :class:`Samples` of E environments of ``crafts`` (every
    environment at the crafts' own values)."""
    E, dtype = num_envs, np.dtype(dtype)
    fields = {}
    for kind in KINDS:  # the samples' rows, geometry, each body's range
        fields[kind.name] = _once([r for c in crafts for r in kind.rows(c)], kind.width, dtype)
        for suffix, attr in kind.geometry:
            vectors = [getattr(s, attr) for c in crafts for s in kind.of(c)]
            fields[f"{kind.name}_{suffix}"] = _once(vectors, 3, dtype)
        fields[f"{kind.name}_at"] = _ranges([len(kind.of(c)) for c in crafts])
    # the control wiring: each control surface's deflection per channel, each thruster's
    offsets = np.cumsum([0] + [len(c.control_names) for c in crafts])
    mix, thr_ch = [], []
    for b, c in enumerate(crafts):
        drive = surface_mix(c)
        for p in KIND["flap"].of(c):  # the row over every body's channels
            row = np.zeros(offsets[-1])
            row[offsets[b] : offsets[b + 1]] = drive[p.name]
            mix.append(row)
        thr_ch.extend(
            -1 if t.control is None else offsets[b] + c.control_names.index(t.control)
            for t in c.thrusters
        )
    bodies = body_rows(
        np.array([c.mass_kg for c in crafts]),
        np.stack([c.inertia_tensor for c in crafts]),
        runaway=np.array([c.runaway for c in crafts]),
    ).astype(dtype)
    materials = np.asarray([CT.material_row(c) for c in crafts], dtype=np.float64)
    shape_table = _once([r for c in crafts for r in CT.shape_rows(c)], CT.NSHAPE, dtype)
    return Model(
        prm=prm.astype(dtype),
        wprm=wprm.astype(dtype),
        swell=np.ascontiguousarray(swell, dtype=np.float64),
        # copies, each environment's own and writable: np.ascontiguousarray would keep the
        # read-only broadcast where it is already contiguous (one environment, no shapes),
        # and a read-only array is another type to numba (a second compile of every kernel
        # for num_envs=1) and refuses set_mass_properties
        body=np.broadcast_to(bodies, (E, *bodies.shape)).copy(),
        shape_at=_ranges([len(c.shapes) for c in crafts]),
        shape=np.broadcast_to(shape_table, (E, *shape_table.shape)).copy(),
        contact_body=np.broadcast_to(materials.astype(dtype), (E, len(crafts), CT.NCBODY)).copy(),
        cprm=cprm.astype(dtype),
        grid=np.array(grid, dtype=dtype),  # a copy: a Ground keeps its own read-only
        actuator=np.zeros((0, 2), dtype=dtype),
    ), Samples(
        flap_mix=np.asarray(mix, dtype=dtype).reshape(len(mix), int(offsets[-1])),
        thr_channel=np.asarray(thr_ch, dtype=np.int64),
        factor_row=np.zeros((len(FACTORS), sum(c.num_samples for c in crafts)), np.int64),
        factor=np.ones((1, E), dtype=dtype),
        **fields,
    )
