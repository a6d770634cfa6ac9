"""The bad-input table's row: one input a user might give, the exception it must raise and
the words its message must hold (the argument's name, the bad value, what is allowed).

Each ``test_*.py`` here defines ``ROWS`` (a list of :class:`Row`) and runs them with
:func:`check`; ``tests/bad_inputs/test_count.py`` keeps the whole table at least as long as
the issue that started it asked (197 rows).
"""

from __future__ import annotations

import re
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import pytest


@dataclass(frozen=True)
class Row:
    """``call()`` must raise ``error`` (or a subclass) with every one of ``words`` in its
    message (case-insensitive substrings)."""

    id: str
    call: Callable[[], object]
    error: type[BaseException]
    words: Sequence[str]


def params(rows: Sequence[Row]):
    """``rows`` as pytest parameters, each named by its id (ids must be distinct)."""
    ids = [r.id for r in rows]
    dup = sorted({i for i in ids if ids.count(i) > 1})
    assert not dup, f"duplicate row ids {dup}"
    return [pytest.param(r, id=r.id) for r in rows]


def check(row: Row) -> None:
    """Run one row: the error type, every word, and no garbled message (a message is one
    readable sentence, not a bare repr, a numpy internals message or an empty string)."""
    with pytest.raises(BaseException) as caught:
        row.call()
    exc = caught.value
    if not isinstance(exc, row.error):
        tb = "".join(traceback.format_exception(exc))
        raise AssertionError(f"{row.id}: expected {row.error.__name__}, got:\n{tb}")
    message = str(exc)
    if isinstance(exc, KeyError) and exc.args:  # KeyError's str() is the repr of its key
        message = str(exc.args[0])
    assert len(message) >= 15, f"{row.id}: message too short to name anything: {message!r}"
    missing = [w for w in row.words if w.lower() not in message.lower()]
    assert not missing, f"{row.id}: message lacks {missing}: {message!r}"
    assert not re.search(r"object is not (iterable|subscriptable)", message), message
