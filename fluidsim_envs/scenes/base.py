"""What every scene shares: parameters, seeding, actions, autoreset, episode bookkeeping.

A scene subclasses :class:`FluidVectorEnv`, fills in three hooks (``_draw_reset``,
``_advance``, ``_observe``) and names its ``View`` (the rgb_array frames); :class:`FluidEnv`
turns any scene into a single Gymnasium env that is the batch of one, so there is one
implementation of each scene.

The step path is compiled calls from preallocated arrays: the physics, then the scene's one
task kernel (reward terms, flags and the observation of every sub-env, in parallel over
sub-envs from ``PARALLEL_MIN_BODIES`` of them), then, for the sub-envs whose episode ended,
the scene's start (the dart's compiled, the others' vectorized numpy) and their observation
alone. Python does the API's checks and the info dict.

Viewers (the ``View`` behind ``render()``, a scene's Rerun hooks) read the env through public,
read-only accessors (``last_action``, ``episode_steps``, ``episodes`` here, the scene's own
beside them) and keep their own state; the env's step never touches it.

Seeding: ``reset(seed=s)`` gives sub-env i the generator of ``SeedSequence(s).spawn(E)[i]``
(spawned children do not depend on E, so sub-env i sees the same randomness for any batch
size), and ``reset(seed=[s0, s1, ...])`` gives sub-env i ``SeedSequence(s_i).spawn(1)[0]``,
which is what the single env seeded with ``s_i`` uses. Each sub-env draws only from its own
generator, so its episodes do not depend on the others. ``options={"stream": name}`` takes
the same seeds from another purpose's stream (``fluidsim_envs.seeding``: a training run's
episodes are never the evaluation's).

Every episode start draws ``draws_per_episode`` uniforms in [0, 1) from its sub-env's
generator. They are drawn ahead, several episodes' worth at a time, into the sub-env's pool
(``_pool``; a snapshot keeps it with the generator): a generator's ``random(a)`` then
``random(b)`` is its ``random(a + b)``, so each episode gets exactly the numbers it would
have drawn at its start, and a sub-env's generator is called once every few episodes
instead of at each start.
"""

from __future__ import annotations

import dataclasses
import sys
from collections.abc import Callable, Sequence
from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from .. import seeding as SD
from ..physics import checks as CK
from .snapshot import EnvState

# --------------------------------------------------------------------------------------------
# parameters


def make_params(cls: type, kwargs: dict[str, Any]):
    """Build the frozen parameter dataclass ``cls`` from keyword arguments; an unknown key is
    an error that lists the valid ones."""
    valid = [f.name for f in dataclasses.fields(cls)]
    unknown = sorted(set(kwargs) - set(valid))
    if unknown:
        raise TypeError(f"{cls.__name__}: unknown parameter(s) {unknown}; valid: {valid}")
    return cls(**kwargs)


def check_choice(owner: str, key: str, value, choices: Sequence[str]) -> None:
    CK.choice(owner, key, value, choices)


# --------------------------------------------------------------------------------------------
# the vector env

POOL_DRAWS = 128  # uniforms drawn ahead per sub-env: 1 KiB each (16 MiB at 16384 sub-envs)


def sum_rows(terms: np.ndarray) -> np.ndarray:
    """``terms[0] + terms[1] + ...`` in that order, for each sub-env: the same sums for any
    number of sub-envs. (``terms.sum(axis=0)`` sums one sub-env's column of eight or more
    terms pairwise, in another order than a batch's row by row: rewards that differ in the
    last bit between a batch and a single env.)"""
    out = terms[0].copy()
    for row in terms[1:]:
        out += row
    return out


class FluidVectorEnv(VectorEnv):
    """A batch of one scene, stepped by one compiled physics call per step.

    Autoreset is same-step (``metadata["autoreset_mode"]``): when a sub-env's episode ends,
    ``step`` returns the first observation of its next episode, and the last observation and
    info of the ended one in ``info["final_obs"]`` and ``info["final_info"]`` (rows marked by
    ``info["_final_obs"]``), as Gymnasium's ``SyncVectorEnv`` does in that mode.

    Subclasses set ``Params``, ``obs_dim`` and ``View`` and implement the hooks below.
    """

    metadata: dict[str, Any] = {
        "autoreset_mode": AutoresetMode.SAME_STEP,
        "render_modes": ["rgb_array"],
        "render_fps": 30,  # each instance's: its action rate (dt x substeps)
    }
    Params: type
    obs_dim: int
    observation_layout: tuple[tuple[str, str, str], ...]  # (name, unit, description) a column
    reward_terms: tuple[str, ...]
    # the rgb_array viewer: View(env) with frame(env_index) -> [H, W, 3] uint8, made on the
    # first render() and owning whatever it keeps between frames
    View: type
    # the scene's arrays that hold what decides a sub-env's future beyond the physics (the
    # task: targets, routes, counters, last flags), each with its sub-env axis: what a
    # snapshot (get_state) copies beside the base's own (_BASE_STATE). An array made in
    # _build with a sub-env axis belongs here (tests/scenes/test_snapshot.py checks)
    state_fields: tuple[tuple[str, int], ...] = ()
    version = 0  # the N of the env's -vN (realism.Version1: 1); its tuned pilot's gains

    def __init__(
        self, num_envs: int = 1, render_mode: str | None = None, autoreset: bool = True, **kwargs
    ) -> None:
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)):
            raise ValueError(f"num_envs must be a positive integer, got {num_envs!r}")
        if num_envs < 1:
            raise ValueError(f"num_envs must be a positive integer, got {num_envs!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(
                f"render_mode must be None or one of {self.metadata['render_modes']}, "
                f"got {render_mode!r}"
            )
        self.params = make_params(self.Params, kwargs)
        # frames are one action apart: a recording plays in real time at the action rate
        period_s = self.params.dt * self.params.substeps
        self.metadata = {**self.metadata, "render_fps": _fps(period_s)}
        self.num_envs = E = int(num_envs)
        self.render_mode = render_mode
        self.autoreset = CK.flag(type(self).__name__, "autoreset", autoreset)
        if not autoreset:
            self.metadata = {**self.metadata, "autoreset_mode": AutoresetMode.DISABLED}
        self._keep_none = np.zeros(E, dtype=bool)  # a mask of no sub-env (observe, read)
        self._build()
        # each sub-env's pool of episode-start uniforms (see the module docstring): about
        # POOL_DRAWS numbers, whole episodes of them
        self._pool_episodes = max(1, POOL_DRAWS // max(self.draws_per_episode, 1))
        self._pool = np.zeros((E, self._pool_episodes * self.draws_per_episode))
        self._pool_next = np.full(E, self._pool_episodes, dtype=np.int64)
        n_act = len(self.action_names)
        self.single_action_space = gym.spaces.Box(-1.0, 1.0, (n_act,), np.float32)
        self.action_space = batch_space(self.single_action_space, E)
        low, high = self._observation_bounds()
        self.single_observation_space = gym.spaces.Box(low, high, (self.obs_dim,), np.float32)
        self.observation_space = batch_space(self.single_observation_space, E)

        self._rngs: list[np.random.Generator | None] = [None] * E
        self._obs = np.zeros((E, self.obs_dim), dtype=np.float32)
        # the exact observation the task computes; through sensors (v1) the pilot sees
        # their readings of it in _obs, else _obs is it
        self._truth = self._obs if self.sensors is None else np.zeros_like(self._obs)
        self._all = np.arange(E)
        self._elapsed = np.zeros(E, dtype=np.int64)
        self._sums = np.zeros((len(self.reward_terms), E))  # per-episode reward-term sums
        self._act = np.zeros((E, len(self.action_names)))
        self._needs_reset = np.ones(E, dtype=bool)
        self._episodes = np.zeros(E, dtype=np.int64)
        self._view = None
        # callables hook(ended_ids, info, reward) that a same-step autoreset calls just before
        # it restarts sub-envs ``ended_ids``: the state still holds their ended episodes (how
        # the Rerun logger records each episode's last state); ``info`` and ``reward`` are the
        # step's
        self.before_autoreset: list[Callable[[np.ndarray, dict, np.ndarray], None]] = []

    # ---- hooks ----------------------------------------------------------------------------

    action_names: tuple[str, ...] = ()

    def _build(self) -> None:
        """Create the simulator and buffers from ``self.params``."""
        raise NotImplementedError

    # uniforms in [0, 1) each episode start draws (set by _build: it may depend on params)
    draws_per_episode: int = 0
    # the instruments between the exact observation and the pilot (sensors.SensorModel;
    # set by _build, v1), with each sub-env's noise key [E] uint64; None: exact readings
    sensors = None
    noise_keys = None

    def _draw_reset(self, ids: np.ndarray, u: np.ndarray) -> None:
        """Start new episodes in sub-envs ``ids`` from ``u`` [len(ids), draws_per_episode]:
        each row the uniforms its sub-env's generator drew for this episode."""
        raise NotImplementedError

    def _advance(self, actions: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict]:
        """Apply ``actions`` [E, n] in [-1, 1], step the physics and write the observation of
        every sub-env whose state did not diverge into ``self._truth`` (one task kernel does
        the terms, flags and observations); return arrays the env does not write again
        (terminated [E], diverged [E], reward terms [len(reward_terms), E], info {key: [E]})."""
        raise NotImplementedError

    def _observe(self, out: np.ndarray, ids: np.ndarray) -> None:
        """Write the observation of sub-envs ``ids`` (int64) into their rows of ``out``
        [E, obs_dim] (float32)."""
        raise NotImplementedError

    # ---- what viewers read (read-only) ---------------------------------------------------

    @property
    def last_action(self) -> np.ndarray:
        """The last step's actions [E, n], clipped to [-1, 1] (read-only; zeros at an
        episode's start, before its first action)."""
        return _read_only(self._act)

    @property
    def observation(self) -> np.ndarray:
        """The current observation of every sub-env [E, obs_dim] (read-only): what the last
        reset or step returned, the autoreset's first observation for an ended episode."""
        return _read_only(self._obs)

    @property
    def episode_steps(self) -> np.ndarray:
        """Steps taken in each sub-env's current episode [E] (read-only)."""
        return _read_only(self._elapsed)

    @property
    def episode_return(self) -> np.ndarray:
        """The reward summed over each sub-env's current episode so far [E] (a copy; 0 right
        after a reset, the autoreset's included)."""
        return sum_rows(self._sums)

    @property
    def episodes(self) -> np.ndarray:
        """Episodes started in each sub-env [E] (read-only): a viewer's cue to restart what it
        keeps per episode."""
        return _read_only(self._episodes)

    @property
    def view(self):
        """The rgb_array viewer (``View(self)``), made on first use."""
        if self._view is None:
            self._view = self.View(self)
        return self._view

    # ---- Gymnasium API --------------------------------------------------------------------

    RESET_OPTIONS = ("env_ids", "reset_mask", "stream")

    def reset(self, *, seed: int | Sequence[int | None] | None = None, options=None):
        """Reset every sub-env, or some.

        Args:
            seed: None (fresh entropy the first time, then each sub-env's generator goes
                on), an integer >= 0 (Python or NumPy), or a list of one per sub-env of
                those (None entries: fresh entropy) or of ``SeedSequence`` s, each sub-env's
                own (a batch split over vector envs: ``wrappers.levels``).
            options: None, or a dict with at most one of ``"env_ids"`` (indices in
                [0, num_envs), or a boolean mask of length num_envs) and ``"reset_mask"``
                (a boolean mask of length num_envs, Gymnasium's vector-env convention):
                only those sub-envs restart (their observation rows change; the others keep
                theirs); an empty list or an all-False mask restarts none. Beside either,
                ``"stream"`` with a seed: the purpose the seed serves (``"training"``,
                ``"tuning"``; ``"evaluation"``, the default, is Gymnasium's
                ``reset(seed=s)``), whose episodes no other stream's seed gives
                (:mod:`fluidsim_envs.seeding`).

        Every input is checked before anything changes."""
        E = self.num_envs
        ids = np.unique(self._reset_ids(options))  # a sub-env listed twice starts once
        stream = self._stream(seed, options)
        if seed is None:
            if any(r is None for r in self._rngs):
                self._seed(np.random.SeedSequence().spawn(E))
        elif isinstance(seed, (list, tuple)) or (isinstance(seed, np.ndarray) and seed.ndim == 1):
            if len(seed) != E:
                raise ValueError(f"reset: expected {E} seeds, one per sub-env, got {len(seed)}")
            self._seed([_child(s, i, stream) for i, s in enumerate(seed)])
        else:
            seed = CK.seed("reset", f"seed (or a list of {E}, one per sub-env)", seed)
            self._seed(SD.root(seed, stream).spawn(E))
        self._start(ids)
        self._observe(self._truth, ids)
        self._read(ids, start=True)
        return self._obs.copy(), self._info_after_reset()

    def _reset_ids(self, options) -> np.ndarray:
        """The sub-envs ``reset(options=...)`` restarts (all without options)."""
        if options is None:
            return np.arange(self.num_envs)
        valid = list(self.RESET_OPTIONS)
        if not isinstance(options, dict):
            raise ValueError(
                f"reset: options must be a dict (keys {valid}) or None, got {CK.show(options)}"
            )
        unknown = [k for k in options if k not in valid]
        if unknown:
            raise ValueError(f"reset: unknown option(s) {unknown}; valid options are {valid}")
        if len(set(options) - {"stream"}) > 1:
            raise ValueError("reset: pass one of options 'env_ids' and 'reset_mask', not both")
        if "reset_mask" in options:
            mask = options["reset_mask"]
            if not (isinstance(mask, np.ndarray) and mask.dtype == np.bool_):
                raise ValueError(
                    f"reset: options['reset_mask'] must be a boolean numpy array of shape "
                    f"({self.num_envs},), got {CK.show(mask)}"
                )
            return self._ids("reset: options['reset_mask']", mask)
        return self._ids("reset", options.get("env_ids"))

    @staticmethod
    def _stream(seed, options) -> str:
        """The seed stream ``options["stream"]`` names (``fluidsim_envs.seeding``; default
        "evaluation"): only with a seed, which it is the stream of."""
        if not options or "stream" not in options:
            return "evaluation"
        if seed is None:
            raise ValueError(
                f"reset: options['stream'] ({options['stream']!r}) chooses the episodes a seed "
                "gives: pass a seed with it"
            )
        return SD.check_stream("reset: options['stream']", options["stream"])

    def step(self, actions):
        a = CK.real_array("step", "actions", actions)  # no str, None, object, ragged, bools
        if a.shape != self._act.shape:
            if a.size == self._act.size and self.num_envs == 1:
                a = a.reshape(self._act.shape)
            else:
                raise ValueError(
                    f"step: actions must have shape {self._act.shape} "
                    f"({', '.join(self.action_names)}), got {a.shape}: {CK.show(actions)}"
                )
        if not np.isfinite(a).all():
            bad = np.argwhere(~np.isfinite(a))[0]
            raise ValueError(
                f"step: actions contain {a[tuple(bad)]} at {tuple(int(i) for i in bad)}: "
                "actions must be finite"
            )
        if self._needs_reset.any():
            raise RuntimeError(
                f"step called on sub-env(s) {np.flatnonzero(self._needs_reset)[:8].tolist()} "
                "whose episode has ended (or never started): call reset first"
            )
        # the actuators' limits: Box(-1, 1) commands beyond them saturate
        np.clip(a, -1.0, 1.0, out=self._act)

        # the observation of a diverged sub-env keeps its last finite one: never NaN to the
        # learner (the task kernel skips those rows)
        terminated, diverged, terms, info = self._advance(self._act)
        self._elapsed += 1
        self._read(self._all, start=False, skip=diverged)  # a diverged one keeps its last
        reward = sum_rows(terms)
        self._sums += terms
        terminated |= diverged
        truncated = (self._elapsed >= self.params.max_episode_steps) & ~terminated
        info["physics_diverged"] = diverged
        info["reward_terms"] = dict(zip(self.reward_terms, terms, strict=True))

        done = terminated | truncated
        if done.any():
            ended = np.flatnonzero(done)
            # the ended episodes' totals, masked like Gymnasium's other per-sub-env keys
            info["episode_terms"] = dict(zip(self.reward_terms, self._sums.copy(), strict=True))
            info["_episode_terms"] = done
            info["episode_steps"] = self._elapsed.copy()
            info["_episode_steps"] = done
            if "success" in info:  # Gymnasium's and SB3's name for it, at the episode's end
                info["is_success"], info["_is_success"] = info["success"].copy(), done
            if self.autoreset:
                info["final_info"] = dict(info)
                info["_final_info"] = done
                info["final_obs"] = self._obs.copy()
                info["_final_obs"] = done
                for hook in self.before_autoreset:
                    hook(ended, info, reward)
                self._start(ended)
                self._observe(self._truth, ended)
                self._read(ended, start=True)
                for key, value in self._info_after_reset().items():  # the new episodes'
                    info[key], info[f"_{key}"] = value, done
            else:
                self._needs_reset[ended] = True
        return self._obs.copy(), reward, terminated, truncated, info

    # ---- snapshots --------------------------------------------------------------------------

    def get_state(self, env_ids=None) -> EnvState:
        """A snapshot of sub-envs ``env_ids`` (None: all): their physics, task, episode
        clocks and sums, last actions and observations, and generators; picklable."""
        ids = self._ids("get_state", env_ids)
        task = {
            name: np.moveaxis(getattr(self, name), axis, 0)[ids].copy()
            for name, axis in self._state_arrays()
        }
        return EnvState(
            env=f"{type(self).__module__}:{type(self).__qualname__}",
            params=self.params,
            physics=self.sim.get_state(ids),
            task=task,
            rngs=tuple(
                None if self._rngs[i] is None else self._rngs[i].bit_generator.state for i in ids
            ),  # fmt: skip
        )

    def set_state(self, state: EnvState, env_ids=None) -> np.ndarray:
        """Restore sub-envs ``env_ids`` (None: all) from ``state`` (one row each, in order; a
        snapshot of this env class with equal parameters). From there they step bit for bit
        as the sub-envs it was taken from did. Returns the observations of every sub-env
        ``[E, obs_dim]`` (a copy), as reset does."""
        ids = self._ids("set_state", env_ids)
        here = f"{type(self).__module__}:{type(self).__qualname__}"
        if not isinstance(state, EnvState):
            raise TypeError(f"set_state: expected an EnvState (get_state), got {state!r:.80}")
        if state.env != here:
            raise ValueError(f"set_state: a snapshot of {state.env}, not of {here}")
        if state.params != self.params:
            theirs, ours = dataclasses.asdict(state.params), dataclasses.asdict(self.params)
            diff = [f"{k}={v!r} (here {ours[k]!r})" for k, v in theirs.items() if v != ours[k]]
            raise ValueError(f"set_state: the snapshot's env has other parameters: {diff}")
        if len(state) != ids.size or np.unique(ids).size != ids.size:
            raise ValueError(
                f"set_state: a snapshot of {len(state)} sub-envs cannot fill env_ids of "
                f"{ids.size} ({np.unique(ids).size} distinct): one row per sub-env, each once "
                "(EnvState.repeat or clone_state copy one sub-env into many)"
            )
        fields = self._state_arrays()
        if set(state.task) != {name for name, _ in fields}:
            raise ValueError(
                f"set_state: the snapshot's task arrays {sorted(state.task)} are not this "
                f"env's {sorted(name for name, _ in fields)}"
            )
        for name, axis in fields:  # every check before the first write
            arr, got = getattr(self, name), np.asarray(state.task[name])
            want = (ids.size, *np.delete(arr.shape, axis))
            if got.shape != want or got.dtype != arr.dtype:
                raise ValueError(
                    f"set_state: snapshot array {name!r} is {got.dtype}{list(got.shape)}, "
                    f"expected {arr.dtype}{list(want)}"
                )
        self.sim.set_state(state.physics, ids)  # checks its own arrays before writing
        for name, axis in fields:
            np.moveaxis(getattr(self, name), axis, 0)[ids] = state.task[name]
        for i, rng_state in zip(ids, state.rngs, strict=True):
            if rng_state is None:
                self._rngs[i] = None
                continue
            if self._rngs[i] is None:
                self._rngs[i] = np.random.Generator(np.random.PCG64())
            self._rngs[i].bit_generator.state = rng_state
        self._np_random = self._rngs[0]
        return self._obs.copy()

    def clone_state(self, src_env: int, dst_env_ids) -> None:
        """Copy sub-env ``src_env`` into sub-envs ``dst_env_ids``: each then steps as it would."""
        if not (
            isinstance(src_env, (int, np.integer))
            and not isinstance(src_env, bool)
            and 0 <= src_env < self.num_envs
        ):
            raise ValueError(
                f"clone_state: src_env must be a sub-env index in [0, {self.num_envs}), "
                f"got {src_env!r}"
            )
        src = np.array([src_env], dtype=np.int64)
        dst = self._ids("clone_state", dst_env_ids)
        self.set_state(self.get_state(src).repeat(dst.size), dst)

    def redraw_future(self, task: dict, rng: np.random.Generator) -> dict:
        """A snapshot's task arrays (``EnvState.task``) with what its episodes drew at their
        start for later, and have not met yet, drawn again from ``rng``: the planner's
        rollouts then meet a future like the episode's, not the episode's own. The present
        (and the past) is kept. A scene with such draws overrides this; here there are none."""
        return task

    def _state_arrays(self) -> tuple[tuple[str, int], ...]:
        return _BASE_STATE + tuple(self.state_fields)

    def _ids(self, what: str, env_ids) -> np.ndarray:
        """``env_ids`` as indices (None: every sub-env), or an error naming them (the
        Simulator's check: its environments are the sub-envs)."""
        return self.sim._env_ids(what, env_ids).astype(np.int64)

    def render(self):
        if self.render_mode is None:
            gym.logger.warn("render() called without render_mode; pass render_mode='rgb_array'")
            return None
        return tuple(self.view.frame(i) for i in range(self.num_envs))

    # ---- internals ------------------------------------------------------------------------

    def _observation_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """[-1, 1] for a column of unit "1" (a sine or cosine, a direction's component, an
        actuator's normalized position, a wetted fraction) that no instrument reads (a
        reading's noise has no bound); unbounded elsewhere (speeds, distances: the runaway
        flag ends an episode before they leave the model, but no closed bound holds)."""
        unit = np.array([u == "1" for _, u, _ in self.observation_layout[: self.obs_dim]])
        high = np.where(unit & ~self._read_by_instrument(), 1.0, np.inf).astype(np.float32)
        return -high, high

    def _read_by_instrument(self) -> np.ndarray:
        """[obs_dim] bool: the columns an instrument reads (none without sensors)."""
        return np.zeros(self.obs_dim, dtype=bool)

    def _seed(self, sequences) -> None:
        self._rngs = [np.random.Generator(np.random.PCG64(s)) for s in sequences]
        self._np_random = self._rngs[0]
        self._pool_next[:] = self._pool_episodes  # new generators: the pools are spent

    def _draws(self, ids: np.ndarray) -> np.ndarray:
        """The next episode's uniforms of sub-envs ``ids`` [len(ids), draws_per_episode],
        from their pools, refilled from their generators where spent."""
        n, k = self.draws_per_episode, self._pool_episodes
        for i in ids[self._pool_next[ids] >= k]:
            self._pool[i] = self._rngs[i].random(k * n)
            self._pool_next[i] = 0
        at = self._pool_next[ids]
        self._pool_next[ids] += 1
        return self._pool.reshape(self.num_envs, k, n)[ids, at]

    def _start(self, ids: np.ndarray) -> None:
        # no action yet, nor the last episode's controls (what a viewer draws of the new
        # episode); the scene's start may set its own
        self._act[ids] = 0.0
        self.sim.center_actuators(ids)
        self._draw_reset(ids, self._draws(ids))
        self._elapsed[ids] = 0
        self._episodes[ids] += 1
        self._sums[:, ids] = 0.0
        self._needs_reset[ids] = False

    def _read(self, ids: np.ndarray, start: bool, skip=None) -> None:
        """The sensors' readings of sub-envs ``ids`` into ``_obs`` from ``_truth``
        (``start``: their episodes begin; ``skip`` [E]: keep these readings); nothing
        without sensors (_obs is _truth)."""
        if self._truth is not self._obs:
            skip = self._keep_none if skip is None else skip
            self.sensors.read(ids, start, self._elapsed, self.noise_keys, self._truth,
                              self._obs, skip)  # fmt: skip

    def _info_after_reset(self) -> dict:
        """What a reset tells of the new episodes (also put in a step's info, masked, where
        sub-envs restarted): nothing here."""
        return {}


def _child(seed, i: int, stream: str) -> np.random.SeedSequence:
    """The sequence of a sub-env given its own seed: a SeedSequence as it is, an integer's
    single child in ``stream`` (as the single env reset with it)."""
    if isinstance(seed, np.random.SeedSequence):
        return seed
    return SD.root(CK.seed("reset", f"seed[{i}]", seed), stream).spawn(1)[0]


# what every scene's sub-env holds beyond its scene's state_fields: (attribute, sub-env axis)
_BASE_STATE = (
    ("_pool", 0),
    ("_pool_next", 0),
    ("_obs", 0),
    ("_truth", 0),
    ("_elapsed", 0),
    ("_sums", 1),
    ("_act", 0),
    ("_needs_reset", 0),
    ("_episodes", 0),
)


def _fps(period_s: float) -> float | int:
    """Frames per second of one frame per action: an int where the action rate is one."""
    fps = 1.0 / period_s
    return round(fps) if abs(fps - round(fps)) < 1e-9 * fps else fps


def _read_only(a: np.ndarray) -> np.ndarray:
    view = a.view()
    view.flags.writeable = False
    return view


# --------------------------------------------------------------------------------------------
# the single env: the batch of one


def _first(value):
    """Sub-env 0's entry of a batched info value."""
    if isinstance(value, dict):
        return {k: _first(v) for k, v in value.items() if not k.startswith("_")}
    if isinstance(value, np.ndarray) and value.ndim >= 1:
        v = value[0]
        return v.item() if isinstance(v, np.generic) else v
    return value


class FluidEnv(gym.Env):
    """A single env that is a :class:`FluidVectorEnv` of one sub-env without autoreset."""

    vector_cls: type[FluidVectorEnv]
    metadata = FluidVectorEnv.metadata
    _spec = None

    def __init__(self, render_mode: str | None = None, **kwargs) -> None:
        self.vector = self.vector_cls(
            num_envs=1, render_mode=render_mode, autoreset=False, **kwargs
        )
        self.params, self.version = self.vector.params, self.vector.version
        self.metadata = {**type(self).metadata, "render_fps": self.vector.metadata["render_fps"]}
        self.render_mode = render_mode
        self.action_space = self.vector.single_action_space
        self.observation_space = self.vector.single_observation_space

    def reset(self, *, seed: int | None = None, options=None):
        """``seed``: None or an integer >= 0; ``options`` as the vector env's."""
        seed = CK.seed("reset", "seed", seed)  # a NumPy int as an int: gymnasium takes ints
        self.vector._reset_ids(options)  # checked before gymnasium's generator is touched
        self.vector._stream(seed, options)
        super().reset(seed=seed)  # keeps gymnasium's bookkeeping; the generator is replaced
        obs, info = self.vector.reset(seed=None if seed is None else [seed], options=options)
        self._np_random = self.vector._rngs[0]
        return obs[0], _first(info)

    def step(self, action):
        a = CK.real_array("step", "action", action)
        if a.shape not in (self.action_space.shape, (1, *self.action_space.shape)):
            raise ValueError(
                f"step: action must have shape {self.action_space.shape} "
                f"({', '.join(self.vector.action_names)}), got {a.shape}: {CK.show(action)}"
            )
        obs, reward, terminated, truncated, info = self.vector.step(a.reshape(1, -1))
        return obs[0], float(reward[0]), bool(terminated[0]), bool(truncated[0]), _first(info)

    def get_state(self) -> EnvState:
        """A snapshot of the env (:meth:`FluidVectorEnv.get_state`)."""
        return self.vector.get_state()

    def limit_episodes(self, steps: int) -> None:
        """Truncate episodes after ``steps`` actions from now on (``max_episode_steps``)."""
        params = dataclasses.replace(self.params, max_episode_steps=steps)  # checked
        self.vector.params = self.params = params

    @property
    def spec(self):
        return self._spec

    @spec.setter
    def spec(self, spec) -> None:
        # gym.make(id, max_episode_steps=N) gives N to the TimeLimit it wraps around the env
        # and nothing to the env, which truncates (and scores an episode's last step) on its
        # own limit: set on the env right after building it, the spec is the one moment the
        # env can take N from make's frame, so that both limits agree (-1, no TimeLimit: the
        # env keeps its own)
        self._spec = spec
        caller = sys._getframe(1)
        if caller.f_code is gym.envs.registration.make.__code__:
            steps = caller.f_locals.get("max_episode_steps")
            given = "max_episode_steps" in (caller.f_locals.get("env_spec_kwargs") or {})
            if steps is None and not given:  # the spec's (gym.make(env.spec) of one made so)
                steps = getattr(caller.f_locals.get("env_spec"), "max_episode_steps", None)
            if isinstance(steps, int) and steps > 0 and steps != self.params.max_episode_steps:
                self.limit_episodes(steps)

    def set_state(self, state: EnvState) -> np.ndarray:
        """Restore a snapshot of this env (or of one sub-env of a vector env of it: take it
        with ``EnvState.take([i])``); returns the observation."""
        obs = self.vector.set_state(state)
        self._np_random = self.vector._rngs[0]
        return obs[0]

    def render(self):
        frames = self.vector.render()
        return None if frames is None else frames[0]

    def close(self) -> None:
        self.vector.close()
