"""The one validation kit: every input check of the package, each error naming where, the key
and the bad value (``"World: air_density_kgm3 must be > 0, got -1.0"``).

Each function returns the value as the caller stores it (a float, an int, a tuple, an array)
and raises ``error`` (ValueError unless the caller has its own subclass, such as
``CraftError`` or ``ConfigError``). Bounds are inclusive unless named ``gt`` / ``lt``.
"""

from __future__ import annotations

import dataclasses
import math
import sys
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

_REAL = (int, float, np.integer, np.floating)
_SHOW = 120  # the longest repr a message quotes


def show(value: Any) -> str:
    """``repr(value)``, cut to a length a message can hold."""
    text = repr(value)
    return text if len(text) <= _SHOW else text[: _SHOW - 3] + "..."


def plain(value: Any) -> Any:
    """A NumPy scalar as the Python number, bool or string it holds; anything else as it is.
    What parameter sets store: numba then compiles one type per parameter (a np.float32
    argument would be a second specialization), and reprs and equality stay plain."""
    return value.item() if isinstance(value, np.generic) else value


def plain_fields(obj: Any) -> None:
    """Every field of the (frozen) dataclass ``obj`` through :func:`plain`, in place."""
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if isinstance(value, np.generic):
            object.__setattr__(obj, f.name, value.item())


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
    if ok and isinstance(value, (int, np.integer)):  # math.isnan(10**400) would overflow
        ok = integer or abs(int(value)) <= sys.float_info.max
    else:
        ok = ok and not math.isnan(value) and (math.isfinite(value) or not finite)
    ok = ok and (ge is None or value >= ge) and (gt is None or value > gt)
    ok = ok and (le is None or value <= le) and (lt is None or value < lt)
    if not ok:
        kind = "an integer" if integer else "a finite number" if finite else "a number"
        raise error(f"{where}: {key} must be {kind}{_bounds(ge, gt, le, lt)}, got {show(value)}")
    return int(value) if integer else float(value)


def vector(
    where: str, key: str, value: Any, n: int = 3, error: type[Exception] = ValueError
) -> tuple[float, ...]:
    """``n`` finite numbers, as a tuple of floats."""
    if not isinstance(value, (list, tuple, np.ndarray)) or len(value) != n:
        raise error(f"{where}: {key} must be a list of {n} numbers, got {show(value)}")
    return tuple(number(where, f"{key}[{i}]", v, error=error) for i, v in enumerate(value))


def direction(where: str, key: str, value: Any, error: type[Exception] = ValueError):
    """A non-zero 3-vector, normalized."""
    v = vector(where, key, value, 3, error)
    norm = math.sqrt(sum(c * c for c in v))
    if norm < 1e-9:
        raise error(f"{where}: {key} must be a non-zero direction, got {show(value)}")
    return (v[0] / norm, v[1] / norm, v[2] / norm)


def flag(where: str, key: str, value: Any, error: type[Exception] = ValueError) -> bool:
    """True or False, nothing that merely converts to one."""
    if not isinstance(value, (bool, np.bool_)):
        raise error(f"{where}: {key} must be True or False, got {show(value)}")
    return bool(value)


def choice(where: str, key: str, value: Any, choices: Sequence, error=ValueError):
    """One of ``choices``, of a choice's own type: 1 is not True, 1.0 is not 1, and an
    unhashable or array value is refused rather than compared."""
    v = plain(value)
    if not any(type(v) is type(c) and v == c for c in choices):
        raise error(f"{where}: {key} must be one of {list(choices)}, got {show(value)}")
    return v


def value_range(where: str, key: str, value: Any, ge=None, le=None, error=ValueError):
    """A (low, high) pair with ge <= low <= high <= le."""
    if not isinstance(value, (tuple, list, np.ndarray)) or len(value) != 2:
        raise error(f"{where}: {key} must be a (low, high) pair, got {show(value)}")
    low, high = (number(where, key, v, ge=ge, le=le, error=error) for v in value)
    if low > high:
        raise error(f"{where}: {key} must have low <= high, got {show(value)}")
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
        raise error(f"{where}: expected a table, got {show(data)}")
    valid = list(valid)
    unknown = sorted(set(data) - set(valid))
    if unknown:
        raise error(f"{where}: unknown key(s) {unknown}; valid keys are {valid}")
    missing = [k for k in required if k not in data]
    if missing:
        raise error(f"{where}: missing required key(s) {missing}")


def real_array(where: str, key: str, value: Any, error=ValueError) -> np.ndarray:
    """Real numbers (Python or NumPy ints and floats, or nested lists or arrays of them) as a
    float64 array (no copy of one already); a bool, a string, None, an object or complex
    array, or a ragged list is refused naming ``key`` (numpy would convert some of them or
    fail with a message that names nothing). Values are not checked for finiteness."""
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError):  # a ragged list
        raw = None
    if raw is None or raw.dtype.kind not in "iuf":
        what = "a ragged list" if raw is None else "bools" if raw.dtype.kind == "b" else None
        got = f"{what}: {show(value)}" if what else show(value)
        raise error(
            f"{where}: {key} must be real numbers (ints or floats, a list or an array of "
            f"them), got {got}"
        )
    return np.asarray(raw, dtype=np.float64)


def array(where: str, key: str, value: Any, shape=None, error=ValueError) -> np.ndarray:
    """Numbers as a float64 array, broadcast to ``shape`` (None: as they are), all finite."""
    arr = real_array(where, key, value, error)
    if shape is not None:
        try:
            arr = np.broadcast_to(arr, shape)
        except ValueError:
            dims = ", ".join(map(str, shape))
            raise error(
                f"{where}: {key} of shape {arr.shape} does not broadcast to [{dims}], "
                f"got {show(value)}"
            ) from None
    if not np.all(np.isfinite(arr)):
        raise error(f"{where}: {key} has non-finite values: {show(value)}")
    return arr


def env_ids(where: str, value: Any, num_envs: int, error=ValueError) -> np.ndarray:
    """Environments as int64 indices: None (all of them), indices in [0, num_envs) (Python
    or NumPy ints, a list or a 1-D array; empty: none), or a boolean mask of length
    ``num_envs`` (True: that environment). Anything else names the value and what is
    allowed: 0.5 would truncate to environment 0, and a mask read as indices would pick
    environments 0 and 1."""
    if value is None:
        return np.arange(num_envs, dtype=np.int64)
    allowed = f"a boolean mask of length {num_envs} or indices in [0, {num_envs})"
    try:
        ids = np.asarray(value)
    except (TypeError, ValueError):  # a ragged list
        ids = None
    if ids is not None and ids.dtype.kind == "b":
        if ids.shape != (num_envs,):
            raise error(
                f"{where}: env_ids as a boolean mask must have shape ({num_envs},), one per "
                f"environment, got shape {ids.shape}: {show(value)}"
            )
        return np.flatnonzero(ids).astype(np.int64)
    if ids is not None and ids.ndim == 1 and ids.size == 0:
        return np.zeros(0, dtype=np.int64)
    if ids is None or ids.ndim != 1 or ids.dtype.kind not in "iu":
        hint = " (a list, even of one)" if ids is not None and ids.ndim == 0 else ""
        raise error(f"{where}: env_ids must be {allowed}{hint}, got {show(value)}")
    outside = ids[(ids < 0) | (ids >= num_envs)]
    if outside.size:
        raise error(
            f"{where}: env_ids {outside.tolist()} out of range: env_ids must be {allowed}, "
            f"got {show(value)}"
        )
    return ids.astype(np.int64)


def seed(where: str, key: str, value: Any, error=ValueError) -> int | None:
    """A seed: None (fresh entropy) or an integer in [0, 2**128) (a Python or NumPy int).
    The bound keeps the seed streams apart (``fluidsim_envs.seeding``): NumPy pads a seed
    of fewer than four 32-bit words before the spawn key, and a longer one could spell
    another stream's key."""
    if value is None:
        return None
    if (
        isinstance(value, bool)
        or not isinstance(value, (int, np.integer))
        or not 0 <= value < 2**128
    ):
        raise error(f"{where}: {key} must be None or an integer in [0, 2**128), got {show(value)}")
    return int(value)
