"""Training across difficulty levels (``levels`` in a config; wrappers/levels.py): a run's
sub-envs split over the levels, its evaluations at its own level; combinations that cannot
run are errors at load that name the keys."""

from __future__ import annotations

import pytest
import yaml

from fluidsim_envs.rl import train as train_cli
from fluidsim_envs.rl.config import ConfigError, load_config


def test_a_run_trains_on_every_level_and_warm_starts_with_a_pilot_per_level(tmp_path):
    run_dir = tmp_path / "run"
    args = [
        "paper_airplane_v1_ppo", "--set", "levels=[easy, standard, hard]", "n_envs=6",
        "warm_start.steps=600", "total_timesteps=96", "algorithm.n_steps=16",
        "algorithm.batch_size=48", "eval.freq=0", "checkpoint.freq=0",
        "--run-dir", str(run_dir), "--no-progress-bar",
    ]  # fmt: skip
    assert train_cli.main(args) == 0
    config = yaml.safe_load((run_dir / "config.yaml").read_text())
    assert config["levels"] == ["easy", "standard", "hard"]
    assert "difficulty" not in config["env_kwargs"]  # each part's own
    assert load_config(run_dir / "config.yaml").levels == ("easy", "standard", "hard")
    meta = yaml.safe_load((run_dir / "run.yaml").read_text())
    assert meta["warm_start"]["env_steps"] == 600


@pytest.mark.parametrize(
    "extra, message",
    [
        ("levels: [easy, hard, hard]\nn_envs: 2\n", "n_envs: 2 sub-envs for the 3 entries"),
        ("levels: [easy, brutal]\n", "unknown difficulty levels \\['brutal'\\]"),
        (
            "levels: [easy, hard]\nenv_kwargs: {difficulty: hard}\n",
            "levels \\['easy', 'hard'\\] with env_kwargs.difficulty 'hard'",
        ),
        (
            "levels: [easy, hard]\ncurriculum: [{timesteps: 10, env_kwargs: {}}]\n",
            "levels \\['easy', 'hard'\\] with a curriculum",
        ),
    ],
)
def test_levels_that_cannot_run_are_named_at_load(tmp_path, extra, message):
    cfg = tmp_path / "c.yaml"
    cfg.write_text(
        "env_id: fluidsim/PaperAirplane-v1\n"
        "algorithm: {name: ppo, n_steps: 16, batch_size: 16}\n"
        + ("" if "n_envs" in extra else "n_envs: 4\n")
        + extra
    )
    with pytest.raises(ConfigError, match=message):
        load_config(cfg)


def test_levels_need_an_env_with_levels(tmp_path):
    cfg = tmp_path / "c.yaml"
    cfg.write_text(
        "env_id: fluidsim/PaperAirplane-v0\nalgorithm: {name: ppo, n_steps: 16, batch_size: 16}\n"
        "n_envs: 4\n"
        "levels: [easy, hard]\n"
    )
    with pytest.raises(ConfigError, match="PaperAirplane-v0 has no difficulty levels"):
        load_config(cfg)
