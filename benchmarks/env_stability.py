"""Each env's physics step limit per integrator: the largest ``dt`` at which no fuzzed episode
diverged, with the parameters at their extremes and adversarial actions.

``benchmarks/study_stability.py`` finds where each integrator stops being bounded on each
craft's maneuver in still air; in an env the craft meets more (the dart in a 15 m/s wind
thrown at 20 m/s, the boat in a steep sea at full power, adversarial controls:
``fuzz.EXTREMES``), and what the env must refuse is the step at which *its* episodes run
away. For each scene and integrator
(float64: the study finds the same limits in float32), a bisection on log dt between the
scene's default dt / 8 and its largest accepted dt (``--halvings`` steps) runs
``fuzz.run_case`` (extreme parameters, ``--env-steps`` sub-env steps over ``--num-envs``
sub-envs) and calls a dt *stable* when no episode ended ``physics_diverged``. The limit is
the largest stable dt found, rounded down to two significant digits.

Writes ``docs/env_stability.csv``; ``scenes/limits.py``'s ``DT_LIMIT_S`` is that table
(``tests/scenes/test_limits.py`` checks)::

    python -m benchmarks.env_stability              # about 15 minutes on 2 cores, cold
    python -m benchmarks.env_stability --quick      # 2 halvings, fewer steps, into build/
"""

from __future__ import annotations

import math

from benchmarks.common import arguments, describe, write_csv
from benchmarks.fuzz import Case, run_case
from fluidsim_envs.physics.kernels import INTEGRATORS
from fluidsim_envs.scenes import SCENES, V0_SCENES

HEADER = (
    "env", "integrator", "default_dt_s", "dt_stable_s", "dt_unstable_s", "dt_limit_s",
    "limit_over_default", "env_steps_per_run", "runs",
)  # fmt: skip


def round_down(x: float, digits: int = 2) -> float:
    """``x`` rounded toward zero to ``digits`` significant digits (0.0913 -> 0.091)."""
    scale = 10 ** (math.floor(math.log10(x)) - digits + 1)
    return math.floor(x / scale + 1e-9) * scale


def bisect(env_id: str, integrator: str, env_steps: int, num_envs: int, halvings: int):
    """(largest stable dt, smallest unstable dt (inf if none), runs) for one scene and
    integrator; the stable one is nan where even the lowest dt diverged."""
    runs = 0

    def stable(dt: float) -> bool:
        nonlocal runs
        runs += 1
        case = Case(env_id, "extreme", "float64", integrator, dt)
        return run_case(case, env_steps, num_envs)["diverged"] == 0

    cls = SCENES[env_id].params_cls
    lo, hi = cls().dt / 8, cls.RANGES["dt"].hi  # the largest dt the parameters accept
    if not stable(lo):
        return math.nan, lo, runs
    if stable(hi):
        return hi, math.inf, runs
    for _ in range(halvings):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
    return lo, hi, runs


def main() -> None:
    parser = arguments(__doc__, "2 halvings, 2e4 env-steps a run", "env_stability.csv")
    parser.add_argument("--env-steps", type=float, default=2e5, help="per run (default 2e5)")
    parser.add_argument("--num-envs", type=int, default=512)
    parser.add_argument("--halvings", type=int, default=7)
    args = parser.parse_args()
    steps, halvings = (2e4, 2) if args.quick else (args.env_steps, args.halvings)
    rows = []
    for env_id, scene in V0_SCENES.items():  # per craft: v1 flies v0's
        default = scene.params_cls().dt
        for integrator in INTEGRATORS:
            good, bad, runs = bisect(env_id, integrator, int(steps), args.num_envs, halvings)
            limit = round_down(good) if math.isfinite(good) else math.nan
            rows.append(
                (env_id, integrator, default, good, bad, limit, limit / default, int(steps), runs)
            )
            print(
                f"{env_id:28s} {integrator:17s} stable {good:.4g} s, unstable {bad:.4g} s: "
                f"limit {limit:.3g} s ({limit / default:.2f} x the default {default:.4g} s)",
                flush=True,
            )
    if not args.quick or args.out != parser.get_default("out"):
        cells = [[f"{x:.6g}" if isinstance(x, float) else x for x in row] for row in rows]
        write_csv(args.out, HEADER, cells, describe(False))
        print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
