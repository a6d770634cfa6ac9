"""Named layouts: a scene declares each of its packed arrays (observation columns, reward-term
and flag rows, task-state rows, the task config vector) once, as a tuple of names, and derives
every index from it with :func:`index`."""

from __future__ import annotations

from collections.abc import Sequence
from types import MappingProxyType


def index(names: Sequence[str]) -> MappingProxyType:
    """A read-only mapping name -> position for the layout ``names`` (distinct strings); a
    misspelled name is a KeyError at import, not a wrong column."""
    names = tuple(names)
    if len(set(names)) != len(names) or not all(isinstance(n, str) for n in names):
        dup = sorted({n for n in names if names.count(n) > 1})
        raise ValueError(f"a layout's names must be distinct strings, got duplicates {dup}")
    return MappingProxyType({name: i for i, name in enumerate(names)})
