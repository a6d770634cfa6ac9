"""float32 physics in the envs: what it changes in accuracy and task outcomes, against float64.

Each env runs its default physics (``integrator``, ``dt``, ``substeps``) in float64 and in
float32 (``dtype="float32"``: the state, the samples and the forces in single precision; the
clocks and observations as ever), over the same episodes, with the machinery of
``benchmarks/study_env_integrators.py``: E episodes in one vector env reset with one seed, the
first episode of each sub-env.

- Closed loop: the env's scripted pilot flies both; success rate (with its 95% Wilson
  interval), mean return, and the share of episodes whose success agrees with the reference's.
- Open loop: the reference's pilot actions (rk4 at a quarter of the default dt, float64)
  replayed in both: the craft's position error against the reference (median and 90th
  percentile, m) after 1, 3 and 10 s and at the episode's end; and float32 against float64
  directly (the rounding's own effect, same actions).

Speed is in ``docs/bench_envs.csv`` (its float32 and float64 rows, one run). Writes
``docs/study_float32.csv``; :func:`markdown` renders it for docs/study.md
(``benchmarks.report``).

    python -m benchmarks.study_float32 [--quick] [--episodes N]
"""

from __future__ import annotations

import math
import time

import numpy as np

from benchmarks.common import DOCS, arguments, describe, out_dir, read_csv, wilson, write_csv
from benchmarks.study_env_integrators import (
    SCENES,
    Config,
    position_errors,
    run_episodes,
)

SCENE_NAMES = ("paper_airplane", "submarine_wake", "boat_on_step", "boat_swell")
HORIZONS = ("1s", "3s", "10s", "end")


def main() -> None:
    parser = arguments(__doc__, "16 episodes, into build/")
    parser.add_argument("--episodes", type=int, default=None, help="episodes (sub-envs)")
    parser.add_argument("--seed", type=int, default=0, help="reset seed of the episodes")
    args = parser.parse_args()
    out = out_dir(args.out, args.quick)
    episodes = args.episodes or (16 if args.quick else 256)
    machine = describe()
    rows = []
    t0 = time.perf_counter()
    for scene in (s for s in SCENES if s.name in SCENE_NAMES):
        p = scene.params()
        step_s = float(p.dt) * int(p.substeps)
        ref_cfg = Config("rk4, dt/4 (reference)", "rk4", p.dt / 4, 4 * p.substeps, True)
        ref = run_episodes(scene, ref_cfg, episodes, args.seed)
        replay = (ref["actions"], ref["length"])
        opened = {}
        for dtype in ("float64", "float32"):
            cfg = Config(f"{p.integrator}, {dtype}", p.integrator, p.dt, p.substeps, dtype=dtype)
            closed = run_episodes(scene, cfg, episodes, args.seed)
            opened[dtype] = run_episodes(scene, cfg, episodes, args.seed, replay=replay)
            errs = position_errors(opened[dtype], ref, step_s)
            k = int(closed["success"].sum())
            lo, hi = wilson(k, episodes)
            row = {
                "scene": scene.name,
                "integrator": p.integrator,
                "dt_s": p.dt,
                "substeps": p.substeps,
                "dtype": dtype,
                "episodes": episodes,
                "success_rate": k / episodes,
                "success_low": lo,
                "success_high": hi,
                "success_agree": float(np.mean(closed["success"] == ref["success"])),
                "return_mean": float(np.mean(closed["return"])),
                "physics_diverged": int(closed["physics_diverged"].sum()),
            }
            for h in HORIZONS:
                row[f"err_{h}_median_m"], row[f"err_{h}_p90_m"], _ = errs[h]
            rows.append(row)
        direct = position_errors(opened["float32"], opened["float64"], step_s)
        for h in HORIZONS:
            rows[-1][f"f32_vs_f64_{h}_median_m"], rows[-1][f"f32_vs_f64_{h}_p90_m"], _ = direct[h]
        print(f"{scene.name}: done ({time.perf_counter() - t0:.0f} s)", flush=True)
    header = list(dict.fromkeys(k for r in rows for k in r))
    path = out / "study_float32.csv"
    cells = [[_fmt(r.get(k, "")) for k in header] for r in rows]
    write_csv(path, header, cells, machine)
    print(f"wrote {path}\n{markdown(path)}")


def _fmt(x) -> str:
    if isinstance(x, float):
        return "" if math.isnan(x) else f"{x:.6g}"
    return str(x)


def markdown(path=None) -> str:
    """docs/study.md's float32 table from ``docs/study_float32.csv``."""
    path = DOCS / "study_float32.csv" if path is None else path
    if not path.is_file():
        return "(no docs/study_float32.csv yet: run python -m benchmarks.study_float32)"
    _, rows = read_csv(path)

    def m(x: str) -> str:
        return "" if x == "" else f"{float(x):.2g}"

    lines = [
        "| scene | dtype | success (95% CI) | mean return | agrees with reference "
        "| error at 1 s / 3 s / 10 s / end (m, median) | float32 against float64 (m, median) |",
        "|---|---|---|---:|---:|---|---|",
    ]
    for r in rows:
        ci = f"{float(r['success_rate']):.0%} [{float(r['success_low']):.0%}, " + (
            f"{float(r['success_high']):.0%}]"
        )
        errs = " / ".join(m(r[f"err_{h}_median_m"]) for h in HORIZONS)
        direct = " / ".join(m(r.get(f"f32_vs_f64_{h}_median_m", "")) for h in HORIZONS)
        lines.append(
            f"| {r['scene']} | {r['dtype']} | {ci} | {float(r['return_mean']):.1f} | "
            f"{float(r['success_agree']):.0%} | {errs} | {direct if direct.strip(' /') else ''} |"
        )
    n = rows[0]["episodes"] if rows else "?"
    lines += [
        "",
        f"{n} episodes per row, the same in each; the reference is rk4 at a quarter of the "
        "env's dt in float64, and the open-loop errors replay its pilot's actions.",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
