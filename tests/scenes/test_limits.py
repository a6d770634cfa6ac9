"""Each scene's step limit is the measured one (docs/env_stability.csv, written by
``python -m benchmarks.env_stability``), its default sits inside it, and a step past it is
refused with the limit in the message."""

import math
import pathlib

import gymnasium as gym
import pytest

from benchmarks.common import read_csv
from fluidsim_envs.physics.kernels import INTEGRATORS
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes import limits as LIM

CSV = pathlib.Path(__file__).parents[2] / "docs" / "env_stability.csv"


def _measured() -> dict[str, dict[str, float]]:
    _, rows = read_csv(CSV)
    out: dict[str, dict[str, float]] = {}
    for row in rows:
        out.setdefault(row["env"].split("/")[1], {})[row["integrator"]] = float(row["dt_limit_s"])
    return out


def test_the_limits_table_is_the_measured_one():
    measured = _measured()
    assert set(measured) == {i.split("/")[1] for i in SCENES}  # every version its own
    for scene, limits in measured.items():
        assert set(limits) == set(INTEGRATORS), scene
        for integrator, value in limits.items():
            code = LIM.DT_LIMIT_S[scene].get(integrator, math.nan)
            assert code == value or (math.isnan(code) and math.isnan(value)), (
                f"{scene} {integrator}: limits.py says {code}, the CSV {value}: run "
                "python -m benchmarks.env_stability and copy its table"
            )


@pytest.mark.parametrize("env_id", [i for i in SCENES if SCENES[i].version > 0])
def test_a_later_version_is_limited_at_most_to_its_v0s_step(env_id):
    # v1 at easy flies v0's craft in v0's world: its limit (measured at hard) is bounded by
    # v0's (benchmarks/env_stability.py bisects below it)
    own, first = (
        LIM.DT_LIMIT_S[env_id.split("/")[1]],
        LIM.DT_LIMIT_S[SCENES[env_id].first_id.split("/")[1]],
    )
    assert set(own) == set(first)
    for integrator, limit in own.items():
        # nan: no step tried held (v0's nan makes the later version's nan too)
        if math.isnan(first[integrator]):
            assert math.isnan(limit), integrator
        else:
            assert limit <= first[integrator], integrator


@pytest.mark.parametrize("env_id", list(SCENES))
def test_the_default_step_is_inside_its_limit(env_id):
    p = SCENES[env_id].params_cls()
    assert p.dt <= LIM.DT_LIMIT_S[env_id.split("/")[1]][p.integrator]


@pytest.mark.parametrize("env_id", list(SCENES))
def test_a_step_past_the_limit_is_refused_naming_the_limit(env_id):
    cls = SCENES[env_id].params_cls
    limits = LIM.DT_LIMIT_S[env_id.split("/")[1]]
    # the integrator whose limit is the tightest (the boat's others reach the range's end;
    # one that held at no step is refused at every step: below)
    integrator = min((i for i in limits if not math.isnan(limits[i])), key=limits.get)
    limit = limits[integrator]
    assert limit < cls.RANGES["dt"].hi
    want = rf"dt must be <= {limit:g} s with integrator '{integrator}'"
    with pytest.raises(ValueError, match=want):
        cls(dt=limit * 1.01, integrator=integrator)
    cls(dt=limit, integrator=integrator)  # the limit itself is allowed
    with LIM.unchecked():  # how the limit is measured
        cls(dt=limit * 1.01, integrator=integrator)
    with pytest.raises(ValueError, match="dt must be <="):
        gym.make(env_id, dt=limit * 1.01, integrator=integrator)


@pytest.mark.parametrize("env_id", list(SCENES))
def test_reward_weights_are_bounded(env_id):
    cls = SCENES[env_id].params_cls
    with pytest.raises(ValueError, match=r"w_crash must be a finite number in \[0, 1000\]"):
        cls(w_crash=1e308)


def test_an_integrator_that_held_at_no_step_is_refused_by_name():
    """A nan limit (it diverged in the fuzz at every step tried): any dt is refused, the
    message says why."""
    unheld = [(s, i) for s, limits in LIM.DT_LIMIT_S.items() for i, v in limits.items()
              if math.isnan(v)]  # fmt: skip
    assert unheld  # SubmarineWake's implicit midpoint (docs/env_stability.csv)
    for scene, integrator in unheld:
        env_id = f"fluidsim/{scene}"
        with pytest.raises(ValueError, match=f"integrator '{integrator}' diverged in this env"):
            SCENES[env_id].params_cls(dt=1e-4, integrator=integrator)
