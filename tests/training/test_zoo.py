"""The zoo (``zoo/<Env-vN>-<algo>/``, written by ``python -m benchmarks.zoo``): every config
with published runs has its entry; each entry is complete and under 2 MiB, holds the best
published run, and its ``evaluation.csv`` (the README's zoo row) is reproduced number for
number by ``fluidsim-evaluate`` on this machine kind (``benchmarks.zoo --check``)."""

from __future__ import annotations

import pytest

from benchmarks import zoo
from benchmarks.results import RUNS_CSV, published_rows

ENTRIES = sorted(p for p in zoo.ZOO.glob("*") if p.is_dir())
# configs with published runs of the config as it is now: a config changed since (its runs to
# train again, docs/results.md lists them) keeps its entry until they are
PUBLISHED = sorted(
    {
        r["config"]
        for r in published_rows(RUNS_CSV)
        if r.get("config_digest") == zoo.config_digest(r["config"])
    }
)


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


def _rows(trained_return: float, trained_success: float) -> list[dict]:
    rows = [("trained SAC", trained_return, trained_success), ("random", -4.9, 0.0078125)]
    return [
        {"policy": p, "episodes": "256", "return_mean": repr(r), "success_rate": repr(s)}
        for p, r, s in rows
    ]


def test_on_its_own_cpu_an_entry_reproduces_to_the_bit_on_another_to_its_rounding():
    kept = _rows(18.448012, 0.8125)
    # the last bits moved (as a rocketlake moved the PPO entries'): only another CPU forgives
    nudged = _rows(18.448012 * (1 + 1e-6), 0.8125)
    assert zoo.compare(kept, nudged, "rocketlake", "rocketlake") != []
    assert zoo.compare(kept, nudged, "rocketlake", "skylake-avx512") == []
    assert zoo.compare(kept, nudged, None, "rocketlake") == []  # a table that names no CPU
    assert zoo.compare(kept, kept, "rocketlake", "rocketlake") == []
    # further than a CPU's rounding moves it: a different policy
    moved_return = _rows(18.448012 * (1 + 3 * zoo.OTHER_CPU_RETURN_REL), 0.8125)
    moved_success = _rows(18.448012, 0.8125 + (zoo.OTHER_CPU_SUCCESS_EPISODES + 1) / 256)
    for again in (moved_return, moved_success):
        (line,) = zoo.compare(kept, again, "rocketlake", "skylake-avx512")
        assert line.startswith("trained SAC on skylake-avx512 (evaluated on rocketlake)")
    assert zoo.compare(kept, kept[::-1], "rocketlake", "skylake-avx512") == [
        "policies ['random', 'trained SAC'] != ['trained SAC', 'random']"
    ]
