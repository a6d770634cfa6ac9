"""Bad inputs to the envs of every registered id: ``gym.make`` keyword arguments, reset seeds
and options, actions of the single and the vector env, and snapshot misuse (``get_state``,
``set_state``, ``clone_state``, ``EnvState.take`` / ``repeat``): each is refused with an
error that names the argument and the bad value. And NumPy scalars are numbers to the envs.

The envs here are built once per worker (:func:`functools.cache`, one sub-env or two) and
shared by the rows: every row is refused before anything changes, so sharing changes no
result. Parameter rows fail in the parameters' check, before a simulator is built."""

from __future__ import annotations

import functools

import gymnasium as gym
import numpy as np
import pytest

import fluidsim_envs  # noqa: F401  (registers the ids)
from fluidsim_envs.scenes import SCENES
from tests.bad_inputs.table import Row, check, params

NAN, INF = float("nan"), float("inf")
DART, BOAT, SUB = "fluidsim/PaperAirplane-v0", "fluidsim/BoatOnStep-v0", "fluidsim/SubmarineWake-v0"
DART1, BOAT1, SUB1 = (e.replace("-v0", "-v1") for e in (DART, BOAT, SUB))
SHORT = {DART: "dart", BOAT: "boat", SUB: "sub", DART1: "dart1", BOAT1: "boat1", SUB1: "sub1"}
assert set(SHORT) == set(SCENES), "a new scene needs its rows here"


def n_actions(env_id: str) -> int:
    return len(SCENES[env_id].vector_cls.action_names)


@functools.cache
def single(env_id: str):
    """``gym.make(env_id)`` (with its wrappers, as users get it), reset once."""
    env = gym.make(env_id)
    env.reset(seed=0)
    return env


@functools.cache
def vector(env_id: str, **kwargs):
    """The vector env of two sub-envs, through ``gym.make_vec``, reset once."""
    venv = gym.make_vec(env_id, num_envs=2, vectorization_mode="vector_entry_point", **kwargs)
    venv.reset(seed=0)
    return venv


def make(env_id: str, **kwargs):
    return functools.partial(gym.make, env_id, **kwargs)


def make_vec(env_id: str, **kwargs):
    return functools.partial(gym.make_vec, env_id, vectorization_mode="vector_entry_point",
                             **kwargs)  # fmt: skip


# --------------------------------------------------------------------------------------------
# parameters: gym.make(id, **kwargs)

# (row, kwargs, words) that every scene refuses alike; the id and the scene's name in words
COMMON = [
    ("dt-nan", {"dt": NAN}, ["dt", "nan"]),
    ("dt-big-np", {"dt": np.float32(1.0)}, ["dt", "1.0"]),
    ("dt-str", {"dt": "0.01"}, ["dt", "'0.01'"]),
    ("dt-bool", {"dt": True}, ["dt", "True"]),
    ("dt-0", {"dt": 0.0}, ["dt", "0.0"]),
    ("substeps-float", {"substeps": 1.5}, ["substeps", "1.5", "integer"]),
    ("substeps-0", {"substeps": 0}, ["substeps", "got 0"]),
    ("integrator-name", {"integrator": "leapfrog"}, ["integrator", "'leapfrog'", "rk4"]),
    ("integrator-int", {"integrator": 3}, ["integrator", "got 3"]),
    ("dtype-f16", {"dtype": "float16"}, ["dtype", "'float16'", "float32"]),
    ("dtype-type", {"dtype": np.float32}, ["dtype", "numpy.float32"]),
    ("w-crash-neg", {"w_crash": -1.0}, ["w_crash", "-1.0", "in [0, 1000]"]),
    ("w-crash-str", {"w_crash": "big"}, ["w_crash", "'big'"]),
]

# gym.make takes max_episode_steps for its own TimeLimit (and checks it there): the vector
# env's gym.make_vec passes it on to the scene's parameters
VEC_COMMON = [
    ("steps-0", {"max_episode_steps": 0}, ["max_episode_steps", "got 0"]),
    ("steps-npfloat", {"max_episode_steps": np.float64(10)}, ["max_episode_steps", "10.0"]),
    ("steps-inf", {"max_episode_steps": INF}, ["max_episode_steps", "inf"]),
    ("steps-str", {"max_episode_steps": "50"}, ["max_episode_steps", "'50'"]),
]

# each scene's own: (row, kwargs, words)
OWN = {
    DART: [
        ("launch-height-reversed", {"launch_height_m": (8.0, 4.0)},
         ["launch_height_m", "(8.0, 4.0)", "low <= high"]),
        ("launch-height-scalar", {"launch_height_m": 5.0}, ["launch_height_m", "5.0", "pair"]),
        ("launch-height-nan", {"launch_height_m": (NAN, 5.0)}, ["launch_height_m", "nan"]),
        ("launch-speed-3", {"launch_speed_mps": (1, 2, 3)}, ["launch_speed_mps", "(1, 2, 3)"]),
        ("bearing-wide", {"target_bearing_deg": (-270.0, 0.0)},
         ["target_bearing_deg", "-270.0", "[-180, 180]"]),
        ("arena-neg", {"arena_radius_m": -1.0}, ["arena_radius_m", "-1.0"]),
        ("upright-2", {"upright_min": 2.0}, ["upright_min", "2.0", "[-1, 1]"]),
        ("ceiling-low", {"ceiling_m": 5.0}, ["ceiling_m", "5.0", "launch"]),
        ("wind-bool", {"wind_speed_mps": (False, True)}, ["wind_speed_mps", "False"]),
    ],
    BOAT: [
        ("swell-int", {"swell": 5}, ["swell", "5"]),
        ("swell-steep", {"swell": [(5.0, 10.0)]}, ["swell", "steepness", "amplitude_m=5.0"]),
        ("buoy-bodies-int", {"buoy_bodies": 1}, ["buoy_bodies", "got 1", "True or False"]),
        ("power-0", {"engine_power_w": 0}, ["engine_power_w", "got 0"]),
        ("speed-str", {"target_speed_mps": ("a", "b")}, ["target_speed_mps", "'a'"]),
        ("turn-wide", {"turn_deg": (-200.0, 0.0)}, ["turn_deg", "-200.0", "[-120, 120]"]),
        ("buoy-radius-wide", {"buoy_radius_m": 9.0},
         ["buoy_radius_m", "9.0", "gate_half_width_m"]),
        ("heel-nan", {"capsize_heel_deg": NAN}, ["capsize_heel_deg", "nan"]),
    ],
    SUB: [
        ("wake-int", {"wake": 1}, ["wake", "got 1", "True or False"]),
        ("screws-3", {"screws": 3}, ["screws", "3", "[1, 2]"]),
        ("dipoles-0", {"wake_dipoles": 0}, ["wake_dipoles", "0"]),
        ("straight-1.5", {"straight_fraction": 1.5}, ["straight_fraction", "1.5", "[0, 1]"]),
        ("floor-shallow", {"floor_depth_m": 30.0}, ["floor_depth_m", "30.0", "lead"]),
        ("depth-reversed", {"lead_depth_m": (40.0, 25.0)}, ["lead_depth_m", "(40.0, 25.0)"]),
        ("noise-neg", {"noise": -0.5}, ["noise", "-0.5"]),
        ("circulation-str", {"circulation": "1"}, ["circulation", "'1'"]),
    ],
}  # fmt: skip
# v1's knobs (scenes/realism.py), refused alike by every v1 scene
KNOBS = [
    ("difficulty-name", {"difficulty": "medium"}, ["difficulty", "'medium'", "standard"]),
    ("difficulty-int", {"difficulty": 1}, ["difficulty", "got 1"]),
    ("sensor-scale-neg", {"sensor_scale": -0.5}, ["sensor_scale", "-0.5", "[0, 10]"]),
    ("latency-float", {"sensor_latency_steps": 1.5}, ["sensor_latency_steps", "1.5", "integer"]),
    ("tau-0", {"surface_time_constant_s": 0.0}, ["surface_time_constant_s", "0.0"]),
    ("thrust-tau-0", {"thrust_time_constant_s": 0}, ["thrust_time_constant_s", "got 0"]),
    ("rate-nan", {"surface_rate_dps": NAN}, ["surface_rate_dps", "nan"]),
    ("mass-reversed", {"mass_scale": (1.2, 0.8)}, ["mass_scale", "(1.2, 0.8)", "low <= high"]),
    ("mass-0", {"mass_scale": (0.0, 1.0)}, ["mass_scale", "0.0", "finite number in ["]),
    ("efficiency-up", {"efficiency_scale": (1.0, 1.2)}, ["efficiency_scale", "1.2", "[0, 1]"]),
    ("actuators-int", {"actuators": 1}, ["actuators", "got 1", "True or False"]),
    ("probes-str", {"observe_samples": "yes"}, ["observe_samples", "'yes'", "True or False"]),
]
for _v0, _v1 in ((DART, DART1), (BOAT, BOAT1), (SUB, SUB1)):
    OWN[_v1] = OWN[_v0] + KNOBS
OWN[DART1] += [  # the dart's moving air
    ("turbulence-name", {"turbulence": "stormy"}, ["turbulence", "'stormy'", "moderate"]),
    ("gust-neg", {"gust_mps": -1.0}, ["gust_mps", "-1.0", "[0, 20]"]),
    ("gust-duration-0", {"gust_duration_s": 0.0}, ["gust_duration_s", "0.0"]),
]
OWN[BOAT1] += [  # the boat's moving air and water
    ("sea-neg", {"sea_hs_m": -0.1}, ["sea_hs_m", "-0.1", "[0, 1.2]"]),
    ("sea-and-swell", {"sea_hs_m": 0.2, "swell": [(0.1, 20.0)]}, ["swell", "sea_hs_m", "both"]),
    ("wind-nan", {"wind_mps": NAN}, ["wind_mps", "nan"]),
]
OWN[SUB1] += [  # the UUV's current
    ("current-neg", {"current_mps": -0.2}, ["current_mps", "-0.2", "[0, 3]"]),
    ("current-time-0", {"current_time_s": 0.0}, ["current_time_s", "0.0"]),
]


def param_rows() -> list[Row]:
    rows = []
    for env_id, short in SHORT.items():
        scene = env_id.split("/")[1]
        for name, kwargs, words in COMMON + OWN[env_id]:
            rows.append(Row(f"{short}-{name}", make(env_id, **kwargs), ValueError, [scene, *words]))
        for name, kwargs, words in VEC_COMMON:
            call = make_vec(env_id, num_envs=1, **kwargs)
            rows.append(Row(f"{short}-vec-{name}", call, ValueError, [scene, *words]))
        rows.append(Row(f"{short}-unknown-param", make(env_id, wnd=1.0), TypeError,
                        ["unknown parameter", "'wnd'", "dt"]))  # fmt: skip
        rows.append(Row(f"{short}-num-envs-0", make_vec(env_id, num_envs=0), ValueError,
                        ["num_envs", "got 0", "positive"]))  # fmt: skip
        rows.append(Row(f"{short}-num-envs-float", make_vec(env_id, num_envs=1.5), ValueError,
                        ["num_envs", "1.5"]))  # fmt: skip
    cls = SCENES[DART].vector_cls
    rows += [
        Row("dart-num-envs-bool", lambda: cls(num_envs=True), ValueError, ["num_envs", "True"]),
        Row("dart-render-human", lambda: cls(render_mode="human"), ValueError,
            ["render_mode", "'human'", "rgb_array"]),
    ]  # fmt: skip
    return rows


# --------------------------------------------------------------------------------------------
# reset: seeds and options

SEEDS = [  # (row, seed, words) on the vector env of 2
    ("float", 1.5, ["seed", "1.5", "integer in [0, 2**128)"]),
    ("negative", -1, ["seed", "-1"]),
    ("huge", 2**128, ["seed", str(2**128)]),  # past it, seed streams could meet
    ("bool", True, ["seed", "True"]),
    ("str", "1", ["seed", "'1'"]),
    ("npfloat", np.float64(3.0), ["seed", "3.0"]),
    ("dict", {"a": 1}, ["seed", "{'a': 1}"]),
    ("list-float", [1, 2.5], ["seed[1]", "2.5"]),
    ("list-negative", [1, -1], ["seed[1]", "-1"]),
    ("list-short", [1], ["seeds", "2", "got 1"]),
    ("list-nested", [[1], [2]], ["seed[0]", "[1]"]),
]

OPTIONS = [  # (row, options, words) on the vector env of 2
    ("ids-half", {"env_ids": [0.5]}, ["env_ids", "[0.5]", "[0, 2)"]),
    ("ids-10", {"env_ids": [10]}, ["env_ids", "[10]", "out of range", "[0, 2)"]),
    ("ids-negative", {"env_ids": [-1]}, ["env_ids", "-1"]),
    ("ids-mask-short", {"env_ids": np.array([True])}, ["env_ids", "mask", "(2,)", "(1,)"]),
    ("ids-mask-2d", {"env_ids": np.array([[True, False]])}, ["env_ids", "mask", "(1, 2)"]),
    ("ids-2d", {"env_ids": [[0, 1]]}, ["env_ids", "[[0, 1]]"]),
    ("ids-str", {"env_ids": "0"}, ["env_ids", "'0'"]),
    ("ids-scalar", {"env_ids": 1}, ["env_ids", "got 1", "list"]),
    ("ids-ragged", {"env_ids": [[0], [0, 1]]}, ["env_ids", "[[0], [0, 1]]"]),
    ("unknown-key", {"env_id": [0]}, ["unknown option", "'env_id'", "env_ids", "reset_mask"]),
    ("not-dict", "env_ids", ["options", "'env_ids'", "dict"]),
    ("both", {"env_ids": [0], "reset_mask": np.array([True, False])},
     ["env_ids", "reset_mask", "not both"]),
    ("mask-list", {"reset_mask": [True, False]}, ["reset_mask", "[True, False]", "boolean"]),
    ("mask-ints", {"reset_mask": np.array([1, 0])}, ["reset_mask", "array([1, 0])"]),
    ("mask-short", {"reset_mask": np.array([True])}, ["reset_mask", "(2,)", "(1,)"]),
]  # fmt: skip


def reset_rows() -> list[Row]:
    rows = []
    for name, seed, words in SEEDS:
        rows.append(Row(f"vec-seed-{name}", lambda s=seed: vector(DART).reset(seed=s),
                        ValueError, ["reset", *words]))  # fmt: skip
    for name, options, words in OPTIONS:
        rows.append(Row(f"vec-options-{name}", lambda o=options: vector(DART).reset(options=o),
                        ValueError, ["reset", *words]))  # fmt: skip
    for env_id, short in SHORT.items():
        rows += [
            Row(f"{short}-seed-float", lambda e=env_id: single(e).reset(seed=1.5), ValueError,
                ["reset", "seed", "1.5"]),
            Row(f"{short}-seed-negative", lambda e=env_id: single(e).reset(seed=-3), ValueError,
                ["seed", "-3", "[0, 2**128)"]),
            Row(f"{short}-seed-list", lambda e=env_id: single(e).reset(seed=[1]), ValueError,
                ["seed", "[1]"]),
            Row(f"{short}-options-ids", lambda e=env_id: single(e).reset(options={"env_ids": [1]}),
                ValueError, ["env_ids", "[1]", "[0, 1)"]),
            Row(f"{short}-vec-seed-str", lambda e=env_id: vector(e).reset(seed="x"), ValueError,
                ["seed", "'x'"]),
        ]  # fmt: skip
    return rows


# --------------------------------------------------------------------------------------------
# actions

# (row, actions or a function of the action count, words) for the vector env of 2
VEC_ACTIONS = [
    ("str", "a", ["actions", "'a'", "numbers"]),
    ("none", None, ["actions", "None"]),
    ("object", lambda n: np.zeros((2, n), dtype=object), ["actions", "object"]),
    ("ragged", lambda n: [[0.0] * n, [0.0]], ["actions", "ragged"]),
    ("bools", lambda n: np.zeros((2, n), dtype=bool), ["actions", "bools"]),
    ("shape", lambda n: np.zeros(n), ["actions", "shape (2, ", "got ({n},)"]),
    ("nan", lambda n: np.full((2, n), NAN), ["actions", "nan", "(0, 0)", "finite"]),
    ("inf", lambda n: np.full((2, n), -INF), ["actions", "-inf", "(0, 0)"]),
    ("dict", {"aileron": 0.0}, ["actions", "{'aileron': 0.0}"]),
    ("complex", lambda n: np.zeros((2, n), dtype=complex), ["actions", "0.j"]),
]
SINGLE_ACTIONS = [
    ("str", "up", ["action", "'up'"]),
    ("none", None, ["action", "None"]),
    ("object", lambda n: np.array([0.0] * (n - 1) + [None], dtype=object), ["action", "None"]),
    ("ragged", lambda n: [[0.0], [0.0, 0.0]], ["action", "ragged"]),
    ("shape", lambda n: np.zeros(n + 1), ["action", "shape (", "got ({n1},)"]),
    ("nan", lambda n: np.full(n, NAN), ["actions", "nan", "finite"]),
]


def _actions(value, n: int):
    return value(n) if callable(value) else value


def _words(words: list[str], n: int) -> list[str]:
    """``{n}`` and ``{n1}`` in ``words`` as the action count and one more."""
    return [w.replace("{n}", str(n)).replace("{n1}", str(n + 1)) for w in words]


def action_rows() -> list[Row]:
    rows = []
    for env_id, short in SHORT.items():
        n = n_actions(env_id)
        for name, value, words in VEC_ACTIONS:
            call = functools.partial(lambda e, v: vector(e).step(_actions(v, n_actions(e))),
                                     env_id, value)  # fmt: skip
            rows.append(Row(f"{short}-vec-action-{name}", call, ValueError, _words(words, n)))
        for name, value, words in SINGLE_ACTIONS:
            call = functools.partial(lambda e, v: single(e).step(_actions(v, n_actions(e))),
                                     env_id, value)  # fmt: skip
            rows.append(Row(f"{short}-action-{name}", call, ValueError, _words(words, n)))
    return rows


# --------------------------------------------------------------------------------------------
# snapshots: get_state, set_state, clone_state, EnvState


def _venv():
    return vector(DART).unwrapped


def _env(env_id: str):
    """The single env under gym.make's wrappers, which do not pass snapshots on."""
    return single(env_id).unwrapped


def state_rows() -> list[Row]:
    V = ValueError
    other = functools.partial(vector, DART, w_crash=5.0)  # the dart with other parameters
    # fmt: off
    return [
        Row("venv-get-state-ids-5", lambda: _venv().get_state(env_ids=[5]), V,
            ["get_state", "env_ids", "[5]"]),
        Row("venv-get-state-ids-half", lambda: _venv().get_state(env_ids=[0.5]), V,
            ["get_state", "env_ids", "0.5"]),
        Row("venv-get-state-ids-str", lambda: _venv().get_state(env_ids="all"), V,
            ["get_state", "env_ids", "'all'"]),
        Row("venv-set-state-int", lambda: _venv().set_state(5), TypeError,
            ["set_state", "EnvState", "5"]),
        Row("venv-set-state-other-scene",
            lambda: _venv().set_state(vector(SUB).unwrapped.get_state()), V,
            ["set_state", "SubmarineWake", "PaperAirplane"]),
        Row("venv-set-state-other-params",
            lambda: _venv().set_state(other().unwrapped.get_state()), V,
            ["set_state", "other parameters", "w_crash=5.0"]),
        Row("venv-set-state-too-few", lambda: _venv().set_state(_venv().get_state([0])), V,
            ["set_state", "1 sub-envs", "env_ids of 2"]),
        Row("venv-set-state-repeat", lambda: _venv().set_state(_venv().get_state(), env_ids=[0, 0]),
            V, ["set_state", "env_ids", "1 distinct"]),
        Row("venv-set-state-ids-3", lambda: _venv().set_state(_venv().get_state([0]), env_ids=[3]),
            V, ["set_state", "env_ids", "[3]"]),
        Row("venv-clone-src-half", lambda: _venv().clone_state(1.5, [0]), V,
            ["clone_state", "src_env", "1.5", "[0, 2)"]),
        Row("venv-clone-src-bool", lambda: _venv().clone_state(True, [1]), V,
            ["src_env", "True"]),
        Row("venv-clone-src-negative", lambda: _venv().clone_state(-1, [0]), V,
            ["src_env", "-1"]),
        Row("venv-clone-src-2", lambda: _venv().clone_state(2, [0]), V, ["src_env", "got 2"]),
        Row("venv-clone-dst-7", lambda: _venv().clone_state(0, [7]), V,
            ["clone_state", "env_ids", "[7]"]),
        Row("venv-clone-dst-half", lambda: _venv().clone_state(0, [0.5]), V,
            ["clone_state", "env_ids", "[0.5]"]),
        Row("venv-clone-dst-str", lambda: _venv().clone_state(0, "1"), V,
            ["clone_state", "env_ids", "'1'"]),
        Row("single-set-state-int", lambda: _env(DART).set_state(5), TypeError,
            ["set_state", "EnvState", "5"]),
        Row("single-set-state-two", lambda: _env(DART).set_state(_venv().get_state()), V,
            ["set_state", "2 sub-envs", "env_ids of 1"]),
        Row("single-set-state-boat", lambda: _env(DART).set_state(_env(BOAT).get_state()),
            V, ["set_state", "BoatOnStep", "PaperAirplane"]),
        Row("take-half", lambda: _venv().get_state().take([0.5]), V,
            ["EnvState.take", "rows", "[0.5]", "[0, 2)"]),
        Row("take-3", lambda: _venv().get_state().take([3]), V, ["rows", "[3]"]),
        Row("repeat-0", lambda: _venv().get_state().repeat(0), V, ["repeat", "k", "0"]),
        Row("repeat-float", lambda: _venv().get_state().repeat(2.0), V, ["k", "2.0"]),
    ]
    # fmt: on


# a sea past what linear wave theory holds, from knobs each within its own range: the
# message names the knobs and the height and period that would do
SEA_ROWS = [
    Row("boat1-steep-sea", make_vec(BOAT1, sea_hs_m=1.2, sea_tp_s=1.7, wind_mps=30.0),
        ValueError, ["sea_hs_m=1.2", "sea_tp_s=1.7", "steepness", "sea_tp_s >=",
                     "sea_hs_m <="]),
]  # fmt: skip

ROWS = param_rows() + reset_rows() + action_rows() + state_rows() + SEA_ROWS


@pytest.mark.parametrize("row", params(ROWS))
def test_bad_env_input_is_named(row):
    check(row)


# --------------------------------------------------------------------------------------------
# what a boolean mask resets, and NumPy scalars as numbers


def _episodes_after(options) -> np.ndarray:
    venv = SCENES[DART].vector_cls(num_envs=3)
    venv.reset(seed=1)
    before, obs = venv.episodes.copy(), venv.observation.copy()
    venv.reset(options=options)
    restarted = venv.episodes - before
    kept = restarted == 0
    np.testing.assert_array_equal(venv.observation[kept], obs[kept])  # untouched rows stay
    return restarted


@pytest.mark.parametrize(
    "options, restarted",
    [
        ({"env_ids": np.array([False, True, True])}, [0, 1, 1]),  # a mask, not indices 0 and 1
        ({"reset_mask": np.array([True, False, True])}, [1, 0, 1]),  # Gymnasium's convention
        ({"env_ids": [2]}, [0, 0, 1]),
        ({"env_ids": np.array([0, 2], dtype=np.uint8)}, [1, 0, 1]),
        ({"env_ids": []}, [0, 0, 0]),
        ({"reset_mask": np.zeros(3, dtype=bool)}, [0, 0, 0]),
        (None, [1, 1, 1]),
    ],
)
def test_reset_options_restart_exactly_the_named_sub_envs(options, restarted):
    np.testing.assert_array_equal(_episodes_after(options), restarted)


NUMPY_PARAMS = {  # each scene's parameters given as NumPy scalars and arrays
    DART: {"launch_height_m": np.array([4.0, 6.0], np.float32), "w_effort": np.float32(0.02)},
    BOAT: {"engine_power_w": np.int64(60_000), "buoy_bodies": np.bool_(False)},
    SUB: {"wake_dipoles": np.int32(8), "screws": np.int64(2), "wake": np.bool_(True)},
}
for _v0, _v1 in ((DART, DART1), (BOAT, BOAT1), (SUB, SUB1)):  # and v1's knobs
    NUMPY_PARAMS[_v1] = {**NUMPY_PARAMS[_v0], "sensor_latency_steps": np.int64(2),
                         "mass_scale": np.array([0.9, 1.1]), "actuators": np.bool_(True),
                         "sensor_scale": np.float32(0.5)}  # fmt: skip


@pytest.mark.parametrize("env_id", sorted(SHORT))
def test_numpy_scalars_are_numbers_to_the_envs(env_id):
    dt = SCENES[env_id].params_cls().dt
    kwargs = {"dt": np.float32(dt), "substeps": np.int64(2), **NUMPY_PARAMS[env_id]}
    env = gym.make(env_id, **kwargs)
    p = env.unwrapped.params
    assert type(p.dt) is float and type(p.substeps) is int and p.substeps == 2
    env.reset(seed=np.int64(3))
    env.step(np.zeros(n_actions(env_id), np.float32))

    venv = gym.make_vec(env_id, num_envs=np.int64(2), vectorization_mode="vector_entry_point",
                        max_episode_steps=np.int32(50), **kwargs)  # fmt: skip
    venv.reset(seed=[np.int64(1), np.uint32(2)], options={"env_ids": np.array([1], np.int32)})
    venv.reset(seed=np.uint64(4), options={"reset_mask": np.array([True, False])})
    venv.step(np.zeros((2, n_actions(env_id)), np.float16))
    base = venv.unwrapped
    base.clone_state(np.int64(0), np.array([1], np.int16))
    base.set_state(base.get_state(np.array([1, 0], np.int64)), env_ids=[np.int64(0), 1])
    assert base.params.max_episode_steps == 50
