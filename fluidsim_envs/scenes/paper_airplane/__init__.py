"""PaperAirplane-v0: glide a paper dart to a target on the ground and land on it.

- ``env.py``: the env (parameters, episode start, step, the public state viewers read);
- ``kernel.py``: the observation, reward-term, flag and config layouts and the task kernels;
- ``view.py``: the rgb_array frames; ``rerun.py``: the Rerun hooks;
- ``pilot.py``: the scripted baseline pilot and the demo.
"""

import dataclasses

import numpy as np

from ..keys import Axis
from ..planner import PlannerConfig
from ..scene import Scene
from .env import PaperAirplaneEnv, PaperAirplaneParams, PaperAirplaneVectorEnv
from .kernel import OBS, OBS_NAMES, OBSERVATION
from .mesh import meshes
from .pilot import PaperAirplanePilot, PilotGains, demo, make_hand_pilot, make_pilot
from .rerun import PaperAirplaneRerun
from .v1 import OBSERVATION_V1, PaperAirplaneV1Env, PaperAirplaneV1Params, PaperAirplaneV1VectorEnv
from .view import PaperAirplaneView


def _blow_up(venv, env_index: int) -> None:
    """Sub-env ``env_index``'s state goes infinite (a stand-in for a real blow-up)."""
    st, _, _ = venv.sim.kernel_arrays()
    st[:, :, env_index] = np.inf


SCENE = Scene(
    id="fluidsim/PaperAirplane-v0",
    summary="glide a paper dart to a target on the ground and land on it",
    success="landed (sink under {crash_sink_mps:g} m/s, upright) within {success_radius_m:g} m "
    "of the target",
    env_cls=PaperAirplaneEnv,
    vector_cls=PaperAirplaneVectorEnv,
    params_cls=PaperAirplaneParams,
    observation=OBSERVATION,
    pilot=make_pilot,
    hand_pilot=make_hand_pilot,
    planner_config=PlannerConfig(samples=64, horizon=45, hold=1, noise_std=0.3, guided=True),
    view=PaperAirplaneView,
    rerun=PaperAirplaneRerun,
    demo=demo,
    short_episodes={"launch_height_m": (1.5, 2.5), "max_episode_steps": 40},
    diverge=_blow_up,
    meshes=meshes,
    # a flight sim's stick: the arrows, pulled back (Down) for nose up; the rudder on A/D
    keys=(
        Axis("aileron", "left", "right"),
        Axis("elevator", "up", "down"),
        Axis("rudder", "a", "d"),
    ),
)

# v1: the same task with a randomized craft, sensors and actuators (v1.py)
SCENE_V1 = dataclasses.replace(
    SCENE,
    id="fluidsim/PaperAirplane-v1",
    env_cls=PaperAirplaneV1Env,
    vector_cls=PaperAirplaneV1VectorEnv,
    params_cls=PaperAirplaneV1Params,
    observation=OBSERVATION_V1,
)

__all__ = [
    "OBS",
    "OBSERVATION",
    "OBS_NAMES",
    "SCENE",
    "SCENE_V1",
    "PaperAirplaneEnv",
    "PaperAirplaneParams",
    "PaperAirplanePilot",
    "PaperAirplaneVectorEnv",
    "PilotGains",
]
