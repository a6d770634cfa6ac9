"""Bad input to training runs: every field of a config (wrong type, out of range, NaN or inf,
unknown or duplicate key), config files, ``--set`` overrides, the paths the commands write to
and ``--resume`` of a folder that cannot be resumed. Each is refused before anything trains
or any run folder is written, with a message naming the key (or path) and the bad value. The
command-line rows run the CLIs' ``main`` and read what it printed: exit status 2 and one
``prog: error: ...`` message, as argparse gives, never a traceback."""

from __future__ import annotations

import contextlib
import copy
import io
import tempfile
from pathlib import Path
from typing import Any
from unittest import mock

import numpy as np
import pytest

from fluidsim_envs.rl import evaluate as evaluate_cli
from fluidsim_envs.rl import train as train_cli
from fluidsim_envs.rl.config import ConfigError, config_from_dict, dump_config, load_config
from tests.bad_inputs.table import Row, check, params

PPO = {"env_id": "fluidsim/PaperAirplane-v0", "algorithm": {"name": "ppo"}}
SAC = {**PPO, "algorithm": {"name": "sac"}, "policy": {"net_arch": [8]}}
# a config whose runs, were one to start by mistake, would end at once
TINY = {
    **PPO,
    "n_envs": 2,
    "total_timesteps": 16,
    "algorithm": {"name": "ppo", "n_steps": 8, "batch_size": 16},
    "eval": {"freq": 0},
    "checkpoint": {"freq": 0},
}
# files and folders the rows make, removed when the session ends
_TMP = tempfile.TemporaryDirectory(prefix="bad-run-inputs-")


class CliError(Exception):
    """What a command printed when it refused its input (exit status 2)."""


def folder() -> Path:
    """A fresh empty folder."""
    return Path(tempfile.mkdtemp(dir=_TMP.name))


def with_key(base: dict, key: str, value: Any) -> dict:
    """``base`` with the dotted ``key`` set to ``value``."""
    out = copy.deepcopy(base)
    *parents, last = key.split(".")
    node = out
    for part in parents:
        node = node.setdefault(part, {})
    node[last] = value
    return out


def field(label: str, key: str, value: Any, *words: str, base: dict = PPO) -> Row:
    """``key`` set to ``value`` in a config given as data: a :class:`ConfigError` naming the
    key, the value (its repr, unless ``words`` say how it shows) and ``words``."""
    shown = words or (repr(value),)
    name = "sac" if base is SAC else "config"
    return Row(
        f"{name}-{key}-{label}",
        lambda: config_from_dict(with_key(base, key, value)),
        ConfigError,
        (key, *shown),
    )


def yaml_file(text: str | bytes):
    """A call that loads ``text`` as a config file."""

    def call():
        path = folder() / "config.yaml"
        if isinstance(text, bytes):
            path.write_bytes(text)
        else:
            path.write_text(text)
        return load_config(path)

    return call


def cli(main, *argv) -> None:
    """Run a CLI's ``main``; a :class:`CliError` with what it printed when it refused the
    input as it should (status 2, one ``prog: error:`` message, no traceback)."""
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            status = main([str(a) for a in argv])
        except SystemExit as e:  # argparse's own errors
            status = e.code
    text = err.getvalue()
    assert status == 2, f"exit status {status}, printed: {text}"
    assert "Traceback" not in text and ": error: " in text.splitlines()[-1], text
    raise CliError(text.strip())


def train(*argv) -> Any:
    """``fluidsim-train ARGV``; it must refuse before training (training is patched out)."""
    with mock.patch.object(train_cli, "train", side_effect=AssertionError("training started")):
        return cli(train_cli.main, *argv, "--no-progress-bar")


def evaluate(*argv) -> Any:
    return cli(evaluate_cli.main, *argv, "--no-planner")


def run_folder(files: dict[str, str | bytes] | None = None) -> Path:
    """A run folder of :data:`TINY`: its config.yaml, then ``files`` (path: contents)."""
    run = folder()
    dump_config(config_from_dict(TINY), run / "config.yaml")
    for name, data in (files or {}).items():
        path = run / name
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(data, bytes):
            path.write_bytes(data)
        else:
            path.write_text(data)
    return run


def resume(make_run, *argv):
    """``fluidsim-train --resume RUN ARGV`` for the folder ``make_run()`` makes."""
    return lambda: cli(train_cli.main, "--resume", make_run(), *argv, "--no-progress-bar")


def without_gpu(call):
    """``call`` on a machine where torch sees no CUDA device."""

    def run():
        with mock.patch("torch.cuda.is_available", return_value=False):
            return call()

    return run


def a_file() -> Path:
    path = folder() / "a_file"
    path.write_text("not a folder")
    return path


NAN, INF = float("nan"), float("inf")

CONFIG_ROWS = [
    # the top level
    field("zero", "n_envs", 0, "0", ">= 1"),
    field("word", "n_envs", "eight"),
    field("fraction", "n_envs", 2.5),
    field("bool", "n_envs", True),
    field("negative", "total_timesteps", -5),
    field("null", "total_timesteps", None),
    field("negative", "seed", -1, "-1", "4294967295"),
    field("2**32", "seed", 2**32),
    field("fraction", "seed", 1.5),
    field("word", "seed", "zero"),
    field("numpy-negative", "seed", np.int64(-1), "-1"),
    field("tpu", "device", "tpu", "'tpu'", "cuda:N"),
    field("cuda-99", "device", "cuda:99", "'cuda:99'", "does not exist"),
    field("cpu-index", "device", "cpu:1", "'cpu:1'"),
    field("number", "device", 0, "got 0"),
    Row(
        "config-device-cuda-without-gpu",
        without_gpu(lambda: config_from_dict({**PPO, "device": "cuda"})),
        ConfigError,
        ("device", "'cuda'", "does not exist", "no CUDA device"),
    ),
    field("unknown-key", "n_env", 8, "unknown key", "valid keys"),
    field("unknown", "env_id", "fluidsim/Nope-v0"),
    field("number", "env_id", 42),
    field("list", "env_kwargs", [1, 2], "[1, 2]", "mapping"),
    field("unknown-param", "env_kwargs", {"wingspan_m": 1}, "wingspan_m", "unknown"),
    Row(
        "config-not-a-mapping",
        lambda: config_from_dict("fluidsim/PaperAirplane-v0"),
        ConfigError,
        ("the config must be a mapping", "PaperAirplane"),
    ),
    # normalize
    field("negative", "normalize.clip_obs", -1, "-1", "> 0"),
    field("zero", "normalize.clip_obs", 0),
    field("nan", "normalize.clip_obs", NAN),
    field("negative", "normalize.clip_reward", -10),
    field("zero", "normalize.epsilon", 0.0),
    field("words", "normalize.enabled", "yes please"),
    field("unknown-key", "normalize.clip", 5, "unknown key", "clip_obs"),
    # eval and checkpoint
    field("negative", "eval.seed", -5),
    field("2**32", "eval.seed", 2**32),
    field("negative", "eval.freq", -1),
    field("zero", "eval.n_episodes", 0),
    field("unknown-key", "eval.episodes", 3, "unknown key", "n_episodes"),
    field("negative", "checkpoint.freq", -100),
    field("word", "checkpoint.save_replay_buffer", "yes"),
    # PPO
    field("nan", "algorithm.learning_rate", NAN),
    field("inf", "algorithm.learning_rate", INF),
    field("negative", "algorithm.learning_rate", -3e-4),
    field("numpy-nan", "algorithm.learning_rate", np.float32("nan"), "nan"),
    field("exponent-string", "algorithm.learning_rate", "3e-4", "'3e-4'", "3.0e-4"),
    field("schedule-string", "algorithm.learning_rate", "lin_3e-4", "lin_3e-4", "lr_schedule"),
    field("cosine", "algorithm.lr_schedule", "cosine", "'cosine'", "'constant' or 'linear'"),
    field("number", "algorithm.lr_schedule", 1),
    field("zero", "algorithm.n_steps", 0),
    field("one", "algorithm.batch_size", 1, "normalize_advantage"),
    field("above-rollout", "algorithm.batch_size", 10**6, "1000000", "n_steps x n_envs"),
    field("zero", "algorithm.n_epochs", 0),
    field("above-1", "algorithm.gamma", 1.5, "1.5", "(0, 1]"),
    field("zero", "algorithm.gamma", 0.0),
    field("nan", "algorithm.gamma", NAN),
    field("negative", "algorithm.gae_lambda", -0.1),
    field("zero", "algorithm.clip_range", 0.0),
    field("negative", "algorithm.clip_range_vf", -0.2),
    field("negative", "algorithm.ent_coef", -0.01),
    field("inf", "algorithm.vf_coef", INF),
    field("zero", "algorithm.max_grad_norm", 0.0),
    field("below-minus-1", "algorithm.sde_sample_freq", -2),
    field("zero", "algorithm.target_kl", 0.0),
    field("word", "algorithm.use_sde", "on"),
    field("unknown-key", "algorithm.gama", 0.9, "unknown key", "gamma"),
    field("sac-key", "algorithm.buffer_size", 10, "unknown key"),
    field("dqn", "algorithm.name", "dqn", "'dqn'", "'ppo', 'sac'"),
    Row(
        "config-algorithm-without-name",
        lambda: config_from_dict({**PPO, "algorithm": {"gamma": 0.9}}),
        ConfigError,
        ("algorithm", "name", "ppo"),
    ),
    # SAC
    field("zero", "algorithm.buffer_size", 0, base=SAC),
    field("negative", "algorithm.learning_starts", -1, base=SAC),
    field("zero", "algorithm.tau", 0.0, base=SAC),
    field("above-1", "algorithm.tau", 2.0, base=SAC),
    field("zero", "algorithm.train_freq", 0, base=SAC),
    field("zero", "algorithm.gradient_steps", 0, base=SAC),
    field("below-minus-1", "algorithm.gradient_steps", -2, base=SAC),
    field("word", "algorithm.ent_coef", "big", base=SAC),
    field("negative-init", "algorithm.ent_coef", "auto_-0.1", base=SAC),
    field("negative", "algorithm.ent_coef", -0.5, base=SAC),
    field("auto-init", "algorithm.target_entropy", "auto_1", base=SAC),
    field("nan", "algorithm.target_entropy", NAN, base=SAC),
    field("zero", "algorithm.target_update_interval", 0, base=SAC),
    field("ppo-key", "algorithm.n_epochs", 3, "unknown key", base=SAC),
    # policy
    field("negative-layer", "policy.net_arch", [64, -1], "64, -1"),
    field("string", "policy.net_arch", "64,64"),
    field("wrong-heads", "policy.net_arch", {"pi": [8], "qf": [8]}, "['pi', 'vf']", "qf"),
    field("swish", "policy.activation_fn", "swish"),
    field("nan", "policy.log_std_init", NAN),
    field("word", "policy.ortho_init", "no"),
    field("ortho-for-sac", "policy.ortho_init", False, "ppo only", base=SAC),
]

FILE_ROWS = [
    Row(
        "file-duplicate-top-key",
        yaml_file(
            "env_id: fluidsim/PaperAirplane-v0\nn_envs: 8\nalgorithm: {name: ppo}\nn_envs: 16\n"
        ),
        ConfigError,
        ("duplicate key", "'n_envs'", "line 4", "line 2"),
    ),
    Row(
        "file-duplicate-nested-key",
        yaml_file(
            "env_id: fluidsim/PaperAirplane-v0\nalgorithm:\n  name: ppo\n  gamma: 0.9\n"
            "  gamma: 0.99\n"
        ),
        ConfigError,
        ("duplicate key", "'gamma'", "line 5"),
    ),
    Row(
        "file-duplicate-flow-key",
        yaml_file("env_id: fluidsim/PaperAirplane-v0\nalgorithm: {name: ppo, name: sac}\n"),
        ConfigError,
        ("duplicate key", "'name'", "line 2"),
    ),
    Row(
        "file-nan-clip",
        yaml_file(
            "env_id: fluidsim/PaperAirplane-v0\nalgorithm: {name: ppo}\n"
            "normalize: {clip_obs: .nan}\n"
        ),
        ConfigError,
        ("normalize.clip_obs", "nan"),
    ),
    Row(
        "file-inf-learning-rate",
        yaml_file(
            "env_id: fluidsim/PaperAirplane-v0\nalgorithm: {name: ppo, learning_rate: .inf}\n"
        ),
        ConfigError,
        ("algorithm.learning_rate", "inf"),
    ),
    Row(
        "file-negative-seed",
        yaml_file("env_id: fluidsim/PaperAirplane-v0\nalgorithm: {name: ppo}\nseed: -1\n"),
        ConfigError,
        ("config.yaml", "seed", "-1"),
    ),
    Row(
        "file-not-yaml",
        yaml_file("env_id: [unclosed\n"),
        ConfigError,
        ("config.yaml", "not valid YAML"),
    ),
    Row(
        "file-a-list",
        yaml_file("- env_id\n- algorithm\n"),
        ConfigError,
        ("config.yaml", "expected a mapping", "['env_id', 'algorithm']"),
    ),
    Row(
        "file-binary",
        yaml_file(b"\xff\xfe\x00binary"),
        ConfigError,
        ("config.yaml", "cannot be read as text"),
    ),
    Row(
        "file-missing",
        lambda: load_config(folder() / "nowhere.yaml"),
        ConfigError,
        ("nowhere.yaml", "neither a file nor a shipped config"),
    ),
]

SET_ROWS = [
    Row(
        "set-no-equals",
        lambda: train("paper_airplane_ppo", "--set", "n_envs"),
        CliError,
        ("--set", "KEY=VALUE", "'n_envs'"),
    ),
    Row(
        "set-into-a-string",
        lambda: train("paper_airplane_ppo", "--set", "env_id.x=1"),
        CliError,
        ("env_id", "fluidsim/PaperAirplane-v0", "not a mapping"),
    ),
    Row(
        "set-seed-negative",
        lambda: train("paper_airplane_ppo", "--set", "seed=-1"),
        CliError,
        ("fluidsim-train: error:", "seed", "-1"),
    ),
    Row(
        "set-eval-seed-negative",
        lambda: train("paper_airplane_ppo", "--set", "eval.seed=-5"),
        CliError,
        ("eval.seed", "-5"),
    ),
    Row(
        "set-device-tpu",
        lambda: train("paper_airplane_ppo", "--set", "device=tpu"),
        CliError,
        ("device", "'tpu'"),
    ),
    Row(
        "set-clip-obs-negative",
        lambda: train("paper_airplane_ppo", "--set", "normalize.clip_obs=-1"),
        CliError,
        ("normalize.clip_obs", "-1"),
    ),
    Row(
        "set-gamma-nan",
        lambda: train("paper_airplane_ppo", "--set", "algorithm.gamma=.nan"),
        CliError,
        ("algorithm.gamma", "nan"),
    ),
    Row(
        "set-not-yaml",
        lambda: train("paper_airplane_ppo", "--set", "algorithm.gamma=["),
        CliError,
        ("--set", "algorithm.gamma=[", "not valid YAML", "line 1"),
    ),
    Row(
        "set-duplicate-key",
        lambda: train("paper_airplane_ppo", "--set", "policy={a: 1, a: 2}"),
        CliError,
        ("--set", "duplicate key", "'a'"),
    ),
    Row(
        "set-unknown-key",
        lambda: train("paper_airplane_ppo", "--set", "algorithm.learnin_rate=0.1"),
        CliError,
        ("unknown key", "algorithm.learnin_rate"),
    ),
    Row(
        "set-schedule-string",
        lambda: train("paper_airplane_ppo", "--set", "algorithm.lr_schedule=cosine"),
        CliError,
        ("algorithm.lr_schedule", "'cosine'"),
    ),
    Row(
        "train-no-config",
        lambda: train(),
        CliError,
        ("a config is required", "--resume"),
    ),
    Row(
        "train-unknown-option",
        lambda: train("paper_airplane_ppo", "--bogus"),
        CliError,
        ("unrecognized arguments", "--bogus"),
    ),
]

PATH_ROWS = [
    Row(
        "run-dir-under-a-file",
        lambda: train("paper_airplane_ppo", "--run-dir", a_file() / "run"),
        CliError,
        ("--run-dir", "a_file/run", "is not a folder"),
    ),
    Row(
        "run-dir-a-file",
        lambda: train("paper_airplane_ppo", "--run-dir", a_file()),
        CliError,
        ("--run-dir", "a_file", "not a folder"),
    ),
    Row(
        "run-dir-in-proc",
        lambda: train("paper_airplane_ppo", "--run-dir", "/proc/fluidsim/run"),
        CliError,
        ("--run-dir", "/proc/fluidsim/run", "cannot write in /proc"),
    ),
    Row(
        "run-dir-in-sys",
        lambda: train("paper_airplane_ppo", "--run-dir", "/sys/fluidsim-run"),
        CliError,
        ("--run-dir", "/sys/fluidsim-run", "cannot write in /sys"),
    ),
    Row(
        "run-dir-holds-a-run",
        lambda: train("paper_airplane_ppo", "--run-dir", run_folder()),
        CliError,
        ("already holds a run", "--resume"),
    ),
    Row(
        "rerun-in-proc",
        lambda: evaluate(folder(), "--rerun", "/proc/fluidsim/episodes.rrd"),
        CliError,
        ("fluidsim-evaluate: error:", "--rerun", "/proc/fluidsim/episodes.rrd", "cannot write"),
    ),
    Row(
        "rerun-a-folder",
        lambda: evaluate(folder(), "--rerun", folder()),
        CliError,
        ("--rerun", "is a folder, not a file"),
    ),
    Row(
        "rerun-under-a-file",
        lambda: evaluate(folder(), "--rerun", a_file() / "episodes.rrd"),
        CliError,
        ("--rerun", "a_file/episodes.rrd", "is not a folder"),
    ),
    Row(
        "evaluate-out-under-a-file",
        lambda: evaluate("--env-id", "fluidsim/PaperAirplane-v0", "--out", a_file() / "x"),
        CliError,
        ("--out", "a_file/x", "is not a folder"),
    ),
    Row(
        "evaluate-out-in-sys",
        lambda: evaluate("--env-id", "fluidsim/PaperAirplane-v0", "--out", "/sys/fluidsim"),
        CliError,
        ("--out", "/sys/fluidsim", "cannot write"),
    ),
]

GARBAGE = b"PK\x03\x04 not really a zip"

RESUME_ROWS = [
    Row(
        "resume-missing-folder",
        resume(lambda: folder() / "nowhere"),
        CliError,
        ("--resume", "nowhere", "run folder not found"),
    ),
    Row(
        "resume-a-file",
        resume(a_file),
        CliError,
        ("--resume", "a_file", "not a folder"),
    ),
    Row(
        "resume-empty-folder",
        resume(folder),
        CliError,
        ("--resume", "not a run folder", "no config.yaml"),
    ),
    Row(
        "resume-nothing-saved",
        resume(run_folder),
        CliError,
        ("nothing saved to resume from", "checkpoints/", "model.safetensors"),
    ),
    Row(
        "resume-corrupt-checkpoint",
        resume(lambda: run_folder({"checkpoints/model_1024_steps.safetensors": GARBAGE})),
        CliError,
        ("skipped checkpoints/model_1024_steps.safetensors", "does not load", "nothing saved"),
    ),
    Row(
        "resume-empty-checkpoint",
        resume(lambda: run_folder({"checkpoints/model_2048_steps.safetensors": b""})),
        CliError,
        ("skipped checkpoints/model_2048_steps.safetensors", "nothing saved"),
    ),
    Row(
        "resume-corrupt-final-model",
        resume(lambda: run_folder({"model.safetensors": GARBAGE})),
        CliError,
        ("skipped model.safetensors", "does not load", "nothing saved"),
    ),
    Row(
        "resume-config-duplicate-key",
        resume(lambda: run_folder({"config.yaml": "n_envs: 2\nn_envs: 4\n"})),
        CliError,
        ("config.yaml", "duplicate key", "'n_envs'"),
    ),
    Row(
        "resume-config-not-a-mapping",
        resume(lambda: run_folder({"config.yaml": "just words\n"})),
        CliError,
        ("config.yaml", "expected a mapping", "'just words'"),
    ),
    Row(
        "resume-bad-override",
        resume(run_folder, "--set", "seed=-1"),
        CliError,
        ("seed", "-1"),
    ),
    Row(
        "resume-with-run-dir",
        resume(run_folder, "--run-dir", "elsewhere"),
        CliError,
        ("--resume RUN", "takes its config and folder from RUN"),
    ),
]


def too_large() -> None:
    """``fluidsim-train`` with more sub-envs than the machine holds (its available memory
    made 1 GiB: the refusal, not the machine, is under test; were it to build the envs,
    the patched ``_build`` fails the row)."""
    with (
        mock.patch.object(train_cli.memory, "available_bytes", return_value=2**30),
        mock.patch.object(train_cli, "_build", side_effect=AssertionError("envs built")),
    ):
        cli(train_cli.main, "paper_airplane_v1_ppo", "--set", "n_envs=100000",
            "--run-dir", folder() / "r", "--no-progress-bar")  # fmt: skip


def zoo_entry() -> Path:
    """A copy of a shipped zoo entry (its model: the policy's weights alone)."""
    import shutil

    zoo = Path(__file__).resolve().parents[2] / "zoo" / "PaperAirplane-v1-ppo"
    return Path(shutil.copytree(zoo, folder() / "entry"))


def sweep(*argv) -> None:
    from fluidsim_envs.rl import sweep as sweep_cli

    cli(sweep_cli.main, *argv)


FAULT_ROWS = [
    Row("evaluate-a-file", lambda: evaluate(a_file()), CliError,
        ("a_file", "is a file, not a run folder")),
    Row("evaluate-pickled-model", lambda: evaluate(run_folder({"model.zip": GARBAGE})),
        CliError, ("model.zip", "an SB3 pickle", "runs any code", "--allow-pickle")),
    Row("resume-pickled-states", resume(lambda: run_folder({"model.zip": GARBAGE})), CliError,
        ("SB3 pickles", "python -m fluidsim_envs.rl.convert", "--allow-pickle")),
    Row("resume-zoo-entry", resume(zoo_entry), CliError,
        ("a zoo entry", "holds a policy to act with", "read-only to --resume", "--run-dir")),
    Row("train-more-than-memory", too_large, CliError,
        ("n_envs=100,000", "GiB", "1.0 GiB available", "lower n_envs")),
    Row("sweep-search-of-another-algorithm",
        lambda: sweep("paper_airplane_v1_ppo", "--search", "sac", "--trials", "2"), CliError,
        ("tunes sac's keys", "algorithm.gradient_steps", "algorithm is ppo", "--search ppo")),
]  # fmt: skip


ROWS = CONFIG_ROWS + FILE_ROWS + SET_ROWS + PATH_ROWS + RESUME_ROWS + FAULT_ROWS


@pytest.mark.parametrize("row", params(ROWS))
def test_bad_run_input(row):
    check(row)
