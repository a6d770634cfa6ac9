"""The one owner of threads (:mod:`fluidsim_envs.threads`): what it chooses, the counts it
refuses, that it sets numba's and torch's pools and gives them back, and that the training
CLI goes through it (its plan line, run.yaml, a count above the cores refused by name)."""

from __future__ import annotations

import numba
import pytest

from fluidsim_envs import threads
from fluidsim_envs.threads import ThreadError, choose


def test_defaults_one_torch_thread_and_numba_on_every_core():
    plan = choose(cores=2, load=0.0)
    assert (plan.torch, plan.numba, plan.cores) == (1, min(2, threads.numba_pool_size()), 2)
    assert not plan.busy
    assert plan.describe().startswith("threads: numba")


def test_cores_default_to_the_process_affinity():
    import os

    assert choose().cores == len(os.sched_getaffinity(0))


def test_a_busy_machine_is_said_with_its_load_and_what_was_chosen():
    line = choose(cores=2, load=2.9).describe()
    assert "the machine is busy: load average 2.9 at start" in line
    assert "torch 1" in line and "torch kept to 1 thread" in line
    assert "busy" not in choose(cores=2, load=0.4).describe()


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"torch": 3}, "torch_threads 3: more than the 2 cores this process may use"),
        ({"torch": 0}, "torch_threads 0: at least 1"),
        ({"torch": -1}, "torch_threads -1: at least 1"),
        ({"numba": 5}, "numba_threads 5: more than the 2 cores"),
        ({"numba": 0}, "numba_threads 0: at least 1"),
        ({"torch": 1.5}, "torch_threads must be an integer, got 1.5"),
        ({"numba": True}, "numba_threads must be an integer, got True"),
    ],
)
def test_bad_counts_are_refused_by_name(kwargs, message):
    with pytest.raises(ThreadError, match=message):
        choose(cores=2, load=0.0, **kwargs)


def test_owned_sets_both_pools_and_gives_them_back():
    import torch

    numba_before, torch_before = numba.get_num_threads(), torch.get_num_threads()
    plan = threads.Threads(cores=1, numba=1, torch=1)
    with threads.owned(plan):
        assert numba.get_num_threads() == 1 and torch.get_num_threads() == 1
    assert numba.get_num_threads() == numba_before
    assert torch.get_num_threads() == torch_before


def test_training_runs_on_the_owners_threads(tmp_path, capsys):
    """The plan line names the threads; run.yaml keeps them; a count above the cores this
    process may use is an error naming it, before anything is written."""
    import yaml

    from fluidsim_envs.rl import train

    tiny = ["total_timesteps=64", "n_envs=4", "algorithm.n_steps=16", "algorithm.batch_size=32",
            "eval.freq=0", "checkpoint.freq=0"]  # fmt: skip
    args = ["paper_airplane_ppo", "--no-progress-bar", "--set", *tiny]
    assert train.main([*args, "--run-dir", str(tmp_path / "r")]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[1].startswith("threads: numba ") and ", torch 1, on " in out[1]
    meta = yaml.safe_load((tmp_path / "r" / "run.yaml").read_text())
    assert meta["threads"]["torch"] == meta["torch_threads"] == 1
    assert meta["threads"]["cores"] == threads.available_cores()
    too_many = threads.available_cores() + 1
    bad = [*args, f"torch_threads={too_many}", "--run-dir", str(tmp_path / "bad")]
    assert train.main(bad) == 2
    err = capsys.readouterr().err
    assert f"torch_threads {too_many}: more than the {too_many - 1} cores" in err
    assert not (tmp_path / "bad").exists()


def test_a_torch_team_is_warned_of():
    line = choose(torch=2, cores=2, load=0.0).describe()
    assert "torch 2" in line and "warning: a torch team of several threads" in line


def test_the_owner_does_not_start_numbas_pool_for_its_default():
    """numba's pool starts with every thread when a kernel first needs it: the owner leaves
    it unstarted for that count (a started pool beside a torch team spins), and reads the
    count without starting it."""
    import subprocess
    import sys

    code = (
        "from fluidsim_envs import threads\n"
        "plan = threads.choose(torch=1, cores=threads.numba_pool_size())\n"
        "with threads.owned(plan):\n"
        "    assert not threads.numba_pool_started()\n"
        "assert threads.current().numba == threads.numba_pool_size()\n"
        "assert not threads.numba_pool_started()\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
