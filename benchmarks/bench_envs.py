"""Env-steps per second of our vector envs against their own physics alone and beside
gymnasium's CartPole vector env, float64 and float32, in one run.

For each env, dtype and num_envs in (1, 64, 1024, 4096, 16384), interleaved round by round:

- ``vector``: ``make_vec(id, num_envs, vectorization_mode="vector_entry_point")``, reset with
  a seed, then ``WINDOW`` steps with random actions (drawn beforehand, not timed), autoresets
  included, as in training;
- ``physics``: the same env's simulator alone, ``sim.step(controls, steps=substeps)``, for
  ``WINDOW`` calls from the same freshly reset states: what the physics of a vector step
  costs. ``vector / physics`` is what the task, the autoreset and the API add;
- ``bare``: the env's craft in a plain ``Simulator(craft, World(), integrator=..., dt=...)`` at
  the same size (in water or air as the env, without its floor, swell, wake or task), at call
  lengths of 1, ``substeps`` and 16 steps: the
  craft's own physics speed; the best of them over sizes is the craft's best (``physics``
  against it says what the env's world, its floor and its call length cost).

Each figure is the best of ``--repeats`` rounds, in env-steps (one action of one sub-env, the
env's ``substeps`` physics steps) per second. The single env (``gym.make``, gymnasium's
default wrappers) and extra variants (the submarine without its wake, the boat in swell and
with buoy bodies, the first defaults' symplectic Euler) are measured in float64. CartPole-v1
is the peer: an almost empty env (four numbers of state), the ceiling of the Gymnasium API.

Writes ``docs/bench_envs.csv`` (machine in ``#`` lines) and ``docs/bench_envs.png``;
``benchmarks.report`` writes docs/benchmarks.md's tables from the CSV (:func:`markdown`).

    python -m benchmarks.bench_envs [--quick]
"""

from __future__ import annotations

import math
import time

import gymnasium as gym
import numpy as np

from benchmarks.common import (
    DOCS,
    ROOT,
    arguments,
    describe,
    load_average,
    rate_over,
    read_csv,
    write_csv,
)
from fluidsim_envs.physics import Simulator, World
from fluidsim_envs.scenes import SCENES

ENVS = tuple(SCENES)  # every registered scene
DTYPES = ("float64", "float32")
NUM_ENVS = (1, 64, 1024, 4096, 16384)
WINDOW = 16  # steps per timed window, from fresh resets
SWELL = ((0.3, 30.0, 45.0), (0.15, 12.0, -60.0))
# extra rows, float64 vector only: (label, env id, make kwargs)
VARIANTS = (
    ("SubmarineWake-v0 wake=False", "fluidsim/SubmarineWake-v0", {"wake": False}),
    # a surface height under every sample, every evaluation
    ("BoatOnStep-v0 swell", "fluidsim/BoatOnStep-v0", {"swell": SWELL}),
    # the 12 buoys as moored floating bodies: 13 bodies and contact
    ("BoatOnStep-v0 buoy_bodies", "fluidsim/BoatOnStep-v0", {"buoy_bodies": True}),
    # the first defaults: symplectic Euler at half the step (as many force evaluations per
    # action as rk2 at the default; the submarine: 5 against 4)
    *(
        (
            f"{short} symplectic_euler",
            f"fluidsim/{short}",
            {"integrator": "symplectic_euler", "dt": dt, "substeps": n},
        )
        for short, dt, n in (
            ("PaperAirplane-v0", 1 / 240, 8),
            ("SubmarineWake-v0", 1 / 50, 5),
            ("BoatOnStep-v0", 1 / 200, 10),
        )
    ),  # fmt: skip
)
PEER = "CartPole-v1"
COLUMNS = ("env", "dtype", "kind", "num_envs", "call_steps", "env_steps_per_s")


def actions_for(space, n: int, rng) -> list:
    """Pre-drawn random actions, cycled through in the timed loop."""
    if isinstance(space, gym.spaces.Discrete) or (
        isinstance(space, gym.spaces.MultiDiscrete) and space.shape
    ):
        hi = space.n if isinstance(space, gym.spaces.Discrete) else space.nvec
        return [rng.integers(0, hi, size=space.shape) for _ in range(n)]
    return [rng.uniform(space.low, space.high).astype(space.dtype) for _ in range(n)]


class EnvRig:
    """One env at one size: its vector env, the same env's simulator alone, and a plain
    simulator of its craft; each timed over windows of ``WINDOW`` steps from fresh resets."""

    def __init__(self, env_id: str, num_envs: int, kwargs: dict) -> None:
        self.venv = gym.make_vec(
            env_id, num_envs=num_envs, vectorization_mode="vector_entry_point", **kwargs
        )
        env = self.venv.unwrapped
        self.n = num_envs
        rng = np.random.default_rng(0)
        self.acts = actions_for(self.venv.action_space, WINDOW, rng)
        self.controls = [
            rng.uniform(-1, 1, (num_envs, len(env.sim.control_names))) for _ in range(WINDOW)
        ]
        self.substeps = env.params.substeps
        self.venv.reset(seed=0)
        for a in self.acts:  # compile (or load) everything first
            self.venv.step(a)
        for c in self.controls[:2]:
            env.sim.step(c, steps=self.substeps)
        self.bare = None

    def vector(self, seconds: float) -> float:
        def run():
            self.venv.reset(seed=0)
            t = time.perf_counter()
            for a in self.acts:
                self.venv.step(a)
            return time.perf_counter() - t

        return _windows(run, self.n * WINDOW, seconds)

    def physics(self, seconds: float) -> float:
        sim = self.venv.unwrapped.sim

        def run():
            self.venv.reset(seed=0)
            t = time.perf_counter()
            for c in self.controls:
                sim.step(c, steps=self.substeps)
            return time.perf_counter() - t

        return _windows(run, self.n * WINDOW, seconds)

    def bare_rates(self, seconds: float) -> dict[int, float]:
        """The craft alone, at call lengths 1, substeps and 16: env-steps per second (one
        env-step being ``substeps`` physics steps)."""
        env = self.venv.unwrapped
        if self.bare is None:
            p = env.params
            world = World(water=env.sim.world.water)  # no floor, swell, wake or task
            self.bare = Simulator(
                env.sim.crafts, world, num_envs=self.n, dt=p.dt, integrator=p.integrator,
                dtype=p.dtype,
            )  # fmt: skip
        sim, out = self.bare, {}
        for steps in sorted({1, self.substeps, 16}):
            sim.reset()
            sim.step(self.controls[0], steps=steps)
            calls = max(1, WINDOW * self.substeps // steps)

            def run(steps=steps, calls=calls):
                sim.reset()
                t = time.perf_counter()
                for i in range(calls):
                    sim.step(self.controls[i % WINDOW], steps=steps)
                return time.perf_counter() - t

            out[steps] = _windows(run, self.n * calls * steps / self.substeps, seconds)
        return out

    def close(self) -> None:
        self.venv.close()


def _windows(run, work: float, seconds: float) -> float:
    """Best rate of timed windows (``run`` returns its seconds) over about ``seconds``."""
    best, t0 = 0.0, time.perf_counter()
    while True:
        best = max(best, work / run())
        if time.perf_counter() - t0 >= seconds:
            return best


def cartpole(num_envs: int, seconds: float) -> float:
    venv = gym.make_vec(PEER, num_envs=num_envs, vectorization_mode="vector_entry_point")
    acts = actions_for(venv.action_space, WINDOW, np.random.default_rng(0))
    venv.reset(seed=0)
    for a in acts:
        venv.step(a)

    def run():
        t = time.perf_counter()
        for a in acts:
            venv.step(a)
        return time.perf_counter() - t

    rate = _windows(run, num_envs * WINDOW, seconds)
    venv.close()
    return rate


def stepping(venv, acts: list):
    """A run for ``common.rate_over``: the actions one after the other on a vector env (which
    resets its ended sub-envs itself); returns the env-steps done (bench_peers,
    study_model_cost)."""
    work = len(acts) * venv.num_envs

    def run() -> int:
        for a in acts:
            venv.step(a)
        return work

    return run


def single_rate(env_id: str, seconds: float, repeats: int = 1) -> float:
    """The single env's (``gym.make``, gymnasium's default wrappers) env-steps per second:
    the best of ``repeats`` runs of about ``seconds``."""
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
    parser = arguments(__doc__, "shorter, noisier runs, 1024 envs at most", "bench_envs.csv")
    parser.add_argument("--seconds", type=float, default=0.5, help="per figure and round")
    parser.add_argument("--repeats", type=int, default=3, help="interleaved rounds")
    args = parser.parse_args()
    quick = args.quick
    if quick and args.out == DOCS / "bench_envs.csv":  # never over the published numbers
        args.out = ROOT / "build" / "bench_envs_quick.csv"
    seconds, repeats = (0.1, 1) if quick else (args.seconds, args.repeats)
    sizes = NUM_ENVS[:3] if quick else NUM_ENVS

    machine = describe()
    rows: list[tuple] = []

    def add(env, dtype, kind, n, steps, rate):
        rows.append((env, dtype, kind, n, steps, f"{rate:.1f}"))
        print(f"{env:30s} {dtype:8s} {kind:8s} {n:6d} {steps:3d} {rate:14,.0f}", flush=True)

    for env_id in (*ENVS, PEER):
        add(env_id, "float64", "single", 1, 0, single_rate(env_id, seconds, repeats))
    for n in sizes:
        best = max(cartpole(n, seconds) for _ in range(repeats))
        add(PEER, "float32", "vector", n, 0, best)
        for env_id in ENVS:
            for dtype in DTYPES:
                rig = EnvRig(env_id, n, {"dtype": dtype})
                vec = phys = 0.0
                bare: dict[int, float] = {}
                for _ in range(repeats):  # interleaved: vector, physics, bare, ...
                    vec = max(vec, rig.vector(seconds))
                    phys = max(phys, rig.physics(seconds))
                    for k, r in rig.bare_rates(seconds / 3).items():
                        bare[k] = max(bare.get(k, 0.0), r)
                rig.close()
                name = env_id.split("/")[-1]
                add(name, dtype, "vector", n, rig.substeps, vec)
                add(name, dtype, "physics", n, rig.substeps, phys)
                for k, r in bare.items():
                    add(name, dtype, "bare", n, k, r)
        for label, env_id, kwargs in VARIANTS:
            rig = EnvRig(env_id, n, kwargs)
            vec = max(rig.vector(seconds) for _ in range(repeats))
            rig.close()
            add(label, "float64", "vector", n, rig.substeps, vec)

    out = write_csv(args.out, COLUMNS, rows, [*machine, load_average()])
    print(f"\nwrote {out}")
    print(markdown(out))
    if not quick:
        plot(out, DOCS / "bench_envs.png")


# ---- reading the CSV -----------------------------------------------------------------------


def _table(path):
    _, rows = read_csv(path)
    return {
        (r["env"], r["dtype"], r["kind"], int(r["num_envs"]), int(r["call_steps"])): float(
            r["env_steps_per_s"]
        )
        for r in rows
    }


def _best_bare(t: dict, env: str, dtype: str) -> float:
    return max((v for (e, d, k, _, _), v in t.items() if (e, d, k) == (env, dtype, "bare")),
               default=math.nan)  # fmt: skip


def _get(t: dict, env: str, dtype: str, kind: str, n: int) -> float:
    hits = [v for (e, d, k, m, _), v in t.items() if (e, d, k, m) == (env, dtype, kind, n)]
    return max(hits) if hits else math.nan


def _steps(t: dict, env: str, dtype: str, kind: str, n: int) -> int:
    """The call length of a (single) row: the env's substeps for its physics rows."""
    return next(s for (e, d, k, m, s) in t if (e, d, k, m) == (env, dtype, kind, n))


def markdown(path=None) -> str:
    """docs/benchmarks.md's env tables from ``docs/bench_envs.csv``: per env, dtype and
    num_envs, env-steps/s of the vector env, over its physics alone, over the craft's best
    bare physics, and over CartPole's vector env; then the variants."""
    path = DOCS / "bench_envs.csv" if path is None else path
    if not path.is_file():
        return "(no docs/bench_envs.csv yet: run python -m benchmarks.bench_envs)"
    t = _table(path)
    envs = list(dict.fromkeys(e for (e, d, k, _, _) in t if d in DTYPES and k == "physics"))
    sizes = sorted({m for (_, _, k, m, _) in t if k == "vector" and m > 0})
    lines = [
        "| env | dtype | num_envs | env-steps/s | vector / physics | physics / bare "
        "| physics / best bare | vs CartPole |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for env in envs:
        for dtype in DTYPES:
            best = _best_bare(t, env, dtype)
            for n in sizes:
                vec = _get(t, env, dtype, "vector", n)
                phys = _get(t, env, dtype, "physics", n)
                cart = _get(t, PEER, "float32", "vector", n)
                if math.isnan(vec):
                    continue
                same = t.get((env, dtype, "bare", n, _steps(t, env, dtype, "physics", n)))
                lines.append(
                    f"| {env} | {dtype} | {n} | {vec:,.0f} | {phys / vec:.2f} | "
                    f"{(same or math.nan) / phys:.2f} | {best / phys:.2f} | {vec / cart:.3f} |"
                )
    lines += [
        "",
        "vector / physics: how many times longer a vector step takes than its physics alone "
        "(1.00: the task, the autoreset and the API cost nothing); physics / bare: how many "
        "times longer the env's physics takes than its craft alone in an empty world at the "
        "same size and call length (what the env's world costs: floor, wind, swell, wake); "
        "physics / best bare: the same against the craft alone at its best size and call "
        "length (what the env's call length of one action's substeps costs besides).",
        "",
        "| variant (float64) | " + " | ".join(f"{n}" for n in sizes) + " |",
        "|---|" + "---:|" * len(sizes),
    ]
    variants = dict.fromkeys(
        e for (e, d, k, _, _) in t if k == "vector" and e not in envs and e != PEER
    )
    single = {e: v for (e, d, k, _, _), v in t.items() if k == "single"}
    for label in variants:
        lines.append(
            f"| {label} | "
            + " | ".join(f"{_get(t, label, 'float64', 'vector', n):,.0f}" for n in sizes)
            + " |"
        )
    lines += [
        "",
        "Single env (`gym.make`, one sub-env, gymnasium's wrappers), env-steps/s: "
        + ", ".join(f"{e.split('/')[-1]} {v:,.0f}" for e, v in single.items())
        + ".",
    ]
    return "\n".join(lines)


def plot(path, png) -> None:
    """Env-steps/s against num_envs: each env's vector step (float64 solid, float32 dashed),
    its physics alone (dotted), and CartPole's vector env."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = _table(path)
    envs = list(dict.fromkeys(e for (e, d, k, _, _) in t if k == "physics"))
    sizes = sorted({m for (_, _, k, m, _) in t if k == "vector"})
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for i, env in enumerate(envs):
        color = f"C{i}"
        for dtype, style in (("float64", "-"), ("float32", "--")):
            ax.plot(sizes, [_get(t, env, dtype, "vector", n) for n in sizes], style, color=color,
                    marker="o", ms=3, label=f"{env} {dtype}")  # fmt: skip
        ax.plot(sizes, [_get(t, env, "float64", "physics", n) for n in sizes], ":",
                color=color, label=f"{env} physics alone (float64)")  # fmt: skip
    ax.plot(sizes, [_get(t, PEER, "float32", "vector", n) for n in sizes], "-", color="k",
            marker="s", ms=3, label=f"{PEER} (gymnasium)")  # fmt: skip
    peers = DOCS / "bench_peers.csv"  # single-process peers (benchmarks/bench_peers.py)
    if peers.is_file():
        seen = set()
        for r in read_csv(peers)[1]:
            if r["section"] == "peer" and r["subject"] not in seen:
                seen.add(r["subject"])
                ax.axhline(float(r["value"]), color="0.5", ls="-.", lw=0.8)
                ax.text(sizes[0], float(r["value"]) * 1.1, f"{r['subject']}: {r['unit']}, one "
                        "process (bench_peers.csv)", fontsize=7, color="0.3")  # fmt: skip
    ax.set(xscale="log", yscale="log", xlabel="num_envs (sub-envs of one vector env)",
           ylabel="env-steps per second", title="Vector env throughput, 2 cores")  # fmt: skip
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2, loc="lower right")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    plt.close(fig)
    print(f"wrote {png}")


if __name__ == "__main__":
    main()
