"""The training CLI end to end on a tiny budget: train.py writes a self-describing run folder,
evaluate.py evaluates it beside the baselines, --resume continues an interrupted run, and bad
input (a misspelled key, a missing file, a run folder that does not fit together, a corrupt
model) is a clear error, not a traceback."""

from __future__ import annotations

import csv
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
import yaml

from fluidsim_envs.rl import evaluate as evaluate_cli
from fluidsim_envs.rl import train as train_cli

REPO = Path(__file__).resolve().parents[2]
CONFIG = REPO / "configs" / "paper_airplane_ppo.yaml"
# 2 PPO rollouts of 8 envs x 128 steps, evaluated (2 episodes) and checkpointed after each
TINY = [
    "total_timesteps=2048",
    "n_envs=8",
    "algorithm.n_steps=128",
    "algorithm.batch_size=256",
    "eval.freq=1024",
    "eval.n_episodes=2",
    "checkpoint.freq=1024",
]


def run_script(script: str, *args, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, str(REPO / "training" / script), *map(str, args)],
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=300,
    )


@pytest.fixture(scope="module")
def run(tmp_path_factory) -> Path:
    """One tiny training run through the real CLI, shared by the tests below (read-only:
    tests that change a run work on a copy)."""
    where = tmp_path_factory.mktemp("train")
    run_dir = where / "run"
    done = run_script("train.py", CONFIG, "--set", *TINY, "--run-dir", run_dir, cwd=where)
    assert done.returncode == 0, done.stderr[-3000:]
    return run_dir


def copy_run(run: Path, tmp_path: Path) -> Path:
    return Path(shutil.copytree(run, tmp_path / "run"))


def test_train_writes_a_self_describing_run_folder(run):
    for name in (
        "config.yaml",
        "run.yaml",
        "model.zip",
        "vecnormalize.pkl",
        "monitor.csv",
        "learning_curve.png",
        "eval/history.csv",
        "eval/evaluations.npz",
        "best/best_model.zip",
    ):
        assert (run / name).is_file(), name
    assert sorted(p.name for p in (run / "checkpoints").iterdir()) == [
        "model_1024_steps.zip",
        "model_2048_steps.zip",
        "model_vecnormalize_1024_steps.pkl",
        "model_vecnormalize_2048_steps.pkl",
    ]
    assert any((run / "tb").rglob("events.out.tfevents.*"))
    # the resolved config: the file's values with the overrides applied, all keys present
    cfg = yaml.safe_load((run / "config.yaml").read_text())
    assert cfg["total_timesteps"] == 2048 and cfg["n_envs"] == 8
    assert cfg["algorithm"]["n_steps"] == 128 and cfg["algorithm"]["gae_lambda"] == 0.95
    assert cfg["policy"]["net_arch"] == {"pi": [64, 64], "vf": [64, 64]}
    meta = yaml.safe_load((run / "run.yaml").read_text())
    assert meta["env_id"] == "fluidsim/PaperAirplane-v0" and meta["algorithm"] == "ppo"
    assert meta["command"][1:4] == ["training/train.py", str(CONFIG), "--set"]
    assert "total_timesteps=2048" in meta["command_line"]
    assert set(meta["git"]) == {"revision", "dirty"}
    assert meta["git"]["revision"] is None or len(meta["git"]["revision"]) == 40
    assert meta["seeds"]["model"] == 0 and meta["num_timesteps"] == 2048
    assert meta["versions"]["stable_baselines3"]
    (timing,) = meta["timing"]  # where the time went: the envs against the learner
    assert timing["env_steps"] == 2048 and 0.0 < timing["env_share"] < 1.0
    assert timing["train_env_s"] + timing["eval_env_s"] < timing["wall_s"]
    with (run / "eval" / "history.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert [int(r["timesteps"]) for r in rows] == [1024, 2048]
    assert all(np.isfinite(float(r["mean_return"])) for r in rows)
    assert all(0.0 <= float(r["success_rate"]) <= 1.0 for r in rows)
    monitor = (run / "monitor.csv").read_text().splitlines()
    assert monitor[1] == "r,l,t,success" and len(monitor) > 10
    assert (run / "learning_curve.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_evaluate_compares_the_model_with_the_pilot_and_random(run, tmp_path):
    run = copy_run(run, tmp_path)
    done = run_script("evaluate.py", run, "--episodes", 6, "--seed", 5, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-3000:]
    table = done.stdout
    assert "trained PPO" in table and "scripted pilot" in table and "random" in table
    for metric in ("return_mean", "return_std", "success_rate", "landed_mean", "distance_m_mean"):
        assert metric in table
    with (run / "evaluation.csv").open() as f:
        rows = {r["policy"]: r for r in csv.DictReader(f)}
    assert set(rows) == {"trained PPO", "scripted pilot", "random"}
    for r in rows.values():
        assert r["seed"] == "5" and r["episodes"] == "6"
        assert 0.0 <= float(r["success_rate"]) <= 1.0
        assert np.isfinite(float(r["return_mean"])) and float(r["return_std"]) >= 0.0
    # the same seeded episodes for every policy, and deterministic: a rerun gives the same
    again = evaluate_cli.evaluate(run, 6, 5)
    assert {r["policy"]: r["return_mean"] for r in again} == pytest.approx(
        {p: float(r["return_mean"]) for p, r in rows.items()}, rel=1e-6
    )


def test_evaluate_writes_a_rerun_recording(run, tmp_path):
    pytest.importorskip("rerun")
    pytest.importorskip("fluidsim_envs.wrappers.rerun_logger")
    run = copy_run(run, tmp_path)
    rrd = tmp_path / "eval.rrd"
    assert evaluate_cli.main([str(run), "--episodes", "3", "--rerun", str(rrd)]) == 0
    assert rrd.is_file() and rrd.stat().st_size > 1000
    # the baselines still ran after the logger closed its env
    assert (run / "evaluation.csv").read_text().count("\n") == 4


def test_resume_continues_an_interrupted_run(run, tmp_path):
    run = copy_run(run, tmp_path)
    # interrupted after the first checkpoint: drop what came later
    for name in (
        "model.zip",
        "vecnormalize.pkl",
        "checkpoints/model_2048_steps.zip",
        "checkpoints/model_vecnormalize_2048_steps.pkl",
    ):
        (run / name).unlink()
    # in-process (the CLI's main, without the interpreter start-up of the tests above)
    assert train_cli.main(["--resume", str(run), "--no-progress-bar"]) == 0
    from stable_baselines3 import PPO

    assert PPO.load(run / "model.zip", device="cpu").num_timesteps == 2048
    assert (run / "checkpoints" / "model_2048_steps.zip").is_file()
    meta = yaml.safe_load((run / "run.yaml").read_text())
    (resumed,) = meta["resumes"]
    assert resumed["from"] == "model_1024_steps.zip" and resumed["timesteps"] == 1024
    assert meta["num_timesteps"] == 2048
    with (run / "eval" / "history.csv").open() as f:  # appended, not restarted
        steps = [int(r["timesteps"]) for r in csv.DictReader(f)]
    assert steps == [1024, 2048, 2048]
    monitor = (run / "monitor.csv").read_text()
    assert monitor.count("r,l,t,success") == 1  # one header, rows of both sessions


def test_resume_needs_a_checkpoint(run, tmp_path, capsys):
    run = copy_run(run, tmp_path)
    shutil.rmtree(run / "checkpoints")
    assert train_cli.main(["--resume", str(run)]) == 2
    assert "no checkpoint" in capsys.readouterr().err
    assert train_cli.main([str(CONFIG), "--resume", str(run)]) == 2
    assert "takes its config and folder from RUN" in capsys.readouterr().err


def test_train_cli_reports_a_misspelled_key_without_a_traceback(tmp_path):
    bad = tmp_path / "typo.yaml"
    bad.write_text(CONFIG.read_text().replace("n_envs:", "n_env:"))
    done = run_script("train.py", bad, cwd=tmp_path)
    assert done.returncode == 2
    assert "unknown key 'n_env' in the config; valid keys: env_id" in done.stderr
    assert "Traceback" not in done.stderr
    assert not (tmp_path / "runs").exists()


def test_train_cli_bad_inputs(tmp_path, capsys):
    assert train_cli.main([str(tmp_path / "missing.yaml")]) == 2
    assert "config file not found" in capsys.readouterr().err
    assert train_cli.main([str(CONFIG), "--set", "algorithm.learnin_rate=0.1"]) == 2
    assert "unknown key 'algorithm.learnin_rate'" in capsys.readouterr().err
    assert train_cli.main([]) == 2
    assert "a config file is required" in capsys.readouterr().err


def test_evaluate_refuses_a_model_of_another_algorithm(run, tmp_path, capsys):
    from stable_baselines3 import SAC

    from fluidsim_envs.wrappers.sb3 import make_sb3_vec_env

    run = copy_run(run, tmp_path)
    venv = make_sb3_vec_env("fluidsim/PaperAirplane-v0", 1)
    SAC("MlpPolicy", venv, buffer_size=10, device="cpu").save(run / "model.zip")
    assert evaluate_cli.main([str(run), "--episodes", "2"]) == 2
    err = capsys.readouterr().err
    assert "config.yaml says algorithm 'ppo' but model.zip holds a sac model" in err


def test_evaluate_refuses_a_model_of_another_env(run, tmp_path, capsys):
    run = copy_run(run, tmp_path)
    cfg = yaml.safe_load((run / "config.yaml").read_text())
    cfg["env_id"] = "fluidsim/SubmarineWake-v0"
    (run / "config.yaml").write_text(yaml.safe_dump(cfg))
    assert evaluate_cli.main([str(run), "--episodes", "2"]) == 2
    err = capsys.readouterr().err
    assert "trained on observations (15,)" in err and "SubmarineWake-v0 has (22,)" in err
    assert "belongs to another env" in err


@pytest.mark.parametrize("damage", ["garbage", "truncated", "no data"])
def test_evaluate_refuses_a_corrupt_model(run, tmp_path, capsys, damage):
    run = copy_run(run, tmp_path)
    model = run / "model.zip"
    if damage == "garbage":
        model.write_bytes(b"this is not a zip file")
    elif damage == "truncated":
        model.write_bytes(model.read_bytes()[:2000])
    else:
        with zipfile.ZipFile(model, "w") as z:
            z.writestr("readme.txt", "no model here")
    assert evaluate_cli.main([str(run), "--episodes", "2"]) == 2
    assert "model.zip: corrupt or not an SB3 model" in capsys.readouterr().err


def test_evaluate_bad_run_folders(run, tmp_path, capsys):
    assert evaluate_cli.main([str(tmp_path / "nowhere")]) == 2
    assert "run folder not found" in capsys.readouterr().err
    assert evaluate_cli.main([str(tmp_path)]) == 2
    assert "not a run folder (no config.yaml)" in capsys.readouterr().err
    run = copy_run(run, tmp_path)
    (run / "vecnormalize.pkl").unlink()
    assert evaluate_cli.main([str(run), "--episodes", "2"]) == 2
    assert "vecnormalize.pkl is missing" in capsys.readouterr().err
    (run / "model.zip").unlink()
    assert evaluate_cli.main([str(run)]) == 2
    assert "no model.zip" in capsys.readouterr().err


def test_sac_config_trains_and_evaluates(tmp_path):
    """The shipped SAC config builds its model (Q-network heads, no reward normalization)
    and a few hundred steps of it train and evaluate, in-process."""
    run = tmp_path / "sac"
    overrides = [
        "total_timesteps=200",
        "n_envs=2",
        "algorithm.learning_starts=100",
        "algorithm.buffer_size=1000",
        "eval.freq=0",
        "checkpoint.freq=0",
    ]
    sac_config = REPO / "configs" / "paper_airplane_sac.yaml"
    args = [str(sac_config), "--set", *overrides, "--run-dir", str(run), "--no-progress-bar"]
    assert train_cli.main(args) == 0
    from stable_baselines3 import SAC

    model = SAC.load(run / "model.zip", device="cpu")
    assert model.num_timesteps == 200 and model.policy.actor.latent_pi[0].out_features == 256
    rows = evaluate_cli.evaluate(run, 2, 0)
    assert [r["policy"] for r in rows] == ["trained SAC", "scripted pilot", "random"]
