"""The training CLI end to end on a tiny budget: fluidsim-train writes a self-describing run
folder (every env parameter, the best model with its statistics) and tells the user what it
does; fluidsim-evaluate evaluates the final or best model beside the baselines; --resume
continues an interrupted run; and bad input (a misspelled key, a missing file or extra, a run
folder that does not fit together, a corrupt model) is a clear error, not a traceback."""

from __future__ import annotations

import csv
import dataclasses
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from fluidsim_envs.physics.jit import target_cpu
from fluidsim_envs.rl import cli
from fluidsim_envs.rl import evaluate as evaluate_cli
from fluidsim_envs.rl import train as train_cli
from fluidsim_envs.rl.config import shipped_configs
from fluidsim_envs.rl.runs import MONITOR_STEPS

REPO = Path(__file__).resolve().parents[2]
CONFIG = shipped_configs()["paper_airplane_ppo"]
CONFIG_ENV = "fluidsim/PaperAirplane-v0"
# 2 PPO rollouts of 8 envs x 128 steps (2000 asked: rounded up to whole rollouts), evaluated
# (2 episodes) and checkpointed after each
TINY = [
    "total_timesteps=2000",
    "n_envs=8",
    "algorithm.n_steps=128",
    "algorithm.batch_size=256",
    "eval.freq=1024",
    "eval.n_episodes=2",
    "checkpoint.freq=1024",
    "torch_threads=1",
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
def trained(tmp_path_factory) -> tuple[Path, str]:
    """One tiny training run through the real CLI (the shipped config found by its name), and
    what it printed; shared by the tests below (read-only: tests that change a run work on a
    copy)."""
    where = tmp_path_factory.mktemp("train")
    run_dir = where / "run"
    args = ("paper_airplane_ppo", "--set", *TINY, "--run-dir", run_dir, "--no-progress-bar")
    done = run_script("train.py", *args, cwd=where)
    assert done.returncode == 0, done.stderr[-3000:]
    return run_dir, done.stdout


@pytest.fixture(scope="module")
def run(trained) -> Path:
    return trained[0]


def copy_run(run: Path, tmp_path: Path) -> Path:
    return Path(shutil.copytree(run, tmp_path / "run"))


def test_train_writes_a_self_describing_run_folder(run):
    for name in (
        "config.yaml",
        "run.yaml",
        "model.safetensors",
        "vecnormalize.safetensors",
        "monitor.csv",
        "learning_curve.png",
        "eval/history.csv",
        "eval/evaluations.npz",
        "best/best_model.safetensors",
        "best/vecnormalize.safetensors",  # the statistics the best model was evaluated with
    ):
        assert (run / name).is_file(), name
    assert sorted(p.name for p in (run / "checkpoints").iterdir()) == [
        "model_1024_steps.safetensors",
        "model_2048_steps.safetensors",
        "model_vecnormalize_1024_steps.safetensors",
        "model_vecnormalize_2048_steps.safetensors",
    ]
    assert any((run / "tb").rglob("events.out.tfevents.*"))
    # the resolved config: the file's values with the overrides applied, all keys present
    cfg = yaml.safe_load((run / "config.yaml").read_text())
    assert cfg["total_timesteps"] == 2000 and cfg["n_envs"] == 8
    assert cfg["algorithm"]["n_steps"] == 128 and cfg["algorithm"]["gae_lambda"] == 0.95
    assert cfg["policy"]["net_arch"] == {"pi": [64, 64], "vf": [64, 64]}
    # every env parameter, not only those the config changed: the run replays the same env
    from fluidsim_envs.scenes import SCENES
    from fluidsim_envs.scenes.base import make_params

    params_cls = SCENES["fluidsim/PaperAirplane-v0"].params_cls
    assert make_params(params_cls, cfg["env_kwargs"]) == params_cls()
    assert len(cfg["env_kwargs"]) == len(dataclasses.fields(params_cls))
    meta = yaml.safe_load((run / "run.yaml").read_text())
    assert meta["env_id"] == "fluidsim/PaperAirplane-v0" and meta["algorithm"] == "ppo"
    assert meta["env_version"] == 0 and meta["versions"]["fluidsim_envs"]
    assert meta["command"][:3] == ["fluidsim-train", "paper_airplane_ppo", "--set"]
    assert "total_timesteps=2000" in meta["command_line"]
    assert set(meta["git"]) == {"revision", "dirty"}
    assert meta["git"]["revision"] is None or len(meta["git"]["revision"]) == 40
    assert meta["seeds"]["model"] == 0 and meta["num_timesteps"] == 2048
    assert meta["seeds"]["train_stream"] == "training"  # never the evaluation's episodes
    assert "(training)" in meta["seeds"]["train_envs"]
    assert meta["versions"]["stable_baselines3"]
    assert meta["cpu"] == target_cpu()  # a seed's policy repeats to the bit on this CPU only
    (timing,) = meta["timing"]  # where the time went: the envs against the learner
    assert timing["env_steps"] == 2048 and 0.0 < timing["env_share"] < 1.0
    assert timing["train_env_s"] + timing["eval_env_s"] < timing["wall_s"]
    with (run / "eval" / "history.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert [int(r["timesteps"]) for r in rows] == [1024, 2048]
    assert all(np.isfinite(float(r["mean_return"])) for r in rows)
    assert all(0.0 <= float(r["success_rate"]) <= 1.0 for r in rows)
    monitor = (run / "monitor.csv").read_text().splitlines()
    # SB3's columns, then the run's timesteps at each episode's end (what a resume trims by)
    assert monitor[1] == "r,l,t,success,timesteps" and len(monitor) > 10
    assert meta["device"] == "cpu"  # where the model was (auto resolved)
    assert meta["torch_threads"] == 1 and cfg["torch_threads"] == 1  # set before the model
    best = yaml.safe_load((run / "best" / "best.yaml").read_text())
    assert best["mean_return"] == pytest.approx(max(float(r["mean_return"]) for r in rows))
    assert (run / "learning_curve.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_train_says_what_it_does(trained):
    """The plan (with the rounding to whole rollouts), a line per evaluation without the
    progress bar, and at the end the commands that use the run."""
    run, out = trained
    lines = out.splitlines()
    assert "2,048 env steps (2,000 asked, rounded up to whole rollouts of 128 x 8)" in lines[0]
    evals = [line for line in lines if line.startswith("eval @")]
    assert len(evals) == 2 and "1,024 steps" in evals[0] and "2,048 steps" in evals[1]
    assert all("success" in line and "env-steps/s" in line for line in evals)
    assert "new best" in evals[0]
    assert any(line.startswith("done: 2,048 env steps") for line in lines)
    assert f"fluidsim-evaluate {run}" in out and f"tensorboard --logdir {run}/tb" in out
    assert f"--rerun {run}/episodes.rrd" in out


def test_trained_success_reaches_tensorboard(run):
    """``is_success`` in the final info: SB3 logs rollout/success_rate from it."""
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    (events,) = (run / "tb").rglob("events.out.tfevents.*")
    acc = EventAccumulator(str(events))
    acc.Reload()
    assert "rollout/success_rate" in acc.Tags()["scalars"]


def test_train_warns_when_evaluation_or_checkpoints_never_happen(tmp_path, capsys):
    args = ["paper_airplane_ppo", "--set", *TINY, "eval.freq=4096", "checkpoint.freq=0"]
    args += ["--run-dir", str(tmp_path / "r"), "--no-progress-bar"]
    import torch

    threads = torch.get_num_threads()  # one per core unless set
    assert train_cli.main(args) == 0  # on TINY's torch_threads=1 ...
    assert torch.get_num_threads() == threads  # ... for the run only: the process's again
    out = capsys.readouterr().out
    assert "warning: no evaluation will run: eval.freq is 4,096 env steps" in out
    assert "checkpoint" not in out.split("warning")[-1].split("\n")[0]  # freq 0: asked for none
    assert "eval @" not in out and "--model best" not in out
    assert evaluate_cli.main([str(tmp_path / "r"), "--model", "best"]) == 2
    assert "the run never evaluated" in capsys.readouterr().err


def test_evaluate_the_best_model_with_its_own_statistics(run, tmp_path):
    """best/ holds the statistics of the step the best model comes from (its checkpoint's),
    and evaluating it needs no other."""
    from safetensors.numpy import load_file

    with (run / "eval" / "history.csv").open() as f:
        rows = list(csv.DictReader(f))
    best_step = max(rows, key=lambda r: float(r["mean_return"]))["timesteps"]
    saved = run / "checkpoints" / f"model_vecnormalize_{best_step}_steps.safetensors"
    counts = [load_file(p)["obs_rms/count"] for p in (run / "best/vecnormalize.safetensors", saved)]
    assert counts[0] == counts[1]
    run = copy_run(run, tmp_path)
    (run / "vecnormalize.safetensors").unlink()  # the final model's: the best one must not need it
    rows = evaluate_cli.evaluate(run, 4, 0, which="best", planner=False)
    assert rows[0]["policy"] == "trained PPO (best)"
    assert (run / "evaluation_best.csv").is_file() and not (run / "evaluation.csv").exists()


def test_a_missing_extra_says_which_pip_install_fixes_it(monkeypatch, capsys):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util,
        "find_spec",
        lambda name, *a: None if name == "stable_baselines3" else real(name, *a),
    )
    assert cli.train(["paper_airplane_ppo"]) == 2
    err = capsys.readouterr().err
    assert "fluidsim-train needs stable_baselines3" in err
    assert 'pip install "fluidsim-envs[train]"' in err


@pytest.mark.parametrize("module", ["train", "evaluate"])
def test_python_m_prints_help(module):
    done = subprocess.run(
        [sys.executable, "-m", f"fluidsim_envs.rl.{module}", "--help"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0 and done.stdout.startswith("usage: python -m fluidsim_envs.rl.")
    if module == "train":
        assert "shipped configs: boat_on_step_ppo, boat_on_step_v1_ppo," in done.stdout


def baselines() -> list[str]:
    """The baselines' rows without the planner."""
    return ["tuned pilot", "hand-set pilot", "random"]


def read_table(path: Path) -> tuple[list[str], dict[str, dict[str, str]]]:
    lines = path.read_text().splitlines()
    comments = [line for line in lines if line.startswith("#")]
    return comments, {r["policy"]: r for r in csv.DictReader(lines[len(comments) :])}


def test_evaluate_compares_the_model_with_the_baselines(run, tmp_path):
    run = copy_run(run, tmp_path)
    args = ("--episodes", 6, "--seed", 5, "--no-planner")
    done = run_script("evaluate.py", run, *args, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-3000:]
    table = done.stdout
    assert all(p in table for p in ("trained PPO", *baselines()))
    for metric in ("return_mean", "return_std", "success_rate", "landed_mean", "distance_m_mean"):
        assert metric in table
    assert "trained PPO: 6 episodes ..." in table and "trained PPO: done in " in table
    text = (run / "evaluation.csv").read_text()
    comments, rows = read_table(run / "evaluation.csv")
    assert comments[0].startswith("# command: fluidsim-evaluate") and "model: final at 2048" in text
    assert "# env overrides: none (the run's env_kwargs)" in comments
    assert list(rows) == ["trained PPO", *baselines()]
    for r in rows.values():
        assert r["seed"] == "5" and r["episodes"] == "6"
        assert 0.0 <= float(r["success_rate"]) <= 1.0
        assert np.isfinite(float(r["return_mean"])) and float(r["return_std"]) >= 0.0
        for c in ("return_mean", "success_rate", "distance_m_mean"):  # with its interval
            assert float(r[f"{c}_lo"]) <= float(r[c]) <= float(r[f"{c}_hi"])
    # the same seeded episodes for every policy, and deterministic: a rerun gives the same
    again = evaluate_cli.evaluate(run, 6, 5, planner=False)
    assert {r["policy"]: r["return_mean"] for r in again} == pytest.approx(
        {p: float(r["return_mean"]) for p, r in rows.items()}, rel=1e-6
    )
    assert (run / "evaluation.csv").read_text() == text  # intervals included


def test_evaluate_a_run_out_of_distribution(run, tmp_path, capsys):
    """--env sets env parameters on top of the run's, and --out keeps the table apart."""
    run = copy_run(run, tmp_path)
    out = tmp_path / "ood"
    args = [str(run), "--episodes", "3", "--no-planner", "--out", str(out)]
    assert evaluate_cli.main([*args, "--env", "max_episode_steps=7", "--env=dt=5e-3"]) == 0
    assert "3 episodes, seed 0, env overrides: max_episode_steps=7 dt=0.005" in (
        capsys.readouterr().out
    )
    assert not (run / "evaluation.csv").exists()
    comments, rows = read_table(out / "evaluation.csv")
    assert list(rows) == ["trained PPO", *baselines()]
    for r in rows.values():  # the override reached the env: every episode cut at 7 steps
        assert float(r["length_mean"]) == 7.0 and float(r["truncated_mean"]) == 1.0
    assert "--env max_episode_steps=7 --env dt=0.005" in comments[0]
    assert "# env overrides: max_episode_steps=7 dt=0.005 (on the run's env_kwargs)" in comments
    assert evaluate_cli.main([*args, "--env", "max_episode_stepz=7"]) == 2
    err = capsys.readouterr().err
    assert "--env: PaperAirplaneParams: unknown parameter(s) ['max_episode_stepz']" in err
    assert evaluate_cli.main([str(run), "--env-id", "fluidsim/PaperAirplane-v0"]) == 2
    assert "pass a run folder or --env-id, not both" in capsys.readouterr().err


def test_evaluate_writes_a_rerun_recording(run, tmp_path):
    pytest.importorskip("rerun")
    pytest.importorskip("fluidsim_envs.wrappers.rerun_logger")
    run = copy_run(run, tmp_path)
    rrd = tmp_path / "eval.rrd"
    args = [str(run), "--episodes", "3", "--rerun", str(rrd), "--no-planner"]
    assert evaluate_cli.main(args) == 0
    assert rrd.is_file() and rrd.stat().st_size > 1000
    # the baselines still ran after the logger closed its env
    _, rows = read_table(run / "evaluation.csv")
    assert list(rows) == ["trained PPO", *baselines()]


def monitor_rows(run: Path) -> list[dict[str, str]]:
    lines = (run / "monitor.csv").read_text().splitlines()
    assert sum(line.startswith("r,l,t,") for line in lines) == 1  # one header
    return list(csv.DictReader(lines[1:]))


def history_rows(run: Path) -> list[dict[str, str]]:
    with (run / "eval" / "history.csv").open() as f:
        return list(csv.DictReader(f))


def test_a_curriculum_trains_its_stages_in_order_and_says_so(tmp_path):
    """Episodes cut at 20 steps for the first rollout, then the run's own: the monitor's
    episodes before the switch are all short, after it some are longer; the evaluations fly
    the run's own episodes throughout; the plan and the switch are told; the run folder's
    config writes the stage's parameters down."""
    stage = "curriculum=[{timesteps: 1000, env_kwargs: {max_episode_steps: 20}}]"
    args = ("paper_airplane_ppo", "--set", *TINY, stage, "--run-dir", tmp_path / "run")
    done = run_script("train.py", *args, "--no-progress-bar", cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-3000:]
    lines = done.stdout.splitlines()
    assert "(a curriculum: episodes of max_episode_steps: 20 for 1,000 steps, then " in lines[0]
    assert "curriculum: from 1,024 timesteps on, the run's own episodes" in lines
    rows = monitor_rows(tmp_path / "run")
    before = [int(r["l"]) for r in rows if int(r[MONITOR_STEPS]) <= 1024]
    after = [int(r["l"]) for r in rows if int(r[MONITOR_STEPS]) > 1024]
    assert before and max(before) == 20 and max(after) > 20, (before, after)
    assert float(history_rows(tmp_path / "run")[0]["mean_length"]) > 20  # during the stage
    cfg = yaml.safe_load((tmp_path / "run" / "config.yaml").read_text())
    (written,) = cfg["curriculum"]
    assert written["timesteps"] == 1000 and written["env_kwargs"]["max_episode_steps"] == 20
    assert set(written["env_kwargs"]) == set(cfg["env_kwargs"])  # every parameter, resolved
    assert cfg["env_kwargs"]["max_episode_steps"] > 20


def test_resume_continues_an_interrupted_run(run, tmp_path, capsys):
    """A run killed after its first checkpoint while it wrote the second in place (left
    truncated) resumes from the first, saying which it skipped and why; its best model stays
    unless an evaluation beats it; its evaluation history and its episodes go on from the
    checkpoint, without the lost stretch and with times that never step back."""
    run = copy_run(run, tmp_path)
    for name in ("model.safetensors", "vecnormalize.safetensors"):
        (run / name).unlink()
    newest = run / "checkpoints" / "model_2048_steps.safetensors"
    newest.write_bytes(newest.read_bytes()[:2000])
    # the best score of an evaluation in the lost stretch, out of reach of the resumed run
    score = yaml.safe_load((run / "best" / "best.yaml").read_text())
    (run / "best" / "best.yaml").write_text(yaml.safe_dump({**score, "mean_return": 1e9}))
    best_model = (run / "best" / "best_model.safetensors").read_bytes()
    history = [r for r in history_rows(run) if int(r["timesteps"]) <= 1024]
    episodes = [r for r in monitor_rows(run) if int(r["timesteps"]) <= 1024]
    npz = np.load(run / "eval" / "evaluations.npz")["results"][:1]

    # in-process (the CLI's main, without the interpreter start-up of the tests above)
    assert train_cli.main(["--resume", str(run), "--no-progress-bar"]) == 0
    err = capsys.readouterr().err
    skipped = "--resume: skipped checkpoints/model_2048_steps.safetensors: model_2048_steps"
    assert f"{skipped}.safetensors does not load" in err
    from fluidsim_envs.rl.runs import saved_timesteps

    assert saved_timesteps(run / "model.safetensors") == 2048
    assert (run / "checkpoints" / "model_2048_steps.safetensors").is_file()
    meta = yaml.safe_load((run / "run.yaml").read_text())
    (resumed,) = meta["resumes"]
    assert resumed["from"] == "checkpoints/model_1024_steps.safetensors"
    assert resumed["timesteps"] == 1024
    assert "--resume" in resumed["command_line"] and resumed["device"] == "cpu"
    assert meta["num_timesteps"] == 2048
    # no worse evaluation replaced the best
    assert (run / "best" / "best_model.safetensors").read_bytes() == best_model
    assert yaml.safe_load((run / "best" / "best.yaml").read_text())["mean_return"] == 1e9
    # the lost stretch's evaluation (2048) dropped, then evaluated again: once each, the
    # evaluation before the checkpoint as it was
    rows = history_rows(run)
    assert [int(r["timesteps"]) for r in rows] == [1024, 2048] and rows[0] == history[0]
    saved = np.load(run / "eval" / "evaluations.npz")
    assert saved["timesteps"].tolist() == [1024, 2048]
    np.testing.assert_array_equal(saved["results"][:1], npz)
    # the episodes up to the checkpoint as they were, then the resumed run's, after it
    after = monitor_rows(run)
    assert after[: len(episodes)] == episodes
    assert all(int(r["timesteps"]) > 1024 for r in after[len(episodes) :])
    assert len(after) > len(episodes)
    times = [float(r["t"]) for r in after]
    assert times == sorted(times)
    steps = [int(r["timesteps"]) for r in after]
    assert steps == sorted(steps) and steps[-1] <= 2048


@pytest.mark.parametrize(
    ("damage", "why"),
    [
        ("empty", "model_2048_steps.safetensors does not load: not a saved model"),
        ("foreign", "model_2048_steps.safetensors does not load: not a saved model (no fluidsim"),
        ("statistics missing", "its statistics model_vecnormalize_2048_steps.safetensors are"),
        ("statistics truncated", "model_vecnormalize_2048_steps.safetensors does not load"),
        ("statistics as model", "model_2048_steps.safetensors does not load: holds a saved 'st"),
    ],
)
def test_resume_falls_back_to_the_newest_checkpoint_that_loads(run, tmp_path, damage, why):
    from safetensors.numpy import save_file

    run = copy_run(run, tmp_path)
    model, stats = (
        run / "checkpoints" / f"model{p}_2048_steps.safetensors" for p in ("", "_vecnormalize")
    )
    if damage == "empty":
        model.write_bytes(b"")
    elif damage == "foreign":  # a safetensors file of someone else's: no header of ours
        save_file({"w": np.zeros(3, np.float32)}, model)
    elif damage == "statistics missing":
        stats.unlink()
    elif damage == "statistics as model":
        shutil.copy(stats, model)
    else:
        stats.write_bytes(stats.read_bytes()[:100])
    (run / "model.safetensors").write_bytes(b"")  # the final model, damaged too: skipped first
    said = []
    restart = train_cli.restart_point(run, normalize=True, say=said.append)
    assert restart.steps == 1024 and restart.model.name == "model_1024_steps.safetensors"
    assert said[0].startswith("--resume: skipped model.safetensors: model.safetensors does not")
    assert said[1].startswith(f"--resume: skipped checkpoints/model_2048_steps.safetensors: {why}")


def test_a_damaged_best_model_is_set_aside_on_resume(run, tmp_path, capsys):
    """A truncated best model is noticed, moved aside with its score (kept for a look), and
    the resumed run's next evaluation makes a new best."""
    run = copy_run(run, tmp_path)
    model = run / "best" / "best_model.safetensors"
    model.write_bytes(model.read_bytes()[:1000])
    for name in ("model_2048_steps.safetensors", "model_vecnormalize_2048_steps.safetensors"):
        (run / "checkpoints" / name).unlink()
    (run / "model.safetensors").unlink()
    assert train_cli.main(["--resume", str(run), "--no-progress-bar"]) == 0
    err = capsys.readouterr().err
    assert "best_model.safetensors: not a saved model" in err and "set aside in" in err
    (aside,) = (run / "best").glob("damaged-*")
    assert sorted(p.name for p in aside.iterdir()) == [
        "best.yaml", "best_model.safetensors", "vecnormalize.safetensors"
    ]  # fmt: skip
    best = yaml.safe_load((run / "best" / "best.yaml").read_text())
    assert best["timesteps"] == 2048  # the resumed run's evaluation, the new best
    evaluate_cli.load_run(run, "best")


def test_a_full_disk_is_named_and_loses_nothing(tmp_path, capsys, monkeypatch):
    """The disk fills up while a checkpoint is written: one clear error that says how to go
    on, the checkpoint before it whole, and the run resumes from it once there is room."""
    import errno

    from fluidsim_envs.rl import saved

    real_save, calls = saved.save_model, []

    def save_model(model, path, *args):
        calls.append(path)
        if model.num_timesteps == 2048:
            open(path, "wb").write(b"half a mo")  # noqa: SIM115 (what a full disk leaves)
            raise RuntimeError("safetensors: write failed") from OSError(
                errno.ENOSPC, "No space left on device"
            )
        real_save(model, path, *args)

    monkeypatch.setattr(saved, "save_model", save_model)
    run = tmp_path / "run"
    args = ["paper_airplane_ppo", "--set", *TINY, "--run-dir", str(run), "--no-progress-bar"]
    assert train_cli.main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no space left on the disk" in err[0], err
    assert f"continue the run: fluidsim-train --resume {run}" in err[0]
    # the checkpoint at 2048 stops short of its model (its statistics were written first:
    # without the model they are no checkpoint); no temporary file is left
    assert sorted(p.name for p in (run / "checkpoints").iterdir()) == [
        "model_1024_steps.safetensors",
        "model_vecnormalize_1024_steps.safetensors",
        "model_vecnormalize_2048_steps.safetensors",
    ]
    monkeypatch.setattr(saved, "save_model", real_save)
    assert train_cli.main(["--resume", str(run), "--no-progress-bar"]) == 0


def test_a_run_folder_keeps_its_best_score(run, tmp_path, capsys):
    """best/best.yaml holds the best evaluation's score, which a resume reads back; a run of
    an older version, without it, takes the best of its whole evaluation history (before the
    resume trims it)."""
    from fluidsim_envs.rl.runs import BestModel, EvalLog

    run = copy_run(run, tmp_path)
    rows = history_rows(run)
    best_row = max(rows, key=lambda r: float(r["mean_return"]))
    best = BestModel.open(run / "best")
    assert best.score == pytest.approx(float(best_row["mean_return"]), rel=1e-6)
    assert best.record["timesteps"] == int(best_row["timesteps"])
    (run / "best" / "best.yaml").unlink()
    best = BestModel.open(run / "best", EvalLog.load(run / "eval"))
    assert best.score == pytest.approx(float(best_row["mean_return"]), rel=1e-12)
    assert "has no best.yaml: its score is taken as the best of" in capsys.readouterr().err
    assert yaml.safe_load((run / "best" / "best.yaml").read_text())["mean_return"] == best.score


def test_a_start_that_fails_leaves_nothing_that_blocks_a_retry(tmp_path, monkeypatch):
    """A new run whose model cannot be built removes the folders it created; a folder that
    was there before stays, without a config.yaml that would make it 'already a run'."""

    def broken(*args, **kwargs):
        raise RuntimeError("no model today")

    monkeypatch.setattr(train_cli, "_model", broken)
    run_dir = tmp_path / "new" / "run"
    args = ["paper_airplane_ppo", "--set", *TINY, "--no-progress-bar", "--run-dir", str(run_dir)]
    with pytest.raises(RuntimeError, match="no model today"):
        train_cli.main(args)
    assert not (tmp_path / "new").exists()
    run_dir.mkdir(parents=True)
    (run_dir / "notes.txt").write_text("mine")
    with pytest.raises(RuntimeError, match="no model today"):
        train_cli.main(args)
    assert (run_dir / "notes.txt").is_file() and not (run_dir / "config.yaml").exists()


def test_resume_a_finished_run_for_more_steps(run, tmp_path, capsys):
    """--resume with a larger total continues from the final model when it went furthest."""
    run = copy_run(run, tmp_path)
    for name in ("model_2048_steps.safetensors", "model_vecnormalize_2048_steps.safetensors"):
        (run / "checkpoints" / name).unlink()
    args = ["--resume", str(run), "--set", "total_timesteps=3072", "--no-progress-bar"]
    assert train_cli.main(args) == 0
    meta = yaml.safe_load((run / "run.yaml").read_text())
    assert meta["resumes"][-1]["from"] == "model.safetensors"
    assert meta["resumes"][-1]["timesteps"] == 2048
    assert meta["num_timesteps"] == 3072
    assert train_cli.main(["--resume", str(run), "--no-progress-bar"]) == 0
    out = capsys.readouterr().out
    assert "already at 3,072 timesteps; nothing to train" in out and "warning" not in out


def test_resume_needs_a_checkpoint(run, tmp_path, capsys):
    run = copy_run(run, tmp_path)
    shutil.rmtree(run / "checkpoints")
    (run / "model.safetensors").unlink()  # an interrupted run that never checkpointed
    assert train_cli.main(["--resume", str(run)]) == 2
    assert "nothing saved to resume from" in capsys.readouterr().err
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
    assert "config not found" in capsys.readouterr().err
    assert train_cli.main([str(CONFIG), "--set", "algorithm.learnin_rate=0.1"]) == 2
    assert "unknown key 'algorithm.learnin_rate'" in capsys.readouterr().err
    assert train_cli.main([]) == 2
    assert "a config is required" in capsys.readouterr().err
    assert train_cli.main(["paper_airplane_pppo"]) == 2
    err = capsys.readouterr().err
    assert "'paper_airplane_pppo' is neither a file nor a shipped config" in err
    assert "paper_airplane_ppo" in err.split("shipped config")[1]


def test_evaluate_refuses_a_model_of_another_algorithm(run, tmp_path, capsys):
    from stable_baselines3 import SAC

    from fluidsim_envs.rl import saved
    from fluidsim_envs.wrappers.sb3 import make_sb3_vec_env

    run = copy_run(run, tmp_path)
    venv = make_sb3_vec_env("fluidsim/PaperAirplane-v0", 1)
    sac = SAC("MlpPolicy", venv, buffer_size=10, device="cpu")
    saved.save_model(sac, run / "model.safetensors")
    assert evaluate_cli.main([str(run), "--episodes", "2"]) == 2
    err = capsys.readouterr().err
    assert "config.yaml says algorithm 'ppo' but the file holds a sac model" in err


def test_evaluate_refuses_a_model_of_another_env(run, tmp_path, capsys):
    run = copy_run(run, tmp_path)
    cfg = yaml.safe_load((run / "config.yaml").read_text())
    cfg["env_id"], cfg["env_kwargs"] = "fluidsim/SubmarineWake-v0", {}
    (run / "config.yaml").write_text(yaml.safe_dump(cfg))
    assert evaluate_cli.main([str(run), "--episodes", "2"]) == 2
    err = capsys.readouterr().err
    assert "trained on observations (15,)" in err and "SubmarineWake-v0 has (22,)" in err
    assert "belongs to another env" in err


@pytest.mark.parametrize(
    ("damage", "why"),
    [
        ("garbage", "not a saved model (SafetensorError"),
        ("truncated", "not a saved model (SafetensorError"),
        ("no header", "not a saved model (no fluidsim-envs header)"),
        ("other shapes", "does not fit the config's policy"),
    ],
)
def test_evaluate_refuses_a_corrupt_model(run, tmp_path, capsys, damage, why):
    import json

    from safetensors.numpy import load_file, save_file

    run = copy_run(run, tmp_path)
    model = run / "model.safetensors"
    if damage == "garbage":
        model.write_bytes(b"this is not a safetensors file")
    elif damage == "truncated":
        model.write_bytes(model.read_bytes()[:-2000])
    elif damage == "no header":
        save_file(load_file(model), model)
    else:  # the header of the model, the weights of another size
        from safetensors import safe_open

        with safe_open(model, "numpy") as f:
            metadata = f.metadata()
        arrays = {k: np.zeros((3,), v.dtype) for k, v in load_file(model).items()}
        save_file(arrays, model, metadata=metadata)
        assert json.loads(metadata["fluidsim"])["kind"] == "model"
    assert evaluate_cli.main([str(run), "--episodes", "2"]) == 2
    assert f"model.safetensors: {why}" in capsys.readouterr().err


def test_evaluate_bad_run_folders(run, tmp_path, capsys):
    assert evaluate_cli.main([str(tmp_path / "nowhere")]) == 2
    assert "run folder not found" in capsys.readouterr().err
    assert evaluate_cli.main([str(tmp_path)]) == 2
    assert "not a run folder (no config.yaml)" in capsys.readouterr().err
    run = copy_run(run, tmp_path)
    (run / "vecnormalize.safetensors").unlink()
    assert evaluate_cli.main([str(run), "--episodes", "2"]) == 2
    assert "vecnormalize.safetensors is missing" in capsys.readouterr().err
    (run / "model.safetensors").unlink()
    assert evaluate_cli.main([str(run)]) == 2
    assert "no model.safetensors" in capsys.readouterr().err
    assert evaluate_cli.main([str(run / "config.yaml")]) == 2
    assert "config.yaml: is a file, not a run folder" in capsys.readouterr().err


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
    args = ["paper_airplane_sac", "--set", *overrides, "--run-dir", str(run), "--no-progress-bar"]
    assert train_cli.main(args) == 0
    cfg, policy = evaluate_cli.load_run(run)
    assert cfg.algorithm.name == "sac" and policy.actor.latent_pi[0].out_features == 256
    from fluidsim_envs.rl.runs import saved_timesteps

    assert saved_timesteps(run / "model.safetensors") == 200
    rows = evaluate_cli.evaluate(run, 2, 0, planner=False)
    assert [r["policy"] for r in rows] == ["trained SAC", *baselines()]


@pytest.mark.parametrize("normalize", [True, False])
def test_sac_goes_through_a_curriculum(tmp_path, capsys, normalize):
    """Off-policy, with and without VecNormalize: the switch gives SAC the new episodes'
    first observations (the replay buffer's unnormalized copy too) and training goes on."""
    run = tmp_path / "sac"
    overrides = [
        "total_timesteps=120",
        "n_envs=2",
        "algorithm.learning_starts=40",
        "algorithm.buffer_size=1000",
        "eval.freq=0",
        "checkpoint.freq=0",
        f"normalize.enabled={str(normalize).lower()}",
        "curriculum=[{timesteps: 60, env_kwargs: {max_episode_steps: 5}}]",
    ]
    args = ["paper_airplane_sac", "--set", *overrides, "--run-dir", str(run), "--no-progress-bar"]
    assert train_cli.main(args) == 0
    assert "curriculum: from 60 timesteps on, the run's own episodes" in capsys.readouterr().out
    lengths = [int(r["l"]) for r in monitor_rows(run)]
    assert lengths and max(lengths) == 5  # after the switch: episodes still in flight


def test_a_stage_with_other_spaces_is_refused_before_training(tmp_path, capsys):
    """A stage whose env observes otherwise (no probe columns) cannot feed the policy: an
    error naming the stage, and the failed start leaves no folder behind."""
    stage = "curriculum=[{timesteps: 1000, env_kwargs: {observe_samples: false}}]"
    run = tmp_path / "run"
    args = ["paper_airplane_v1_ppo", "--set", *TINY, "levels=[]", stage, "--run-dir", str(run)]
    assert train_cli.main([*args, "--no-progress-bar"]) == 2
    assert "curriculum[0]: its env's (observation, action) spaces" in capsys.readouterr().err
    assert not run.exists()
