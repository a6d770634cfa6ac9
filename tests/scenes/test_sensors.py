"""The sensor model of scenes/sensors.py against its definition: white noise of the
configured standard deviation, a first-order Gauss-Markov bias (stationary standard
deviation ``bias``, autocorrelation exp(-lag / bias_time_s): IEEE Std 952-1997, annex C),
resolution and latency. Tolerances: five standard errors of each estimator."""

import math

import numpy as np
import pytest

from fluidsim_envs.scenes import noise as NZ
from fluidsim_envs.scenes.sensors import Sensor, SensorModel

E = 20_000
H = 0.1  # s between readings


def _run(sensor, steps, latency=0, truth=None, names=("x",)):
    model = SensorModel((sensor,), names, 1.0, H, latency, E)
    keys = NZ.keys_from_uniforms(np.random.default_rng(3).random(E))
    ids = np.arange(E)
    counter = np.zeros(E, dtype=np.int64)
    t = np.zeros((E, len(names)), dtype=np.float32)
    out = np.zeros_like(t)
    rows = []
    for k in range(steps):
        counter[:] = k
        if truth is not None:
            t[:] = truth(k)
        model.read(ids, k == 0, counter, keys, t, out, np.zeros(E, bool))
        rows.append(out[:, 0].astype(np.float64).copy())
    return np.array(rows)  # [steps, E]


def test_white_noise_has_its_standard_deviation():
    x = _run(Sensor("n", ("x",), noise=0.1), 3)
    se = 0.1 / math.sqrt(2 * E)  # of a sample standard deviation
    for row in x:
        assert abs(row.std() - 0.1) < 5 * se
    assert abs(np.corrcoef(x[1], x[2])[0, 1]) < 5 / math.sqrt(E)  # fresh every step


def test_bias_is_stationary_and_wanders_at_its_time_constant():
    tau = 1.0
    x = _run(Sensor("b", ("x",), noise=0.0, bias=0.2, bias_time_s=tau), 31)
    for k in (0, 10, 30):  # the turn-on bias and later: the same law
        assert abs(x[k].std() - 0.2) < 5 * 0.2 / math.sqrt(2 * E)
    for lag in (1, 10, 30):
        r = np.corrcoef(x[0], x[lag])[0, 1]
        assert abs(r - math.exp(-lag * H / tau)) < 5 / math.sqrt(E)


def test_readings_are_quantized():
    x = _run(Sensor("q", ("x",), noise=0.013, quantum=0.01), 2)
    assert np.allclose(x / 0.01, np.round(x / 0.01), atol=1e-4)
    assert np.unique(np.round(x[1] / 0.01)).size > 5


@pytest.mark.parametrize("latency", [0, 1, 3])
def test_latency_gives_the_reading_of_k_steps_ago(latency):
    x = _run(Sensor("l", ("x",), noise=0.0), 8, latency=latency, truth=lambda k: k)
    expected = [max(k - latency, 0) for k in range(8)]
    np.testing.assert_array_equal(x[:, 0], expected)


def test_unread_columns_pass_through_exactly():
    model = SensorModel((Sensor("n", ("x",), noise=1.0),), ("x", "y"), 1.0, H, 0, 4)
    truth = np.array([[0.0, 1.25]] * 4, dtype=np.float32)
    out = np.zeros_like(truth)
    keys = NZ.keys_from_uniforms(np.linspace(0, 0.9, 4))
    model.read(np.arange(4), True, np.zeros(4, np.int64), keys, truth, out, np.zeros(4, bool))
    np.testing.assert_array_equal(out[:, 1], 1.25)
    assert np.all(out[:, 0] != 0.0)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"noise": -0.1}, "noise must be a finite number >= 0, got -0.1"),
        ({"noise": 0.1, "bias": 0.1}, "a bias needs bias_time_s > 0"),
        ({"noise": 0.1, "quantum": float("nan")}, "quantum must be"),
    ],
)
def test_bad_sensors_are_named(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Sensor("bad", ("x",), **kwargs)


def test_a_column_the_observation_lacks_is_named():
    with pytest.raises(ValueError, match="reads column 'z'"):
        SensorModel((Sensor("s", ("z",), noise=0.1),), ("x",), 1.0, H, 0, 1)
