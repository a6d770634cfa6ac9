"""Fuzz every env: adversarial actions, parameters at their extremes, both precisions.

Each *case* is one env id, a set of parameters (``nominal``: the defaults; ``extreme``: the
ranges that make each craft's life hardest, :data:`EXTREMES`), a dtype, an integrator and a
physics step (the env's default, or a fraction of the scene's limit, ``scenes/limits.py``).
A case steps a vector env of ``--num-envs`` sub-envs with actions from :class:`Adversary`
(per sub-env, one of: uniform noise every step; bang-bang held for a random 1-30 steps;
sinusoids of 0.1-10 Hz; commands of 1e6 that saturate) and checks after every step:

- ``nonfinite``: observations, rewards and ``final_obs`` that are not finite (must be 0);
- ``unflagged_runaways``: a sub-env step whose body moved farther than the fluid samples'
  speed clamp allows in that step (``max_fluid_speed_mps * dt * substeps``) without
  ``info["physics_diverged"]`` (must be 0; the positions of ended episodes are read in the
  autoreset hook, before the reset moves them);
- ``diverged``: episodes ended by ``physics_diverged``, per episode (the divergence rate);
- ``max_reward``: the largest |reward| of a step that did not diverge.

Writes ``docs/fuzz.csv`` (one row per case, machine in ``#`` lines) and exits non-zero when
any case has a non-finite value or an unflagged runaway::

    python -m benchmarks.fuzz --env-steps 1e8        # the published run (16 min on 2 cores)
    python -m benchmarks.fuzz --quick                # a few seconds per case, into build/
    python -m benchmarks.fuzz --env fluidsim/PaperAirplane-v1 --env fluidsim/BoatOnStep-v1 \
        --env fluidsim/SubmarineWake-v1 --env-steps 1e7 --out docs/fuzz_v1.csv  # v1 at hard

``tests/scenes/test_fuzz.py`` runs :func:`run_case` at a small budget. :func:`run_witness`
checks the flag against the same states stepped at a quarter of the step
(``benchmarks/witness.py``).
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time

import gymnasium as gym
import numpy as np

from benchmarks.common import arguments, describe, write_csv
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes import limits as LIM

# the parameters at the ends of their ranges that make each craft's life hardest
EXTREMES = {
    "fluidsim/PaperAirplane-v0": {
        "wind_speed_mps": (10.0, 15.0),
        "launch_speed_mps": (15.0, 20.0),
        "launch_pitch_deg": (-90.0, 90.0),
        "launch_roll_deg": (-180.0, 180.0),
        "launch_height_m": (10.0, 25.0),
    },
    "fluidsim/BoatOnStep-v0": {
        "engine_power_w": 1e7,
        "target_speed_mps": (30.0, 40.0),
        "turn_deg": (-120.0, 120.0),
        # steepness 0.25 and 0.26 (at most 0.3): a short steep sea on the beam and the bow
        "swell": ((1.0, 25.0, 0.0), (0.5, 12.0, 90.0)),
    },
    "fluidsim/SubmarineWake-v0": {
        "lead_speed_mps": (4.0, 5.0),
        "lead_turn_deg_s": (-10.0, 10.0),
        "circulation": 2.0,
        "noise": 1.0,
        "wake_dipoles": 32,
    },
}
# v1 flies the same crafts: v0's extremes, with every knob at its hardest level (the boat's
# sea is hard's irregular one, which replaces v0's swell)
EXTREMES.update(
    {
        i.replace("-v0", "-v1"): {k: v for k, v in kw.items() if k != "swell"}
        | {"difficulty": "hard"}
        for i, kw in list(EXTREMES.items())
    }
)
MODES = ("uniform", "bang_bang", "sinusoid", "saturated")


@dataclasses.dataclass(frozen=True)
class Case:
    env_id: str
    params: str  # "nominal" or "extreme"
    dtype: str
    integrator: str
    dt_s: float | None = None  # the physics step (None: the env's default)

    def kwargs(self) -> dict:
        kw = dict(EXTREMES[self.env_id]) if self.params == "extreme" else {}
        dt = SCENES[self.env_id].params_cls().dt if self.dt_s is None else self.dt_s
        return {**kw, "dtype": self.dtype, "integrator": self.integrator, "dt": dt}


def dt_limit(env_id: str, integrator: str) -> float:
    """The scene's step limit for ``integrator`` (scenes/limits.py)."""
    return LIM.DT_LIMIT_S[env_id.split("/")[1]][integrator]


class Adversary:
    """Actions [E, n] that try to break the physics, each sub-env in one of :data:`MODES`
    (redrawn with its episode), from one seeded generator."""

    def __init__(self, num_envs: int, n_act: int, seed: int) -> None:
        self.rng = np.random.default_rng(seed)
        self.E, self.n = num_envs, n_act
        self.mode = np.zeros(num_envs, dtype=np.int64)
        self.held = np.zeros((num_envs, n_act))
        self.left = np.zeros(num_envs, dtype=np.int64)
        self.freq = np.zeros((num_envs, n_act))
        self.phase = np.zeros((num_envs, n_act))
        self.t = np.zeros(num_envs)
        self.restart(np.arange(num_envs))

    def restart(self, ids: np.ndarray) -> None:
        k = ids.size
        self.mode[ids] = self.rng.integers(0, len(MODES), k)
        self.left[ids] = 0
        self.freq[ids] = 10 ** self.rng.uniform(-1, 1, (k, self.n))  # 0.1-10 Hz
        self.phase[ids] = self.rng.uniform(0, 2 * np.pi, (k, self.n))
        self.t[ids] = 0.0

    def __call__(self, period_s: float) -> np.ndarray:
        E, n, rng = self.E, self.n, self.rng
        act = rng.uniform(-1, 1, (E, n))  # "uniform"
        renew = self.left <= 0
        self.held[renew] = rng.choice([-1.0, 1.0], (int(renew.sum()), n))
        self.left[renew] = rng.integers(1, 31, int(renew.sum()))
        self.left -= 1
        bang = self.mode == 1
        act[bang] = self.held[bang]
        sine = self.mode == 2
        act[sine] = np.sin(2 * np.pi * self.freq[sine] * self.t[sine, None] + self.phase[sine])
        sat = self.mode == 3
        act[sat] = 1e6 * self.held[sat]
        self.t += period_s
        return act


def run_case(case: Case, env_steps: int, num_envs: int, seed: int = 0) -> dict:
    """Step ``case`` for ``env_steps`` sub-env steps or the next multiple of ``num_envs``;
    the counts of the module's checks."""
    with LIM.unchecked():
        venv = gym.make_vec(
            case.env_id, num_envs=num_envs, vectorization_mode="vector_entry_point",
            **case.kwargs(),
        )  # fmt: skip
    env = venv.unwrapped
    p = env.params
    reach = env.sim.world.max_fluid_speed_mps * p.dt * p.substeps
    ended_pos = np.zeros_like(env.sim.pos)

    def keep_last(ended, info, reward):  # the ended episodes' bodies, before the reset
        ended_pos[ended] = env.sim.pos[ended]

    env.before_autoreset.append(keep_last)
    adversary = Adversary(num_envs, env.single_action_space.shape[0], seed)
    obs, _ = venv.reset(seed=seed)
    counts = dict(env_steps=0, episodes=0, diverged=0, nonfinite=int((~np.isfinite(obs)).sum()))
    counts.update(unflagged_runaways=0, max_reward=0.0, max_displacement_m=0.0)
    steps = max(1, -(-int(env_steps) // num_envs))  # at least the budget
    start = time.perf_counter()
    for _ in range(steps):
        before = env.sim.pos.copy()
        obs, reward, terminated, truncated, info = venv.step(adversary(p.dt * p.substeps))
        done = terminated | truncated
        after = np.where(done[:, None, None], ended_pos, env.sim.pos)
        moved = np.sqrt(((after - before) ** 2).sum(axis=-1)).max(axis=1)  # [E], worst body
        flagged = info["physics_diverged"]
        counts["unflagged_runaways"] += int((~flagged & (moved > reach * 1.0001)).sum())
        counts["max_displacement_m"] = max(counts["max_displacement_m"], float(moved.max()))
        bad = ~np.isfinite(obs).all(axis=1) | ~np.isfinite(reward)
        if "final_obs" in info:
            bad |= info["_final_obs"] & ~np.isfinite(info["final_obs"]).all(axis=1)
        counts["nonfinite"] += int(bad.sum())
        if (~flagged).any():
            counts["max_reward"] = max(counts["max_reward"], float(np.abs(reward[~flagged]).max()))
        counts["episodes"] += int(done.sum())
        counts["diverged"] += int(flagged.sum())
        counts["env_steps"] += num_envs
        if done.any():
            adversary.restart(np.flatnonzero(done))
    counts["seconds"] = time.perf_counter() - start
    counts["reach_m"] = reach
    venv.close()
    return counts


WITNESS_SPLIT = 4  # the witness steps dt / 4, four times as many substeps
WITNESS_TOLERANCE_M = 1.0  # per action: farther apart than this, one run is wrong
WITNESS_TOLERANCE_DEG = 30.0  # per action: turned apart by more than this, one run is wrong


def _pose(sim) -> tuple[np.ndarray, np.ndarray]:
    """The bodies' positions [E, B, 3] and unit quaternions [E, B, 4]."""
    return sim.pos, sim.quat


def _keep_pose(sim, ended: np.ndarray, end: tuple) -> None:
    """The ended episodes' poses, kept before the autoreset replaces them."""
    for kept, now in zip(end, _pose(sim), strict=True):
        kept[ended] = now[ended]


def run_witness(case: Case, env_steps: int, num_envs: int, seed: int = 0) -> dict:
    """``case`` stepped beside an independent witness: before each action the witness (the
    same env at dt / :data:`WITNESS_SPLIT` with that many times the substeps, the same
    action period) takes the case's whole state (physics, task, generators), both take the
    action, and their bodies' positions and attitudes are compared. Farther apart than
    :data:`WITNESS_TOLERANCE_M`, or turned apart by more than :data:`WITNESS_TOLERANCE_DEG`,
    with neither run flagging ``physics_diverged``, counts as ``unflagged_disagreements``: a
    wrong step that the runaway flag let through (attitudes are compared on actions that
    end no episode: see below). Attitude matters on its own: a craft
    whose turn runs away (angular momentum carried onto its light axis) can spin at ten
    times any rate the flow gives it while its center still moves as the witness's does."""
    kwargs = case.kwargs()
    substeps = kwargs.get("substeps", SCENES[case.env_id].params_cls().substeps)
    fine = {**kwargs, "dt": kwargs["dt"] / WITNESS_SPLIT, "substeps": substeps * WITNESS_SPLIT}
    with LIM.unchecked():
        venvs = [
            gym.make_vec(
                case.env_id, num_envs=num_envs, vectorization_mode="vector_entry_point", **kw
            )  # fmt: skip
            for kw in (kwargs, fine)
        ]
    env, witness = (v.unwrapped for v in venvs)
    ends = [(np.zeros_like(e.sim.pos), np.zeros_like(e.sim.quat)) for e in (env, witness)]
    for e, end in zip((env, witness), ends, strict=True):
        e.before_autoreset.append(lambda ended, info, reward, e=e, end=end: _keep_pose(
            e.sim, ended, end))  # fmt: skip
    adversary = Adversary(num_envs, env.single_action_space.shape[0], seed)
    venvs[0].reset(seed=seed)
    counts = dict(env_steps=0, unflagged_disagreements=0, max_disagreement_m=0.0,
                  max_disagreement_deg=0.0, max_unflagged_disagreement_m=0.0,
                  max_unflagged_disagreement_deg=0.0)  # fmt: skip
    period = env.params.dt * env.params.substeps
    for _ in range(max(1, -(-int(env_steps) // num_envs))):
        state = env.get_state()
        witness.set_state(dataclasses.replace(state, params=witness.params))
        action = adversary(period)
        out = [v.step(action) for v in venvs]
        pose = []
        for e, end, (_, _, terminated, truncated, _) in zip((env, witness), ends, out, strict=True):
            done = terminated | truncated
            pose.append(
                [
                    np.where(done[:, None, None], k, x)
                    for k, x in zip(end, _pose(e.sim), strict=True)
                ]
            )
        apart = np.sqrt(((pose[0][0] - pose[1][0]) ** 2).sum(axis=-1)).max(axis=1)
        cos = np.abs((pose[0][1] * pose[1][1]).sum(axis=-1)).clip(max=1.0)
        turned = np.degrees(2.0 * np.arccos(cos)).max(axis=1)
        # an action that ends its episode (a crash, touching the lead) is judged by where
        # the event happened, not by the attitude a rigid bounce leaves after it: that
        # depends on when within a step the body touched, and no reward or observation uses it
        turned[out[0][2] | out[1][2]] = 0.0
        flagged = out[0][4]["physics_diverged"] | out[1][4]["physics_diverged"]
        wrong = ~flagged & ((apart > WITNESS_TOLERANCE_M) | (turned > WITNESS_TOLERANCE_DEG))
        counts["unflagged_disagreements"] += int(wrong.sum())
        for gap, unit in ((apart, "m"), (turned, "deg")):
            counts[f"max_disagreement_{unit}"] = max(counts[f"max_disagreement_{unit}"],
                                                     float(gap.max()))  # fmt: skip
            if wrong.any():
                key = f"max_unflagged_disagreement_{unit}"
                counts[key] = max(counts[key], float(gap[wrong].max()))
        counts["env_steps"] += num_envs
        done = out[0][2] | out[0][3]
        if done.any():
            adversary.restart(np.flatnonzero(done))
    for v in venvs:
        v.close()
    return counts


def cases(quick: bool) -> list[Case]:
    """Every env x nominal/extreme x dtype at its default integrator and dt, and, for each
    integrator with a limit, extreme parameters at half and all of it (float64)."""
    out = []
    for env_id, scene in SCENES.items():
        default = scene.params_cls().integrator
        for params in ("nominal", "extreme"):
            for dtype in ("float64", "float32"):
                out.append(Case(env_id, params, dtype, default))
        limits = LIM.DT_LIMIT_S[env_id.split("/")[1]]
        # an integrator that held at no step tried (nan) is refused by the env at any step
        integrators = [default] if quick else sorted(i for i in limits if not math.isnan(limits[i]))
        for integrator in integrators:
            for fraction in (0.5, 1.0):
                dt = fraction * dt_limit(env_id, integrator)
                out.append(Case(env_id, "extreme", "float64", integrator, dt))
    return out


HEADER = (
    "env", "params", "dtype", "integrator", "dt_s", "substeps", "num_envs", "env_steps",
    "episodes", "diverged", "divergence_rate", "nonfinite", "unflagged_runaways",
    "max_reward", "max_displacement_m", "reach_m", "seconds",
)  # fmt: skip


def main() -> None:
    parser = arguments(__doc__, "about 2e5 env-steps per case", "fuzz.csv")
    parser.add_argument("--env-steps", type=float, default=1e8, help="in all (default 1e8)")
    parser.add_argument("--num-envs", type=int, default=2048, help="at most, a case")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--env",
        action="append",
        choices=list(SCENES),
        help="only these envs (repeatable; default: every registered one)",
    )
    args = parser.parse_args()
    out = args.out if not args.quick or args.out != parser.get_default("out") else None
    todo = [c for c in cases(args.quick) if not args.env or c.env_id in args.env]
    # every case its share, weighted by what a step costs (the submarine's wake, the boat)
    weight = {"fluidsim/PaperAirplane-v0": 4.0, "fluidsim/BoatOnStep-v0": 1.0}
    weight = {c.env_id: weight.get(SCENES[c.env_id].first_id, 0.5) for c in todo}
    total = sum(weight[c.env_id] for c in todo)
    budget = 2e5 * len(todo) if args.quick else args.env_steps
    rows, failed = [], 0
    for case in todo:
        share = math.ceil(budget * weight[case.env_id] / total)
        # fewer sub-envs where the share is small: each then flies two whole episodes (a
        # share spread thinner ends none, and the episode ends are what the fuzz checks)
        episode = SCENES[case.env_id].params_cls().max_episode_steps
        num_envs = int(min(args.num_envs, max(32, share // (2 * episode))))
        r = run_case(case, share, num_envs, args.seed)
        kw = case.kwargs()
        rate = r["diverged"] / max(r["episodes"], 1)
        rows.append(
            (
                case.env_id,
                case.params,
                case.dtype,
                case.integrator,
                kw["dt"],
                SCENES[case.env_id].params_cls().substeps,
                num_envs,
                r["env_steps"],
                r["episodes"],
                r["diverged"],
                rate,
                r["nonfinite"],
                r["unflagged_runaways"],
                r["max_reward"],
                r["max_displacement_m"],
                r["reach_m"],
                r["seconds"],
            )  # fmt: skip
        )
        failed += r["nonfinite"] > 0 or r["unflagged_runaways"] > 0
        print(
            f"{case.env_id:28s} {case.params:8s} {case.dtype:8s} {case.integrator:17s} "
            f"dt {kw['dt']:.4g}: {r['env_steps']:,} steps, {r['episodes']:,} episodes, "
            f"diverged {rate:.2%}, non-finite {r['nonfinite']}, unflagged runaways "
            f"{r['unflagged_runaways']}, max |reward| {r['max_reward']:.3g} "
            f"({r['seconds']:.0f} s)",
            flush=True,
        )
    if out is not None:
        write_csv(out, HEADER, [[_cell(x) for x in row] for row in rows], describe(False))
        print(f"wrote {out}")
    steps = sum(r[7] for r in rows)
    print(f"{steps:,} env-steps in {len(rows)} cases; {failed} case(s) failed")
    sys.exit(1 if failed else 0)


def _cell(x):
    return f"{x:.6g}" if isinstance(x, float) else x


if __name__ == "__main__":
    main()
