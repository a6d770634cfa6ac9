"""SubmarineWake-v0's frames: the view owns the wake's tracers; the env's step never touches
them; looked at every step they move with the water step by step, looked at now and then they
catch up; a new episode reseeds them."""

import numpy as np

from fluidsim_envs.scenes.submarine_wake import SubmarineWakeVectorEnv
from fluidsim_envs.scenes.submarine_wake.view import TRACERS, WatchedTracers


def test_tracers_belong_to_the_view_and_follow_the_steps():
    venv = SubmarineWakeVectorEnv(num_envs=2, render_mode="rgb_array", max_episode_steps=6)
    venv.reset(seed=3)
    assert venv._view is None and "_tracers" not in vars(venv)
    first = venv.render()
    assert len(first) == 2 and first[0].dtype == np.uint8
    seen = venv.view.watched.tracers
    assert sorted(seen) == [0, 1] and len(seen[0].positions) == TRACERS
    start = seen[0].positions.copy()
    # another watcher that looks only after three steps catches up (in the lead's water now)
    late = WatchedTracers(venv)
    late.update(0)
    for _ in range(3):
        before = seen[0].positions.copy()
        venv.step(np.zeros((2, 3)))
        np.testing.assert_array_equal(seen[0].positions, before)  # step leaves the view alone
        venv.render()
    assert not np.allclose(seen[0].positions, start)  # the water moved them
    caught_up = late.update(0).positions
    assert not np.allclose(caught_up, start)
    assert caught_up.shape == seen[0].positions.shape
    # the episode ends (time limit) and restarts: the tracers are reseeded around the lead
    for _ in range(3):
        *_, truncated, _ = venv.step(np.zeros((2, 3)))
    assert truncated.all()
    venv.render()
    fresh = WatchedTracers(venv)
    np.testing.assert_array_equal(fresh.update(0).positions, seen[0].positions)
