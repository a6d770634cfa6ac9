"""The privileged critic (rl/privileged.py): the value function reads the exact observation
beside the readings, the policy the readings alone; a run trains, saves, loads and is
evaluated with it; combinations that cannot run are errors at load naming the keys."""

from __future__ import annotations

import numpy as np
import pytest
import torch as th

from fluidsim_envs.rl import evaluate as evaluate_cli
from fluidsim_envs.rl import train as train_cli
from fluidsim_envs.rl.config import ConfigError, load_config
from fluidsim_envs.rl.privileged import PrivilegedCriticPolicy, WithTruth, actor_mask, pad
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.wrappers.sb3 import SB3VecEnv

SUB = "fluidsim/SubmarineWake-v1"


def test_the_observation_is_the_reading_then_the_exact_one_to_the_episodes_end():
    """Beside a copy of the env that does not restart its episodes: each step's observation
    is its reading then its exact observation, and at a time limit ``final_obs`` holds the
    ended episode's last exact observation, not the next episode's first."""
    wrapped = WithTruth(SCENES[SUB].vector_cls(num_envs=3, max_episode_steps=4))
    plain = SCENES[SUB].vector_cls(num_envs=3, max_episode_steps=4, autoreset=False)
    obs, _ = wrapped.reset(seed=2)
    want, _ = plain.reset(seed=2)
    D = want.shape[1]
    assert obs.shape == (3, 2 * D) and wrapped.single_observation_space.shape == (2 * D,)
    np.testing.assert_array_equal(obs[:, :D], want)
    np.testing.assert_array_equal(obs[:, D:], plain._truth)
    assert not np.array_equal(obs[:, D:], obs[:, :D])  # standard's instruments are noisy
    for _ in range(4):
        action = np.full((3, 3), 0.2)
        obs, _, _, truncated, info = wrapped.step(action)
        want, *_ = plain.step(action)
    assert truncated.all()
    np.testing.assert_array_equal(info["final_obs"][:, :D], want)
    np.testing.assert_array_equal(info["final_obs"][:, D:], plain._truth)
    assert not np.array_equal(obs[:, D:], plain._truth)  # the next episodes' first
    wrapped.close()
    assert wrapped.base.before_autoreset == []


def test_the_actor_never_reads_the_exact_columns_and_the_critic_does():
    from stable_baselines3 import PPO

    venv = SB3VecEnv(WithTruth(SCENES[SUB].vector_cls(num_envs=2)))
    D = venv.observation_space.shape[0] // 2
    model = PPO(
        PrivilegedCriticPolicy, venv, n_steps=8, batch_size=16, seed=0,
        policy_kwargs={"actor_mask": actor_mask(D)},
    )  # fmt: skip
    rng = np.random.default_rng(0)
    reading = rng.normal(size=(5, D)).astype(np.float32)
    full = np.concatenate([reading, rng.normal(size=(5, D)).astype(np.float32)], axis=1)
    a_full, _ = model.predict(full, deterministic=True)
    a_pad, _ = model.predict(pad(reading), deterministic=True)
    np.testing.assert_array_equal(a_full, a_pad)
    with th.no_grad():
        v_full = model.policy.predict_values(th.as_tensor(full))
        v_pad = model.policy.predict_values(th.as_tensor(pad(reading)))
    assert not th.equal(v_full, v_pad)
    with pytest.raises(ValueError, match="actor_mask has 3 columns"):
        PPO(PrivilegedCriticPolicy, venv, policy_kwargs={"actor_mask": [True] * 3})


def test_a_privileged_run_trains_across_levels_and_is_evaluated(tmp_path):
    run_dir = tmp_path / "run"
    args = [
        "submarine_wake_v1_ppo", "--set", "privileged_critic=true", "levels=[standard, hard]",
        "warm_start.steps=256", "total_timesteps=64", "n_envs=4", "algorithm.n_steps=16",
        "algorithm.batch_size=64", "eval.freq=0", "checkpoint.freq=0",
        "--run-dir", str(run_dir), "--no-progress-bar",
    ]  # fmt: skip
    assert train_cli.main(args) == 0
    cfg, policy = evaluate_cli.load_run(run_dir)  # the policy rebuilt, its weights loaded
    assert cfg.privileged_critic and isinstance(policy, PrivilegedCriticPolicy)
    rows = evaluate_cli.evaluate(run_dir, episodes=2, seed=0, planner=False)
    assert rows[0]["episodes"] == 2


@pytest.mark.parametrize(
    "text, message",
    [
        ("env_id: fluidsim/PaperAirplane-v1\nalgorithm: {name: sac}\n", "privileged_critic "
         "with algorithm.name 'sac'"),
        ("env_id: fluidsim/PaperAirplane-v0\nalgorithm: {name: ppo, n_steps: 16, "
         "batch_size: 16}\n", "PaperAirplane-v0 has no instruments"),
    ],
)  # fmt: skip
def test_a_privileged_critic_that_cannot_run_is_named_at_load(tmp_path, text, message):
    cfg = tmp_path / "c.yaml"
    cfg.write_text(text + "privileged_critic: true\n")
    with pytest.raises(ConfigError, match=message):
        load_config(cfg)
