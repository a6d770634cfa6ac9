"""Moving water for an underwater scene: an ocean current, steady over the episode (a speed
and a horizontal direction drawn at its start) plus a slow variation of each horizontal
component, a first-order Gauss-Markov process (standard deviation ``variation_mps``,
correlation time ``time_s``: the tidal and inertial wander of a coastal current, minutes
long), stepped exactly each action: ``x <- a x + sigma sqrt(1 - a^2) n``,
``a = exp(-h / time_s)``; an episode starts in the stationary law. Its normals come from
:mod:`.noise` (the sub-env's key, its step, the pair of lane 4000)."""

from __future__ import annotations

import math

from numba import njit

from . import noise as NZ

_LANE = 4000


@njit(cache=True, error_model="numpy")
def current(ids, start, keys, counter, mean, state, variation_mps, time_s, step, flow):
    """Write the water velocity of sub-envs ``ids`` over their next step into
    ``flow[3:6]``: the episode's ``mean`` [E, 3] plus the wander ``state`` [E, 2] (begun in
    its stationary law at ``start``, else advanced one step of ``step`` s; ``counter`` [E]
    the steps taken, the noise counter that plus one)."""
    a = math.exp(-step / time_s)
    drive = variation_mps * math.sqrt(max(1.0 - a * a, 0.0))
    for i in range(ids.size):
        e = ids[i]
        t = 0 if start else counter[e] + 1
        n = NZ.normal_pair(keys[e], t, _LANE)
        for c in range(2):
            if start:
                state[e, c] = variation_mps * n[c]
            else:
                state[e, c] = a * state[e, c] + drive * n[c]
        flow[3, e] = mean[e, 0] + state[e, 0]
        flow[4, e] = mean[e, 1] + state[e, 1]
        flow[5, e] = mean[e, 2]
