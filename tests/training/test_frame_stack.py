"""frame_stack: a policy that sees its last k observations. Training stacks them with SB3's
VecFrameStack over the normalized observations; evaluation (fluidsim-evaluate, enjoy, the
results) feeds the model the same stacks through evaluate.StackedPolicy, checked here against
VecFrameStack itself, and a stacked run trains and evaluates end to end."""

from __future__ import annotations

import numpy as np
import pytest
from stable_baselines3.common.vec_env import VecFrameStack

from fluidsim_envs.rl import evaluate as evaluate_cli
from fluidsim_envs.rl import train as train_cli
from fluidsim_envs.rl.config import ConfigError, load_config
from fluidsim_envs.wrappers.sb3 import make_sb3_vec_env

ENV = "fluidsim/PaperAirplane-v1"


class Recorder:
    """A stand-in model: records what it is asked to act on, acts with zeros."""

    def __init__(self, actions: int) -> None:
        self.seen, self.actions = [], actions

    def predict(self, obs, deterministic=True):
        self.seen.append(np.array(obs))
        return np.zeros((len(obs), self.actions)), None


def test_the_stacked_policy_sees_what_vec_frame_stack_gave():
    """Over one episode and the next one's start in every sub-env (an episode ended and
    reset(mask) called, as enjoy does), the model gets, step by step, the observations SB3's
    VecFrameStack gives in training: the last 3, oldest first, zeros before an episode's
    first."""
    frames, n = 3, 4
    sb3 = VecFrameStack(make_sb3_vec_env(ENV, n, seed=2), frames)
    ours = make_sb3_vec_env(ENV, n, seed=2).venv
    model = Recorder(ours.single_action_space.shape[0])
    policy = evaluate_cli.StackedPolicy(model, lambda obs: obs, frames)
    want = [sb3.reset()]
    obs, _ = ours.reset(seed=2)
    policy.reset()
    actions = policy(obs)
    for _ in range(40):
        stacked, _, dones, _ = sb3.step(actions)
        want.append(stacked)
        obs, _, terminated, truncated, _ = ours.step(actions)
        if np.any(terminated | truncated):
            policy.reset(terminated | truncated)
        actions = policy(obs)
    for t, (a, b) in enumerate(zip(want, model.seen, strict=True)):
        np.testing.assert_array_equal(a, b, err_msg=f"step {t}")
    assert np.any(model.seen[1][:, : ours.single_observation_space.shape[0]] == 0.0)


def test_frame_stack_is_checked_at_load(tmp_path):
    cfg = tmp_path / "c.yaml"
    cfg.write_text(f"env_id: {ENV}\nframe_stack: 0\nalgorithm: {{name: ppo}}\n")
    with pytest.raises(ConfigError, match="frame_stack"):
        load_config(cfg)


def test_a_stacked_run_trains_and_evaluates(tmp_path):
    """A tiny PPO run with frame_stack 2: its model reads two observations, and the run's
    evaluation flies it through the stacking policy."""
    run_dir = tmp_path / "run"
    args = [
        "paper_airplane_v1_ppo", "--set", "frame_stack=2", "total_timesteps=512", "n_envs=4",
        "algorithm.n_steps=128", "algorithm.batch_size=128", "eval.freq=0", "warm_start.steps=256",
        "checkpoint.freq=0", "--run-dir", str(run_dir), "--no-progress-bar",
    ]  # fmt: skip
    assert train_cli.main(args) == 0
    cfg, model = evaluate_cli.load_run(run_dir)
    dim = make_sb3_vec_env(ENV, 1).observation_space.shape[0]
    # the shipped config's privileged critic stacks the exact half beside each reading
    halves = 2 if cfg.privileged_critic else 1
    assert cfg.frame_stack == 2 and model.observation_space.shape == (2 * halves * dim,)
    assert evaluate_cli.main([str(run_dir), "--episodes", "4", "--no-planner"]) == 0
