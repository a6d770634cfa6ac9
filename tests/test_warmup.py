"""python -m fluidsim_envs.warmup: compiles (here: loads, the suite has compiled them) each
env's kernels with a line per env, and refuses an unknown id by name."""

import subprocess
import sys

import pytest

from fluidsim_envs.scenes import SCENES
from fluidsim_envs.warmup import main, warm


def test_warm_steps_each_env_and_says_so():
    lines = []
    env_id = next(iter(SCENES))
    took = warm([env_id], parallel=False, say=lines.append)
    assert list(took) == [env_id] and took[env_id] > 0.0
    assert lines[0].startswith(f"compiling {env_id}") and f"{env_id}: ready in" in lines[1]


def test_unknown_env_is_refused_by_name(capsys):
    with pytest.raises(SystemExit):
        main(["fluidsim/Zeppelin-v0"])
    assert "unknown env id(s) ['fluidsim/Zeppelin-v0']" in capsys.readouterr().err


def test_module_prints_its_help():
    out = subprocess.run(
        [sys.executable, "-m", "fluidsim_envs.warmup", "--help"],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    assert "Compile the physics kernels ahead" in out.stdout and "--no-parallel" in out.stdout
