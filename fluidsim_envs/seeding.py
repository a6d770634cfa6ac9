"""Seed streams: one numeric seed gives each purpose episodes of its own.

``reset(seed=s)`` draws sub-env i's episodes from ``SeedSequence(s).spawn(E)[i]``: the
evaluation stream, Gymnasium's meaning of a seed, and what ``fluidsim-evaluate --seed s``
flies. A training run seeded s and the pilots' tuning pass ``options={"stream": name}``
with their seed, and draw from ``SeedSequence(s, spawn_key=(K,))`` instead, K the stream's
key. (The zoo's fresh episodes and GIFs are an evaluation's, at a seed of their own: seed 3.)
NumPy hashes a SeedSequence's seed, padded to four 32-bit words, followed by its spawn key's
words; an evaluation sub-env's key is ``(i,)`` (one word), another stream's ``(K, i)`` with K
above 2**32 (three words), so, seeds being below 2**128 (``checks.seed``), no sub-env of one
stream has the inputs of any sub-env of another, at any seed: a run seeded 0 never trains on
the episodes the evaluation seeded 0 grades (tests/scenes/test_seeding.py).
"""

from __future__ import annotations

import numpy as np

#: the purposes a seed can serve; "evaluation" is ``reset(seed=s)`` without a stream
STREAMS = ("evaluation", "training", "tuning")


def _key(name: str) -> int:
    # the name's bytes as a number: readable in a run's record, and above 2**32 for every
    # stream, so that it is never an evaluation sub-env's index
    return int.from_bytes(name.encode(), "big")


KEYS = {name: _key(name) for name in STREAMS[1:]}


def check_stream(where: str, stream) -> str:
    """``stream`` if it names one of :data:`STREAMS`, else a ValueError naming it."""
    if not isinstance(stream, str) or stream not in STREAMS:
        raise ValueError(f"{where}: unknown seed stream {stream!r}; streams are {list(STREAMS)}")
    return stream


def root(seed: int, stream: str = "evaluation") -> np.random.SeedSequence:
    """The SeedSequence whose children are a batch's sub-envs: ``spawn(E)[i]`` is sub-env i's
    (and ``spawn(1)[0]`` the single env's)."""
    if stream == "evaluation":
        return np.random.SeedSequence(seed)
    return np.random.SeedSequence(seed, spawn_key=(KEYS[check_stream("root", stream)],))


def describe(seed: int, n: int, stream: str = "evaluation") -> str:
    """How sub-env i of a batch of ``n`` seeded ``seed`` in ``stream`` draws (a run's record)."""
    if stream == "evaluation":
        return f"SeedSequence({seed}).spawn({n})[i] for env i"
    return f"SeedSequence({seed}, spawn_key=({KEYS[stream]},)).spawn({n})[i] for env i ({stream})"
