"""The pieces that keep a run folder whole through kills, without training: atomic writes, the
best model's commit, the evaluation history and monitor.csv trimmed to a restart point; and
the config checks that run before a folder exists (duplicate YAML keys, NumPy scalars,
devices). The kills themselves: benchmarks/kill_resume.py."""

from __future__ import annotations

import csv
import math
import os
from pathlib import Path

import numpy as np
import pytest
import torch
import yaml

from fluidsim_envs.rl import files, saved
from fluidsim_envs.rl.config import (
    ConfigError,
    config_from_dict,
    config_to_dict,
    load_config,
    load_yaml,
)
from fluidsim_envs.rl.runs import BestModel, EvalLog, trim_monitor

MINIMAL = {"env_id": "fluidsim/PaperAirplane-v0", "algorithm": {"name": "ppo"}}


# --------------------------------------------------------------------------------------------
# atomic writes


def test_a_failed_write_leaves_the_old_file_whole_and_no_temporary(tmp_path):
    path = tmp_path / "model.safetensors"
    path.write_bytes(b"old model")
    with pytest.raises(RuntimeError), files.atomic_path(path) as tmp:
        tmp.write_bytes(b"half a ne")
        assert tmp.parent == tmp_path and tmp.suffix == path.suffix and tmp.name.startswith(".")
        raise RuntimeError("killed")
    assert path.read_bytes() == b"old model"
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]
    files.write_bytes(path, b"new model")
    assert path.read_bytes() == b"new model"
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]


def test_temporary_files_of_killed_writes_are_removed_and_nothing_else(tmp_path):
    (tmp_path / "eval").mkdir()
    left = [tmp_path / ".run.yaml.x1.partial.yaml", tmp_path / "eval" / ".h.csv.x.partial.csv"]
    kept = [tmp_path / "run.yaml", tmp_path / ".hidden", tmp_path / "eval" / "history.csv"]
    for p in left + kept:
        p.write_text("x")
    assert sorted(files.remove_partials(tmp_path)) == sorted(left)
    assert all(p.exists() for p in kept) and not any(p.exists() for p in left)


@pytest.mark.parametrize("where", ["file", "under a file", "/proc", "/sys"])
def test_unwritable_paths_are_named_with_the_reason(tmp_path, where):
    (tmp_path / "a_file").write_text("x")
    path = {
        "file": tmp_path / "a_file",
        "under a file": tmp_path / "a_file" / "run",
        "/proc": Path("/proc/fluidsim-run"),
        "/sys": Path("/sys/fluidsim-run"),
    }[where]
    with pytest.raises(files.RunError, match=f"--run-dir {path}: ") as caught:
        files.check_writable_folder(path, "--run-dir")
    assert any(w in str(caught.value) for w in ("not a folder", "cannot write in"))
    files.check_writable_folder(tmp_path / "new" / "run", "--run-dir")  # creatable: fine
    assert not (tmp_path / "new").exists()  # and not created by the check


# --------------------------------------------------------------------------------------------
# the best model


@pytest.fixture(autouse=True)
def fake_files(monkeypatch):
    """The saved files as the fakes below write them (a word each, not weights)."""
    monkeypatch.setattr(saved, "save_model", lambda model, path: model.save(path))
    monkeypatch.setattr(saved, "save_statistics", lambda stats, path: stats.save(path))
    monkeypatch.setattr(saved, "read_header", lambda path, kind: {})


class FakeModel:
    """What BestModel.save uses of an SB3 model: the model and its statistics written
    (:func:`fake_files`), get_vec_normalize_env()."""

    def __init__(self, name: str, fail_stats: bool = False) -> None:
        self.name, self.fail_stats = name, fail_stats

    def save(self, path) -> None:
        Path(path).write_text(f"model {self.name}")

    def get_vec_normalize_env(self):
        model = self

        class Stats:
            def save(self, path) -> None:
                if model.fail_stats:
                    raise KeyboardInterrupt  # a kill between the model and its statistics
                Path(path).write_text(f"stats {model.name}")

        return Stats()


def best_files(folder: Path) -> tuple[str, str, float]:
    score = yaml.safe_load((folder / "best.yaml").read_text())["mean_return"]
    return (
        (folder / BestModel.MODEL).read_text(),
        (folder / BestModel.STATS).read_text(),
        score,
    )


def test_a_kill_before_the_commit_keeps_the_old_best_whole(tmp_path):
    best = BestModel(tmp_path)
    best.save(FakeModel("a"), {"mean_return": 17.18, "timesteps": 1024})
    with pytest.raises(KeyboardInterrupt):
        best.save(FakeModel("b", fail_stats=True), {"mean_return": 20.0, "timesteps": 2048})
    reopened = BestModel.open(tmp_path)
    assert best_files(tmp_path) == ("model a", "stats a", 17.18) and reopened.score == 17.18
    assert not list(tmp_path.glob(".pending-*"))


def test_a_kill_after_the_commit_is_completed_on_the_next_start(tmp_path, monkeypatch):
    best = BestModel(tmp_path)
    best.save(FakeModel("a"), {"mean_return": 1.0})
    real_replace, replaced = os.replace, []

    def replace(src, dst):
        # the renames of a save: the pending model and statistics, best.yaml (the commit),
        # the model to its final name, then the statistics: the kill lands before that one
        if len(replaced) == 4:
            raise KeyboardInterrupt
        replaced.append(Path(dst).name)
        os.rename(src, dst)

    monkeypatch.setattr(os, "replace", replace)
    with pytest.raises(KeyboardInterrupt):
        best.save(FakeModel("b"), {"mean_return": 2.0})
    monkeypatch.setattr(os, "replace", real_replace)
    assert replaced[2:] == ["best.yaml", BestModel.MODEL]
    assert (tmp_path / BestModel.MODEL).read_text() == "model b"  # statistics still "a"
    assert (tmp_path / BestModel.STATS).read_text() == "stats a"
    assert BestModel.open(tmp_path).score == 2.0
    assert best_files(tmp_path) == ("model b", "stats b", 2.0)
    assert not list(tmp_path.glob(".pending-*"))


def test_an_evaluation_reads_the_committed_best_without_touching_the_folder(tmp_path, monkeypatch):
    """fluidsim-evaluate --model best beside a trainer between its commit and its renames:
    it reads the committed pending files and deletes or renames nothing (the trainer's own
    renames must still find them)."""
    best = BestModel(tmp_path)
    best.save(FakeModel("a"), {"mean_return": 1.0})
    real_replace, calls = os.replace, []

    def replace(src, dst):  # the kill: right after best.yaml (the commit)
        if calls and calls[-1] == "best.yaml":
            raise KeyboardInterrupt
        calls.append(Path(dst).name)
        real_replace(src, dst)

    monkeypatch.setattr(os, "replace", replace)
    with pytest.raises(KeyboardInterrupt):
        best.save(FakeModel("b"), {"mean_return": 2.0})
    monkeypatch.setattr(os, "replace", real_replace)
    before = sorted(p.name for p in tmp_path.iterdir())
    model, stats = BestModel(tmp_path).committed()
    assert (model.read_text(), stats.read_text()) == ("model b", "stats b")
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    assert BestModel(tmp_path / "none").committed()[0] == tmp_path / "none" / BestModel.MODEL


def test_run_files_get_the_mode_a_plain_write_gives(tmp_path):
    files.write_text(tmp_path / "a.yaml", "x: 1\n")
    (tmp_path / "b.yaml").write_text("x: 1\n")
    mode = lambda name: (tmp_path / name).stat().st_mode & 0o777  # noqa: E731
    assert mode("a.yaml") == mode("b.yaml")


def test_no_best_yet_scores_minus_infinity(tmp_path):
    assert BestModel.open(tmp_path / "best").score == -math.inf


# --------------------------------------------------------------------------------------------
# the evaluation history and monitor.csv


def test_the_evaluation_history_is_trimmed_to_the_restart_and_goes_on(tmp_path):
    log = EvalLog(tmp_path)
    for steps, mean in ((1024, 1.0), (2048, 17.18), (3072, 3.0)):
        log.add(steps, [mean - 1, mean + 1], [80, 90], [0.0, 1.0])
    log.save()
    again = EvalLog.load(tmp_path)
    again.trim(2048)
    again.add(3072, [1.03, 1.03], [70, 70], [])  # a resumed evaluation without success flags
    again.add(4096, [5.0, 6.0, 7.0], [60, 60, 60], [1.0, 1.0, 1.0])  # more episodes
    again.save()
    data = np.load(tmp_path / "evaluations.npz")
    assert data["timesteps"].tolist() == [1024, 2048, 3072, 4096]
    assert data["results"].shape == (4, 3) and np.isnan(data["results"][0, 2])
    with (tmp_path / "history.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert [int(r["timesteps"]) for r in rows] == [1024, 2048, 3072, 4096]
    assert [float(r["mean_return"]) for r in rows] == pytest.approx([1.0, 17.18, 1.03, 6.0])
    assert math.isnan(float(rows[2]["success_rate"])) and float(rows[3]["success_rate"]) == 1
    assert EvalLog.load(tmp_path).best_mean() == pytest.approx(17.18)


MONITOR = """#{"t_start": 1700000000.0, "env_id": "fluidsim/PaperAirplane-v0"}
r,l,t,success,timesteps
1.5,40,0.5,False,320
2.5,50,1.25,True,1024
3.5,60,2.0,False,1032
4.5,70,2.5,False,2048
5.5,8"""


def test_monitor_rows_after_the_restart_and_a_cut_row_are_dropped(tmp_path):
    path = tmp_path / "monitor.csv"
    path.write_text(MONITOR)
    assert trim_monitor(path, 1024) == 1.25  # the resumed run's times go on from here
    assert path.read_text() == "\n".join(MONITOR.splitlines()[:4]) + "\n"


def test_a_monitor_of_an_older_version_keeps_its_rows(tmp_path):
    path = tmp_path / "monitor.csv"
    old = MONITOR.replace(",timesteps", "").replace(",320", "").replace(",1024", "")
    path.write_text("\n".join(old.splitlines()[:4]) + "\n")
    said = []
    assert trim_monitor(path, 0, say=said.append) == 1.25
    lines = path.read_text().splitlines()
    assert lines[1] == "r,l,t,success,timesteps" and lines[2] == "1.5,40,0.5,False,"
    assert "has no timesteps column" in said[0]


# --------------------------------------------------------------------------------------------
# the config, before any folder


def test_a_key_given_twice_is_an_error_naming_it_and_its_lines(tmp_path):
    path = tmp_path / "twice.yaml"
    text = "env_id: fluidsim/PaperAirplane-v0\nalgorithm:\n  name: ppo\n  gamma: 0.9\n"
    path.write_text(text + "  gamma: 0.99\nn_envs: 2\n")
    with pytest.raises(ConfigError, match=r"twice.yaml: duplicate key 'gamma' at line 5 \(first"):
        load_config(path)
    # a merge key's values may be overridden: not a duplicate
    merged = load_yaml("base: &b {n: 1, m: 2}\nmine:\n  <<: *b\n  n: 3\n", "test")
    assert merged["mine"] == {"n": 3, "m": 2}
    with pytest.raises(ConfigError, match="--set 'policy={a: 1, a: 2}': the value: duplicate"):
        load_config("paper_airplane_ppo", ["policy={a: 1, a: 2}"])


def test_numpy_scalars_are_numbers():
    cfg = config_from_dict(
        {
            **MINIMAL,
            "n_envs": np.int64(8),
            "algorithm": {
                "name": "ppo",
                "learning_rate": np.float32(3e-4),
                "n_steps": np.int32(256),
            },
            "policy": {"net_arch": np.array([16, 16]), "ortho_init": np.bool_(False)},
            "env_kwargs": {"max_episode_steps": np.int64(50)},
        }
    )
    assert cfg.n_envs == 8 and type(cfg.n_envs) is int
    assert type(cfg.algorithm.learning_rate) is float and cfg.policy.net_arch == (16, 16)
    assert cfg.policy.ortho_init is False and type(cfg.env_kwargs["max_episode_steps"]) is int
    assert yaml.safe_dump(config_to_dict(cfg))  # plain data: the run folder can write it


def test_devices_are_checked_against_what_torch_sees(monkeypatch):
    for device in ("cpu", "auto"):
        assert config_from_dict({**MINIMAL, "device": device}).device == device
    monkeypatch.setattr(torch.cuda, "is_available", lambda: True)
    monkeypatch.setattr(torch.cuda, "device_count", lambda: 2)
    assert config_from_dict({**MINIMAL, "device": "cuda:1"}).device == "cuda:1"
    with pytest.raises(ConfigError, match=r"device 'cuda:7' does not exist: torch sees 2 CUDA"):
        config_from_dict({**MINIMAL, "device": "cuda:7"})
    monkeypatch.setattr(torch.cuda, "is_available", lambda: False)
    with pytest.raises(ConfigError, match="device 'cuda' does not exist: torch sees no CUDA"):
        config_from_dict({**MINIMAL, "device": "cuda"})


def test_a_run_resumed_where_an_evaluation_was_interrupted_evaluates_first(tmp_path):
    """Ctrl-C during the evaluation at step S saves its checkpoint at S without it: the
    resumed run evaluates at S before training on, and only then (not when S is logged, nor
    off the evaluation period)."""
    from fluidsim_envs.rl.callbacks import Evaluations

    ran = []
    log = EvalLog(tmp_path)
    log.add(512, [1.0], [10], [])
    for steps, logged, expect in ((1024, [512], True), (512, [512], False), (768, [512], False)):
        log.timesteps = list(logged)
        cb = Evaluations(None, 512, 1, 0, log, BestModel(tmp_path / "best"), lambda *a: None)
        cb._evaluate = lambda steps=steps: ran.append(steps)  # the episodes need a model
        cb.num_timesteps = steps
        cb._on_training_start()
        assert (ran[-1:] == [steps]) == expect, (steps, ran)
