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
the largest stable dt found, rounded down to two significant digits. A v1 is measured at
``hard`` (``fuzz.EXTREMES``: v0's extremes, every knob at its hardest level), between its
default dt / 8 and its v0's limit: at ``easy`` it flies v0's craft in v0's world, so its
limit is at most v0's at any level (its ``dt_unstable_s`` is inf where it was stable up to
v0's limit: nothing above was tried).

Writes ``docs/env_stability.csv``; ``scenes/limits.py``'s ``DT_LIMIT_S`` is that table
(``tests/scenes/test_limits.py`` checks)::

    python -m benchmarks.env_stability              # about 30 minutes on 2 cores, cold
    python -m benchmarks.env_stability --quick      # 2 halvings, fewer steps, into build/
    python -m benchmarks.env_stability --env fluidsim/BoatOnStep-v1   # one env's rows
"""

from __future__ import annotations

import math
from pathlib import Path

from benchmarks.common import arguments, describe, keep_others, write_csv
from benchmarks.fuzz import Case, run_case
from fluidsim_envs.physics.kernels import INTEGRATORS
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes import limits as LIM

HEADER = (
    "env", "integrator", "default_dt_s", "dt_stable_s", "dt_unstable_s", "dt_limit_s",
    "limit_over_default", "env_steps_per_run", "runs",
)  # fmt: skip


def round_down(x: float, digits: int = 2) -> float:
    """``x`` rounded toward zero to ``digits`` significant digits (0.0913 -> 0.091)."""
    scale = 10 ** (math.floor(math.log10(x)) - digits + 1)
    return math.floor(x / scale + 1e-9) * scale


def bisect(
    env_id: str, integrator: str, env_steps: int, num_envs: int, halvings: int, bound=math.inf
):
    """(largest stable dt, smallest unstable dt (inf if none up to the top), runs) for one
    scene and integrator, between its default dt / 8 and the smaller of its largest
    accepted dt and ``bound`` (a later version: its v0's limit); the stable one is nan where
    even the lowest dt diverged."""
    runs = 0

    def stable(dt: float) -> bool:
        nonlocal runs
        runs += 1
        case = Case(env_id, "extreme", "float64", integrator, dt)
        return run_case(case, env_steps, num_envs)["diverged"] == 0

    if math.isnan(bound):  # its v0 held at no step tried: nor can it, flying v0's craft
        return math.nan, math.nan, runs
    cls = SCENES[env_id].params_cls
    lo, hi = cls().dt / 8, min(cls.RANGES["dt"].hi, bound)
    if not stable(lo):
        return math.nan, lo, runs
    if stable(hi):
        return hi, math.inf, runs
    for _ in range(halvings):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
    return lo, hi, runs


def write(out: Path, rows: list, measured: list[str]) -> None:
    """``out``: ``rows`` (the envs ``measured``), and the other envs' rows kept from ``out``."""
    cells = [[f"{x:.6g}" if isinstance(x, float) else x for x in row] for row in rows]
    cells, notes = keep_others(out, HEADER, cells, measured)
    order = list(INTEGRATORS)
    cells.sort(key=lambda r: (r[0][-2:], r[0], order.index(r[1])))
    write_csv(out, HEADER, cells, describe(False) + notes)


def main() -> None:
    parser = arguments(__doc__, "2 halvings, 2e4 env-steps a run", "env_stability.csv")
    parser.add_argument("--env-steps", type=float, default=2e5, help="per run (default 2e5)")
    parser.add_argument("--num-envs", type=int, default=512)
    parser.add_argument("--halvings", type=int, default=7)
    parser.add_argument("--env", nargs="+", choices=sorted(SCENES), default=sorted(SCENES),
                        help="measure these (the others' rows are kept from --out)")  # fmt: skip
    args = parser.parse_args()
    steps, halvings = (2e4, 2) if args.quick else (args.env_steps, args.halvings)
    keep = not args.quick or args.out != parser.get_default("out")
    rows, done = [], []
    limits = {k: dict(v) for k, v in LIM.DT_LIMIT_S.items()}  # v0's as measured, once it is
    for env_id in sorted(SCENES, key=lambda i: (SCENES[i].version, i)):  # v0's first
        if env_id not in args.env:
            continue
        scene = SCENES[env_id]
        default = scene.params_cls().dt
        first = scene.first_id.split("/")[1]
        for integrator in INTEGRATORS:
            # a later version at easy flies v0's craft in v0's world: at most v0's limit
            bound = limits[first][integrator] if scene.version > 0 else math.inf
            good, bad, runs = bisect(env_id, integrator, int(steps), args.num_envs, halvings, bound)
            limit = round_down(good) if math.isfinite(good) else math.nan
            rows.append(
                (env_id, integrator, default, good, bad, limit, limit / default, int(steps), runs)
            )
            limits.setdefault(env_id.split("/")[1], {})[integrator] = limit
            print(
                f"{env_id:28s} {integrator:17s} stable {good:.4g} s, unstable {bad:.4g} s: "
                f"limit {limit:.3g} s ({limit / default:.2f} x the default {default:.4g} s)",
                flush=True,
            )
        done.append(env_id)
        if keep:  # after each env: a killed run keeps what it measured
            write(Path(args.out), rows, done)
    if keep:
        print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
