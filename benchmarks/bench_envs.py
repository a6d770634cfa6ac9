"""Env-steps per second of our vector envs beside gymnasium's CartPole vector env, same run.

For each env and num_envs in (1, 64, 1024, 4096, 16384): ``make_vec(id, num_envs,
vectorization_mode="vector_entry_point")``, reset with a seed, then step with random actions
(drawn beforehand, not timed) until ~``--seconds`` have passed; the figure is the best of
``--repeats`` such runs, in env-steps (one action of one sub-env) per second. Episode ends and
autoresets happen inside the timed loop, as in training. The single env (``gym.make``, with
gymnasium's default wrappers) is measured the same way. CartPole-v1 is the peer: an almost
empty env (four numbers of state), so its rate is the ceiling of the Gymnasium API itself.

Writes ``docs/bench_envs.csv`` (machine in ``#`` lines) and prints a table with our rate over
CartPole's at each num_envs.

    python -m benchmarks.bench_envs [--quick]
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from benchmarks.common import arguments, describe, rate_over, write_csv
from fluidsim_envs.scenes import SCENES

ENVS = tuple(SCENES)  # every registered scene
SWELL = ((0.3, 30.0, 45.0), (0.15, 12.0, -60.0))
# extra rows: (label, env id, make kwargs, watch): SubmarineWake-v0 without its wake, and
# with the wake's tracers of sub-env 0 advanced every step (what rendering or logging costs)
VARIANTS = (
    ("SubmarineWake-v0 wake=False", "fluidsim/SubmarineWake-v0", {"wake": False}, False),
    ("SubmarineWake-v0 +tracers", "fluidsim/SubmarineWake-v0", {"render_mode": "rgb_array"}, True),
    # BoatOnStep-v0 in two-wave swell: a surface height under every sample, every evaluation
    ("BoatOnStep-v0 swell", "fluidsim/BoatOnStep-v0", {"swell": SWELL}, False),
    # BoatOnStep-v0 with its 12 buoys as moored floating bodies: 13 bodies and contact
    ("BoatOnStep-v0 buoy_bodies", "fluidsim/BoatOnStep-v0", {"buoy_bodies": True}, False),
    # the envs' first defaults, symplectic Euler at half the step (the same force evaluations
    # per action as rk2 at the default; the submarine: 5 against 4): what the switch cost
    *(
        (
            f"{short} symplectic_euler",
            f"fluidsim/{short}",
            {
                "integrator": "symplectic_euler",
                "dt": dt,
                "substeps": n,
            },
            False,
        )
        for short, dt, n in (
            ("PaperAirplane-v0", 1 / 240, 8),
            ("SubmarineWake-v0", 1 / 50, 5),
            ("BoatOnStep-v0", 1 / 200, 10),
        )
    ),
)
PEER = "CartPole-v1"
NUM_ENVS = (1, 64, 1024, 4096, 16384)


def actions_for(space, n: int, rng) -> list:
    """Pre-drawn random actions, cycled through in the timed loop."""
    if isinstance(space, gym.spaces.Discrete) or (
        isinstance(space, gym.spaces.MultiDiscrete) and space.shape
    ):
        hi = space.n if isinstance(space, gym.spaces.Discrete) else space.nvec
        return [rng.integers(0, hi, size=space.shape) for _ in range(n)]
    return [rng.uniform(space.low, space.high).astype(space.dtype) for _ in range(n)]


def vector_rate(
    env_id: str, num_envs: int, seconds: float, repeats: int, kwargs=None, watch=False
) -> float:
    venv = gym.make_vec(
        env_id, num_envs=num_envs, vectorization_mode="vector_entry_point", **(kwargs or {})
    )
    acts = actions_for(venv.action_space, 16, np.random.default_rng(0))
    venv.reset(seed=0)
    if watch:  # one frame of sub-env 0 starts its tracers; steps then advance them
        venv.unwrapped._frame(0)
    for a in acts:  # warm-up: compile, caches
        venv.step(a)
    best = max(rate_over(stepping(venv, acts), seconds) for _ in range(repeats))
    venv.close()
    return best


def stepping(venv, acts: list):
    """A run for ``rate_over``: the actions one after the other on a vector env (which resets
    its ended sub-envs itself); returns the env-steps done."""
    work = len(acts) * venv.num_envs

    def run() -> int:
        for a in acts:
            venv.step(a)
        return work

    return run


def single_rate(env_id: str, seconds: float, repeats: int) -> float:
    env = gym.make(env_id)
    acts = actions_for(env.action_space, 64, np.random.default_rng(0))
    env.reset(seed=0)

    def run() -> int:
        for a in acts:
            _, _, term, trunc, _ = env.step(a)
            if term or trunc:
                env.reset()
        return len(acts)

    best = max(rate_over(run, seconds) for _ in range(repeats))
    env.close()
    return best


def main() -> None:
    parser = arguments(__doc__, "shorter, noisier runs", "bench_envs.csv")
    parser.add_argument("--seconds", type=float, default=1.0)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    seconds, repeats = (0.3, 1) if args.quick else (args.seconds, args.repeats)

    machine = describe()
    rows = []
    for env_id in (*ENVS, PEER):
        rate = single_rate(env_id, seconds, repeats)
        rows.append((env_id, "single", 1, rate))
        print(f"{env_id:28s} single           {rate:14,.0f} env-steps/s")
        for n in NUM_ENVS:
            rate = vector_rate(env_id, n, seconds, repeats)
            rows.append((env_id, "vector", n, rate))
            print(f"{env_id:28s} vector {n:6d}    {rate:14,.0f} env-steps/s")

    for label, env_id, kwargs, watch in VARIANTS:
        for n in NUM_ENVS:
            rate = vector_rate(env_id, n, seconds, repeats, kwargs, watch)
            rows.append((label, "vector", n, rate))
            print(f"{label:28s} vector {n:6d}    {rate:14,.0f} env-steps/s")

    peer = {(kind, n): r for e, kind, n, r in rows if e == PEER}
    print(f"\nratio to {PEER} at the same num_envs (higher is better)")
    for env_id, kind, n, r in rows:
        if env_id != PEER and (kind, n) in peer:
            print(f"{env_id:28s} {kind:6s} {n:6d}  x{r / peer[(kind, n)]:.3f}")

    out = write_csv(
        args.out,
        ("env", "kind", "num_envs", "env_steps_per_s", "ratio_to_cartpole"),
        [
            (env_id, kind, n, f"{r:.1f}", f"{ratio:.4f}")
            for env_id, kind, n, r in rows
            for ratio in [r / peer[(kind, n)] if (kind, n) in peer else float("nan")]
        ],
        machine,
    )
    print(f"\nwrote {out}")


if __name__ == "__main__":
    main()
