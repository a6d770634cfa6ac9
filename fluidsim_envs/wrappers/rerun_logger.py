"""Log chosen sub-envs of a native vector env to Rerun: an ``.rrd`` file or a live viewer.

What is logged where. Each logged sub-env e has its own entity root ``env/e`` (world frame:
x, y level, z up):

- ``env/e/body/b``: body b's pose (``Transform3D``), every step. Below it, in the body's
  frame: ``mesh``, the craft's render mesh (``Scene.meshes``, static), and ``surfaces``, its
  control surfaces, whose vertices are logged as the commands turn them; ``forces``, every
  fluid sample's force (``Simulator.sample_forces``: plates, cylinders, buoyancy, thrusters)
  as an arrow from its point, scaled by the static ``scale_m_per_n`` on the same entity; and,
  hidden by the blueprint (tick them on in the viewer), the collision shapes (``boxes``,
  ``spheres``) and the samples as their kinds' glyphs (``samples/<form>``,
  ``physics.model.Glyph``). The surfaces are logged every ``SURFACE_PERIOD_S`` of simulated
  time and the forces every ``FORCE_PERIOD_S`` (and both at each episode's first and last
  step); where the forces act, once per episode.
- ``env/e/trail``: body 0's path, a segment per step, colored by episode.
- ``env/e/controls``: each control channel's command in [-1, 1] (a series per channel, named
  by a static ``SeriesLines``, as are the series below).
- ``env/e/reward``: the step's reward (``total``) and its terms (none at a reset).
- ``env/e/state``: speed, height and attitude; ``env/e/state/task``: the task's measures
  (none at a reset).
- The scene's own entities, from its Rerun hooks (``SCENES[id].rerun``, in
  ``fluidsim_envs/scenes/<scene>/rerun.py``: the ground or water around the course, targets,
  buoys, the lead submarine and the wake's tracers).

Timelines: ``step`` (a sequence: 0 at the first reset, +1 per step of the vector env),
``time`` (simulated seconds since then: ``step`` times the action period) and ``episode``
(each logged sub-env's episode, from 0). On ``step`` and ``time`` the views play the
episodes in order; on ``episode`` each tick shows an episode's last state with its whole
trail (the plots read best on ``time``).

Episodes: a step that ends an episode logs that episode's last state (taken just before the
vector env's same-step autoreset, through ``FluidVectorEnv.before_autoreset``), so the
touchdown is what the views show at that step. The next episode's logging starts at the
following step, with the state after its first action: its reset state, which the autoreset
gave at the same step as the last one, is not logged (it would hide the last state on
``step`` and ``time``). A ``reset`` logs the first state of the episodes it starts. With
``episodes_per_env=n`` a sub-env is no longer logged once n of its episodes have ended, so
that a recording holds whole episodes.

Size: the rows of each sub-env are held in memory and sent as one chunk per entity
(``send_columns``) every ``FLUSH_ROWS`` rows (``LIVE_FLUSH_ROWS`` when streaming to a
viewer), when its last episode ends (``episodes_per_env``), on :meth:`RerunLogger.flush` and
on :meth:`~RerunLogger.close`. A recording stays within ``STATIC_BYTES`` plus
``BYTES_PER_SIM_MINUTE`` per simulated minute per logged sub-env (tested for every scene;
``python -m fluidsim_envs.wrappers.rerun_layout record`` measures it).

The recording's application is ``fluidsim-<Name-vN>`` (the viewer keeps a blueprint per
application) and its name the env id, with ``name`` after it (e.g. the run).

Blueprint (sent with every recording): a column per logged sub-env (tabs beyond
``MAX_COLUMNS``): a 3D view whose eye starts behind the craft and follows body 0, with the
line grid at z = 0, above three plots: controls, reward, state. The time panel opens on
``time``.

Rerun is optional: this module imports without it, and :class:`RerunLogger` raises an
ImportError that says how to install it.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from gymnasium.vector import VectorEnv, VectorWrapper

from ..physics import Craft
from ..physics.kernels import quat_matrices
from ..physics.model import GLYPH_FORMS, glyphs
from ..scenes import SCENES, Scene
from ..scenes.base import FluidVectorEnv
from ..scenes.mesh import RenderMesh, split_by_body
from ..scenes.rerun import BUOY, mesh3d

INSTALL_HINT = 'pip install "fluidsim-envs[rerun]"'
# the size budget: what a recording may take, per logged sub-env (measured: see the report
# of ``python -m fluidsim_envs.wrappers.rerun_layout record``)
BYTES_PER_SIM_MINUTE = 1_000_000
STATIC_BYTES = 200_000  # the blueprint, meshes, shapes, names, each entity's first chunk
# what is drawn less often than every step (simulated time between logs)
SURFACE_PERIOD_S, FORCE_PERIOD_S = 0.1, 0.2  # control surfaces; sample forces
FLUSH_ROWS, LIVE_FLUSH_ROWS = 1024, 30  # rows held per sub-env before they are sent
MAX_COLUMNS = 4  # sub-envs side by side in the blueprint; more go into tabs
EYE_OFFSET = (-2.0, -1.0, 0.7)  # the eye's start, in craft sizes (behind, right, above)
BODY, FORCE, SAMPLE = (235, 235, 240), (255, 120, 40), (60, 130, 220)
TRAIL_COLORS = ((250, 200, 60), (90, 200, 250), (240, 110, 160), (140, 230, 120))  # by episode
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
        name: what the recording is called in the viewer, after the env id (e.g. the run).
        episodes_per_env: stop logging a sub-env once this many of its episodes have ended
            (None: log every episode).

    :meth:`close` sends what is held, closes the recording, then the wrapped env.
    """

    def __init__(
        self,
        venv: VectorEnv,
        path: str | None = None,
        env_ids: Sequence[int] = (0,),
        spawn: bool = False,
        recording_id: str | None = None,
        name: str | None = None,
        episodes_per_env: int | None = None,
    ) -> None:
        rr = import_rerun()
        super().__init__(venv)
        self.base, self.scene = _check_env(venv)
        self.env_ids = _check_ids(env_ids, self.base.num_envs)
        if path is None and not spawn:
            raise ValueError("RerunLogger: give a path (an .rrd file), spawn=True, or both")
        self.episodes_per_env = _check_limit(episodes_per_env)
        self.rr = rr
        self.rec = _open(rr, self.scene, path, spawn, recording_id, name)
        self.action_period_s = self.base.params.dt * self.base.params.substeps
        self.step_index = -1  # the first reset logs step 0
        self.scale_m_per_n = _force_scale(self.base.sim.crafts[0])  # arrows of all bodies
        self.meshes = tuple(_Mesh(m) for m in self.scene.meshes(self.base))
        self.size_m = self.meshes[0].size_m
        self._flush_rows = LIVE_FLUSH_ROWS if spawn else FLUSH_ROWS
        self._logs = {e: _EnvLog(_Columns(rr, self.rec)) for e in self.env_ids}
        self._last_rows: set[int] = set()  # sub-envs whose last row the autoreset hook logged
        self._closed = False
        self._colors: dict[str, dict] = {}  # plot -> series name -> its color
        self._blueprint_sent = False
        self.hooks = self.scene.rerun(self)  # the scene's part of the recording
        self._log_static()
        self.base.before_autoreset.append(self._before_autoreset)

    # ---- the Gymnasium API ----------------------------------------------------------------

    def reset(self, *, seed=None, options=None):
        before = self.base.episodes.copy()
        obs, info = self.env.reset(seed=seed, options=options)
        # the sub-envs that restarted, however the options named them (indices, a mask)
        ids = np.flatnonzero(self.base.episodes != before)
        self.step_index += 1
        for e in self.env_ids:
            if np.isin(e, ids) and self._active(e):
                self._start_episode(e)
                self._log_row(e, "first")
        if not self._blueprint_sent:
            self._send_blueprint()
        return obs, info

    def step(self, actions):
        self.step_index += 1
        self._last_rows.clear()
        try:
            obs, reward, terminated, truncated, info = self.env.step(actions)
        except Exception:
            self.step_index -= 1
            raise
        done = terminated | truncated
        for e in self.env_ids:
            log = self._logs[e]
            if not (log.running or log.opening):  # past its episodes, or not started
                continue
            if e in self._last_rows:  # its episode ended, the next has begun: logged from
                self._end_episode(e)  # the next step on, so the last state shows at this one
                log.opening = self._active(e)
                continue
            self._open_pending(e)
            self._log_row(e, "last" if done[e] else "step", info, reward[e])
            if done[e]:  # no autoreset: the next reset starts the next episode
                self._end_episode(e)
        return obs, reward, terminated, truncated, info

    def flush(self) -> None:
        """Send every row held so far and flush the recording."""
        for log in self._logs.values():
            log.columns.send()
        self.rec.flush()

    def close(self, **kwargs: Any) -> None:
        if not self._closed:
            self._closed = True
            self.base.before_autoreset.remove(self._before_autoreset)
            if not self._blueprint_sent:
                self._send_blueprint()
            self.flush()
            self.rec.disconnect()
        super().close(**kwargs)

    # ---- what the scene hooks call ----------------------------------------------------------

    def log(self, e: int, path: str, data, static: bool = False) -> None:
        """Log ``data`` (an archetype) at ``env/e/path`` now (at the current row's times):
        for what is logged once or once per episode."""
        self.rec.log(f"env/{e}/{path}", data, static=static)

    def record(self, e: int, path: str, kind, **fields) -> None:
        """A row of archetype ``kind`` at ``env/e/path``, held and sent in columns: for what
        changes every step or episode (the rest of the archetype logged static once).
        ``fields``: ``kind.columns`` arguments, each an array of this row's instances (the
        same number in each)."""
        log = self._logs[e]
        log.columns.add(f"env/{e}/{path}", kind, log.now, **fields)

    def scalars(self, e: int, path: str, values: dict[str, float]) -> None:
        """A row of named series at ``env/e/path``; every row of a path names the same
        series, in the same order (the names are logged once, as a static ``SeriesLines``)."""
        log = self._logs[e]
        names = tuple(values)
        known = log.series.setdefault(path, names)
        if known is names:
            lines = self.rr.SeriesLines(names=list(names), colors=self._series_colors(path, names))
            self.log(e, path, lines, static=True)
        elif known != names:
            raise ValueError(f"RerunLogger: env/{e}/{path} had series {known}, now {names}")
        row = np.fromiter(values.values(), dtype=np.float64, count=len(names))
        self.record(e, path, self.rr.Scalars, scalars=row)

    def _series_colors(self, path: str, names) -> list[tuple[int, int, int]]:
        """A color per series, the same in every env's plots: the next palette color of its
        plot (``state`` and ``state/task`` draw in one) at the series' first appearance."""
        plot = self._colors.setdefault(path.split("/")[0], {})
        for name in names:
            plot.setdefault(name, SERIES_COLORS[len(plot) % len(SERIES_COLORS)])
        return [plot[name] for name in names]

    def every(self, e: int, period_s: float) -> bool:
        """Whether this row of sub-env e is one to draw on when drawing every ``period_s`` of
        simulated time: an episode's first and last rows, and then one per period."""
        log = self._logs[e]
        if log.kind != "step" or log.opens:
            return True
        steps = max(1, round(period_s / self.action_period_s))
        return int(self.base.episode_steps[e]) % steps == 0

    # ---- episodes and rows ------------------------------------------------------------------

    def _active(self, e: int) -> bool:
        return self.episodes_per_env is None or self._logs[e].ended < self.episodes_per_env

    def _open_pending(self, e: int) -> None:
        """Start logging the episode an autoreset began at the last step, if one waits: its
        first logged row is the one about to be logged."""
        log = self._logs[e]
        if log.opening:
            log.opening = False
            self._start_episode(e)
            log.opens = True

    def _start_episode(self, e: int) -> None:
        log = self._logs[e]
        log.episode += 1
        log.running = True
        log.trail_end = None  # a new trail

    def _end_episode(self, e: int) -> None:
        log = self._logs[e]
        log.running = False
        log.ended += 1
        if not self._active(e):  # its last episode: nothing more will come
            log.columns.send()

    def _before_autoreset(self, ended: np.ndarray, info: dict, reward: np.ndarray) -> None:
        """The base env's hook: the last rows of the logged episodes that end now."""
        for e in self.env_ids:
            if np.isin(e, ended) and (self._logs[e].running or self._logs[e].opening):
                self._open_pending(e)  # a one-step episode: its only row is its last
                self._log_row(e, "last", info, reward[e])
                self._last_rows.add(e)

    def _log_row(self, e: int, kind: str, info: dict | None = None, reward=None) -> None:
        """One row of sub-env e at the current step: ``kind`` is "first" (a new episode's
        first state), "step" or "last" (an episode's last state). The first row of an episode
        an autoreset began is a "step" or "last" row that opens it (``_EnvLog.opens``)."""
        log = self._begin_row(e, kind)
        sim = self.base.sim
        controls = sim.controls.copy()  # the last step's commands (the Simulator keeps them)
        if kind == "first":
            controls[e] = 0.0  # a new episode has none yet
        if log.opens:
            self.hooks.episode(e)
        pos = np.asarray(sim.pos[e], dtype=np.float64)
        quat = np.asarray(sim.quat[e], dtype=np.float64)
        if np.isfinite(pos).all() and np.isfinite(quat).all():  # a diverged state: plots only
            self._log_poses(e, pos, quat)
            if self.every(e, FORCE_PERIOD_S):
                self._log_forces(e, controls, pos, quat)
            if self.every(e, SURFACE_PERIOD_S):
                self._log_surfaces(e, controls[e])
        self._log_controls(e, controls[e])
        if info is not None:
            terms = {k: float(v[e]) for k, v in info["reward_terms"].items()}
            self.scalars(e, "reward", {"total": float(reward), **terms})
        self.hooks.step(e, info)
        log.rows += 1
        log.opens = False
        if log.rows % self._flush_rows == 0:
            log.columns.send()

    def _begin_row(self, e: int, kind: str) -> _EnvLog:
        """Sub-env e's row times, for what is held (``record``) and what is logged now."""
        log = self._logs[e]
        log.opens = kind == "first" or log.opens
        log.kind = kind
        log.now = (self.step_index, self.step_index * self.action_period_s, log.episode)
        self.rec.set_time("step", sequence=self.step_index)
        self.rec.set_time("time", duration=log.now[1])
        self.rec.set_time("episode", sequence=log.episode)
        return log

    def _log_poses(self, e: int, pos: np.ndarray, quat: np.ndarray) -> None:
        log = self._logs[e]
        for b in range(len(pos)):
            self.record(
                e,
                f"body/{b}",
                self.rr.Transform3D,
                translation=pos[b : b + 1],
                quaternion=_xyzw(quat[b : b + 1]),
            )
        if log.trail_end is not None:  # None at an episode's first row
            color = TRAIL_COLORS[log.episode % len(TRAIL_COLORS)]
            segment = np.stack([log.trail_end, pos[0]])[None]
            self.record(
                e,
                "trail",
                self.rr.LineStrips3D,
                strips=segment,
                colors=np.array([color], dtype=np.uint8),
            )
        log.trail_end = pos[0].copy()
        if log.eye is None:
            log.eye = _eye(pos[0], quat[0], self.size_m)

    def _log_forces(self, e: int, controls: np.ndarray, pos: np.ndarray, quat: np.ndarray):
        """Each body's sample forces, in its frame; where they act, once an episode (fixed on
        the body, but a new episode may move its center of mass)."""
        Arrows3D = self.rr.Arrows3D
        points, forces, body = self.base.sim.sample_forces(controls, env_index=e)
        for b in range(len(pos)):
            mine = body == b
            if mine.any():
                turn = body_rotation(quat[b])
                if self._logs[e].opens:
                    self.record(
                        e, f"body/{b}/forces", Arrows3D, origins=(points[mine] - pos[b]) @ turn
                    )
                vectors = forces[mine] @ turn * self.scale_m_per_n
                self.record(e, f"body/{b}/forces", Arrows3D, vectors=vectors)

    def _log_surfaces(self, e: int, commands: np.ndarray) -> None:
        """Each body's control surfaces as its commands turn them."""
        split = split_by_body(self.base.sim.crafts, commands)
        for b, (mesh, mine) in enumerate(zip(self.meshes, split, strict=True)):
            if mesh.moving is not None:
                verts = mesh.mesh.posed(mine)[mesh.moving]
                self.record(e, f"body/{b}/surfaces", self.rr.Mesh3D, vertex_positions=verts)

    def _log_controls(self, e: int, commands: np.ndarray) -> None:
        names = self.base.sim.control_names
        self.scalars(e, "controls", dict(zip(names, commands.tolist(), strict=True)))

    # ---- what is logged once ----------------------------------------------------------------

    def _log_static(self) -> None:
        rr = self.rr
        self.rec.log("/", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
        for e in self.env_ids:
            for b, (craft, mesh) in enumerate(zip(self.base.sim.crafts, self.meshes, strict=True)):
                self._logs[e].hidden += _log_shapes(self, e, f"body/{b}", craft)
                self._logs[e].hidden += _log_samples(self, e, f"body/{b}/samples", craft)
                mesh.log(self, e, f"body/{b}")
                if craft.num_samples:
                    forces = rr.Arrows3D.from_fields(colors=FORCE)
                    self.log(e, f"body/{b}/forces", forces, static=True)
                    scale = rr.AnyValues(scale_m_per_n=self.scale_m_per_n)
                    self.log(e, f"body/{b}/forces", scale, static=True)
            self.hooks.world(e)

    def _send_blueprint(self) -> None:
        self._blueprint_sent = True
        self.rec.send_blueprint(blueprint(self), make_active=True, make_default=True)


# --------------------------------------------------------------------------------------------
# what each logged sub-env keeps, and the rows held until they are sent


@dataclass
class _EnvLog:
    columns: _Columns
    episode: int = -1  # the episode being logged (from 0)
    ended: int = 0  # episodes that have ended
    running: bool = False  # an episode is being logged
    opening: bool = False  # an autoreset began an episode, logged from the next step on
    opens: bool = False  # the current row is its episode's first
    kind: str = "first"  # the current row's: first, step or last
    now: tuple = (0, 0.0, 0)  # the current row's (step, time, episode)
    rows: int = 0
    trail_end: np.ndarray | None = None
    eye: tuple | None = None  # (eye position, look target) at the first logged state
    series: dict = field(default_factory=dict)  # path -> the series' names
    hidden: list = field(default_factory=list)  # entities the blueprint hides


@dataclass
class _Rows:
    kind: type  # the archetype
    fields: dict  # name -> list of arrays, a row each
    times: list = field(default_factory=list)  # (step, time, episode) per row
    counts: list = field(default_factory=list)  # instances per row


class _Columns:
    """Temporal rows held in memory and sent as one chunk per entity (``send_columns``)."""

    def __init__(self, rr, rec) -> None:
        self.rr, self.rec = rr, rec
        self.rows: dict[tuple[str, tuple[str, ...]], _Rows] = {}  # (path, fields) -> rows

    def add(self, path: str, kind: type, now: tuple, **fields) -> None:
        arrays = {k: np.array(v) for k, v in fields.items()}  # copies: rows outlive the state
        counts = {len(a) for a in arrays.values()}
        if len(counts) != 1:
            raise ValueError(f"RerunLogger: the fields of {path} differ in length: {counts}")
        key = (path, tuple(sorted(arrays)))
        rows = self.rows.get(key)
        if rows is None:
            rows = self.rows[key] = _Rows(kind, {k: [] for k in arrays})
        elif rows.kind is not kind:
            raise ValueError(f"RerunLogger: {path} holds {rows.kind.__name__}, got {kind.__name__}")
        rows.times.append(now)
        rows.counts.append(counts.pop())
        for k, a in arrays.items():
            rows.fields[k].append(a)

    def send(self) -> None:
        rr = self.rr
        for (path, _), rows in self.rows.items():
            step = np.array([t[0] for t in rows.times], dtype=np.int64)
            time_s = np.array([t[1] for t in rows.times], dtype=np.float64)
            episode = np.array([t[2] for t in rows.times], dtype=np.int64)
            indexes = [
                rr.TimeColumn("step", sequence=step),
                rr.TimeColumn("time", duration=time_s),
                rr.TimeColumn("episode", sequence=episode),
            ]
            data = {k: np.concatenate(v) for k, v in rows.fields.items()}
            columns = rows.kind.columns(**data).partition(rows.counts)
            self.rec.send_columns(path, indexes=indexes, columns=columns)
        self.rows.clear()


# --------------------------------------------------------------------------------------------
# the blueprint


def blueprint(lg: RerunLogger):
    """The layout: a column per logged sub-env (3D view over controls, reward and state),
    side by side up to ``MAX_COLUMNS``, else in tabs; the time panel on ``time``."""
    rrb = importlib.import_module("rerun.blueprint")
    columns = [
        rrb.Vertical(
            _view3d(lg, e),
            rrb.TimeSeriesView(origin=f"/env/{e}/controls", name=f"env {e}: controls"),
            rrb.TimeSeriesView(origin=f"/env/{e}/reward", name=f"env {e}: reward"),
            rrb.TimeSeriesView(origin=f"/env/{e}/state", name=f"env {e}: state"),
            row_shares=[3.0, 1.0, 1.0, 1.0],
            name=f"env {e}",
        )
        for e in lg.env_ids
    ]
    top = rrb.Horizontal(*columns) if len(columns) <= MAX_COLUMNS else rrb.Tabs(*columns)
    return rrb.Blueprint(
        top,
        rrb.BlueprintPanel(state="collapsed"),
        rrb.SelectionPanel(state="collapsed"),
        rrb.TimePanel(state="expanded", timeline="time"),
    )


SERIES_COLORS = (  # matplotlib's tab10: a series has the same color in every env's plot
    (31, 119, 180), (255, 127, 14), (44, 160, 44), (214, 39, 40), (148, 103, 189),
    (140, 86, 75), (227, 119, 194), (127, 127, 127), (188, 189, 34), (23, 190, 207),
)  # fmt: skip


def _view3d(lg: RerunLogger, e: int):
    """Sub-env e's 3D view: its eye starts behind the craft and follows body 0; the trail
    shows every episode up to the time cursor (on ``episode``: the current one, whole)."""
    rr, rrb = lg.rr, importlib.import_module("rerun.blueprint")
    root = f"/env/{e}"
    eye = lg._logs[e].eye
    controls = rrb.EyeControls3D(
        kind=rrb.Eye3DKind.Orbital,
        position=None if eye is None else eye[0],
        look_target=None if eye is None else eye[1],
        eye_up=(0.0, 0.0, 1.0),
        # the mesh, not the body: the viewer follows only an entity with geometry of its own
        # (a bare Transform3D is not tracked; seen in the web viewer, rerun 0.41)
        tracking_entity=f"{root}/body/0/mesh",
    )
    upto = [
        rrb.VisibleTimeRange(
            t, start=rrb.TimeRangeBoundary.infinite(), end=rrb.TimeRangeBoundary.cursor_relative()
        )
        for t in ("step", "time")
    ]
    now = rrb.TimeRangeBoundary.cursor_relative(seq=0)
    whole = rrb.VisibleTimeRange("episode", start=now, end=now)
    overrides: dict[str, Any] = {p: rrb.EntityBehavior(visible=False) for p in lg._logs[e].hidden}
    overrides[f"{root}/trail"] = rrb.VisibleTimeRanges([*upto, whole])
    spacing = 10.0 ** math.floor(math.log10(5.0 * lg.size_m))
    return rrb.Spatial3DView(
        origin=root,
        name=f"env {e}",
        eye_controls=controls,
        line_grid=rrb.LineGrid3D(visible=True, spacing=spacing, plane=rr.components.Plane3D.XY),
        overrides=overrides,
    )


def _eye(pos: np.ndarray, quat: np.ndarray, size_m: float) -> tuple[np.ndarray, np.ndarray]:
    """(eye, look target): ``EYE_OFFSET`` craft sizes from the body, in its heading's frame."""
    nose = body_rotation(quat)[:, 0]
    heading = math.atan2(nose[1], nose[0])
    fwd = np.array([math.cos(heading), math.sin(heading), 0.0])
    left = np.array([-fwd[1], fwd[0], 0.0])
    dx, dy, dz = EYE_OFFSET
    return pos + size_m * (dx * fwd + dy * left + dz * np.array([0.0, 0.0, 1.0])), pos.copy()


# --------------------------------------------------------------------------------------------
# the craft's render mesh


class _Mesh:
    """A render mesh split in two: what never moves (``mesh``, logged once) and the control
    surfaces (``surfaces``: triangles, colors and normals once, vertices as they turn)."""

    def __init__(self, mesh: RenderMesh) -> None:
        self.mesh = mesh
        rest = mesh.posed(None)
        hinged = np.zeros(len(rest), dtype=bool)
        start = 0
        for part in mesh.parts:
            hinged[start : start + len(part.vertices_m)] = part.sample is not None
            start += len(part.vertices_m)
        self.rest, self.hinged_mask = rest, hinged
        self.moving = np.flatnonzero(hinged) if mesh.hinged and hinged.any() else None
        self.size_m = float(np.ptp(rest, axis=0).max()) if len(rest) else 1.0

    def log(self, lg: RerunLogger, e: int, path: str) -> None:
        tris, colors = self.mesh.triangles, self.mesh.colors
        for name, keep in (("mesh", ~self.hinged_mask), ("surfaces", self.hinged_mask)):
            mine = keep[tris].all(axis=1)  # the triangles of the kept vertices, renumbered
            if mine.any():
                t = (np.cumsum(keep) - 1)[tris[mine]]
                drawing = mesh3d(lg.rr, self.rest[keep], t, colors[mine], name == "mesh")
                lg.log(e, f"{path}/{name}", drawing, static=True)


# --------------------------------------------------------------------------------------------
# helpers


def _check_env(venv) -> tuple[FluidVectorEnv, Scene]:
    base = venv.unwrapped
    if not isinstance(base, FluidVectorEnv):
        raise TypeError(f"RerunLogger wraps a fluidsim_envs vector env, got {type(base)}")
    scene = next((sc for sc in SCENES.values() if isinstance(base, sc.vector_cls)), None)
    if scene is None:
        raise TypeError(f"RerunLogger: no scene in SCENES for {type(base).__name__}")
    return base, scene


def _check_ids(env_ids, num_envs: int) -> tuple[int, ...]:
    ids = [int(e) for e in env_ids]
    if not ids or any(e < 0 or e >= num_envs for e in ids) or len(set(ids)) < len(ids):
        raise ValueError(
            f"RerunLogger: env_ids must be distinct sub-env indices in [0, {num_envs}), "
            f"got {env_ids!r}"
        )
    return tuple(ids)


def _check_limit(episodes_per_env):
    n = episodes_per_env
    if n is not None and (isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1):
        raise ValueError(
            f"RerunLogger: episodes_per_env must be a positive integer or None, got {n!r}"
        )
    return n


def _open(rr, scene: Scene, path, spawn: bool, recording_id, name):
    """The recording stream: application ``fluidsim-<Name-vN>``, named after the env (and
    ``name``); without log_time, and batching logged rows over seconds, not milliseconds."""
    env = scene.id.split("/")[-1]
    batcher = rr.ChunkBatcherConfig.DEFAULT()
    batcher.flush_tick = 2.0
    rec = rr.RecordingStream(f"fluidsim-{env}", recording_id=recording_id, batcher_config=batcher)
    rec.set_log_time_enabled(False)
    if spawn:
        rec.spawn(connect=path is None)
        if path is not None:
            rec.set_sinks(rr.GrpcSink(), rr.FileSink(str(path)))
    else:
        rec.save(str(path))
    rec.send_recording_name(env if name is None else f"{env}: {name}")
    return rec


def _xyzw(quat: np.ndarray) -> np.ndarray:
    """Scalar-first quaternions [n, 4] as Rerun's (x, y, z, w)."""
    return quat[:, [1, 2, 3, 0]]


def body_rotation(q) -> np.ndarray:
    """The rotation matrix (body to world) of a unit quaternion (w, x, y, z)."""
    return quat_matrices(np.asarray(q, dtype=np.float64).reshape(1, 4).copy())[0]


def _force_scale(craft: Craft) -> float:
    """Arrow length per newton: the mean force per sample that would carry the craft's weight
    draws as a quarter of its reach (the farthest sample from its center of mass)."""
    offsets = [s.offset_m for s in (*craft.plates, *craft.cylinders, *craft.buoyancy)]
    reach = max((float(np.linalg.norm(o)) for o in offsets), default=1.0)
    per_sample = craft.mass_kg * 9.81 / max(craft.num_samples, 1)
    return 0.25 * reach / per_sample


def _log_shapes(lg: RerunLogger, e: int, path: str, craft: Craft) -> list[str]:
    """A body's collision shapes in its own frame, static; the entities logged."""
    rr = lg.rr
    boxes = [s for s in craft.shapes if s.kind == "box"]
    spheres = [s for s in craft.shapes if s.kind == "sphere"]
    logged = []
    if boxes:
        drawing = rr.Boxes3D(
            centers=[s.center_m for s in boxes],
            half_sizes=[s.half_extents_m for s in boxes],
            colors=BODY,
            fill_mode="solid",
        )
        lg.log(e, f"{path}/boxes", drawing, static=True)
        logged.append(f"/env/{e}/{path}/boxes")
    if spheres:
        drawing = rr.Ellipsoids3D(
            centers=[s.center_m for s in spheres],
            half_sizes=[[s.radius_m] * 3 for s in spheres],
            colors=BUOY,
            fill_mode="solid",
        )
        lg.log(e, f"{path}/spheres", drawing, static=True)
        logged.append(f"/env/{e}/{path}/spheres")
    return logged


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


def _log_samples(lg: RerunLogger, e: int, path: str, craft: Craft) -> list[str]:
    """A body's samples in its own frame, static: one entity per glyph form; the subtree
    logged (empty if none)."""
    marks = glyphs(craft)
    for form in GLYPH_FORMS:
        mine = [g for g in marks if g.form == form]
        if mine:
            center = np.array([g.center_m for g in mine], dtype=np.float64)
            axis = np.array([g.axis for g in mine], dtype=np.float64)
            size = np.array([g.size for g in mine], dtype=np.float64)
            drawing = DRAW[form](lg.rr, center, axis, size, lg.scale_m_per_n)
            lg.log(e, f"{path}/{form}", drawing, static=True)
    return [f"/env/{e}/{path}"] if marks else []


__all__ = ["BYTES_PER_SIM_MINUTE", "INSTALL_HINT", "STATIC_BYTES", "RerunLogger", "import_rerun"]
