"""Training configs: YAML files (one per env x algorithm; the shipped ones in
``configs/``, found by name) loaded with a safe YAML loader that refuses a key
given twice (:class:`UniqueKeyLoader`) into frozen dataclasses. The keys are
Stable-Baselines3's own hyperparameter names, grouped in sections; rl-zoo3 cannot load these
files (its hyperparameter files are keyed by env id, with policy kwargs as Python strings).

Every key is checked before anything is written: an unknown one is an error that names it and
lists the valid ones, a value of the wrong type an error that names the key and the value,
every number must be finite and within its field's range (each section's ``RANGES``; seeds
in [0, 2**32 - 1]), and the device must exist (``check_device``). NumPy scalars are accepted
where numbers are. ``--set key=value`` overrides reach nested keys through dots
(``algorithm.learning_rate=1.0e-4``, ``env_kwargs.max_episode_steps=300``); each value is
read as YAML.

    >>> cfg = config_from_dict({"env_id": "fluidsim/PaperAirplane-v0",
    ...                         "algorithm": {"name": "ppo", "n_steps": 128}})
    >>> cfg.algorithm.n_steps, cfg.policy.activation_fn
    (128, 'tanh')
    >>> config_from_dict(config_to_dict(cfg)) == cfg
    True
"""

from __future__ import annotations

import dataclasses
import math
import re
import types
import typing
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar, Literal

import numpy as np
import yaml

from . import files

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


#: the largest seed: NumPy's and torch's global seeding take 32-bit seeds
SEED_MAX = 2**32 - 1


@dataclass(frozen=True)
class Range:
    """The bounds of a numeric field (inclusive unless ``gt`` / ``lt``), as a message says
    them: `` >= 1``, `` in (0, 1]``."""

    ge: float | None = None
    gt: float | None = None
    le: float | None = None
    lt: float | None = None

    def holds(self, x: float) -> bool:
        return not (
            (self.ge is not None and x < self.ge)
            or (self.gt is not None and x <= self.gt)
            or (self.le is not None and x > self.le)
            or (self.lt is not None and x >= self.lt)
        )

    def __str__(self) -> str:
        low = (f"[{self.ge!r}", f" >= {self.ge!r}") if self.ge is not None else None
        low = (f"({self.gt!r}", f" > {self.gt!r}") if self.gt is not None else low
        high = (f"{self.le!r}]", f" <= {self.le!r}") if self.le is not None else None
        high = (f"{self.lt!r})", f" < {self.lt!r}") if self.lt is not None else high
        if low and high:
            return f" in {low[0]}, {high[0]}"
        return (low or high or ("", ""))[1]


POSITIVE = Range(gt=0)
AT_LEAST_1 = Range(ge=1)
NON_NEGATIVE = Range(ge=0)
UNIT = Range(gt=0, le=1)  # a discount or a mixing factor
SEED = Range(ge=0, le=SEED_MAX)
SDE_FREQ = Range(ge=-1)  # -1 (and 0): new noise only at each rollout's start


# --------------------------------------------------------------------------------------------
# the config
#
# Each section's RANGES bounds its numeric fields; a number field without an entry must only
# be finite (NaN and inf are refused everywhere).


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

    RANGES: ClassVar[dict[str, Range]] = {
        "learning_rate": POSITIVE,
        "n_steps": AT_LEAST_1,
        "batch_size": AT_LEAST_1,
        "n_epochs": AT_LEAST_1,
        "gamma": UNIT,
        "gae_lambda": Range(ge=0, le=1),
        "clip_range": POSITIVE,
        "clip_range_vf": POSITIVE,
        "ent_coef": NON_NEGATIVE,
        "vf_coef": NON_NEGATIVE,
        "max_grad_norm": POSITIVE,
        "sde_sample_freq": SDE_FREQ,
        "target_kl": POSITIVE,
    }

    def check(self, n_envs: int | None) -> None:
        """``n_envs`` None: the checks of single keys only (not the batch against the
        rollout of ``n_steps x n_envs``)."""
        if n_envs is not None and self.batch_size > self.n_steps * n_envs:
            raise ConfigError(
                f"algorithm.batch_size ({self.batch_size}) must be at most n_steps x n_envs "
                f"({self.n_steps} x {n_envs} = {self.n_steps * n_envs})"
            )
        if self.normalize_advantage and self.batch_size < 2:
            # SB3 normalizes the advantages over each batch: one sample has no spread
            raise ConfigError(
                f"algorithm.batch_size must be at least 2 with normalize_advantage, "
                f"got {self.batch_size}"
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
    target_entropy: str | float = "auto"  # "auto" (-dim(actions)) or a number
    use_sde: bool = False
    sde_sample_freq: int = -1
    use_sde_at_warmup: bool = False

    RANGES: ClassVar[dict[str, Range]] = {
        "learning_rate": POSITIVE,
        "buffer_size": AT_LEAST_1,
        "learning_starts": NON_NEGATIVE,
        "batch_size": AT_LEAST_1,
        "tau": UNIT,
        "gamma": UNIT,
        "train_freq": AT_LEAST_1,
        "gradient_steps": Range(ge=-1),
        "ent_coef": POSITIVE,
        "target_update_interval": AT_LEAST_1,
        "sde_sample_freq": SDE_FREQ,
    }

    def check(self, n_envs: int | None) -> None:
        if self.gradient_steps == 0:
            raise ConfigError("algorithm.gradient_steps must be -1 or positive, got 0")
        if isinstance(self.ent_coef, str) and not _auto_ent_coef(self.ent_coef):
            raise ConfigError(
                f"algorithm.ent_coef must be a number > 0, 'auto' or 'auto_<init>' with "
                f"<init> > 0, got {self.ent_coef!r}"
            )
        if isinstance(self.target_entropy, str) and self.target_entropy != "auto":
            raise ConfigError(
                f"algorithm.target_entropy must be a number or 'auto', got {self.target_entropy!r}"
            )


def _auto_ent_coef(text: str) -> bool:
    """``auto``, or ``auto_<init>`` with a finite initial value > 0 (what SB3 accepts)."""
    if text == "auto":
        return True
    head, _, init = text.partition("_")
    try:
        value = float(init)
    except ValueError:
        return False
    return head == "auto" and math.isfinite(value) and value > 0


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

    RANGES: ClassVar[dict[str, Range]] = {}


@dataclass(frozen=True)
class NormalizeConfig:
    """``VecNormalize``: running normalization of observations and rewards (its ``gamma`` is
    the algorithm's)."""

    enabled: bool = True
    norm_obs: bool = True
    norm_reward: bool = True
    clip_obs: float = 10.0  # > 0: normalized observations are clipped to [-clip_obs, clip_obs]
    clip_reward: float = 10.0
    epsilon: float = 1.0e-8

    RANGES: ClassVar[dict[str, Range]] = {
        "clip_obs": POSITIVE,
        "clip_reward": POSITIVE,
        "epsilon": POSITIVE,
    }


@dataclass(frozen=True)
class EvalConfig:
    """Periodic evaluation on a separate env of ``n_episodes`` sub-envs, one episode each,
    with deterministic actions; it is reseeded with ``seed`` before every evaluation so each
    one flies the same episodes."""

    freq: int = 50_000  # env steps (all envs together) between evaluations; 0: none
    n_episodes: int = 16
    seed: int = 1_000_000

    RANGES: ClassVar[dict[str, Range]] = {
        "freq": NON_NEGATIVE,
        "n_episodes": AT_LEAST_1,
        "seed": SEED,
    }


@dataclass(frozen=True)
class CheckpointConfig:
    """Checkpoints (model and normalization statistics) that ``--resume`` continues from."""

    freq: int = 100_000  # env steps (all envs together) between checkpoints; 0: none
    save_replay_buffer: bool = False  # off-policy only; large

    RANGES: ClassVar[dict[str, Range]] = {"freq": NON_NEGATIVE}


#: who a warm start copies: the scene's tuned pilot, or its planner (an oracle of the present)
TEACHERS = ("pilot", "planner")


@dataclass(frozen=True)
class WarmStartConfig:
    """A warm start before RL (``rl/warm_start.py``; PPO): the ``teacher`` (the scene's tuned
    ``pilot``, or its ``planner`` at its default budget) flies the training envs for ``steps``
    env steps (all envs together), then the policy's mean action is fitted to the teacher's
    actions and its value function to the returns they earned (``epochs`` passes, minibatches
    of ``batch_size``, Adam at ``learning_rate``). The teacher's steps are not the run's
    timesteps: run.yaml counts them apart. 0 steps: none."""

    steps: int = 0
    teacher: str = "pilot"
    epochs: int = 10
    batch_size: int = 4096
    learning_rate: float = 1.0e-3

    RANGES: ClassVar[dict[str, Range]] = {
        "steps": NON_NEGATIVE,
        "epochs": AT_LEAST_1,
        "batch_size": AT_LEAST_1,
        "learning_rate": POSITIVE,
    }


@dataclass(frozen=True)
class StageConfig:
    """A curriculum stage: ``timesteps`` env steps (all envs together) trained on episodes
    of ``env_kwargs`` (set on top of the run's own ``env_kwargs``). The evaluations fly the
    run's own episodes throughout, so the learning curve is the task's."""

    timesteps: int
    env_kwargs: dict[str, Any] = field(default_factory=dict)

    RANGES: ClassVar[dict[str, Range]] = {"timesteps": AT_LEAST_1}


@dataclass(frozen=True)
class TrainConfig:
    """One training run: an env, an algorithm and how to train and evaluate it."""

    env_id: str
    algorithm: AlgorithmConfig
    env_kwargs: dict[str, Any] = field(default_factory=dict)  # the env's parameters
    n_envs: int = 16
    total_timesteps: int = 1_000_000
    seed: int = 0  # the model's; env i draws seeding.root(seed, "training").spawn(n_envs)[i]
    device: str = "cpu"  # auto, cpu, cuda, cuda:N or mps; checked against what torch sees
    # the run's threads (fluidsim_envs.threads owns them): torch's intra-op threads for the
    # policy's forward passes and updates, and numba's for the env kernels; null: one torch
    # thread and numba on every core this process may use, so that the two pools never spin
    # against each other (benchmarks/bench_training.py). At most the cores there are.
    torch_threads: int | None = None
    numba_threads: int | None = None
    # memory for noisy, lagging instruments: the policy (and its critic) sees the last
    # frame_stack observations side by side, oldest first (SB3's VecFrameStack over the
    # normalized ones; zeros before an episode's first); 1: the present only
    frame_stack: int = 1
    # difficulty levels trained side by side: n_envs split over the entries as evenly as whole
    # sub-envs allow (a level named twice gets two shares; wrappers/levels.py), each at
    # env_kwargs with its own difficulty, so that one policy serves each; empty: env_kwargs'
    # level alone
    levels: tuple[str, ...] = ()
    # an asymmetric actor-critic (PPO, v1): the value function also reads the exact
    # observation before the instruments, the policy its readings alone (rl/privileged.py)
    privileged_critic: bool = False
    policy: PolicyConfig = PolicyConfig()
    normalize: NormalizeConfig = NormalizeConfig()
    eval: EvalConfig = EvalConfig()
    checkpoint: CheckpointConfig = CheckpointConfig()
    warm_start: WarmStartConfig = WarmStartConfig()
    # stages trained in order before the run's own episodes (e.g. an easier difficulty first,
    # where a policy finds the task that the full one hides behind its costs); the stages
    # together must leave steps for the run's own env_kwargs
    curriculum: tuple[StageConfig, ...] = ()

    RANGES: ClassVar[dict[str, Range]] = {
        "n_envs": AT_LEAST_1,
        "total_timesteps": AT_LEAST_1,
        "seed": SEED,
        "torch_threads": AT_LEAST_1,
        "numba_threads": AT_LEAST_1,
        "frame_stack": Range(ge=1, le=64),
    }

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


class UniqueKeyLoader(yaml.SafeLoader):
    """``yaml.SafeLoader`` that refuses a key given twice in one mapping, naming it and its
    lines (the plain loader keeps the last value without a word, so a config that sets a
    key twice would train with whichever came last)."""

    def construct_mapping(self, node, deep=False):
        first: dict[Any, int] = {}
        for key_node, _ in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":
                continue  # `<<: *base` merges keys that the mapping's own keys may override
            key = self.construct_object(key_node, deep=True)
            line = key_node.start_mark.line + 1
            try:
                if key in first:
                    raise ConfigError(
                        f"duplicate key {key!r} at line {line} (first given at line "
                        f"{first[key]}): give each key once"
                    )
                first[key] = line
            except TypeError:  # an unhashable key: the base loader reports it
                pass
        return super().construct_mapping(node, deep=deep)


def load_yaml(text: str, source: str) -> Any:
    """``text`` read as YAML with :class:`UniqueKeyLoader` (safe, no key twice); an error
    starting with ``source`` (a file, an option) otherwise."""
    try:
        return yaml.load(text, Loader=UniqueKeyLoader)
    except yaml.YAMLError as e:
        raise ConfigError(f"{source}: not valid YAML: {_one_line(e)}") from None
    except ConfigError as e:
        raise ConfigError(f"{source}: {e}") from None


def _one_line(error: yaml.YAMLError) -> str:
    """PyYAML's error as one line (its own text spans several, with a drawing of the spot)."""
    mark = getattr(error, "problem_mark", None)
    problem = getattr(error, "problem", None)
    if problem and mark is not None:
        return f"{problem} (line {mark.line + 1}, column {mark.column + 1})"
    return " ".join(str(error).split())


def read_yaml(path: str | Path) -> Any:
    """The YAML file at ``path`` (:func:`load_yaml`); unreadable is a :class:`ConfigError`."""
    try:
        text = Path(path).read_text()
    except (OSError, UnicodeDecodeError) as e:
        raise ConfigError(f"{path}: cannot be read as text ({e})") from None
    return load_yaml(text, str(path))


def load_config(path: str | Path, overrides: typing.Sequence[str] = ()) -> TrainConfig:
    """Read the YAML config at ``path`` (a file, or a shipped config's name), apply
    ``key=value`` overrides, and check it."""
    path = find_config(path)
    raw = read_yaml(path)
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
    value = load_yaml(text, f"{flag} {item!r}: the value")
    if isinstance(value, str) and _EXPONENT.fullmatch(value.strip()):
        value = float(value)
    return key, value


def apply_overrides(raw: dict[str, Any], overrides: typing.Sequence[str]) -> dict[str, Any]:
    """A copy of ``raw`` with each ``a.b.c=value`` set (``value`` read as YAML)."""
    import copy

    out = copy.deepcopy(raw)
    for item in overrides:
        key, value = parse_assignment(item, "--set")
        set_key(out, key, value, f"--set {item!r}")
    return out


def get_key(raw: dict[str, Any], key: str) -> Any:
    """The dotted ``key`` of ``raw`` (None where a part of the way is missing)."""
    node: Any = raw
    for part in key.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    return node


def add_overrides_argument(parser, help_text: str) -> None:
    """The commands' ``--set KEY=VALUE ...`` option (repeatable; into ``args.overrides``)."""
    parser.add_argument(
        "--set",
        dest="overrides",
        metavar="KEY=VALUE",
        nargs="+",
        action="extend",
        default=[],
        help=help_text,
    )


def set_key(raw: dict[str, Any], key: str, value: Any, what: str) -> None:
    """Set the dotted ``key`` (``algorithm.learning_rate``) of ``raw`` to ``value`` in place,
    making the mappings on the way; ``what`` names the setting in the error where a part of the
    way is not a mapping."""
    *parents, last = key.split(".")
    node = raw
    for depth, part in enumerate(parents):
        node = node.setdefault(part, {})
        if not isinstance(node, dict):
            where = ".".join(parents[: depth + 1])
            raise ConfigError(f"{what}: {where} is {node!r}, not a mapping")
    node[last] = value


def config_from_dict(raw: dict[str, Any], joint: bool = True) -> TrainConfig:
    """Build and check a :class:`TrainConfig` from plain data. ``joint=False`` leaves out
    the checks that tie one key to another (a batch no larger than a rollout): a search
    space's values are checked one at a time, where such a pair is not yet decided."""
    cfg = _build(TrainConfig, raw, "")
    _check(cfg, joint)
    return cfg


def config_to_dict(cfg: Any) -> Any:
    """Plain data (dicts, lists, numbers, strings) that :func:`config_from_dict` reads back;
    NumPy scalars and arrays become Python numbers and lists (YAML can write those)."""
    if dataclasses.is_dataclass(cfg):
        return {f.name: config_to_dict(getattr(cfg, f.name)) for f in dataclasses.fields(cfg)}
    if isinstance(cfg, dict):
        return {k: config_to_dict(v) for k, v in cfg.items()}
    if isinstance(cfg, (tuple, list, np.ndarray)):
        return [config_to_dict(v) for v in cfg]
    if isinstance(cfg, np.generic):
        return cfg.item()
    return cfg


def dump_config(cfg: TrainConfig, path: str | Path) -> None:
    """``cfg`` as YAML at ``path``, written atomically (a kill leaves the old file or this)."""
    files.write_text(path, yaml.safe_dump(config_to_dict(cfg), sort_keys=False))


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
    if tp is Any:
        return "any values"
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


_INTEGERS = (int, np.integer)
_NUMBERS = (int, float, np.integer, np.floating)
_BOOLS = (bool, np.bool_)


def _convert(value: Any, tp: Any, where: str) -> Any:
    """``value`` as type ``tp`` (NumPy scalars accepted where numbers are, stored as Python
    numbers), or a :class:`ConfigError` naming ``where`` and the value."""
    origin = typing.get_origin(tp)
    if tp is Any:
        return config_to_dict(value)  # plain data: YAML writes it into the run folder
    if dataclasses.is_dataclass(tp):
        return _build(tp, value, where)
    if origin in (typing.Union, types.UnionType):
        for option in typing.get_args(tp):
            try:
                return _convert(value, option, where)
            except ConfigError:
                continue
        raise _type_error(value, tp, where)
    if origin is Literal:
        if isinstance(value, str) and value in typing.get_args(tp):
            return str(value)
        raise _type_error(value, tp, where)
    if origin is tuple:
        return _convert_tuple(value, tp, where)
    if origin is dict:
        if not isinstance(value, dict):
            raise _type_error(value, tp, where)
        _, item = typing.get_args(tp)
        return {str(k): _convert(v, item, f"{where}.{k}") for k, v in value.items()}
    return _convert_scalar(value, tp, where)


def _convert_tuple(value: Any, tp: Any, where: str) -> tuple:
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if not isinstance(value, (list, tuple)):
        raise _type_error(value, tp, where)
    (item,) = (a for a in typing.get_args(tp) if a is not Ellipsis)
    return tuple(_convert(v, item, f"{where}[{i}]") for i, v in enumerate(value))


def _convert_scalar(value: Any, tp: Any, where: str) -> Any:
    is_bool = isinstance(value, _BOOLS)
    if tp is type(None) and value is None:
        return None
    if tp is bool and is_bool:
        return bool(value)
    if tp is int and isinstance(value, _INTEGERS) and not is_bool:
        return int(value)
    if tp is float and isinstance(value, _NUMBERS) and not is_bool:
        return float(value)
    if tp is str and isinstance(value, str):
        return str(value)
    if tp in (type(None), bool, int, float, str):
        raise _type_error(value, tp, where)
    raise TypeError(f"config type {tp} of {where} is not supported")  # a bug here, not input


def _type_error(value: Any, tp: Any, where: str) -> ConfigError:
    hint = ""
    if isinstance(value, str):
        try:
            float(value)
            hint = " (YAML reads 3e-4 as a string: write 3.0e-4)"
        except ValueError:
            if where.endswith("learning_rate"):
                hint = " (a schedule is set by lr_schedule: constant or linear)"
    return ConfigError(f"{where} must be {_type_name(tp)}, got {value!r}{hint}")


# --------------------------------------------------------------------------------------------
# checks across fields


def _check(cfg: TrainConfig, joint: bool = True) -> None:
    _check_numbers(cfg, "")
    cfg.algorithm.check(cfg.n_envs if joint else None)
    _check_policy(cfg.policy, cfg.algorithm.name)
    check_device(cfg.device)
    _check_env(cfg.env_id, cfg.env_kwargs)
    _check_curriculum(cfg)
    _check_levels(cfg, joint)
    _check_privileged(cfg)
    if cfg.warm_start.steps and cfg.algorithm.name == "ppo" and cfg.algorithm.gamma >= 1.0:
        raise ConfigError(
            "warm_start.steps with algorithm.gamma 1.0: the warm start's value targets are "
            "discounted returns (gamma < 1)"
        )
    if cfg.warm_start.teacher not in TEACHERS:
        raise ConfigError(
            f"warm_start.teacher must be one of {list(TEACHERS)}, got {cfg.warm_start.teacher!r}"
        )
    if cfg.warm_start.steps and cfg.algorithm.name != "ppo":
        raise ConfigError(
            f"warm_start.steps ({cfg.warm_start.steps}) with algorithm.name "
            f"{cfg.algorithm.name!r}: a warm start fits PPO's policy and value function; "
            "set warm_start.steps to 0 or train ppo"
        )


def _check_privileged(cfg: TrainConfig) -> None:
    """A privileged critic is PPO's value function, on an env with instruments (v1)."""
    if not cfg.privileged_critic:
        return
    if cfg.algorithm.name != "ppo":
        raise ConfigError(
            f"privileged_critic with algorithm.name {cfg.algorithm.name!r}: the privileged "
            "critic is PPO's value function (SAC's critics judge actions on the policy's own "
            "input); set privileged_critic to false or train ppo"
        )
    if not hasattr(_check_env(cfg.env_id, cfg.env_kwargs), "difficulty"):
        raise ConfigError(
            f"privileged_critic: {cfg.env_id} has no instruments (its readings are exact); "
            "the v1 envs have"
        )


def _check_levels(cfg: TrainConfig, joint: bool = True) -> None:
    """Levels split the run's sub-envs (one at least per entry), on a v1 env, with neither a
    difficulty in env_kwargs nor a curriculum (both set the level another way)."""
    if not cfg.levels:
        return
    from fluidsim_envs.wrappers.levels import shares

    try:
        shares(list(cfg.levels), cfg.n_envs if joint else len(cfg.levels), "levels with n_envs")
    except ValueError as err:
        raise ConfigError(str(err)) from None
    if "difficulty" in cfg.env_kwargs:
        raise ConfigError(
            f"levels {list(cfg.levels)} with env_kwargs.difficulty "
            f"{cfg.env_kwargs['difficulty']!r}: the levels set each sub-env's difficulty; "
            "drop one of the two"
        )
    if cfg.curriculum:
        raise ConfigError(
            f"levels {list(cfg.levels)} with a curriculum of {len(cfg.curriculum)} stages: "
            "train the levels side by side or one after another, not both"
        )
    if not hasattr(_check_env(cfg.env_id, cfg.env_kwargs), "difficulty"):
        raise ConfigError(f"levels: {cfg.env_id} has no difficulty levels (the v1 envs have)")


def _check_curriculum(cfg: TrainConfig) -> None:
    """Each stage's numbers are in range and its env parameters build; the stages leave
    steps for the run's own episodes."""
    for i, stage in enumerate(cfg.curriculum):
        _check_numbers(stage, f"curriculum[{i}]")
        _check_env(cfg.env_id, {**cfg.env_kwargs, **stage.env_kwargs}, f"curriculum[{i}].")
    staged = sum(stage.timesteps for stage in cfg.curriculum)
    if staged >= cfg.total_timesteps:
        raise ConfigError(
            f"curriculum: its stages take {staged:,} timesteps, leaving none of "
            f"total_timesteps ({cfg.total_timesteps:,}) for the run's own env_kwargs"
        )


def stage_starts(cfg: TrainConfig) -> list[tuple[int, dict[str, Any]]]:
    """(first timestep, env parameters) of each curriculum stage in order, the run's own
    ``env_kwargs`` last (from the stages' end on).

    >>> cfg = config_from_dict({"env_id": "fluidsim/PaperAirplane-v0",
    ...     "algorithm": {"name": "ppo"}, "total_timesteps": 10,
    ...     "curriculum": [{"timesteps": 4, "env_kwargs": {"max_episode_steps": 50}}]})
    >>> stage_starts(cfg)
    [(0, {'max_episode_steps': 50}), (4, {})]
    """
    starts, at = [], 0
    for stage in cfg.curriculum:
        starts.append((at, {**cfg.env_kwargs, **stage.env_kwargs}))
        at += stage.timesteps
    return [*starts, (at, dict(cfg.env_kwargs))]


def _check_numbers(section: Any, prefix: str) -> None:
    """Every number of ``section`` and its subsections is finite and in its field's range
    (the section's ``RANGES``); ``env_kwargs`` is left to the env's own parameter checks."""
    ranges = getattr(section, "RANGES", {})
    for f in dataclasses.fields(section):
        value = getattr(section, f.name)
        where = _where(prefix, f.name)
        if dataclasses.is_dataclass(value):
            _check_numbers(value, where)
        elif isinstance(value, _NUMBERS) and not isinstance(value, _BOOLS):
            _check_number(where, value, ranges.get(f.name, Range()))


def _check_number(where: str, value: float, bounds: Range) -> None:
    # an int is finite (math.isfinite(10**400) would overflow): its bounds decide
    if (isinstance(value, int) or math.isfinite(value)) and bounds.holds(value):
        return
    kind = "an integer" if isinstance(value, int) else "a finite number"
    raise ConfigError(f"{where} must be {kind}{bounds}, got {value!r}")


#: the devices a config may name: torch's names (an index only for the accelerators)
_DEVICE = re.compile(r"auto|cpu|(cuda|mps)(:(\d+))?")


def check_device(device: str) -> None:
    """``device`` is ``auto`` (SB3 picks: CUDA if torch sees one, else the CPU), ``cpu``, or
    an accelerator that exists on this machine: ``cuda``, ``cuda:N`` (N below torch's device
    count) or ``mps``. Training on another device than the config names would leave a run
    folder that says it ran where it did not."""
    match = _DEVICE.fullmatch(device)
    if match is None:
        raise ConfigError(
            f"device must be 'auto', 'cpu', 'cuda', 'cuda:N' or 'mps', got {device!r}"
        )
    kind, index = match.group(1), int(match.group(3) or 0)
    if kind is None:
        return
    import torch

    if kind == "cuda":
        count = torch.cuda.device_count() if torch.cuda.is_available() else 0
        if index >= count:
            seen = f"{count} CUDA device(s)" if count else "no CUDA device"
            raise ConfigError(
                f"device {device!r} does not exist: torch sees {seen} here; use device: cpu "
                "(or auto)"
            )
    elif not torch.backends.mps.is_available() or index > 0:
        raise ConfigError(
            f"device {device!r} does not exist: torch sees no MPS device here; use device: cpu "
            "(or auto)"
        )


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

    def every(env_kwargs: dict[str, Any]) -> dict[str, Any]:
        params = _check_env(cfg.env_id, env_kwargs)
        kwargs = {f.name: getattr(params, f.name) for f in dataclasses.fields(params)}
        if cfg.levels:  # each part's own (a knob left None follows the part's level)
            kwargs.pop("difficulty")
        return config_to_dict(kwargs)

    # each stage resolved from its own parameters over the run's as given (over the run's
    # resolved ones, a stage's `difficulty` would be overridden by the knobs written down)
    stages = tuple(
        dataclasses.replace(stage, env_kwargs=every({**cfg.env_kwargs, **stage.env_kwargs}))
        for stage in cfg.curriculum
    )
    return dataclasses.replace(cfg, env_kwargs=every(cfg.env_kwargs), curriculum=stages)


def _check_env(env_id: str, env_kwargs: dict[str, Any], where: str = ""):
    """The env id is registered and its parameters accept ``env_kwargs`` (built here, so a
    bad parameter is reported before any training starts); returns the parameters. ``where``
    prefixes the error's key (``curriculum[0].``)."""
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
        raise ConfigError(f"{where}env_kwargs: {e}") from None
