"""Ranges that hold: each v1 knob's declared range, per craft, measured at each end and at
the corners that combine the craft's physics knobs, for how many episodes end
``physics_diverged``.

A *case* is one v1 env at ``hard`` (every other knob at its hardest level), its default
integrator and dt, with one knob at one end of its declared range (a span at ``(low, low)``
and ``(high, high)``: every episode draws that end), or a *corner*: the seven physics knobs
of :data:`CORNER_KNOBS` each at one of its ends (all 128 combinations). Each case flies
``--episodes`` episodes (one per sub-env, whole: the case steps ``max_episode_steps``) under
the fuzz's adversarial actions (``benchmarks/fuzz.py``'s :class:`~benchmarks.fuzz.Adversary`:
noise, bang-bang, sinusoids, saturated commands), and counts the episodes that diverged.

Writes ``docs/ranges.csv`` (a row per case: env, knob, end, value, episodes, diverged,
rate); ``tests/scenes/test_ranges.py`` checks that every declared range of every v1 env is
the one the table measured, and that no end and no corner diverges in 1% of its episodes
or more (:data:`LIMIT`)::

    python -m benchmarks.ranges --jobs 2        # the published table (2 cores)
    python -m benchmarks.ranges --quick         # 16 episodes a case, printed only
"""

from __future__ import annotations

import itertools
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from benchmarks.common import DOCS, arguments, describe, keep_others, write_csv
from benchmarks.fuzz import run_case
from fluidsim_envs.scenes import SCENES
from fluidsim_envs.scenes.limits import Bound, Span

LIMIT = 0.01  # the share of episodes a range's end may lose to divergence
CSV = DOCS / "ranges.csv"
#: the knobs that change the craft's physics (mass, its distribution, its forces): their
#: ends combine in the corners
CORNER_KNOBS = (
    "mass_scale", "inertia_scale", "com_shift_m", "area_scale", "efficiency_scale",
    "thrust_scale", "density_scale",
)  # fmt: skip
HEADER = ("env", "knob", "end", "value", "episodes", "diverged", "rate", "nonfinite")


def v1_envs() -> list[str]:
    return [i for i in SCENES if i.endswith("-v1")]


def knob_ranges(env_id: str) -> dict[str, Bound | Span]:
    """Every knob of the env's v1 with its declared range (the shared ones with the scene's
    own over them), numbers only (a choice, a flag: no end to measure)."""
    rules = SCENES[env_id].params_cls.KNOB_RANGES
    return {k: r for k, r in rules.items() if isinstance(r, Bound | Span)}


def ends(rule: Bound | Span) -> dict[str, object]:
    """The value that puts a knob at each end of its range."""
    if isinstance(rule, Span):
        return {"low": (rule.lo, rule.lo), "high": (rule.hi, rule.hi)}
    return {"low": rule.lo, "high": rule.hi}


def cases(env_id: str) -> list[tuple[str, str, dict]]:
    """(knob, end, env kwargs) of each case of ``env_id``: every knob's two ends, then the
    corners (knob ``corner``, end the seven ends' initials)."""
    rules = knob_ranges(env_id)
    out = [(k, end, {k: v}) for k, rule in rules.items() for end, v in ends(rule).items()]
    for combo in itertools.product(("low", "high"), repeat=len(CORNER_KNOBS)):
        kwargs = {k: ends(rules[k])[end] for k, end in zip(CORNER_KNOBS, combo, strict=True)}
        out.append(("corner", "".join(e[0] for e in combo), kwargs))
    return out


class _Case:
    """What :func:`benchmarks.fuzz.run_case` reads of a case."""

    def __init__(self, env_id: str, kwargs: dict) -> None:
        self.env_id, self._kwargs = env_id, kwargs

    def kwargs(self) -> dict:
        return {"difficulty": "hard", **self._kwargs}


def measure(env_id: str, kwargs: dict, episodes: int, seed: int = 0) -> dict:
    """The fuzz's counts for ``episodes`` whole episodes of ``env_id`` with ``kwargs``."""
    steps = SCENES[env_id].params_cls().max_episode_steps
    return run_case(_Case(env_id, kwargs), steps * episodes, episodes, seed)


def markdown() -> str:
    """docs/ranges.csv as a table: per env and knob its two ends with their divergence
    rates, then each env's corners (how many, the worst)."""
    from benchmarks.common import read_csv

    if not CSV.is_file():
        return "(no docs/ranges.csv yet: run python -m benchmarks.ranges)"
    comments, table = read_csv(CSV)
    lines = ["| env | knob | low | diverged | high | diverged |", "|---|---|---|---:|---|---:|"]
    for env in dict.fromkeys(r["env"] for r in table):
        rows = [r for r in table if r["env"] == env]
        for knob in dict.fromkeys(r["knob"] for r in rows if r["knob"] != "corner"):
            low, high = (next(r for r in rows if r["knob"] == knob and r["end"] == e)
                         for e in ("low", "high"))  # fmt: skip
            lines.append(
                f"| {env.split('/')[1]} | `{knob}` | {low['value']} | {_rate(low)} "
                f"| {high['value']} | {_rate(high)} |"
            )
        corners = [r for r in rows if r["knob"] == "corner"]
        worst = max(corners, key=lambda r: float(r["rate"]))
        lines.append(
            f"| {env.split('/')[1]} | {len(corners)} corners of {', '.join(CORNER_KNOBS)} "
            f"| | | worst: {worst['end']} | {_rate(worst)} |"
        )
    episodes = min(int(r["episodes"]) for r in table)
    command = next((c[len("command: ") :] for c in comments if c.startswith("command: ")), "")
    lines += ["", f"At least {episodes:,} episodes a case (`{command}`); a corner is named by "
              f"its knobs' ends in that order (l: low, h: high). No case may lose "
              f"{LIMIT:.0%} of its episodes."]  # fmt: skip
    return "\n".join(lines)


def _rate(row: dict) -> str:
    return f"{float(row['rate']):.2%} of {int(row['episodes']):,}"


def _measure(job: tuple) -> dict:
    return measure(*job)


def main() -> None:
    parser = arguments(__doc__, "16 episodes a case", "ranges.csv")
    parser.add_argument("--episodes", type=int, default=256, help="per case (default 256)")
    parser.add_argument("--env", action="append", choices=v1_envs(),
                        help="only these (the others' rows are kept from --out)")  # fmt: skip
    parser.add_argument("--jobs", type=int, default=1, help="processes (each case alone)")
    args = parser.parse_args()
    episodes = 16 if args.quick else args.episodes
    todo = [(env_id, *case) for env_id in args.env or v1_envs() for case in cases(env_id)]
    with ProcessPoolExecutor(args.jobs) as pool:  # each case seeded alike: any --jobs
        results = pool.map(_measure, [(e, kw, episodes) for e, _, _, kw in todo])
        rows, failed = [], 0
        for (env_id, knob, end, kwargs), r in zip(todo, results, strict=True):
            rate = r["diverged"] / max(r["episodes"], 1)
            value = "" if knob == "corner" else kwargs[knob]
            rows.append((env_id, knob, end, value, r["episodes"], r["diverged"], f"{rate:.6g}",
                         r["nonfinite"]))  # fmt: skip
            failed += rate >= LIMIT
            print(f"{env_id:28s} {knob:22s} {end:8s} {value!s:14s} diverged {rate:.2%} "
                  f"of {r['episodes']:,}", flush=True)  # fmt: skip
    out = args.out if not args.quick or args.out != parser.get_default("out") else None
    if out is not None:  # an env not measured keeps its rows
        order = v1_envs()
        rows, notes = keep_others(Path(out), HEADER, rows, args.env or order)
        rows.sort(key=lambda r: order.index(r[0]))  # stable: each env's cases in order
        write_csv(out, HEADER, rows, describe(False) + notes)
        print(f"wrote {out}")
    print(f"{len(rows)} cases; {failed} at or over {LIMIT:.0%} divergence")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
