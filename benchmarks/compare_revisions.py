"""Speed of two source trees of the package, measured in the same run, interleaved.

    git worktree add ../old <commit>          # the revision to compare with
    python -m benchmarks.compare_revisions ../old . --out docs/compare_revisions.csv
    python -m benchmarks.compare_revisions ../old . --only env --rounds 5 --out envs.csv

Absolute times drift on shared machines; a ratio between two trees measured in alternation
does not. Each round runs every case in a fresh interpreter that imports the package from
one tree, then the same in the other tree (A B A B ...); a tree's figure for a case is its
best over ``--rounds`` rounds. The cases: the dart's kernel (rk2, float32 and float64,
E = 1, 64, 1024, 16384, serial on one thread and parallel on two), every other integrator
at E = 16384, one step call at E = 1 (the round trip through Python), the three envs'
vector step with random actions at E = 64 and 4096 (best of 5 repeats of 0.2-1 s each per
round: at 2 threads one such step varies by 10-25% here). Only the public API is used
(``Simulator``, ``gym.make_vec``), so any revision since the envs' rk2 defaults runs the same
child code. Cold compile time (the first step with an empty numba cache) is measured once
per tree, first.

CSV columns: case, tree (``old``/``new``), value, unit; the printed table adds new/old (for
a rate, > 1 is faster; for a time, < 1 is faster).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from benchmarks.common import describe, write_csv

CHILD = r"""
import json, sys, time
import numpy as np
import numba

def best(fn, calls, repeats):
    fn()
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        out.append((time.perf_counter() - t0) / calls)
    return min(out)

def compile_s():
    from fluidsim_envs.physics import Craft, Simulator, World
    sim = Simulator(Craft.load("paper_airplane"), World(), num_envs=64, dt=1 / 240,
                    parallel=False)
    t0 = time.perf_counter()
    sim.step()
    return time.perf_counter() - t0

def kernel(integrator, dtype, num_envs, parallel, threads):
    from fluidsim_envs.physics import Craft, Simulator, World
    numba.set_num_threads(threads)
    E = num_envs
    sim = Simulator(Craft.load("paper_airplane"), World(), num_envs=E, dt=1 / 240,
                    integrator=integrator, dtype=np.dtype(dtype), parallel=parallel)
    ctrl = np.random.default_rng(0).uniform(-1, 1, (E, 3))
    sim.reset(pos=(0, 0, 1e4), lin_vel=(6.0, 0, 0))
    steps = max(1, int(400_000 // E))
    return E * steps / best(lambda: sim.step(ctrl, steps=steps), 1, 5)

def call():
    from fluidsim_envs.physics import Craft, Simulator, World
    sim = Simulator(Craft.load("paper_airplane"), World(), num_envs=1, dt=1 / 240,
                    integrator="rk2", parallel=False)
    ctrl = np.zeros((1, 3))
    sim.reset(pos=(0, 0, 1e4), lin_vel=(6.0, 0, 0))
    return 1e6 * best(lambda: sim.step(ctrl, steps=1), 2000, 7)

def env(env_id, num_envs):
    import gymnasium as gym
    import fluidsim_envs  # noqa: F401
    numba.set_num_threads(2)
    E = num_envs
    venv = gym.make_vec(env_id, num_envs=E, vectorization_mode="vector_entry_point")
    venv.reset(seed=0)
    acts = np.random.default_rng(0).uniform(-1, 1, (16, E, venv.action_space.shape[1]))
    acts = acts.astype(np.float32)
    k = [0]
    def step():
        venv.step(acts[k[0] % 16]); k[0] += 1
    calls = max(8, 200_000 // E)  # 0.2-1 s a repeat: a 2-thread step varies 10-25%
    out = E / best(step, calls, 5)
    venv.close()
    return out

cases = json.loads(sys.argv[1])
print(json.dumps([globals()[c["kind"]](**c["args"]) for c in cases]))
"""

ENVS = ("fluidsim/PaperAirplane-v0", "fluidsim/BoatOnStep-v0", "fluidsim/SubmarineWake-v0")
# written out, not read from fluidsim_envs.scenes.SCENES: the old tree may predate it


def cases(quick: bool) -> list[dict]:
    """Each case: (name, unit, the child function, its arguments)."""
    out = []
    sizes = (1, 16384) if quick else (1, 64, 1024, 16384)
    for dtype in ("float32", "float64"):
        for E in sizes:
            for parallel, threads in ((False, 1), (True, 2)):
                kernel = f"parallel/{threads}" if parallel else "serial"
                out.append(dict(
                    name=f"kernel rk2 {dtype} E={E} {kernel}", unit="body-steps/s",
                    kind="kernel", args=dict(integrator="rk2", dtype=dtype, num_envs=E,
                                             parallel=parallel, threads=threads),
                ))  # fmt: skip
    for integ in ("explicit_euler", "symplectic_euler", "velocity_verlet", "rk4", "verlet_tetra"):
        out.append(dict(
            name=f"kernel {integ} float64 E=16384 parallel/2", unit="body-steps/s",
            kind="kernel", args=dict(integrator=integ, dtype="float64", num_envs=16384,
                                     parallel=True, threads=2),
        ))  # fmt: skip
    out.append(dict(name="step call E=1", unit="us", kind="call", args={}))
    for env_id in ENVS:
        for E in (64,) if quick else (64, 4096):
            out.append(dict(name=f"env {env_id.split('/')[1]} E={E}", unit="env-steps/s",
                            kind="env", args=dict(env_id=env_id, num_envs=E)))  # fmt: skip
    return out


def run(tree: Path, todo: list[dict], cache: str | None = None) -> list[float]:
    """Run the cases in one fresh interpreter importing the package from ``tree``."""
    env = dict(os.environ, PYTHONPATH=str(tree.resolve()))
    if cache:
        env["NUMBA_CACHE_DIR"] = cache
    payload = json.dumps([{"kind": c["kind"], "args": c["args"]} for c in todo])
    out = subprocess.run(
        [sys.executable, "-c", CHILD, payload], env=env, cwd=tempfile.gettempdir(),
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    if out.returncode:
        raise RuntimeError(f"{tree} failed:\n{out.stderr[-3000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old", type=Path, help="the tree to compare with (a git worktree)")
    parser.add_argument("new", type=Path, help="the tree measured against it")
    parser.add_argument("--rounds", type=int, default=3, help="A/B alternations")
    parser.add_argument("--quick", action="store_true", help="fewer cases")
    parser.add_argument(
        "--only", action="append", default=None, help="cases whose name has this (repeatable); "
        "no cold compile then",
    )  # fmt: skip
    parser.add_argument("--out", type=Path, default=Path("docs/compare_revisions.csv"))
    args = parser.parse_args()
    trees = {"old": args.old, "new": args.new}
    machine = describe()
    rows = []
    compile_case = [dict(kind="compile_s", args={})]
    for label, tree in trees.items() if args.only is None else ():
        with tempfile.TemporaryDirectory() as cache:
            (sec,) = run(tree, compile_case, cache=cache)
        rows.append(("cold compile", label, sec, "s"))
        print(f"cold compile {label}: {sec:.1f} s", flush=True)
    todo = [c for c in cases(args.quick) if not args.only or any(k in c["name"] for k in args.only)]
    for tree in trees.values():  # fill each tree's own numba cache
        run(tree, compile_case)
    results = {label: [] for label in trees}
    for r in range(args.rounds):
        for label, tree in trees.items():
            results[label].append(run(tree, todo))
            print(f"round {r + 1} {label} done", flush=True)
    for i, case in enumerate(todo):
        lower = case["unit"] == "us"
        pick = {k: (min if lower else max)(round_[i] for round_ in v) for k, v in results.items()}
        for label in trees:
            rows.append((case["name"], label, pick[label], case["unit"]))
        print(
            f"{case['name']:46s} old {pick['old']:11.4g} new {pick['new']:11.4g} "
            f"new/old {pick['new'] / pick['old']:.3f}"
        )
    note = f"old = {args.old}, new = {args.new}; best of {args.rounds} interleaved rounds"
    write_csv(args.out, ("case", "tree", "value", "unit"), rows, [*machine, note])


if __name__ == "__main__":
    main()
