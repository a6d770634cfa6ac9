"""fluidsim-envs: Gymnasium environments for vehicles in fluids, on batched numba physics.

Importing the package registers the environments of :data:`fluidsim_envs.scenes.SCENES`:

- ``fluidsim/PaperAirplane-v0``: glide a paper dart to a target and land on it.
- ``fluidsim/SubmarineWake-v0``: hold a small UUV on station in a submarine's wake.
- ``fluidsim/BoatOnStep-v0``: get a planing speedboat up on step and run a course of gates.
"""

from gymnasium.envs.registration import register

from . import compiling
from .scenes import SCENES

compiling.install()  # a line on stderr while numba compiles (only on a cold cache)

for _scene in SCENES.values():
    register(
        id=_scene.id,
        entry_point=_scene.entry_point,
        vector_entry_point=_scene.vector_entry_point,
    )
del _scene
