"""The one validation kit: every input check of the package, each error naming where, the key
and the bad value (``"World: air_density_kgm3 must be > 0, got -1.0"``).

Each function returns the value as the caller stores it (a float, an int, a tuple, an array)
and raises ``error`` (ValueError unless the caller has its own subclass, such as
``CraftError`` or ``ConfigError``). Bounds are inclusive unless named ``gt`` / ``lt``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

_REAL = (int, float, np.integer, np.floating)


def _bounds(ge=None, gt=None, le=None, lt=None) -> str:
    """`` > 0``, `` in [1, 1000]``, ...: the bounds as a message says them."""
    low = f"[{ge:g}" if gt is None and ge is not None else f"({gt:g}" if gt is not None else None
    high = f"{le:g}]" if lt is None and le is not None else f"{lt:g})" if lt is not None else None
    if low and high:
        return f" in {low}, {high}"
    if low:
        return f" >= {ge:g}" if gt is None else f" > {gt:g}"
    if high:
        return f" <= {le:g}" if lt is None else f" < {lt:g}"
    return ""


def number(
    where: str,
    key: str,
    value: Any,
    *,
    ge=None,
    gt=None,
    le=None,
    lt=None,
    integer: bool = False,
    finite: bool = True,
    error: type[Exception] = ValueError,
):
    """A real number (not a bool; an int if ``integer``: 4.0 for a count would fail later,
    where the error could not name the key), finite unless ``finite=False`` (then inf is
    allowed, NaN never), within the bounds given. Returns a float (an int if ``integer``)."""
    kinds = (int, np.integer) if integer else _REAL
    ok = isinstance(value, kinds) and not isinstance(value, bool)
    ok = ok and not math.isnan(value) and (math.isfinite(value) or not finite)
    ok = ok and (ge is None or value >= ge) and (gt is None or value > gt)
    ok = ok and (le is None or value <= le) and (lt is None or value < lt)
    if not ok:
        kind = "an integer" if integer else "a finite number" if finite else "a number"
        raise error(f"{where}: {key} must be {kind}{_bounds(ge, gt, le, lt)}, got {value!r}")
    return int(value) if integer else float(value)


def vector(
    where: str, key: str, value: Any, n: int = 3, error: type[Exception] = ValueError
) -> tuple[float, ...]:
    """``n`` finite numbers, as a tuple of floats."""
    if not isinstance(value, (list, tuple, np.ndarray)) or len(value) != n:
        raise error(f"{where}: {key} must be a list of {n} numbers, got {value!r}")
    return tuple(number(where, f"{key}[{i}]", v, error=error) for i, v in enumerate(value))


def direction(where: str, key: str, value: Any, error: type[Exception] = ValueError):
    """A non-zero 3-vector, normalized."""
    v = vector(where, key, value, 3, error)
    norm = math.sqrt(sum(c * c for c in v))
    if norm < 1e-9:
        raise error(f"{where}: {key} must be a non-zero direction, got {value!r}")
    return (v[0] / norm, v[1] / norm, v[2] / norm)


def flag(where: str, key: str, value: Any, error: type[Exception] = ValueError) -> bool:
    """True or False, nothing that merely converts to one."""
    if not isinstance(value, (bool, np.bool_)):
        raise error(f"{where}: {key} must be True or False, got {value!r}")
    return bool(value)


def choice(where: str, key: str, value: Any, choices: Sequence, error=ValueError):
    """One of ``choices``."""
    if value not in choices:
        raise error(f"{where}: {key} must be one of {list(choices)}, got {value!r}")
    return value


def value_range(where: str, key: str, value: Any, ge=None, le=None, error=ValueError):
    """A (low, high) pair with ge <= low <= high <= le."""
    if not isinstance(value, (tuple, list)) or len(value) != 2:
        raise error(f"{where}: {key} must be a (low, high) pair, got {value!r}")
    low, high = (number(where, key, v, ge=ge, le=le, error=error) for v in value)
    if low > high:
        raise error(f"{where}: {key} must have low <= high, got {value!r}")
    return low, high


def keys(
    where: str,
    data: Any,
    valid: Iterable[str],
    required: Iterable[str] = (),
    error: type[Exception] = ValueError,
) -> None:
    """A mapping whose keys are all ``valid`` and include every ``required`` one."""
    if not isinstance(data, dict):
        raise error(f"{where}: expected a table, got {data!r}")
    valid = list(valid)
    unknown = sorted(set(data) - set(valid))
    if unknown:
        raise error(f"{where}: unknown key(s) {unknown}; valid keys are {valid}")
    missing = [k for k in required if k not in data]
    if missing:
        raise error(f"{where}: missing required key(s) {missing}")


def array(where: str, key: str, value: Any, shape=None, error=ValueError) -> np.ndarray:
    """Numbers as a float64 array, broadcast to ``shape`` (None: as they are), all finite."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise error(f"{where}: {key} must be numbers, got {value!r}") from None
    if shape is not None:
        try:
            arr = np.broadcast_to(arr, shape)
        except ValueError:
            dims = ", ".join(map(str, shape))
            raise error(
                f"{where}: {key} of shape {arr.shape} does not broadcast to [{dims}]"
            ) from None
    if not np.all(np.isfinite(arr)):
        raise error(f"{where}: {key} has non-finite values: {value!r}")
    return arr
