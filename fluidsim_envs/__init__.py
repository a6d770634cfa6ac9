"""fluidsim-envs: Gymnasium environments for vehicles in fluids, on batched numba physics.

Importing the package registers the environments:

- ``fluidsim/PaperAirplane-v0``: glide a paper dart to a target and land on it.
- ``fluidsim/SubmarineWake-v0``: hold a small UUV on station in a submarine's wake.
- ``fluidsim/BoatOnStep-v0``: get a planing speedboat up on step and run a course of gates.
"""

from gymnasium.envs.registration import register

register(
    id="fluidsim/PaperAirplane-v0",
    entry_point="fluidsim_envs.envs.paper_airplane:PaperAirplaneEnv",
    vector_entry_point="fluidsim_envs.envs.paper_airplane:PaperAirplaneVectorEnv",
)

register(
    id="fluidsim/SubmarineWake-v0",
    entry_point="fluidsim_envs.envs.submarine_wake:SubmarineWakeEnv",
    vector_entry_point="fluidsim_envs.envs.submarine_wake:SubmarineWakeVectorEnv",
)

register(
    id="fluidsim/BoatOnStep-v0",
    entry_point="fluidsim_envs.envs.boat_on_step:BoatOnStepEnv",
    vector_entry_point="fluidsim_envs.envs.boat_on_step:BoatOnStepVectorEnv",
)
