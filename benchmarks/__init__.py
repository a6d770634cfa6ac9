"""Speed, accuracy and stability studies of fluidsim-envs: ``python -m benchmarks.<name>``."""
