"""benchmarks/results.py's statistics on made-up episodes: IQM and mean over runs with
rliable's stratified bootstrap, a baseline's single run bootstrapped over its episodes, the
normalized score (random 0, tuned pilot 1), and the table that says where a trained policy
is below the tuned pilot."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from fluidsim_envs.rl.config import config_to_dict, load_config

pytest.importorskip("rliable")

from benchmarks import results  # noqa: E402


def episodes(env: str, policy: str, run: str, returns, level: str = "standard") -> list[dict]:
    return [
        {"env": env, "level": level, "policy": policy, "run": run, "episode": i, "return": r,
         "success": r > 5}
        for i, r in enumerate(returns)
    ]  # fmt: skip


@pytest.fixture(autouse=True)
def _fewer_resamples(monkeypatch):
    monkeypatch.setattr(results, "REPS", 4000)  # intervals to about 1%: enough for these checks


@pytest.fixture
def matrices():
    rng = np.random.default_rng(0)
    rows = episodes("E", "tuned pilot", "-", 10.0 + rng.normal(0, 1, 64))
    rows += episodes("E", "random", "-", rng.normal(0, 1, 64))
    rows += episodes("E", "planner", "-", 12.0 + rng.normal(0, 1, 64))
    for k, level in enumerate((2.0, 4.0, 6.0, 8.0, 30.0)):  # an outlier run: IQM resists it
        rows += episodes("E", "PPO", f"t{k}", level + rng.normal(0, 0.1, 64))
    return results.score_matrices(rows)


def test_iqm_and_mean_over_runs(matrices):
    ppo = matrices[("E", "standard", "PPO")]["return"]
    assert ppo.shape == (5, 64)
    est = results.interval_estimates(ppo)
    means = np.sort(ppo.mean(axis=1))
    # rliable's IQM is scipy's trim_mean at 25%: of five runs it drops the lowest and the
    # highest (int(0.25 * 5) = 1 at each end) and averages the other three
    iqm = means[1:4].mean()
    assert est["iqm"][0] == pytest.approx(iqm, abs=1e-9)
    assert est["mean"][0] == pytest.approx(means.mean())
    assert est["iqm"][1] <= est["iqm"][0] <= est["iqm"][2]
    assert est["iqm"][0] < 7.0 < est["mean"][0]  # the outlier run moves the mean, not the IQM


def test_a_baseline_is_bootstrapped_over_its_episodes(matrices):
    pilot = matrices[("E", "standard", "tuned pilot")]["return"]
    est = results.interval_estimates(pilot)
    assert est["iqm"] == est["mean"]
    mean, lo, hi = est["mean"]
    assert mean == pytest.approx(pilot.mean())
    assert lo < mean < hi and hi - lo == pytest.approx(2 * 1.96 / 8, rel=0.25)  # sigma 1, 64


def test_the_table_says_where_training_is_below_the_pilot(tmp_path, monkeypatch):
    rng = np.random.default_rng(1)
    rows = episodes("E", "tuned pilot", "-", 10.0 + rng.normal(0, 1, 64))
    rows += episodes("E", "random", "-", rng.normal(0, 1, 64))
    for k, level in enumerate((2.0, 3.0, 4.0, 5.0, 6.0)):
        rows += episodes("E", "PPO", f"t{k}", level + rng.normal(0, 0.1, 64))
        rows += episodes("E", "SAC", f"t{k}", 9.0 + level / 2 + rng.normal(0, 0.1, 64))
    summary = results.summary_rows(results.score_matrices(rows))
    by = {r["policy"]: r for r in summary}
    assert by["tuned pilot"]["normalized_iqm"] == pytest.approx(1.0)
    assert by["random"]["normalized_iqm"] == pytest.approx(0.0, abs=1e-12)
    csv = tmp_path / "results.csv"
    monkeypatch.setattr(results, "CSV", csv)
    results.write_csv(csv, results.COLUMNS, ([r[c] for c in results.COLUMNS] for r in summary))
    table = results.markdown()
    ppo = next(line for line in table.splitlines() if "| PPO |" in line)
    sac = next(line for line in table.splitlines() if "| SAC |" in line)
    # IQM 4 [3, 5] against the pilot's 10 [9.8, 10.2], every run under it; SAC's 11 above
    assert "| **below**; under its mean: t0; t1; t2; t3; t4 |  |" in ppo
    assert sac.endswith("| above |  |")  # no run under the pilot: none named; no planner


def test_the_bar_is_the_best_pilot(tmp_path, monkeypatch):
    """With pilots of several gains, the one of highest mean return is the bar: the
    normalization's 1 and what *vs best pilot* compares with, whichever its name."""
    rng = np.random.default_rng(2)
    rows = episodes("E", "tuned pilot", "-", 6.0 + rng.normal(0, 1, 64))
    rows += episodes("E", "hand-set pilot", "-", 10.0 + rng.normal(0, 1, 64))
    rows += episodes("E", "random", "-", rng.normal(0, 1, 64))
    for k in range(5):  # above the tuned pilot, below the hand-set one
        rows += episodes("E", "PPO", f"t{k}", 8.0 + rng.normal(0, 0.1, 64))
    matrices = results.score_matrices(rows)
    assert results.best_pilot(matrices, "E") == "hand-set pilot"
    summary = results.summary_rows(matrices)
    by = {r["policy"]: r for r in summary}
    assert by["hand-set pilot"]["normalized_iqm"] == pytest.approx(1.0)
    assert by["tuned pilot"]["normalized_iqm"] < 1.0
    monkeypatch.setattr(results, "CSV", tmp_path / "results.csv")
    results.write_csv(results.CSV, results.COLUMNS, ([r[c] for c in results.COLUMNS]
                                                     for r in summary))  # fmt: skip
    ppo = next(line for line in results.markdown().splitlines() if "| PPO |" in line)
    assert "| **below**; under its mean: t0; t1; t2; t3; t4 |  |" in ppo  # every run named
    assert by["PPO"]["worst"] == min(matrices[("E", "standard", "PPO")]["return"].mean(axis=1))


def test_profiles_resample_whole_runs():
    """Five runs at different levels: the band over runs is wide where they disagree; one
    run (a baseline) is resampled over its episodes."""
    rng = np.random.default_rng(2)
    runs = np.array([level + rng.normal(0, 0.1, 64) for level in (1.0, 2.0, 3.0, 4.0, 5.0)])
    taus = np.array([2.5])
    curve, band = results.profile(runs, taus)
    assert curve[0] == pytest.approx(0.6)  # three runs of five above 2.5
    assert band[1, 0] - band[0, 0] > 0.5  # whole runs resampled: 0.2 to 1.0 or so
    one, one_band = results.profile(runs[2:3], np.array([3.0]))
    assert 0.2 < one[0] < 0.8 and one_band[0, 0] < one[0] < one_band[1, 0]


def test_seeds_train_in_consecutive_sweeps():
    assert results.chunks([4, 0, 1, 3]) == [[0, 1], [3, 4]]
    assert results.chunks([]) == []


def test_runs_of_several_sessions_add_up(tmp_path, monkeypatch):
    """A session's rows replace those of the same config and seed; the others are kept."""
    path = tmp_path / "runs.csv"
    cols, key = ("config", "seed", "value"), ("config", "seed")
    results.merge(path, cols, [("a", 0, 1.0), ("a", 1, 2.0)], key)
    rows = results.merge(path, cols, [("a", 1, 3.0), ("b", 0, 4.0)], key)
    assert [(r["config"], r["seed"], r["value"]) for r in rows] == [
        ("a", "0", "1.0"), ("a", "1", "3.0"), ("b", "0", "4.0"),
    ]  # fmt: skip
    # the seeds still missing: neither published with the config as it is now nor finished
    # on this machine
    monkeypatch.setattr(results, "RUNS_CSV", path)
    monkeypatch.setattr(results, "SWEEPS", tmp_path / "sweeps")
    name = "paper_airplane_v1_ppo"
    run = tmp_path / "sweeps" / name / "seeds3-3" / "runs" / "t0"
    run.mkdir(parents=True)
    shipped = config_to_dict(load_config(name))
    (run / "config.yaml").write_text(yaml.safe_dump({**shipped, "seed": 3, "torch_threads": 1}))
    (run / "run.yaml").write_text(yaml.safe_dump({"seeds": {"train_stream": "training"}}))
    (run / "model.safetensors").write_bytes(b"")
    digest = results.config_digest(name)
    assert results.config_digest(run / "config.yaml") == digest  # seed and threads aside
    # an override is what the run trains: the same digest as the file that says it
    changed = tmp_path / "changed.yaml"
    changed.write_text(yaml.safe_dump({**shipped, "n_envs": 96}))
    assert results.config_digest(name, ["n_envs=96"]) == results.config_digest(changed)
    assert results.config_digest(name, ["n_envs=96"]) != digest
    assert results.config_digest(name, ["seed=7"]) == digest
    path.write_text(f"config,seed,config_digest,train_stream\n{name},0,{digest},training\n"
                    f"{name},1,{digest},training\n{name},2,0123456789ab,training\n"
                    f"{name},5,{digest},evaluation\n")  # fmt: skip
    # seed 2: trained with another config; a run on the evaluation stream is trained again
    assert results.missing_seeds(name, 5) == [2, 4]
    assert results.missing_seeds(name, 6) == [2, 4, 5]
    assert results.stale_runs([name]) == [(name, 2)]
    assert (
        "`paper_airplane_v1_ppo`: 3 of 5 runs on the training stream, 1 on the evaluation "
        "stream to train again" in results.missing_markdown()
    )
    for seed, change, stream in ((4, {"n_envs": 96}, "training"), (5, {}, "evaluation")):
        other = run.parent / f"t{seed}"
        other.mkdir()
        (other / "config.yaml").write_text(yaml.safe_dump({**shipped, "seed": seed, **change}))
        (other / "run.yaml").write_text(yaml.safe_dump({"seeds": {"train_stream": stream}}))
        (other / "model.safetensors").write_bytes(b"")
    # not the run of another config, nor the one of the shared stream
    assert list(results.local_runs(name)) == [3]


def test_baselines_are_flown_once_and_read_back(tmp_path, monkeypatch):
    """The baselines' committed episodes are read back, at the results' own seed and episode
    count; a baseline missing there, another seed, or ``fresh`` flies them again."""
    monkeypatch.setattr(results, "EPISODES_CSV", tmp_path / "episodes.csv")
    monkeypatch.setattr(results, "SWEEPS", tmp_path / "sweeps")
    rows = [r for b in results.BASELINES for r in episodes("Dart-v1", b, "-", [1.0, 7.0])]
    rows += episodes("Dart-v1", "PPO", "seed 0", [9.0, 9.0])
    cols = results.EPISODE_COLUMNS
    results.write_csv(results.EPISODES_CSV, cols, ([int(r[c]) if c == "success" else r[c]
                                                     for c in cols] for r in rows))  # fmt: skip
    got = results.baseline_episodes("fluidsim/Dart-v1", "standard", 2, results.EVAL_SEED)
    assert sorted(got) == sorted(results.BASELINES)
    assert got["random"]["return"].tolist() == [1.0, 7.0]
    assert got["random"]["success"].tolist() == [0, 1]
    assert results.published_baselines("Dart-v1", "standard", 3) == {}  # not those asked for
    assert results.published_baselines("Dart-v1", "easy", 2) == {}  # another level's
    assert results.published_baselines("Boat-v1", "standard", 2) == {}

    flown = []

    def fly(env_id, level, name, episodes, seed):
        flown.append(name)
        return {"return": np.full(episodes, 2.0), "success": np.ones(episodes, dtype=int)}

    monkeypatch.setattr(results, "fly_baseline", fly)
    for seed, fresh in ((results.EVAL_SEED + 1, False), (results.EVAL_SEED, True)):
        results.baseline_episodes("fluidsim/Dart-v1", "standard", 2, seed, fresh)
        assert flown == list(results.BASELINES), (seed, fresh)
        flown.clear()
    # the planner flies standard only: an hour a level on the boat
    results.baseline_episodes("fluidsim/Dart-v1", "hard", 2, results.EVAL_SEED)
    assert flown == [*results.PILOTS, "random"]
    flown.clear()
    # the boat's planner left out (hours): the others flown, the planner not, and then each
    # read back from its cache
    boat = ("fluidsim/Boat-v1", "standard", 2, results.EVAL_SEED)
    got = results.baseline_episodes(*boat, planner=False)
    assert flown == [*results.PILOTS, "random"] and sorted(got) == sorted(flown)
    assert results.baseline_episodes(*boat) and flown == [
        *results.PILOTS, "random", "planner"]  # fmt: skip


def test_the_page_is_written_from_the_csvs(tmp_path, monkeypatch):
    for name in ("CSV", "RUNS_CSV"):
        monkeypatch.setattr(results, name, tmp_path / f"{name}.csv")
    assert "no docs/results.csv yet" in results.page()
    results.write_csv(
        results.RUNS_CSV,
        results.RUN_COLUMNS,
        [
            ("paper_airplane_v1_ppo", 0, "d1", "abc", "training", 3_000_000, 300.0, 640.0, 19.5,
             18.25, "f"),
        ],
    )  # fmt: skip
    page = results.page()
    assert (
        "| paper_airplane_v1_ppo | 0 | `d1` | `abc` | training | 3,000,000 | 5.0 | 640.0 | 19.50 "
        "| 18.25 |" in page
    )
    assert "`boat_on_step_v1_ppo`: 0 of 5 runs" in page
    assert "Every run here did." in page


def test_the_page_lists_the_baselines_not_yet_flown(tmp_path, monkeypatch):
    """An env with results but without its planner's episodes gets the line that flies it;
    an env without results gets none (its configs' lines say what to train)."""
    for name in ("EPISODES_CSV", "RUNS_CSV"):
        monkeypatch.setattr(results, name, tmp_path / f"{name}.csv")
    rows = [r for b in ("tuned pilot", "random") for r in episodes("BoatOnStep-v1", b, "-", [1.0])]
    cols = results.EPISODE_COLUMNS
    results.write_csv(results.EPISODES_CSV, cols, ([int(r[c]) if c == "success" else r[c]
                                                     for c in cols] for r in rows))  # fmt: skip
    lines = results.missing_markdown().splitlines()
    assert (
        "- BoatOnStep-v1 at standard: the planner's episodes "
        "(`python -m benchmarks.results --configs boat_on_step_v1_ppo`)"
    ) in lines
    assert not any("planner" in line for line in lines if " at standard" not in line)
    assert any(line.startswith("- BoatOnStep-v1 at hard: the tuned pilot's") for line in lines)
    assert not any("SubmarineWake-v1:" in line or "PaperAirplane-v1:" in line for line in lines)


def test_the_planner_before_issue_44_reads_as_the_clairvoyant_one(tmp_path, monkeypatch):
    """Rows the results wrote as "planner (oracle)" were flown by the planner that kept the
    episode's noise keys: they read back as that reference, never as the planner."""
    monkeypatch.setattr(results, "EPISODES_CSV", tmp_path / "episodes.csv")
    rows = episodes("Dart-v1", "planner (oracle)", "-", [3.0, 5.0])
    cols = results.EPISODE_COLUMNS
    results.write_csv(results.EPISODES_CSV, cols, ([int(r[c]) if c == "success" else r[c]
                                                     for c in cols] for r in rows))  # fmt: skip
    assert results.published_baselines("Dart-v1", "standard", 2) == {}  # not the planner now
    (row,) = {(r["policy"], r["return"]) for r in results.episode_table() if r["return"] == "3.0"}
    assert row == ("planner (clairvoyant, before issue 44)", "3.0")


def test_each_level_has_its_own_bar_and_the_planner_its_share(tmp_path, monkeypatch):
    """A policy above the pilot at easy and below it at hard is said so at each; rows of a
    level compare within it; at standard the share of the planner's mean is given."""
    rng = np.random.default_rng(3)
    rows = []
    for level, pilot in (("easy", 10.0), ("standard", 8.0), ("hard", 4.0)):
        rows += episodes("E", "tuned pilot", "-", pilot + rng.normal(0, 1, 64), level)
        rows += episodes("E", "random", "-", rng.normal(0, 1, 64), level)
        for k in range(5):
            rows += episodes("E", "PPO", f"t{k}", 6.0 + k / 4 + rng.normal(0, 0.1, 64), level)
    rows += episodes("E", "planner", "-", 6.5 + rng.normal(0, 0.1, 64), "standard")
    summary = results.summary_rows(results.score_matrices(rows))
    assert [(r["level"], r["policy"]) for r in summary][:3] == [
        ("easy", "tuned pilot"),
        ("easy", "PPO"),
        ("easy", "random"),
    ]
    monkeypatch.setattr(results, "CSV", tmp_path / "results.csv")
    results.write_csv(results.CSV, results.COLUMNS, ([r[c] for c in results.COLUMNS]
                                                     for r in summary))  # fmt: skip
    ppo = {line.split(" | ")[1]: line for line in results.markdown().splitlines()
           if "| PPO |" in line}  # fmt: skip
    assert "| **below**; under its mean" in ppo["easy"] and ppo["easy"].endswith("|  |")
    assert "| **below**; under its mean" in ppo["standard"]
    assert ppo["standard"].endswith(f"| {100 * 6.5 / 6.5:.0f}% |")  # PPO's mean 6.5 of 6.5
    assert "| above |" in ppo["hard"]
