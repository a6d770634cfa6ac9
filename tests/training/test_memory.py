"""A run too large for the machine is refused before it allocates, with the numbers: the
per-sub-env bound the estimate uses holds for every env, and the estimate names the keys."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from fluidsim_envs.rl import memory
from fluidsim_envs.rl.config import load_config
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.wrappers.sb3 import make_sb3_vec_env


@pytest.mark.parametrize("env_id", sorted(SCENES))
def test_a_sub_env_holds_less_than_the_bound(env_id):
    """What one more sub-env holds once built, reset and stepped through the SB3 adapter
    (tracemalloc sees NumPy's arrays and Python's objects alike)."""
    make_sb3_vec_env(env_id, 2).reset()  # its kernels compiled outside the measurement
    held = []
    for n in (1, 129):
        tracemalloc.start()
        venv = make_sb3_vec_env(env_id, n)
        venv.reset()
        venv.step(np.zeros((n, *venv.action_space.shape), dtype=np.float32))
        held.append(tracemalloc.get_traced_memory()[0])
        tracemalloc.stop()
        venv.close()
    per_env = (held[1] - held[0]) / 128
    assert 0 < per_env < memory.ENV_BYTES, per_env


def test_a_run_too_large_is_named(tmp_path):
    cfg = load_config("paper_airplane_v1_ppo")
    meminfo = tmp_path / "meminfo"
    meminfo.write_text("MemTotal:       24000000 kB\nMemAvailable:   20000000 kB\n")
    available = memory.available_bytes(meminfo, tmp_path / "no-cgroup")
    assert available == 20000000 * 1024
    (tmp_path / "memory.max").write_text("8589934592\n")  # a container's 8 GiB, 1 GiB in use
    (tmp_path / "memory.current").write_text("1073741824\n")
    assert memory.available_bytes(meminfo, tmp_path) == 7 * 2**30
    assert memory.problem(cfg, 40, 3, available) is None  # the shipped config fits
    import dataclasses

    big = dataclasses.replace(cfg, n_envs=100_000_000)
    why = memory.problem(big, 40, 3, available)
    assert "n_envs=100,000,000" in why and "rollout buffer" in why and "19.1 GiB available" in why
    assert memory.problem(big, 40, 3, None) is None  # where the kernel does not say: no check
    assert memory.available_bytes(tmp_path / "none", tmp_path / "none") is None
