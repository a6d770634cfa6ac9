"""fluidsim-envs."""
