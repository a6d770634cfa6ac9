"""RerunLogger: episodes of each scene logged to an .rrd file, read back and compared with the
env's own state (each episode's last state captured at the autoreset, as the logger takes
it), rewards, sample forces and render meshes; the blueprint; whole episodes for evaluation;
the size budget; the error without rerun."""

import importlib
import sys

import gymnasium as gym
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import fluidsim_envs  # noqa: F401  (registers the envs)

rr = pytest.importorskip("rerun")
import pyarrow as pa  # noqa: E402  (rerun's dependency)
from rerun.chunk import RrdReader  # noqa: E402

from fluidsim_envs.physics import Craft  # noqa: E402
from fluidsim_envs.physics.craft import available  # noqa: E402
from fluidsim_envs.physics.model import GLYPH_FORMS, glyphs  # noqa: E402
from fluidsim_envs.scenes import SCENES  # noqa: E402
from fluidsim_envs.scenes.boat_on_step.rerun import SWELL_PERIOD_S  # noqa: E402
from fluidsim_envs.wrappers.rerun_logger import (  # noqa: E402
    BYTES_PER_SIM_MINUTE,
    DRAW,
    FORCE_PERIOD_S,
    STATIC_BYTES,
    SURFACE_PERIOD_S,
    RerunLogger,
    _turn_from_z,
)

E, LOGGED, STEPS, EPISODE = 3, 1, 9, 5  # the first episodes end (truncated) at step 5; rows
# are keyed (step, episode): a step that ends an episode has a row of each


def read_rrd(path) -> dict[str, list[dict]]:
    """Every row of the recording by entity path: {column: value} (static rows: no step)."""
    rows: dict[str, list[dict]] = {}
    for chunk in RrdReader(path).stream():
        batch = chunk.to_record_batch()
        names = [n for n in batch.schema.names if n != "rerun.controls.RowId"]
        columns = {n: _values(batch.column(n)) for n in names}
        for k in range(batch.num_rows):
            rows.setdefault(chunk.entity_path, []).append({n: columns[n][k] for n in names})
    return rows


def _values(column: pa.Array) -> list:
    """Python values; durations (the ``time`` timeline) as integer nanoseconds."""
    if pa.types.is_duration(column.type):
        column = column.cast(pa.int64())
    return column.to_pylist()


def series(rows, entity: str, column: str) -> dict[tuple[int, int], object]:
    """One component of a temporal entity by (step, episode), its single instance unwrapped;
    a step that ends an episode has a row of each."""
    out = {}
    for row in rows.get(entity, []):
        if "step" in row and row.get(column) is not None:
            value = row[column]
            key = (row["step"], row["episode"])
            assert key not in out, (entity, column, key)
            out[key] = value[0] if isinstance(value, list) and len(value) == 1 else value
    return out


def static(rows, entity: str, column: str):
    (value,) = [r[column] for r in rows[entity] if "step" not in r and column in r]
    return value


def snapshot(env, reward=None) -> dict:
    """What the logger logs of sub-env LOGGED now, taken from the env."""
    sim = env.sim
    points, forces, _ = sim.sample_forces(sim.controls.copy(), env_index=LOGGED)
    return {
        "pos": np.array(sim.pos[LOGGED]),
        "vel": np.array(sim.lin_vel[LOGGED]),
        "quat": np.array(sim.quat[LOGGED]),
        "controls": sim.controls[LOGGED].copy(),
        "points": points,
        "forces": forces,
        "clock": float(sim.clock[LOGGED]),
        "reward": reward,
    }


def run(env_id: str, path, watch=None, **kwargs) -> tuple[dict, dict, object]:
    """STEPS random steps through the logger, sub-env LOGGED logged; what the env held at each
    logged row, by (step, episode): after each step, and at each episode's end (taken by our
    own autoreset hook, after the logger's)."""
    venv = gym.make_vec(
        env_id, num_envs=E, vectorization_mode="vector_entry_point", max_episode_steps=EPISODE,
        **kwargs,
    )  # fmt: skip
    env = venv.unwrapped
    logger = RerunLogger(venv, path=str(path), env_ids=(LOGGED,), recording_id="test")
    seen: dict[tuple[int, int], dict] = {}
    ending: list[dict] = []

    def capture(ended, info, reward):
        if LOGGED in ended:
            terms = {k: v[LOGGED] for k, v in info["reward_terms"].items()}
            ending.append({**snapshot(env), "terms": terms, "watched": watch and watch(env)})

    env.before_autoreset.append(capture)
    rng = np.random.default_rng(0)
    _, info = logger.reset(seed=1)
    seen[0, 0] = {**snapshot(env), "terms": {}, "watched": watch and watch(env)}
    for step in range(1, STEPS + 1):
        _, reward, _, _, info = logger.step(rng.uniform(-1, 1, (E, 3)))
        episode = int(env.episodes[LOGGED]) - 1
        if ending:  # the episode that ended at this step: its last state is this step's row
            seen[step, episode - 1] = {**ending.pop(), "reward": reward[LOGGED]}
            continue  # the next episode's reset state is not logged
        terms = {k: v[LOGGED] for k, v in info["reward_terms"].items()}
        now = {**snapshot(env, reward[LOGGED]), "terms": terms, "watched": watch and watch(env)}
        seen[step, episode] = now
    logger.close()
    return read_rrd(path), seen, env


def kind(key) -> str:
    step, episode = key
    if step == 0:
        return "first"  # the reset's
    if episode > 0 and step == EPISODE * episode + 1:
        return "opening"  # the first row of an episode the autoreset began
    return "last" if step == EPISODE * (episode + 1) else "step"


def drawn(key, period_s, env) -> bool:
    """Whether the logger draws at this row: first and last rows, then one per period."""
    every = max(1, round(period_s / (env.params.dt * env.params.substeps)))
    return kind(key) != "step" or (key[0] - EPISODE * key[1]) % every == 0


FIRST_COLUMN = {  # where each glyph form's drawing keeps its positions
    "square": "Boxes3D:centers",
    "rod": "Capsules3D:translations",
    "ball": "Ellipsoids3D:centers",
    "arrow": "Arrows3D:origins",
}


def check_samples(rows, root, craft) -> None:
    """Every sample drawn once, static, as its kind's glyph, where the glyph says."""
    marks = glyphs(craft)
    drawn_samples = 0
    for form in GLYPH_FORMS:
        mine = [g for g in marks if g.form == form]
        entity = f"{root}/body/0/samples/{form}"
        if not mine:
            assert entity not in rows
            continue
        where = np.array(static(rows, entity, FIRST_COLUMN[form]))
        if form == "rod":  # a capsule is placed by its end
            ends = [np.subtract(g.center_m, 0.5 * g.size * np.array(g.axis)) for g in mine]
            np.testing.assert_allclose(where, ends, rtol=1e-6, atol=1e-6)
        else:
            np.testing.assert_allclose(where, [g.center_m for g in mine], rtol=1e-6, atol=1e-6)
        drawn_samples += len(where)
    assert drawn_samples == craft.num_samples


def test_every_glyph_form_has_a_drawing_and_every_kind_a_form():
    assert set(DRAW) == set(GLYPH_FORMS)
    for name in available():
        assert {g.form for g in glyphs(Craft.load(name))} <= set(GLYPH_FORMS), name


def test_glyphs_turn_up_onto_their_axis():
    rng = np.random.default_rng(0)
    axes = np.concatenate([[[0, 0, 1.0], [0, 0, -1.0], [1.0, 0, 0]], rng.normal(size=(20, 3))])
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    for (x, y, z, w), axis in zip(_turn_from_z(axes), axes, strict=True):
        turned = Rotation.from_quat([x, y, z, w]).apply([0.0, 0.0, 1.0])
        np.testing.assert_allclose(turned, axis, atol=1e-12)


def check_poses(rows, seen, env, root) -> None:
    """Every row's pose, time and trail; episode 0's last state alone at step EPISODE (the
    autoreset's state of episode 1 is not logged), episode 1 from the next step on."""
    keys = sorted(seen)
    assert keys == [(k, 0) for k in range(EPISODE + 1)] + [
        (k, 1) for k in range(EPISODE + 1, STEPS + 1)
    ]
    translation = series(rows, f"{root}/body/0", "Transform3D:translation")
    quaternion = series(rows, f"{root}/body/0", "Transform3D:quaternion")
    times = series(rows, f"{root}/body/0", "time")
    assert sorted(translation) == keys
    dt = env.params.dt * env.params.substeps
    for key in keys:
        s = seen[key]
        np.testing.assert_allclose(translation[key], s["pos"][0], rtol=1e-6, atol=1e-5)
        w, x, y, z = s["quat"][0]
        np.testing.assert_allclose(quaternion[key], [x, y, z, w], rtol=1e-6, atol=1e-6)
        assert times[key] == pytest.approx(key[0] * dt * 1e9, abs=1.0)
    # the episode's end is there, and differs from the next episode's start
    assert not np.allclose(seen[EPISODE, 0]["pos"][0], seen[EPISODE + 1, 1]["pos"][0])
    trail = series(rows, f"{root}/trail", "LineStrips3D:strips")
    # a segment per step, none into an episode's first row
    assert sorted(trail) == [k for k in keys if kind(k) not in ("first", "opening")]
    for (step, episode), (start, end) in trail.items():
        before = (step - 1, episode)
        np.testing.assert_allclose(start, seen[before]["pos"][0], rtol=1e-6, atol=1e-5)
        np.testing.assert_allclose(end, seen[step, episode]["pos"][0], rtol=1e-6, atol=1e-5)


def check_forces(rows, seen, env, root) -> None:
    """Drawn rows: the arrows, in the body's frame, put back in the world, are the sample
    forces where they act."""
    origins = series(rows, f"{root}/body/0/forces", "Arrows3D:origins")
    vectors = series(rows, f"{root}/body/0/forces", "Arrows3D:vectors")
    scale = static(rows, f"{root}/body/0/forces", "scale_m_per_n")[0]
    assert scale > 0.0
    assert sorted(origins) == [k for k in sorted(seen) if kind(k) in ("first", "opening")]
    assert sorted(vectors) == [k for k in sorted(seen) if drawn(k, FORCE_PERIOD_S, env)]
    assert len(vectors) < len(seen)  # not every step
    origins = {episode: where for (_, episode), where in origins.items()}
    n = env.sim.crafts[0].num_samples
    for key in vectors:
        s = seen[key]
        turn = Rotation.from_quat(s["quat"][0][[1, 2, 3, 0]])
        world = turn.apply(origins[key[1]]) + s["pos"][0]
        np.testing.assert_allclose(world, s["points"][:n], rtol=1e-6, atol=1e-5)
        big = np.abs(s["forces"]).max()
        np.testing.assert_allclose(
            turn.apply(vectors[key]) / scale, s["forces"][:n], rtol=1e-5, atol=1e-5 * big
        )


def check_mesh(rows, seen, env, root) -> None:
    """The render mesh: the fixed part once, the control surfaces as the commands turn them."""
    mesh = scene_of(env).meshes(env)[0]
    hinged = np.concatenate([np.full(len(p.vertices_m), p.sample is not None) for p in mesh.parts])
    fixed = np.array(static(rows, f"{root}/body/0/mesh", "Mesh3D:vertex_positions"))
    np.testing.assert_allclose(fixed, mesh.posed(None)[~hinged], rtol=1e-6, atol=1e-6)
    faces = static(rows, f"{root}/body/0/mesh", "Mesh3D:triangle_indices")
    assert len(faces) + len(
        static(rows, f"{root}/body/0/surfaces", "Mesh3D:triangle_indices")
    ) == len(mesh.triangles)
    surfaces = series(rows, f"{root}/body/0/surfaces", "Mesh3D:vertex_positions")
    assert sorted(surfaces) == [k for k in sorted(seen) if drawn(k, SURFACE_PERIOD_S, env)]
    channels = len(mesh.craft.control_names)
    for key, verts in surfaces.items():
        commands = seen[key]["controls"][:channels]
        np.testing.assert_allclose(verts, mesh.posed(commands)[hinged], rtol=1e-6, atol=1e-6)
    assert any(np.ptp(np.array([v for v in surfaces.values()]), axis=0).ravel() > 1e-4)  # turning


def scene_of(env):
    return next(s for s in SCENES.values() if isinstance(env, s.vector_cls))


def check_common(rows, seen, env) -> None:
    root = f"/env/{LOGGED}"
    check_samples(rows, root, env.sim.crafts[0])
    assert static(rows, "/", "ViewCoordinates:xyz") == [[3, 5, 1]]  # right-handed, z up
    assert not any(p.startswith("/env/0") for p in rows)  # only the chosen sub-env
    check_poses(rows, seen, env, root)
    check_forces(rows, seen, env, root)
    check_mesh(rows, seen, env, root)
    names = static(rows, f"{root}/controls", "SeriesLines:names")
    assert names == list(env.sim.control_names)
    commands = series(rows, f"{root}/controls", "Scalars:scalars")
    terms = static(rows, f"{root}/reward", "SeriesLines:names")
    rewards = series(rows, f"{root}/reward", "Scalars:scalars")
    assert sorted(rewards) == [k for k in sorted(seen) if kind(k) != "first"]  # not at a reset
    for key, s in seen.items():
        expected = np.zeros_like(s["controls"]) if kind(key) == "first" else s["controls"]
        assert commands[key] == expected.tolist()
        if kind(key) != "first":
            assert terms == ["total", *s["terms"]]
            assert rewards[key] == [s["reward"], *s["terms"].values()]
    # the new episode at step EPISODE starts without a command, the last one had some
    assert any(commands[EPISODE, 0]) and (EPISODE, 1) not in commands
    state = series(rows, f"{root}/state", "Scalars:scalars")
    altitude = static(rows, f"{root}/state", "SeriesLines:names").index("altitude_m")
    assert {k: v[altitude] for k, v in state.items()} == {
        k: s["pos"][0, 2] for k, s in seen.items()
    }


def test_paper_airplane(tmp_path):
    rows, seen, env = run("fluidsim/PaperAirplane-v0", tmp_path / "dart.rrd")
    check_common(rows, seen, env)
    root = f"/env/{LOGGED}"
    craft = env.craft
    half = static(rows, f"{root}/body/0/boxes", "Boxes3D:half_sizes")
    np.testing.assert_allclose(half, [s.half_extents_m for s in craft.shapes], rtol=1e-6)
    target = series(rows, f"{root}/target", "Points3D:positions")
    assert sorted(target) == [(0, 0), (EPISODE + 1, 1)]  # each episode's, at its first row
    np.testing.assert_allclose(target[EPISODE + 1, 1][:2], env.target[LOGGED], rtol=1e-6)
    ground = np.array(series(rows, f"{root}/ground", "Mesh3D:vertex_positions")[EPISODE + 1, 1])
    assert np.allclose(ground[:, 2], -0.005)  # the ground around this course, not beyond
    for xy in (env.target[LOGGED], seen[EPISODE + 1, 1]["pos"][0, :2]):
        assert (ground[:, :2].min(0) < xy).all() and (xy < ground[:, :2].max(0)).all()
    assert np.ptp(ground[:, :2], axis=0).max() < 4 * env.params.arena_radius_m
    speed = series(rows, f"{root}/state", "Scalars:scalars")
    for k in ((0, 0), (3, 0), (EPISODE, 0)):
        assert speed[k][0] == pytest.approx(np.linalg.norm(seen[k]["vel"][0]), rel=1e-12)
    distance = series(rows, f"{root}/state/task", "Scalars:scalars")
    assert sorted(distance) == sorted(k for k in seen if kind(k) != "first")


def test_boat_on_step_with_swell(tmp_path):
    swell = ((0.3, 20.0, 30.0),)
    rows, seen, env = run("fluidsim/BoatOnStep-v0", tmp_path / "boat.rrd", swell=swell)
    check_common(rows, seen, env)
    root = f"/env/{LOGGED}"
    buoys = series(rows, f"{root}/buoys", "Points3D:positions")
    assert sorted(buoys) == [(0, 0), (EPISODE + 1, 1)]
    first = np.asarray(buoys[EPISODE + 1, 1])
    np.testing.assert_allclose(first[:, :2], env.buoys[LOGGED], rtol=1e-6)
    gates = series(rows, f"{root}/gates", "LineStrips3D:strips")
    assert len(gates[EPISODE + 1, 1]) == len(env.buoys[LOGGED]) // 2
    water = series(rows, f"{root}/water", "Mesh3D:vertex_positions")
    assert sorted(water) == [k for k in sorted(seen) if drawn(k, SWELL_PERIOD_S, env)]
    for key, vertices in water.items():  # the surface at that row's clock, around the boat
        v = np.asarray(vertices)
        expected = env.world.surface_height(v[:, 0], v[:, 1], seen[key]["clock"])
        np.testing.assert_allclose(v[:, 2], expected, atol=1e-6)
        assert np.ptp(v[:, 2]) > 0.3  # a swell, not a flat sheet
        np.testing.assert_allclose(v.mean(0)[:2], seen[key]["pos"][0, :2], atol=1e-3)
    state = series(rows, f"{root}/state", "Scalars:scalars")
    assert state[3, 0][0] == pytest.approx(np.linalg.norm(seen[3, 0]["vel"][0, :2]), rel=1e-12)
    names = static(rows, f"{root}/state", "SeriesLines:names")
    w, x, y, z = seen[0, 0]["quat"][0]
    trim = state[0, 0][names.index("trim_deg")]
    assert trim == pytest.approx(np.degrees(np.arcsin(2 * (x * z - w * y))), abs=1e-9)
    assert trim > 0.0  # at rest the bow floats a little up


def test_submarine_wake(tmp_path):
    from fluidsim_envs.scenes.submarine_wake.rerun import TRACER_PERIOD_S, TRACERS_LOGGED
    from fluidsim_envs.scenes.submarine_wake.view import TRACERS, WatchedTracers

    watched = []

    def watch(env):  # the view's own tracers, looked at every row: the same water
        if not watched:
            watched.append(WatchedTracers(env))
        return watched[0].update(LOGGED).positions.copy()

    rows, seen, env = run("fluidsim/SubmarineWake-v0", tmp_path / "sub.rrd", watch=watch)
    check_common(rows, seen, env)
    root = f"/env/{LOGGED}"
    tracers = series(rows, f"{root}/tracers", "Points3D:positions")
    assert sorted(tracers) == [k for k in sorted(seen) if drawn(k, TRACER_PERIOD_S, env)]
    stride = TRACERS // TRACERS_LOGGED
    for key, positions in tracers.items():  # seeded at each episode's start, moved each step
        assert len(positions) == TRACERS_LOGGED
        np.testing.assert_allclose(positions, seen[key]["watched"][::stride], rtol=1e-6)
    last = [tracers[k] for k in sorted(tracers) if k[1] == 0]
    assert not np.allclose(last[0], last[-1])  # they move with the water
    lead = series(rows, f"{root}/lead", "Transform3D:translation")
    np.testing.assert_allclose(lead[STEPS, 1], env.lead[:3, LOGGED], rtol=1e-6)
    floor = np.array(series(rows, f"{root}/floor", "Mesh3D:vertex_positions")[EPISODE + 1, 1])
    assert set(floor[:, 2]) == {-env.params.floor_depth_m}


def test_the_blueprint_and_the_name_go_with_the_recording(tmp_path):
    path = tmp_path / "named.rrd"
    venv = gym.make_vec("fluidsim/PaperAirplane-v0", num_envs=3,
                        vectorization_mode="vector_entry_point")  # fmt: skip
    logger = RerunLogger(venv, path=str(path), env_ids=(0, 2), name="run 7")
    logger.reset(seed=0)
    start = venv.unwrapped.sim.pos.copy()
    logger.step(np.zeros((3, 3)))
    logger.close()
    reader = RrdReader(path)
    (recording,) = reader.recordings()
    assert recording.application_id == "fluidsim-PaperAirplane-v0"
    rows = read_rrd(path)
    assert static(rows, "/__properties", "RecordingInfo:name") == ["PaperAirplane-v0: run 7"]
    (store,) = reader.blueprints()
    found: dict[str, list] = {}  # blueprint component -> its rows (single values unwrapped)
    for chunk in reader.stream(store=store):
        batch = chunk.to_record_batch()
        for name in batch.schema.names:
            if ":" in name:
                rows = _values(batch.column(name))
                found.setdefault(name, []).extend(v[0] if len(v) == 1 else v for v in rows)
    views = found["ViewBlueprint:class_identifier"]
    assert sorted(views) == ["3D"] * 2 + ["TimeSeries"] * 6  # a column per sub-env
    origins = found["ViewBlueprint:space_origin"]
    for e in (0, 2):
        for group in ("", "/controls", "/reward", "/state"):
            assert f"/env/{e}{group}" in origins
    tracked = found["EyeControls3D:tracking_entity"]
    assert sorted(tracked) == ["/env/0/body/0/mesh", "/env/2/body/0/mesh"]  # follow the craft
    for target, eye in zip(
        found["EyeControls3D:look_target"], found["EyeControls3D:position"], strict=True
    ):
        assert any(np.allclose(target, start[e, 0], atol=1e-5) for e in (0, 2))  # the launch
        assert 0.1 < np.linalg.norm(np.subtract(eye, target)) < 3.0  # close to the dart
    assert found["TimePanelBlueprint:timeline"] == ["time"]
    # the collision shapes and glyphs are there, hidden; the trail shows its history
    assert found["EntityBehavior:visible"] == [False] * 4  # boxes and samples, two sub-envs
    for ranges in found["VisibleTimeRanges:ranges"]:
        assert [r["timeline"] for r in ranges] == ["step", "time", "episode"]
        assert ranges[0]["range"] == {"start": None, "end": 0}  # up to the cursor


def test_evaluation_logs_whole_episodes(tmp_path):
    """episodes_per_env=1: each logged sub-env's first episode, from its first state to its
    last (the touchdown, taken before the autoreset), and nothing of the next."""
    from fluidsim_envs.evaluation import first_episodes

    scene = SCENES["fluidsim/PaperAirplane-v0"]
    venv = gym.make_vec(scene.id, num_envs=4, vectorization_mode="vector_entry_point",
                        **scene.short_episodes)  # fmt: skip
    env = venv.unwrapped
    path = tmp_path / "eval.rrd"
    logger = RerunLogger(venv, path=str(path), env_ids=(0, 3), episodes_per_env=1)
    last: dict[int, np.ndarray] = {}

    def capture(ended, info, reward):
        for e in ended:
            last.setdefault(int(e), np.array(env.sim.pos[e, 0]))

    env.before_autoreset.append(capture)
    results = first_episodes(logger, scene.pilot(logger), seed=3)
    logger.close()
    assert env.episodes.min() >= 2  # the sub-envs went on past their first episode
    rows = read_rrd(path)
    for e in (0, 3):
        poses = series(rows, f"/env/{e}/body/0", "Transform3D:translation")
        length = int(results["length"][e])
        assert sorted(poses) == [(k, 0) for k in range(length + 1)]  # one whole episode
        np.testing.assert_allclose(poses[length, 0], last[e], rtol=1e-6, atol=1e-6)
        rewards = series(rows, f"/env/{e}/reward", "Scalars:scalars")
        assert max(rewards) == (length, 0)


def test_a_diverged_episode_ends_in_the_plots_not_the_views(tmp_path):
    """A blown-up state: its last row has no pose (nothing finite to draw), its reward and
    state are there (NaN where the state is), and the next episode starts as any other."""
    scene = SCENES["fluidsim/PaperAirplane-v0"]
    venv = gym.make_vec(scene.id, num_envs=2, vectorization_mode="vector_entry_point")
    path = tmp_path / "diverged.rrd"
    logger = RerunLogger(venv, path=str(path), env_ids=(1,))
    logger.reset(seed=0)
    logger.step(np.zeros((2, 3)))
    scene.diverge(venv.unwrapped, 1)
    _, _, terminated, _, info = logger.step(np.zeros((2, 3)))
    assert terminated[1] and info["physics_diverged"][1]
    logger.close()
    rows = read_rrd(path)
    poses = series(rows, "/env/1/body/0", "Transform3D:translation")
    assert sorted(poses) == [(0, 0), (1, 0)]  # no pose for the blown-up state
    assert all(np.isfinite(p).all() for p in poses.values())
    assert (2, 0) in series(rows, "/env/1/reward", "Scalars:scalars")
    assert np.isnan(series(rows, "/env/1/state", "Scalars:scalars")[2, 0]).any()


SIZE_STEPS = {  # about 20 simulated seconds of each scene
    "fluidsim/PaperAirplane-v0": 600,
    "fluidsim/BoatOnStep-v0": 400,
    "fluidsim/SubmarineWake-v0": 200,
}


@pytest.mark.parametrize("env_id", sorted(SIZE_STEPS))
def test_a_recording_keeps_to_its_size_budget(env_id, tmp_path):
    """Two sub-envs flown by the scripted pilot: the file within STATIC_BYTES and
    BYTES_PER_SIM_MINUTE per simulated minute per logged sub-env, in few chunks."""
    logged, steps = (0, 1), SIZE_STEPS[env_id]
    venv = gym.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point")
    path = tmp_path / "size.rrd"
    logger = RerunLogger(venv, path=str(path), env_ids=logged)
    pilot = SCENES[env_id].pilot(logger)
    obs, _ = logger.reset(seed=0)
    for _ in range(steps):
        obs, _, terminated, truncated, _ = logger.step(pilot(obs))
        if hasattr(pilot, "reset") and (terminated | truncated).any():
            pilot.reset(terminated | truncated)
    logger.close()
    env = venv.unwrapped
    minutes = steps * env.params.dt * env.params.substeps / 60.0
    budget = len(logged) * (STATIC_BYTES + BYTES_PER_SIM_MINUTE * minutes)
    size = path.stat().st_size
    assert size <= budget, (env_id, size, budget)
    chunks = sum(1 for _ in RrdReader(path).stream())
    assert chunks <= 60 * len(logged), chunks  # sent as columns, not row by row
    assert size > 0.2 * budget  # the budget is measured, not a blank cheque


def test_the_layout_picture_is_drawn_from_a_recording(tmp_path):
    """rerun_layout: record measures the file against the budget; draw lays the blueprint's
    panels out from the recording (the docs picture's command)."""
    from fluidsim_envs.wrappers import rerun_layout

    rrd, png = tmp_path / "dart.rrd", tmp_path / "layout.png"
    sizes = rerun_layout.record("fluidsim/PaperAirplane-v0", rrd, envs=2, seed=0, minutes=None)
    assert sizes["bytes"] == rrd.stat().st_size <= sizes["budget_bytes"]
    assert 0 < sizes["static_bytes"] < sizes["bytes"]
    assert rerun_layout.Recording(rrd).envs() == [0, 1]
    assert rerun_layout.main(["draw", str(rrd), str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size < 300_000
    assert rerun_layout.main(["record", "fluidsim/Nope-v0", str(rrd)]) == 2  # named error


def test_bad_arguments():
    venv = gym.make_vec("fluidsim/PaperAirplane-v0", num_envs=2,
                        vectorization_mode="vector_entry_point")  # fmt: skip
    with pytest.raises(ValueError, match="env_ids must be distinct sub-env indices"):
        RerunLogger(venv, path="unused.rrd", env_ids=(2,))
    with pytest.raises(ValueError, match="give a path"):
        RerunLogger(venv)
    with pytest.raises(ValueError, match="episodes_per_env must be a positive integer.*0"):
        RerunLogger(venv, path="unused.rrd", episodes_per_env=0)
    with pytest.raises(TypeError, match="fluidsim_envs vector env"):
        RerunLogger(gym.make_vec("CartPole-v1", num_envs=1), path="unused.rrd")
    assert venv.unwrapped.before_autoreset == []  # no refused logger left a hook behind


def test_without_rerun_import_works_and_use_says_how_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "rerun", None)  # `import rerun` now raises ImportError
    monkeypatch.delitem(sys.modules, "fluidsim_envs.wrappers.rerun_logger")
    module = importlib.import_module("fluidsim_envs.wrappers.rerun_logger")
    venv = gym.make_vec("fluidsim/PaperAirplane-v0", num_envs=1,
                        vectorization_mode="vector_entry_point")  # fmt: skip
    with pytest.raises(ImportError, match=r'pip install "fluidsim-envs\[rerun\]"'):
        module.RerunLogger(venv, path="unused.rrd")
