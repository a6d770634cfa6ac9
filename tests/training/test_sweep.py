"""fluidsim-sweep: a two-trial search on an embedded local Ray at a tiny budget, end to end
(run folders as fluidsim-train writes them, the results table, a resume that finds nothing
left to run), and each bad input a clear error that names it, before Ray starts."""

from __future__ import annotations

import csv
import socket
from pathlib import Path

import pytest
import yaml

from fluidsim_envs.rl import sweep as sweep_cli
from fluidsim_envs.rl.config import ConfigError, config_from_dict, config_to_dict, load_config
from fluidsim_envs.rl.space import apply_params, base_point, check_space, find_space, parse_space

# 4 PPO rollouts of 8 envs x 32 steps, each evaluated (2 episodes) and checkpointed
TINY = [
    "n_envs=8",
    "algorithm.n_steps=32",
    "algorithm.batch_size=64",
    "total_timesteps=1024",
    "eval.freq=256",
    "eval.n_episodes=2",
    "checkpoint.freq=256",
]
SPACE = {
    "algorithm.learning_rate": {"loguniform": [1.0e-4, 1.0e-3]},
    "algorithm.n_epochs": {"int": [2, 6]},
}


def base() -> dict:
    return config_to_dict(load_config("paper_airplane_ppo", TINY))


def write_space(folder: Path, space) -> Path:
    path = folder / "space.yaml"
    path.write_text(yaml.safe_dump(space))
    return path


# --------------------------------------------------------------------------------------------
# the search space


def test_a_space_maps_each_kind_to_its_tune_domain():
    space = parse_space(
        {
            **SPACE,
            "algorithm.batch_size": {"choice": [64, 128]},
            "algorithm.gamma": {"uniform": [0.9, 0.99]},
        },
        "s",
    )
    check_space(space, base(), "s")
    domains = {k: d.tune_domain() for k, d in space.items()}
    assert domains["algorithm.n_epochs"].upper == 7  # Tune's upper end is excluded: 6 included
    assert domains["algorithm.learning_rate"].lower == 1.0e-4
    assert list(domains["algorithm.batch_size"].categories) == [64, 128]
    raw = apply_params(base(), {"algorithm.n_epochs": 3, "algorithm.gamma": 0.95})
    assert raw["algorithm"]["n_epochs"] == 3 and raw["algorithm"]["gamma"] == 0.95


@pytest.mark.parametrize("name", ["ppo", "sac"])
def test_the_shipped_spaces_fit_their_shipped_configs(name):
    """Each shipped space's every value on each shipped config of its algorithm, and every
    combination where keys are tied (PPO's batch within its rollout)."""
    import itertools

    from fluidsim_envs.rl.config import shipped_configs

    path = find_space(name)
    space = parse_space(yaml.safe_load(path.read_text()), str(path))
    configs = [c for c in shipped_configs() if c.endswith(f"_{name}")]
    assert configs
    for config in configs:
        raw = config_to_dict(load_config(config))
        check_space(space, raw, str(path))
        choices = [d for d in space.values() if d.kind == "choice"]
        for values in itertools.product(*(d.values for d in choices)):
            picked = {d.key: v for d, v in zip(choices, values, strict=True)}
            config_from_dict(apply_params(raw, picked))


def test_the_base_point_names_what_the_config_leaves_unset():
    space = parse_space(
        {
            "env_kwargs.wind_speed_mps": {"uniform": [0.0, 3.0]},
            "algorithm.target_kl": {"choice": [0.01, 0.05]},
        },
        "s",
    )
    point, notes = base_point(space, base())
    assert point == {"env_kwargs.wind_speed_mps": 0.0, "algorithm.target_kl": 0.01}
    assert all("the config does not set it" in n for n in notes) and len(notes) == 2


def test_the_base_point_is_the_config_where_the_space_can_draw_it():
    space = parse_space({**SPACE, "algorithm.batch_size": {"choice": [32, 64]}}, "s")
    point, notes = base_point(space, base())
    assert point == {
        "algorithm.learning_rate": 3.0e-4,
        "algorithm.n_epochs": 6,
        "algorithm.batch_size": 64,
    }
    assert notes == [
        "algorithm.n_epochs: the config's 10 is outside algorithm.n_epochs ~ int[2, 6]; 6"
    ]


@pytest.mark.parametrize(
    ("space", "named"),
    [
        ({"algorithm.learnin_rate": {"uniform": [0.1, 0.2]}}, "learnin_rate"),
        ({"env_kwargs.no_such_knob": {"uniform": [0.1, 0.2]}}, "no_such_knob"),
        ({"algorithm.learning_rate": {"loguniform": [1.0e-3, 1.0e-3]}}, "empty or a single value"),
        ({"algorithm.n_epochs": {"int": [6, 2]}}, "[6, 2] is empty"),
        ({"algorithm.n_epochs": {"int": [2.5, 6]}}, "integers"),
        ({"algorithm.learning_rate": {"loguniform": [0.0, 1.0e-3]}}, "0 < low"),
        ({"algorithm.batch_size": {"choice": []}}, "non-empty list"),
        ({"algorithm.gamma": {"normal": [0.9, 0.1]}}, "expected one distribution"),
        ({"algorithm.gamma": [0.9, 0.99]}, "expected one distribution"),
        ({"seed": {"int": [0, 9]}}, "--seeds"),
        ({"algorithm.gamma": {"uniform": [0.9, 1.5]}}, "1.5"),  # an end the config refuses
        ({}, "maps config keys"),
    ],
)
def test_a_bad_space_is_an_error_that_names_it(space, named):
    with pytest.raises(ConfigError, match="space.yaml") as e:
        check_space(parse_space(space, "space.yaml"), base(), "space.yaml")
    assert named in str(e.value)


# --------------------------------------------------------------------------------------------
# bad input on the command line: refused before Ray starts


def closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]  # closed again on leaving: nothing answers there


@pytest.mark.parametrize(
    ("args", "named"),
    [
        (["--seeds", "0"], "--seeds 0"),
        (["--trials", "3"], "--trials 3: only with --search"),
        (["--search", "missing.yaml"], "--search missing.yaml: file not found, nor a shipped"),
        (["--cpus-per-trial", "0"], "--cpus-per-trial 0"),
        (["--torch-threads", "2"], "--torch-threads 2: from 1 to --cpus-per-trial (1)"),
        (["--grace", "999999"], "--grace 999999.0: ASHA's first rung must be in (0, total"),
        (["--target", "5"], "--target 5.0 needs --wall-budget-s"),
        (["--wall-budget-s", "60"], "--wall-budget-s 60.0: only with --target"),
        (["--address", "nohostport"], "expected HOST:PORT"),
        (["--set", "eval.freq=0"], "eval.freq is 0"),
        (["--target", "nan", "--wall-budget-s", "60"], "--target nan: must be a finite number"),
        (["--target", "5", "--wall-budget-s", "inf"], "--wall-budget-s inf: must be a finite"),
        (["--grace", "nan"], "--grace nan: ASHA's first rung must be in (0, total_timesteps"),
    ],
)
def test_bad_arguments_are_errors_that_name_them(tmp_path, capsys, monkeypatch, args, named):
    monkeypatch.chdir(tmp_path)
    assert sweep_cli.main(["paper_airplane_ppo", "--set", *TINY, *args]) == 2
    assert named in capsys.readouterr().err
    assert not (tmp_path / "sweeps").exists()


def test_an_unreachable_address_is_an_error_that_names_it(tmp_path, capsys):
    address = f"127.0.0.1:{closed_port()}"
    argv = ["paper_airplane_ppo", "--address", address, "--sweep-dir", str(tmp_path / "s")]
    assert sweep_cli.main(argv) == 2
    err = capsys.readouterr().err
    assert f"--address {address}: nothing answers" in err and "ray start --head" in err


def test_resume_needs_a_sweep_folder_and_takes_its_settings_from_it(tmp_path, capsys):
    assert sweep_cli.main(["--resume", str(tmp_path)]) == 2
    assert "not a sweep folder (no sweep.yaml)" in capsys.readouterr().err
    assert sweep_cli.main(["--resume", str(tmp_path), "--seeds", "3", "--trials", "2"]) == 2
    err = capsys.readouterr().err
    assert "takes its settings from DIR/sweep.yaml, not from --seeds, --trials" in err
    (tmp_path / "sweep.yaml").write_text("folder: x\nno_such_setting: 1\n")
    assert sweep_cli.main(["--resume", str(tmp_path)]) == 2
    assert "sweep.yaml: not a sweep this version can resume" in capsys.readouterr().err


# --------------------------------------------------------------------------------------------
# a real sweep on local Ray


@pytest.fixture(scope="module")
def swept(tmp_path_factory) -> Path:
    where = tmp_path_factory.mktemp("sweep")
    space = write_space(where, SPACE)
    folder = where / "s"
    argv = ["paper_airplane_ppo", "--set", *TINY, "--search", str(space), "--trials", "2"]
    assert sweep_cli.main([*argv, "--sweep-dir", str(folder)]) == 0
    return folder


def table(folder: Path) -> list[dict]:
    with (folder / "results.csv").open() as f:
        return list(csv.DictReader(f))


def test_a_two_trial_search_writes_run_folders_and_one_table(swept):
    rows = table(swept)
    assert len(rows) == 2
    for row in rows:
        assert row["status"] in ("finished", "stopped early"), row
        run = swept / row["run_dir"]
        assert (run / "config.yaml").is_file() and (run / "eval" / "history.csv").is_file()
        cfg = yaml.safe_load((run / "config.yaml").read_text())
        # the sampled values are what the run trained with, on the trial's cores
        assert cfg["algorithm"]["learning_rate"] == pytest.approx(
            float(row["algorithm.learning_rate"])
        )
        assert cfg["algorithm"]["n_epochs"] == int(row["algorithm.n_epochs"])
        assert 1.0e-4 <= cfg["algorithm"]["learning_rate"] <= 1.0e-3
        assert cfg["torch_threads"] == 1
        assert float(row["peak_rss_mb"]) > 0 and float(row["wall_s"]) > 0
        if row["status"] == "finished":
            assert int(row["timesteps"]) == 1024 and (run / "model.safetensors").is_file()
    # the first trial is the config itself: learning rate 3e-4, its n_epochs of 10 outside
    # the space, so the nearest the space draws, 6
    assert {(float(r["algorithm.learning_rate"]), int(r["algorithm.n_epochs"])) for r in rows} >= {
        (3.0e-4, 6)
    }
    best = [float(r["best_return"]) for r in rows]
    assert best == sorted(best, reverse=True)
    md = (swept / "results.md").read_text()
    assert "algorithm.learning_rate ~ loguniform[0.0001, 0.001]" in md
    assert md.count("\n| ") == 3  # the header and two trials


def test_a_finished_sweep_resumes_to_nothing_left(swept, capsys):
    before = table(swept)
    assert sweep_cli.main(["--resume", str(swept)]) == 0
    assert "resuming" in capsys.readouterr().out
    assert table(swept) == before


def test_seeds_of_one_sampled_config_race_to_a_target(tmp_path):
    """--search with --seeds: Repeater gives each sampled config every seed (the same values);
    --target ends each trial at its first evaluation at or above it, and ranks by time."""
    space = write_space(tmp_path, SPACE)
    folder = tmp_path / "s"
    argv = ["paper_airplane_ppo", "--set", *TINY, "--search", str(space), "--trials", "1"]
    argv += ["--seeds", "2", "--target", "-1000", "--wall-budget-s", "120"]
    assert sweep_cli.main([*argv, "--cpus-per-trial", "2", "--sweep-dir", str(folder)]) == 0
    rows = table(folder)
    assert sorted(int(r["seed"]) for r in rows) == [0, 1]
    assert len({(r["algorithm.learning_rate"], r["algorithm.n_epochs"]) for r in rows}) == 1
    for row in rows:
        assert row["status"] == "reached target" and int(row["timesteps"]) == 256
        assert float(row["time_to_target_s"]) == float(row["wall_s"]) > 0
        # the trial ended itself and its run finished before Tune heard the last evaluation
        assert (folder / row["run_dir"] / "model.safetensors").is_file()
        # two CPUs: numba's threads take them, torch keeps one (docs/training.md)
        run_config = yaml.safe_load((folder / row["run_dir"] / "config.yaml").read_text())
        assert run_config["torch_threads"] == 1
    times = [float(r["time_to_target_s"]) for r in rows]
    assert times == sorted(times)


@pytest.mark.parametrize(
    ("steps", "model", "status"),
    [
        (2_995_200, True, "finished"),  # the last evaluation before the last rollouts
        (3_000_000, False, "finished"),
        (1_000_000, False, "stopped early"),  # ASHA cut it: no final model
    ],
)
def test_a_trial_that_ended_by_itself_is_finished(tmp_path, steps, model, status):
    from types import SimpleNamespace

    from fluidsim_envs.rl.sweep_results import SweepProgress, read_status

    base = {**config_to_dict(load_config("paper_airplane_v1_ppo")), "total_timesteps": 3_000_000}
    run_dir = tmp_path / "runs" / "t0"
    run_dir.mkdir(parents=True)
    if model:
        (run_dir / "model.safetensors").write_bytes(b"")
    said = []
    progress = SweepProgress(sweep_cli.Sweep(folder=str(tmp_path), base=base), said.append)
    last = {"timesteps": steps, "run_dir": str(run_dir), "best_return": 1.0, "wall_s": 9.0}
    progress.on_trial_complete(0, [], SimpleNamespace(trial_id="t0", last_result=last))
    assert read_status(tmp_path)["t0"]["status"] == status
    assert said == [f"trial t0 {status} at {steps:,} steps"]
