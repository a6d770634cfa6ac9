"""The sampling planner (scenes/planner.py): an oracle of the present whose rollouts are the
env itself, so that, told the episode's future noise (clairvoyant), the return it predicts for
its plan is the return flying that plan earns, bit for bit, and, as it ships, its plans do
not depend on that future; its budget is checked; the same seed plans the same."""

import dataclasses

import numpy as np
import pytest

from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes.planner import Planner, PlannerConfig, coloured_noise
from fluidsim_envs.scenes.submarine_wake import kernel as TK

IDS = list(SCENES)


@pytest.mark.parametrize("guided", [False, True], ids=["actions", "guided"])
@pytest.mark.parametrize("sid", IDS, ids=[s.split("/")[1] for s in IDS])
def test_a_plan_earns_what_its_rollouts_predicted(sid, guided):
    """Plan once (one knot held for the whole look-ahead), then fly it through the planner in
    the real env: the summed reward equals the clairvoyant planner's score of that plan
    exactly (its rollouts are copies of the env, the episode's noise keys included, and
    guided, of the pilot's memory, bit for bit)."""
    scene = SCENES[sid]
    venv = scene.vector_cls(num_envs=2)
    obs, _ = venv.reset(seed=11)
    planner = scene.planner(
        venv, samples=4, horizon=1, hold=6, elites=2, iterations=2, guided=guided,
        clairvoyant=True,
    )  # fmt: skip
    if guided:  # the pilot flies the episode before the plan: its memory is not empty
        for _ in range(3):
            obs, *_ = venv.step(planner.pilot(obs))
    earned, alive = np.zeros(2), np.ones(2, dtype=bool)
    for _ in range(planner.config.lookahead):
        obs, reward, terminated, truncated, _ = venv.step(planner(obs))
        earned += np.where(alive, reward, 0.0)
        alive &= ~(terminated | truncated)
    assert planner.timing["plans"] == 1 and planner.timing["physics"] > 0.0
    np.testing.assert_array_equal(earned, planner.value)


NOISY = [s for s in IDS if s.endswith("-v1")]


def _later_gust(task):
    gusts = task["_gusts"].copy()  # at the episode's start: not begun yet
    gusts[:, 0] += 0.5
    gusts[:, 3:] = gusts[:, [4, 5, 3]]
    return {"_gusts": gusts}


def _other_route(task):
    route = task["route"].copy()  # at the episode's start: on its first segment
    route[:, :, 0] = np.cumsum(np.full(route.shape[:2], 13.0), axis=1)
    route[:, 1:, 1:] = route[:, 1:, 1:][:, ::-1]
    return {"route": route}


# each scene's draws for later, changed as another episode with the same present would have them
OTHER_FUTURE = {"PaperAirplane": _later_gust, "SubmarineWake": _other_route}


@pytest.mark.parametrize("sid", NOISY, ids=[s.split("/")[1] for s in NOISY])
def test_the_planner_does_not_read_the_episodes_future(sid):
    """Two copies of the same present whose futures differ (their noise keys: the gusts,
    currents and sensor noise to come; and what the episode drew at its start for later: the
    dart's gust not yet begun, the lead submarine's route ahead) get the same plans and scores
    from the planner, which draws its rollouts' keys and those draws itself; the clairvoyant
    reference scores them apart."""
    scene = SCENES[sid]
    venv = scene.vector_cls(num_envs=2)
    venv.reset(seed=5)
    present = venv.get_state()
    task = {**present.task, "noise_keys": present.task["noise_keys"] ^ np.uint64(0x5DEECE66D)}
    task.update(OTHER_FUTURE.get(sid.split("/")[1][:-3], lambda t: {})(present.task))
    other = dataclasses.replace(present, task=task)
    seen = {}
    for clairvoyant in (False, True):
        for name, state in (("same", present), ("other", other)):
            obs = venv.set_state(state)
            planner = scene.planner(venv, samples=6, horizon=8, hold=2, clairvoyant=clairvoyant)
            seen[clairvoyant, name] = (planner(obs), planner.value.copy())
    for a, b in zip(seen[False, "same"], seen[False, "other"], strict=True):
        np.testing.assert_array_equal(a, b)
    assert not np.array_equal(seen[True, "same"][1], seen[True, "other"][1])


def test_the_same_seed_plans_the_same():
    scene = SCENES["fluidsim/PaperAirplane-v0"]
    actions = []
    for _ in range(2):
        venv = scene.vector_cls(num_envs=3)
        obs, _ = venv.reset(seed=4)
        planner = scene.planner(venv, samples=6, horizon=4, elites=2)
        flown = []
        for _ in range(3):
            flown.append(planner(obs))
            obs, *_ = venv.step(flown[-1])
        actions.append(flown)
    np.testing.assert_array_equal(actions[0], actions[1])


def test_a_plan_is_kept_for_hold_actions_and_made_again_after_a_reset():
    scene = SCENES["fluidsim/SubmarineWake-v0"]
    venv = scene.vector_cls(num_envs=2)
    obs, _ = venv.reset(seed=0)
    planner = scene.planner(venv, samples=4, horizon=2, hold=3, elites=2)
    for _ in range(4):
        obs, *_ = venv.step(planner(obs))
    assert planner.timing["plans"] == 2  # at actions 0 and 3
    planner.reset(np.array([False, True]))
    planner(obs)
    assert planner.timing["plans"] == 3


def test_coloured_noise_has_unit_spread_and_is_smooth():
    rng = np.random.default_rng(0)
    white = coloured_noise(rng, (2000, 30, 1), 0.0)
    smooth = coloured_noise(rng, (2000, 30, 1), 2.0)
    np.testing.assert_allclose(smooth.std(axis=1), 1.0, rtol=1e-9)

    def lag1(x):  # correlation of neighbouring actions
        return np.mean(x[:, 1:] * x[:, :-1])

    assert abs(lag1(white)) < 0.1 and lag1(smooth) > 0.8


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"samples": 0}, "samples must be a positive integer, got 0"),
        ({"horizon": 0}, "horizon must be a positive integer, got 0"),
        ({"hold": 1.5}, "hold must be a positive integer, got 1.5"),
        ({"samples": 2, "elites": 4}, r"elites \(4\) must not exceed samples \(2\)"),
        ({"noise_std": -1.0}, r"noise_std must be in \[0.0, 2.0\], got -1.0"),
    ],
)
def test_bad_budgets_are_named(kwargs, message):
    with pytest.raises(ValueError, match=message):
        PlannerConfig(**kwargs)


def test_the_planner_needs_a_fluidsim_vector_env():
    import gymnasium as gym

    with pytest.raises(TypeError, match="needs a fluidsim vector env, got CartPoleEnv"):
        Planner(gym.make("CartPole-v1"))


def test_a_gust_not_begun_is_drawn_again_and_one_begun_is_kept():
    """PaperAirplane-v1 with a gust in the first 2 s: after 1 s, a gust still ahead moves to
    a moment between now and 2 s and a direction of unit length; one begun stays as it is."""
    venv = SCENES["fluidsim/PaperAirplane-v1"].vector_cls(
        num_envs=64, gust_mps=3.0, gust_within_s=2.0
    )
    venv.reset(seed=3)
    for _ in range(round(1.0 / venv._period_s)):
        venv.step(np.zeros((64, len(venv.action_names))))
    task = venv.get_state().task
    now = task["_elapsed"] * venv._period_s
    new = venv.redraw_future(task, np.random.default_rng(0))["_gusts"]
    ahead = now < task["_gusts"][:, 0]
    assert 0 < ahead.sum() < 64
    np.testing.assert_array_equal(new[~ahead], task["_gusts"][~ahead])
    assert np.all((new[ahead, 0] >= now[ahead]) & (new[ahead, 0] <= 2.0))
    assert not np.any(new[ahead, 0] == task["_gusts"][ahead, 0])
    np.testing.assert_allclose(np.linalg.norm(new[:, 3:], axis=1), 1.0, rtol=1e-12)
    np.testing.assert_array_equal(new[:, 1:3], task["_gusts"][:, 1:3])


def test_the_lead_route_ahead_is_drawn_again_and_the_past_kept():
    """SubmarineWake-v1 after 25 s: segments ended stay, the one the lead is on keeps its
    speed and turn and ends after now within its length limits, later ones are drawn within
    the route's ranges; the route's ends still rise."""
    venv = SCENES["fluidsim/SubmarineWake-v1"].vector_cls(num_envs=32)
    venv.reset(seed=4)
    p = venv.params
    for _ in range(250):
        venv.step(np.zeros((32, 3)))
    task = venv.get_state().task
    old, new = task["route"], venv.redraw_future(task, np.random.default_rng(1))["route"]
    now = task["lead"][:, TK.L_TIME]
    for r in range(32):
        on = int((old[r, :, 0] <= now[r]).sum())
        begun = old[r, on - 1, 0] if on else 0.0
        np.testing.assert_array_equal(new[r, :on], old[r, :on])
        np.testing.assert_array_equal(new[r, on, 1:], old[r, on, 1:])
        length = new[r, on, 0] - begun
        assert new[r, on, 0] > now[r] and p.segment_s[0] <= length <= p.segment_s[1]
        lengths = np.diff(new[r, on:, 0])
        assert np.all((lengths >= p.segment_s[0]) & (lengths <= p.segment_s[1]))
        speeds = new[r, on + 1 :, 1]
        assert np.all((speeds >= p.lead_speed_mps[0]) & (speeds <= p.lead_speed_mps[1]))
        assert not np.array_equal(new[r, on + 1 :], old[r, on + 1 :])
