"""Saved models and statistics are numbers: loading a run folder or zoo entry runs no code
from it (a crafted pickle that would leave a marker file is never unpickled by evaluate,
enjoy, resume or the converter without --allow-pickle), and what is saved comes back
exactly (weights, optimizer states, timesteps, statistics, replay buffers)."""

from __future__ import annotations

import base64
import json
import pickle
import shutil
import zipfile
from pathlib import Path

import numpy as np
import pytest
import torch

from fluidsim_envs import enjoy
from fluidsim_envs.rl import convert, saved
from fluidsim_envs.rl import evaluate as evaluate_cli
from fluidsim_envs.rl import train as train_cli
from fluidsim_envs.rl.config import load_config
from tests.tiny_run import train_tiny

# one rollout of 4 x 64 steps, then another, a checkpoint after each
TINY = (
    "total_timesteps=256 n_envs=4 algorithm.n_steps=64 algorithm.batch_size=64 eval.freq=0 "
    "checkpoint.freq=128 torch_threads=1"
).split()


@pytest.fixture(scope="module")
def run(tmp_path_factory) -> Path:
    return train_tiny(tmp_path_factory.mktemp("saved") / "run", "paper_airplane_ppo", *TINY)


class Payload:
    """Unpickled, it creates ``marker`` (what any code a pickle names could do)."""

    def __init__(self, marker: Path) -> None:
        self.marker = marker

    def __reduce__(self):
        return (Path.touch, (self.marker,))


def plant(folder: Path, marker: Path) -> None:
    """SB3's pickled files, each carrying the payload, where a run keeps its models: the
    final model (in the zip's JSON ``data``, as SB3 serializes an object), its statistics,
    the best model and a checkpoint."""
    blob = base64.b64encode(pickle.dumps(Payload(marker))).decode()
    data = json.dumps({"observation_space": {":type:": "x", ":serialized:": blob}})
    for zip_path in (
        folder / "model.zip",
        folder / "best" / "best_model.zip",
        folder / "checkpoints" / "model_128_steps.zip",
    ):
        zip_path.parent.mkdir(parents=True, exist_ok=True)
        with zipfile.ZipFile(zip_path, "w") as z:
            z.writestr("data", data)
        stats = zip_path.parent / (
            "model_vecnormalize_128_steps.pkl" if "steps" in zip_path.name else "vecnormalize.pkl"
        )
        stats.write_bytes(pickle.dumps(Payload(marker)))


def test_no_command_runs_a_planted_pickle(run, tmp_path, capsys):
    marker = tmp_path / "pwned"
    folder = tmp_path / "from_a_stranger"
    folder.mkdir()
    shutil.copy(run / "config.yaml", folder)
    plant(folder, marker)

    assert evaluate_cli.main([str(folder), "--episodes", "2", "--no-planner"]) == 2
    err = capsys.readouterr().err
    assert "model.zip: an SB3 pickle" in err and "--allow-pickle" in err
    assert evaluate_cli.main([str(folder), "--model", "best", "--episodes", "2"]) == 2
    assert "best_model.zip: an SB3 pickle" in capsys.readouterr().err
    assert enjoy.main([str(folder), "--video", str(tmp_path / "x.gif")]) == 2
    assert "an SB3 pickle" in capsys.readouterr().err
    assert train_cli.main(["--resume", str(folder), "--no-progress-bar"]) == 2
    assert "its saved states are SB3 pickles" in capsys.readouterr().err
    assert convert.main([str(folder)]) == 2
    assert "pass --allow-pickle" in capsys.readouterr().err
    assert not marker.exists()

    # beside files of numbers, the pickles are not even opened
    for name in ("model.safetensors", "vecnormalize.safetensors"):
        shutil.copy(run / name, folder)
    assert evaluate_cli.main([str(folder), "--episodes", "2", "--no-planner"]) == 0
    assert not marker.exists()

    # the payload is real: the flag that says "I trust this file" is what lets it run
    (folder / "model.safetensors").unlink()
    evaluate_cli.main([str(folder), "--episodes", "2", "--no-planner", "--allow-pickle"])
    assert "unpickling runs whatever code the file carries" in capsys.readouterr().err
    assert marker.exists()


def test_a_saved_model_comes_back_exactly(run):
    """Weights and optimizer states into a model built from the config (resume), the
    policy alone into a policy built from it (evaluate): the same numbers, the same acts."""
    cfg = train_cli.resolved(load_config(run / "config.yaml"))
    restart = train_cli.final_paths(run, 256)
    venv = train_cli.make_env(cfg, cfg.n_envs, 0, stats=restart.stats)
    try:
        model = train_cli._model(cfg, run, venv, None, 0)
        before = str(model.get_parameters())
        saved.load_into(model, restart.model)
        assert model.num_timesteps == 256 and str(model.get_parameters()) != before
        again = run.parent / "again.safetensors"
        saved.save_model(model, again)
        assert again.read_bytes() == restart.model.read_bytes()  # what was read is all it held
        adam = model.policy.optimizer.state_dict()["state"]
        assert adam and all(int(s["step"]) > 0 for s in adam.values())
        _, policy = evaluate_cli.load_run(run)
        obs = np.random.default_rng(0).normal(size=(16, *venv.observation_space.shape))
        obs = obs.astype(np.float32)
        np.testing.assert_array_equal(
            policy.predict(obs, deterministic=True)[0], model.predict(obs, deterministic=True)[0]
        )
        # every observation of the run (4 sub-envs x 64 steps, and their first), and SB3's
        # 1e-4 to start the count
        assert venv.obs_rms.count == pytest.approx(4 * 65 + 1e-4, abs=1e-9)
        assert venv.obs_rms.mean.shape == venv.observation_space.shape
    finally:
        venv.close()


def test_an_off_policy_state_comes_back_exactly(tmp_path):
    """SAC: its critics' and entropy coefficient's optimizers, the coefficient itself and
    its replay buffer."""
    from stable_baselines3 import SAC

    from fluidsim_envs.wrappers.sb3 import make_sb3_vec_env

    venv = make_sb3_vec_env("fluidsim/PaperAirplane-v0", 2)
    try:
        model = SAC("MlpPolicy", venv, buffer_size=200, learning_starts=20, seed=0, device="cpu")
        model.learn(60)
        saved.save_model(model, tmp_path / "m.safetensors")
        saved.save_replay(model.replay_buffer, tmp_path / "r.safetensors")
        other = SAC("MlpPolicy", venv, buffer_size=200, learning_starts=20, seed=1, device="cpu")
        saved.load_into(other, tmp_path / "m.safetensors")
        saved.load_replay(other.replay_buffer, tmp_path / "r.safetensors")
    finally:
        venv.close()
    assert str(other.get_parameters()) == str(model.get_parameters())
    assert torch.equal(other.log_ent_coef, model.log_ent_coef) and other.num_timesteps == 60
    buffer, kept = other.replay_buffer, model.replay_buffer
    assert (buffer.pos, buffer.full) == (kept.pos, kept.full) == (30, False)
    np.testing.assert_array_equal(buffer.observations, kept.observations)
    np.testing.assert_array_equal(buffer.rewards, kept.rewards)


def test_a_policy_only_file_is_not_a_state_to_resume(run, tmp_path, capsys):
    """A zoo entry holds the policy's weights alone: it flies, and --resume says why it
    cannot train on."""
    entry = Path(shutil.copytree(run, tmp_path / "entry"))
    shutil.rmtree(entry / "checkpoints")
    saved.copy_policy(run / "model.safetensors", entry / "model.safetensors")
    assert saved.model_header(entry / "model.safetensors")["policy_only"]
    evaluate_cli.load_run(entry)
    assert train_cli.main(["--resume", str(entry), "--no-progress-bar"]) == 2
    assert "zoo entries are read-only to --resume" in capsys.readouterr().err


def test_convert_turns_trusted_pickles_into_numbers(run, tmp_path):
    """SB3's own files (as versions before this one saved them) convert to the same policy."""
    from stable_baselines3 import PPO

    old = Path(shutil.copytree(run, tmp_path / "old"))
    cfg = train_cli.resolved(load_config(run / "config.yaml"))
    venv = train_cli.make_env(cfg, cfg.n_envs, 0, stats=run / "vecnormalize.safetensors")
    try:
        model = train_cli._model(cfg, run, venv, train_cli.final_paths(run, 256), 0)
        for name in ("model.safetensors", "vecnormalize.safetensors"):
            (old / name).unlink()
        model.save(old / "model.zip")
        model.get_vec_normalize_env().save(str(old / "vecnormalize.pkl"))
    finally:
        venv.close()
    assert isinstance(PPO.load(old / "model.zip"), PPO)
    shutil.rmtree(old / "checkpoints")
    said = []
    with pytest.raises(convert.RunError, match="allow_pickle=True"):
        convert.convert(old, allow_pickle=False)
    assert convert.convert(old, allow_pickle=True, remove=True, say=said.append) == 2
    assert not (old / "model.zip").exists() and not (old / "vecnormalize.pkl").exists()
    (_, a), (_, b) = evaluate_cli.load_run(run), evaluate_cli.load_run(old)
    for x, y in zip(a.state_dict().values(), b.state_dict().values(), strict=True):
        assert torch.equal(x, y)


@pytest.mark.parametrize(
    ("change", "why"),
    [
        ({"settings": {"gamma": "0.99"}}, "gamma = '0.99'"),
        ({"settings": {"clip_obs": -1.0}}, "clip_obs = -1.0"),
        ({"settings": {"norm_obs": 1}}, "norm_obs = 1"),
        ({"obs_rms/var": -1.0}, "negative variance"),
        ({"obs_rms/count": float("nan")}, "not finite"),
    ],
)
def test_crafted_statistics_are_refused_by_name(run, tmp_path, change, why):
    """Statistics whose header or arrays a hand changed: an error that names what is wrong,
    before a VecNormalize is built from them."""
    from safetensors import safe_open
    from safetensors.numpy import load_file, save_file

    source = run / "vecnormalize.safetensors"
    with safe_open(source, "numpy") as f:
        header = json.loads(f.metadata()["fluidsim"])
    arrays = load_file(source)
    for key, value in change.items():
        if key == "settings":
            header["settings"].update(value)
        else:
            arrays[key] = np.full_like(arrays[key], value)
    bad = tmp_path / "vecnormalize.safetensors"
    save_file(arrays, bad, metadata={"fluidsim": json.dumps(header)})
    cfg = train_cli.resolved(load_config(run / "config.yaml"))
    venv = train_cli.make_env(cfg, 2, 0)
    try:
        with pytest.raises(saved.NotOurs, match=why):
            saved.load_statistics(bad, venv.venv)
    finally:
        venv.close()
