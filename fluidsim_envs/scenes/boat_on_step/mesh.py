"""The speedboat's render mesh: the V-bottom hull closed by its transom and deck, the
windscreen, the outboard, the skeg, and the rudder and trim tabs hinged to their plates.

The hull's lines are :class:`~fluidsim_envs.scenes.boat_on_step.view.HullShape`'s (keel,
chine and sheer at each station of the craft's bottom plates), the very outlines the
elevation draws, so the two pictures of the boat cannot disagree. Each trim tab lies in its
plate's plane from its hinge at the transom (HullShape's hinge and chord); the rudder and
skeg are squares of their plates' areas centered on them, the rudder turning about its
center (an outboard turns its whole leg).
"""

from __future__ import annotations

import math

import numpy as np

from ...physics import Craft
from ..mesh import Part, RenderMesh, panel
from .view import COWL_M, PROP_RADIUS_M, HullShape

TOPSIDES, BOTTOM, DECK = (245, 245, 240), (196, 64, 52), (206, 200, 188)
GLASS, GEAR, TAB = (120, 165, 200), (72, 72, 84), (250, 150, 30)
SCREEN_SHARE = 0.75  # the windscreen's width, of the beam where it stands


def boat_mesh(craft: Craft) -> RenderMesh:
    """The speedboat of ``craft`` (see the module docstring)."""
    shape = HullShape(craft)
    parts = [*_hull(shape), *_screens(shape), *_outboards(craft, shape)]
    plates = {p.name: p for p in craft.plates}
    tabs = [c for c in craft.controls if c.name == "trim_tabs"]
    for s, (hinge, chord, base) in zip(tabs[0].surfaces if tabs else (), shape.tabs, strict=True):
        p = plates[s.sample]
        half = 0.5 * p.area_m2 / chord  # the tab's half-width: its plate's area over its chord
        aft = chord * np.array([-math.cos(base), 0.0, -math.sin(base)])
        side = np.array([0.0, half, 0.0])
        corners = [hinge - side, hinge + side, hinge + side + aft, hinge - side + aft]
        parts.append(panel(p.name, corners, TAB, p.normal, p.name, tuple(hinge)))
    for p in craft.plates:  # skeg and rudder: plates across y on the centerline
        if abs(p.normal[1]) > 0.9 and p.offset_m[1] == 0.0:
            c, h = np.asarray(p.offset_m, dtype=np.float64), 0.5 * math.sqrt(p.area_m2)
            corners = [c + [-h, 0, -h], c + [h, 0, -h], c + [h, 0, h], c + [-h, 0, h]]
            hinged = p.hinge_axis is not None
            parts.append(
                panel(p.name, corners, GEAR, p.normal, p.name if hinged else None, tuple(c))
            )
    return RenderMesh(craft, tuple(parts))


def _hull(shape: HullShape) -> list[Part]:
    """Bottom (keel to chines), topsides (chines up to the sheer) and deck, as three closed-up
    parts wound outward, and the transom."""
    n = len(shape.x)
    x, hb = shape.x, shape.half_beam
    keel = np.stack([x, np.zeros(n), shape.keel_z], 1)
    chine = [np.stack([x, s * hb, shape.chine_z], 1) for s in (1.0, -1.0)]
    sheer = [np.stack([x, s * hb, np.full(n, shape.sheer_z)], 1) for s in (1.0, -1.0)]
    bottom = _band(chine[0], keel) + _band(keel, chine[1])
    sides = _band(sheer[0], chine[0]) + _band(chine[1], sheer[1])
    deck = _band(sheer[1], sheer[0])
    (k, cp, cs, sp, ss) = (keel[0], chine[0][0], chine[1][0], sheer[0][0], sheer[1][0])
    transom = [np.array([k, ss, sp, cp]), np.array([k, cs, ss, ss])]  # facing aft
    return [
        _solid("bottom", bottom, BOTTOM),
        _solid("topsides", sides, TOPSIDES),
        _solid("deck", deck, DECK),
        _solid("transom", transom, TOPSIDES),
    ]


def _band(a: np.ndarray, b: np.ndarray) -> list[np.ndarray]:
    """Quads between two lines running stern to stem, ``b`` a quarter turn clockwise from
    ``a`` about body x (seen from ahead): their right-hand normals point out of the hull."""
    return [np.array([a[i], a[i + 1], b[i + 1], b[i]]) for i in range(len(a) - 1)]


def _solid(name: str, quads: list[np.ndarray], color) -> Part:
    """Quads (corners in order, normals out) as one part of the closed hull, two triangles
    each."""
    verts = np.concatenate(quads)
    tris = [[4 * k, 4 * k + 1, 4 * k + 2] for k in range(len(quads))]
    tris += [[4 * k, 4 * k + 2, 4 * k + 3] for k in range(len(quads))]
    return Part(name, verts, np.array(tris), color, closed=True)


def _screens(shape: HullShape) -> list[Part]:
    """Each windscreen: from the sheer up to its sample's height, raked aft, across most of
    the beam where it stands."""
    parts = []
    for k, (foot, top) in enumerate(shape.screens):
        w = SCREEN_SHARE * float(np.interp(foot[0], shape.x, shape.half_beam))
        y = np.array([0.0, w, 0.0])
        parts.append(panel(f"windscreen_{k}", [foot - y, foot + y, top + y, top - y], GLASS))
    return parts


def _outboards(craft: Craft, shape: HullShape) -> list[Part]:
    """Each outboard: a cowl over the transom, a leg down to its thruster, a propeller
    disc across the thrust."""
    parts = []
    for k, t in enumerate(craft.thrusters):
        x, y, z = t.offset_m
        cowl = np.array([x, y, shape.sheer_z + 0.5 * COWL_M])
        parts.append(_box(f"cowl_{k}", cowl, (COWL_M, 0.6 * COWL_M, COWL_M), GEAR))
        leg = np.array([x, y, 0.5 * (z + shape.sheer_z)])
        parts.append(_box(f"leg_{k}", leg, (0.12, 0.06, shape.sheer_z - z), GEAR))
        r = PROP_RADIUS_M
        blade = [(x, y - r, z), (x, y, z - r), (x, y + r, z), (x, y, z + r)]
        parts.append(panel(f"propeller_{k}", blade, GEAR, t.direction))
    return parts


def _box(name: str, center, size, color) -> Part:
    """An axis-aligned box, wound outward."""
    c, h = np.asarray(center, dtype=np.float64), 0.5 * np.asarray(size, dtype=np.float64)
    v = c + h * np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    # corner index = 4 (x > 0) + 2 (y > 0) + (z > 0)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = [t for a, b, c_, d in quads for t in ((a, b, c_), (a, c_, d))]
    return Part(name, v, np.array(tris), color, closed=True)


def meshes(venv) -> tuple[RenderMesh, ...]:
    """BoatOnStep-v0's one body: the speedboat (``Scene.meshes``)."""
    return (boat_mesh(venv.craft),)


__all__ = ["boat_mesh", "meshes"]
