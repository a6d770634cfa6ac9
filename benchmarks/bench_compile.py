"""Where a cold first step goes: per env, the seconds of the first ``gym.make`` + ``reset`` +
``step`` and of every numba compile under them.

Each env runs in its own Python process (``--cold``, the default: with ``NUMBA_CACHE_DIR``
pointing at a fresh empty folder, so every kernel compiles; ``--warm`` reuses one folder per
env, so a second run shows the cache's load time). The child listens to numba's
``"numba:compile"`` events (one per dispatcher and signature compiled; they nest: a kernel
compiles the non-inlined kernels it calls while typing its own body) and ``"numba:run_pass"``
events (to split a compile's own time into typing, lowering, which holds LLVM's optimization
and machine code, and the rest). Numba links each callee's LLVM module into its caller's and
optimizes and emits the whole again, so a dispatcher's own ("self") time grows with what it
calls, not only with its own code.

Rows of ``docs/bench_compile.csv`` (``env, what, seconds, note``):

- ``first make``, ``first reset``, ``first step``, ``first total`` (make + reset + step),
  ``import`` (``import fluidsim_envs``), ``second step`` (a warm call, for scale);
- ``compiles`` (note: how many dispatcher compiles, and how many of them this package's);
- ``compile <module.function>``: per dispatcher of this package, the seconds of its compiles
  excluding the nested ones (self), summed over its signatures; the note holds the number of
  signatures, their dtypes, the inclusive seconds and the self time's split
  (``lower``: lowering + LLVM, ``type``: typing, ``other``);
- ``phase <make|reset|step>``: the compile seconds spent inside each phase.

    python -m benchmarks.bench_compile                 # all envs, cold, docs/bench_compile.csv
    python -m benchmarks.bench_compile --env fluidsim/PaperAirplane-v0 --repeat 2
    python -m benchmarks.bench_compile --child fluidsim/PaperAirplane-v0   # one env, JSON out

Timings on a loaded 2-core machine vary by 10-20%: ``--repeat`` runs every env again
(one process each, in turn) and the CSV keeps every run (column ``run``).
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from collections import defaultdict

import numba

from benchmarks.common import ROOT, arguments, load_average, read_csv, write_csv

ENVS = ("fluidsim/PaperAirplane-v0", "fluidsim/SubmarineWake-v0", "fluidsim/BoatOnStep-v0")
PACKAGE = "fluidsim_envs"
COLUMNS = ("env", "run", "what", "seconds", "note")


# ---- child: one env, one process ------------------------------------------------------------


class _Recorder:
    """numba:compile and numba:run_pass events as a tree of timed frames."""

    def __init__(self) -> None:
        self.stack: list[dict] = []
        self.compiles: list[dict] = []  # one per finished numba:compile
        self.phase = "import"

    # numba.core.event.Listener's interface (duck-typed: on_start / on_end)
    def on_start(self, ev) -> None:
        data = ev.data or {}
        if ev.kind == "numba:compile":
            disp = data.get("dispatcher")
            fn = getattr(disp, "py_func", None)
            name = f"{getattr(fn, '__module__', '?')}.{getattr(fn, '__qualname__', '?')}"
            frame = dict(kind="compile", name=name, args=str(data.get("args")), phase=self.phase)
        else:
            frame = dict(kind="pass", name=str(data.get("name", "")).split(" [")[0])
        frame.update(t0=time.perf_counter(), children=0.0, passes=defaultdict(float))
        self.stack.append(frame)

    def on_end(self, ev) -> None:
        frame = self.stack.pop()
        took = time.perf_counter() - frame["t0"]
        if self.stack:  # a pass's own time excludes whatever runs inside it
            self.stack[-1]["children"] += took
        owner = next((f for f in reversed(self.stack) if f["kind"] == "compile"), None)
        if frame["kind"] == "pass":
            # the pass's own time belongs to the compile that runs it
            if owner is not None:
                owner["passes"][frame["name"]] += took - frame["children"]
            return
        if owner is not None:  # a compile's own time excludes the compiles nested in it
            owner["nested"] = owner.get("nested", 0.0) + took
        self.compiles.append(
            dict(
                name=frame["name"],
                args=frame["args"],
                phase=frame["phase"],
                inclusive=took,
                self=took - frame.get("nested", 0.0),
                passes=dict(frame["passes"]),
                depth=sum(1 for f in self.stack if f["kind"] == "compile"),
                parent=owner["name"] if owner is not None else "",
            )
        )


def child(env_id: str) -> dict:
    """Time import, make, reset and two steps of ``env_id``; every compile under them."""
    from numba.core import event

    rec = _Recorder()

    class Listener(event.Listener):
        def on_start(self, ev):
            rec.on_start(ev)

        def on_end(self, ev):
            rec.on_end(ev)

    listener = Listener()
    event.register("numba:compile", listener)
    event.register("numba:run_pass", listener)
    out = {"env": env_id}
    t0 = time.perf_counter()
    import gymnasium as gym
    import numpy as np

    import fluidsim_envs

    out["module"] = fluidsim_envs.__file__
    out["import"] = time.perf_counter() - t0
    for phase in ("make", "reset", "step", "second step"):
        rec.phase = phase
        t0 = time.perf_counter()
        if phase == "make":
            env = gym.make(env_id)
        elif phase == "reset":
            env.reset(seed=0)
        else:
            env.step(np.zeros(env.action_space.shape, dtype=env.action_space.dtype))
        out[phase] = time.perf_counter() - t0
    out["compiles"] = rec.compiles
    return out


# ---- parent: a process per env, the CSV ---------------------------------------------------------


def _dtypes(args: str) -> str:
    return "/".join(d for d in ("float32", "float64") if d in args) or "-"


def rows_of(res: dict, run: int) -> list[tuple]:
    env = res["env"]
    total = res["make"] + res["reset"] + res["step"]
    rows = [
        (env, run, "first total", total, "make + reset + step"),
        (env, run, "first make", res["make"], ""),
        (env, run, "first reset", res["reset"], ""),
        (env, run, "first step", res["step"], ""),
        (env, run, "second step", res["second step"], ""),
        (env, run, "import", res["import"], ""),
    ]
    comps = res["compiles"]
    ours = [c for c in comps if c["name"].startswith(PACKAGE)]
    top = [c for c in comps if c["depth"] == 0]
    rows.append(
        (
            env,
            run,
            "compiles",
            sum(c["inclusive"] for c in top),
            f"{len(comps)} dispatcher compiles, {len(ours)} of {PACKAGE}",
        )  # fmt: skip
    )
    for phase in ("make", "reset", "step"):
        s = sum(c["inclusive"] for c in top if c["phase"] == phase)
        n = sum(1 for c in comps if c["phase"] == phase)
        rows.append((env, run, f"phase {phase}", s, f"{n} compiles"))
    per = defaultdict(list)
    for c in comps:
        per[c["name"] if c["name"].startswith(PACKAGE) else "(numba/numpy internals)"].append(c)
    ranked = sorted(per.items(), key=lambda kv: -sum(c["self"] for c in kv[1]))
    for name, cs in ranked:
        self_s = sum(c["self"] for c in cs)
        lower = sum(v for c in cs for k, v in c["passes"].items() if "lowering" in k.lower())
        typing = sum(v for c in cs for k, v in c["passes"].items() if "type_inference" in k.lower())
        note = (
            f"{len(cs)} sig; {'+'.join(sorted({_dtypes(c['args']) for c in cs}))}; "
            f"incl {max(c['inclusive'] for c in cs):.2f}; lower {lower:.2f} type {typing:.2f} "
            f"other {self_s - lower - typing:.2f}"
        )
        rows.append((env, run, f"compile {name.removeprefix(PACKAGE + '.')}", self_s, note))
    return rows


def run_child(env_id: str, cache: str) -> dict:
    environ = dict(os.environ, NUMBA_CACHE_DIR=cache, FLUIDSIM_QUIET="1")
    environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), environ.get("PYTHONPATH")]))
    proc = subprocess.run(
        [sys.executable, "-m", "benchmarks.bench_compile", "--child", env_id],
        env=environ, cwd=ROOT, capture_output=True, text=True, check=False,
    )  # fmt: skip
    if proc.returncode != 0:
        raise RuntimeError(f"{env_id}: child failed\n{proc.stderr[-4000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def first_step_range(path=ROOT / "docs" / "bench_compile.csv") -> str:
    """The cold first step as the docs quote it, ``"A-B s"``: the fastest and the slowest
    env's mean ``first total`` over the runs in ``path`` (tests/test_readme.py checks that
    README.md, docs/benchmarks.md, the warmup and the compile notice say this)."""
    totals = defaultdict(list)
    for row in read_csv(path)[1]:
        if row["what"] == "first total":
            totals[row["env"]].append(float(row["seconds"]))
    means = [sum(v) / len(v) for v in totals.values()]
    return f"{min(means):.0f}-{max(means):.0f} s"


def main(argv=None) -> None:
    parser = arguments(__doc__, "the first env only, one run", "bench_compile.csv")
    parser.add_argument("--child", metavar="ENV", help="(internal) time one env, print JSON")
    parser.add_argument("--env", action="append", help="env id (repeatable; default: all)")
    parser.add_argument("--json", metavar="DIR", help="also keep each child's JSON there")
    parser.add_argument("--repeat", type=int, default=1, help="runs per env (default 1)")
    mode = parser.add_mutually_exclusive_group()
    mode.add_argument("--cold", dest="cold", action="store_true", default=True,
                      help="a fresh NUMBA_CACHE_DIR per env and run (the default)")  # fmt: skip
    mode.add_argument("--warm", dest="cold", action="store_false",
                      help="one cache folder per env, filled by a first untimed run")  # fmt: skip
    args = parser.parse_args(argv)
    if args.child:
        print(json.dumps(child(args.child)))
        return
    envs = args.env or (ENVS[:1] if args.quick else ENVS)
    machine = [  # not common.describe(): its parallel probe compiles a step kernel here
        f"{platform.machine()}, os.cpu_count: {os.cpu_count()}, python "
        f"{platform.python_version()}, numba {numba.__version__}",
        load_average("start"),
    ]
    print("\n".join(machine), flush=True)
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_compile_") as tmp:
        warm_dirs = {}
        if not args.cold:
            for env in envs:
                warm_dirs[env] = tempfile.mkdtemp(dir=tmp)
                run_child(env, warm_dirs[env])
        for run in range(args.repeat):
            for env in envs:  # in turn, so that a change of load hits every env alike
                cache = tempfile.mkdtemp(dir=tmp) if args.cold else warm_dirs[env]
                res = run_child(env, cache)
                if args.json:
                    os.makedirs(args.json, exist_ok=True)
                    name = f"{env.split('/')[-1]}-{run}.json"
                    with open(os.path.join(args.json, name), "w") as f:
                        json.dump(res, f, indent=1)
                got = rows_of(res, run)
                rows += got
                for r in got[:8]:
                    print(f"{r[0]:28s} {r[1]} {r[2]:24s} {r[3]:8.2f}  {r[4]}", flush=True)
                for r in got[8:40]:
                    print(f"{'':28s}   {r[2]:48s} {r[3]:7.2f}  {r[4]}", flush=True)
    notes = [*machine, f"mode: {'cold' if args.cold else 'warm'}", load_average()]
    path = write_csv(args.out, COLUMNS, rows, notes)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
