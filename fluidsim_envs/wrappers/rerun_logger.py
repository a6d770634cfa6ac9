"""Log chosen sub-envs of a native vector env to Rerun: an ``.rrd`` file or a live viewer.

Each logged sub-env i has its own entity root ``env/i`` (world frame: x, y level, z up):

- ``env/i/body/b``: body b's pose (``Transform3D``); below it, in the body's frame, its
  collision shapes (``boxes``, ``spheres``; static), or a box around its samples if it has
  none.
- ``env/i/forces``: every sample's force (plates, cylinders, buoyancy, thrusters; from
  ``Simulator.sample_forces``) as an arrow from its world point, scaled by the static
  ``scale_m_per_n`` on the same entity.
- ``env/i/controls/<channel>``: each control channel's command in [-1, 1], and for a
  control surface its deflection, ``<channel>_deg`` (the command times its limit).
- ``env/i/reward/total`` and ``env/i/reward/<term>``: the step's reward and its terms.
- ``env/i/state/...``: speed, height and attitude as fit the scene.
- The scene: the ground and the target (PaperAirplane), the water surface, the buoys and
  the gates (BoatOnStep; a swell's surface is re-logged around the boat every few steps),
  the surface, the floor, the lead submarine, the station point and the wake's tracers
  (SubmarineWake).

Timelines: ``step`` (a sequence: 0 at the first reset, +1 per step) and ``time`` (simulated
seconds since then: ``step`` times the scene's action period). A step that ends an episode
logs its reward and the next episode's first state (the vector env resets in the same step).

Rerun is optional: this module imports without it, and :class:`RerunLogger` raises an
ImportError that says how to install it.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from gymnasium.vector import VectorEnv, VectorWrapper

from ..envs import submarine_wake_kernel as SK
from ..envs import submarine_wake_render as SR
from ..envs.base import FluidVectorEnv
from ..envs.boat_on_step import BoatOnStepVectorEnv
from ..envs.paper_airplane import PaperAirplaneVectorEnv
from ..envs.submarine_wake import LEAD_LENGTH_M, LEAD_RADIUS_M, SubmarineWakeVectorEnv
from ..physics import Craft

if TYPE_CHECKING:
    import rerun

INSTALL_HINT = 'pip install "fluidsim-envs[rerun]"'
SWELL_EVERY = 5  # steps between re-logs of a moving (swell) water surface
SWELL_HALF_M, SWELL_CELLS = 40.0, 32  # that surface: a square around the boat, its cells
PLANE_HALF_M = 1000.0  # static planes (calm water, sea floor): far beyond any course
WATER, GROUND, FLOOR = (40, 110, 170, 120), (150, 180, 130), (150, 130, 90)
BODY, FORCE, TARGET, BUOY = (235, 235, 240), (255, 120, 40), (210, 40, 40), (250, 140, 20)


def import_rerun():
    """The ``rerun`` module, or an ImportError that says how to install it."""
    try:
        return importlib.import_module("rerun")
    except ImportError as err:
        raise ImportError(
            f"RerunLogger needs the rerun-sdk package: {INSTALL_HINT} (or pip install "
            f'"rerun-sdk>=0.41,<0.42")'
        ) from err


class RerunLogger(VectorWrapper):
    """A vector wrapper that logs sub-envs ``env_ids`` of a :class:`FluidVectorEnv` on every
    reset and step (see the module docstring for what is logged where).

    Args:
        venv: the native vector env (or a wrapper of one that keeps its spaces).
        path: write a recording to this ``.rrd`` file.
        env_ids: the sub-envs to log.
        spawn: stream to a Rerun viewer started for it (with ``path``: both).
        recording_id: the recording's id (default: a random one); runs with the same id
            merge in the viewer.

    :meth:`close` flushes and closes the recording, then the wrapped env.
    """

    def __init__(
        self,
        venv: VectorEnv,
        path: str | None = None,
        env_ids: Sequence[int] = (0,),
        spawn: bool = False,
        recording_id: str | None = None,
    ) -> None:
        rr = import_rerun()
        super().__init__(venv)
        base = venv.unwrapped
        if not isinstance(base, FluidVectorEnv):
            raise TypeError(f"RerunLogger wraps a fluidsim_envs vector env, got {type(base)}")
        scene = _SCENES.get(type(base))
        if scene is None:
            raise TypeError(f"RerunLogger: no Rerun scene for {type(base).__name__}")
        ids = [int(e) for e in env_ids]
        if not ids or any(e < 0 or e >= base.num_envs for e in ids) or len(set(ids)) < len(ids):
            raise ValueError(
                f"RerunLogger: env_ids must be distinct sub-env indices in "
                f"[0, {base.num_envs}), got {env_ids!r}"
            )
        if path is None and not spawn:
            raise ValueError("RerunLogger: give a path (an .rrd file), spawn=True, or both")
        self.rr = rr
        self.base = base
        self.env_ids = tuple(ids)
        self.scene = scene
        self.rec = rr.RecordingStream("fluidsim_envs", recording_id=recording_id)
        if spawn:
            self.rec.spawn(connect=path is None)
            if path is not None:
                self.rec.set_sinks(rr.GrpcSink(), rr.FileSink(str(path)))
        else:
            self.rec.save(str(path))
        self.action_period_s = base.params.dt * base.params.substeps
        self.step_index = -1  # the first reset logs step 0
        self._closed = False
        # one scale per sub-env (its first body's): arrows of different bodies compare
        self.scale_m_per_n = {e: _force_scale(base.sim.crafts[0]) for e in self.env_ids}
        self._controls = [c for craft in base.sim.crafts for c in craft.controls]  # channels
        self._log_static()

    # ---- the Gymnasium API ----------------------------------------------------------------

    def reset(self, *, seed=None, options=None):
        obs, info = self.env.reset(seed=seed, options=options)
        started = np.zeros(self.base.num_envs, dtype=bool)
        started[np.asarray((options or {}).get("env_ids", np.arange(self.base.num_envs)))] = True
        self._log_step(started, info=None)
        return obs, info

    def step(self, actions):
        obs, reward, terminated, truncated, info = self.env.step(actions)
        started = np.asarray(info.get("_final_obs", np.zeros(self.base.num_envs, dtype=bool)))
        self._log_step(started, info=info, reward=reward)
        return obs, reward, terminated, truncated, info

    def close(self, **kwargs: Any) -> None:
        if not self._closed:
            self._closed = True
            self.rec.flush()
            self.rec.disconnect()
        super().close(**kwargs)

    # ---- logging --------------------------------------------------------------------------

    def log(self, e: int, path: str, data, static: bool = False) -> None:
        """Log ``data`` (an archetype) at ``env/e/path``."""
        self.rec.log(f"env/{e}/{path}", data, static=static)

    def scalar(self, e: int, path: str, value: float) -> None:
        self.rec.log(f"env/{e}/{path}", self.rr.Scalars(float(value)))

    def _log_static(self) -> None:
        rr = self.rr
        self.rec.log("/", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
        for e in self.env_ids:
            for b, craft in enumerate(self.base.sim.crafts):
                _log_shapes(self, e, f"body/{b}", craft)
            self.log(e, "forces", rr.AnyValues(scale_m_per_n=self.scale_m_per_n[e]), static=True)
            self.scene.world(self, e)

    def _log_step(self, started: np.ndarray, info: dict | None, reward=None) -> None:
        rr, sim = self.rr, self.base.sim
        self.step_index += 1
        self.rec.set_time("step", sequence=self.step_index)
        self.rec.set_time("time", duration=self.step_index * self.action_period_s)
        # the commands of the last step (the Simulator keeps them); a new episode has none yet
        controls = sim.controls.copy()
        controls[started] = 0.0
        pos = np.asarray(sim.pos, dtype=np.float64)
        quat = np.asarray(sim.quat, dtype=np.float64)
        for e in self.env_ids:
            if started[e]:
                self.scene.episode(self, e)
            for b in range(sim.num_bodies):
                w, x, y, z = quat[e, b]
                self.log(
                    e,
                    f"body/{b}",
                    rr.Transform3D(
                        translation=pos[e, b], quaternion=rr.Quaternion(xyzw=[x, y, z, w])
                    ),
                )
            points, forces, _ = sim.sample_forces(controls, env_index=e)
            self.log(
                e,
                "forces",
                rr.Arrows3D(origins=points, vectors=forces * self.scale_m_per_n[e], colors=FORCE),
            )
            for name, control, value in zip(
                sim.control_names, self._controls, controls[e], strict=True
            ):
                self.scalar(e, f"controls/{name}", value)
                if control.max_deflection_deg > 0.0:  # a surface: its deflection too
                    self.scalar(e, f"controls/{name}_deg", value * control.max_deflection_deg)
            if info is not None:
                self.scalar(e, "reward/total", reward[e])
                for term, values in info["reward_terms"].items():
                    self.scalar(e, f"reward/{term}", values[e])
            self.scene.step(self, e, info)


# --------------------------------------------------------------------------------------------
# geometry helpers


def _force_scale(craft: Craft) -> float:
    """Arrow length per newton: the mean force per sample that would carry the craft's weight
    draws as a quarter of its reach (the farthest sample from its center of mass)."""
    offsets = [s.offset_m for s in (*craft.plates, *craft.cylinders, *craft.buoyancy)]
    reach = max((float(np.linalg.norm(o)) for o in offsets), default=1.0)
    per_sample = craft.mass_kg * 9.81 / max(craft.num_samples, 1)
    return 0.25 * reach / per_sample


def _log_shapes(lg: RerunLogger, e: int, path: str, craft: Craft) -> None:
    """A body's shapes in its own frame, static: its collision shapes, else the box around
    its samples (at least 2 cm thick)."""
    rr = lg.rr
    boxes = [s for s in craft.shapes if s.kind == "box"]
    spheres = [s for s in craft.shapes if s.kind == "sphere"]
    centers = [s.center_m for s in boxes]
    halves = [s.half_extents_m for s in boxes]
    if not craft.shapes:  # no collision shapes: the box around its samples
        pts = np.array([s.offset_m for s in (*craft.plates, *craft.cylinders, *craft.buoyancy)])
        pts = pts.reshape(-1, 3) if pts.size else np.zeros((1, 3))
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        centers, halves = [0.5 * (lo + hi)], [np.maximum(0.5 * (hi - lo), 0.01)]
    if centers:
        lg.log(
            e,
            f"{path}/boxes",
            rr.Boxes3D(centers=centers, half_sizes=halves, colors=BODY, fill_mode="solid"),
            static=True,
        )
    if spheres:
        lg.log(
            e,
            f"{path}/spheres",
            rr.Ellipsoids3D(
                centers=[s.center_m for s in spheres],
                half_sizes=[[s.radius_m] * 3 for s in spheres],
                colors=BUOY,
                fill_mode="solid",
            ),
            static=True,
        )


def _plane(rr: rerun, z: float, half: float, color):
    """A level square at height z, centered over the origin: a Mesh3D of two triangles."""
    corners = [[-half, -half, z], [half, -half, z], [half, half, z], [-half, half, z]]
    return rr.Mesh3D(
        vertex_positions=corners, triangle_indices=[[0, 1, 2], [0, 2, 3]], albedo_factor=color
    )


def _grid_triangles(n: int) -> np.ndarray:
    """Triangle indices of an (n + 1) x (n + 1) vertex grid, row-major."""
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    a = (i * (n + 1) + j).ravel()
    b, c, d = a + 1, a + n + 1, a + n + 2
    return np.concatenate([np.stack([a, b, d], 1), np.stack([a, d, c], 1)]).astype(np.uint32)


def _attitude_deg(quat) -> tuple[float, float]:
    """(pitch, roll) in degrees: nose (body x) up +, right side (-y) down +."""
    w, x, y, z = (float(v) for v in quat)
    nose_z = 2.0 * (x * z - w * y)  # the world z of body x
    left_z = 2.0 * (y * z + w * x)  # of body y
    up_z = 1.0 - 2.0 * (x * x + y * y)  # of body z
    return math.degrees(math.asin(max(-1.0, min(1.0, nose_z)))), math.degrees(
        math.atan2(left_z, up_z)
    )


def _log_motion(
    lg: RerunLogger, e: int, horizontal: bool = False, angles=("pitch_deg", "roll_deg")
) -> None:
    """Speed (over the ground; horizontal only if asked), height and attitude of body 0
    (``angles``: the names of its pitch and roll)."""
    sim = lg.base.sim
    v = np.asarray(sim.lin_vel[e, 0], dtype=np.float64)
    lg.scalar(e, "state/speed_mps", np.linalg.norm(v[:2] if horizontal else v))
    lg.scalar(e, "state/altitude_m", sim.pos[e, 0, 2])
    pitch, roll = _attitude_deg(sim.quat[e, 0])
    lg.scalar(e, f"state/{angles[0]}", pitch)
    lg.scalar(e, f"state/{angles[1]}", roll)


# --------------------------------------------------------------------------------------------
# the scenes: what each draws once (world), at each episode's start and every step


def _airplane_world(lg: RerunLogger, e: int) -> None:
    half = lg.base.params.arena_radius_m
    lg.log(e, "ground", _plane(lg.rr, 0.0, half, GROUND), static=True)


def _airplane_episode(lg: RerunLogger, e: int) -> None:
    env, rr = lg.base, lg.rr
    tx, ty = env.target[e]
    ring = np.linspace(0.0, 2.0 * np.pi, 49)
    r = env.params.success_radius_m
    circle = np.stack([tx + r * np.cos(ring), ty + r * np.sin(ring), 0.0 * ring], axis=1)
    lg.log(e, "target", rr.Points3D([[tx, ty, 0.0]], radii=0.1, colors=TARGET))
    lg.log(e, "target/ring", rr.LineStrips3D([circle], colors=TARGET))


def _airplane_step(lg: RerunLogger, e: int, info: dict | None) -> None:
    _log_motion(lg, e)
    if info is not None:
        lg.scalar(e, "state/distance_to_target_m", info["distance_m"][e])


def _boat_world(lg: RerunLogger, e: int) -> None:
    if not lg.base.world.swell:  # calm: one flat sheet; a swell is logged as it moves
        lg.log(e, "water", _plane(lg.rr, 0.0, PLANE_HALF_M, WATER), static=True)


def _boat_episode(lg: RerunLogger, e: int) -> None:
    env, rr = lg.base, lg.rr
    marks = np.concatenate([env.buoys[e], np.zeros((len(env.buoys[e]), 1))], axis=1)
    lg.log(e, "buoys", rr.Points3D(marks, radii=env.params.buoy_radius_m, colors=BUOY))
    lg.log(e, "gates", rr.LineStrips3D(np.stack([marks[0::2], marks[1::2]], 1), colors=BUOY))


def _boat_step(lg: RerunLogger, e: int, info: dict | None) -> None:
    env = lg.base
    _log_motion(lg, e, horizontal=True, angles=("trim_deg", "heel_deg"))
    if env.world.swell and lg.step_index % SWELL_EVERY == 0:
        n = SWELL_CELLS
        x0, y0 = (float(c) for c in env.sim.pos[e, 0, :2])
        u = np.linspace(-SWELL_HALF_M, SWELL_HALF_M, n + 1)
        x, y = np.meshgrid(x0 + u, y0 + u, indexing="ij")
        z = env.world.surface_height(x, y, env.sim.clock[e])
        vertices = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
        lg.log(
            e,
            "water",
            lg.rr.Mesh3D(
                vertex_positions=vertices, triangle_indices=_grid_triangles(n), albedo_factor=WATER
            ),
        )


def _lead_pose(env: SubmarineWakeVectorEnv, e: int) -> tuple[np.ndarray, float]:
    """The lead submarine's position and heading (it is scripted, not a simulated body)."""
    lead = env.lead[:, e]
    return np.array([lead[SK.L_X], lead[SK.L_Y], lead[SK.L_Z]]), float(lead[SK.L_HEADING])


def _sub_world(lg: RerunLogger, e: int) -> None:
    rr, p = lg.rr, lg.base.params
    lg.log(e, "water", _plane(rr, 0.0, PLANE_HALF_M, WATER), static=True)
    lg.log(e, "floor", _plane(rr, -p.floor_depth_m, PLANE_HALF_M, FLOOR), static=True)
    half = [0.5 * LEAD_LENGTH_M, LEAD_RADIUS_M, LEAD_RADIUS_M]
    hull = rr.Ellipsoids3D(half_sizes=[half], colors=(120, 125, 135), fill_mode="solid")
    lg.log(e, "lead/hull", hull, static=True)


def _sub_episode(lg: RerunLogger, e: int) -> None:
    env = lg.base
    if env.params.wake and e not in env._tracers:  # the env advances the tracers it holds
        env._tracers[e] = SR.start_tracers(env, e)


def _sub_step(lg: RerunLogger, e: int, info: dict | None) -> None:
    env, rr = lg.base, lg.rr
    _log_motion(lg, e)
    lg.scalar(e, "state/depth_m", -env.sim.pos[e, 0, 2])
    if info is not None:
        lg.scalar(e, "state/station_distance_m", info["station_distance_m"][e])
    pos, heading = _lead_pose(env, e)
    c, s = math.cos(heading), math.sin(heading)
    turn = rr.Quaternion(xyzw=[0.0, 0.0, math.sin(heading / 2), math.cos(heading / 2)])
    lg.log(e, "lead", rr.Transform3D(translation=pos, quaternion=turn))
    sx, sy, sz = env.station[e]
    station = pos + [c * sx - s * sy, s * sx + c * sy, sz]
    lg.log(e, "station", rr.Points3D([station], radii=0.3, colors=(90, 230, 120)))
    tracers = env._tracers.get(e)
    if tracers is not None:
        speed = np.clip(tracers.speeds / max(env.lead[SK.L_SPEED, e], 0.1), 0.0, 1.0)
        colors = np.stack([70 + 180 * speed, 110 + 120 * speed, 160 + 90 * speed], 1)
        lg.log(
            e, "tracers", rr.Points3D(tracers.positions, radii=0.05, colors=colors.astype(np.uint8))
        )


@dataclass(frozen=True)
class _Scene:
    world: Callable[[RerunLogger, int], None]  # static geometry, once
    episode: Callable[[RerunLogger, int], None]  # at the start of each episode
    step: Callable[[RerunLogger, int, dict | None], None]  # every reset and step


_SCENES: dict[type, _Scene] = {
    PaperAirplaneVectorEnv: _Scene(_airplane_world, _airplane_episode, _airplane_step),
    BoatOnStepVectorEnv: _Scene(_boat_world, _boat_episode, _boat_step),
    SubmarineWakeVectorEnv: _Scene(_sub_world, _sub_episode, _sub_step),
}

__all__ = ["INSTALL_HINT", "RerunLogger", "import_rerun"]
