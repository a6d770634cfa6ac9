"""BoatOnStep-v0's frames: shape and content of both panels, the view following the boat and
its attitude, the trim tab's deflection, the wake restarting with the episode, a vector env's
frames and gymnasium's RecordVideo."""

import math

import gymnasium as gym
import numpy as np
import pytest

import fluidsim_envs  # noqa: F401
from fluidsim_envs.physics.kernels import quat_matrices
from fluidsim_envs.scenes.boat_on_step import kernel as TK
from fluidsim_envs.scenes.boat_on_step import view as R

ID = "fluidsim/BoatOnStep-v0"
SHAPE = (R.PLAN_H + R.SIDE_H, R.WIDTH, 3)


def panels(frame):
    """(plan, elevation), without the divider rows."""
    return frame[: R.PLAN_H - 1], frame[R.PLAN_H + 1 :]


def mask(img, color, tol=0):
    """Pixels of ``color`` (within ``tol`` in each channel)."""
    return (np.abs(img.astype(int) - np.asarray(color)) <= tol).all(axis=2)


def set_attitude(venv, trim_deg, yaw=0.0, z=0.3, e=0):
    """Put sub-env e's boat at (0, 0, z), heading ``yaw``, bow up by ``trim_deg``."""
    t = math.radians(trim_deg)
    quat = np.array(
        [
            math.cos(yaw / 2) * math.cos(t / 2),
            math.sin(yaw / 2) * math.sin(t / 2),
            -math.cos(yaw / 2) * math.sin(t / 2),
            math.sin(yaw / 2) * math.cos(t / 2),
        ]
    )
    venv.sim.reset(pos=(0.0, 0.0, z), quat=quat[None, None], env_ids=[e])


def hull_ends(side):
    """Top row of the hull's color at its aft and forward ends (the leftmost and rightmost
    tenth of its columns) in the elevation."""
    rows, cols = np.nonzero(mask(side, R.HULL))
    span = cols.max() - cols.min()
    aft = rows[cols <= cols.min() + 0.1 * span].min()
    fore = rows[cols >= cols.max() - 0.1 * span].min()
    return aft, fore


@pytest.fixture
def env():
    env = gym.make(ID, render_mode="rgb_array")
    env.reset(seed=0)
    yield env
    env.close()


def test_frames_have_a_fixed_shape_and_two_drawn_panels(env):
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.shape == SHAPE
    plan, side = panels(frame)
    # the plan at the start: water, grid, the first leg and the hull (the gates are far off)
    for img, n in ((plan, 4), (side, 8)):
        assert len(np.unique(img.reshape(-1, 3), axis=0)) >= n
    # the hull in both: its planform (5 m x 1.8 m, pointed: ~7 m^2 at 3 px/m) and profile
    assert 30 <= mask(plan, R.HULL).sum() <= 120
    assert mask(side, R.HULL).sum() > 3000
    # the plan is centered on the boat; the elevation shows sky over water, the tab and gear
    rows, cols = np.nonzero(mask(plan, R.HULL))
    assert abs(rows.mean() - R.PLAN_H / 2) < 4 and abs(cols.mean() - R.WIDTH / 2) < 4
    assert (side[0] == R.SKY).all() and mask(side, R.WATER).sum() > 10_000
    assert mask(side, R.TAB).any() and mask(side, R.GEAR).any()
    assert mask(plan, R.COURSE).any()  # the first leg starts at the boat


def test_frame_follows_the_boat(env):
    first = env.render()
    for _ in range(40):
        env.step(np.array([1.0, 0.0, 0.0]))
        frame = env.render()
    assert not np.array_equal(frame, first)
    plan, side = panels(frame)
    # still centered on the boat, with its wake (the newest stretch in the wake color) behind
    rows, cols = np.nonzero(mask(plan, R.HULL))
    assert abs(rows.mean() - R.PLAN_H / 2) < 4 and abs(cols.mean() - R.WIDTH / 2) < 4
    venv = env.unwrapped.vector
    assert venv.view.tracks[0].n == 41
    wake = mask(plan, R.WAKE, tol=50) & ~mask(plan, R.HULL)  # its newest few meters
    wake_rows, wake_cols = np.nonzero(wake)
    assert len(wake_rows) > 10
    rot = quat_matrices(np.ascontiguousarray(venv.sim.quat[0], dtype=np.float64))[0]
    fwd = np.array([rot[0, 0], -rot[1, 0]])  # the heading in image (x right, y down)
    rel = np.stack([wake_cols - cols.mean(), wake_rows - rows.mean()], 1)
    assert (rel @ fwd < 0).mean() > 0.9  # the wake lies astern
    # the speed bar has grown from nothing to the boat's speed
    speed = math.hypot(*venv.sim.lin_vel[0, 0, :2])
    bar = mask(side, R.BAR_OK) | mask(side, R.BAR_OFF)
    assert not (mask(panels(first)[1], R.BAR_OK) | mask(panels(first)[1], R.BAR_OFF)).any()
    length = bar.any(axis=0).sum()
    vmax = 1.5 * max(venv.params.target_speed_mps)
    assert length == pytest.approx((R.WIDTH - 24) * speed / vmax, abs=2)


@pytest.mark.parametrize("yaw", [0.0, 2.0, -2.5])
def test_elevation_shows_the_trim_with_the_bow_to_the_right(env, yaw):
    venv = env.unwrapped.vector
    set_attitude(venv, 12.0, yaw)
    aft, fore = hull_ends(panels(env.render())[1])
    # the hull's 5 m turned 12 degrees bow up: the bow ~54 px above the transom
    assert aft - fore > 0.6 * 5.0 * math.sin(math.radians(12.0)) * R.SIDE_SCALE
    set_attitude(venv, -6.0, yaw)
    aft_down, fore_down = hull_ends(panels(env.render())[1])
    assert fore_down > fore + 40  # bow down: its top lower than at 12 degrees bow up
    # level, the stem (whose keel rises to the sheer) tops out with the transom
    set_attitude(venv, 0.0, yaw)
    aft_level, fore_level = hull_ends(panels(env.render())[1])
    assert abs(aft_level - fore_level) <= 2


def test_elevation_shows_the_heave(env):
    venv = env.unwrapped.vector
    tops = []
    for z in (0.0, 0.5):
        set_attitude(venv, 0.0, z=z)
        tops.append(np.nonzero(mask(panels(env.render())[1], R.HULL))[0].min())
    assert tops[0] - tops[1] == pytest.approx(0.5 * R.SIDE_SCALE, abs=2)


def test_trim_tab_drawn_at_its_deflection(env):
    venv = env.unwrapped.vector
    lowest = []
    for a in (-1.0, 1.0):
        venv._act[0, 2] = a
        lowest.append(np.nonzero(mask(panels(env.render())[1], R.TAB))[0].max())
    chord = R.HullShape(venv.craft).tabs[0][1]
    drop = chord * math.sin(math.radians(15.0)) * R.SIDE_SCALE  # flush to fully down
    assert lowest[1] - lowest[0] == pytest.approx(drop, abs=3)


def test_next_gate_highlighted_and_passed_gates_dimmed():
    env = gym.make(ID, render_mode="rgb_array", first_leg_m=(30.0, 30.0), leg_m=(20.0, 20.0))
    env.reset(seed=3)
    venv = env.unwrapped.vector
    plan = panels(env.render())[0]
    assert mask(plan, R.NEXT_GATE).any() and not mask(plan, R.DIM).any()
    venv.task[TK.K_GATE, 0] = 3  # gates 1 and 2 behind
    plan = panels(env.render())[0]
    assert mask(plan, R.DIM).sum() > 4 * 10  # their four buoys and legs
    venv.task[TK.K_GATE, 0] = 7  # the course run through: nothing highlighted
    plan = panels(env.render())[0]
    assert not mask(plan, R.NEXT_GATE).any()


def test_swell_draws_a_wavy_surface(env):
    calm = panels(env.render())[1]
    # waves 4 m long travelling along the boat's heading: the side view cuts them square
    w, x, y, z = env.unwrapped.vector.sim.quat[0, 0]
    heading = math.degrees(math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)))
    swell = gym.make(ID, render_mode="rgb_array", swell=[(0.19, 4.0, heading)])
    swell.reset(seed=0)
    wavy = panels(swell.render())[1]
    # the water's top row, column by column
    top_calm = np.argmax(mask(calm, R.WATER), axis=0)
    top_wavy = np.argmax(mask(wavy, R.WATER), axis=0)
    clear = np.r_[0:100, R.WIDTH - 40 : R.WIDTH]  # columns clear of the boat
    assert np.ptp(top_calm[clear]) == 0 and np.ptp(top_wavy[clear]) > 10


@pytest.mark.filterwarnings("error::RuntimeWarning")
def test_a_diverged_state_still_renders(env):
    st, _, _ = env.unwrapped.vector.sim.kernel_arrays()
    st[:, 0, 0] = np.nan
    frame = env.render()
    assert frame.shape == SHAPE and not mask(frame, R.HULL).any()


def test_vector_env_renders_each_sub_env_and_restarts_the_wake():
    venv = gym.make_vec(
        ID,
        num_envs=2,
        vectorization_mode="vector_entry_point",
        render_mode="rgb_array",
        max_episode_steps=5,
    )
    venv.reset(seed=0)
    frames = venv.render()
    assert isinstance(frames, tuple) and len(frames) == 2
    assert all(f.shape == SHAPE and f.dtype == np.uint8 for f in frames)
    assert not np.array_equal(frames[0], frames[1])  # different courses
    inner = venv.unwrapped
    for _ in range(4):
        venv.step(np.ones((2, 3)))
        venv.render()
    assert [inner.view.tracks[e].n for e in range(2)] == [5, 5]
    _, _, _, truncated, _ = venv.step(np.ones((2, 3)))  # the fifth step: autoreset
    assert truncated.all()
    venv.render()
    assert [inner.view.tracks[e].n for e in range(2)] == [1, 1]
    np.testing.assert_allclose(inner.view.tracks[0].points(), [[0.0, 0.0]], atol=1e-9)
    inner.step(np.ones((2, 3)))  # unrendered steps leave the view alone
    assert [inner.view.tracks[e].n for e in range(2)] == [1, 1]
    venv.close()


def test_track_ring_buffer_keeps_the_newest_positions_in_order():
    tr = R.Track(0)
    for i in range(R.TRACK_LEN + 7):
        tr.push((i, -i))
    pts = tr.points()
    assert len(pts) == R.TRACK_LEN
    np.testing.assert_array_equal(pts[:, 0], np.arange(7, R.TRACK_LEN + 7))


def test_record_video_writes_an_episode(tmp_path):
    """gymnasium's RecordVideo turns the rgb_array frames into a video file."""
    pytest.importorskip("moviepy")
    from gymnasium.wrappers import RecordVideo

    env = gym.make(ID, render_mode="rgb_array", max_episode_steps=30)
    env = RecordVideo(
        env, str(tmp_path / "videos"), episode_trigger=lambda e: True, disable_logger=True
    )
    env.reset(seed=0)
    while not any(env.step(np.array([1.0, 0.0, 0.0]))[2:4]):
        pass
    env.close()
    videos = list((tmp_path / "videos").glob("*.mp4"))
    assert len(videos) == 1 and videos[0].stat().st_size > 1000
