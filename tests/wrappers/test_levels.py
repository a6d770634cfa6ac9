"""LevelMix (wrappers/levels.py): sub-envs at several difficulty levels in one vector env,
each stepping bit for bit as the same sub-env of a vector env of its level, with the same
seed's draws; its infos are one batch's; bad splits are named."""

import numpy as np
import pytest

from fluidsim_envs.scenes import SCENES
from fluidsim_envs.wrappers.levels import LevelMix, concat_infos, shares
from fluidsim_envs.wrappers.sb3 import SB3VecEnv

V1 = [s for s in SCENES if s.endswith("-v1")]


@pytest.mark.parametrize("stream", ["evaluation", "training"])
@pytest.mark.parametrize("sid", V1, ids=[s.split("/")[1] for s in V1])
def test_each_sub_env_steps_as_in_a_vector_env_of_its_level(sid, stream):
    """Sub-env i of a mixture seeded s is sub-env i of a vector env of its level seeded s
    (any stream), through resets: the same observations, rewards and ends."""
    mix = LevelMix(sid, ["easy", "standard", "hard"], num_envs=6, max_episode_steps=12)
    alone = {
        level: SCENES[sid].vector_cls(num_envs=6, difficulty=level, max_episode_steps=12)
        for level in ("easy", "standard", "hard")
    }
    rows = {level: np.flatnonzero(np.array(mix.levels) == level) for level in alone}
    options = {"stream": stream}
    obs, _ = mix.reset(seed=21, options=options)
    want = {level: env.reset(seed=21, options=options)[0] for level, env in alone.items()}
    rng = np.random.default_rng(0)
    for t in range(30):  # past two time limits: the autoresets draw alike too
        for level, r in rows.items():
            np.testing.assert_array_equal(obs[r], want[level][r], err_msg=f"{level} at {t}")
        actions = rng.uniform(-1, 1, (6, len(mix.action_names)))
        obs, reward, term, trunc, info = mix.step(actions)
        for level, env in alone.items():
            o, rw, te, tr, _ = env.step(actions)
            r = rows[level]
            want[level] = o
            np.testing.assert_array_equal(reward[r], rw[r])
            np.testing.assert_array_equal(term[r] | trunc[r], (te | tr)[r])
        assert info["success"].shape == (6,)


def test_infos_side_by_side_keep_their_masks():
    a = {"x": np.array([1.0, 2.0]), "_x": np.array([True, False]), "d": {"y": np.ones(2)}}
    b = {"d": {"y": np.zeros(3)}, "z": np.array([4, 5, 6])}
    out = concat_infos([a, b], [2, 3])
    np.testing.assert_array_equal(out["x"], [1.0, 2.0, 0.0, 0.0, 0.0])
    np.testing.assert_array_equal(out["_x"], [True, False, False, False, False])
    np.testing.assert_array_equal(out["d"]["y"], [1, 1, 0, 0, 0])
    assert "_d" not in out
    np.testing.assert_array_equal(out["_z"], [False, False, True, True, True])


def test_a_mixture_trains_through_the_sb3_adapter_and_splits_a_pilot():
    sid = "fluidsim/SubmarineWake-v1"
    mix = LevelMix(sid, ["standard", "hard"], num_envs=4)
    venv = SB3VecEnv(mix, success_key="success")
    venv.seed(3)
    obs = venv.reset()
    pilot = mix.split(SCENES[sid].pilot)
    parts = [SCENES[sid].pilot(p) for p in mix.parts]
    np.testing.assert_array_equal(
        pilot(obs), np.concatenate([parts[0](obs[:2]), parts[1](obs[2:])])
    )
    obs, rewards, dones, infos = venv.step(pilot(obs))
    assert obs.shape == (4, mix.single_observation_space.shape[0]) and len(infos) == 4
    pilot.reset(np.array([True, False, False, True]))


@pytest.mark.parametrize(
    "levels, n, message",
    [
        (["easy", "hard", "hard"], 2, "2 sub-envs for the 3 entries"),
        (["easy", "medium"], 4, "unknown difficulty levels \\['medium'\\]"),
        ("easy", 4, "a list of difficulty levels"),
        ([], 4, "a list of difficulty levels"),
    ],
)
def test_bad_levels_are_named(levels, n, message):
    with pytest.raises(ValueError, match=message):
        shares(levels, n)


def test_a_difficulty_beside_the_levels_is_an_error():
    with pytest.raises(ValueError, match="drop difficulty='hard'"):
        LevelMix("fluidsim/PaperAirplane-v1", ["easy"], num_envs=2, difficulty="hard")


def test_a_level_named_twice_gets_two_shares():
    assert shares(["standard", "hard", "hard"], 6) == {"standard": 2, "hard": 4}


def test_sub_envs_split_as_evenly_as_whole_ones_allow():
    assert shares(["easy", "standard", "hard"], 64) == {"easy": 22, "standard": 21, "hard": 21}
    assert shares(["standard", "hard", "standard"], 5) == {"standard": 3, "hard": 2}


@pytest.mark.parametrize(
    "options, message",
    [
        ({"reset_mask": np.ones(3)}, "reset_mask must be a boolean array of shape \\(3,\\)"),
        ({"reset_mask": np.ones(2, dtype=bool)}, "reset_mask must be a boolean array"),
        ({"env_ids": [0], "reset_mask": np.ones(3, dtype=bool)}, "conflicting options"),
        ({"stream": "showcase!"}, "unknown seed stream"),
    ],
)
def test_bad_reset_options_are_named(options, message):
    mix = LevelMix("fluidsim/PaperAirplane-v1", ["easy", "standard", "hard"], num_envs=3)
    mix.reset(seed=0)
    with pytest.raises(ValueError, match=message):
        mix.reset(options=options)
