"""The console scripts (``fluidsim-train``, ``fluidsim-evaluate``, ``fluidsim-sweep``,
``fluidsim-enjoy``, ``fluidsim-play``; pyproject's ``[project.scripts]``). They check the
extras they need before importing anything from them, so a missing one is an error that says
which ``pip install`` fixes it. ``--help`` works without them where the command's parser can
be built without them (``build_parser``: sweep, enjoy, play): it prints the options and then
the missing extra's ``pip install``."""

from __future__ import annotations

import importlib
import sys

from .extras import MissingExtra, require


def train(argv: list[str] | None = None) -> int:
    """``fluidsim-train``: :func:`fluidsim_envs.rl.train.main`."""
    return _run("fluidsim-train", "fluidsim_envs.rl.train", argv)


def evaluate(argv: list[str] | None = None) -> int:
    """``fluidsim-evaluate``: :func:`fluidsim_envs.rl.evaluate.main`."""
    return _run("fluidsim-evaluate", "fluidsim_envs.rl.evaluate", argv)


def sweep(argv: list[str] | None = None) -> int:
    """``fluidsim-sweep``: :func:`fluidsim_envs.rl.sweep.main` (needs the ``sweep`` extra,
    which installs the ``train`` one too: named first)."""
    return _run("fluidsim-sweep", "fluidsim_envs.rl.sweep", argv, extras=("sweep", "train"))


def enjoy(argv: list[str] | None = None) -> int:
    """``fluidsim-enjoy``: :func:`fluidsim_envs.enjoy.main` (needs the ``train`` extra, and
    from the ``play`` extra pygame for a window, moviepy for a ``--video`` other than a GIF)."""
    prog, module = "fluidsim-enjoy", "fluidsim_envs.enjoy"
    args = _argv(argv)
    only: dict[str, tuple[str, ...]] = {}
    if not _asks_help(args):
        given = importlib.import_module(module).build_parser(prog).parse_args(args)
        if given.video is not None and not given.video.lower().endswith(".gif"):
            only["play"] = ("moviepy",)
        elif given.video is None and given.rerun is None:
            only["play"] = ("pygame",)
    return _run(prog, module, args, ("train", *only), only)


def play(argv: list[str] | None = None) -> int:
    """``fluidsim-play``: :func:`fluidsim_envs.play.main` (needs the ``play`` extra)."""
    return _run("fluidsim-play", "fluidsim_envs.play", argv, extras=("play",))


def _argv(argv: list[str] | None) -> list[str]:
    return list(sys.argv[1:] if argv is None else argv)


def _asks_help(args: list[str]) -> bool:
    """``-h`` or ``--help`` among the options (before a ``--``), as argparse reads them."""
    options = args[: args.index("--")] if "--" in args else args
    return any(a in ("-h", "--help") for a in options)


def _run(
    prog: str,
    module: str,
    argv: list[str] | None,
    extras: tuple[str, ...] = ("train",),
    only: dict[str, tuple[str, ...]] | None = None,
) -> int:
    """Run ``module``'s ``main`` once every extra of ``extras`` is installed (of an extra in
    ``only``, the modules it names)."""
    args = _argv(argv)
    try:
        for extra in extras:
            require(extra, prog, (only or {}).get(extra))
    except MissingExtra as e:
        if _asks_help(args):
            _help_without(prog, module, e)
            return 0
        print(f"{prog}: error: {e}", file=sys.stderr)
        return 2
    return importlib.import_module(module).main(args, prog=prog)


def _help_without(prog: str, module: str, missing: MissingExtra) -> None:
    """``--help`` with an extra missing: the command's options where its parser can be
    built without the extra, then what to install to run it."""
    try:
        build_parser = getattr(importlib.import_module(module), "build_parser", None)
    except ImportError:  # the module itself needs the extra
        build_parser = None
    if build_parser is not None:
        build_parser(prog).print_help()
        print()
    print(f"not installed here: {missing}")


__all__ = ["enjoy", "evaluate", "play", "sweep", "train"]
