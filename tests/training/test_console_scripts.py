"""The console scripts of pyproject's ``[project.scripts]``: each one's ``--help`` works and
explains every option; one whose extra is missing says which ``pip install`` adds it, and its
``--help`` still lists its options (the sweep's parser is built without Ray)."""

from __future__ import annotations

import argparse
import importlib
import sys
import tomllib
from pathlib import Path

import pytest

from fluidsim_envs.rl import cli
from fluidsim_envs.rl.extras import EXTRAS

PYPROJECT = Path(__file__).resolve().parents[2] / "pyproject.toml"
SCRIPTS = tomllib.loads(PYPROJECT.read_text())["project"]["scripts"]


def entry_point(name: str):
    """The function the installed script ``name`` calls (``module:function``)."""
    module, _, function = SCRIPTS[name].partition(":")
    return getattr(importlib.import_module(module), function)


def without(monkeypatch, *modules: str) -> None:
    """Make ``modules`` (and their submodules already imported) unimportable, as where their
    extra is not installed: ``find_spec`` finds nothing and ``import`` fails."""
    for name in [m for m in sys.modules if m.split(".")[0] in modules] + list(modules):
        monkeypatch.setitem(sys.modules, name, None)


def help_of(monkeypatch, capsys, name: str) -> tuple[str, argparse.ArgumentParser]:
    """The script's ``--help`` text and its parser, once it exited with status 0."""
    shown: list[argparse.ArgumentParser] = []
    real = argparse.ArgumentParser.print_help

    def spy(self, file=None):
        shown.append(self)
        real(self, file)

    monkeypatch.setattr(argparse.ArgumentParser, "print_help", spy)
    try:
        status = entry_point(name)(["--help"])
    except SystemExit as e:  # argparse's --help
        status = e.code
    assert status in (0, None), status
    assert len(shown) == 1
    return capsys.readouterr().out, shown[0]


def test_pyproject_installs_the_five_commands():
    assert set(SCRIPTS) == {
        "fluidsim-train",
        "fluidsim-evaluate",
        "fluidsim-sweep",
        "fluidsim-enjoy",
        "fluidsim-play",
    }
    assert all(value.startswith("fluidsim_envs.rl.cli:") for value in SCRIPTS.values())


@pytest.mark.parametrize("name", sorted(SCRIPTS))
def test_each_script_helps_with_every_option(monkeypatch, capsys, name):
    out, parser = help_of(monkeypatch, capsys, name)
    assert out.startswith(f"usage: {name} ")  # named as the user typed it
    for action in parser._actions:
        if isinstance(action, argparse._HelpAction):
            continue
        what = "/".join(action.option_strings) or action.dest
        assert action.help and action.help != argparse.SUPPRESS, f"{name} {what}: no help"
    assert "not installed here" not in out


@pytest.mark.parametrize(
    ("name", "missing", "extra", "option"),
    [
        ("fluidsim-sweep", EXTRAS["sweep"], "sweep", "--address"),
        ("fluidsim-play", ("pygame",), "play", "--scale"),
        ("fluidsim-enjoy", ("stable_baselines3",), "train", "--video"),
    ],
)
def test_help_without_the_extra_lists_the_options_and_the_pip_install(
    monkeypatch, capsys, name, missing, extra, option
):
    """The module is imported again with the extra's packages blocked: its parser must build
    without them (the sweep module imports Ray only where a sweep runs)."""
    without(monkeypatch, *missing)
    if name == "fluidsim-sweep":  # imported afresh; put back as it was after the test
        import fluidsim_envs.rl

        original = importlib.import_module("fluidsim_envs.rl.sweep")
        monkeypatch.setattr(fluidsim_envs.rl, "sweep", original)
        monkeypatch.delitem(sys.modules, "fluidsim_envs.rl.sweep")
    out, parser = help_of(monkeypatch, capsys, name)
    assert out.startswith(f"usage: {name} ") and option in out
    last = out.strip().splitlines()[-1]
    assert last.startswith(f"not installed here: {name} needs {missing[0]}")
    assert last.endswith(f'pip install "fluidsim-envs[{extra}]"')
    # and without --help, the same line as an error before anything runs
    assert entry_point(name)(["x"]) == 2
    assert f'pip install "fluidsim-envs[{extra}]"' in capsys.readouterr().err


@pytest.mark.parametrize(
    ("argv", "needs"),
    [
        (["RUN"], "pygame"),  # a window
        (["RUN", "--video", "flight.mp4"], "moviepy"),
        (["RUN", "--video", "flight.gif"], None),  # Pillow, which the train extra brings
        (["RUN", "--rerun", "flight.rrd"], None),
    ],
)
def test_enjoy_asks_for_the_play_extra_where_it_needs_it(monkeypatch, capsys, argv, needs):
    without(monkeypatch, "pygame", "moviepy")
    assert cli.enjoy(argv) == 2
    err = capsys.readouterr().err
    if needs is not None:
        play = 'pip install "fluidsim-envs[play]"'
        assert (
            err
            == f"fluidsim-enjoy: error: fluidsim-enjoy needs {needs} (the 'play' extra): {play}\n"
        )
    else:  # on to the folder, which does not exist
        assert "pip install" not in err and "RUN" in err
