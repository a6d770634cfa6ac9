"""Log chosen sub-envs of a native vector env to Rerun: an ``.rrd`` file or a live viewer.

Each logged sub-env i has its own entity root ``env/i`` (world frame: x, y level, z up):

- ``env/i/body/b``: body b's pose (``Transform3D``); below it, in the body's frame, its
  collision shapes (``boxes``, ``spheres``; static), or a box around its samples if it has
  none, and its samples (``samples/<form>``, static): each drawn as its kind's glyph
  declares (``physics.model.Glyph``: plates as squares, cylinders as rods, buoyancy as
  balls or squares, thrusters as arrows at full thrust).
- ``env/i/forces``: every sample's force (plates, cylinders, buoyancy, thrusters; from
  ``Simulator.sample_forces``) as an arrow from its world point, scaled by the static
  ``scale_m_per_n`` on the same entity.
- ``env/i/controls/<channel>``: each control channel's command in [-1, 1], and for a
  control surface its deflection, ``<channel>_deg`` (the command times its limit).
- ``env/i/reward/total`` and ``env/i/reward/<term>``: the step's reward and its terms.
- ``env/i/state/...``: speed, height and attitude as fit the scene.
- The scene's own entities, from its Rerun hooks (``SCENES[id].rerun``, in
  ``fluidsim_envs/scenes/<scene>/rerun.py``): what it draws once, at each episode's start and
  every step.

Timelines: ``step`` (a sequence: 0 at the first reset, +1 per step) and ``time`` (simulated
seconds since then: ``step`` times the scene's action period). A step that ends an episode
logs its reward and the next episode's first state (the vector env resets in the same step).

Rerun is optional: this module imports without it, and :class:`RerunLogger` raises an
ImportError that says how to install it.
"""

from __future__ import annotations

import importlib
from collections.abc import Sequence
from typing import Any

import numpy as np
from gymnasium.vector import VectorEnv, VectorWrapper

from ..physics import Craft
from ..physics.model import GLYPH_FORMS, glyphs
from ..scenes import SCENES, Scene
from ..scenes.base import FluidVectorEnv
from ..scenes.rerun import BUOY

INSTALL_HINT = 'pip install "fluidsim-envs[rerun]"'
BODY, FORCE, SAMPLE = (235, 235, 240), (255, 120, 40), (60, 130, 220)
PLATE_THICKNESS_M = 0.002


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
        scene = _scene_of(base)
        if scene is None:
            raise TypeError(f"RerunLogger: no scene in SCENES for {type(base).__name__}")
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
        self.hooks = scene.rerun(self)  # the scene's part of the recording (its own state)
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
                _log_samples(self, e, f"body/{b}/samples", craft)
            self.log(e, "forces", rr.AnyValues(scale_m_per_n=self.scale_m_per_n[e]), static=True)
            self.hooks.world(e)

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
                self.hooks.episode(e)
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
            self.hooks.step(e, info)


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


def _turn_from_z(axis: np.ndarray) -> np.ndarray:
    """Quaternions ``[n, 4]`` (x, y, z, w) that turn +z onto each unit ``axis [n, 3]``."""
    q = np.stack([-axis[:, 1], axis[:, 0], 0.0 * axis[:, 0], 1.0 + axis[:, 2]], axis=1)
    q[axis[:, 2] < -1.0 + 1e-12] = (1.0, 0.0, 0.0, 0.0)  # -z: half a turn about x
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _squares(rr, center, axis, size, scale_m_per_n):
    return rr.Boxes3D(
        centers=center,
        half_sizes=np.stack([size / 2, size / 2, np.full_like(size, PLATE_THICKNESS_M / 2)], 1),
        quaternions=_turn_from_z(axis),
        colors=SAMPLE,
        fill_mode="solid",
    )


def _rods(rr, center, axis, size, scale_m_per_n):
    return rr.Capsules3D(
        lengths=size,
        radii=0.05 * size,
        translations=center - 0.5 * size[:, None] * axis,  # a capsule starts at its origin
        quaternions=_turn_from_z(axis),
        colors=SAMPLE,
    )


def _balls(rr, center, axis, size, scale_m_per_n):
    half = np.repeat(size[:, None], 3, axis=1)
    return rr.Ellipsoids3D(centers=center, half_sizes=half, colors=SAMPLE, fill_mode="solid")


def _arrows(rr, center, axis, size, scale_m_per_n):
    # a thruster's arrow is its full thrust at the force arrows' scale
    return rr.Arrows3D(origins=center, vectors=axis * size[:, None] * scale_m_per_n, colors=FORCE)


# each glyph form's drawing (physics.model.GLYPH_FORMS; tests check that none is missing)
DRAW = {"square": _squares, "rod": _rods, "ball": _balls, "arrow": _arrows}


def _log_samples(lg: RerunLogger, e: int, path: str, craft: Craft) -> None:
    """A body's samples in its own frame, static: one entity per glyph form."""
    marks = glyphs(craft)
    for form in GLYPH_FORMS:
        mine = [g for g in marks if g.form == form]
        if mine:
            center = np.array([g.center_m for g in mine], dtype=np.float64)
            axis = np.array([g.axis for g in mine], dtype=np.float64)
            size = np.array([g.size for g in mine], dtype=np.float64)
            drawing = DRAW[form](lg.rr, center, axis, size, lg.scale_m_per_n[e])
            lg.log(e, f"{path}/{form}", drawing, static=True)


def _scene_of(base: FluidVectorEnv) -> Scene | None:
    """The registered scene whose vector env ``base`` is."""
    return next((sc for sc in SCENES.values() if isinstance(base, sc.vector_cls)), None)


__all__ = ["INSTALL_HINT", "RerunLogger", "import_rerun"]
