"""``benchmarks.train_wallclock``'s time to a good pilot: a run's first evaluation at the
tuned pilot's return, with the run's clock then; none for a run that never reached it, and
no target for a v0 env (its pilots have no v1 row)."""

from __future__ import annotations

import csv

from benchmarks import train_wallclock as W
from benchmarks.sweep_envs import pilot_return
from fluidsim_envs.rl.runs import EVAL_HISTORY_COLUMNS


def _history(run, returns):
    (run / "eval").mkdir(parents=True)
    with (run / "eval" / "history.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, EVAL_HISTORY_COLUMNS)
        w.writeheader()
        for i, r in enumerate(returns, 1):
            w.writerow({"timesteps": 100 * i, "mean_return": r, "std_return": 1.0,
                        "mean_length": 10, "success_rate": 0.5, "wall_s": 7.5 * i})  # fmt: skip


def test_the_first_evaluation_at_the_pilots_return_and_its_clock(tmp_path):
    target = pilot_return("fluidsim/PaperAirplane-v1")
    _history(tmp_path, [target - 5, target - 0.01, target, target + 3])
    assert W.to_pilot(tmp_path, "fluidsim/PaperAirplane-v1") == (target, 300, 22.5)


def test_a_run_below_the_pilot_and_a_v0_run_have_no_time(tmp_path):
    target = pilot_return("fluidsim/PaperAirplane-v1")
    _history(tmp_path, [target - 5, target - 1])
    assert W.to_pilot(tmp_path, "fluidsim/PaperAirplane-v1") == (target, "", "")
    assert W.to_pilot(tmp_path, "fluidsim/PaperAirplane-v0") == ("", "", "")


def test_a_v1_config_trains_before_and_after_its_retune():
    assert W.variants("paper_airplane_v1_ppo") == {
        "before": ("algorithm.n_epochs=10", "algorithm.learning_rate=3.0e-4"),
        "after": (),
    }
    assert set(W.variants("paper_airplane_ppo")) == {"before", "256x64"}
