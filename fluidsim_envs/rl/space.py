"""A sweep's search space: a YAML file mapping config keys (as ``--set`` names them) to one
distribution each, checked against the config it varies before anything runs.

.. code-block:: yaml

    algorithm.learning_rate: {loguniform: [1.0e-4, 1.0e-3]}
    algorithm.n_epochs: {int: [5, 20]}            # both ends included
    algorithm.batch_size: {choice: [512, 1024, 2048]}
    normalize.epsilon: {loguniform: [1.0e-8, 1.0e-2]}

The distributions: ``uniform`` and ``loguniform`` (floats in ``[low, high]``), ``int`` and
``logint`` (integers, both ends included), ``choice`` (any YAML values). Every key must name
a config field (``env_kwargs.*`` an env parameter), and both ends of each range and every
choice must make a valid config: an unknown key, an empty range or a value the config refuses
is an error that names it. ``configs/search/`` ships a space per algorithm,
found by name (``--search ppo``). The seed is not searched: ``fluidsim-sweep --seeds N``
repeats each trial over seeds.

    >>> space = parse_space({"algorithm.gamma": {"uniform": [0.95, 0.999]}}, "space.yaml")
    >>> space["algorithm.gamma"]
    Dimension(key='algorithm.gamma', kind='uniform', values=(0.95, 0.999))
"""

from __future__ import annotations

import copy
import dataclasses
import math
import numbers
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .config import ALGORITHMS, SHIPPED, ConfigError, config_from_dict, get_key, set_key

#: the search spaces that ship with the package, found by name (``--search ppo``)
SHIPPED_SPACES = SHIPPED / "search"

#: the distributions a search space may name, and what each takes
KINDS = {
    "uniform": "[low, high], floats, low < high",
    "loguniform": "[low, high], floats, 0 < low < high",
    "int": "[low, high], integers, low < high, both included",
    "logint": "[low, high], integers, 1 <= low < high, both included",
    "choice": "a non-empty list of values",
}

#: keys a sweep sets itself (``--seeds``, ``--cpus-per-trial``), never searched
RESERVED = ("seed", "torch_threads", "numba_threads")


@dataclass(frozen=True)
class Dimension:
    """One searched key: its distribution ``kind`` and ``values`` (a range's two ends, or the
    choices)."""

    key: str
    kind: str
    values: tuple

    def tune_domain(self):
        """The Ray Tune domain (OptunaSearch turns it into Optuna's distribution)."""
        from ray import tune

        low, high = self.values[0], self.values[-1]
        return {
            "uniform": lambda: tune.uniform(low, high),
            "loguniform": lambda: tune.loguniform(low, high),
            "int": lambda: tune.randint(low, high + 1),  # Tune's upper end is excluded
            "logint": lambda: tune.lograndint(low, high + 1),
            "choice": lambda: tune.choice(list(self.values)),
        }[self.kind]()

    def nearest(self, value: Any) -> Any:
        """``value`` if this dimension can draw it, else the nearest value it can (a range's
        end, for a config value outside it); a choice it lacks is None."""
        if self.kind == "choice":
            return value if value in self.values else None
        low, high = self.values
        return min(max(value, low), high)

    def __str__(self) -> str:
        if self.kind == "choice":
            return f"{self.key} in {list(self.values)}"
        return f"{self.key} ~ {self.kind}[{self.values[0]}, {self.values[1]}]"


def find_space(name_or_path: str | Path) -> Path:
    """A search space file: ``name_or_path`` itself if it is a file, else the shipped space
    of that name; an error that lists the shipped ones otherwise."""
    path = Path(name_or_path)
    if path.is_file():
        return path
    shipped = {p.stem: p for p in sorted(SHIPPED_SPACES.glob("*.yaml"))}
    if path.parent == Path(".") and path.name.removesuffix(".yaml") in shipped:
        return shipped[path.name.removesuffix(".yaml")]
    raise ConfigError(
        f"--search {name_or_path}: file not found, nor a shipped search space "
        f"({', '.join(shipped)})"
    )


def parse_space(raw: Any, source: str) -> dict[str, Dimension]:
    """The dimensions of a search space read from YAML (``source`` names it in errors)."""
    if not isinstance(raw, dict) or not raw:
        raise ConfigError(
            f"{source}: a search space maps config keys to distributions "
            f"(e.g. 'algorithm.learning_rate: {{loguniform: [1.0e-4, 1.0e-3]}}'), got {raw!r}"
        )
    return {str(key): _dimension(str(key), spec, source) for key, spec in raw.items()}


def _dimension(key: str, spec: Any, source: str) -> Dimension:
    where = f"{source}: {key}"
    if key in RESERVED:
        raise ConfigError(f"{where}: set by the sweep itself (--seeds, --cpus-per-trial)")
    if not isinstance(spec, dict) or len(spec) != 1 or next(iter(spec)) not in KINDS:
        kinds = "; ".join(f"{k}: {v}" for k, v in KINDS.items())
        raise ConfigError(f"{where}: expected one distribution ({kinds}), got {spec!r}")
    kind, values = next(iter(spec.items()))
    if kind == "choice":
        if not isinstance(values, list) or not values:
            raise ConfigError(f"{where}: choice needs a non-empty list of values, got {values!r}")
        return Dimension(key, kind, tuple(values))
    return Dimension(key, kind, _range(where, kind, values))


def _range(where: str, kind: str, values: Any) -> tuple:
    integer = kind in ("int", "logint")
    number = numbers.Integral if integer else numbers.Real
    ok = isinstance(values, list) and len(values) == 2
    ok = ok and all(isinstance(v, number) and not isinstance(v, bool) for v in values)
    if not ok or not all(math.isfinite(v) for v in values):
        raise ConfigError(f"{where}: {kind} needs {KINDS[kind]}, got {values!r}")
    low, high = (int(v) for v in values) if integer else (float(v) for v in values)
    if not low < high:
        raise ConfigError(
            f"{where}: {kind} range [{low}, {high}] is empty or a single value "
            "(a fixed value belongs in the config or --set)"
        )
    if (kind == "loguniform" and low <= 0) or (kind == "logint" and low < 1):
        raise ConfigError(f"{where}: {kind} needs {KINDS[kind]}, got [{low}, {high}]")
    return (low, high)


def check_space(space: dict[str, Dimension], base: dict[str, Any], source: str) -> None:
    """Every key names a config field and every end and choice is a value it takes, set in
    ``base`` (a config as plain data) one dimension at a time. What ties keys together (a
    batch no larger than a rollout) is checked by each trial, on its whole config: a trial
    whose combination is refused ends as an error that names it."""
    _check_algorithm(space, base, source)
    for dim in space.values():
        for value in dim.values:
            raw = copy.deepcopy(base)
            try:
                set_key(raw, dim.key, value, f"{source}: {dim.key}")
                config_from_dict(raw, joint=False)
            except ConfigError as e:
                raise ConfigError(f"{source}: {dim.key} = {value!r}: {e}") from None


def _check_algorithm(space: dict[str, Dimension], base: dict[str, Any], source: str) -> None:
    """A space that tunes another algorithm's keys: an error that says whose they are."""
    ours = base.get("algorithm", {}).get("name")
    keys = [k.split(".", 1)[1] for k in space if k.startswith("algorithm.")]
    fields = {n: {f.name for f in dataclasses.fields(c)} for n, c in ALGORITHMS.items()}
    foreign = [k for k in keys if k not in fields.get(ours, set())]
    theirs = [n for n, names in fields.items() if n != ours and foreign and set(keys) <= names]
    if foreign and theirs:
        raise ConfigError(
            f"{source}: tunes {theirs[0]}'s keys ({', '.join(f'algorithm.{k}' for k in foreign)}), "
            f"but the config's algorithm is {ours}: pass --search {ours} (or a space of "
            f"{ours}'s keys)"
        )


def base_point(space: dict[str, Dimension], base: dict[str, Any]) -> tuple[dict, list[str]]:
    """The config's own values of the searched keys, as a point of the space (the search's
    first trial: the config it must beat), and a line for each value the space cannot draw,
    saying what stands in for it."""
    point, notes = {}, []
    for key, dim in space.items():
        node = get_key(base, key)
        near = None if node is None else dim.nearest(node)
        if node is None:  # unset (an env parameter left at its default) or null
            near = dim.values[0]
            notes.append(f"{key}: the config does not set it; {near!r}")
        elif near is None:
            near = dim.values[0]
            notes.append(f"{key}: the config's {node!r} is no choice of the space; {near!r}")
        elif near != node:
            notes.append(f"{key}: the config's {node!r} is outside {dim}; {near!r}")
        point[key] = near
    return point, notes


def apply_params(base: dict[str, Any], params: dict[str, Any]) -> dict[str, Any]:
    """A copy of ``base`` with each searched key set to its sampled value."""
    raw = copy.deepcopy(base)
    for key, value in params.items():
        set_key(raw, key, plain(value), f"search key {key}")
    return raw


def plain(value: Any) -> Any:
    """NumPy scalars (Optuna's and Tune's samples) as Python numbers."""
    return value.item() if hasattr(value, "item") else value


__all__ = [
    "KINDS",
    "Dimension",
    "apply_params",
    "base_point",
    "check_space",
    "find_space",
    "parse_space",
    "plain",
]
