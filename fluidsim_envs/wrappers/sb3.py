"""A native vector env as a Stable-Baselines3 ``VecEnv``, in-process and without copies of
the env per sub-env.

Our vector envs reset an ended episode in the same step (Gymnasium's ``SAME_STEP`` autoreset
mode), which is SB3's convention too, so :class:`SB3VecEnv` only reshapes what they return:
the batched info dict becomes SB3's list of per-env dicts, and an ended episode's last
observation and info (``info["final_obs"]``, ``info["final_info"]``) become that env's info
with ``"terminal_observation"`` and ``"TimeLimit.truncated"``, exactly as SB3's
``DummyVecEnv`` over the single envs reports them (``tests/wrappers/test_sb3.py`` checks it
step by step). Seeding goes through the env's own ``SeedSequence``: ``seed(s)`` makes the next
``reset()`` call ``venv.reset(seed=s)``, so sub-env i draws from ``SeedSequence(s).spawn(E)[i]``
exactly as in ``gym.make_vec(...).reset(seed=s)`` (and for any E), never from ``s + i``.
:meth:`SB3VecEnv.seed_each` gives sub-env i the stream of the single env seeded ``seeds[i]``
(what ``DummyVecEnv.seed`` does, for comparisons with it). ``stream="training"`` seeds a
training run's sub-envs from a stream of their own (``fluidsim_envs.seeding``).

    >>> from fluidsim_envs.wrappers.sb3 import make_sb3_vec_env
    >>> venv = make_sb3_vec_env("fluidsim/PaperAirplane-v0", n_envs=4, seed=0)
    >>> obs = venv.reset()
    >>> obs, rewards, dones, infos = venv.step(np.zeros((4, 3), dtype=np.float32))
    >>> obs.shape, rewards.dtype, len(infos)
    ((4, 15), dtype('float32'), 4)
    >>> venv.close()
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Sequence
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv, VectorWrapper
from stable_baselines3.common.vec_env.base_vec_env import (
    VecEnv,
    VecEnvIndices,
    VecEnvObs,
    VecEnvStepReturn,
)

from .. import seeding as SD
from ..physics import checks as CK

# The autoreset bookkeeping of a same-step vector env; not part of any one env's info.
_AUTORESET_KEYS = ("final_obs", "final_info")


def _row(value: Any, i: int) -> Any:
    """Sub-env ``i``'s entry of a batched info value, as the single env reports it (NumPy
    scalars become Python numbers; nested dicts are taken row by row, masks dropped)."""
    if isinstance(value, dict):
        return {k: _row(v, i) for k, v in value.items() if not k.startswith("_")}
    if isinstance(value, np.ndarray) and value.ndim >= 1:
        v = value[i]
        return v.item() if isinstance(v, np.generic) else v.copy()
    return value


def _carried(info: dict[str, Any], keys: Sequence[str] | None):
    """The (key, value) entries of a batched info dict that become per-env entries: all but
    the masks and the autoreset bookkeeping, or only ``keys`` (None: all)."""
    if keys is not None:
        return [(k, info[k]) for k in keys if k in info]
    return [(k, v) for k, v in info.items() if not k.startswith("_") and k not in _AUTORESET_KEYS]


def _env_info(info: dict[str, Any], i: int, keys: Sequence[str] | None = None) -> dict[str, Any]:
    """Sub-env ``i``'s dict from a batched info dict (only ``keys``' entries unless None),
    honoring Gymnasium's ``_key`` masks."""
    out = {}
    for key, value in _carried(info, keys):
        mask = info.get(f"_{key}")
        if mask is not None and not mask[i]:
            continue
        out[key] = _row(value, i)
    return out


def _column(value: Any, n: int) -> list[Any]:
    """Every sub-env's entry of a batched info value, ``[_row(value, i) for i in range(n)]``,
    a whole column at a time: a 1-D array of numbers becomes Python numbers in one
    ``tolist()`` (the same values ``.item()`` gives), where a call per sub-env and key cost
    several times the env's own step."""
    if isinstance(value, dict):
        columns = {k: _column(v, n) for k, v in value.items() if not k.startswith("_")}
        return [{k: c[i] for k, c in columns.items()} for i in range(n)]
    if isinstance(value, np.ndarray) and value.ndim == 1 and value.dtype.kind in "biuf":
        return value.tolist()
    return [_row(value, i) for i in range(n)]


def _env_infos(
    info: dict[str, Any], n: int, keys: Sequence[str] | None = None
) -> list[dict[str, Any]]:
    """``[_env_info(info, i, keys) for i in range(n)]``, a key at a time (:func:`_column`)."""
    out: list[dict[str, Any]] = [{} for _ in range(n)]
    for key, value in _carried(info, keys):
        mask = info.get(f"_{key}")
        column = _column(value, n)
        if mask is None:
            for env_info, v in zip(out, column, strict=True):
                env_info[key] = v
        else:
            for env_info, v, m in zip(out, column, np.asarray(mask).tolist(), strict=True):
                if m:
                    env_info[key] = v
    return out


class SB3VecEnv(VecEnv):
    """Present a Gymnasium vector env with same-step autoreset (any :class:`FluidVectorEnv`,
    or a ``VectorWrapper`` around one) as an SB3 ``VecEnv``.

    Attributes and methods reached through ``get_attr``, ``set_attr`` and ``env_method`` are
    the vector env's, shared by all its sub-envs: a query for some indices answers for each,
    and a change or call must name all of them.

    Parameters
    ----------
    venv
        The vector env; it is closed with this adapter.
    success_key
        An info key to copy into ``"is_success"`` at an episode's end, the key SB3 reads for
        success rates (``EvalCallback``); None (the default) adds nothing, as DummyVecEnv.
    info_keys
        The env's info entries each sub-env's dict carries (besides SB3's own
        ``terminal_observation``, ``TimeLimit.truncated`` and ``is_success``); None (the
        default): all of them, as DummyVecEnv. Training reads only a few, and a dict per
        sub-env of every nested entry (reward terms, the drawn physics) cost more than the
        env's own step at 256 envs.
    stream
        The seed stream :meth:`seed` draws from (``fluidsim_envs.seeding``): "evaluation"
        (the default: ``venv.reset(seed=s)``), or "training" for a training run, whose
        episodes are then never those an evaluation at the same seed flies.
    """

    def __init__(
        self,
        venv: VectorEnv,
        *,
        success_key: str | None = None,
        info_keys: Sequence[str] | None = None,
        stream: str = "evaluation",
    ) -> None:
        mode = venv.metadata.get("autoreset_mode")
        if mode != AutoresetMode.SAME_STEP:
            raise ValueError(
                f"SB3VecEnv needs a vector env with same-step autoreset "
                f"(metadata['autoreset_mode'] == AutoresetMode.SAME_STEP), got {mode!r}"
            )
        self.venv = venv
        self.stream = SD.check_stream("SB3VecEnv", stream)
        self.success_key = success_key
        self.info_keys = None if info_keys is None else tuple(info_keys)
        if success_key is not None and self.info_keys is not None:
            self.info_keys = tuple(dict.fromkeys((*self.info_keys, success_key)))
        self._actions: np.ndarray | None = None
        self._batch_seed: int | None = None  # from seed(), for the next reset()
        self.env_seconds = 0.0  # wall time inside the vector env's reset and step
        self.env_steps = 0  # transitions stepped (num_envs per step)
        super().__init__(venv.num_envs, venv.single_observation_space, venv.single_action_space)
        self.metadata = venv.metadata  # as DummyVecEnv: the env's own metadata

    # ---- stepping -------------------------------------------------------------------------

    def seed(self, seed: int | None = None) -> list[np.random.SeedSequence]:
        """Seed every sub-env at the next :meth:`reset` through the env's ``SeedSequence``:
        sub-env i gets ``seeding.root(seed, stream).spawn(num_envs)[i]``, the generator
        ``venv.reset(seed=seed, options={"stream": stream})`` gives it (in the evaluation
        stream ``SeedSequence(seed).spawn(num_envs)[i]``; never SB3's default ``seed + i``).
        Without a seed, one is drawn from fresh entropy. Returns the sub-envs' seed
        sequences."""
        if seed is None:
            seed = int(np.random.SeedSequence().generate_state(1)[0])  # fresh OS entropy
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
            raise ValueError(f"SB3VecEnv.seed: expected an int or None, got {seed!r}")
        CK.seed("SB3VecEnv.seed", "seed", seed)  # in [0, 2**128): the streams stay apart
        self._batch_seed = int(seed)
        self._reset_seeds()
        return SD.root(self._batch_seed, self.stream).spawn(self.num_envs)

    def seed_each(self, seeds: Sequence[int]) -> list[int]:
        """Give sub-env i, at the next :meth:`reset`, the stream of the single env reset with
        ``seed=seeds[i]`` (``DummyVecEnv.seed(s)`` seeds its envs ``s + i`` this way)."""
        seeds = [int(s) for s in seeds]
        if len(seeds) != self.num_envs:
            raise ValueError(
                f"SB3VecEnv.seed_each: expected {self.num_envs} seeds, got {len(seeds)}"
            )
        self._batch_seed = None
        self._seeds = seeds
        return seeds

    def reset(self) -> VecEnvObs:
        """Reset every env with the seed from :meth:`seed` (or :meth:`seed_each`) and the
        options from :meth:`set_options` (both used once), as ``DummyVecEnv.reset`` does."""
        seed: int | list[int | None] | None = None  # every env continues its own generator
        if self._batch_seed is not None:
            seed = self._batch_seed  # the env spawns one child sequence per sub-env
        elif any(s is not None for s in self._seeds):
            seed = list(self._seeds)
        options = self._options
        if any(o != options[0] for o in options):
            raise ValueError(
                "SB3VecEnv.reset: the vector env takes one options dict for all its sub-envs, "
                f"got different ones per env: {options}"
            )
        options = dict(options[0] or {})
        if seed is not None and self.stream != "evaluation":
            options["stream"] = self.stream
        t = time.perf_counter()
        obs, info = self.venv.reset(seed=seed, options=options or None)
        self.env_seconds += time.perf_counter() - t
        self.reset_infos = _env_infos(info, self.num_envs, self.info_keys)
        self._batch_seed = None
        self._reset_seeds()
        self._reset_options()
        return np.array(obs, copy=True)

    def step_async(self, actions: np.ndarray) -> None:
        self._actions = np.asarray(actions)

    def step_wait(self) -> VecEnvStepReturn:
        if self._actions is None:
            raise RuntimeError("SB3VecEnv.step_wait called without step_async")
        t = time.perf_counter()
        obs, rewards, terminated, truncated, info = self.venv.step(self._actions)
        self.env_seconds += time.perf_counter() - t
        self.env_steps += self.num_envs
        self._actions = None
        terminated = np.asarray(terminated, dtype=bool)
        truncated = np.asarray(truncated, dtype=bool)
        dones = terminated | truncated
        ended = np.flatnonzero(dones).tolist()
        # the running envs' infos column by column; an ended env's is its final info
        infos = _env_infos(info, self.num_envs, self.info_keys)
        for i in ended:
            infos[i] = _env_info(info["final_info"], i, self.info_keys)
        # SB3's reading of Gymnasium's flags (DummyVecEnv.step_wait)
        time_limit = (truncated & ~terminated).tolist()
        for env_info, flag in zip(infos, time_limit, strict=True):
            env_info["TimeLimit.truncated"] = flag
        for i in ended:
            infos[i]["terminal_observation"] = np.array(info["final_obs"][i], copy=True)
            self.reset_infos[i] = {}  # the autoreset's info: our envs report none
            if self.success_key is not None:
                infos[i]["is_success"] = infos[i][self.success_key]
        # DummyVecEnv keeps rewards in a float32 buffer
        return np.array(obs, copy=True), np.asarray(rewards, dtype=np.float32), dones, infos

    def close(self) -> None:
        self.venv.close()

    def replace(self, venv: VectorEnv) -> None:
        """Step ``venv`` from now on in place of the vector env (closed here): a curriculum's
        next stage. It must have the same number of sub-envs and the same spaces (a policy
        reads and acts on both); the counters go on, the next :meth:`reset` starts it."""
        if venv.metadata.get("autoreset_mode") != AutoresetMode.SAME_STEP:
            raise ValueError(
                "SB3VecEnv.replace: the new vector env must autoreset in the same step"
            )
        theirs = (venv.num_envs, venv.single_observation_space, venv.single_action_space)
        ours = (self.num_envs, self.observation_space, self.action_space)
        if theirs != ours:
            raise ValueError(
                "SB3VecEnv.replace: the new vector env's (num_envs, observation space, action "
                f"space) {theirs} differ from this one's {ours}"
            )
        self.venv.close()
        self.venv = venv
        self.metadata = venv.metadata
        self._actions = None

    # ---- rendering ------------------------------------------------------------------------

    def get_images(self) -> Sequence[np.ndarray | None]:
        if self.render_mode != "rgb_array":
            warnings.warn(
                f"The render mode is {self.render_mode}, but get_images needs 'rgb_array'",
                stacklevel=2,
            )
            return [None] * self.num_envs
        return list(self.venv.render())

    # ---- attributes -----------------------------------------------------------------------

    def _chain(self) -> list[VectorEnv]:
        """The vector env's wrappers, outermost first, then the env itself."""
        chain, env = [], self.venv
        while isinstance(env, VectorWrapper):
            chain.append(env)
            env = env.env
        return [*chain, env]

    def _all(self, indices: VecEnvIndices, what: str) -> None:
        if sorted(self._get_indices(indices)) != list(range(self.num_envs)):
            raise ValueError(
                f"SB3VecEnv.{what}: the vector env's attributes and methods are shared by all "
                f"{self.num_envs} sub-envs; pass indices=None, got {indices!r}"
            )

    def _lookup(self, name: str) -> Any:
        for env in self._chain():
            try:
                return getattr(env, name)
            except AttributeError:
                continue
        raise AttributeError(f"{type(self.venv).__name__} has no attribute {name!r}")

    def get_attr(self, attr_name: str, indices: VecEnvIndices = None) -> list[Any]:
        value = self._lookup(attr_name)
        return [value for _ in self._get_indices(indices)]

    def set_attr(self, attr_name: str, value: Any, indices: VecEnvIndices = None) -> None:
        self._all(indices, "set_attr")
        for env in self._chain():  # the innermost holder of the name, else the outermost env
            if attr_name in vars(env):
                setattr(env, attr_name, value)
                return
        setattr(self.venv, attr_name, value)

    def env_method(
        self, method_name: str, *method_args, indices: VecEnvIndices = None, **method_kwargs
    ) -> list[Any]:
        """Call the vector env's method once; every listed index gets its result."""
        self._all(indices, "env_method")
        result = self._lookup(method_name)(*method_args, **method_kwargs)
        return [result for _ in self._get_indices(indices)]

    def env_is_wrapped(
        self, wrapper_class: type[gym.Wrapper], indices: VecEnvIndices = None
    ) -> list[bool]:
        """Whether the vector env is wrapped in ``wrapper_class`` (a vector wrapper); a
        single-env wrapper such as SB3's ``Monitor`` never is."""
        wrapped = any(isinstance(env, wrapper_class) for env in self._chain()[:-1])
        return [wrapped for _ in self._get_indices(indices)]


def make_vector_env(env_id: str, n_envs: int, **env_kwargs: Any) -> VectorEnv:
    """``n_envs`` sub-envs of ``env_id`` in one native vector env (its vector entry point)."""
    import fluidsim_envs  # noqa: F401  (registers the ids)

    return gym.make_vec(
        env_id, num_envs=n_envs, vectorization_mode="vector_entry_point", **env_kwargs
    )


def make_sb3_vec_env(
    env_id: str,
    n_envs: int,
    seed: int | None = None,
    *,
    success_key: str | None = None,
    info_keys: Sequence[str] | None = None,
    stream: str = "evaluation",
    levels: Sequence[str] = (),
    truth: bool = False,
    **env_kwargs: Any,
) -> SB3VecEnv:
    """``n_envs`` sub-envs of ``env_id`` in one native vector env, as an SB3 ``VecEnv``.

    ``env_kwargs`` set the env's parameters (an unknown one is an error listing the valid
    ones). With ``seed``, the first ``reset()`` seeds the sub-envs as
    ``venv.reset(seed=seed)`` does (see :meth:`SB3VecEnv.seed`).
    ``success_key``, ``info_keys``, ``stream``: see :class:`SB3VecEnv`. ``levels``: the
    sub-envs split over these difficulty levels (:class:`~.levels.LevelMix`). ``truth``:
    each observation followed by the exact one (``rl.privileged.WithTruth``).
    """
    wrap = None
    if truth:
        from ..rl.privileged import WithTruth as wrap
    if levels:
        from .levels import LevelMix

        venv = LevelMix(env_id, levels, n_envs, wrap=wrap, **env_kwargs)
    else:
        venv = make_vector_env(env_id, n_envs, **env_kwargs)
        venv = venv if wrap is None else wrap(venv)
    sb3_venv = SB3VecEnv(
        venv,
        success_key=success_key,
        info_keys=info_keys,
        stream=stream,
    )
    if seed is not None:
        sb3_venv.seed(seed)
    return sb3_venv
