"""The runaway flag against an independent witness: each v1 env stepped under the fuzz's
adversarial actions beside the same env at a quarter of its step, which takes the env's
whole state before every action (:func:`benchmarks.fuzz.run_witness`). Two runs of one
state that end an action more than :data:`~benchmarks.fuzz.WITNESS_TOLERANCE_M` apart, with
neither flagging ``physics_diverged``, are a wrong step the flag let through.

Cases, per v1 env at its default integrator and dt: ``hard`` and the fuzz's extremes
(``nominal``, ``extreme``), and ``--draws`` draws of every knob uniformly within its declared
range (``benchmarks/ranges.py``: per craft), each a case of its own (a draw whose sea is
steeper than linear theory is refused by the env and skipped, said). Writes
``docs/fuzz_witness.csv``::

    python -m benchmarks.witness --env-steps 1e8 --jobs 2    # the published table
    python -m benchmarks.witness --quick                     # a few seconds a case, printed
"""

from __future__ import annotations

import dataclasses
import math
import sys
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from benchmarks.common import DOCS, arguments, describe, read_csv, write_csv
from benchmarks.fuzz import (
    WITNESS_SPLIT,
    WITNESS_TOLERANCE_DEG,
    WITNESS_TOLERANCE_M,
    Case,
    run_witness,
)
from benchmarks.ranges import knob_ranges, v1_envs
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes.limits import Bound, Span

CSV = DOCS / "fuzz_witness.csv"
HEADER = ("env", "case", "knobs", "env_steps", "unflagged_disagreements",
          "max_disagreement_m", "max_disagreement_deg", "max_unflagged_disagreement_m",
          "max_unflagged_disagreement_deg")  # fmt: skip


@dataclasses.dataclass(frozen=True)
class DrawCase(Case):
    """A case whose knobs are one uniform draw within their declared ranges."""

    knobs: tuple = ()  # (name, value) pairs

    def kwargs(self) -> dict:
        return {**super().kwargs(), **dict(self.knobs)}


def draw(env_id: str, rng: np.random.Generator) -> dict:
    """Every numeric knob of ``env_id`` drawn uniformly within its declared range."""
    out = {}
    for name, rule in knob_ranges(env_id).items():
        if isinstance(rule, Span):
            out[name] = tuple(sorted(float(x) for x in rng.uniform(rule.lo, rule.hi, 2)))
        elif rule.integer:
            out[name] = int(rng.integers(int(rule.lo), int(rule.hi) + 1))
        elif isinstance(rule, Bound):
            out[name] = float(rng.uniform(rule.lo, rule.hi))
    return out


def cases(draws: int, seed: int) -> list[Case]:
    out = []
    rng = np.random.default_rng(seed)
    for env_id in v1_envs():
        integrator = SCENES[env_id].params_cls().integrator
        out += [Case(env_id, p, "float64", integrator) for p in ("nominal", "extreme")]
        for _ in range(draws):
            knobs = tuple(draw(env_id, rng).items())
            out.append(DrawCase(env_id, "nominal", "float64", integrator, knobs=knobs))
    return out


def _run(job: tuple) -> dict | str:
    case, steps, num_envs, seed = job
    try:
        return run_witness(case, steps, num_envs, seed)
    except ValueError as e:  # a draw the env refuses (a sea too steep): said, skipped
        return str(e)


def markdown() -> str:
    """docs/fuzz_witness.csv summed per env and kind of case."""
    if not CSV.is_file():
        return "(no docs/fuzz_witness.csv yet: run python -m benchmarks.witness)"
    comments, table = read_csv(CSV)
    lines = [
        "| env | cases | env-steps | unflagged disagreements | largest gap (m) "
        "| largest turn apart (deg) | largest unflagged gap (m, deg) |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for env in dict.fromkeys(r["env"] for r in table):
        for kind in ("nominal", "extreme", "draw"):
            rows = [r for r in table if r["env"] == env and r["case"] == kind]
            if not rows:
                continue
            steps = sum(int(r["env_steps"]) for r in rows)
            wrong = sum(int(r["unflagged_disagreements"]) for r in rows)
            # (a table written before attitudes were compared: nan in their columns)
            gap, turn, un_m, un_deg = (
                max(float(r.get(k) or "nan") for r in rows) for k in HEADER[5:]
            )
            name = f"{len(rows)} draws" if kind == "draw" else kind
            lines.append(f"| {env.split('/')[1]} | {name} | {steps:,} | {wrong:,} | {gap:.3g} "
                         f"| {turn:.3g} | {un_m:.3g}, {un_deg:.3g} |")  # fmt: skip
    command = next((c[len("command: ") :] for c in comments if c.startswith("command: ")), "")
    lines += ["", f"The witness steps a quarter of the step ({WITNESS_SPLIT} times the "
              f"substeps); a gap past {WITNESS_TOLERANCE_M:g} m, or attitudes turned apart by "
              f"more than {WITNESS_TOLERANCE_DEG:g} deg, in one action with neither run "
              f"flagged is an unflagged disagreement (`{command}`)."]  # fmt: skip
    return "\n".join(lines)


def main() -> None:
    parser = arguments(__doc__, "2e4 env-steps a case", "fuzz_witness.csv")
    parser.add_argument("--env-steps", type=float, default=1e7, help="in all (default 1e7)")
    parser.add_argument("--num-envs", type=int, default=256)
    parser.add_argument("--draws", type=int, default=16, help="knob draws per env")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--jobs", type=int, default=1)
    args = parser.parse_args()
    todo = cases(args.draws, args.seed)
    share = 2e4 if args.quick else math.ceil(args.env_steps / len(todo))
    jobs = [(c, share, args.num_envs, args.seed) for c in todo]
    with ProcessPoolExecutor(args.jobs) as pool:
        results = list(pool.map(_run, jobs))
    rows, failed = [], 0
    for case, r in zip(todo, results, strict=True):
        kind = "draw" if isinstance(case, DrawCase) else case.params
        knobs = " ".join(f"{k}={v}" for k, v in getattr(case, "knobs", ()))
        if isinstance(r, str):
            print(f"{case.env_id} {kind}: refused by the env, skipped: {r}")
            continue
        rows.append((case.env_id, kind, knobs, r["env_steps"], r["unflagged_disagreements"],
                     *(f"{r[k]:.6g}" for k in HEADER[5:])))  # fmt: skip
        failed += r["unflagged_disagreements"] > 0
        print(f"{case.env_id:28s} {kind:8s} {r['env_steps']:>10,} steps: "
              f"{r['unflagged_disagreements']} unflagged, largest gap "
              f"{r['max_disagreement_m']:.3g} m, {r['max_disagreement_deg']:.3g} deg",
              flush=True)  # fmt: skip
    out = args.out if not args.quick or args.out != parser.get_default("out") else None
    if out is not None:
        write_csv(out, HEADER, rows, describe(False))
        print(f"wrote {out}")
    print(
        f"{sum(r[3] for r in rows):,} env-steps in {len(rows)} cases; {failed} with "
        "unflagged disagreements"
    )
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
