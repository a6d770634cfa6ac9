"""fluidsim_envs.zoo: the entries listed and found by name from anywhere, and the plain-SB3
example of docs/zoo.md run as written, scoring what the entry's evaluation.csv publishes."""

import contextlib
import io
import math
import re
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("stable_baselines3")

from fluidsim_envs import zoo  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def test_the_entries_are_the_repository_s_zoo_and_found_by_name_from_anywhere(
    tmp_path, monkeypatch
):
    # (in a checkout the package's copy is the repository's zoo/ through a link; the wheel's
    # own copy is flown by .ci/package_check, outside the checkout)
    names = sorted(p.name for p in (ROOT / "zoo").iterdir() if p.is_dir())
    assert zoo.list() == zoo.names() == names and len(names) >= 4
    monkeypatch.chdir(tmp_path)  # outside the checkout's folder
    for name in names:
        assert zoo.path(name) == zoo.path(f"zoo/{name}") == zoo.ENTRIES / name
    with pytest.raises(zoo.ZooError, match=r"'Nope-v1-ppo' is neither a zoo entry \(Boat"):
        zoo.path("Nope-v1-ppo")


def test_an_entry_acts_on_one_observation_or_a_batch():
    import gymnasium as gym

    entry = zoo.load("SubmarineWake-v1-ppo")
    assert entry.env_id == "fluidsim/SubmarineWake-v1" and entry.published()["policy"]
    env = gym.make(entry.env_id, **entry.env_kwargs)
    obs, _ = env.reset(seed=0)
    action = entry(obs)
    assert action.shape == env.action_space.shape
    np.testing.assert_array_equal(entry(np.stack([obs, obs]))[1], action)
    np.testing.assert_array_equal(entry.predict(obs)[0], action)
    with pytest.raises(ValueError, match="deterministically"):
        entry.predict(obs, deterministic=False)


def _example() -> str:
    text = (ROOT / "docs" / "zoo.md").read_text()
    block = re.search(
        r"<!-- zoo-example -->\n```python\n(.*?)```\n<!-- /zoo-example -->", text, re.S
    )
    assert block, "docs/zoo.md lost its example"
    return block.group(1)


def test_the_docs_plain_sb3_example_scores_the_published_return():
    """The example as the docs show it: its mean agrees with the published one to within
    sampling (Entry.agrees), and a mean far off does not."""
    scope: dict = {}
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(_example(), "docs/zoo.md", "exec"), scope)  # noqa: S102
    assert "agrees: True" in out.getvalue(), out.getvalue()
    entry, returns = scope["entry"], np.asarray(scope["returns"])
    assert len(returns) == 256 and entry.agrees(returns)
    assert not entry.agrees(returns - 3.0 * returns.std() / math.sqrt(len(returns)) - 1.0)


def test_enjoy_flies_an_entry_by_name_outside_the_checkout(tmp_path, monkeypatch):
    from fluidsim_envs.enjoy import enjoy

    monkeypatch.chdir(tmp_path)
    results = enjoy(
        "PaperAirplane-v1-ppo", episodes=1, seed=3, video="dart.gif", say=lambda *a: None
    )
    assert len(results) == 1 and (tmp_path / "dart.gif").stat().st_size > 0
