"""SubmarineWake-v0: hold a small UUV on station in a cruising submarine's wake.

- ``env.py``: the env (parameters, episode start, step, the public state viewers read);
- ``kernel.py``: the observation, reward-term, flag, lead-state and config layouts and the
  task kernels;
- ``view.py``: the rgb_array frames (and the tracers' bookkeeping); ``rerun.py``: the Rerun
  hooks;
- ``pilot.py``: the scripted baseline pilot and the demo.
"""

import dataclasses

from ..keys import Axis
from ..planner import PlannerConfig
from ..scene import Scene
from .env import SubmarineWakeEnv, SubmarineWakeParams, SubmarineWakeVectorEnv
from .kernel import OBS, OBS_NAMES, OBSERVATION
from .mesh import meshes
from .pilot import StationGains, SubmarineWakePilot, demo, make_hand_pilot, make_pilot
from .rerun import SubmarineWakeRerun
from .v1 import OBSERVATION_V1, SubmarineWakeV1Env, SubmarineWakeV1Params, SubmarineWakeV1VectorEnv
from .view import SubmarineWakeView

SCENE = Scene(
    id="fluidsim/SubmarineWake-v0",
    summary="hold a small UUV on station in a submarine's wake",
    success="{success_fraction:.0%} of the steps within {success_radius_m:g} m of the station "
    "point, no crash",
    env_cls=SubmarineWakeEnv,
    vector_cls=SubmarineWakeVectorEnv,
    params_cls=SubmarineWakeParams,
    observation=OBSERVATION,
    pilot=make_pilot,
    hand_pilot=make_hand_pilot,
    planner_config=PlannerConfig(samples=16, horizon=20, hold=3, noise_std=0.3, guided=True),
    view=SubmarineWakeView,
    rerun=SubmarineWakeRerun,
    demo=demo,
    short_episodes={"max_episode_steps": 40, "lost_distance_m": 5.0},
    meshes=meshes,
    # the thrust on W/S stays where left; the rudder on the arrows, the planes pulled back
    # (Down) for nose up
    keys=(
        Axis("thrust", "s", "w", spring=False),
        Axis("rudder", "left", "right"),
        Axis("dive_planes", "up", "down"),
    ),
)

# v1: the same task with a randomized craft, sensors and actuators (v1.py)
SCENE_V1 = dataclasses.replace(
    SCENE,
    id="fluidsim/SubmarineWake-v1",
    env_cls=SubmarineWakeV1Env,
    vector_cls=SubmarineWakeV1VectorEnv,
    params_cls=SubmarineWakeV1Params,
    observation=OBSERVATION_V1,
)

__all__ = [
    "OBS",
    "OBSERVATION",
    "OBS_NAMES",
    "SCENE",
    "SCENE_V1",
    "StationGains",
    "SubmarineWakeEnv",
    "SubmarineWakeParams",
    "SubmarineWakePilot",
    "SubmarineWakeVectorEnv",
]
