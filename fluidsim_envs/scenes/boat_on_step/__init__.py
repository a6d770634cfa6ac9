"""BoatOnStep-v0: get a planing speedboat up on step and run a course of gates.

- ``env.py``: the env (parameters, episode start, step, the public state viewers read);
- ``kernel.py``: the observation, reward-term, flag, task-state, course and config layouts
  and the task kernels;
- ``view.py``: the rgb_array frames; ``rerun.py``: the Rerun hooks;
- ``pilot.py``: the scripted baseline pilot and the demo.
"""

import dataclasses

from ..keys import Axis
from ..planner import PlannerConfig
from ..scene import Scene
from .env import GATES, BoatOnStepEnv, BoatOnStepParams, BoatOnStepVectorEnv
from .kernel import OBS, OBS_NAMES, OBSERVATION
from .mesh import meshes
from .pilot import BoatOnStepPilot, HelmGains, demo, make_hand_pilot, make_pilot
from .rerun import BoatOnStepRerun
from .v1 import OBSERVATION_V1, BoatOnStepV1Env, BoatOnStepV1Params, BoatOnStepV1VectorEnv
from .view import BoatOnStepView

SCENE = Scene(
    id="fluidsim/BoatOnStep-v0",
    summary="get a planing speedboat up on step and run a course of gates",
    success="every gate of the course passed (none missed), no crash",
    env_cls=BoatOnStepEnv,
    vector_cls=BoatOnStepVectorEnv,
    params_cls=BoatOnStepParams,
    observation=OBSERVATION,
    pilot=make_pilot,
    hand_pilot=make_hand_pilot,
    planner_config=PlannerConfig(samples=16, horizon=20, hold=10, noise_std=0.3, guided=True),
    view=BoatOnStepView,
    rerun=BoatOnStepRerun,
    demo=demo,
    short_episodes={"max_episode_steps": 40},
    meshes=meshes,
    # the throttle on W/S and the trim tabs on Up/Down stay where left; the wheel on the arrows
    keys=(
        Axis("throttle", "s", "w", spring=False),
        Axis("rudder", "left", "right"),
        Axis("trim_tabs", "up", "down", spring=False),
    ),
)

# v1: the same task with a randomized craft, sensors and actuators (v1.py)
SCENE_V1 = dataclasses.replace(
    SCENE,
    id="fluidsim/BoatOnStep-v1",
    env_cls=BoatOnStepV1Env,
    vector_cls=BoatOnStepV1VectorEnv,
    params_cls=BoatOnStepV1Params,
    observation=OBSERVATION_V1,
)

__all__ = [
    "GATES",
    "OBS",
    "OBSERVATION",
    "OBS_NAMES",
    "SCENE",
    "SCENE_V1",
    "BoatOnStepEnv",
    "BoatOnStepParams",
    "BoatOnStepPilot",
    "BoatOnStepVectorEnv",
    "HelmGains",
]
