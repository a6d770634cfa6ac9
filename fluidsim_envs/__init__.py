"""fluidsim-envs: Gymnasium environments for vehicles in fluids, on batched numba physics.

Importing the package registers the environments of :data:`fluidsim_envs.scenes.SCENES`:

- ``fluidsim/PaperAirplane-v0``: glide a paper dart to a target and land on it.
- ``fluidsim/SubmarineWake-v0``: hold a small UUV on station in a submarine's wake.
- ``fluidsim/BoatOnStep-v0``: get a planing speedboat up on step and run a course of gates.

and their ``-v1``: the same tasks with a craft drawn anew each episode, real instruments and
actuators, moving air and water at a ``difficulty`` level, and what the craft's fluid samples
meet in the observation (``scenes/realism.py``, ``scenes/probes.py``).
"""

from gymnasium.envs.registration import register

from . import compiling
from .scenes import SCENES

compiling.install()  # a line on stderr while numba compiles (only on a cold cache)

# No ``reward_threshold``: an episode is solved by its success flag (``info["success"]``,
# ``Scene.success``: landed on the target, the course run, the station held), which no return
# states (a return mixes progress, comfort and effort terms whose weights are parameters).
# ``max_episode_steps``: the scene's default, what ``spec.max_episode_steps`` says; the env
# takes gym.make's own (FluidEnv.spec), and make_vec hands it to the vector env.
for _scene in SCENES.values():
    register(
        id=_scene.id,
        entry_point=_scene.entry_point,
        vector_entry_point=_scene.vector_entry_point,
        max_episode_steps=_scene.params_cls().max_episode_steps,
    )
del _scene
