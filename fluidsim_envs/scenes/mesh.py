"""A craft's render mesh: the triangles the rgb_array frames and the Rerun recordings draw, in
the body frame, with its control surfaces turning as the physics turns their plates.

The mesh is drawing, not physics: it does not enter any force. What moves it comes from the
craft's own data, so that a picture cannot disagree with the simulation: a hinged part names
the plate it draws (``Part.sample``), and its deflection is the one the physics gives that
plate, ``sum over channels of gain * command * max_deflection_deg`` about the plate's
``hinge_axis`` (right-hand rule; :class:`~fluidsim_envs.physics.craft.Control`).

A scene builds its crafts' meshes (``Scene.meshes``); :meth:`RenderMesh.from_craft` is the
fallback any craft has: a thin square per plate, hinged ones turning.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ..physics import Craft
from ..physics.model import surface_mix

PAPER = (245, 245, 240)


@dataclass(frozen=True)
class Part:
    """A rigid piece of a render mesh: triangles of one color, in the body frame (m).

    A part with ``sample`` set is a control surface: it turns about the line through
    ``hinge_point_m`` along that plate's ``hinge_axis`` by the plate's deflection. A
    ``closed`` part is a solid whose triangles are wound with their right-hand normals
    outward, so that a renderer may skip those facing away (a thin sheet is seen from both
    sides).
    """

    name: str
    vertices_m: np.ndarray  # [V, 3]
    triangles: np.ndarray  # [T, 3] vertex indices
    color: tuple[int, int, int] = PAPER
    sample: str | None = None
    hinge_point_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    closed: bool = False

    def __post_init__(self) -> None:
        v = np.asarray(self.vertices_m, dtype=np.float64)
        t = np.asarray(self.triangles, dtype=np.int64)
        if v.ndim != 2 or v.shape[1] != 3 or not np.isfinite(v).all():
            raise ValueError(f"part {self.name!r}: vertices_m must be finite [V, 3]")
        if t.ndim != 2 or t.shape[1] != 3 or t.size and (t.min() < 0 or t.max() >= len(v)):
            raise ValueError(f"part {self.name!r}: triangles must index its {len(v)} vertices")
        object.__setattr__(self, "vertices_m", v)
        object.__setattr__(self, "triangles", t)


@dataclass(frozen=True)
class RenderMesh:
    """The parts of one body's mesh, bound to its craft's control channels.

    :meth:`posed` gives the whole mesh for one set of channel commands: vertices ``[V, 3]``
    (body frame), triangles ``[T, 3]`` and one color per triangle ``[T, 3]`` (uint8). The
    triangles and colors never change; only a hinged part's vertices do.
    """

    craft: Craft
    parts: tuple[Part, ...]
    # per hinged part: (its slice of the vertices, hinge point, unit axis, rad per channel)
    _hinges: tuple = field(init=False, repr=False)
    _vertices: np.ndarray = field(init=False, repr=False)
    _triangles: np.ndarray = field(init=False, repr=False)
    _colors: np.ndarray = field(init=False, repr=False)
    _closed: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        plates = {p.name: p for p in self.craft.plates}
        mix = surface_mix(self.craft)  # the physics' own deflection per channel (rad)
        hinges, start = [], 0
        for part in self.parts:
            stop = start + len(part.vertices_m)
            if part.sample is not None:
                plate = plates.get(part.sample)
                if plate is None or plate.hinge_axis is None:
                    raise ValueError(
                        f"part {part.name!r}: sample {part.sample!r} is not a hinged plate of "
                        f"craft {self.craft.name!r}"
                    )
                rad = mix.get(part.sample, np.zeros(len(self.craft.controls)))
                axis = np.asarray(plate.hinge_axis, dtype=np.float64)
                point = np.asarray(part.hinge_point_m, dtype=np.float64)
                hinges.append((slice(start, stop), point, axis, rad))
            start = stop
        offsets = np.cumsum([0] + [len(p.vertices_m) for p in self.parts[:-1]])
        fixed = {  # what never changes, built once
            "_hinges": tuple(hinges),
            "_vertices": np.concatenate([p.vertices_m for p in self.parts]),
            "_triangles": np.concatenate(
                [p.triangles + o for p, o in zip(self.parts, offsets, strict=True)]
            ),
            "_colors": np.concatenate(
                [np.tile(np.uint8(p.color), (len(p.triangles), 1)) for p in self.parts]
            ),
            "_closed": np.concatenate([np.full(len(p.triangles), p.closed) for p in self.parts]),
        }
        for name, value in fixed.items():
            if isinstance(value, np.ndarray):
                value.flags.writeable = False
            object.__setattr__(self, name, value)

    @property
    def triangles(self) -> np.ndarray:
        """``[T, 3]`` indices into :meth:`posed`'s vertices (read-only)."""
        return self._triangles

    @property
    def colors(self) -> np.ndarray:
        """``[T, 3]`` uint8: each triangle's part color (read-only)."""
        return self._colors

    @property
    def closed(self) -> np.ndarray:
        """``[T]`` bool: each triangle's part is ``closed`` (its back faces never show)."""
        return self._closed

    @property
    def hinged(self) -> bool:
        """Whether any part moves with the controls (else :meth:`posed` is constant)."""
        return bool(self._hinges)

    def posed(self, commands: ArrayLike | None = None) -> np.ndarray:
        """Vertices ``[V, 3]`` (body frame, m) with each control surface turned by
        ``commands`` (the craft's channels, in [-1, 1]; None: all centered)."""
        v = self._vertices.copy()
        if commands is None or not self._hinges:
            return v
        c = np.asarray(commands, dtype=np.float64)
        for where, point, axis, rad in self._hinges:
            angle = float(rad @ c)
            if angle != 0.0:
                v[where] = point + (v[where] - point) @ _rotation(axis, angle).T
        return v

    @classmethod
    def from_craft(cls, craft: Craft, color=PAPER) -> RenderMesh:
        """The fallback: each plate a square of its area in its plane (hinged ones turning
        about their center line), each cylinder a thin square prism along its axis."""
        parts = []
        for p in craft.plates:
            n = np.asarray(p.normal)
            u = _along(n, p.hinge_axis)
            w = np.cross(n, u)
            h = 0.5 * np.sqrt(p.area_m2)
            c = np.asarray(p.offset_m)
            quad = np.array([c + h * (u + w), c + h * (u - w), c - h * (u + w), c - h * (u - w)])
            hinged = p.hinge_axis is not None and _driven(craft, p.name)
            # wound to face along the plate's normal, as a posed control surface must
            parts.append(panel(p.name, quad, color, n, p.name if hinged else None, tuple(c)))
        for s in craft.cylinders:
            a = np.asarray(s.axis)
            half = np.sqrt(s.area_m2)
            r = 0.1 * half
            u = _along(a, None)
            w = np.cross(a, u)
            ring = [r * (np.cos(t) * u + np.sin(t) * w) for t in np.arange(4) * np.pi / 2]
            c = np.asarray(s.offset_m)
            verts = np.array([c - half * a + q for q in ring] + [c + half * a + q for q in ring])
            tris = [[k, (k + 1) % 4, 4 + (k + 1) % 4] for k in range(4)]
            tris += [[k, 4 + (k + 1) % 4, 4 + k] for k in range(4)]
            parts.append(Part(s.name, verts, tris, color))
        return cls(craft, tuple(parts))


def _driven(craft: Craft, sample: str) -> bool:
    return any(s.sample == sample for c in craft.controls for s in c.surfaces)


def _along(n: np.ndarray, hint) -> np.ndarray:
    """A unit vector across ``n``: along ``hint`` if given, else along body x (or y)."""
    for guess in ((hint,) if hint is not None else ()) + ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0)):
        u = np.asarray(guess, dtype=np.float64)
        u = u - (u @ n) * n
        if np.linalg.norm(u) > 1e-6:
            return u / np.linalg.norm(u)
    raise ValueError(f"no direction across {n}")


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """The rotation matrix of ``angle`` (rad) about the unit ``axis`` (Rodrigues)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)


def craft_meshes(venv) -> tuple[RenderMesh, ...]:
    """The fallback meshes of a vector env's bodies (``Scene.meshes``' default)."""
    return tuple(RenderMesh.from_craft(c) for c in venv.sim.crafts)


def body_commands(sim, env_index: int) -> list[np.ndarray]:
    """Each body's channel commands in sub-env ``env_index`` (``sim.controls`` holds all the
    bodies' channels end to end, in ``sim.crafts`` order): what :meth:`RenderMesh.posed`
    takes."""
    return split_by_body(sim.crafts, sim.controls[env_index])


def split_by_body(crafts, commands) -> list[np.ndarray]:
    """One environment's ``commands`` (all bodies' channels end to end) cut into each
    craft's."""
    ends = np.cumsum([len(c.control_names) for c in crafts])
    return np.split(np.asarray(commands, dtype=np.float64), ends[:-1])


# ---- building parts ------------------------------------------------------------------------


def panel(
    name: str,
    corners: ArrayLike,
    color=PAPER,
    normal: ArrayLike | None = None,
    sample: str | None = None,
    hinge_point_m=(0.0, 0.0, 0.0),
) -> Part:
    """A flat convex polygon (``corners [K, 3]`` in order around it) as a fan of triangles,
    wound so that its right-hand normal points along ``normal`` when given (a control
    surface drawn with its plate's normal)."""
    c = np.asarray(corners, dtype=np.float64)
    fan = np.array([[0, k, k + 1] for k in range(1, len(c) - 1)])
    if normal is not None:
        n = np.cross(c[1] - c[0], c[2] - c[0])
        if n @ np.asarray(normal, dtype=np.float64) < 0.0:
            fan = fan[:, ::-1]
    return Part(name, c, fan, color, sample, tuple(float(v) for v in hinge_point_m))


def revolve(name: str, x: ArrayLike, r: ArrayLike, color, segments: int = 24) -> Part:
    """A body of revolution about the body x axis: the profile ``r(x)`` (stations from tail
    to nose) turned through ``segments`` sides; an end with r = 0 closes to a point, one with
    r > 0 gets a flat cap."""
    x = np.asarray(x, dtype=np.float64)
    r = np.asarray(r, dtype=np.float64)
    if x.ndim != 1 or x.shape != r.shape or len(x) < 2 or (r < 0).any():
        raise ValueError(f"part {name!r}: x and r must be matching profiles (r >= 0)")
    t = 2.0 * np.pi * np.arange(segments) / segments
    ring = np.stack([np.zeros(segments), np.cos(t), np.sin(t)], 1)
    verts = (x[:, None, None] * [1.0, 0.0, 0.0] + r[:, None, None] * ring).reshape(-1, 3)
    tris = []
    for i in range(len(x) - 1):
        a, b = i * segments, (i + 1) * segments
        for k in range(segments):
            k1 = (k + 1) % segments
            if r[i] > 0.0:  # not from a point (each triangle would have two corners there)
                tris.append([a + k, a + k1, b + k1])
            if r[i + 1] > 0.0:
                tris.append([a + k, b + k1, b + k])
    for end in (0, len(x) - 1):  # flat caps (a fan about the ring's first vertex)
        if r[end] > 0.0:
            o = end * segments
            fan = [[o, o + k, o + k + 1] for k in range(1, segments - 1)]
            tris += [f[::-1] for f in fan] if end == 0 else fan  # facing out: aft, forward
    return Part(name, verts, np.array(tris), color, closed=True)


__all__ = ["Part", "RenderMesh", "body_commands", "craft_meshes", "panel", "revolve"]
