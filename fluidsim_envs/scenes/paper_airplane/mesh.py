"""The paper dart's render mesh: a folded delta with a keel below and a fin above, its
ailerons, elevators and rudder hinged to the plates the physics turns.

Sizes come from the craft (``paper_airplane.toml``): the delta fills the collision boxes'
extent (nose to trailing edge, tip to tip, keel depth), each trailing-edge flap is centered on
its plate's span station, the fin's centroid sits at its plate and its height is twice the
plate's height. The flap chord is the one drawing choice: the plates' areas lump the surface
around them, and cut to those areas the flaps would outgrow the wing.
"""

from __future__ import annotations

import numpy as np

from ...physics import Craft
from ..mesh import PAPER, Part, RenderMesh, panel

FLAP_CHORD_M = 0.02  # a folded-up tab at the trailing edge, as on a real paper dart
AILERON, ELEVATOR, RUDDER = (245, 160, 110), (120, 170, 240), (120, 200, 120)
TINTS = {"aileron": AILERON, "elevator": ELEVATOR, "rudder": RUDDER}


def dart_mesh(craft: Craft) -> RenderMesh:
    """The folded dart of ``craft``: wing halves, keel, fin and the hinged flaps."""
    lo = np.min([np.subtract(s.center_m, s.half_extents_m) for s in craft.shapes], axis=0)
    hi = np.max([np.add(s.center_m, s.half_extents_m) for s in craft.shapes], axis=0)
    nose, tail, tip, keel = float(hi[0]), float(lo[0]), float(hi[1]), float(lo[2])
    hinge = tail + FLAP_CHORD_M

    def edge(x: float) -> float:  # the leading edge's half-span at x: straight nose to tip
        return tip * (nose - x) / (nose - tail)

    plates = {p.name: p for p in craft.plates}
    tint = {s.sample: TINTS.get(c.name, PAPER) for c in craft.controls for s in c.surfaces}
    flaps = [p for p in craft.plates if p.hinge_axis is not None and abs(p.hinge_axis[1]) > 0.9]
    parts = []
    for side in (1.0, -1.0):
        own = [p for p in flaps if p.offset_m[1] * side > 0]
        own.sort(key=lambda p: abs(p.offset_m[1]))
        bounds = _spans([abs(p.offset_m[1]) for p in own], tip)
        root, outer = (bounds[0][0], bounds[-1][1]) if own else (edge(hinge), edge(hinge))
        y_edge, y_root, y_outer, y_tip = (side * y for y in (edge(hinge), root, outer, tip))
        name = "left" if side > 0 else "right"
        # ahead of the hinge line, a triangle; behind it, the flaps between a strip at the
        # root and a sliver at the tip
        h, t = hinge, tail
        parts += [
            panel(f"{name}_wing", [(nose, 0, 0), (h, 0, 0), (h, y_edge, 0)]),
            panel(f"{name}_root", [(h, 0, 0), (h, y_root, 0), (t, y_root, 0), (t, 0, 0)]),
            panel(f"{name}_tip", [(h, y_outer, 0), (h, y_edge, 0), (t, y_tip, 0), (t, y_outer, 0)]),
        ]
        for p, (y0, y1) in zip(own, bounds, strict=True):
            parts.append(_flap(p, hinge, side * y0, side * y1, tint.get(p.name, PAPER)))
    # the keel: the two folded layers as one sheet, deepest aft, rising to the nose
    chin = nose - 0.75 * (nose - tail)
    parts.append(panel("keel", [(nose, 0, 0), (tail, 0, 0), (tail, 0, keel), (chin, 0, keel)]))
    parts += _tail(craft, plates, hinge, tail, tint)
    return RenderMesh(craft, tuple(parts))


def _spans(stations: list[float], tip: float) -> list[tuple[float, float]]:
    """Spanwise (inner, outer) edges of flaps centered on ``stations`` (ascending): they meet
    halfway between neighbours and end as far beyond their station as they begin before it
    (the outermost one short of the tip)."""
    if not stations:
        return []
    mids = [0.5 * (a + b) for a, b in zip(stations[:-1], stations[1:], strict=True)]
    first = 2.0 * stations[0] - (mids[0] if mids else stations[0] + 0.2 * tip)
    last = min(2.0 * stations[-1] - (mids[-1] if mids else first), tip)
    edges = [max(first, 0.0), *mids, last]
    return list(zip(edges[:-1], edges[1:], strict=True))


def _flap(plate, hinge_x: float, y0: float, y1: float, color) -> Part:
    """A trailing-edge flap in its plate's plane: the hinge line at ``hinge_x`` from ``y0``
    to ``y1``, reaching aft one chord."""
    n = np.asarray(plate.normal, dtype=np.float64)
    aft = np.array([-1.0, 0.0, 0.0]) + n[0] * n  # body -x, in the plate's plane
    aft *= FLAP_CHORD_M / np.linalg.norm(aft)
    a, b = np.array([hinge_x, y0, 0.0]), np.array([hinge_x, y1, 0.0])
    return panel(plate.name, [a, b, b + aft, a + aft], color, n, plate.name, (hinge_x, 0.0, 0.0))


def _tail(craft: Craft, plates: dict, hinge_x: float, tail_x: float, tint: dict) -> list[Part]:
    """The fin (above the keel, its centroid at the fin plate) and the rudders behind it: the
    hinged plates on the centerline that turn about body z."""
    rudders = [
        p
        for p in craft.plates
        if p.hinge_axis is not None and abs(p.hinge_axis[2]) > 0.9 and p.offset_m[1] == 0.0
    ]
    parts = []
    for r in rudders:
        height = 2.0 * r.offset_m[2]
        corners = [(hinge_x, 0, 0), (hinge_x, 0, height), (tail_x, 0, height), (tail_x, 0, 0)]
        parts.append(
            panel(r.name, corners, tint.get(r.name, PAPER), r.normal, r.name, (hinge_x, 0, 0))
        )
    fins = [
        p
        for p in plates.values()
        if p.hinge_axis is None and abs(p.normal[1]) > 0.9 and p.offset_m[1] == 0.0
    ]
    for f in fins:
        height = 2.0 * f.offset_m[2]
        lead = 3.0 * f.offset_m[0] - 2.0 * hinge_x  # a triangle's centroid is its mean corner
        parts.append(panel(f.name, [(lead, 0, 0), (hinge_x, 0, 0), (hinge_x, 0, height)]))
    return parts


def meshes(venv) -> tuple[RenderMesh, ...]:
    """PaperAirplane-v0's one body: the dart (``Scene.meshes``)."""
    return (dart_mesh(venv.craft),)


__all__ = ["FLAP_CHORD_M", "dart_mesh", "meshes"]
