"""The console scripts (``fluidsim-train``, ``fluidsim-evaluate``; pyproject's
``[project.scripts]``). They check the ``train`` extra before importing anything from it, so a
missing one is an error that says which ``pip install`` fixes it."""

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


def _run(prog: str, module: str, argv: list[str] | None) -> int:
    try:
        require("train", prog)
    except MissingExtra as e:
        print(f"{prog}: error: {e}", file=sys.stderr)
        return 2
    return importlib.import_module(f"{__package__}.{module}").main(argv, prog=prog)


__all__ = ["evaluate", "train"]
