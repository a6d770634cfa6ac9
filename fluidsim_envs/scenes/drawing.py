"""What the scenes' rgb_array frames share: a craft's render mesh drawn at its pose (shaded,
with its shadow), cameras that follow a craft, the ground, and the on-screen readout."""

from __future__ import annotations

import math

import numpy as np

from .mesh import RenderMesh
from .render import Camera, Canvas, text_size

PLATE_COLOR = (245, 245, 240)
EDGE_COLOR = (60, 60, 70)
HUD_BACK, HUD_TEXT = (20, 24, 32), (240, 240, 235)


def place(mesh: RenderMesh, commands, pos, rot) -> np.ndarray:
    """The world vertices ``[V, 3]`` of ``mesh`` posed by ``commands`` (its craft's channels)
    at ``pos`` with body-to-world rotation ``rot``."""
    return mesh.posed(commands) @ np.asarray(rot).T + np.asarray(pos)


def draw_mesh(
    canvas: Canvas, camera: Camera, mesh: RenderMesh, commands, pos, rot, shadow_z=None
) -> None:
    """Paint ``mesh`` (shaded, depth-tested) at ``pos``/``rot`` with its control surfaces at
    ``commands``; with ``shadow_z``, first its shadow straight down on the plane z =
    ``shadow_z`` (a sun overhead: the shadow marks the point below the craft, the height cue
    a viewer reads)."""
    world = place(mesh, commands, pos, rot)
    if shadow_z is not None:
        canvas.shadow(camera, world[mesh.triangles], plane_z=shadow_z)
    canvas.mesh(camera, world, mesh.triangles, mesh.colors, closed=mesh.closed)


def framing_camera(
    pos,
    vel,
    goals,
    back_m: float,
    above_deg: float,
    fov_deg: tuple[float, float] = (55.0, 90.0),
    min_eye_z: float | None = None,
    width: int = 480,
    height: int = 360,
) -> Camera:
    """A chase camera that keeps the craft (at ``pos``, moving at ``vel``) and the points
    ``goals`` ``[K, 3]`` in view.

    It sits ``back_m`` away on the side away from the first goal (behind the craft along
    its track when over it), ``above_deg`` above the craft's flight path (so that a diving
    craft is still seen from above, not edge-on), and looks along the mean of the
    directions to the craft and the goals. The wider they spread, the wider its field of
    view, from ``fov_deg[0]`` up to ``fov_deg[1]``; past that it backs off. Both change
    smoothly with the geometry, so that a video neither jumps nor pumps. ``min_eye_z`` keeps
    it above the ground. A diverged (non-finite) craft gets a camera that draws nothing.
    """
    pos, vel = np.asarray(pos, dtype=np.float64), np.asarray(vel, dtype=np.float64)
    points = np.concatenate([pos[None], np.asarray(goals, dtype=np.float64).reshape(-1, 3)])
    if not (np.isfinite(points).all() and np.isfinite(vel).all()):
        return Camera.look_at(np.full(3, np.nan), np.zeros(3), width=width, height=height)
    track = vel * [1.0, 1.0, 0.0]
    speed = float(np.linalg.norm(track))
    track = track / speed if speed > 1e-6 else np.array([1.0, 0.0, 0.0])
    away = (pos - points[min(1, len(points) - 1)]) * [1.0, 1.0, 0.0]
    dist = float(np.linalg.norm(away))
    # far from the goal: behind the craft as seen from the goal; near it: behind the craft
    back = away / max(dist, 1e-9) * min(dist / 2.0, 1.0) - 0.5 * track
    if not np.linalg.norm(back) > 1e-6:
        back = -track
    back /= np.linalg.norm(back)
    climb = math.degrees(math.atan2(vel[2], speed)) if speed > 1e-6 else 0.0
    up = math.radians(min(max(above_deg - climb, 10.0), 80.0))
    offset = back_m * (math.cos(up) * back + [0.0, 0.0, math.sin(up)])

    def eye_at(scale: float) -> np.ndarray:
        eye = pos + scale * offset
        if min_eye_z is not None:
            eye[2] = max(eye[2], min_eye_z)
        return eye

    def aim(eye: np.ndarray) -> tuple[np.ndarray, float]:  # the look direction, the spread
        rays = points - eye
        rays /= np.maximum(np.linalg.norm(rays, axis=1, keepdims=True), 1e-12)
        look = _unit(rays.sum(axis=0))
        return look, 2.0 * math.degrees(math.acos(min(max((rays @ look).min(), -1.0), 1.0)))

    # each point within 3/4 of the half field of view from the center (it is wider across)
    fit = 1.0 / 0.75
    scale = 1.0
    if aim(eye_at(1.0))[1] * fit > fov_deg[1]:  # backing off narrows the spread: bisect
        lo, hi = 1.0, 8.0
        for _ in range(12):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if aim(eye_at(mid))[1] * fit > fov_deg[1] else (lo, mid)
        scale = hi
    eye = eye_at(scale)
    look, spread = aim(eye)
    fov = min(max(spread * fit, fov_deg[0]), fov_deg[1])
    return Camera.look_at(eye, eye + look, width=width, height=height, fov_deg=fov)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / max(float(np.linalg.norm(v)), 1e-12)


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


def readout(canvas: Canvas, lines: list[str], x: int = 6, y: int = 6, color=HUD_TEXT) -> None:
    """The on-screen readout: ``lines`` of text on a dark, half-transparent box whose top-left
    corner is at ``(x, y)``."""
    text = "\n".join(lines)
    w, h = text_size(text)
    canvas.rect(x, y, x + w + 8, y + h + 8, HUD_BACK, alpha=0.6)
    canvas.text(x + 4, y + 4, text, color)


def signed(v: float, digits: int = 2) -> str:
    """A command for the readout: sign always shown, fixed width; '?' when not finite."""
    return f"{v:+.{digits}f}" if math.isfinite(v) else "?"


def number(v: float, digits: int = 1) -> str:
    """A value for the readout; '?' when not finite (a diverged state still renders)."""
    return f"{v:.{digits}f}" if math.isfinite(v) else "?"
