"""Crafts drawn from their own data for ``render_mode="rgb_array"``: each plate a square of its
area in its plane, each cylinder a stroke along its axis, seen by a chase camera."""

from __future__ import annotations

import numpy as np

from ..physics import Craft
from .render import Camera, Canvas

PLATE_COLOR = (245, 245, 240)
EDGE_COLOR = (60, 60, 70)


class CraftMesh:
    """Body-frame triangles and strokes of a craft (m)."""

    def __init__(self, craft: Craft) -> None:
        tris = []
        for p in craft.plates:
            n = np.asarray(p.normal)
            u = np.array([1.0, 0.0, 0.0]) - n[0] * n  # along the body x where the plate allows
            if np.linalg.norm(u) < 1e-6:
                u = np.array([0.0, 1.0, 0.0]) - n[1] * n
            u /= np.linalg.norm(u)
            w = np.cross(n, u)
            h = 0.5 * np.sqrt(p.area_m2)
            c = np.asarray(p.offset_m)
            a, b, d, e = c + h * (u + w), c + h * (u - w), c - h * (u + w), c - h * (u - w)
            tris += [(a, b, d), (a, d, e)]
        self.triangles = np.array(tris).reshape(-1, 3, 3)
        strokes = [
            (np.asarray(s.offset_m) - np.sqrt(s.area_m2) * np.asarray(s.axis),
             np.asarray(s.offset_m) + np.sqrt(s.area_m2) * np.asarray(s.axis))
            for s in craft.cylinders
        ]  # fmt: skip
        self.strokes = np.array(strokes).reshape(-1, 2, 3)

    def draw(self, canvas: Canvas, camera: Camera, pos, rot) -> None:
        """Paint the craft at ``pos`` with body-to-world rotation ``rot``."""
        if len(self.triangles):
            world = self.triangles @ rot.T + pos
            canvas.triangles(camera, world, PLATE_COLOR)
            edges = np.concatenate([world[:, [0, 1]], world[:, [1, 2]]])
            canvas.lines(camera, edges[:, 0], edges[:, 1], EDGE_COLOR)
        if len(self.strokes):
            world = self.strokes @ rot.T + pos
            canvas.lines(camera, world[:, 0], world[:, 1], EDGE_COLOR, thickness=2)


def chase_camera(pos, rot, back_m: float, up_m: float, width=480, height=360) -> Camera:
    """A camera ``back_m`` behind the craft along its level heading and ``up_m`` above it."""
    heading = np.array([rot[0, 0], rot[1, 0], 0.0])
    norm = np.linalg.norm(heading)
    heading = heading / norm if norm > 1e-6 else np.array([1.0, 0.0, 0.0])
    eye = pos - back_m * heading + np.array([0.0, 0.0, up_m])
    return Camera.look_at(eye, pos, width=width, height=height, fov_deg=55.0)


def fill_ground(canvas: Canvas, camera: Camera, color) -> None:
    """Paint the image below the horizon (a level camera sees it through the point at
    infinity straight ahead, at eye height)."""
    ahead = camera.rotation[2] * np.array([1.0, 1.0, 0.0])
    if np.linalg.norm(ahead) < 1e-6:  # looking straight down or up: all ground or all sky
        if camera.rotation[2, 2] < 0:
            canvas.fill_rows(0, camera.height, color)
        return
    far = camera.eye + 1e6 * ahead / np.linalg.norm(ahead)
    pixels, depth = camera.project(far[None])
    if depth[0] > camera.near and np.isfinite(pixels[0, 1]):
        canvas.fill_rows(pixels[0, 1], camera.height, color)
