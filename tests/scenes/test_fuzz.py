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


@pytest.mark.parametrize("env_id", [i for i in SCENES if i.endswith("-v1")])
def test_a_witness_at_a_quarter_step_agrees_or_the_flag_says_why(env_id):
    """benchmarks/witness.py at a small budget: the witness takes the env's state before each
    action (the two then differ by the step's error only, far under the tolerances in
    position and attitude), and no
    wrong step goes unflagged, at hard's extremes and at a draw of every knob in its range."""
    import numpy as np

    from benchmarks.fuzz import WITNESS_TOLERANCE_DEG, WITNESS_TOLERANCE_M, run_witness
    from benchmarks.witness import DrawCase, draw

    integrator = SCENES[env_id].params_cls().integrator
    knobs = tuple(draw(env_id, np.random.default_rng(3)).items())
    if env_id.startswith("fluidsim/BoatOnStep"):  # a sea of any height, at a period it holds
        knobs += (("sea_tp_s", 8.0),)
    for case in (
        Case(env_id, "extreme", "float64", integrator),
        DrawCase(env_id, "nominal", "float64", integrator, knobs=knobs),
    ):
        r = run_witness(case, env_steps=3_200, num_envs=32, seed=7)
        assert r["unflagged_disagreements"] == 0, r
        assert 0.0 < r["max_disagreement_m"] < WITNESS_TOLERANCE_M, r
        assert 0.0 < r["max_disagreement_deg"] < WITNESS_TOLERANCE_DEG, r
