"""fluidsim-envs: Gymnasium environments for vehicles in fluids, on batched numba physics.

Importing the package registers the environments:

- ``fluidsim/PaperAirplane-v0``: glide a paper dart to a target and land on it.
"""

from gymnasium.envs.registration import register

register(
    id="fluidsim/PaperAirplane-v0",
    entry_point="fluidsim_envs.envs.paper_airplane:PaperAirplaneEnv",
    vector_entry_point="fluidsim_envs.envs.paper_airplane:PaperAirplaneVectorEnv",
)
