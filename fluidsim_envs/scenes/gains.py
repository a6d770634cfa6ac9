"""A scripted pilot's gains: the hand-set defaults of its frozen dataclass, and the tuned set
that ``benchmarks/tune_pilots.py`` writes beside the pilot as ``tuned_gains.json``.

A pilot module that can be tuned defines (``scenes/submarine_wake/pilot.py`` is an example):

- ``GAINS``: its frozen gains dataclass, a subclass of :class:`TunableGains` (the defaults are
  the hand-set gains; ``GAINS.tuned()`` reads the tuned ones);
- ``SEARCH_SPACE``: ``{gain: (low, high)}``, the range the tuner searches for each gain (the
  hand-set value inside it; :func:`check_search_space`);
- ``make_pilot(venv, gains=None)``: the pilot with ``gains`` (None: the tuned gains), the
  factory the scene registry holds; ``make_hand_pilot(venv)``: the pilot with the hand-set
  gains.

Each env version's pilot has its own tuned set, tuned on that version's episodes:
``tuned_gains.json`` for v0, ``tuned_gains_v1.json`` for v1 (:func:`tuned_file`); the
registry's pilot reads the one of the env it flies (``GAINS.for_env(venv)``). The file holds
the gains and how they were found (the command, the tuning seeds,
episodes and trials, the objective's value and the success rate on the tuning episodes, the
Optuna version and git revision): see :func:`write_tuned`. It ships with the package
(pyproject's package data); a pilot without one is an error that names the missing file.
"""

from __future__ import annotations

import dataclasses
import json
import re
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Self

TUNED_FILE = "tuned_gains.json"


class TunableGains:
    """Base of a pilot's frozen gains dataclass: adds :meth:`tuned` (no fields of its own)."""

    @classmethod
    def tuned(cls, path: str | Path | None = None, version: int = 0) -> Self:
        """The tuned gains, from ``path`` (default: the ``version``'s file beside the module
        that defines this class, :func:`tuned_path`)."""
        return gains_from(cls, read_tuned(path or tuned_path(cls, version)))

    @classmethod
    def for_env(cls, venv) -> Self:
        """The gains tuned on the version of ``venv`` (a vector env or a wrapper of one)."""
        return cls.tuned(version=getattr(venv.unwrapped, "version", 0))


def tuned_file(version: int = 0) -> str:
    """The tuned gains' file name of an env version: v0's is :data:`TUNED_FILE`."""
    return TUNED_FILE if version == 0 else f"tuned_gains_v{version}.json"


def tuned_path(gains_cls: type, version: int = 0) -> Path:
    """Where ``gains_cls``'s tuned gains for env ``version`` live: :func:`tuned_file` in its
    module's folder."""
    return Path(sys.modules[gains_cls.__module__].__file__).with_name(tuned_file(version))


def read_tuned(path: str | Path) -> dict[str, Any]:
    """The record :func:`write_tuned` wrote to ``path``; a missing file is an error naming it
    and the command that writes it."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(
            f"{path}: no tuned gains (written by `python -m benchmarks.tune_pilots ENV_ID "
            "--write`; shipped as package data)"
        )
    try:
        record = json.loads(path.read_text())
    except json.JSONDecodeError as e:
        raise ValueError(f"{path}: not a tuned-gains record (unreadable JSON: {e})") from None
    if not isinstance(record, dict) or not isinstance(record.get("gains"), dict):
        raise ValueError(f"{path}: not a tuned-gains record (no 'gains' table)")
    return record


def gains_from(gains_cls: type, record: Mapping[str, Any]) -> Any:
    """``gains_cls`` with the record's gains over its defaults; a gain the class does not have
    is an error that lists the ones it has."""
    fields = {f.name for f in dataclasses.fields(gains_cls)}
    unknown = sorted(set(record["gains"]) - fields)
    if unknown:
        raise ValueError(
            f"{gains_cls.__name__} has no gain {', '.join(unknown)} (it has: {sorted(fields)})"
        )
    return gains_cls(**{k: float(v) for k, v in record["gains"].items()})


def write_tuned(path: str | Path, gains: Any, **provenance: Any) -> Path:
    """Write ``gains`` (every field of the dataclass) and ``provenance`` (how they were found)
    to ``path`` as JSON."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    record = {"gains": dataclasses.asdict(gains), **provenance}
    text = json.dumps(record, indent=2)
    # a list of numbers on one line (the search space's ranges)
    text = re.sub(r"\[\s+([^\[\]{}]*?)\s+\]", lambda m: f"[{' '.join(m[1].split())}]", text)
    path.write_text(text + "\n")
    return path


def check_search_space(gains: Any, space: Mapping[str, tuple[float, float]]) -> None:
    """Every key of ``space`` is a gain of ``gains``, each range has low < high, and the
    hand-set value lies inside it (the tuner starts from it)."""
    name = type(gains).__name__
    fields = {f.name for f in dataclasses.fields(gains)}
    for key, (low, high) in space.items():
        if key not in fields:
            raise ValueError(f"SEARCH_SPACE names {key!r}, not a gain of {name}: {sorted(fields)}")
        if not low < high:
            raise ValueError(f"SEARCH_SPACE[{key!r}] = ({low}, {high}): low must be below high")
        value = getattr(gains, key)
        if not low <= value <= high:
            raise ValueError(
                f"SEARCH_SPACE[{key!r}] = ({low}, {high}) leaves out {name}.{key} = {value}"
            )


__all__ = [
    "TUNED_FILE",
    "TunableGains",
    "check_search_space",
    "gains_from",
    "read_tuned",
    "tuned_file",
    "tuned_path",
    "write_tuned",
]
