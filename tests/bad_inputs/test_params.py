"""Every env parameter past each end of its declared range (scenes/limits.py, each parameter
class's ``RANGES``), not a number, NaN, inf or a bool; spans turned around or of the wrong
length; a ``dt`` past each integrator's measured limit. Each is refused naming the parameter
and the value."""

import math

import gymnasium as gym
import pytest

from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes import limits as LIM
from tests.bad_inputs.table import Row, check, params


def _bound_rows(own, cls, key, rule):
    make = lambda v: lambda: cls(**{key: v})  # noqa: E731
    rows = []
    if rule.lo is not None:
        bad = rule.lo - (1 if rule.integer else max(abs(rule.lo) * 0.5, 1e-3))
        rows.append(Row(f"{own}-{key}-below", make(bad), ValueError, [key, f"{bad!r}"[:6]]))
    if rule.hi is not None:
        bad = rule.hi + (1 if rule.integer else max(abs(rule.hi) * 0.5, 1e-3))
        rows.append(Row(f"{own}-{key}-above", make(bad), ValueError, [key, f"{bad!r}"[:6]]))
    rows.append(Row(f"{own}-{key}-nan", make(math.nan), ValueError, [key, "nan"]))
    rows.append(Row(f"{own}-{key}-inf", make(math.inf), ValueError, [key, "inf"]))
    rows.append(Row(f"{own}-{key}-bool", make(True), ValueError, [key, "True"]))
    rows.append(Row(f"{own}-{key}-string", make("1"), ValueError, [key, "'1'"]))
    if rule.integer:
        rows.append(Row(f"{own}-{key}-float", make(2.5), ValueError, [key, "2.5", "integer"]))
    return rows


def _span_rows(own, cls, key, rule):
    make = lambda v: lambda: cls(**{key: v})  # noqa: E731
    lo, hi = rule.lo, rule.hi
    mid = (lo + hi) / 2
    under = lo - max(abs(lo) * 0.5, 1.0)
    over = hi + max(abs(hi) * 0.5, 1.0)
    return [
        Row(f"{own}-{key}-turned", make((hi, lo)), ValueError, [key, "low <= high"]),
        Row(f"{own}-{key}-low-under", make((under, mid)), ValueError, [key, f"{under:g}"]),
        Row(f"{own}-{key}-high-over", make((mid, over)), ValueError, [key, f"{over:g}"]),
        Row(f"{own}-{key}-scalar", make(mid), ValueError, [key, "(low, high) pair"]),
        Row(f"{own}-{key}-three", make((lo, mid, hi)), ValueError, [key, "(low, high) pair"]),
        Row(f"{own}-{key}-nan", make((math.nan, mid)), ValueError, [key, "nan"]),
    ]


def _step_rows(own, cls):
    rows = []
    for integrator, limit in LIM.DT_LIMIT_S.get(own, {}).items():
        if not math.isfinite(limit) or limit >= cls.RANGES["dt"].hi:
            continue  # stable over the whole range: nothing past the limit to refuse
        dt = min(limit * 1.5, cls.RANGES["dt"].hi)
        call = lambda dt=dt, m=integrator: cls(dt=dt, integrator=m)  # noqa: E731
        words = ["dt must be <=", f"{limit:g}", repr(integrator), "env_stability"]
        rows.append(Row(f"{own}-dt-past-{integrator}-limit", call, ValueError, words))
    return rows


def _rows():
    rows = []
    for env_id, scene in SCENES.items():
        own, cls = env_id.split("/")[1], scene.params_cls
        for key, rule in cls.RANGES.items():
            maker = _span_rows if isinstance(rule, LIM.Span) else _bound_rows
            rows += maker(own, cls, key, rule)
        rows += _step_rows(own, cls)
        rows += [
            Row(f"{own}-unknown-key", lambda i=env_id: gym.make(i, wind=3), TypeError,
                ["wind", "valid"]),
            Row(f"{own}-integrator", lambda c=cls: c(integrator="leapfrog"), ValueError,
                ["integrator", "'leapfrog'", "rk2"]),
            Row(f"{own}-dtype", lambda c=cls: c(dtype="float16"), ValueError,
                ["dtype", "'float16'", "float32"]),
            Row(f"{own}-autoreset", lambda v=scene.vector_cls: v(autoreset=1), ValueError,
                ["autoreset", "True or False", "1"]),
        ]  # fmt: skip
    return rows


ROWS = _rows()


@pytest.mark.parametrize("row", params(ROWS))
def test_bad_parameter(row):
    check(row)
