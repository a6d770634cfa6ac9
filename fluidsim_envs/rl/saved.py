"""What a run saves of a model, its normalization statistics and its replay buffer: numbers
and plain metadata, in files whose loading runs no code.

Each is one `safetensors <https://huggingface.co/docs/safetensors>`_ file: named arrays and a
JSON header (``metadata["fluidsim"]``: what the file is, for which algorithm, the plain
values beside the arrays). Reading one parses a length, JSON and raw bytes; nothing in it
names a class or a function. The policy is rebuilt from the run's ``config.yaml`` (read with
YAML's safe loader; its env must be one of ours) and its weights loaded into it.

SB3's own files (``model.zip``, ``vecnormalize.pkl``, ``replay_buffer.pkl``) are pickles: the
zip's ``data`` carries cloudpickled objects and the statistics are a pickled ``VecNormalize``.
Unpickling runs whatever the file asks for, so a run folder or zoo entry from someone else
would be a program. They are read only by the ``load_pickled_*`` functions here, each
after a warning, which the commands call behind ``--allow-pickle`` (``python -m
fluidsim_envs.rl.convert --allow-pickle`` turns such a folder into these files once).

Layouts, tensors named by a path and their container kept as a skeleton in the header:

- **model** (``model.safetensors``): every state dict SB3 saves of the algorithm (the policy,
  its optimizers) and its torch variables (SAC's entropy coefficient), and ``num_timesteps``;
- **statistics** (``vecnormalize.safetensors``): ``VecNormalize``'s running mean, variance
  and count of observations and of returns, and its settings;
- **replay** (``replay_buffer.safetensors``): the buffer's arrays, its position and fill.
"""

from __future__ import annotations

import json
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from .files import RunError

FORMAT = "fluidsim-envs"
VERSION = 1
HEADER = "fluidsim"  # the metadata key holding the JSON header
SUFFIX = ".safetensors"
PICKLE_WARNING = (
    "{path}: loading an SB3 pickle (--allow-pickle): unpickling runs whatever code the file "
    "carries, with your permissions. Do this only for files you made or whose source you trust."
)

#: the replay buffer's arrays (SB3's ``ReplayBuffer``); ``next_observations`` is absent with
#: ``optimize_memory_usage``
REPLAY_ARRAYS = ("observations", "next_observations", "actions", "rewards", "dones", "timeouts")


POLICY_ONLY = "holds a policy to act with (a zoo entry), not a state to train on"


class NotOurs(RunError):
    """A file that is not one of these (another format, damaged, or of another kind)."""


# --------------------------------------------------------------------------------------------
# the file: arrays and a header


def _write(path: Path, arrays: dict[str, np.ndarray], header: dict[str, Any]) -> None:
    from safetensors.numpy import save_file

    header = {"format": FORMAT, "version": VERSION, **header}
    # (np.ascontiguousarray would make a 0-d array, an optimizer's step count, 1-d)
    arrays = {k: v if v.flags.c_contiguous else v.copy() for k, v in arrays.items()}
    save_file(arrays, str(path), metadata={HEADER: json.dumps(header)})


def read_header(path: Path, kind: str) -> dict[str, Any]:
    """The header of a file of ``kind`` (``model``, ``statistics``, ``replay``), checked; a
    :class:`NotOurs` that names the file and what is wrong otherwise."""
    from safetensors import safe_open

    try:
        with safe_open(str(path), framework="numpy") as f:
            metadata = f.metadata() or {}
    except FileNotFoundError:
        raise NotOurs(f"{path}: missing") from None
    except Exception as e:  # whatever a damaged or foreign file raises
        raise NotOurs(f"{path}: not a saved {kind} ({type(e).__name__}: {e})") from None
    try:
        header = json.loads(metadata[HEADER])
    except (KeyError, ValueError):
        header = None
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        raise NotOurs(f"{path}: not a saved {kind} (no {FORMAT} header)")
    if header.get("kind") != kind:
        raise NotOurs(f"{path}: holds a saved {header.get('kind')!r}, not a {kind}")
    if header.get("version") != VERSION:
        raise NotOurs(f"{path}: format version {header.get('version')!r}; this reads {VERSION}")
    return header


def read_arrays(path: Path, kind: str, prefix: str = "") -> tuple[dict[str, Any], dict[str, Any]]:
    """(header, arrays whose names start with ``prefix``) of a file of ``kind``, checked."""
    from safetensors import safe_open

    header = read_header(path, kind)
    try:
        with safe_open(str(path), framework="numpy") as f:
            arrays = {k: f.get_tensor(k) for k in f.keys() if k.startswith(prefix)}  # noqa: SIM118
    except Exception as e:
        raise NotOurs(f"{path}: damaged {kind} ({type(e).__name__}: {e})") from None
    return header, arrays


# --------------------------------------------------------------------------------------------
# nested state (state dicts, optimizer states) as named arrays and a JSON skeleton


def _flatten(value, name: str, arrays: dict[str, np.ndarray]):
    """``value``'s skeleton: tensors and arrays stored in ``arrays`` under their path (their
    place marked ``{"array": path}``), dicts as key-value pairs (optimizer states are keyed
    by int), numbers, strings, booleans and None as they are."""
    import torch

    if isinstance(value, torch.Tensor):
        arrays[name] = value.detach().cpu().clone().numpy()
        return {"array": name, "torch": True}
    if isinstance(value, np.ndarray):
        arrays[name] = value.copy()
        return {"array": name}
    if isinstance(value, dict):
        return {"pairs": [[k, _flatten(v, f"{name}/{k}", arrays)] for k, v in value.items()]}
    if isinstance(value, list | tuple):
        kind = "list" if isinstance(value, list) else "tuple"  # Adam's betas: a tuple
        return {kind: [_flatten(v, f"{name}/{i}", arrays) for i, v in enumerate(value)]}
    if value is None or isinstance(value, bool | int | float | str):
        return {"value": value}
    raise TypeError(f"{name}: cannot save a {type(value).__name__} as plain data")


def _unflatten(skeleton, arrays: dict[str, np.ndarray], path: Path):
    try:
        return _unflatten_checked(skeleton, arrays, path)
    except (TypeError, ValueError):  # a skeleton of the wrong shape: pairs not pairs, ...
        raise NotOurs(f"{path}: damaged model header") from None


def _unflatten_checked(skeleton, arrays: dict[str, np.ndarray], path: Path):
    import torch

    if not isinstance(skeleton, dict) or len(skeleton) not in (1, 2):
        raise NotOurs(f"{path}: damaged model header")
    if "array" in skeleton:
        if skeleton["array"] not in arrays:
            raise NotOurs(f"{path}: the array {skeleton['array']!r} is missing")
        array = arrays[skeleton["array"]]
        return torch.from_numpy(array.copy()) if skeleton.get("torch") else array
    if "pairs" in skeleton:
        return {k: _unflatten_checked(v, arrays, path) for k, v in skeleton["pairs"]}
    if "list" in skeleton:
        return [_unflatten_checked(v, arrays, path) for v in skeleton["list"]]
    if "tuple" in skeleton:
        return tuple(_unflatten_checked(v, arrays, path) for v in skeleton["tuple"])
    if "value" in skeleton:
        return skeleton["value"]
    raise NotOurs(f"{path}: damaged model header")


# --------------------------------------------------------------------------------------------
# models


def save_model(model, path: Path, policy_only: bool = False) -> None:
    """``model``'s state dicts (policy and optimizers), torch variables and timesteps;
    ``policy_only``: the policy's weights alone, what acting needs (a zoo entry: Adam's
    moments are as large again as the networks)."""
    state_dicts, variables = model._get_torch_save_params()
    if policy_only:
        state_dicts, variables = ["policy"], []
    arrays: dict[str, np.ndarray] = {}
    params = model.get_parameters()
    skeleton = {name: _flatten(params[name], name, arrays) for name in state_dicts}
    tensors = {}
    for name in variables:
        tensors[name] = _flatten(_attribute(model, name), f"variables/{name}", arrays)
    header = {
        "kind": "model",
        "algorithm": type(model).__name__.lower(),
        "observation_shape": list(model.observation_space.shape),
        "action_shape": list(model.action_space.shape),
        "num_timesteps": int(model.num_timesteps),
        "episodes": int(model._episode_num),
        "updates": int(getattr(model, "_n_updates", 0)),
        "policy_only": policy_only,
        "state_dicts": skeleton,
        "variables": tensors,
    }
    _write(path, arrays, header)


def copy_policy(source: Path, path: Path) -> None:
    """The policy's weights of the saved model ``source`` alone, to ``path``."""
    header, arrays = read_arrays(source, "model", prefix="policy/")
    if "policy" not in header.get("state_dicts", {}):
        raise NotOurs(f"{source}: holds no policy")
    header = {k: v for k, v in header.items() if k not in ("format", "version")}
    header |= {"policy_only": True, "variables": {}}
    header["state_dicts"] = {"policy": header["state_dicts"]["policy"]}
    _write(path, arrays, header)


def _attribute(obj, dotted: str):
    for part in dotted.split("."):
        obj = getattr(obj, part)
    return obj


def model_header(path: Path) -> dict[str, Any]:
    """A saved model's header (its algorithm, spaces, timesteps), checked."""
    header = read_header(path, "model")
    for key, kind in (("algorithm", str), ("num_timesteps", int), ("state_dicts", dict)):
        if not isinstance(header.get(key), kind):
            raise NotOurs(f"{path}: damaged model header ({key})")
    return header


def check_model(
    path: Path, algorithm: str, env_id: str | None, observation_shape, action_shape
) -> None:
    """A :class:`~.files.RunError` unless the model at ``path`` is of ``algorithm`` for those
    shapes (a run's ``config.yaml``'s, of its env ``env_id``)."""
    header = model_header(path)
    if header["algorithm"] != algorithm:
        raise RunError(
            f"{path}: config.yaml says algorithm {algorithm!r} but the file holds a "
            f"{header['algorithm']} model"
        )
    shapes = (tuple(header.get("observation_shape", ())), tuple(header.get("action_shape", ())))
    if shapes != (tuple(observation_shape), tuple(action_shape)):
        env = f"config.yaml's env {env_id}" if env_id else "config.yaml's env"
        raise RunError(
            f"{path}: the model was trained on observations {shapes[0]} and actions "
            f"{shapes[1]}, but {env} has {tuple(observation_shape)} and "
            f"{tuple(action_shape)}: the model belongs to another env"
        )


def load_into(model, path: Path) -> None:
    """The saved state at ``path`` into ``model`` (built from the same config): weights,
    optimizer states, torch variables and timesteps."""
    header = model_header(path)
    if header.get("policy_only"):
        raise NotOurs(f"{path}: {POLICY_ONLY}")
    check_model(path, type(model).__name__.lower(), None, model.observation_space.shape,
                model.action_space.shape)  # fmt: skip
    state_dicts, variables = model._get_torch_save_params()
    theirs = (sorted(header["state_dicts"]), sorted(header.get("variables", {})))
    if theirs != (sorted(state_dicts), sorted(variables)):  # names only from the model's own
        raise NotOurs(
            f"{path}: holds {theirs[0]} and {theirs[1]}, the config's model "
            f"{sorted(state_dicts)} and {sorted(variables)}"
        )
    _, arrays = read_arrays(path, "model")
    params = {n: _unflatten(s, arrays, path) for n, s in header["state_dicts"].items()}
    try:
        model.set_parameters(params, exact_match=True, device=model.device)
        for name, skeleton in header.get("variables", {}).items():
            _attribute(model, name).data.copy_(_unflatten(skeleton, arrays, path))
    except (ValueError, RuntimeError, KeyError, AttributeError) as e:
        raise NotOurs(f"{path}: does not fit the config's model ({e})") from None
    model.num_timesteps = header["num_timesteps"]
    model._episode_num = int(header.get("episodes", 0))
    model._n_updates = int(header.get("updates", 0))


def load_policy_weights(policy, path: Path) -> None:
    """The policy's weights (its state dict alone) from a saved model into ``policy``."""
    header = model_header(path)
    if "policy" not in header["state_dicts"]:
        raise NotOurs(f"{path}: holds no policy")
    _, arrays = read_arrays(path, "model", prefix="policy/")
    state = _unflatten(header["state_dicts"]["policy"], arrays, path)
    try:
        policy.load_state_dict(state, strict=True)
    except RuntimeError as e:
        raise NotOurs(f"{path}: does not fit the config's policy ({e})") from None


# --------------------------------------------------------------------------------------------
# normalization statistics

_STATISTICS_SETTINGS = ("norm_obs", "norm_reward", "clip_obs", "clip_reward", "gamma", "epsilon")


def save_statistics(vec_normalize, path: Path) -> None:
    """``VecNormalize``'s running statistics and settings."""
    arrays = {}
    for name in ("obs_rms", "ret_rms"):
        rms = getattr(vec_normalize, name)
        if isinstance(rms, dict):
            raise TypeError(f"{name}: only Box observations are saved, not a Dict space's")
        # (the returns' mean is a NumPy scalar once updated)
        arrays[f"{name}/mean"] = np.asarray(rms.mean, dtype=np.float64)
        arrays[f"{name}/var"] = np.asarray(rms.var, dtype=np.float64)
        arrays[f"{name}/count"] = np.asarray([rms.count], dtype=np.float64)
    settings = {k: _plain(getattr(vec_normalize, k)) for k in _STATISTICS_SETTINGS}
    _write(path, arrays, {"kind": "statistics", "settings": settings})


def _non_negative(value) -> bool:
    """A finite number (or array of them) >= 0, not a boolean."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.ndarray):
        return False
    x = np.asarray(value, dtype=float)
    return bool(np.isfinite(x).all() and (x >= 0).all())


def _plain(value):
    return value.item() if isinstance(value, np.generic) else value


def load_statistics(path: Path, venv):
    """A ``VecNormalize`` over ``venv`` with the statistics and settings saved at ``path``;
    a :class:`NotOurs` where they do not fit ``venv``'s observations."""
    from stable_baselines3.common.vec_env import VecNormalize

    header, arrays = read_arrays(path, "statistics")
    settings = header.get("settings")
    if not isinstance(settings, dict) or set(settings) != set(_STATISTICS_SETTINGS):
        raise NotOurs(f"{path}: damaged statistics header")
    for key, value in settings.items():  # flags, then finite non-negative numbers
        flag = key.startswith("norm_")
        ok = isinstance(value, bool) if flag else _non_negative(value)
        if not ok:
            raise NotOurs(f"{path}: statistics setting {key} = {value!r} is not a valid value")
    vec_normalize = VecNormalize(venv, **settings)
    for name in ("obs_rms", "ret_rms"):
        rms = getattr(vec_normalize, name)
        try:
            mean, var = arrays[f"{name}/mean"], arrays[f"{name}/var"]
            count = float(arrays[f"{name}/count"][0])
        except (KeyError, IndexError):
            raise NotOurs(f"{path}: damaged statistics ({name} missing)") from None
        if not (np.isfinite(mean).all() and _non_negative(var) and count > 0):
            raise NotOurs(f"{path}: damaged statistics ({name}: not finite, or a negative "
                          "variance or count)")  # fmt: skip
        if mean.shape != rms.mean.shape or var.shape != rms.var.shape:
            raise NotOurs(
                f"{path}: statistics of {name} for shape {mean.shape}, but the env's is "
                f"{rms.mean.shape}: they belong to another env"
            )
        rms.mean, rms.var, rms.count = mean, var, count
    return vec_normalize


# --------------------------------------------------------------------------------------------
# replay buffers


def save_replay(buffer, path: Path) -> None:
    """An off-policy model's replay buffer: its arrays, position and fill."""
    arrays = {k: getattr(buffer, k) for k in REPLAY_ARRAYS if getattr(buffer, k, None) is not None}
    header = {"kind": "replay", "pos": int(buffer.pos), "full": bool(buffer.full)}
    _write(path, arrays, header)


def load_replay(buffer, path: Path) -> None:
    """The replay buffer saved at ``path`` into ``buffer`` (built from the same config)."""
    header, arrays = read_arrays(path, "replay")
    ours = {k for k in REPLAY_ARRAYS if getattr(buffer, k, None) is not None}
    if set(arrays) != ours:
        raise NotOurs(f"{path}: holds {sorted(arrays)}, the config's buffer {sorted(ours)}")
    for name, array in arrays.items():
        mine = getattr(buffer, name)
        if array.shape != mine.shape or array.dtype != mine.dtype:
            raise NotOurs(
                f"{path}: {name} of {array.dtype} {array.shape}, the config's buffer "
                f"{mine.dtype} {mine.shape} (buffer_size or n_envs changed?)"
            )
    pos, full = header.get("pos"), header.get("full")
    if not (isinstance(pos, int) and 0 <= pos < buffer.buffer_size and isinstance(full, bool)):
        raise NotOurs(f"{path}: damaged replay header (pos {pos!r}, full {full!r})")
    for name, array in arrays.items():
        getattr(buffer, name)[...] = array
    buffer.pos, buffer.full = pos, full


# --------------------------------------------------------------------------------------------
# SB3's pickles, behind --allow-pickle


def pickle_warning(path: Path) -> None:
    print(PICKLE_WARNING.format(path=path), file=sys.stderr, flush=True)


def load_pickled_model(algorithm_cls, path: Path):
    """An SB3 model zip (a pickle: see the module's docstring), after the warning."""
    pickle_warning(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # SB3's own warnings about versions
        return algorithm_cls.load(path, device="cpu")


def load_pickled_replay(path: Path):
    """A pickled replay buffer (SB3's ``replay_buffer.pkl``), after the warning."""
    from stable_baselines3.common.save_util import load_from_pkl

    pickle_warning(path)
    return load_from_pkl(path)


def load_pickled_vec_normalize(path: Path):
    """A pickled ``VecNormalize`` without an env under it (to convert), after the warning."""
    import pickle

    pickle_warning(path)
    with path.open("rb") as f:
        return pickle.load(f)


def load_pickled_statistics(path: Path, venv):
    """A pickled ``VecNormalize`` (SB3's ``vecnormalize.pkl``) over ``venv``, after the
    warning."""
    from stable_baselines3.common.vec_env import VecNormalize

    pickle_warning(path)
    return VecNormalize.load(str(path), venv)
