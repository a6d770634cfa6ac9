"""The scripted SubmarineWake-v0 pilot holds station: it beats doing nothing and random."""

import numpy as np

from fluidsim_envs.evaluation import first_episodes, random_policy, zero_policy
from fluidsim_envs.scenes.submarine_wake import SubmarineWakePilot, SubmarineWakeVectorEnv


def test_pilot_holds_station_and_earns_more_than_doing_nothing():
    """128 seeded episodes each. Doing nothing leaves the vehicle at 30 N of thrust, slower or
    faster than the lead and off its heading, so it drifts off station (and often loses the
    lead); the pilot closes on the station point and stays near it."""
    venv = SubmarineWakeVectorEnv(num_envs=128)
    pilot = first_episodes(venv, SubmarineWakePilot(), seed=123)
    idle = first_episodes(venv, zero_policy(venv), seed=123)
    rand = first_episodes(venv, random_policy(venv, 0), seed=123)
    assert pilot["truncated"].mean() > 0.95  # it rarely crashes or loses the lead
    assert pilot["on_station_fraction"].mean() > 0.6
    assert pilot["on_station_fraction"].mean() > 5 * idle["on_station_fraction"].mean()
    assert pilot["success"].mean() > 0.3 > idle["success"].mean()
    assert pilot["return"].mean() > idle["return"].mean() + 100.0
    assert pilot["return"].mean() > rand["return"].mean() + 100.0
    assert np.isfinite(pilot["return"]).all()
