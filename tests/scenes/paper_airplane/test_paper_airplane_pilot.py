"""The scripted PaperAirplane-v0 pilot flies the task: it beats holding the controls still."""

import numpy as np

from fluidsim_envs.evaluation import first_episodes, random_policy, zero_policy
from fluidsim_envs.scenes.paper_airplane import PaperAirplanePilot, PaperAirplaneVectorEnv


def test_pilot_lands_closer_and_earns_more_than_doing_nothing():
    """256 seeded throws each. Doing nothing glides trimmed straight ahead and lands
    wherever the glide ends; the pilot turns to the target and circles off excess height, so
    it must land much closer on average, more often within the success radius, and earn a
    higher mean return."""
    venv = PaperAirplaneVectorEnv(num_envs=256)
    dt = venv.params.dt * venv.params.substeps
    pilot = first_episodes(venv, PaperAirplanePilot(256, dt=dt), seed=123)
    idle = first_episodes(venv, zero_policy(venv), seed=123)
    rand = first_episodes(venv, random_policy(venv, 0), seed=123)
    assert not pilot["truncated"].any()
    assert pilot["distance_m"].mean() < 0.5 * idle["distance_m"].mean()
    assert pilot["success"].mean() > 3 * max(idle["success"].mean(), 0.01)
    assert pilot["return"].mean() > idle["return"].mean() + 3.0
    assert pilot["return"].mean() > rand["return"].mean() + 3.0
    # the landing itself: most touchdowns right way up and slow enough
    assert pilot["landed"].mean() > 0.6
    assert np.isfinite(pilot["return"]).all()
