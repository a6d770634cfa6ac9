"""Training configs: every shipped config loads; unknown keys, wrong types and bad values are
errors that name them; --set overrides reach nested keys."""

from __future__ import annotations

import pytest
import yaml

from fluidsim_envs.rl.config import (
    SHIPPED,
    ConfigError,
    PPOConfig,
    SACConfig,
    apply_overrides,
    config_from_dict,
    config_to_dict,
    load_config,
)

CONFIGS = SHIPPED  # inside the package: an installed wheel has them
MINIMAL = {"env_id": "fluidsim/PaperAirplane-v0", "algorithm": {"name": "ppo"}}


def test_shipped_configs_cover_every_env_with_ppo_and_the_airplane_with_sac():
    loaded = {p.name: load_config(p) for p in sorted(CONFIGS.glob("*.yaml"))}
    pairs = {(c.env_id, c.algorithm.name) for c in loaded.values()}
    assert pairs >= {
        ("fluidsim/PaperAirplane-v0", "ppo"),
        ("fluidsim/SubmarineWake-v0", "ppo"),
        ("fluidsim/BoatOnStep-v0", "ppo"),
        ("fluidsim/PaperAirplane-v0", "sac"),
        ("fluidsim/PaperAirplane-v1", "ppo"),
        ("fluidsim/SubmarineWake-v1", "ppo"),
        ("fluidsim/BoatOnStep-v1", "ppo"),
        ("fluidsim/PaperAirplane-v1", "sac"),
    }
    for name, cfg in loaded.items():
        # every key of the file is spelled out and survives the round trip
        raw = yaml.safe_load((CONFIGS / name).read_text())
        assert config_from_dict(config_to_dict(cfg)) == cfg
        assert set(raw) <= set(config_to_dict(cfg))


def test_overrides_reach_nested_keys_and_read_values_as_yaml():
    raw = apply_overrides(
        MINIMAL,
        [
            "n_envs=8",
            "algorithm.learning_rate=1.0e-4",
            "env_kwargs.launch_height_m=[2, 3]",
            "policy.net_arch={pi: [32], vf: [16, 16]}",
            "eval.freq=0",
        ],
    )
    cfg = config_from_dict(raw)
    assert cfg.n_envs == 8 and cfg.algorithm.learning_rate == 1e-4 and cfg.eval.freq == 0
    assert cfg.env_kwargs == {"launch_height_m": [2, 3]}
    assert cfg.policy.net_arch == {"pi": (32,), "vf": (16, 16)}
    assert MINIMAL == {"env_id": "fluidsim/PaperAirplane-v0", "algorithm": {"name": "ppo"}}
    with pytest.raises(ConfigError, match="--set expects KEY=VALUE"):
        apply_overrides(MINIMAL, ["n_envs"])
    with pytest.raises(ConfigError, match="env_id is 'fluidsim/PaperAirplane-v0', not a mapping"):
        apply_overrides(MINIMAL, ["env_id.x=1"])


@pytest.mark.parametrize(
    ("overrides", "message"),
    [
        (["n_env=8"], r"unknown key 'n_env' in the config; valid keys: env_id, algorithm"),
        (["algorithm.gama=0.9"], r"unknown key 'algorithm.gama' in algorithm; valid keys: name,"),
        (["eval.episodes=3"], r"unknown key 'eval.episodes' in eval; valid keys: freq, n_epi"),
        (["algorithm.buffer_size=10"], r"unknown key 'algorithm.buffer_size'"),  # a SAC key
        (["n_envs=eight"], r"n_envs must be an integer, got 'eight'"),
        (["n_envs=2.5"], r"n_envs must be an integer, got 2.5"),
        (["torch_threads=0"], r"torch_threads must be an integer >= 1, got 0"),
        (["torch_threads=two"], r"torch_threads must be an integer or null, got 'two'"),
        (["torch_threads=1.5"], r"torch_threads must be an integer or null, got 1.5"),
        (["normalize.enabled=yes please"], r"normalize.enabled must be true or false"),
        (
            ["policy.net_arch=[64, many]"],
            r"net_arch must be a list of integers or a mapping of a list of integers, "
            r"got \[64, 'many'\]",
        ),
        (["policy.activation_fn=swish"], r"activation_fn must be one of \['tanh', 'relu'"),
        (["policy.net_arch={pi: [8], qf: [8]}"], r"must name the heads \['pi', 'vf'\]"),
        (["algorithm.name=dqn"], r"algorithm.name must be one of \['ppo', 'sac'\], got 'dqn'"),
        (["algorithm.gamma=1.5"], r"algorithm.gamma must be a finite number in \(0, 1\], got 1.5"),
        (["algorithm.batch_size=4096", "n_envs=2"], r"batch_size \(4096\) must be at most"),
        (["env_id=fluidsim/Nope-v0"], r"env_id must be one of \['fluidsim/BoatOnStep-v0'"),
        (["env_kwargs.wingspan_m=1"], r"env_kwargs: .*unknown parameter\(s\) \['wingspan_m'\]"),
        (["env_kwargs.max_episode_steps=0"], r"env_kwargs: .*max_episode_steps must be"),
        (["curriculum=[{timesteps: 0}]"], r"curriculum\[0\].timesteps must be an integer >= 1"),
        (["curriculum=[{steps: 10}]"], r"unknown key 'curriculum\[0\].steps'"),
        (["curriculum={timesteps: 10}"], r"curriculum must be a list of a mapping"),
        (
            ["curriculum=[{timesteps: 10}, {timesteps: 10, env_kwargs: {wingspan_m: 1}}]"],
            r"curriculum\[1\].env_kwargs: .*unknown parameter\(s\) \['wingspan_m'\]",
        ),
        (
            ["total_timesteps=1000", "curriculum=[{timesteps: 600}, {timesteps: 400}]"],
            r"curriculum: its stages take 1,000 timesteps, leaving none of total_timesteps",
        ),
    ],
)
def test_bad_values_are_errors_that_name_them(overrides, message):
    with pytest.raises(ConfigError, match=message):
        config_from_dict(apply_overrides(MINIMAL, overrides))


def test_missing_required_keys_and_files(tmp_path):
    with pytest.raises(ConfigError, match="missing required key 'env_id'"):
        config_from_dict({"algorithm": {"name": "ppo"}})
    with pytest.raises(ConfigError, match="algorithm must be a mapping with a name"):
        config_from_dict({"env_id": "fluidsim/PaperAirplane-v0", "algorithm": "ppo"})
    with pytest.raises(ConfigError, match="not found: .*nowhere.yaml.* is neither a file"):
        load_config(tmp_path / "nowhere.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("env_id: [unclosed\n")
    with pytest.raises(ConfigError, match="bad.yaml: not valid YAML"):
        load_config(bad)
    bad.write_text("- a list\n")
    with pytest.raises(ConfigError, match="expected a mapping"):
        load_config(bad)


def test_algorithm_sections_are_typed_per_algorithm():
    sac = config_from_dict(
        apply_overrides(
            MINIMAL,
            ["algorithm={name: SAC, ent_coef: 0.1}", "policy.net_arch={pi: [8], qf: [8]}"],
        )
    )
    assert isinstance(sac.algorithm, SACConfig) and sac.algorithm.ent_coef == 0.1
    assert isinstance(config_from_dict(MINIMAL).algorithm, PPOConfig)
    with pytest.raises(ConfigError, match="ent_coef must be a number > 0, 'auto'"):
        config_from_dict(apply_overrides(MINIMAL, ["algorithm={name: sac, ent_coef: big}"]))
    with pytest.raises(ConfigError, match="ortho_init applies to ppo only"):
        config_from_dict(
            apply_overrides(MINIMAL, ["algorithm={name: sac}", "policy.ortho_init=false"])
        )


def test_an_exponent_without_a_dot_is_a_number_on_the_command_line_not_in_a_file():
    """YAML 1.1 reads 3e-4 as a string: --set reads it as the number it means (as
    fluidsim-evaluate's --env does); in a config file it is an error with a hint."""
    cfg = config_from_dict(apply_overrides(dict(MINIMAL), ["algorithm.learning_rate=3e-4"]))
    assert cfg.algorithm.learning_rate == 3e-4
    raw = {**MINIMAL, "algorithm": {"name": "ppo", "learning_rate": "3e-4"}}
    with pytest.raises(ConfigError, match=r"must be a number, got '3e-4' \(YAML reads"):
        config_from_dict(raw)


def test_a_run_trains_on_the_stage_of_its_timesteps():
    """What a resumed run rebuilds its training env with: the stage its timesteps are in."""
    from fluidsim_envs.rl.train import _stage_at

    stages = [
        {"timesteps": 100, "env_kwargs": {"max_episode_steps": 20}},
        {"timesteps": 50, "env_kwargs": {"max_episode_steps": 30}},
    ]
    cfg = config_from_dict({**MINIMAL, "total_timesteps": 1000, "curriculum": stages})
    steps = [_stage_at(cfg, t).get("max_episode_steps") for t in (0, 99, 100, 149, 150, 999)]
    assert steps == [20, 20, 30, 30, None, None]


def test_a_resumed_run_plans_only_the_stages_left():
    """The plan line of a run resumed inside its curriculum names the stage under way with
    its steps left and the stages ahead, not the finished ones."""
    from fluidsim_envs.rl.train import _stages_left

    stages = [
        {"timesteps": 100, "env_kwargs": {"max_episode_steps": 20}},
        {"timesteps": 50, "env_kwargs": {"max_episode_steps": 30}},
    ]
    cfg = config_from_dict({**MINIMAL, "total_timesteps": 1000, "curriculum": stages})
    assert _stages_left(cfg, done=0) == (
        "episodes of max_episode_steps: 20 for 100 steps, "
        "episodes of max_episode_steps: 30 for 50 steps"
    )
    assert _stages_left(cfg, done=120) == "episodes of max_episode_steps: 30 for 30 more steps"
    assert _stages_left(cfg, done=150) == ""
