"""The zoo (``zoo/<Env-vN>-<algo>/``, written by ``python -m benchmarks.zoo``): every config
with published runs has its entry; each entry is complete and under 2 MiB, holds the best
published run, and its ``evaluation.csv`` (the README's zoo row) is reproduced number for
number by ``fluidsim-evaluate`` on this machine kind (``benchmarks.zoo --check``)."""

from __future__ import annotations

import pytest

from benchmarks import zoo
from benchmarks.results import RUNS_CSV, published_rows

ENTRIES = sorted(p for p in zoo.ZOO.glob("*") if p.is_dir())
PUBLISHED = sorted({r["config"] for r in published_rows(RUNS_CSV)})


@pytest.mark.parametrize("config", PUBLISHED)
def test_a_config_with_runs_has_its_entry_holding_the_best_run(config):
    folder = zoo.ZOO / zoo.entry_name(config)
    assert zoo.holds(folder, config, zoo.best_seed(config)), (
        f"{folder}: not the best published run of {config} as it is now (python -m benchmarks.zoo)"
    )


@pytest.mark.parametrize("folder", ENTRIES, ids=lambda p: p.name)
def test_an_entry_is_complete_and_small(folder):
    names = {p.name for p in folder.iterdir()}
    assert set(zoo.FILES) | {"evaluation.csv"} <= names
    assert sum(p.stat().st_size for p in folder.iterdir()) < zoo.MAX_BYTES


@pytest.mark.parametrize("folder", ENTRIES, ids=lambda p: p.name)
def test_an_entry_reproduces_its_evaluation(folder):
    assert zoo.check(folder) == []


def test_the_best_run_is_chosen_on_the_published_episodes(tmp_path, monkeypatch):
    path = tmp_path / "episodes.csv"
    rows = ["env,policy,run,episode,return,success"]
    for seed, level in ((0, 1.0), (1, 3.0), (2, 2.0)):
        rows += [f"PaperAirplane-v1,PPO,seed {seed},{i},{level + i},0" for i in range(4)]
    rows += [f"PaperAirplane-v1,tuned pilot,-,{i},9.0,1" for i in range(4)]
    path.write_text("\n".join(rows) + "\n")
    monkeypatch.setattr(zoo, "EPISODES_CSV", path)
    assert zoo.best_seed("paper_airplane_v1_ppo") == 1
    assert zoo.best_seed("paper_airplane_v1_sac") is None
