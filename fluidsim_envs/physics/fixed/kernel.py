"""The batch kernel: every environment's bodies, ``steps`` integer steps in one compiled call.

Each environment is stepped by ``laws.body_step`` on its own state words only, so the result
does not depend on the batch size, on how environments are spread over threads, or on the
machine (integer arithmetic: ``laws.py``). ``step_parallel`` spreads environments over
numba's threads (``prange``); ``step_serial`` runs on the calling thread.

numba's cache does not see edits to ``laws.py`` (a module these kernels call into): after
editing it, delete ``fluidsim_envs/physics/fixed/__pycache__/*.nbi`` and ``*.nbc``, or the
kernels keep running the old laws (tests/physics/test_fixed.py's comparison with the
plain-Python reference, which runs the new ones, then fails).
"""

from __future__ import annotations

from numba import njit, prange

from .laws import body_inputs, body_step


@njit(cache=True, inline="always")
def _advance(e, st, bc, tab, mix, ctrl, inp, prm, steps, count, diverged):
    """Environment e's inputs from its controls, then its ``steps`` steps (its own words
    only); the two kernels' one body."""
    for b in range(st.shape[1]):
        body_inputs(ctrl[e], tab[b], mix[b], prm, inp[e, b])
    flag = 0
    for _ in range(steps):
        for b in range(st.shape[1]):
            flag |= body_step(st[e, b], bc[b], tab[b], inp[e, b], prm)
    count[e] += steps
    diverged[e] = flag != 0


@njit(cache=True)
def step_serial(st, bc, tab, mix, ctrl, inp, prm, steps, count, diverged):
    """Advance every environment ``steps`` steps: ``st[E, B, 13]`` (int64 words) in place;
    ``bc[B, NBC]``, ``tab[B, n]``, ``mix[B, m]`` the bodies' constants, samples and control
    wiring; ``ctrl[E, C]`` the controls (``laws.ANGLE_BITS``), from which each environment's
    inputs ``inp[E, B, k]`` (deflected control-surface normals, thruster controls) are made
    first (``laws.body_inputs``); ``prm[NPRM]``; ``count[E]`` counts the steps (the clock),
    ``diverged[E]`` is set where a body was flagged during the call."""
    for e in range(st.shape[0]):
        _advance(e, st, bc, tab, mix, ctrl, inp, prm, steps, count, diverged)


@njit(cache=True, parallel=True)
def step_parallel(st, bc, tab, mix, ctrl, inp, prm, steps, count, diverged):
    """:func:`step_serial` with environments spread over numba's threads."""
    for e in prange(st.shape[0]):
        _advance(e, st, bc, tab, mix, ctrl, inp, prm, steps, count, diverged)
