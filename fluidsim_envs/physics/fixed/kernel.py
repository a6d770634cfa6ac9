"""The batch kernel: every environment's bodies, ``steps`` integer steps in one compiled call.

Each environment is stepped by ``laws.body_step`` on its own state words only, so the result
does not depend on the batch size, on how environments are spread over threads, or on the
machine (integer arithmetic: ``laws.py``). ``step_parallel`` spreads environments over
numba's threads (``prange``); ``step_serial`` runs on the calling thread.
"""

from __future__ import annotations

from numba import njit, prange

from .laws import body_step


@njit(cache=True)
def step_serial(st, bc, tab, inp, prm, steps, count, diverged):
    """Advance every environment ``steps`` steps: ``st[E, B, 13]`` (int64 words) in place;
    ``bc[B, NBC]``, ``tab[B, n]`` the bodies' constants and samples, ``inp[E, B, m]`` each
    environment's inputs (deflected control-surface normals, thruster controls),
    ``prm[NPRM]``; ``count[E]`` counts the steps (the clock), ``diverged[E]`` is set where a
    body was flagged during the call."""
    for e in range(st.shape[0]):
        flag = 0
        for _ in range(steps):
            for b in range(st.shape[1]):
                flag |= body_step(st[e, b], bc[b], tab[b], inp[e, b], prm)
        count[e] += steps
        diverged[e] = flag != 0


@njit(cache=True, parallel=True)
def step_parallel(st, bc, tab, inp, prm, steps, count, diverged):
    """:func:`step_serial` with environments spread over numba's threads."""
    for e in prange(st.shape[0]):
        flag = 0
        for _ in range(steps):
            for b in range(st.shape[1]):
                flag |= body_step(st[e, b], bc[b], tab[b], inp[e, b], prm)
        count[e] += steps
        diverged[e] = flag != 0
