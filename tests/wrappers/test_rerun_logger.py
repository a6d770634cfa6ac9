"""RerunLogger: episodes of each scene logged to an .rrd file, read back and compared with the
env's own state, rewards and sample forces; the error without rerun."""

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
from fluidsim_envs.scenes.boat_on_step.rerun import SWELL_EVERY  # noqa: E402
from fluidsim_envs.wrappers.rerun_logger import DRAW, RerunLogger, _turn_from_z  # noqa: E402

E, LOGGED, STEPS, EPISODE = 3, 1, 8, 5  # the episodes end (truncated) at step 5


def read_rrd(path) -> dict[str, list[dict]]:
    """Every row of the recording by entity path: {column: value} (static rows: no step)."""
    rows: dict[str, list[dict]] = {}
    for chunk in RrdReader(path).stream():
        batch = chunk.to_record_batch()
        names = [n for n in batch.schema.names if n not in ("log_time", "rerun.controls.RowId")]
        columns = {n: _values(batch.column(n)) for n in names}
        for k in range(batch.num_rows):
            rows.setdefault(chunk.entity_path, []).append({n: columns[n][k] for n in names})
    return rows


def _values(column: pa.Array) -> list:
    """Python values; durations (the ``time`` timeline) as integer nanoseconds."""
    if pa.types.is_duration(column.type):
        column = column.cast(pa.int64())
    return column.to_pylist()


def series(rows, entity: str, column: str) -> dict[int, object]:
    """One component of a temporal entity by step (its single instance unwrapped)."""
    out = {}
    for row in rows[entity]:
        if "step" in row and row.get(column) is not None:
            value = row[column]
            out[row["step"]] = value[0] if isinstance(value, list) and len(value) == 1 else value
    return out


def static(rows, entity: str, column: str):
    (value,) = [r[column] for r in rows[entity] if "step" not in r and column in r]
    return value


def run(env_id: str, path, watch=None, **kwargs) -> tuple[dict, list[dict]]:
    """STEPS random steps of sub-env LOGGED through the logger; what the env said each step."""
    venv = gym.make_vec(
        env_id, num_envs=E, vectorization_mode="vector_entry_point", max_episode_steps=EPISODE,
        **kwargs,
    )  # fmt: skip
    env = venv.unwrapped
    logger = RerunLogger(venv, path=str(path), env_ids=(LOGGED,), recording_id="test")
    rng = np.random.default_rng(0)
    seen = []
    for step in range(STEPS + 1):
        if step == 0:
            _, info = logger.reset(seed=1)
        else:
            _, reward, _, _, info = logger.step(rng.uniform(-1, 1, (E, 3)))
        # the controls the logger used are the Simulator's now (its sample_forces set them)
        controls = env.sim.controls.copy()
        points, forces, _ = env.sim.sample_forces(controls, env_index=LOGGED)
        seen.append(
            {
                "pos": np.array(env.sim.pos[LOGGED]),
                "vel": np.array(env.sim.lin_vel[LOGGED]),
                "quat": np.array(env.sim.quat[LOGGED]),
                "controls": controls[LOGGED],
                "points": points,
                "forces": forces,
                "terms": {k: v[LOGGED] for k, v in info.get("reward_terms", {}).items()},
                "reward": reward[LOGGED] if step else None,
                "clock": float(env.sim.clock[LOGGED]),
                "watched": None if watch is None else watch(env),
            }
        )
    logger.close()
    return read_rrd(path), seen, env


FIRST_COLUMN = {  # where each glyph form's drawing keeps its positions
    "square": "Boxes3D:centers",
    "rod": "Capsules3D:translations",
    "ball": "Ellipsoids3D:centers",
    "arrow": "Arrows3D:origins",
}


def check_samples(rows, root, craft) -> None:
    """Every sample drawn once, static, as its kind's glyph, where the glyph says."""
    marks = glyphs(craft)
    drawn = 0
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
        drawn += len(where)
    assert drawn == craft.num_samples


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


def check_common(rows, seen, env) -> None:
    root = f"/env/{LOGGED}"
    check_samples(rows, root, env.sim.crafts[0])
    assert static(rows, "/", "ViewCoordinates:xyz") == [[3, 5, 1]]  # right-handed, z up
    assert "/env/0/body/0" not in rows  # only the chosen sub-env
    steps = list(range(STEPS + 1))
    dt = env.params.dt * env.params.substeps
    times = series(rows, f"{root}/body/0", "time")
    np.testing.assert_allclose([times[k] for k in steps], np.array(steps) * dt * 1e9, atol=1.0)
    translation = series(rows, f"{root}/body/0", "Transform3D:translation")
    quaternion = series(rows, f"{root}/body/0", "Transform3D:quaternion")
    origins = series(rows, f"{root}/forces", "Arrows3D:origins")
    vectors = series(rows, f"{root}/forces", "Arrows3D:vectors")
    scale = static(rows, f"{root}/forces", "scale_m_per_n")[0]
    assert scale > 0.0
    for k in steps:
        s = seen[k]
        np.testing.assert_allclose(translation[k], s["pos"][0], rtol=1e-6, atol=1e-5)
        w, x, y, z = s["quat"][0]
        np.testing.assert_allclose(quaternion[k], [x, y, z, w], rtol=1e-6, atol=1e-6)
        assert len(origins[k]) == len(s["points"]) == sum(c.num_samples for c in env.sim.crafts)
        np.testing.assert_allclose(origins[k], s["points"], rtol=1e-6, atol=1e-5)
        big = np.abs(s["forces"]).max()
        np.testing.assert_allclose(
            np.asarray(vectors[k]) / scale, s["forces"], rtol=1e-5, atol=1e-6 * big
        )
        for name, value in zip(env.sim.control_names, s["controls"], strict=True):
            assert series(rows, f"{root}/controls/{name}", "Scalars:scalars")[k] == value
        for control, value in zip(env.craft.controls, s["controls"], strict=True):
            entity = f"{root}/controls/{control.name}_deg"  # surfaces only
            if control.max_deflection_deg == 0.0:
                assert entity not in rows
            else:
                deg = series(rows, entity, "Scalars:scalars")[k]
                assert deg == value * control.max_deflection_deg
        if k:  # a reset has no reward
            for term, value in s["terms"].items():
                assert series(rows, f"{root}/reward/{term}", "Scalars:scalars")[k] == value
            assert series(rows, f"{root}/reward/total", "Scalars:scalars")[k] == s["reward"]
    assert 0 not in series(rows, f"{root}/reward/total", "Scalars:scalars")
    # the new episode at step EPISODE starts without a command
    assert not np.any(seen[EPISODE]["controls"]) and np.any(seen[EPISODE - 1]["controls"])
    altitude = series(rows, f"{root}/state/altitude_m", "Scalars:scalars")
    assert [altitude[k] for k in steps] == [s["pos"][0, 2] for s in seen]
    shapes = [r for r in rows[f"{root}/body/0/boxes"] if "step" not in r]
    assert shapes and shapes[0]["Boxes3D:half_sizes"]


def test_paper_airplane(tmp_path):
    rows, seen, env = run("fluidsim/PaperAirplane-v0", tmp_path / "dart.rrd")
    check_common(rows, seen, env)
    root = f"/env/{LOGGED}"
    craft = env.craft
    half = static(rows, f"{root}/body/0/boxes", "Boxes3D:half_sizes")
    np.testing.assert_allclose(half, [s.half_extents_m for s in craft.shapes], rtol=1e-6)
    assert static(rows, f"{root}/ground", "Mesh3D:vertex_positions")
    target = series(rows, f"{root}/target", "Points3D:positions")
    assert sorted(target) == [0, EPISODE]  # each episode's target, at its start
    np.testing.assert_allclose(target[EPISODE][:2], env.target[LOGGED], rtol=1e-6)
    speed = series(rows, f"{root}/state/speed_mps", "Scalars:scalars")
    for k in (0, 3):
        assert speed[k] == pytest.approx(np.linalg.norm(seen[k]["vel"][0]), rel=1e-12)


def test_boat_on_step_with_swell(tmp_path):
    swell = ((0.3, 20.0, 30.0),)
    rows, seen, env = run("fluidsim/BoatOnStep-v0", tmp_path / "boat.rrd", swell=swell)
    check_common(rows, seen, env)
    root = f"/env/{LOGGED}"
    buoys = series(rows, f"{root}/buoys", "Points3D:positions")
    assert sorted(buoys) == [0, EPISODE]
    np.testing.assert_allclose(np.asarray(buoys[EPISODE])[:, :2], env.buoys[LOGGED], rtol=1e-6)
    gates = series(rows, f"{root}/gates", "LineStrips3D:strips")
    assert len(gates[EPISODE]) == len(env.buoys[LOGGED]) // 2
    water = series(rows, f"{root}/water", "Mesh3D:vertex_positions")
    assert sorted(water) == [k for k in range(STEPS + 1) if k % SWELL_EVERY == 0]
    for k, vertices in water.items():  # the surface at that step's clock, around the boat
        v = np.asarray(vertices)
        expected = env.world.surface_height(v[:, 0], v[:, 1], seen[k]["clock"])
        np.testing.assert_allclose(v[:, 2], expected, atol=1e-6)
        assert np.ptp(v[:, 2]) > 0.3  # a swell, not a flat sheet
        np.testing.assert_allclose(v.mean(0)[:2], seen[k]["pos"][0, :2], atol=1e-3)
    speed = series(rows, f"{root}/state/speed_mps", "Scalars:scalars")  # over the ground
    assert speed[3] == pytest.approx(np.linalg.norm(seen[3]["vel"][0, :2]), rel=1e-12)
    trim = series(rows, f"{root}/state/trim_deg", "Scalars:scalars")
    w, x, y, z = seen[0]["quat"][0]
    assert trim[0] == pytest.approx(np.degrees(np.arcsin(2 * (x * z - w * y))), abs=1e-9)
    assert trim[0] > 0.0  # at rest the bow floats a little up


def test_submarine_wake(tmp_path):
    from fluidsim_envs.scenes.submarine_wake.view import TRACERS, WatchedTracers

    watched = []

    def watch(env):  # the view's own tracers, looked at every step: the same water
        if not watched:
            watched.append(WatchedTracers(env))
        return watched[0].update(LOGGED).positions.copy()

    rows, seen, env = run("fluidsim/SubmarineWake-v0", tmp_path / "sub.rrd", watch=watch)
    check_common(rows, seen, env)
    root = f"/env/{LOGGED}"
    tracers = series(rows, f"{root}/tracers", "Points3D:positions")
    assert sorted(tracers) == list(range(STEPS + 1))
    assert len(tracers[STEPS]) == TRACERS
    for k in range(STEPS + 1):  # seeded at each episode's start (0, EPISODE), moved each step
        np.testing.assert_allclose(tracers[k], seen[k]["watched"], rtol=1e-6)
    assert not np.allclose(tracers[STEPS - 1], tracers[STEPS])  # they move with the water
    lead = series(rows, f"{root}/lead", "Transform3D:translation")
    np.testing.assert_allclose(lead[STEPS], env.lead[:3, LOGGED], rtol=1e-6)
    floor = static(rows, f"{root}/floor", "Mesh3D:vertex_positions")
    assert {v[2] for v in floor} == {-env.params.floor_depth_m}


def test_bad_arguments():
    venv = gym.make_vec("fluidsim/PaperAirplane-v0", num_envs=2,
                        vectorization_mode="vector_entry_point")  # fmt: skip
    with pytest.raises(ValueError, match="env_ids must be distinct sub-env indices"):
        RerunLogger(venv, path="unused.rrd", env_ids=(2,))
    with pytest.raises(ValueError, match="give a path"):
        RerunLogger(venv)
    with pytest.raises(TypeError, match="fluidsim_envs vector env"):
        RerunLogger(gym.make_vec("CartPole-v1", num_envs=1), path="unused.rrd")


def test_without_rerun_import_works_and_use_says_how_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "rerun", None)  # `import rerun` now raises ImportError
    monkeypatch.delitem(sys.modules, "fluidsim_envs.wrappers.rerun_logger")
    module = importlib.import_module("fluidsim_envs.wrappers.rerun_logger")
    venv = gym.make_vec("fluidsim/PaperAirplane-v0", num_envs=1,
                        vectorization_mode="vector_entry_point")  # fmt: skip
    with pytest.raises(ImportError, match=r'pip install "fluidsim-envs\[rerun\]"'):
        module.RerunLogger(venv, path="unused.rrd")
