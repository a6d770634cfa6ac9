"""The kernels' data, by name: ``Model`` (what the crafts and the world are) and ``Data`` (what
changes as they move), numba-typed named tuples built once by :class:`Simulator`.

Like MuJoCo's model and data, or Brax's ``System`` and ``State``: a kernel takes ``(model,
data)`` and reads ``model.plate``, ``data.st``, never a slot number. Every field is an array;
row layouts are named here (the samples' ``S_*`` rows), in ``state.py`` (the state, the body
constants, the scratch) and in ``contact.py`` (``SH_*``, ``CB_*``).

Per environment. What ``Simulator.set_mass_properties`` and ``Simulator.set_sample_scale`` can
change is stored per environment, environments innermost (``[field, sample, E]``), so that
the force loops read it as they read the state: ``body`` (mass, inertia), and each sample's
offset from the center of mass and size (area, volume, efficiency, thrust). What no
environment can change (normals, hinge and cylinder axes, thrust directions, control wiring)
is stored once per sample. An environment left at the craft's values holds the numbers
:func:`craft_rows` packs from the ``Craft``, so it steps bit-identically to a batch built from
that craft alone.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from . import contact as CT
from .craft import Craft
from .state import BODY_FIELDS, NBODY

# per-environment sample rows [S_*, n, E]: the offset from the center of mass (body frame, m)
# first, for every kind, then the kind's sizes
S_OFFSET = 0
S_AREA, S_EFFICIENCY = 3, 4  # plates and control surfaces: area (m^2), efficiency
S_CYL_AREA = 3  # cylinders: side area times drag coefficient (m^2)
S_VOLUME, S_BUOY_AREA = 3, 4  # buoyancy: volume (m^3) or area (m^2), the other 0
S_THRUST_MIN, S_THRUST_MAX = 3, 4  # thrusters: thrust (N) at control -1 and +1
N_PLATE, N_CYL, N_BUOY, N_THR = 5, 4, 5, 5

KINDS = ("plate", "flap", "cyl", "buoy", "thr")  # the order of the samples in every table


class Model(NamedTuple):
    """What the kernels know of the crafts and the world (read-only during a step).

    E environments of B bodies; samples are numbered per kind, all bodies' in a row, and
    ``<kind>_at[b]:<kind>_at[b + 1]`` are body b's. Kinds: ``plate`` (a plate without a
    control), ``flap`` (a control surface), ``cyl``, ``buoy``, ``thr`` (thrusters).
    """

    prm: np.ndarray  # [NPRM] world and step parameters (kernels.P_*), simulation dtype
    wprm: np.ndarray  # [NWPRM] the wake's parameters (wake.W_*; W_ON = 0: no wake)
    swell: np.ndarray  # [n_waves, 5] float64 (a, kx, ky, omega, phase); empty: calm water
    body: np.ndarray  # [E, B, NBODY] mass and inertia (state.BODY_FIELDS), per environment
    plate: np.ndarray  # [N_PLATE, n, E] offset, area, efficiency
    plate_normal: np.ndarray  # [3, n] body frame
    plate_at: np.ndarray  # [B + 1] int64
    flap: np.ndarray  # [N_PLATE, n, E] offset, area, efficiency
    flap_normal: np.ndarray  # [3, n] undeflected
    flap_hinge: np.ndarray  # [3, n] the axis the normal turns about
    flap_mix: np.ndarray  # [n, C] deflection (rad) per unit of each control channel
    flap_at: np.ndarray  # [B + 1]
    cyl: np.ndarray  # [N_CYL, n, E] offset, area
    cyl_axis: np.ndarray  # [3, n]
    cyl_at: np.ndarray  # [B + 1]
    buoy: np.ndarray  # [N_BUOY, n, E] offset, volume, area
    buoy_at: np.ndarray  # [B + 1]
    thr: np.ndarray  # [N_THR, n, E] offset, thrust at -1 and +1
    thr_dir: np.ndarray  # [3, n] unit direction
    thr_channel: np.ndarray  # [n] int64 control channel (-1: none, full thrust)
    thr_at: np.ndarray  # [B + 1]
    shape: np.ndarray  # [E, NSHAPE, n] collision shapes (contact.SH_*), per environment
    shape_at: np.ndarray  # [B + 1]
    contact_body: np.ndarray  # [E, B, NCBODY] restitution, friction, reach (contact.CB_*)
    cprm: np.ndarray  # [NCPRM] contact parameters (contact.C_*)
    grid: np.ndarray  # the ground's height grid ([1, 1] for a plane)


class Data(NamedTuple):
    """What a step reads and writes, besides :class:`Model`; buffers allocated once."""

    st: np.ndarray  # [NSTATE, B, E] the state (state.STATE_FIELDS)
    flow: np.ndarray  # [6, E] air velocity, then water velocity
    src: np.ndarray  # [NSRC, E] the wake source of each environment (wake.source_row)
    clock: np.ndarray  # [E] float64 time (s)
    ctrl: np.ndarray  # [C, E] control channels in [-1, 1]
    flap_now: np.ndarray  # [3, n_flaps, E] deflected control-surface normals, body frame
    external: np.ndarray  # [E, B, 6] held world force and torque (set_external_force)
    warm: np.ndarray  # [E or 0, pairs, NWARM] contact warm starts
    touch: np.ndarray  # [E or 0, pairs] each pair's normal impulse over the last call
    scr: np.ndarray  # [blocks, B, ROWS * BLOCK] the blocks' scratch (state.SCRATCH_FIELDS)
    diverged: np.ndarray  # [E] bool


# --------------------------------------------------------------------------------------------
# packing a craft


def body_rows(mass_kg: np.ndarray, inertia: np.ndarray) -> np.ndarray:
    """``BODY_FIELDS`` rows ``[n, NBODY]`` (float64) of masses ``[n]`` and body inertia
    tensors ``[n, 3, 3]``: mass, inverse inertia, second moment."""
    inertia = np.asarray(inertia, dtype=np.float64)
    inv = np.linalg.inv(inertia)
    trace = inertia[:, 0, 0] + inertia[:, 1, 1] + inertia[:, 2, 2]
    sec = 0.5 * trace[:, None, None] * np.eye(3) - inertia  # tetra.py
    i, j = np.array([0, 1, 2, 0, 0, 1]), np.array([0, 1, 2, 1, 2, 2])  # xx yy zz xy xz yz
    rows = np.concatenate([np.asarray(mass_kg, float)[:, None], inv[:, i, j], sec[:, i, j]], 1)
    assert rows.shape[1] == NBODY == sum(w for _, w in BODY_FIELDS)
    return rows


def is_flap(craft: Craft) -> set[str]:
    """The names of a craft's plates that a control channel drives."""
    return {s.sample for ctl in craft.controls for s in ctl.surfaces}


def sample_rows(craft: Craft) -> dict[str, list[tuple]]:
    """A craft's per-environment sample rows by kind (``S_*`` layout, float64)."""
    flaps = is_flap(craft)
    rows = {k: [] for k in KINDS}
    for p in craft.plates:
        rows["flap" if p.name in flaps else "plate"].append((*p.offset_m, p.area_m2, p.efficiency))
    rows["cyl"] = [(*s.offset_m, s.area_m2) for s in craft.cylinders]
    rows["buoy"] = [(*s.offset_m, s.volume_m3 or 0.0, s.area_m2 or 0.0) for s in craft.buoyancy]
    rows["thr"] = [(*t.offset_m, t.min_thrust_n, t.max_thrust_n) for t in craft.thrusters]
    return rows


def sample_names(craft: Craft) -> dict[str, list[str]]:
    """A craft's sample names by kind, in :func:`sample_rows`' order."""
    flaps = is_flap(craft)
    return {
        "plate": [p.name for p in craft.plates if p.name not in flaps],
        "flap": [p.name for p in craft.plates if p.name in flaps],
        "cyl": [s.name for s in craft.cylinders],
        "buoy": [s.name for s in craft.buoyancy],
        "thr": [t.name for t in craft.thrusters],
    }


def control_names(crafts: Sequence[Craft]) -> list[str]:
    """The simulator's control channels: each craft's, prefixed by its name if several."""
    if len(crafts) == 1:
        return list(crafts[0].control_names)
    return [f"{c.name}.{n}" for c in crafts for n in c.control_names]


def _field_major(rows: list[tuple], width: int, num_envs: int, dtype) -> np.ndarray:
    """``[width, n, E]``: the rows repeated for every environment."""
    table = np.asarray(rows, dtype=np.float64).reshape(-1, width).T.astype(dtype)
    return np.ascontiguousarray(np.repeat(table[:, :, None], num_envs, axis=2))


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
) -> Model:
    """The :class:`Model` of E environments of ``crafts`` (every environment at the crafts'
    own values)."""
    E, dtype = num_envs, np.dtype(dtype)
    offsets = np.cumsum([0] + [len(c.control_names) for c in crafts])
    n_ch = int(offsets[-1])
    rows = {k: [] for k in KINDS}
    counts = {k: [] for k in KINDS}
    plate_normal, flap_normal, flap_hinge, mix, cyl_axis, thr_dir, thr_ch = ([] for _ in range(7))
    shapes, shape_counts = [], []
    for b, c in enumerate(crafts):
        for kind, r in sample_rows(c).items():
            rows[kind].extend(r)
            counts[kind].append(len(r))
        drive: dict[str, np.ndarray] = {}
        for j, ctl in enumerate(c.controls):
            for s in ctl.surfaces:
                row = drive.setdefault(s.sample, np.zeros(n_ch))
                row[offsets[b] + j] += s.gain * math.radians(ctl.max_deflection_deg)
        for p in c.plates:
            if p.name in drive:
                flap_normal.append(p.normal)
                flap_hinge.append(p.hinge_axis)
                mix.append(drive[p.name])
            else:
                plate_normal.append(p.normal)
        cyl_axis.extend(s.axis for s in c.cylinders)
        thr_dir.extend(t.direction for t in c.thrusters)
        thr_ch.extend(
            -1 if t.control is None else offsets[b] + c.control_names.index(t.control)
            for t in c.thrusters
        )
        shapes.extend(CT.shape_rows(c))
        shape_counts.append(len(c.shapes))
    bodies = body_rows(
        np.array([c.mass_kg for c in crafts]), np.stack([c.inertia_tensor for c in crafts])
    ).astype(dtype)
    materials = np.asarray([CT.material_row(c) for c in crafts], dtype=np.float64)
    shape_table = _once(shapes, CT.NSHAPE, dtype)
    return Model(
        prm=prm.astype(dtype),
        wprm=wprm.astype(dtype),
        swell=np.ascontiguousarray(swell, dtype=np.float64),
        body=np.ascontiguousarray(np.broadcast_to(bodies, (E, *bodies.shape))),
        plate=_field_major(rows["plate"], N_PLATE, E, dtype),
        plate_normal=_once(plate_normal, 3, dtype),
        plate_at=_ranges(counts["plate"]),
        flap=_field_major(rows["flap"], N_PLATE, E, dtype),
        flap_normal=_once(flap_normal, 3, dtype),
        flap_hinge=_once(flap_hinge, 3, dtype),
        flap_mix=np.asarray(mix, dtype=dtype).reshape(len(mix), n_ch),
        flap_at=_ranges(counts["flap"]),
        cyl=_field_major(rows["cyl"], N_CYL, E, dtype),
        cyl_axis=_once(cyl_axis, 3, dtype),
        cyl_at=_ranges(counts["cyl"]),
        buoy=_field_major(rows["buoy"], N_BUOY, E, dtype),
        buoy_at=_ranges(counts["buoy"]),
        thr=_field_major(rows["thr"], N_THR, E, dtype),
        thr_dir=_once(thr_dir, 3, dtype),
        thr_channel=np.asarray(thr_ch, dtype=np.int64),
        thr_at=_ranges(counts["thr"]),
        shape=np.ascontiguousarray(np.broadcast_to(shape_table, (E, *shape_table.shape))),
        shape_at=_ranges(shape_counts),
        contact_body=np.ascontiguousarray(
            np.broadcast_to(materials.astype(dtype), (E, len(crafts), CT.NCBODY))
        ),
        cprm=cprm.astype(dtype),
        grid=np.ascontiguousarray(grid, dtype=dtype),
    )
