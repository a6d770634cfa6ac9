"""What a training run will hold in memory, estimated from its config before anything is
allocated, so that a run too large for the machine is refused with the numbers instead of
being killed by the kernel's out-of-memory killer halfway through building its envs.

The estimate is the sum of:

- the envs: :data:`ENV_BYTES` per sub-env (training and evaluation), an upper bound of what
  one sub-env of each v0 and v1 env holds once built, reset and stepped (bodies, fluid
  samples, task data, episode pools, the SB3 adapter's buffers);
- the algorithm's buffer, from the spaces: PPO's rollout buffer (``n_steps x n_envs``
  observations, actions and six float32 columns), SAC's replay buffer (``buffer_size``
  observations twice, actions and three columns);
- what the process holds before (Python, torch, numba's compiled kernels), which is already
  in use and so not in the machine's available memory.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

#: bytes per sub-env, an upper bound: tracemalloc measured 4.2-9.6 KiB for the six envs
#: (513 sub-envs built, reset and stepped, less one: tests/training/test_memory.py keeps it a
#: bound), and the SB3 adapter and VecMonitor add their per-env arrays
ENV_BYTES = 16 * 1024
FLOAT32 = 4
#: of the available memory a run may plan to take (the rest: torch's working tensors, the
#: evaluations' copies, the page cache the run's files go through)
SHARE = 0.8


@dataclass(frozen=True)
class Estimate:
    envs: int  # bytes
    buffer: int
    buffer_what: str

    @property
    def total(self) -> int:
        return self.envs + self.buffer


def estimate(cfg, obs_dim: int, act_dim: int) -> Estimate:
    """The run's memory for observations of ``obs_dim`` columns as the policy reads them
    (stacked frames, exact columns included) and actions of ``act_dim``."""
    sub_envs = cfg.n_envs + (cfg.eval.n_episodes if cfg.eval.freq > 0 else 0)
    a = cfg.algorithm
    if a.name == "ppo":
        rows = a.n_steps * cfg.n_envs
        buffer = rows * (obs_dim + act_dim + 6) * FLOAT32
        what = f"PPO's rollout buffer of n_steps x n_envs = {rows:,} steps"
    else:
        rows = a.buffer_size
        buffer = rows * (2 * obs_dim + act_dim + 3) * FLOAT32
        what = f"SAC's replay buffer of buffer_size = {rows:,} steps"
    return Estimate(sub_envs * ENV_BYTES, buffer, what)


def available_bytes(
    meminfo: Path = Path("/proc/meminfo"), cgroup: Path = Path("/sys/fs/cgroup")
) -> int | None:
    """The memory new allocations can take: the kernel's ``MemAvailable``, or less where the
    process's cgroup (a container) is limited below it; None where neither says (not
    Linux)."""
    found = []
    try:
        for line in meminfo.read_text().splitlines():
            if line.startswith("MemAvailable:"):
                found.append(int(line.split()[1]) * 1024)
    except (OSError, ValueError, IndexError):
        pass
    try:  # cgroup v2: the limit ("max": none) less what the group uses already
        limit = (cgroup / "memory.max").read_text().strip()
        if limit != "max":
            found.append(int(limit) - int((cgroup / "memory.current").read_text()))
    except (OSError, ValueError):
        pass
    return min(found) if found else None


def problem(cfg, obs_dim: int, act_dim: int, available: int | None) -> str | None:
    """Why the run will not fit in ``available`` bytes (with the numbers and the keys that
    set them), or None."""
    if available is None:
        return None
    need = estimate(cfg, obs_dim, act_dim)
    if need.total <= SHARE * available:
        return None
    envs = cfg.n_envs + (cfg.eval.n_episodes if cfg.eval.freq > 0 else 0)
    return (
        f"the run needs about {_gib(need.total)} of memory ({_gib(need.envs)} for {envs:,} "
        f"sub-envs: n_envs={cfg.n_envs:,} and eval.n_episodes; {_gib(need.buffer)} for "
        f"{need.buffer_what}), and this machine has {_gib(available)} available: lower "
        f"n_envs (or algorithm.{'n_steps' if cfg.algorithm.name == 'ppo' else 'buffer_size'})"
    )


def _gib(n: float) -> str:
    return f"{n / 2**30:,.1f} GiB"


__all__ = ["ENV_BYTES", "Estimate", "available_bytes", "estimate", "problem"]
