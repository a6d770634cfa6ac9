"""The fuzz benchmark (benchmarks/fuzz.py) at a small budget: adversarial actions on every
env, nominal and at the parameters' extremes, never give a non-finite observation, reward or
final observation, nor a runaway that is not flagged. The published run (1e8 env-steps) is
in docs/fuzz.csv."""

import pytest

from benchmarks.fuzz import Case, run_case
from fluidsim_envs.scenes import SCENES


@pytest.mark.parametrize("params", ["nominal", "extreme"])
@pytest.mark.parametrize("env_id", list(SCENES))
def test_fuzzed_env_stays_finite_and_flags_every_runaway(env_id, params):
    case = Case(env_id, params, "float64", SCENES[env_id].params_cls().integrator)
    r = run_case(case, env_steps=8_000, num_envs=32, seed=7)
    assert r["env_steps"] == 8_000
    assert r["nonfinite"] == 0
    assert r["unflagged_runaways"] == 0
    # at the default step, inside the measured limit, no episode runs away
    assert r["diverged"] == 0, r
