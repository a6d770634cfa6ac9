"""python -m fluidsim_envs.enjoy: a trained policy flown to a GIF and to a Rerun recording,
with its episodes printed; a folder without a model, and no display without --video or
--rerun, are clear errors."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from PIL import Image

from fluidsim_envs import enjoy
from tests.tiny_run import train_tiny

TINY = [
    "env_id=fluidsim/PaperAirplane-v1",
    "total_timesteps=512",
    "n_envs=8",
    "algorithm.n_steps=64",
    "algorithm.batch_size=64",
    "eval.freq=0",
    "checkpoint.freq=0",
]


@pytest.fixture(scope="module")
def run(tmp_path_factory) -> Path:
    return train_tiny(tmp_path_factory.mktemp("enjoy") / "run", "paper_airplane_ppo", *TINY)


def test_a_policy_flies_to_a_gif_and_a_recording(run, tmp_path, capsys):
    gif, rrd = tmp_path / "flight.gif", tmp_path / "flight.rrd"
    assert enjoy.main([str(run), "--video", str(gif), "--seed", "4"]) == 0
    out = capsys.readouterr().out
    assert "episode 1: return" in out and f"wrote {gif}" in out
    with Image.open(gif) as image:
        length = int(out.split("episode 1: return ")[1].split(", ")[1].split()[0])
        assert image.n_frames == length + 1  # the reset's frame and one per action
    small = tmp_path / "small.gif"
    assert (
        enjoy.main(
            [str(run), "--video", str(small), "--seed", "4", "--stride", "3", "--width", "64",
             "--speed", "3"]
        )
        == 0
    )  # fmt: skip
    capsys.readouterr()
    with Image.open(small) as image:
        kept = len(range(0, length + 1, 3)) + (length % 3 > 0)  # and the last, always
        assert image.size[0] == 64 and image.n_frames == kept
        # 30 Hz, every 3rd frame, 3x speed: 33 ms a frame, stored in GIF's 10 ms units
        assert abs(image.info["duration"] - 1000 / 30) < 10
    assert enjoy.main([str(run), "--video", str(small), "--speed", "0"]) == 2
    assert "--speed must be a positive number, got 0.0" in capsys.readouterr().err
    assert enjoy.main([str(run), "--rerun", str(rrd), "--episodes", "2"]) == 0
    assert "episode 2: return" in capsys.readouterr().out and rrd.stat().st_size > 0


def test_a_folder_without_a_model_is_named(run, tmp_path, capsys):
    bare = tmp_path / "zoo_entry"
    bare.mkdir()
    shutil.copy(run / "config.yaml", bare)
    assert enjoy.main([str(bare), "--video", str(tmp_path / "x.gif")]) == 2
    assert f"{bare}: no model.safetensors" in capsys.readouterr().err
    assert enjoy.main([str(tmp_path / "missing")]) == 2
    assert "no config.yaml" in capsys.readouterr().err


def test_no_display_names_the_other_ways(run, monkeypatch, capsys):
    monkeypatch.setattr("fluidsim_envs.play.sys.platform", "linux")
    for var in ("DISPLAY", "WAYLAND_DISPLAY", "SDL_VIDEODRIVER"):
        monkeypatch.delenv(var, raising=False)
    assert enjoy.main([str(run)]) == 2
    err = capsys.readouterr().err
    assert "no display here" in err and "--video" in err


def test_the_window_shows_every_frame(run, monkeypatch):
    """Without --video or --rerun the episodes play in a window (SDL's dummy driver here,
    not paced to real time)."""
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    shown = []
    real = enjoy.window

    def counting(env_id, fps):
        show = real(env_id, fps)
        return lambda frame: shown.append(frame.shape) or show(frame)

    monkeypatch.setattr(enjoy, "window", counting)
    results = enjoy.enjoy(run, episodes=1, seed=4, realtime=False, say=lambda line: None)
    assert len(shown) == results[0]["length"] + 1 and len(set(shown)) == 1


def test_an_episode_s_frames_end_on_its_own_last_state(run):
    """Episode after episode: each one's first frame, one per action, its last drawn before
    the same-step autoreset (not the next episode's start, which comes next on its own)."""
    import numpy as np

    env_id, venv = enjoy.make_env(run, {}, frames=True, rerun=None)
    _, policy = enjoy.load_policy(run, venv)
    ended = []  # the ended state's frame, drawn by a hook of our own
    venv.before_autoreset.append(lambda *args: ended.append(venv.render()[0]))
    frames, ends = [], []
    results = enjoy.fly(venv, policy, 2, seed=4, on_frame=frames.append, say=lambda line: None,
                        on_end=lambda: ends.append(len(frames) - 1))  # fmt: skip
    first = results[0]["length"] + 1
    assert len(frames) == first + results[1]["length"] + 1 and ends == [first - 1, len(frames) - 1]
    for i, frame in zip(ends, ended, strict=True):
        np.testing.assert_array_equal(frames[i], frame)
    assert len(venv.before_autoreset) == 1  # fly's own hook is gone: ours alone is left
    venv.reset(seed=4)  # the first episode again: its start
    np.testing.assert_array_equal(frames[0], venv.render()[0])
    venv.close()
