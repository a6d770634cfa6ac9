"""The races' summary (``benchmarks.sweep_envs.markdown``, training.md's sweep-races block):
read from a race's table as ``fluidsim-sweep`` writes it and ``publish`` heads it."""

from __future__ import annotations

import csv

from benchmarks import sweep_envs

CONFIG = "paper_airplane_v1_sac"


def _write_race(docs, rows: list[dict]) -> None:
    head = [
        "# command: python -m benchmarks.sweep_envs --configs paper_airplane_v1_sac",
        "# target: the tuned pilot's mean return at standard, 13.85 (docs/study_v1_ppo.csv)",
        "# budget: a trial's wall-clock limit, 720 s",
        "# first trial: aaaa0000 (the config as it was when raced)",
    ]
    with open(docs / f"sweep_{CONFIG}.csv", "w", newline="") as f:
        f.write("\n".join(head) + "\n")
        writer = csv.DictWriter(f, list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def test_the_summary_names_the_config_raced_from_its_rate_and_what_the_best_changes(
    tmp_path, monkeypatch
):
    base = {k: str(v) for k, v in sweep_envs._base_values(CONFIG).items()}
    trial = {"status": "", "best_return": "", "time_to_target_s": "", "timesteps": "", "wall_s": ""}
    best = {**base, "algorithm.gradient_steps": "1"}  # the search's ranking puts it first
    rows = [
        {"trial": "bbbb1111", **best, **trial, "status": "reached target",
         "best_return": "14.2", "time_to_target_s": "300.4", "timesteps": "90000",
         "wall_s": "300.4"},
        {"trial": "aaaa0000", **base, **trial, "status": "stopped early",
         "best_return": "6.5", "timesteps": "30000", "wall_s": "240.0"},
    ]  # fmt: skip
    monkeypatch.setattr(sweep_envs, "DOCS", tmp_path)
    monkeypatch.setattr(sweep_envs, "RACES", {CONFIG: sweep_envs.RACES[CONFIG]})
    _write_race(tmp_path, rows)
    line = sweep_envs.markdown().splitlines()[-1]
    assert line == (
        "| PaperAirplane-v1 SAC | 13.85 | 2 | 1 | stopped by ASHA at 240 s (best 6.5) | 300 s "
        "| 125, 300 | gradient_steps 1 |"
    )


def test_without_a_race_the_summary_says_how_to_run_one(tmp_path, monkeypatch):
    monkeypatch.setattr(sweep_envs, "DOCS", tmp_path)
    assert "python -m benchmarks.sweep_envs" in sweep_envs.markdown()
