"""Craft specifications: a rigid body and the fluid samples, buoyancy and thrusters it carries.

A craft is data. It is written in a TOML file under ``fluidsim_envs/craft/`` (or built in code)
and validated once into a frozen :class:`Craft`; the simulator packs it into flat tables for the
kernels. Every length is in the body frame (x forward, y left, z up) relative to the center of
mass, in SI units; units are in the key names.

File layout (every table optional except the top-level keys)::

    name = "glider"
    mass_kg = 0.005
    inertia_kgm2 = [1e-6, 4e-6, 5e-6]      # principal moments about x, y, z, or a 3x3 tensor

    [[plates]]        # flat plate: name, offset_m, normal, area_m2, efficiency, hinge_axis,
                      # one_sided, friction_coefficient, friction_line, friction_length_m,
                      # friction_area_m2
    [[cylinders]]     # cross-flow cylinder: name, offset_m, axis, area_m2
    [[buoyancy]]      # name, offset_m, kind = "volume" (volume_m3) or "area" (area_m2)
    [[thrusters]]     # name, offset_m, direction, max_thrust_n, min_thrust_n, control
    [[controls]]      # name, max_deflection_deg, surfaces = [{sample=..., gain=...}, ...]
    [[shapes]]        # collision shape: name, kind = "sphere" (radius_m) or "box"
                      # (half_extents_m, axis-aligned in the body frame), center_m
    groups = { wings = ["left_wing", "right_wing"] }   # named sets of samples (top level)

A craft with shapes touches the ground and the other bodies of its environment (contact.py);
``restitution`` and ``friction`` (top level, default 0.5 each) are its contact material.

Directions (normal, axis, hinge_axis, direction) may have any non-zero length and are
normalized on load.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import MISSING, dataclass, field, fields, replace
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from . import checks as CK

Vec3 = tuple[float, float, float]


class CraftError(ValueError):
    """A craft specification that is incomplete or not physical."""


# --------------------------------------------------------------------------------------------
# small validators: each names the offending value


def _finite(where: str, key: str, value: Any) -> float:
    return CK.number(where, key, value, error=CraftError)


def _positive(where: str, key: str, value: Any) -> float:
    return CK.number(where, key, value, gt=0.0, error=CraftError)


def _vec3(where: str, key: str, value: Any) -> Vec3:
    return CK.vector(where, key, value, 3, error=CraftError)  # type: ignore[return-value]


def _unit(where: str, key: str, value: Any) -> Vec3:
    return CK.direction(where, key, value, error=CraftError)


def _name(where: str, key: str, value: Any) -> str:
    if not isinstance(value, str):
        raise CraftError(f"{where}: {key} must be a string, got {CK.show(value)}")
    return value


def _is_real(value: Any) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(
        value, (bool, np.bool_)
    )


def _wanted(annotation: str, value: Any) -> str | None:
    """What a field annotated ``annotation`` takes, where ``value`` is not of it (None: it
    is). Types only: the parts check values (ranges, directions) themselves."""
    if value is None and annotation.endswith(" | None"):
        return None
    base = annotation.removesuffix(" | None")
    if base == "bool":
        return None if isinstance(value, (bool, np.bool_)) else "true or false"
    if base == "str":
        return None if isinstance(value, str) else "a string"
    if base == "float":
        return None if _is_real(value) else "a number"
    if base == "Vec3":
        ok = isinstance(value, (list, tuple, np.ndarray)) and len(value) == 3
        return None if ok and all(_is_real(v) for v in value) else "a list of 3 numbers"
    if base.startswith("tuple["):
        ok = isinstance(value, (list, tuple))
        return None if ok else f"a list of tables ([[...]] in a file), or of {base[6:-6]}s"
    return None


def _check_table(where: str, path: str, data: Any, cls: type) -> None:
    """A table of a craft file (``path``: where in the file, e.g. ``plates[2]``) whose keys
    and value types fit part ``cls``; nested lists of parts (a control's ``surfaces``) too.
    A wrong type would otherwise surface as a bare TypeError or as an error that names the
    part but not where in the file it is."""
    if not isinstance(data, dict):
        raise CraftError(f"{where}: {path} must be a table, got {CK.show(data)}")
    valid = [f.name for f in fields(cls)]
    unknown = [k for k in data if k not in valid]
    if unknown:
        raise CraftError(
            f"{where}: {path}.{unknown[0]} = {CK.show(data[unknown[0]])}: unknown key(s) "
            f"{unknown} in {path}; valid keys are {valid}"
        )
    missing = [f.name for f in fields(cls) if f.default is MISSING and f.name not in data]
    if missing:
        raise CraftError(f"{where}: {path}: missing required key(s) {missing}; got {CK.show(data)}")
    for f in fields(cls):
        if f.name not in data:
            continue
        value = data[f.name]
        wanted = _wanted(f.type, value)
        if wanted:
            raise CraftError(f"{where}: {path}.{f.name} must be {wanted}, got {CK.show(value)}")
        part = _PART_LISTS.get(f.type)
        for i, item in enumerate(value if part else ()):
            if not isinstance(item, part):
                _check_table(where, f"{path}.{f.name}[{i}]", item, part)


# --------------------------------------------------------------------------------------------
# the parts of a craft


FRICTION_LINES = ("ittc1957",)  # a plate's friction_line (forces.ittc1957)
FRICTION_COEFFICIENT_MAX = 0.1  # C_f of real surfaces: 0.001-0.01 (a flat plate's at Re 1e4)
FRICTION_LENGTH_RANGE_M = (1e-4, 1e3)


@dataclass(frozen=True)
class Plate:
    """A flat plate: force along its normal, ``F = -1/2 rho A (v|v| . n) n``.

    ``efficiency`` in [0, 1] removes that fraction of the force's component along the flow
    (1: pure lift, 0: lift and drag of a bare plate). ``hinge_axis`` is the axis its normal
    turns about when a control channel deflects it.

    ``one_sided``: only the face the normal points out of acts, when the plate moves toward
    its normal side (``v . n > 0``, v relative to the fluid); moving away it gives no force
    (``forces.plate_force``). Give such a plate a normal pointing out of the body.

    Skin friction along the plate's plane, ``F = -1/2 rho C_f A_f |v_t| v_t``
    (``forces.friction_force``), on ``friction_area_m2`` (default: ``area_m2``):
    ``C_f = friction_coefficient``, or with ``friction_line = "ittc1957"`` the ITTC-1957
    line at ``Re = |v| friction_length_m / nu`` plus ``friction_coefficient`` as its roughness
    allowance. None of them set: no skin friction.
    """

    name: str
    offset_m: Vec3
    normal: Vec3
    area_m2: float
    efficiency: float = 0.0
    hinge_axis: Vec3 | None = None
    one_sided: bool = False
    friction_coefficient: float = 0.0
    friction_line: str | None = None
    friction_length_m: float | None = None
    friction_area_m2: float | None = None

    def __post_init__(self) -> None:
        where = f"plate {_name('plate', 'name', self.name)!r}"
        object.__setattr__(self, "offset_m", _vec3(where, "offset_m", self.offset_m))
        object.__setattr__(self, "normal", _unit(where, "normal", self.normal))
        object.__setattr__(self, "area_m2", _positive(where, "area_m2", self.area_m2))
        eff = _finite(where, "efficiency", self.efficiency)
        if not 0.0 <= eff <= 1.0:
            raise CraftError(f"{where}: efficiency must be in [0, 1], got {self.efficiency!r}")
        object.__setattr__(self, "efficiency", eff)
        if self.hinge_axis is not None:
            object.__setattr__(self, "hinge_axis", _unit(where, "hinge_axis", self.hinge_axis))
        self._check_friction(where)

    def _check_friction(self, where: str) -> None:
        if not isinstance(self.one_sided, (bool, np.bool_)):
            raise CraftError(
                f"{where}: one_sided must be true or false, got {CK.show(self.one_sided)}"
            )
        object.__setattr__(self, "one_sided", bool(self.one_sided))
        cf = _finite(where, "friction_coefficient", self.friction_coefficient)
        if not 0.0 <= cf <= FRICTION_COEFFICIENT_MAX:
            raise CraftError(
                f"{where}: friction_coefficient must be in [0, {FRICTION_COEFFICIENT_MAX}] "
                f"(C_f of real surfaces is 0.001-0.01), got {self.friction_coefficient!r}"
            )
        object.__setattr__(self, "friction_coefficient", cf)
        line, length = self.friction_line, self.friction_length_m
        if line is not None and line not in FRICTION_LINES:
            raise CraftError(
                f"{where}: friction_line must be one of {list(FRICTION_LINES)}, got {line!r}"
            )
        if line is not None and length is None:
            raise CraftError(
                f"{where}: friction_line {line!r} needs friction_length_m (the length of the "
                "surface along the flow, for the Reynolds number)"
            )
        if length is not None:
            if line is None:
                raise CraftError(
                    f"{where}: friction_length_m ({length!r}) is only read with a "
                    f"friction_line ({list(FRICTION_LINES)})"
                )
            lo, hi = FRICTION_LENGTH_RANGE_M
            length = _finite(where, "friction_length_m", length)
            if not lo <= length <= hi:
                raise CraftError(
                    f"{where}: friction_length_m must be in [{lo:g}, {hi:g}] m, got {length!r}"
                )
            object.__setattr__(self, "friction_length_m", length)
        if self.friction_area_m2 is not None:
            if not self.has_friction:
                raise CraftError(
                    f"{where}: friction_area_m2 ({self.friction_area_m2!r}) needs a "
                    "friction_coefficient > 0 or a friction_line"
                )
            area = _positive(where, "friction_area_m2", self.friction_area_m2)
            object.__setattr__(self, "friction_area_m2", area)

    @property
    def has_friction(self) -> bool:
        return self.friction_coefficient > 0.0 or self.friction_line is not None

    @property
    def skin_area_m2(self) -> float:
        """The area skin friction acts on: ``friction_area_m2`` or ``area_m2``; 0 without
        skin friction (the kernels skip the plate's friction loop)."""
        if not self.has_friction:
            return 0.0
        return self.area_m2 if self.friction_area_m2 is None else self.friction_area_m2

    @property
    def friction_ittc(self) -> float:
        """1.0 where ``friction_line`` is ``"ittc1957"``, else 0.0 (the kernels' row)."""
        return 1.0 if self.friction_line == "ittc1957" else 0.0


@dataclass(frozen=True)
class Cylinder:
    """A slender cylinder: cross-flow drag ``F = -1/2 rho A |v_perp| v_perp``.

    ``v_perp`` is the part of the relative velocity across the axis (Hoerner's cross-flow
    principle), ``area_m2`` the projected side area times its drag coefficient.
    """

    name: str
    offset_m: Vec3
    axis: Vec3
    area_m2: float

    def __post_init__(self) -> None:
        where = f"cylinder {_name('cylinder', 'name', self.name)!r}"
        object.__setattr__(self, "offset_m", _vec3(where, "offset_m", self.offset_m))
        object.__setattr__(self, "axis", _unit(where, "axis", self.axis))
        object.__setattr__(self, "area_m2", _positive(where, "area_m2", self.area_m2))


@dataclass(frozen=True)
class Buoyancy:
    """Buoyancy under the water surface, acting upward at the sample's point.

    ``kind="volume"``: ``rho_water g volume_m3`` once submerged (blended across the surface
    layer). ``kind="area"``: ``rho_water g area_m2 depth``, a spring (the hydrostatic
    pressure on a horizontal area).
    """

    name: str
    offset_m: Vec3
    kind: str
    volume_m3: float | None = None
    area_m2: float | None = None

    def __post_init__(self) -> None:
        where = f"buoyancy {_name('buoyancy', 'name', self.name)!r}"
        object.__setattr__(self, "offset_m", _vec3(where, "offset_m", self.offset_m))
        if self.kind == "volume":
            if self.volume_m3 is None or self.area_m2 is not None:
                raise CraftError(f"{where}: kind 'volume' needs volume_m3 (and no area_m2)")
            object.__setattr__(self, "volume_m3", _positive(where, "volume_m3", self.volume_m3))
        elif self.kind == "area":
            if self.area_m2 is None or self.volume_m3 is not None:
                raise CraftError(f"{where}: kind 'area' needs area_m2 (and no volume_m3)")
            object.__setattr__(self, "area_m2", _positive(where, "area_m2", self.area_m2))
        else:
            raise CraftError(f"{where}: kind must be 'volume' or 'area', got {self.kind!r}")

    @property
    def size(self) -> float:
        """Volume (m^3) or area (m^2), by kind."""
        return self.volume_m3 if self.kind == "volume" else self.area_m2  # type: ignore[return-value]


@dataclass(frozen=True)
class Thruster:
    """A force ``thrust * direction`` at a point. The channel's value c in [-1, 1] gives no
    thrust at 0, ``c * max_thrust_n`` ahead and ``-c * min_thrust_n`` astern
    (``forces.thrust_of``); a thruster without a channel runs at max."""

    name: str
    offset_m: Vec3
    direction: Vec3
    max_thrust_n: float
    min_thrust_n: float = 0.0
    control: str | None = None

    def __post_init__(self) -> None:
        where = f"thruster {_name('thruster', 'name', self.name)!r}"
        if self.control is not None:
            _name(where, "control", self.control)
        object.__setattr__(self, "offset_m", _vec3(where, "offset_m", self.offset_m))
        object.__setattr__(self, "direction", _unit(where, "direction", self.direction))
        hi = _finite(where, "max_thrust_n", self.max_thrust_n)
        lo = _finite(where, "min_thrust_n", self.min_thrust_n)
        if hi < 0.0:
            raise CraftError(f"{where}: max_thrust_n must be >= 0 (ahead), got {hi}")
        if lo > 0.0:
            raise CraftError(
                f"{where}: min_thrust_n must be <= 0 (astern; control 0 is no thrust), got {lo}"
            )
        object.__setattr__(self, "max_thrust_n", hi)
        object.__setattr__(self, "min_thrust_n", lo)


@dataclass(frozen=True)
class Shape:
    """A collision shape fixed to the body: a sphere (``radius_m``) or a box
    (``half_extents_m``, its faces along the body axes), centered at ``center_m``."""

    name: str
    kind: str
    center_m: Vec3 = (0.0, 0.0, 0.0)
    radius_m: float | None = None
    half_extents_m: Vec3 | None = None

    def __post_init__(self) -> None:
        where = f"shape {_name('shape', 'name', self.name)!r}"
        object.__setattr__(self, "center_m", _vec3(where, "center_m", self.center_m))
        if self.kind == "sphere":
            if self.radius_m is None or self.half_extents_m is not None:
                raise CraftError(f"{where}: kind 'sphere' needs radius_m (and no half_extents_m)")
            object.__setattr__(self, "radius_m", _positive(where, "radius_m", self.radius_m))
        elif self.kind == "box":
            if self.half_extents_m is None or self.radius_m is not None:
                raise CraftError(f"{where}: kind 'box' needs half_extents_m (and no radius_m)")
            half = _vec3(where, "half_extents_m", self.half_extents_m)
            for i, h in enumerate(half):
                _positive(where, f"half_extents_m[{i}]", h)
            object.__setattr__(self, "half_extents_m", half)
        else:
            raise CraftError(f"{where}: kind must be 'sphere' or 'box', got {self.kind!r}")

    @property
    def extent_m(self) -> float:
        """The distance from the shape's center to its farthest point."""
        if self.kind == "sphere":
            return self.radius_m
        return math.sqrt(sum(h * h for h in self.half_extents_m))

    @property
    def reach_m(self) -> float:
        """The distance from the center of mass to the shape's farthest point."""
        return float(shape_reach(np.asarray(self.center_m), self.extent_m))


@dataclass(frozen=True)
class Surface:
    """A plate driven by a control channel; ``gain`` scales (and may flip) the deflection."""

    sample: str
    gain: float = 1.0


@dataclass(frozen=True)
class Control:
    """A control channel: action in [-1, 1] deflects each surface by
    ``gain * action * max_deflection_deg`` about the plate's hinge axis (right-hand rule)."""

    name: str
    max_deflection_deg: float = 0.0
    surfaces: tuple[Surface, ...] = ()

    def __post_init__(self) -> None:
        where = f"control {_name('control', 'name', self.name)!r}"
        d = _finite(where, "max_deflection_deg", self.max_deflection_deg)
        if not 0.0 <= d <= 90.0:
            raise CraftError(f"{where}: max_deflection_deg must be in [0, 90], got {d!r}")
        object.__setattr__(self, "max_deflection_deg", d)
        if not isinstance(self.surfaces, (list, tuple)):
            raise CraftError(
                f"{where}: surfaces must be a list of tables ({{sample = ..., gain = ...}}), "
                f"got {CK.show(self.surfaces)}"
            )
        surfaces = []
        for i, s in enumerate(self.surfaces):
            if not isinstance(s, Surface):
                _check_table(where, f"surfaces[{i}]", s, Surface)
                s = Surface(**s)
            _name(f"{where}: surfaces[{i}]", "sample", s.sample)
            surfaces.append(Surface(s.sample, _finite(f"{where}: surfaces[{i}]", "gain", s.gain)))
        object.__setattr__(self, "surfaces", tuple(surfaces))


# the lists of parts a part holds, by annotation (_check_table)
_PART_LISTS = {"tuple[Surface, ...]": Surface}

# --------------------------------------------------------------------------------------------
# the craft


def shape_reach(center_m: np.ndarray, extent_m):
    """A shape's reach from the center of mass: its center's distance plus its extent
    (``center_m [..., 3]``); the one formula for crafts and per-environment centers of mass."""
    c = np.asarray(center_m, dtype=np.float64)
    return np.sqrt(c[..., 0] * c[..., 0] + c[..., 1] * c[..., 1] + c[..., 2] * c[..., 2]) + extent_m


def shift_offsets(offsets_m: np.ndarray, shift_m) -> np.ndarray:
    """Offsets ``[..., 3]`` from a center of mass moved by ``shift_m`` (body frame): ``offset -
    shift``, in float64. The one rule for :meth:`Craft.with_center_of_mass` and the collision
    shapes of ``Simulator.set_mass_properties``; the force loops take the same difference
    per sample (``state.B_COM_SHIFT``), so both give the same numbers, bit for bit."""
    return np.asarray(offsets_m, dtype=np.float64) - np.asarray(shift_m, dtype=np.float64)


def check_inertia(where: str, tensors: np.ndarray, value: Any) -> None:
    """Raise unless every tensor ``[..., 3, 3]`` is symmetric, positive definite and has
    principal moments a mass distribution can have (I1 + I2 >= I3)."""
    if not np.allclose(tensors, np.swapaxes(tensors, -1, -2), rtol=1e-9, atol=0.0):
        raise CraftError(f"{where}: inertia_kgm2 tensor must be symmetric, got {value!r}")
    moments = np.linalg.eigvalsh(tensors)
    if np.any(moments[..., 0] <= 0.0):
        raise CraftError(f"{where}: inertia_kgm2 must be positive definite, got {value!r}")
    bad = moments[..., 0] + moments[..., 1] < moments[..., 2] * (1.0 - 1e-9)
    if np.any(bad):
        first = moments[np.nonzero(bad)][0] if moments.ndim > 1 else moments
        raise CraftError(
            f"{where}: inertia_kgm2 principal moments {first.tolist()} break the triangle "
            "inequality I1 + I2 >= I3: no mass distribution has them"
        )


def _inertia_tensor(where: str, value: Any) -> np.ndarray:
    try:  # refuses strings, bools, None and ragged lists, naming the value
        arr = CK.real_array(where, "inertia_kgm2", value, error=CraftError)
    except CraftError:
        arr = None
    if arr is None or arr.shape not in ((3,), (3, 3)) or not np.all(np.isfinite(arr)):
        raise CraftError(
            f"{where}: inertia_kgm2 must be 3 principal moments or a 3x3 tensor, got {value!r}"
        )
    tensor = np.diag(arr) if arr.shape == (3,) else arr
    check_inertia(where, tensor, value)  # a real mass distribution has I1 + I2 >= I3
    return tensor


@dataclass(frozen=True)
class Craft:
    """A rigid body with the samples, controls and thrusters it carries.

    Examples:
        >>> box = Craft(name="box", mass_kg=1.0, inertia_kgm2=(1.0, 2.0, 3.0))
        >>> box.control_names
        ()
        >>> glider = Craft.load("paper_airplane")
        >>> glider.control_names
        ('aileron', 'elevator', 'rudder')
    """

    name: str
    mass_kg: float
    inertia_kgm2: tuple
    plates: tuple[Plate, ...] = ()
    cylinders: tuple[Cylinder, ...] = ()
    buoyancy: tuple[Buoyancy, ...] = ()
    thrusters: tuple[Thruster, ...] = ()
    controls: tuple[Control, ...] = ()
    shapes: tuple[Shape, ...] = ()
    restitution: float = 0.5
    friction: float = 0.5
    # the speed and turn rate past which the craft has run away (the step flags it: ends its
    # episode ``physics_diverged``), each well above what it reaches in flight; inf: none of
    # its own, the fluid clamp alone (World.max_fluid_speed_mps)
    runaway_speed_mps: float = math.inf
    runaway_rate_dps: float = math.inf
    description: str = ""
    # named sets of samples, {name: [sample names]} (``Simulator.set_sample_scale``)
    groups: Any = ()
    _tensor: np.ndarray = field(default=None, repr=False, compare=False)  # type: ignore[assignment]

    def __post_init__(self) -> None:
        where = f"craft {_name('craft', 'name', self.name)!r}"
        _name(where, "description", self.description)
        object.__setattr__(self, "mass_kg", _positive(where, "mass_kg", self.mass_kg))
        for key in ("restitution", "friction"):
            value = _finite(where, key, getattr(self, key))
            if not (0.0 <= value <= (1.0 if key == "restitution" else math.inf)):
                limits = "in [0, 1]" if key == "restitution" else ">= 0"
                raise CraftError(f"{where}: {key} must be {limits}, got {value!r}")
            object.__setattr__(self, key, value)
        for key in ("runaway_speed_mps", "runaway_rate_dps"):
            value = getattr(self, key)
            if not (isinstance(value, int | float) and not isinstance(value, bool) and value > 0):
                raise CraftError(f"{where}: {key} must be a number > 0 (inf: none), got {value!r}")
            object.__setattr__(self, key, float(value))
        tensor = _inertia_tensor(where, self.inertia_kgm2)
        tensor.setflags(write=False)
        object.__setattr__(self, "_tensor", tensor)
        inertia = np.asarray(self.inertia_kgm2, dtype=float)
        as_tuple = (
            tuple(map(tuple, inertia.tolist())) if inertia.ndim == 2 else tuple(inertia.tolist())
        )
        object.__setattr__(self, "inertia_kgm2", as_tuple)
        for key, cls in (
            ("plates", Plate),
            ("cylinders", Cylinder),
            ("buoyancy", Buoyancy),
            ("thrusters", Thruster),
            ("controls", Control),
            ("shapes", Shape),
        ):
            object.__setattr__(self, key, self._parts(where, key, cls))
        self._check_references(where)
        object.__setattr__(self, "groups", self._check_groups(where, self.groups))

    @property
    def runaway(self) -> tuple[float, float]:
        """(speed m/s, turn rate rad/s) past which the craft has run away (inf: none)."""
        return self.runaway_speed_mps, math.radians(self.runaway_rate_dps)

    def _parts(self, where: str, key: str, cls: type) -> tuple:
        """Field ``key``: a list of ``cls`` or of tables of its fields, as a tuple of ``cls``;
        errors name the table path (``plates[2].area_m2``) and the value."""
        items = getattr(self, key)
        if not isinstance(items, (list, tuple)):
            raise CraftError(
                f"{where}: {key} must be a list of tables ([[{key}]] in a file) or of "
                f"{cls.__name__}s, got {CK.show(items)}"
            )
        parts = []
        for i, item in enumerate(items):
            if not isinstance(item, cls):
                _check_table(where, f"{key}[{i}]", item, cls)
                try:
                    item = cls(**item)
                except CraftError as err:  # a value out of range: say where it is
                    raise CraftError(f"{where}: {key}[{i}]: {err}") from None
            parts.append(item)
        return tuple(parts)

    def _check_groups(self, where: str, groups: Any) -> tuple[tuple[str, tuple[str, ...]], ...]:
        """Groups as ``((name, (sample, ...)), ...)``: hashable, like the rest of a Craft."""
        pairs = list(groups.items()) if isinstance(groups, dict) else groups
        ok = isinstance(pairs, (list, tuple))
        if not (ok and all(isinstance(p, (list, tuple)) and len(p) == 2 for p in pairs)):
            raise CraftError(
                f"{where}: groups must be a table {{name = [sample, ...]}}, got {CK.show(groups)}"
            )
        samples = [s.name for s in (*self.plates, *self.cylinders, *self.buoyancy, *self.thrusters)]
        out = []
        for name, members in pairs:
            if not isinstance(name, str) or name in samples:
                raise CraftError(f"{where}: group name {name!r} must be a string, not a sample's")
            ok = isinstance(members, (list, tuple)) and all(isinstance(m, str) for m in members)
            if not (ok and members):
                raise CraftError(
                    f"{where}: groups.{name} must list sample names, got {CK.show(members)}"
                )
            unknown = [m for m in members if m not in samples]
            if unknown:
                raise CraftError(
                    f"{where}: group {name!r} names unknown samples {unknown}; samples are "
                    f"{samples}"
                )
            out.append((name, tuple(members)))
        return tuple(out)

    def _check_references(self, where: str) -> None:
        names = [s.name for s in (*self.plates, *self.cylinders, *self.buoyancy, *self.thrusters)]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise CraftError(f"{where}: sample names must be unique, repeated: {dup}")
        shapes = [s.name for s in self.shapes]
        dup = sorted({n for n in shapes if shapes.count(n) > 1})
        if dup:
            raise CraftError(f"{where}: shape names must be unique, repeated: {dup}")
        channels = [c.name for c in self.controls]
        if len(set(channels)) != len(channels):
            raise CraftError(f"{where}: control names must be unique, got {channels}")
        plates = {p.name: p for p in self.plates}
        for c in self.controls:
            for s in c.surfaces:
                if s.sample not in plates:
                    raise CraftError(
                        f"{where}: control {c.name!r} drives {s.sample!r}, which is "
                        f"not a plate; plates are {sorted(plates)}"
                    )
                if plates[s.sample].hinge_axis is None:
                    raise CraftError(
                        f"{where}: plate {s.sample!r} is driven by control "
                        f"{c.name!r} but has no hinge_axis"
                    )
        for t in self.thrusters:
            if t.control is not None and t.control not in channels:
                raise CraftError(
                    f"{where}: thruster {t.name!r} is bound to unknown control "
                    f"{t.control!r}; controls are {channels}"
                )

    # ---- derived quantities -------------------------------------------------------------

    @property
    def control_names(self) -> tuple[str, ...]:
        """The control channels in order: the columns of the action this craft takes."""
        return tuple(c.name for c in self.controls)

    @property
    def inertia_tensor(self) -> np.ndarray:
        """The body-frame inertia tensor about the center of mass, 3x3 (kg m^2), read-only."""
        return self._tensor

    @property
    def num_samples(self) -> int:
        return len(self.plates) + len(self.cylinders) + len(self.buoyancy) + len(self.thrusters)

    def with_center_of_mass(self, offset_m) -> Craft:
        """The same craft with its center of mass moved by ``offset_m`` (body frame, m), as by
        ballast of negligible mass: every sample and collision shape keeps its place on the
        airframe, so its offset from the new center of mass shrinks by ``offset_m``; mass and
        inertia are kept.

        Examples:
            >>> tail_heavy = Craft.load("paper_airplane").with_center_of_mass((-0.02, 0, 0))
            >>> tail_heavy.plates[0].offset_m[0]  # left wing, was 0.012 m behind the CG
            0.008
        """
        dx = _vec3(f"craft {self.name!r}", "offset_m", offset_m)

        def moved(items, key="offset_m"):
            def shift(v):
                return tuple(float(a) for a in shift_offsets(v, dx))

            return tuple(replace(s, **{key: shift(getattr(s, key))}) for s in items)

        return replace(
            self,
            plates=moved(self.plates),
            cylinders=moved(self.cylinders),
            buoyancy=moved(self.buoyancy),
            thrusters=moved(self.thrusters),
            shapes=moved(self.shapes, key="center_m"),
        )

    # ---- loading ------------------------------------------------------------------------

    @classmethod
    def from_dict(cls, data: dict, source: str = "<dict>") -> Craft:
        """Validate a parsed craft file; errors name the file, the part and the value."""
        if not isinstance(data, dict):
            raise CraftError(f"{source}: expected a table at the top level")
        valid = [f.name for f in fields(cls) if not f.name.startswith("_")]
        unknown = sorted(set(data) - set(valid))
        if unknown:
            raise CraftError(f"{source}: unknown key(s) {unknown}; valid keys are {valid}")
        missing = [k for k in ("name", "mass_kg", "inertia_kgm2") if k not in data]
        if missing:
            raise CraftError(f"{source}: missing required key(s) {missing}")
        try:
            return cls(**data)
        except CraftError as err:
            raise CraftError(f"{source}: {err}") from None

    @classmethod
    def load(cls, name_or_path: str | Path) -> Craft:
        """Load a shipped craft by name (see :func:`available`) or a TOML file by path."""
        path = Path(name_or_path)
        if path.suffix != ".toml":
            shipped = resources.files("fluidsim_envs.craft") / f"{name_or_path}.toml"
            if not shipped.is_file():
                raise CraftError(
                    f"unknown craft {str(name_or_path)!r}; shipped crafts are "
                    f"{available()} (or pass a path to a .toml file)"
                )
            text, source = shipped.read_text(), f"{name_or_path}.toml"
        else:
            if not path.is_file():
                raise CraftError(f"craft file {str(path)!r} does not exist")
            text, source = path.read_text(), str(path)
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as err:
            raise CraftError(f"{source}: not valid TOML: {err}") from None
        return cls.from_dict(data, source)


def available() -> list[str]:
    """Names of the crafts shipped in ``fluidsim_envs/craft/``."""
    root = resources.files("fluidsim_envs.craft")
    return sorted(p.name[:-5] for p in root.iterdir() if p.name.endswith(".toml"))
