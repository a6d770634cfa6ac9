"""The ablation's runs are found by what they train, so a shipped config that changes trains
its variants again (``benchmarks/ablation.py``)."""

from __future__ import annotations

from benchmarks import ablation


def test_a_variant_run_lives_under_what_it_trains():
    name = "boat_on_step_v1_ppo"
    shipped = ablation.run_dir(name, "shipped", [], 0)
    assert shipped.name == "seed0" and shipped.parent.name.startswith("shipped-")
    off = ablation.variants(name)["no warm start"]
    assert (
        ablation.run_dir(name, "no warm start", off, 0).parent
        != ablation.run_dir(name, "no warm start", ["n_envs=96", *off], 0).parent
    )  # the base config changed: another folder, trained anew
    assert ablation.run_dir(name, "shipped", [], 1).parent == shipped.parent  # seeds side by side


def test_each_race_names_values_a_config_can_take():
    """A race's row trains the config with the values it was raced against: each is a key
    the config has (an unknown one fails at load), and its folder is not the shipped one."""
    for config, races in ablation.RACES.items():
        shipped = ablation.run_dir(config, "shipped", [], 0).parent
        for variant, overrides in races.items():
            assert variant in ablation.variants(config)
            assert ablation.run_dir(config, variant, overrides, 0).parent.name != shipped.name
