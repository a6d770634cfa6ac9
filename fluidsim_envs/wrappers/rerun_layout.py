"""Record a scene's scripted pilot with :class:`~.rerun_logger.RerunLogger` and measure the
file, or draw a recording's blueprint layout as a picture (the Rerun viewer needs a display).

    python -m fluidsim_envs.wrappers.rerun_layout record fluidsim/PaperAirplane-v0 dart.rrd
    python -m fluidsim_envs.wrappers.rerun_layout record fluidsim/SubmarineWake-v0 sub.rrd \\
        --envs 2 --minutes 1
    python -m fluidsim_envs.wrappers.rerun_layout draw dart.rrd docs/rerun_layout.png

(the first and the last: how ``docs/rerun_layout.png`` is made).

``record`` logs each logged sub-env's first episode (``episodes_per_env=1``, as
``evaluate.py --rerun`` does) or, with ``--minutes``, that much simulated time of every
episode, then prints the file's size, the part a recording of the first states alone takes
(the static part: blueprint, meshes, names), and the rest per simulated minute per logged
sub-env, against the logger's budget.

``draw`` lays the panels out as the blueprint does (a column per logged sub-env: the 3D view
over the controls, reward and state plots; the first ``MAX_COLUMNS``, where the blueprint
puts more in tabs), filled with the recording's data at its last
logged step: the 3D panel is the view from the blueprint's eye (its offset from the craft),
centered on the craft as the eye follows it, with the render mesh, the force arrows, the
trail and the line grid at z = 0.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np

from .rerun_logger import (
    BYTES_PER_SIM_MINUTE,
    MAX_COLUMNS,
    STATIC_BYTES,
    body_rotation,
    import_rerun,
)

GROUPS = ("controls", "reward", "state")  # the plots under each 3D view, as in the blueprint

# --------------------------------------------------------------------------------------------
# record


def record(env_id: str, path: Path, envs: int, seed: int, minutes: float | None) -> dict:
    """Log the scripted pilot's episodes of ``envs`` sub-envs to ``path``; the sizes."""
    import gymnasium as gym

    import fluidsim_envs  # noqa: F401  (registers the ids)

    from ..scenes import SCENES
    from .rerun_logger import RerunLogger

    if env_id not in SCENES:
        raise ValueError(f"unknown env id {env_id!r}; known: {sorted(SCENES)}")
    if envs < 1 or (minutes is not None and not minutes > 0):
        raise ValueError(f"--envs must be >= 1 and --minutes > 0, got {envs}, {minutes}")
    ids = list(range(envs))

    def logged(file: Path, per_env: int | None):
        venv = gym.make_vec(env_id, num_envs=envs, vectorization_mode="vector_entry_point")
        return RerunLogger(
            venv,
            path=str(file),
            env_ids=ids,
            episodes_per_env=per_env,
            name=f"scripted pilot, seed {seed}",
        )

    first = logged(path.with_suffix(".static.rrd"), None)  # the first states alone
    first.reset(seed=seed)
    first.close()
    static = path.with_suffix(".static.rrd").stat().st_size
    path.with_suffix(".static.rrd").unlink()
    lg = logged(path, None if minutes else 1)
    period = lg.action_period_s
    steps = _fly(lg, SCENES[env_id].pilot(lg), seed, None if minutes is None else minutes * 60)
    lg.close()
    sim_min = steps * period / 60.0
    size = path.stat().st_size
    return {
        "bytes": size,
        "static_bytes": static,
        "sim_minutes_per_env": sim_min / envs,
        "bytes_per_sim_minute_per_env": (size - static) / sim_min,
        "budget_bytes": envs * STATIC_BYTES + BYTES_PER_SIM_MINUTE * sim_min,
    }


def _fly(lg, pilot, seed: int, seconds: float | None) -> int:
    """Fly the pilot: ``seconds`` of simulated time, or until every logged sub-env's first
    episode has ended. The steps logged, summed over the logged sub-envs."""
    obs, _ = lg.reset(seed=seed)
    logged = 0
    running = np.ones(len(lg.env_ids), dtype=bool)
    while running.any():
        obs, _, terminated, truncated, _ = lg.step(pilot(obs))
        logged += int(running.sum())
        ended = terminated | truncated
        if hasattr(pilot, "reset") and ended.any():
            pilot.reset(ended)
        if seconds is None:
            running &= ~ended[list(lg.env_ids)]
        elif lg.step_index * lg.action_period_s >= seconds:
            running[:] = False
    return logged


# --------------------------------------------------------------------------------------------
# read a recording back


class Recording:
    """What ``draw`` needs of an .rrd file: each entity's static components and its rows
    ``(step, time_s, episode, {component: value})``, and the blueprint's components."""

    def __init__(self, path: Path) -> None:
        rr = import_rerun()
        reader = rr.chunk.RrdReader(str(path))
        self.static: dict[str, dict] = defaultdict(dict)
        self.rows: dict[str, list] = defaultdict(list)
        for chunk in reader.stream():
            self._add(chunk)
        self.blueprint: dict[str, list] = defaultdict(list)
        for store in reader.blueprints():
            for chunk in reader.stream(store=store):
                batch = chunk.to_record_batch()
                for name in batch.schema.names:
                    if ":" in name:
                        self.blueprint[name] += [_one(v) for v in batch.column(name).to_pylist()]
        self.name = (self.static["/__properties"].get("RecordingInfo:name") or ["?"])[0]

    def _add(self, chunk) -> None:
        import pyarrow as pa

        batch = chunk.to_record_batch()
        names = [n for n in batch.schema.names if ":" in n]
        columns = {n: batch.column(n).to_pylist() for n in names}
        if chunk.is_static:
            for n in names:
                self.static[chunk.entity_path][n] = columns[n][-1]
            return
        step = batch.column("step").to_pylist()
        time_ns = batch.column("time").cast(pa.int64()).to_pylist()
        episode = batch.column("episode").to_pylist()
        for k in range(batch.num_rows):
            values = {n: _one(columns[n][k]) for n in names}  # one instance: unwrapped
            self.rows[chunk.entity_path].append((step[k], time_ns[k] * 1e-9, episode[k], values))

    def series(self, entity: str, component: str) -> list:
        """The rows holding ``component``, in (step, episode) order: (step, time, episode,
        value)."""
        out = [
            (s, t, ep, v[component])
            for s, t, ep, v in self.rows.get(entity, [])
            if v.get(component) is not None
        ]
        return sorted(out, key=lambda r: (r[0], r[2]))

    def last(self, entity: str, component: str):
        rows = self.series(entity, component)
        return rows[-1][3] if rows else None

    def envs(self) -> list[int]:
        roots = {int(p.split("/")[2]) for p in self.rows if p.startswith("/env/")}
        return sorted(roots)


def _one(v):
    return v[0] if isinstance(v, list) and len(v) == 1 else v


# --------------------------------------------------------------------------------------------
# draw


def draw(path: Path, out: Path) -> None:
    """The blueprint's layout filled with the recording's data, as a PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rec = Recording(path)
    envs = rec.envs()[:MAX_COLUMNS]
    if not envs:
        raise ValueError(f"{path}: no logged sub-env (no /env/<e> rows)")
    fig = plt.figure(figsize=(4.2 * len(envs) + 0.6, 9.0), dpi=80, facecolor="#1b1d22")
    grid = fig.add_gridspec(
        4,
        len(envs),
        height_ratios=[3, 1, 1, 1],
        hspace=0.45,
        wspace=0.25,
        left=0.06,
        right=0.98,
        top=0.92,
        bottom=0.05,
    )
    for col, e in enumerate(envs):
        ax = fig.add_subplot(grid[0, col], projection="3d")
        _panel3d(ax, rec, e)
        for row, group in enumerate(GROUPS, start=1):
            _plot(fig.add_subplot(grid[row, col]), rec, e, group)
    fig.suptitle(
        f"Rerun blueprint of “{rec.name}” (drawn from {path.name}; cursor at its last "
        f"step, timeline 'time')",
        color="w",
        fontsize=11,
    )
    fig.savefig(out, facecolor=fig.get_facecolor())
    plt.close(fig)


def _panel3d(ax, rec: Recording, e: int) -> None:
    """The 3D view at the last step: centered on body 0 as the eye follows it, seen from the
    blueprint's eye offset, as large around it as that offset."""
    root = f"/env/{e}"
    rows = rec.series(f"{root}/body/0", "Transform3D:translation")
    step, time_s, episode, center = rows[-1]
    center = np.asarray(center)
    offset = _eye_offset(rec, e)
    half = 0.6 * float(np.linalg.norm(offset))
    ax.set_facecolor("#2a2d34")
    ax.computed_zorder = False  # drawn in order: surfaces under the grid under the craft
    _patches(ax, rec, root, center, half)
    _grid(ax, rec, center, half)
    for b in _bodies(rec, root):
        _body(ax, rec, f"{root}/body/{b}", center, half)
    _trail(ax, rec, root, center, half)
    for axis, c in zip("xyz", center, strict=True):
        getattr(ax, f"set_{axis}lim")(c - half, c + half)
    ax.set_box_aspect((1, 1, 1), zoom=1.6)
    elev = math.degrees(math.atan2(offset[2], math.hypot(offset[0], offset[1])))
    ax.view_init(elev=elev, azim=math.degrees(math.atan2(offset[1], offset[0])))
    ax.set_axis_off()
    ax.set_title(
        f"env {e}  ·  step {step}, t = {time_s:.2f} s, episode {episode}", color="w", fontsize=9
    )


def _eye_offset(rec: Recording, e: int) -> np.ndarray:
    """The blueprint's eye position less its look target for sub-env e's view."""
    views = zip(
        rec.blueprint["EyeControls3D:tracking_entity"],
        rec.blueprint["EyeControls3D:position"],
        rec.blueprint["EyeControls3D:look_target"],
        strict=True,
    )
    for tracked, eye, target in views:
        if tracked == f"/env/{e}/body/0":
            return np.subtract(eye, target)
    return np.array([-3.0, -1.5, 1.0])


def _grid(ax, rec: Recording, center, half: float) -> None:
    """The view's line grid at z = 0 (the blueprint's spacing), where it is in view."""
    if abs(center[2]) > half:
        return
    spacing = float((rec.blueprint.get("LineGrid3D:spacing") or [1.0])[0])
    lo, hi = center[:2] - half, center[:2] + half
    for axis in (0, 1):
        for at in np.arange(math.ceil(lo[axis] / spacing), math.floor(hi[axis] / spacing) + 1):
            ends = np.array([[lo[0], lo[1], 0.0], [hi[0], hi[1], 0.0]])
            ends[:, axis] = at * spacing
            ax.plot(*ends.T, color="#6a7080", lw=0.6)


def _patches(ax, rec: Recording, root: str, center, half: float) -> None:
    """The ground, water or floor under the course (level rectangles, as last logged),
    the part of each in view."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    for entity, static in rec.static.items():
        color = static.get("Mesh3D:albedo_factor")
        corners = rec.last(entity, "Mesh3D:vertex_positions")
        if not entity.startswith(root + "/") or color is None or corners is None:
            continue
        c = np.asarray(corners)
        if len(c) != 4 or np.ptp(c[:, 2]) > 0 or abs(c[0, 2] - center[2]) > half:
            continue
        lo = np.maximum(c[:, :2].min(0), center[:2] - half)
        hi = np.minimum(c[:, :2].max(0), center[:2] + half)
        if (lo < hi).all():
            z = c[0, 2]
            quad = [[lo[0], lo[1], z], [hi[0], lo[1], z], [hi[0], hi[1], z], [lo[0], hi[1], z]]
            rgba = [((int(_one(color)) >> s) & 0xFF) / 255.0 for s in (24, 16, 8, 0)]
            ax.add_collection3d(Poly3DCollection([quad], facecolors=[rgba[:3] + [0.45]]))


def _bodies(rec: Recording, root: str) -> list[int]:
    return sorted({int(p.split("/")[4]) for p in rec.rows if p.startswith(f"{root}/body/")})


def _body(ax, rec: Recording, path: str, center, half: float) -> None:
    """A body's render mesh (fixed part and surfaces as last logged) and its force arrows,
    posed as last logged, if near the view's center."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    pos = np.asarray(rec.last(path, "Transform3D:translation"))
    if np.abs(pos - center).max() > 2 * half:
        return
    x, y, z, w = rec.last(path, "Transform3D:quaternion")
    turn = body_rotation((w, x, y, z))
    for part in ("mesh", "surfaces"):
        static = rec.static.get(f"{path}/{part}", {})
        verts = static.get("Mesh3D:vertex_positions") or rec.last(
            f"{path}/{part}", "Mesh3D:vertex_positions"
        )
        if verts is None or "Mesh3D:triangle_indices" not in static:
            continue
        world = np.asarray(verts) @ turn.T + pos
        tris = np.asarray(static["Mesh3D:triangle_indices"], dtype=int)
        colors = _face_colors(static, tris, world)
        ax.add_collection3d(Poly3DCollection(world[tris], facecolors=colors, linewidths=0))
    origins = rec.last(f"{path}/forces", "Arrows3D:origins")
    vectors = rec.last(f"{path}/forces", "Arrows3D:vectors")
    if origins is not None and vectors is not None:
        a = np.asarray(origins) @ turn.T + pos
        v = np.asarray(vectors) @ turn.T
        for p, d in zip(a, v, strict=True):
            ax.plot(*np.stack([p, p + d]).T, color="#ff7828", lw=1.0)


def _face_colors(static: dict, tris: np.ndarray, world: np.ndarray) -> np.ndarray:
    """Each triangle's color (its first vertex's), lit by a light from above."""
    packed = np.asarray(static.get("Mesh3D:vertex_colors") or [0xEBEBF0FF] * len(world))
    rgb = np.stack([(packed >> s) & 0xFF for s in (24, 16, 8)], 1)[tris[:, 0]] / 255.0
    a, b, c = (world[tris[:, k]] for k in range(3))
    n = np.cross(b - a, c - a)
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
    light = 0.55 + 0.45 * np.abs(n @ np.array([0.3, 0.2, 0.93]))
    return np.clip(rgb * light[:, None], 0.0, 1.0)


def _trail(ax, rec: Recording, root: str, center, half: float) -> None:
    """The trail up to the cursor: every segment in view, in its episode's color."""
    rows = rec.series(f"{root}/trail", "LineStrips3D:strips")
    colors = {ep: v.get("LineStrips3D:colors") for _, _, ep, v in rec.rows.get(f"{root}/trail", [])}
    for _, _, episode, strips in rows:
        a, b = np.asarray(strips)
        if max(np.abs(a - center).max(), np.abs(b - center).max()) > half:
            continue
        packed = colors[episode] or 0xFAC83CFF
        rgb = [((packed >> s) & 0xFF) / 255.0 for s in (24, 16, 8)]
        ax.plot(*np.stack([a, b]).T, color=rgb, lw=1.6)


def _plot(ax, rec: Recording, e: int, group: str) -> None:
    """A time-series panel: every series of the group's entities (``state`` with
    ``state/task``), an episode per line, the cursor at the last step."""
    ax.set_facecolor("#2a2d34")
    root = f"/env/{e}/{group}"
    entities = sorted(p for p in rec.rows if p == root or p.startswith(root + "/"))
    cursor = 0.0
    for entity in entities:
        names = rec.static.get(entity, {}).get("SeriesLines:names") or []
        rows = rec.series(entity, "Scalars:scalars")
        for k, name in enumerate(names):
            for ep in sorted({r[2] for r in rows}):
                t = [r[1] for r in rows if r[2] == ep]
                v = [np.atleast_1d(r[3])[k] for r in rows if r[2] == ep]
                ax.plot(
                    t,
                    v,
                    lw=1.0,
                    color=f"C{k + 4 * (entity != root)}",
                    label=name if ep == rows[0][2] else None,
                )
        cursor = max([cursor] + [r[1] for r in rows])
    ax.axvline(cursor, color="w", lw=0.8, alpha=0.6)
    ax.set_title(f"env {e}: {group}", color="w", fontsize=9)
    ax.tick_params(colors="#c8c8c8", labelsize=7)
    ax.legend(fontsize=6, loc="upper left", ncols=2, framealpha=0.3)
    ax.set_xlabel("time (s)", color="#c8c8c8", fontsize=7)


# --------------------------------------------------------------------------------------------
# the command line


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m fluidsim_envs.wrappers.rerun_layout", description=__doc__.split("\n\n")[0]
    )
    sub = parser.add_subparsers(dest="command", required=True)
    rec = sub.add_parser("record", help="record the scripted pilot and measure the file")
    rec.add_argument("env_id")
    rec.add_argument("rrd", type=Path)
    rec.add_argument("--envs", type=int, default=4, help="logged sub-envs (default 4)")
    rec.add_argument("--seed", type=int, default=0)
    rec.add_argument("--minutes", type=float, help="simulated minutes (default: an episode)")
    pic = sub.add_parser("draw", help="draw a recording's blueprint layout")
    pic.add_argument("rrd", type=Path)
    pic.add_argument("png", type=Path)
    args = parser.parse_args(argv)
    try:
        if args.command == "record":
            sizes = record(args.env_id, args.rrd, args.envs, args.seed, args.minutes)
            for key, value in sizes.items():
                print(f"{key:>30}: {value:,.0f}" if value > 10 else f"{key:>30}: {value:.3f}")
        else:
            draw(args.rrd, args.png)
            print(f"written: {args.png} ({args.png.stat().st_size:,} bytes)")
    except ValueError as err:
        print(f"rerun_layout: error: {err}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
