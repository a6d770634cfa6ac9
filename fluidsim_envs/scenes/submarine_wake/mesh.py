"""SubmarineWake-v0's render meshes: the UUV (the one simulated body) and the lead submarine
(a scripted wake source that the view and the recordings draw, not a body).

Both are bodies of revolution with cruciform tails, sized from their crafts:

- the UUV's hull is its two cross-flow cylinders end to end (each ``area_m2 = length x
  diameter``, centered at +-length/2), with a rounded nose and a tapered tail cone; its four
  all-moving fins sit in their plates' planes, each hinged at its plate's center (the stock)
  and spanning from the hull out to as far beyond the plate as the hull is inside it;
- the submarine's hull is the wake field's prolate spheroid (the shape the water flows
  around, so the drawn hull and the tracers' flow agree), with the sail and stern planes
  from the craft's plates and a screw disc at each thruster.
"""

from __future__ import annotations

import numpy as np

from ...physics import Craft, WakeField
from ..mesh import Part, RenderMesh, panel, revolve

UUV_HULL, UUV_FIN, PROP = (250, 120, 40), (60, 62, 74), (40, 40, 46)
SUB_HULL, SUB_FIN = (146, 152, 164), (112, 116, 128)
NOSE_SHARE, TAIL_SHARE, TAIL_END = 0.12, 0.2, 0.45  # UUV profile: of the length; of the radius
SAIL_WIDTH_M = 1.2  # the sail's thickness (the plate gives its length and height only)


def uuv_profile(length: float, radius: float, n: int = 9) -> tuple[np.ndarray, np.ndarray]:
    """Stations ``x`` (tail to nose) and radii of a torpedo hull: a cosine-tapered tail cone
    over ``TAIL_SHARE`` of the length down to ``TAIL_END`` of the radius, a cylinder, and an
    elliptic nose over ``NOSE_SHARE``."""
    half = 0.5 * length
    x_tail, x_nose = -half + TAIL_SHARE * length, half - NOSE_SHARE * length
    t = np.linspace(0.0, 1.0, n)
    tail_x = -half + t * (x_tail + half)
    tail_r = radius * (TAIL_END + (1.0 - TAIL_END) * 0.5 * (1.0 - np.cos(np.pi * t)))
    u = np.sin(0.5 * np.pi * t[1:])  # denser toward the tip, where the nose curves most
    nose_x = x_nose + u * (half - x_nose)
    nose_r = radius * np.sqrt(np.clip(1.0 - u**2, 0.0, 1.0))
    return np.concatenate([tail_x, nose_x]), np.concatenate([tail_r, nose_r])


def uuv_mesh(craft: Craft) -> RenderMesh:
    """The torpedo-shaped UUV of ``craft``: hull, hinged fins and the propeller."""
    halves = [c for c in craft.cylinders if abs(c.axis[0]) > 0.9]
    if not halves:
        raise ValueError(f"craft {craft.name!r}: no hull cylinder along body x to draw")
    length = sum(2.0 * abs(c.offset_m[0]) for c in halves)
    radius = 0.5 * halves[0].area_m2 / (2.0 * abs(halves[0].offset_m[0]))
    x, r = uuv_profile(length, radius)
    parts = [revolve("hull", x, r, UUV_HULL, segments=16)]
    parts += _fins(craft, lambda at: float(np.interp(at, x, r)), UUV_FIN)
    parts += _screws(craft, 0.6 * radius)
    return RenderMesh(craft, tuple(parts))


def lead_mesh(craft: Craft, wake: WakeField) -> RenderMesh:
    """The lead submarine: the wake's spheroid hull, the sail and the stern planes of
    ``craft``, and its screws."""
    a, b = 0.5 * wake.length_m, wake.radius_m
    s = np.linspace(-1.0, 1.0, 17)
    x = a * np.sin(0.5 * np.pi * s)  # denser toward the ends, where the spheroid curves most
    r = b * np.sqrt(np.clip(1.0 - (x / a) ** 2, 0.0, 1.0))

    def hull(at: float) -> float:
        return b * float(np.sqrt(max(1.0 - (at / a) ** 2, 0.0)))

    parts = [revolve("hull", x, r, SUB_HULL, segments=16)]
    for p in craft.plates:
        if p.hinge_axis is None and abs(p.normal[1]) > 0.9 and p.offset_m[2] > 0.0:
            parts.append(_sail(p, hull(p.offset_m[0])))
    parts += _fins(craft, hull, SUB_FIN)
    parts += _screws(craft, 0.25 * b)
    return RenderMesh(craft, tuple(parts))


def _fins(craft: Craft, hull, color) -> list[Part]:
    """Each hinged plate off the axis as an all-moving fin: in its plate's plane, from the
    hull (radius ``hull(x)``) out to as far beyond the plate's center as the hull is inside
    it, its chord giving the plate's area, turning about its hinge through the center."""
    parts = []
    for p in craft.plates:
        c = np.asarray(p.offset_m, dtype=np.float64)
        out = c * [0.0, 1.0, 1.0]
        dist = float(np.linalg.norm(out))
        if p.hinge_axis is None or dist == 0.0:
            continue
        out /= dist
        root = min(hull(c[0]), 0.9 * dist)
        span = 2.0 * (dist - root)
        chord = p.area_m2 / span
        fwd = np.array([0.5 * chord, 0.0, 0.0])
        a, b = c - (dist - root) * out, c + (dist - root) * out
        corners = [a - fwd, a + fwd, b + fwd, b - fwd]
        parts.append(panel(p.name, corners, color, p.normal, p.name, tuple(c)))
    return parts


def _sail(plate, base_z: float) -> Part:
    """The sail: a box standing on the hull (``base_z`` at its station), as tall again above
    the plate's center as the hull is below it, its length giving the plate's area."""
    x, _, zc = plate.offset_m
    top = 2.0 * zc - base_z
    half = 0.5 * plate.area_m2 / (top - base_z)
    w = 0.5 * SAIL_WIDTH_M
    lo = -0.5  # sunk into the hull so that no gap shows where the spheroid curves away
    v = np.array(
        [[x + sx * half, sy * w, z] for z in (base_z + lo, top) for sx in (-1, 1) for sy in (-1, 1)]
    )
    # corners: 0 (-x,-y) 1 (-x,+y) 2 (+x,-y) 3 (+x,+y) at the base, +4 at the top
    quads = [(4, 5, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3), (2, 3, 7, 6), (0, 4, 5, 1)]
    tris = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    return Part("sail", v, np.array(tris), SUB_HULL)  # fmt: skip


def _screws(craft: Craft, radius: float) -> list[Part]:
    """A thin disc at each thruster, across its thrust direction."""
    parts = []
    for t in craft.thrusters:
        x, y, z = t.offset_m
        disc = revolve(t.name, [-0.02 * radius, 0.02 * radius], [radius, radius], PROP, 16)
        parts.append(Part(t.name, disc.vertices_m + [x, y, z], disc.triangles, PROP))
    return parts


def meshes(venv) -> tuple[RenderMesh, ...]:
    """SubmarineWake-v0's one body: the UUV (``Scene.meshes``)."""
    return (uuv_mesh(venv.craft),)


__all__ = ["lead_mesh", "meshes", "uuv_mesh", "uuv_profile"]
