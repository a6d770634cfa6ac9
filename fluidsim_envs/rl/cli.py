"""The console scripts (``fluidsim-train``, ``fluidsim-evaluate``, ``fluidsim-sweep``;
pyproject's ``[project.scripts]``). They check the extras they need before importing anything
from them, so a missing one is an error that says which ``pip install`` fixes it."""

from __future__ import annotations

import importlib
import sys

from .extras import MissingExtra, require


def train(argv: list[str] | None = None) -> int:
    """``fluidsim-train``: :func:`fluidsim_envs.rl.train.main`."""
    return _run("fluidsim-train", "train", argv)


def evaluate(argv: list[str] | None = None) -> int:
    """``fluidsim-evaluate``: :func:`fluidsim_envs.rl.evaluate.main`."""
    return _run("fluidsim-evaluate", "evaluate", argv)


def sweep(argv: list[str] | None = None) -> int:
    """``fluidsim-sweep``: :func:`fluidsim_envs.rl.sweep.main` (needs the ``sweep`` extra)."""
    return _run("fluidsim-sweep", "sweep", argv, extras=("train", "sweep"))


def _run(prog: str, module: str, argv: list[str] | None, extras=("train",)) -> int:
    try:
        for extra in extras:
            require(extra, prog)
    except MissingExtra as e:
        print(f"{prog}: error: {e}", file=sys.stderr)
        return 2
    return importlib.import_module(f"{__package__}.{module}").main(argv, prog=prog)


__all__ = ["evaluate", "sweep", "train"]
