"""The scripted BoatOnStep-v0 pilot gets on plane and runs the course: it beats doing nothing
and random."""

import numpy as np

from fluidsim_envs.evaluation import first_episodes, random_policy, zero_policy
from fluidsim_envs.scenes.boat_on_step import OBS, BoatOnStepPilot, BoatOnStepVectorEnv


def test_pilot_planes_and_runs_the_course():
    """128 seeded courses each. Doing nothing leaves the boat floating at the start; random
    actions wander off the course; the pilot climbs onto the plane in a few seconds and
    passes most gates."""
    venv = BoatOnStepVectorEnv(num_envs=128)
    pilot = first_episodes(venv, BoatOnStepPilot(), seed=123)
    idle = first_episodes(venv, zero_policy(venv), seed=123)
    rand = first_episodes(venv, random_policy(venv, 0), seed=123)
    crashed = pilot["capsized"] | pilot["bow_stuffed"] | pilot["left_course"]
    assert crashed.mean() < 0.05
    assert (pilot["time_to_plane_s"] > 0).all() and pilot["time_to_plane_s"].max() < 6.0
    assert pilot["gates_passed"].mean() > 5.0  # of 6
    assert pilot["success"].mean() > 0.6 > idle["success"].mean() + rand["success"].mean()
    assert pilot["return"].mean() > idle["return"].mean() + 40.0
    assert pilot["return"].mean() > rand["return"].mean() + 40.0
    assert np.isfinite(pilot["return"]).all()


def test_pilot_keeps_an_integrator_per_env_and_resets_it():
    pilot = BoatOnStepPilot()
    obs = np.zeros((3, len(OBS)))
    obs[:, OBS["speed_error"]] = 1.0  # 1 m/s slow: within the PI band
    obs[:, OBS["gate_bearing_cos"]] = 1.0
    obs[:, OBS["gate_heading_cos"]] = 1.0
    for _ in range(10):
        a = pilot(obs)
    assert np.all(a[:, 0] > pilot.gains.cruise_throttle)  # the integral pushes the throttle
    pilot.reset(np.array([True, False, False]))
    b = pilot(obs)
    assert b[0, 0] < b[1, 0]
    assert np.all(np.abs(pilot(obs)) <= 1.0)
