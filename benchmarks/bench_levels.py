"""What each v1 level, and each part of ``standard`` alone, costs in env-steps per second.

For each v1 env: its v0, its v1 at ``easy`` without the probes (``observe_samples=False``:
what the probes cost), at ``easy``, ``standard``, ``hard`` and at ``easy`` with one
part of ``standard`` switched on at a time (``study_levels.settings``: the randomized physics,
the instruments, the actuators, the moving air or water), as vector envs of ``--num-envs``
sub-envs in float64, timed interleaved round by round (``--repeats`` rounds, the best window
of ``WINDOW`` steps each, autoresets included, random actions drawn beforehand).

Writes ``docs/bench_levels.csv`` and ``docs/bench_levels.png``; :func:`markdown` renders the
table for docs/benchmarks.md (``benchmarks.report``).

    python -m benchmarks.bench_levels [--quick] [--num-envs N]
"""

from __future__ import annotations

import time

import gymnasium as gym
import numpy as np

import fluidsim_envs  # noqa: F401  (registers the ids)
from benchmarks.common import DOCS, arguments, describe, load_average, read_csv, write_csv
from benchmarks.study_levels import settings
from fluidsim_envs.scenes import SCENES

WINDOW = 16
COLUMNS = ("env", "setting", "num_envs", "env_steps_per_s", "vs_v0")


class Rig:
    """One env at one setting, its actions drawn beforehand."""

    def __init__(self, env_id: str, kwargs: dict, n: int) -> None:
        self.venv = gym.make_vec(env_id, num_envs=n, vectorization_mode="vector_entry_point",
                                 **kwargs)  # fmt: skip
        rng = np.random.default_rng(0)
        self.acts = [rng.uniform(-1, 1, self.venv.action_space.shape) for _ in range(WINDOW)]
        self.n = n
        self.venv.reset(seed=0)
        for a in self.acts:  # compile (or load) everything first
            self.venv.step(a)

    def rate(self, seconds: float) -> float:
        best, t0 = 0.0, time.perf_counter()
        while time.perf_counter() - t0 < seconds:
            t = time.perf_counter()
            for a in self.acts:
                self.venv.step(a)
            best = max(best, self.n * WINDOW / (time.perf_counter() - t))
        return best


def main() -> None:
    parser = arguments(__doc__, "1024 envs, one short round", "bench_levels.csv")
    parser.add_argument("--num-envs", type=int, default=None, help="sub-envs (default 4096)")
    parser.add_argument("--repeats", type=int, default=3, help="interleaved rounds")
    parser.add_argument("--seconds", type=float, default=0.6, help="per figure and round")
    args = parser.parse_args()
    n = args.num_envs or (1024 if args.quick else 4096)
    repeats = 1 if args.quick else args.repeats
    out = args.out if not args.quick else DOCS.parent / "build" / "bench_levels_quick.csv"
    machine = list(describe())
    rows = []
    for env_id in (i for i, s in SCENES.items() if s.version == 1):
        first = SCENES[env_id].first_id
        rigs = {"v0": Rig(first, {}, n)}
        # the probes' cost: easy reads them (observe_samples, on by default), this does not
        rigs["easy without probes"] = Rig(
            env_id, {"difficulty": "easy", "observe_samples": False}, n
        )
        rigs.update({label: Rig(env_id, kw, n) for label, kw in settings(env_id)})
        best = dict.fromkeys(rigs, 0.0)
        for _ in range(repeats):  # interleaved: every setting once per round
            for label, rig in rigs.items():
                best[label] = max(best[label], rig.rate(args.seconds))
        for label, rate in best.items():
            rows.append((env_id.split("/")[1], label, n, rate, rate / best["v0"]))
            print(f"{env_id} {label:40s} {rate:12,.0f} env-steps/s ({rate / best['v0']:.2f} of v0)",
                  flush=True)  # fmt: skip
        for rig in rigs.values():
            rig.venv.close()
    out.parent.mkdir(parents=True, exist_ok=True)
    cells = [[f"{x:.6g}" if isinstance(x, float) else str(x) for x in r] for r in rows]
    write_csv(out, COLUMNS, cells, [*machine, load_average("end")])
    plot(out, out.with_suffix(".png"))
    print(f"wrote {out}\n{markdown(out)}")


def plot(path, png) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    _, rows = read_csv(path)
    envs = list(dict.fromkeys(r["env"] for r in rows))
    fig, axes = plt.subplots(1, len(envs), figsize=(4.2 * len(envs), 4.2), sharey=True)
    for ax, env in zip(np.atleast_1d(axes), envs, strict=True):
        mine = [r for r in rows if r["env"] == env]
        labels = [r["setting"].replace("easy + standard's ", "+ ") for r in mine]
        ax.barh(labels, [float(r["vs_v0"]) for r in mine], color="tab:blue")
        ax.axvline(1.0, color="k", lw=0.8)
        ax.set_title(env, fontsize=10)
        ax.set_xlabel("env-steps/s over v0's")
        ax.invert_yaxis()
    fig.suptitle(f"v1's cost per level and part ({rows[0]['num_envs']} sub-envs, float64)")
    fig.tight_layout()
    fig.savefig(png, dpi=90)
    plt.close(fig)


def markdown(path=None) -> str:
    """docs/benchmarks.md's table of v1's cost from ``docs/bench_levels.csv``."""
    path = DOCS / "bench_levels.csv" if path is None else path
    if not path.is_file():
        return "(no docs/bench_levels.csv yet: run python -m benchmarks.bench_levels)"
    comments, rows = read_csv(path)
    lines = ["| env | setting | env-steps/s | over v0's |", "|---|---|---:|---:|"]
    for r in rows:
        lines.append(f"| {r['env']} | {r['setting']} | {float(r['env_steps_per_s']):,.0f} | "
                     f"{float(r['vs_v0']):.2f} |")  # fmt: skip
    load = "; ".join(c for c in comments if c.startswith("load average"))
    n = rows[0]["num_envs"] if rows else "?"
    lines += ["", f"{n} sub-envs, float64, 2 threads; {load}."]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
