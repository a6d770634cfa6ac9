"""One owner of a process's threads: numba's (the env kernels, the planner's rollouts) and
torch's (the policy's forward passes and updates), chosen together from the cores this process
may run on (``os.sched_getaffinity``), so that the two pools never spin against each other.

Why an owner: both are OpenMP teams here (numba's ``omp`` threading layer, torch's own
libgomp), and a team's thread that waits at a barrier spins. A torch team of a thread per
core (torch's default) beside numba's started pool takes the cycles the working threads need,
even on a quiet machine; beside any other work, torch's team alone does. PPO on
PaperAirplane-v1 then trained at a fraction of its speed (``python -m
benchmarks.bench_training``, docs/training.md#wall-clock). A second torch thread buys some
speed on a machine doing nothing else and costs several times that beside other work, so
torch gets one thread and numba every core, unless asked otherwise (``torch_threads``,
``numba_threads`` in a training config; ``fluidsim-sweep --torch-threads``).

    >>> from fluidsim_envs.threads import choose
    >>> plan = choose(torch=1, numba=1, cores=2, load=0.1)
    >>> plan.describe()
    'threads: numba 1, torch 1, on 2 cores'
    >>> choose(torch=3, cores=2)
    Traceback (most recent call last):
    ...
    fluidsim_envs.threads.ThreadError: torch_threads 3: more than the 2 cores this process may use
"""

from __future__ import annotations

import contextlib
import functools
import os
import sys
from collections.abc import Iterator
from dataclasses import dataclass

#: torch's intra-op threads unless asked: one (see the module's docstring)
TORCH_DEFAULT = 1
#: the 1-minute load average, per core this process may use, above which the machine is
#: called busy at a run's start (other work then holds at least a quarter of its cores)
BUSY_LOAD_PER_CORE = 0.25


class ThreadError(ValueError):
    """A thread count that cannot be honored: not an integer, below 1, or more than the cores
    this process may use."""


def available_cores() -> int:
    """The cores this process may run on: its CPU affinity where the OS tells it (a
    container's or ``taskset``'s limit), else the machine's count."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # not Linux
        return os.cpu_count() or 1


def load_average() -> float:
    """The 1-minute load average (0 where the OS has none)."""
    try:
        return os.getloadavg()[0]
    except (AttributeError, OSError):
        return 0.0


@dataclass(frozen=True)
class Threads:
    """What a process runs on: ``numba`` threads for the env kernels, ``torch`` intra-op
    threads (and one inter-op thread) for the policy, out of ``cores``; ``load`` is the
    1-minute load average when they were chosen (other work: before this process ran)."""

    cores: int
    numba: int
    torch: int
    load: float = 0.0

    @property
    def busy(self) -> bool:
        """Whether other work already held a share of the cores when these were chosen."""
        return self.load > BUSY_LOAD_PER_CORE * self.cores

    def describe(self) -> str:
        """One line for a plan: the counts, and the load when the machine was busy."""
        line = f"threads: numba {self.numba}, torch {self.torch}, on {self.cores} cores"
        if self.torch > 1:
            line += (
                " (warning: a torch team of several threads and numba's pool spin against "
                "each other once both run: docs/training.md#wall-clock)"
            )
        elif self.busy:
            line += (
                f" (the machine is busy: load average {self.load:.1f} at start; torch kept "
                f"to {self.torch} thread{'s' * (self.torch > 1)} so that its pool and numba's "
                "do not spin against the other work)"
            )
        return line

    def as_dict(self) -> dict:
        """The plain record a run folder keeps."""
        return {"cores": self.cores, "numba": self.numba, "torch": self.torch,
                "load_start": round(self.load, 2)}  # fmt: skip


def _count(name: str, value, cores: int) -> int:
    """``value`` checked as a thread count for ``name``: an integer from 1 to ``cores``."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise ThreadError(f"{name} must be an integer, got {value!r}")
    if value < 1:
        raise ThreadError(f"{name} {value}: at least 1")
    if value > cores:
        raise ThreadError(f"{name} {value}: more than the {cores} cores this process may use")
    return value


def numba_pool_size() -> int:
    """The threads numba's pool was started with (``NUMBA_NUM_THREADS``): the most
    ``numba.set_num_threads`` accepts."""
    import numba

    return int(numba.config.NUMBA_NUM_THREADS)


def choose(
    torch: int | None = None,
    numba: int | None = None,
    *,
    cores: int | None = None,
    load: float | None = None,
) -> Threads:
    """The threads for this process: ``torch`` (default :data:`TORCH_DEFAULT`) and ``numba``
    (default every core, as far as numba's pool goes) out of ``cores`` (default
    :func:`available_cores`). A count that is not an integer from 1 to ``cores`` is a
    :class:`ThreadError` naming it."""
    cores = available_cores() if cores is None else _count("cores", cores, 1 << 16)
    load = load_average() if load is None else float(load)
    torch = _count("torch_threads", TORCH_DEFAULT if torch is None else torch, cores)
    if numba is None:
        numba = min(cores, numba_pool_size())
    else:
        numba = _count("numba_threads", numba, cores)
        if numba > numba_pool_size():
            raise ThreadError(
                f"numba_threads {numba}: more than the {numba_pool_size()} threads numba's "
                "pool was started with (NUMBA_NUM_THREADS)"
            )
    return Threads(cores=cores, numba=numba, torch=torch, load=load)


def numba_pool_started() -> bool:
    """Whether numba's thread pool runs: a parallel kernel, or a call that reads or sets its
    count, starts it (unknown to this numba: taken as started)."""
    from numba.np.ufunc import parallel

    return bool(getattr(parallel, "_is_initialized", True))


def current() -> Threads:
    """The counts in force now (torch's only where torch is imported; else 0), without
    starting numba's pool (not started: the count it will start with)."""
    import numba

    torch = sys.modules.get("torch")
    return Threads(
        cores=available_cores(),
        numba=numba.get_num_threads() if numba_pool_started() else numba_pool_size(),
        torch=torch.get_num_threads() if torch is not None else 0,
        load=load_average(),
    )


def apply(threads: Threads) -> None:
    """Set numba's threads and, where torch is installed, torch's intra-op threads and (once a
    process allows it: before its first inter-op work) its inter-op threads to one. torch is
    imported here when it is not yet: its pool must be sized before the policy first runs."""
    import numba

    # a pool not yet started starts with every thread: started only if fewer are asked for (a
    # started pool beside a torch team of two spins even on a quiet machine)
    if numba_pool_started() or threads.numba != numba_pool_size():
        numba.set_num_threads(threads.numba)
    if threads.torch < 1:  # current() before torch was imported: nothing of torch's to set
        return
    try:
        import torch
    except ImportError:  # the envs alone: no policy to run
        return
    torch.set_num_threads(threads.torch)
    with contextlib.suppress(RuntimeError):  # already set, or inter-op work already ran
        if torch.get_num_interop_threads() != 1:
            torch.set_num_interop_threads(1)


@contextlib.contextmanager
def owned(threads: Threads) -> Iterator[Threads]:
    """``threads`` in force for the block, the counts before it again afterwards (they are
    process-wide: a later evaluation in the same process computes as it would have)."""
    before = current()
    apply(threads)
    try:
        yield threads
    finally:
        apply(before)


def on_owned_threads(fn):
    """``fn`` run on :func:`choose`'s threads (and the caller's again afterwards): a policy's
    float sums depend on torch's thread count, so an evaluation gives the same numbers from
    the command line and from a caller whose torch runs on other threads."""

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        with owned(choose()):
            return fn(*args, **kwargs)

    return wrapper


__all__ = [
    "ThreadError", "Threads", "apply", "available_cores", "choose", "current", "on_owned_threads",
    "owned",
]  # fmt: skip
