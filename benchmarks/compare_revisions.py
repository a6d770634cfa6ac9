"""Speed of two source trees of the package, measured in the same run, interleaved.

    git worktree add ../old <commit>          # the revision to compare with
    python -m benchmarks.compare_revisions ../old . --out docs/compare_revisions.csv

Absolute times drift on shared machines; a ratio between two trees measured in alternation
does not. For every case (the dart's kernel at several batch sizes, dtypes, kernels and
threads; every integrator; one step call at E = 1; the three envs' vector step) each tree
runs in a fresh interpreter that imports the package from that tree, takes the best of a few
timed calls, and the trees alternate (A B A B ...) ``--rounds`` times; a tree's figure is its
best over the rounds. Only the public API is used (``Simulator``, ``gym.make_vec``), so any
revision since the envs' rk2 defaults runs the same child code. Cold compile time (an empty
numba cache) is measured once per tree.

Columns: case, tree (``old``/``new``), value, unit, then the new/old ratio of each case (for
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
case = json.loads(sys.argv[1])

def best(fn, calls, repeats):
    fn()
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn()
        out.append((time.perf_counter() - t0) / calls)
    return min(out)

if case["kind"] == "compile":
    from fluidsim_envs.physics import Craft, Simulator, World
    sim = Simulator(Craft.load("paper_airplane"), World(), num_envs=64, dt=1 / 240,
                    parallel=False)
    t0 = time.perf_counter()
    sim.step()
    print(json.dumps(time.perf_counter() - t0))
elif case["kind"] == "kernel":
    from fluidsim_envs.physics import Craft, Simulator, World
    numba.set_num_threads(case["threads"])
    E = case["num_envs"]
    sim = Simulator(Craft.load("paper_airplane"), World(), num_envs=E, dt=1 / 240,
                    integrator=case["integrator"], dtype=np.dtype(case["dtype"]),
                    parallel=case["parallel"])
    ctrl = np.random.default_rng(0).uniform(-1, 1, (E, 3))
    sim.reset(pos=(0, 0, 1e4), lin_vel=(6.0, 0, 0))
    steps = max(1, int(2_000_000 // (E * 10)))
    sec = best(lambda: sim.step(ctrl, steps=steps), 1, 5)
    print(json.dumps(E * steps / sec))
elif case["kind"] == "call":
    from fluidsim_envs.physics import Craft, Simulator, World
    sim = Simulator(Craft.load("paper_airplane"), World(), num_envs=1, dt=1 / 240,
                    integrator="rk2", parallel=False)
    ctrl = np.zeros((1, 3))
    sim.reset(pos=(0, 0, 1e4), lin_vel=(6.0, 0, 0))
    print(json.dumps(1e6 * best(lambda: sim.step(ctrl, steps=1), 2000, 7)))
else:  # an env's vector step, random actions
    import gymnasium as gym
    import fluidsim_envs  # noqa: F401
    numba.set_num_threads(2)
    E = case["num_envs"]
    venv = gym.make_vec(case["env"], num_envs=E, vectorization_mode="vector_entry_point")
    venv.reset(seed=0)
    acts = np.random.default_rng(0).uniform(-1, 1, (16, E, venv.action_space.shape[1]))
    acts = acts.astype(np.float32)
    k = [0]
    def step():
        venv.step(acts[k[0] % 16]); k[0] += 1
    calls = max(1, 200_000 // E)
    print(json.dumps(E / best(step, calls, 3)))
"""

# written out, not read from fluidsim_envs.scenes.SCENES: the old tree may predate it
ENVS = ("fluidsim/PaperAirplane-v0", "fluidsim/BoatOnStep-v0", "fluidsim/SubmarineWake-v0")


def cases(quick: bool) -> list[dict]:
    out = []
    sizes = (64, 16384) if quick else (1, 64, 1024, 16384)
    for dtype in ("float32", "float64"):
        for E in sizes:
            for parallel, threads in ((False, 1), (True, 2)):
                out.append(dict(kind="kernel", integrator="rk2", dtype=dtype, num_envs=E,
                                parallel=parallel, threads=threads))  # fmt: skip
    for integ in ("explicit_euler", "symplectic_euler", "velocity_verlet", "rk4", "verlet_tetra"):
        out.append(dict(kind="kernel", integrator=integ, dtype="float64", num_envs=16384,
                        parallel=True, threads=2))  # fmt: skip
    out.append(dict(kind="call"))
    for env in ENVS:
        for E in (64, 4096) if not quick else (1024,):
            out.append(dict(kind="env", env=env, num_envs=E))
    return out


def name(case: dict) -> str:
    if case["kind"] == "kernel":
        kernel = f"parallel/{case['threads']}" if case["parallel"] else "serial"
        return f"kernel {case['integrator']} {case['dtype']} E={case['num_envs']} {kernel}"
    if case["kind"] == "env":
        return f"env {case['env'].split('/')[1]} E={case['num_envs']}"
    return {"call": "step call E=1 (us)", "compile": "cold compile (s)"}[case["kind"]]


def run(tree: Path, case: dict, cache: str | None = None) -> float:
    env = dict(os.environ, PYTHONPATH=str(tree.resolve()))
    if cache:
        env["NUMBA_CACHE_DIR"] = cache
    out = subprocess.run(
        [sys.executable, "-c", CHILD, json.dumps(case)], env=env, cwd=tempfile.gettempdir(),
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    if out.returncode:
        raise RuntimeError(f"{tree}: {name(case)} failed:\n{out.stderr[-3000:]}")
    return float(json.loads(out.stdout.strip().splitlines()[-1]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("old", type=Path, help="the tree to compare with (a git worktree)")
    parser.add_argument("new", type=Path, help="the tree measured against it")
    parser.add_argument("--rounds", type=int, default=3, help="A/B alternations per case")
    parser.add_argument("--quick", action="store_true", help="fewer cases")
    parser.add_argument("--out", type=Path, default=Path("docs/compare_revisions.csv"))
    args = parser.parse_args()
    trees = {"old": args.old, "new": args.new}
    machine = describe()
    rows = []
    with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
        for (label, tree), cache in zip(trees.items(), (a, b), strict=True):
            sec = run(tree, dict(kind="compile"), cache=cache)
            rows.append(("cold compile (s)", label, sec, "s"))
            print(f"cold compile {label}: {sec:.1f} s", flush=True)
    for case in [dict(kind="compile")] + cases(args.quick):
        for tree in trees.values():  # fill each tree's own numba cache first
            run(tree, case)
        if case["kind"] == "compile":
            continue
        best = {"old": [], "new": []}
        for _ in range(args.rounds):
            for label, tree in trees.items():
                best[label].append(run(tree, case))
        lower = case["kind"] == "call"
        unit = "us" if lower else "steps/s"
        pick = {k: (min(v) if lower else max(v)) for k, v in best.items()}
        for label in trees:
            rows.append((name(case), label, pick[label], unit))
        ratio = pick["new"] / pick["old"]
        print(f"{name(case):55s} old {pick['old']:12.4g} new {pick['new']:12.4g} "
              f"new/old {ratio:.3f}", flush=True)  # fmt: skip
    note = f"old = {args.old}, new = {args.new}; best of {args.rounds} interleaved rounds"
    write_csv(args.out, ("case", "tree", "value", "unit"), rows, [*machine, note])


if __name__ == "__main__":
    main()
