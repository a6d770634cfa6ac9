"""The warm start (rl/warm_start.py): the tuned pilot flies the training envs, the policy's
mean action and its value function are fitted to it before PPO; the pilot's episodes are not
the run's, and a warm start is PPO's alone."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from fluidsim_envs.rl import train as train_cli
from fluidsim_envs.rl import warm_start as WS
from fluidsim_envs.rl.config import ConfigError, load_config


def test_value_targets_are_each_episodes_discounted_returns():
    """Rewards of 1 at gamma 0.5: G = 2 (1 - 0.5^k) with k steps left in the episode. A sum
    cut by a time limit or by the flight's end is trusted only 3 / (1 - gamma) = 6 steps or
    more before the cut; one that an episode's true end closes is exact."""
    T = 10
    rewards = np.ones((T, 3))
    dones, truncated = np.zeros((T, 3), dtype=bool), np.zeros((T, 3), dtype=bool)
    dones[3, 1] = True  # env 1's episode ends for good after step 3
    dones[7, 2] = truncated[7, 2] = True  # env 2's is cut by its time limit after step 7
    g, valid = WS.value_targets(rewards, dones, truncated, None, gamma=0.5)
    left = 2.0 * (1.0 - 0.5 ** np.arange(T, 0, -1))  # k = T - t steps left
    np.testing.assert_allclose(g[:, 0], left, rtol=1e-6)
    np.testing.assert_allclose(g[:4, 1], left[-4:], rtol=1e-6)
    np.testing.assert_allclose(g[:8, 2], left[-8:], rtol=1e-6)
    assert valid[:5, 0].all() and not valid[5:, 0].any()  # 6 or more steps to the flight's end
    assert valid[:4, 1].all()  # the true end: exact however near
    assert valid[:3, 2].all() and not valid[3:8, 2].any()  # the time limit: a cut


def test_stacked_inputs_start_each_episode_from_zeros():
    obs = np.arange(1.0, 7.0).reshape(3, 1, 2)  # three steps of one env, two columns
    dones = np.array([[False], [True], [False]])  # a new episode from step 2
    x = WS.policy_inputs(obs, dones, None, frames=2)
    np.testing.assert_array_equal(x[:, 0], [[0, 0, 1, 2], [1, 2, 3, 4], [0, 0, 5, 6]])


def test_a_warm_start_is_ppos(tmp_path):
    cfg = tmp_path / "c.yaml"
    cfg.write_text(
        "env_id: fluidsim/PaperAirplane-v1\nalgorithm: {name: sac}\nwarm_start: {steps: 100}\n"
    )
    with pytest.raises(ConfigError, match="warm_start.steps .* algorithm.name 'sac'"):
        load_config(cfg)
    cfg.write_text(
        "env_id: fluidsim/PaperAirplane-v1\nalgorithm: {name: ppo, gamma: 1.0}\n"
        "warm_start: {steps: 100}\n"
    )
    with pytest.raises(ConfigError, match="warm_start.steps with algorithm.gamma 1.0"):
        load_config(cfg)


def test_the_warm_started_policy_flies_like_the_pilot(tmp_path):
    """A tiny run warm started on 4096 pilot steps: run.yaml keeps the warm start, the policy
    now acts close to the pilot (its actions' mean squared error fell), and monitor.csv holds
    PPO's episodes only (none of the pilot's: the run's own steps are too few to end one)."""
    run_dir = tmp_path / "run"
    args = [
        "submarine_wake_v1_ppo", "--set", "warm_start.steps=4096", "warm_start.epochs=20",
        "total_timesteps=64", "n_envs=4", "algorithm.n_steps=16", "algorithm.batch_size=64",
        "eval.freq=0", "checkpoint.freq=0", "--run-dir", str(run_dir), "--no-progress-bar",
    ]  # fmt: skip
    assert train_cli.main(args) == 0
    meta = yaml.safe_load((run_dir / "run.yaml").read_text())
    ws = meta["warm_start"]
    assert ws["teacher"] == "tuned pilot" and ws["env_steps"] == 4096
    assert ws["action_mse"] < ws["action_mse_before"] / 2
    monitor = (run_dir / "monitor.csv").read_text().splitlines()
    assert not [line for line in monitor if line and line[0].isdigit()]


def test_a_teacher_is_named(tmp_path):
    cfg = tmp_path / "c.yaml"
    cfg.write_text(
        "env_id: fluidsim/PaperAirplane-v1\nalgorithm: {name: ppo}\n"
        "warm_start: {steps: 100, teacher: oracle}\n"
    )
    with pytest.raises(ConfigError, match=r"warm_start.teacher must be one of .*'oracle'"):
        load_config(cfg)


def test_the_planner_teaches_each_level_of_a_mixture(tmp_path):
    """The planner as the teacher, one per level (easy and hard side by side): run.yaml names
    it, and the policy's actions moved towards the planner's."""
    run_dir = tmp_path / "run"
    args = [
        "boat_on_step_v1_ppo", "--set", "warm_start.teacher=planner", "warm_start.steps=128",
        "warm_start.epochs=20", "levels=[easy, hard]", "total_timesteps=32", "n_envs=2",
        "algorithm.n_steps=16", "algorithm.batch_size=32", "eval.freq=0", "checkpoint.freq=0",
        "--run-dir", str(run_dir), "--no-progress-bar",
    ]  # fmt: skip
    assert train_cli.main(args) == 0
    ws = yaml.safe_load((run_dir / "run.yaml").read_text())["warm_start"]
    assert ws["teacher"] == "planner" and ws["env_steps"] == 128
    assert ws["action_mse"] < ws["action_mse_before"]


def test_each_part_gets_a_planner_of_its_own_seeded_by_the_run():
    """One planner per level's part, each with its own generator, the same again for the same
    run seed and others for another."""
    from fluidsim_envs.scenes import SCENES

    def seeds(run_seed):
        cfg = load_config("boat_on_step_v1_ppo", ["warm_start.teacher=planner", f"seed={run_seed}"])
        make = WS.teacher_factory(cfg)
        venv = SCENES["fluidsim/BoatOnStep-v1"].vector_cls(num_envs=1)
        try:
            return [make(venv).config.seed for _ in range(2)]
        finally:
            venv.close()

    first = seeds(0)
    assert first[0] != first[1] and seeds(0) == first
    assert not set(seeds(1)) & set(first)
