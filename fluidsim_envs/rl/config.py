"""Training configs: YAML files (one per env x algorithm; the shipped ones in
``fluidsim_envs/configs/``, found by name) loaded with ``yaml.safe_load`` into frozen
dataclasses. The keys are Stable-Baselines3's own hyperparameter names, grouped in sections;
rl-zoo3 cannot load these files (its hyperparameter files are keyed by env id, with policy
kwargs as Python strings).

Every key is checked: an unknown one is an error that names it and lists the valid ones, a
value of the wrong type an error that names the key and the value. ``--set key=value``
overrides reach nested keys through dots (``algorithm.learning_rate=1.0e-4``,
``env_kwargs.max_episode_steps=300``); each value is read as YAML.

    >>> cfg = config_from_dict({"env_id": "fluidsim/PaperAirplane-v0",
    ...                         "algorithm": {"name": "ppo", "n_steps": 128}})
    >>> cfg.algorithm.n_steps, cfg.policy.activation_fn
    (128, 'tanh')
    >>> config_from_dict(config_to_dict(cfg)) == cfg
    True
"""

from __future__ import annotations

import dataclasses
import re
import types
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import yaml

from ..physics import checks as CK

#: activation functions a config may name, and their ``torch.nn`` classes
ACTIVATIONS = {
    "tanh": "Tanh",
    "relu": "ReLU",
    "elu": "ELU",
    "leaky_relu": "LeakyReLU",
    "gelu": "GELU",
    "silu": "SiLU",
}


class ConfigError(ValueError):
    """A config that cannot be used: the message names the offending key and value."""


# --------------------------------------------------------------------------------------------
# the config


@dataclass(frozen=True)
class PPOConfig:
    """Stable-Baselines3 PPO hyperparameters (the names of ``PPO.__init__``)."""

    name: Literal["ppo"] = "ppo"
    learning_rate: float = 3.0e-4
    lr_schedule: Literal["constant", "linear"] = "constant"  # linear: to 0 at the end
    n_steps: int = 256  # per env and rollout
    batch_size: int = 2048
    n_epochs: int = 10
    gamma: float = 0.99
    gae_lambda: float = 0.95
    clip_range: float = 0.2
    clip_range_vf: float | None = None
    normalize_advantage: bool = True
    ent_coef: float = 0.0
    vf_coef: float = 0.5
    max_grad_norm: float = 0.5
    use_sde: bool = False
    sde_sample_freq: int = -1
    target_kl: float | None = None

    def check(self, n_envs: int) -> None:
        _positive(self, "learning_rate", "n_steps", "batch_size", "n_epochs", "clip_range")
        _unit(self, "gamma", "gae_lambda")
        if self.batch_size > self.n_steps * n_envs:
            raise ConfigError(
                f"algorithm.batch_size ({self.batch_size}) must be at most n_steps x n_envs "
                f"({self.n_steps} x {n_envs} = {self.n_steps * n_envs})"
            )


@dataclass(frozen=True)
class SACConfig:
    """Stable-Baselines3 SAC hyperparameters (the names of ``SAC.__init__``)."""

    name: Literal["sac"] = "sac"
    learning_rate: float = 3.0e-4
    lr_schedule: Literal["constant", "linear"] = "constant"
    buffer_size: int = 1_000_000
    learning_starts: int = 10_000
    batch_size: int = 256
    tau: float = 0.005
    gamma: float = 0.99
    train_freq: int = 1  # env steps (of every env) between updates
    gradient_steps: int = -1  # -1: as many as transitions collected
    ent_coef: str | float = "auto"  # "auto", "auto_0.1" (initial value) or a fixed float
    target_update_interval: int = 1
    target_entropy: str | float = "auto"
    use_sde: bool = False
    sde_sample_freq: int = -1
    use_sde_at_warmup: bool = False

    def check(self, n_envs: int) -> None:
        _positive(self, "learning_rate", "buffer_size", "batch_size", "tau", "train_freq")
        _unit(self, "gamma", "tau")
        if self.learning_starts < 0:
            raise ConfigError(f"algorithm.learning_starts must be >= 0, got {self.learning_starts}")
        if self.gradient_steps == 0 or self.gradient_steps < -1:
            raise ConfigError(
                f"algorithm.gradient_steps must be -1 or positive, got {self.gradient_steps}"
            )
        for key in ("ent_coef", "target_entropy"):
            value = getattr(self, key)
            if isinstance(value, str) and not (value == "auto" or value.startswith("auto_")):
                raise ConfigError(
                    f"algorithm.{key} must be a number, 'auto' or 'auto_<init>', got {value!r}"
                )


ALGORITHMS: dict[str, type] = {"ppo": PPOConfig, "sac": SACConfig}
AlgorithmConfig = PPOConfig | SACConfig


@dataclass(frozen=True)
class PolicyConfig:
    """The policy network (SB3 ``policy_kwargs``)."""

    # one list for every head, or per head: {pi: [...], vf: [...]} (PPO), {pi, qf} (SAC)
    net_arch: tuple[int, ...] | dict[str, tuple[int, ...]] = (64, 64)
    activation_fn: str = "tanh"  # a name from ACTIVATIONS
    log_std_init: float | None = None  # initial log std of the Gaussian actions
    ortho_init: bool | None = None  # PPO only: orthogonal initialization (SB3 default: on)


@dataclass(frozen=True)
class NormalizeConfig:
    """``VecNormalize``: running normalization of observations and rewards (its ``gamma`` is
    the algorithm's)."""

    enabled: bool = True
    norm_obs: bool = True
    norm_reward: bool = True
    clip_obs: float = 10.0
    clip_reward: float = 10.0
    epsilon: float = 1.0e-8


@dataclass(frozen=True)
class EvalConfig:
    """Periodic evaluation on a separate env of ``n_episodes`` sub-envs, one episode each,
    with deterministic actions; it is reseeded with ``seed`` before every evaluation so each
    one flies the same episodes."""

    freq: int = 50_000  # env steps (all envs together) between evaluations; 0: none
    n_episodes: int = 16
    seed: int = 1_000_000


@dataclass(frozen=True)
class CheckpointConfig:
    """Checkpoints (model and normalization statistics) that ``--resume`` continues from."""

    freq: int = 100_000  # env steps (all envs together) between checkpoints; 0: none
    save_replay_buffer: bool = False  # off-policy only; large


@dataclass(frozen=True)
class TrainConfig:
    """One training run: an env, an algorithm and how to train and evaluate it."""

    env_id: str
    algorithm: AlgorithmConfig
    env_kwargs: dict[str, Any] = field(default_factory=dict)  # the env's parameters
    n_envs: int = 16
    total_timesteps: int = 1_000_000
    seed: int = 0  # the model's seed; env i gets SeedSequence(seed).spawn(n_envs)[i]
    device: str = "cpu"
    policy: PolicyConfig = PolicyConfig()
    normalize: NormalizeConfig = NormalizeConfig()
    eval: EvalConfig = EvalConfig()
    checkpoint: CheckpointConfig = CheckpointConfig()

    @property
    def env_name(self) -> str:
        """The id without its namespace: ``PaperAirplane-v0``."""
        return self.env_id.rsplit("/", 1)[-1]


# --------------------------------------------------------------------------------------------
# loading


#: where the shipped configs live (inside the package, so an installed wheel has them)
SHIPPED = Path(__file__).resolve().parents[1] / "configs"


def shipped_configs() -> dict[str, Path]:
    """The configs that ship with the package, by name (``paper_airplane_ppo``, ...)."""
    return {p.stem: p for p in sorted(SHIPPED.glob("*.yaml"))}


def find_config(name_or_path: str | Path) -> Path:
    """A config file: ``name_or_path`` itself if it is a file, else the shipped config of
    that name (with or without ``.yaml``); an error that lists the shipped ones otherwise."""
    path = Path(name_or_path)
    if path.is_file():
        return path
    shipped = shipped_configs()
    name = path.name.removesuffix(".yaml")
    if path.parent == Path(".") and name in shipped:
        return shipped[name]
    raise ConfigError(
        f"config not found: {str(name_or_path)!r} is neither a file nor a shipped config "
        f"({', '.join(shipped)})"
    )


def load_config(path: str | Path, overrides: typing.Sequence[str] = ()) -> TrainConfig:
    """Read the YAML config at ``path`` (a file, or a shipped config's name), apply
    ``key=value`` overrides, and check it."""
    path = find_config(path)
    try:
        raw = yaml.safe_load(path.read_text())
    except yaml.YAMLError as e:
        raise ConfigError(f"{path}: not valid YAML: {e}") from e
    if not isinstance(raw, dict):
        raise ConfigError(f"{path}: expected a mapping of keys at the top, got {raw!r}")
    try:
        return config_from_dict(apply_overrides(raw, overrides))
    except ConfigError as e:
        raise ConfigError(f"{path}: {e}") from None


# a number in exponent form without a dot (5e-3): a string to YAML 1.1, a number to us
_EXPONENT = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)[eE][+-]?\d+")


def parse_assignment(item: str, flag: str) -> tuple[str, Any]:
    """``KEY=VALUE`` as ``(key, value)``, the value read as YAML (``[0, 3]`` a list, ``rk4`` a
    string, ``0.005`` and ``5e-3`` numbers); ``flag`` names the option in errors.

    >>> parse_assignment("dt=5e-3", "--env")
    ('dt', 0.005)
    """
    key, sep, text = item.partition("=")
    key = key.strip()
    if not sep or not key:
        raise ConfigError(f"{flag} expects KEY=VALUE, got {item!r}")
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError as e:
        raise ConfigError(f"{flag} {item!r}: the value is not valid YAML: {e}") from None
    if isinstance(value, str) and _EXPONENT.fullmatch(value.strip()):
        value = float(value)
    return key, value


def apply_overrides(raw: dict[str, Any], overrides: typing.Sequence[str]) -> dict[str, Any]:
    """A copy of ``raw`` with each ``a.b.c=value`` set (``value`` read as YAML)."""
    import copy

    out = copy.deepcopy(raw)
    for item in overrides:
        key, value = parse_assignment(item, "--set")
        *parents, last = key.split(".")
        node = out
        for depth, part in enumerate(parents):
            node = node.setdefault(part, {})
            if not isinstance(node, dict):
                where = ".".join(parents[: depth + 1])
                raise ConfigError(f"--set {item!r}: {where} is {node!r}, not a mapping")
        node[last] = value
    return out


def config_from_dict(raw: dict[str, Any]) -> TrainConfig:
    """Build and check a :class:`TrainConfig` from plain data."""
    cfg = _build(TrainConfig, raw, "")
    _check(cfg)
    return cfg


def config_to_dict(cfg: Any) -> Any:
    """Plain data (dicts, lists, numbers, strings) that :func:`config_from_dict` reads back."""
    if dataclasses.is_dataclass(cfg):
        return {f.name: config_to_dict(getattr(cfg, f.name)) for f in dataclasses.fields(cfg)}
    if isinstance(cfg, dict):
        return {k: config_to_dict(v) for k, v in cfg.items()}
    if isinstance(cfg, (tuple, list)):
        return [config_to_dict(v) for v in cfg]
    return cfg


def dump_config(cfg: TrainConfig, path: str | Path) -> None:
    Path(path).write_text(yaml.safe_dump(config_to_dict(cfg), sort_keys=False))


# --------------------------------------------------------------------------------------------
# typed conversion


def _where(prefix: str, key: str) -> str:
    return f"{prefix}.{key}" if prefix else key


def _build(cls: type, raw: Any, prefix: str) -> Any:
    """Instance of dataclass ``cls`` from mapping ``raw``; unknown keys are errors."""
    label = prefix or "the config"
    if not isinstance(raw, dict):
        raise ConfigError(f"{label} must be a mapping, got {raw!r}")
    fields = {f.name: f for f in dataclasses.fields(cls)}
    unknown = [k for k in raw if k not in fields]
    if unknown:
        raise ConfigError(
            f"unknown key {_where(prefix, str(unknown[0]))!r} in {label}; valid keys: "
            f"{', '.join(fields)}"
        )
    hints = typing.get_type_hints(cls)
    kwargs = {}
    for name, f in fields.items():
        where = _where(prefix, name)
        if name not in raw:
            if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
                raise ConfigError(f"missing required key {where!r}")
            continue
        if name == "algorithm" and cls is TrainConfig:
            kwargs[name] = _build_algorithm(raw[name], where)
        else:
            kwargs[name] = _convert(raw[name], hints[name], where)
    return cls(**kwargs)


def _build_algorithm(raw: Any, where: str) -> AlgorithmConfig:
    if not isinstance(raw, dict) or "name" not in raw:
        raise ConfigError(f"{where} must be a mapping with a name ({', '.join(ALGORITHMS)})")
    name = raw["name"]
    if not isinstance(name, str) or name.lower() not in ALGORITHMS:
        raise ConfigError(f"{where}.name must be one of {list(ALGORITHMS)}, got {name!r}")
    return _build(ALGORITHMS[name.lower()], {**raw, "name": name.lower()}, where)


ITEMS = {int: "integers", float: "numbers", str: "strings", bool: "booleans"}


def _type_name(tp: Any) -> str:
    if tp is type(None):
        return "null"
    if typing.get_origin(tp) is Literal:
        return " or ".join(repr(a) for a in typing.get_args(tp))
    if typing.get_origin(tp) in (typing.Union, types.UnionType):
        return " or ".join(_type_name(a) for a in typing.get_args(tp))
    if typing.get_origin(tp) is tuple:
        item = typing.get_args(tp)[0]
        return f"a list of {ITEMS.get(item, _type_name(item))}"
    if typing.get_origin(tp) is dict:
        return f"a mapping of {_type_name(typing.get_args(tp)[1])}"
    if dataclasses.is_dataclass(tp):
        return "a mapping"
    return {int: "an integer", float: "a number", bool: "true or false", str: "a string"}.get(
        tp, str(tp)
    )


def _convert(value: Any, tp: Any, where: str) -> Any:
    origin = typing.get_origin(tp)
    if tp is Any:
        return value
    if dataclasses.is_dataclass(tp):
        return _build(tp, value, where)
    if origin in (typing.Union, types.UnionType):
        for option in typing.get_args(tp):
            try:
                return _convert(value, option, where)
            except ConfigError:
                continue
        raise _type_error(value, tp, where)
    if tp is type(None):
        if value is None:
            return None
        raise _type_error(value, tp, where)
    if origin is Literal:
        if value in typing.get_args(tp):
            return value
        raise _type_error(value, tp, where)
    if origin is tuple:
        if not isinstance(value, (list, tuple)):
            raise _type_error(value, tp, where)
        (item,) = (a for a in typing.get_args(tp) if a is not Ellipsis)
        return tuple(_convert(v, item, f"{where}[{i}]") for i, v in enumerate(value))
    if origin is dict:
        if not isinstance(value, dict):
            raise _type_error(value, tp, where)
        _, item = typing.get_args(tp)
        return {str(k): _convert(v, item, f"{where}.{k}") for k, v in value.items()}
    if tp is bool:
        if isinstance(value, bool):
            return value
        raise _type_error(value, tp, where)
    if tp is int:
        if isinstance(value, int) and not isinstance(value, bool):
            return value
        raise _type_error(value, tp, where)
    if tp is float:
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return float(value)
        raise _type_error(value, tp, where)
    if tp is str:
        if isinstance(value, str):
            return value
        raise _type_error(value, tp, where)
    raise TypeError(f"config type {tp} of {where} is not supported")  # a bug here, not input


def _type_error(value: Any, tp: Any, where: str) -> ConfigError:
    hint = ""
    if isinstance(value, str):
        try:
            float(value)
            hint = " (YAML reads 3e-4 as a string: write 3.0e-4)"
        except ValueError:
            pass
    return ConfigError(f"{where} must be {_type_name(tp)}, got {value!r}{hint}")


# --------------------------------------------------------------------------------------------
# checks across fields


def _positive(obj: Any, *keys: str) -> None:
    for key in keys:
        CK.number("algorithm", key, getattr(obj, key), gt=0, error=ConfigError)


def _unit(obj: Any, *keys: str) -> None:
    for key in keys:
        CK.number("algorithm", key, getattr(obj, key), gt=0.0, le=1.0, error=ConfigError)


def _check(cfg: TrainConfig) -> None:
    for key in ("n_envs", "total_timesteps"):
        if getattr(cfg, key) < 1:
            raise ConfigError(f"{key} must be at least 1, got {getattr(cfg, key)}")
    for key, low in (("eval.freq", 0), ("eval.n_episodes", 1), ("checkpoint.freq", 0)):
        section, name = key.split(".")
        value = getattr(getattr(cfg, section), name)
        if value < low:
            raise ConfigError(f"{key} must be at least {low}, got {value}")
    cfg.algorithm.check(cfg.n_envs)
    _check_policy(cfg.policy, cfg.algorithm.name)
    _check_env(cfg.env_id, cfg.env_kwargs)


def _check_policy(policy: PolicyConfig, algo: str) -> None:
    if policy.activation_fn not in ACTIVATIONS:
        raise ConfigError(
            f"policy.activation_fn must be one of {list(ACTIVATIONS)}, got {policy.activation_fn!r}"
        )
    heads = {"ppo": ("pi", "vf"), "sac": ("pi", "qf")}[algo]
    arch = policy.net_arch
    layers = arch.values() if isinstance(arch, dict) else [arch]
    if isinstance(arch, dict) and sorted(arch) != sorted(heads):
        raise ConfigError(
            f"policy.net_arch for {algo} must name the heads {list(heads)}, got {list(arch)}"
        )
    if any(n < 1 for layer in layers for n in layer):
        raise ConfigError(f"policy.net_arch layer sizes must be positive, got {arch!r}")
    if policy.ortho_init is not None and algo != "ppo":
        raise ConfigError(f"policy.ortho_init applies to ppo only, not {algo}")


def resolved(cfg: TrainConfig) -> TrainConfig:
    """``cfg`` with ``env_kwargs`` holding every parameter of the env, defaults filled in: a
    run folder's config then replays the same env whatever the defaults become."""
    params = _check_env(cfg.env_id, cfg.env_kwargs)
    kwargs = {f.name: getattr(params, f.name) for f in dataclasses.fields(params)}
    return dataclasses.replace(cfg, env_kwargs=config_to_dict(kwargs))


def _check_env(env_id: str, env_kwargs: dict[str, Any]):
    """The env id is registered and its parameters accept ``env_kwargs`` (built here, so a
    bad parameter is reported before any training starts); returns the parameters."""
    import gymnasium as gym
    from gymnasium.envs.registration import load_env_creator

    import fluidsim_envs  # noqa: F401  (registers the ids)
    from fluidsim_envs.scenes.base import make_params

    ours = sorted(k for k in gym.registry if k.startswith("fluidsim/"))
    if env_id not in ours:
        raise ConfigError(f"env_id must be one of {ours}, got {env_id!r}")
    vector_cls = load_env_creator(gym.spec(env_id).vector_entry_point)
    try:
        return make_params(vector_cls.Params, env_kwargs)
    except (TypeError, ValueError) as e:
        raise ConfigError(f"env_kwargs: {e}") from None
