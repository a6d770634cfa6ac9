"""fluidsim-evaluate without a run: the baselines alone (--env-id), the bootstrap intervals
beside every mean, --env overrides that reach the env, the planner's and the hand-set
pilot's rows, and argument errors that say what to pass. Short episodes throughout (each
scene's ``short_episodes``); the run-folder side is in test_cli.py."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from benchmarks import report
from fluidsim_envs.physics.jit import target_cpu
from fluidsim_envs.rl import evaluate as evaluate_cli
from fluidsim_envs.scenes import SCENES, Scene

BOAT = "fluidsim/BoatOnStep-v0"


def short(env_id: str) -> list[str]:
    """--env arguments for the scene's short episodes."""
    return [
        f"--env={item}"
        for item in evaluate_cli.format_overrides(evaluate_cli.find_scene(env_id).short_episodes)
    ]


def baselines(tmp_path, *args, env_id=BOAT, episodes=4, seed=1) -> int:
    argv = ["--env-id", env_id, "--episodes", str(episodes), "--seed", str(seed)]
    return evaluate_cli.main([*argv, "--out", str(tmp_path), *short(env_id), *args])


def read_table(path) -> tuple[list[str], dict[str, dict[str, str]]]:
    lines = path.read_text().splitlines()
    comments = [line for line in lines if line.startswith("#")]
    rows = csv.DictReader(line for line in lines if not line.startswith("#"))
    return comments, {r["policy"]: r for r in rows}


def expected_rows(planner: bool, version: int = 0) -> list[str]:
    """The baselines' rows, in order (on a v1 env, the v0-tuned pilot too)."""
    rows = [evaluate_cli.PLANNER] if planner else []
    rows += [evaluate_cli.TUNED_PILOT] + ([evaluate_cli.V0_PILOT] if version else [])
    return [*rows, evaluate_cli.HAND_PILOT, evaluate_cli.RANDOM]


def test_the_baselines_alone(tmp_path, capsys):
    assert baselines(tmp_path, "--no-planner") == 0
    out = capsys.readouterr().out
    comments, rows = read_table(tmp_path / "evaluation.csv")
    assert list(rows) == expected_rows(planner=False)
    assert comments[0].startswith(f"# command: fluidsim-evaluate --env-id {BOAT} --episodes 4")
    assert any(c.startswith(f"# baselines only: {BOAT}, git ") for c in comments)
    assert any("skipped: planner (--no-planner)" in c for c in comments)
    # the CPU the kernels were compiled for: the zoo's check holds a table to the bit on it
    assert any(c.startswith(f"# cpu: {target_cpu()} (the kernels' target") for c in comments)
    for policy in rows:  # what it evaluates and how long it took
        assert f"{policy}: 4 episodes ..." in out and f"{policy}: done in " in out
    for r in rows.values():
        assert r["seed"] == "1" and r["episodes"] == "4"
        assert np.isfinite(float(r["return_mean"])) and float(r["return_std"]) >= 0.0
    assert f"written: {tmp_path / 'evaluation.csv'}" in out


def test_every_mean_has_an_interval_that_contains_it(tmp_path, capsys):
    assert baselines(tmp_path, "--no-planner", episodes=8) == 0
    out = capsys.readouterr().out
    _, rows = read_table(tmp_path / "evaluation.csv")
    columns = list(next(iter(rows.values())))
    means = [c for c in columns if c.endswith("_mean") or c == "success_rate"]
    assert {"return_mean", "success_rate", "length_mean"} <= set(means)
    for c in means:  # beside it: C, C_lo, C_hi
        assert columns[columns.index(c) + 1 : columns.index(c) + 3] == [f"{c}_lo", f"{c}_hi"]
    for r in rows.values():
        for c in means:
            lo, mean, hi = (float(r[k]) for k in (f"{c}_lo", c, f"{c}_hi"))
            assert lo <= mean <= hi, (r["policy"], c)
    # the returns differ between episodes: a real interval; the printed table shows it
    r = rows[evaluate_cli.TUNED_PILOT]
    assert float(r["return_mean_lo"]) < float(r["return_mean"]) < float(r["return_mean_hi"])
    mean, lo, hi = (float(r[k]) for k in ("return_mean", "return_mean_lo", "return_mean_hi"))
    assert f"{mean:.4g} [{lo:.4g}, {hi:.4g}]" in out


def test_the_table_is_reproducible(tmp_path):
    assert baselines(tmp_path, "--no-planner", episodes=6, seed=3) == 0
    first = (tmp_path / "evaluation.csv").read_text()
    assert baselines(tmp_path, "--no-planner", episodes=6, seed=3) == 0
    assert (tmp_path / "evaluation.csv").read_text() == first


def test_mean_interval():
    assert evaluate_cli.mean_interval([2.0] * 5, seed=0) == (2.0, 2.0)  # all equal
    assert evaluate_cli.mean_interval([True] * 5, seed=0) == (1.0, 1.0)
    assert evaluate_cli.mean_interval([3.0], seed=0) == (3.0, 3.0)  # one episode
    lo, hi = evaluate_cli.mean_interval([1.0, np.nan], seed=0)
    assert np.isnan(lo) and np.isnan(hi)  # a non-finite value: the mean's NaN, no warning
    x = np.random.default_rng(0).exponential(size=200)
    lo, hi = evaluate_cli.mean_interval(x, seed=7)
    assert lo < x.mean() < hi and (lo, hi) == evaluate_cli.mean_interval(x, seed=7)
    assert (lo, hi) != evaluate_cli.mean_interval(x, seed=8)
    lo, hi = evaluate_cli.mean_interval(np.r_[np.zeros(255), 1.0], seed=0)  # one success
    assert lo == 0.0 < 1 / 256 < hi < 0.05


def test_an_env_override_reaches_the_env(tmp_path):
    for steps in (5, 9):
        out = tmp_path / str(steps)
        assert baselines(out, "--no-planner", f"--env=max_episode_steps={steps}") == 0
        comments, rows = read_table(out / "evaluation.csv")
        for r in rows.values():  # every episode cut at the override's horizon
            assert float(r["length_mean"]) == steps and float(r["truncated_mean"]) == 1.0
        assert f"--env max_episode_steps={steps}" in comments[0]
        assert any(
            c.startswith("# env overrides: ") and f"max_episode_steps={steps}" in c
            for c in comments
        )


@pytest.mark.parametrize(
    ("override", "named"),
    [
        ("max_episode_stepz=5", "unknown parameter(s) ['max_episode_stepz']"),
        ("integrator=rk5", "integrator must be one of"),
        ("max_episode_steps=[1,2]", "max_episode_steps"),
        ("max_episode_steps", "--env expects KEY=VALUE, got 'max_episode_steps'"),
        ("dt=[", "--env 'dt=[': the value: not valid YAML"),
    ],
)
def test_a_bad_override_is_an_error_that_names_it(tmp_path, capsys, override, named):
    assert baselines(tmp_path / "out", "--env", override) == 2
    err = capsys.readouterr().err
    assert err.startswith("fluidsim-evaluate: error: ") and named in err
    assert "Traceback" not in err and not (tmp_path / "out").exists()


def test_override_values_are_read_as_yaml():
    env = evaluate_cli.parse_env_overrides(
        ["wind_speed_mps=[0,3]", "integrator=rk4", "dt=0.005", "substeps=2", "dt=5e-3"]
    )
    assert env == {"wind_speed_mps": [0, 3], "integrator": "rk4", "dt": 0.005, "substeps": 2}
    assert evaluate_cli.parse_env_overrides(evaluate_cli.format_overrides(env)) == env
    kwargs = evaluate_cli.env_kwargs_with(
        "fluidsim/PaperAirplane-v0", {"dt": 0.01, "substeps": 4}, env
    )
    assert kwargs["dt"] == 0.005 and kwargs["wind_speed_mps"] == [0, 3]


def test_the_planner_and_hand_pilot_rows(tmp_path, monkeypatch, capsys):
    """The planner gets the very env the episodes run in and the --planner-* settings; the
    rows come in their order. (A stand-in planner: the scene's pilot flies.)"""
    made, given = [], {}
    make_venv = evaluate_cli._make_venv

    def recording_make_venv(*args):
        made.append(make_venv(*args))
        return made[-1]

    def planner(scene, venv, **kwargs):
        given.update(kwargs, venv=venv)
        return scene.pilot(venv)

    monkeypatch.setattr(evaluate_cli, "_make_venv", recording_make_venv)
    monkeypatch.setattr(Scene, "planner", planner)
    args = ("--planner-samples", "3", "--planner-horizon", "2")
    assert baselines(tmp_path, *args) == 0
    assert len(made) == 1 and given == {"samples": 3, "horizon": 2, "venv": made[0]}
    comments, rows = read_table(tmp_path / "evaluation.csv")
    assert list(rows) == ["planner", "tuned pilot", "hand-set pilot", "random"]
    assert rows["planner"]["return_mean"] == rows["tuned pilot"]["return_mean"]
    assert "--planner-samples 3 --planner-horizon 2" in comments[0]
    assert "planner: done in " in capsys.readouterr().out


def test_a_planner_budget_it_refuses_is_an_error(tmp_path, monkeypatch, capsys):
    def planner(scene, venv, samples=32, horizon=30):
        raise ValueError(f"planner: elites (4) must not exceed samples ({samples})")

    monkeypatch.setattr(Scene, "planner", planner)
    assert baselines(tmp_path, "--planner-samples", "2") == 2
    err = capsys.readouterr().err
    assert "error: planner: planner: elites (4) must not exceed samples (2)" in err


@pytest.mark.parametrize("env_id", list(SCENES))
def test_the_scenes_planner_flies(tmp_path, env_id):
    """The real planner, cheaply (2 short episodes, few samples)."""
    args = ("--planner-samples", "4", "--planner-horizon", "3", "--env=max_episode_steps=8")
    assert baselines(tmp_path, *args, env_id=env_id, episodes=2) == 0
    _, rows = read_table(tmp_path / "evaluation.csv")
    version = int(env_id.rsplit("-v", 1)[1])
    assert list(rows) == expected_rows(planner=True, version=version)
    assert 1.0 <= float(rows[evaluate_cli.PLANNER]["length_mean"]) <= 8.0


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ([], "pass a run folder (its model beside the baselines) or --env-id ID --out DIR"),
        (["runs/x", "--env-id", BOAT], "pass a run folder or --env-id, not both"),
        (["--env-id", BOAT], "--env-id needs --out DIR"),
        (["--env-id", BOAT, "--out", "{tmp}", "--model", "best"], "--model needs a run folder"),
        (["--env-id", BOAT, "--out", "{tmp}", "--rerun", "x.rrd"], "--rerun needs a run folder"),
        (["--env-id", "BoatOnStep-v9", "--out", "{tmp}"], "unknown env id 'BoatOnStep-v9'"),
        (["--env-id", BOAT, "--out", "{tmp}", "--episodes", "0"], "--episodes must be at least"),
        (["--env-id", BOAT, "--out", "{tmp}", "--planner-samples", "0"], "--planner-samples "),
        (
            ["--env-id", BOAT, "--out", "{tmp}", "--no-planner", "--planner-horizon", "5"],
            "--planner-samples and --planner-horizon set the planner that --no-planner skips",
        ),
    ],
)
def test_argument_errors_say_what_to_pass(tmp_path, capsys, args, message):
    out = tmp_path / "out"
    assert evaluate_cli.main([a.format(tmp=out) for a in args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("fluidsim-evaluate: error: ") and message in err, err
    if "unknown env id" in message:  # and the registered ones
        assert all(env_id in err for env_id in SCENES)
    assert not out.exists()


def test_the_env_id_may_leave_out_the_prefix(tmp_path):
    assert baselines(tmp_path, "--no-planner", env_id="BoatOnStep-v0", episodes=2) == 0
    comments, _ = read_table(tmp_path / "evaluation.csv")
    assert f"--env-id {BOAT}" in comments[0]


def test_the_report_quotes_each_mean_with_its_interval():
    """benchmarks/report.py's cells: ``mean [lo, hi]`` from an evaluation CSV's columns, the
    mean alone where a table has no interval."""
    assert report._interval("0.5", "0.4", "0.61", percent=True) == "50% [40, 61]"
    assert report._interval("23.79", "22.91", "24.61", percent=False) == "23.8 [22.9, 24.6]"
    assert report._interval("1.26", None, None, percent=False) == "1.3"
    assert report._interval("", "", "", percent=True) == "n/a"
