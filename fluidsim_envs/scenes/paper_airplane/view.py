"""PaperAirplane-v0's frames (480 x 360): the dart seen from behind and above, framed with the
target, over the ground grid (1 m).

- The dart is its render mesh (:mod:`.mesh`), shaded by the sun, its ailerons, elevators and
  rudder at the commands the physics last flew (``sim.controls``), its shadow straight below
  it on the ground and a thin stalk down to the shadow (the height cue).
- The target: a red ring of ``success_radius_m`` (landing inside it is a success) and a post.
- The camera (:func:`~fluidsim_envs.scenes.drawing.framing_camera`) sits behind the dart on
  the side away from the target, above its flight path, and looks between them (and at the
  shadow once the dart is low), widening and then backing off when they would not fit.
- The readout (top left): the episode's time, the speed, the height, the distance to the
  target and the three commands.
"""

from __future__ import annotations

import math

import numpy as np

from ...physics.kernels import quat_matrices
from ..drawing import draw_mesh, fill_ground, framing_camera, number, readout, signed
from ..render import Canvas
from .mesh import meshes

SKY, GROUND, GRID = (200, 222, 245), (186, 204, 170), (150, 175, 140)
TARGET, STALK = (210, 40, 40), (90, 90, 90)
BACK_M, ABOVE_DEG = 0.65, 25.0  # the chase offset: the 28 cm dart a quarter of the frame
MIN_EYE_Z = 0.25  # the camera stays this high above the ground
SHADOW_M = 1.5  # the camera frames the ground below the dart from this height down


class PaperAirplaneView:
    """Frames of a PaperAirplane-v0 vector env; keeps the dart's render mesh."""

    def __init__(self, env) -> None:
        self.env = env
        (self.mesh,) = meshes(env)

    def frame(self, e: int) -> np.ndarray:
        """The [360, 480, 3] image of sub-env e."""
        env = self.env
        pos = np.array(env.sim.pos[e, 0], dtype=np.float64)
        rot = quat_matrices(np.ascontiguousarray(env.sim.quat[e], dtype=np.float64))[0]
        target = np.array([*env.target_xy(e), 0.0])
        camera = chase(env, e, pos, target)
        canvas = Canvas(camera.width, camera.height, background=SKY)
        fill_ground(canvas, camera, GROUND)
        center = pos[:2] if np.isfinite(pos[:2]).all() else target[:2]
        canvas.ground_grid(camera, center, 30.0, 1.0, GRID)
        ring = np.linspace(0.0, 2.0 * np.pi, 49)
        r = env.params.success_radius_m
        circle = target + r * np.stack([np.cos(ring), np.sin(ring), 0 * ring], 1)
        canvas.lines(camera, circle[:-1], circle[1:], TARGET, thickness=2)
        canvas.lines(camera, [target], [target + (0.0, 0.0, 0.5)], TARGET, thickness=2)
        canvas.lines(camera, [(pos[0], pos[1], 0.0)], [pos], STALK)
        draw_mesh(canvas, camera, self.mesh, env.sim.controls[e], pos, rot, shadow_z=0.0)
        readout(canvas, _lines(env, e, pos, target))
        return canvas.image()


def chase(env, e: int, pos: np.ndarray, target: np.ndarray):
    """The camera of sub-env e's frame: it frames the dart, the target and the ground below
    the dart once within ``SHADOW_M`` of it (its shadow; higher up, the point that far
    below: the frame follows the height continuously)."""
    vel = np.array(env.sim.lin_vel[e, 0], dtype=np.float64)
    below = np.array([pos[0], pos[1], max(pos[2] - SHADOW_M, 0.0)])
    return framing_camera(pos, vel, [target, below], BACK_M, ABOVE_DEG, min_eye_z=MIN_EYE_Z)


def _lines(env, e: int, pos: np.ndarray, target: np.ndarray) -> list[str]:
    p = env.params
    t = float(env.episode_steps[e]) * p.dt * p.substeps
    speed = float(np.linalg.norm(env.sim.lin_vel[e, 0]))
    to_go = math.hypot(*(target[:2] - pos[:2]))
    cmd = dict(zip(env.sim.control_names, env.sim.controls[e].tolist(), strict=True))
    ail, elv, rud = cmd["aileron"], cmd["elevator"], cmd["rudder"]
    return [
        f"t {t:4.1f} s  speed {number(speed)} m/s  height {number(pos[2], 2)} m"
        f"  return {number(float(env.episode_return[e]), 2)}",
        f"target {number(to_go)} m  ail {signed(ail)} elv {signed(elv)} rud {signed(rud)}",
    ]
