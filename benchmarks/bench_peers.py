"""Throughput against peers, side by side in one run on this machine (issue 8).

Measured, in one process (the peers in child processes), and written to
``docs/bench_peers.csv`` (the machine first, as ``#`` lines), ``docs/bench_peers.png`` and
``docs/bench_peers.md`` (the tables and their reading, built from that CSV only):

1. ``vector``: env-steps/s (one action of one sub-env) of our three vector envs
   (``gym.make_vec(id, num_envs=n, vectorization_mode="vector_entry_point")``) at
   n = 1, 64, 1024, 4096 with 1 and 2 numba threads (``numba.set_num_threads``), and of
   gymnasium's CartPole vector env (an almost empty env: the cost of the Gymnasium API itself;
   numpy, one thread). The two thread counts of one (env, n) are timed alternately on one
   vector env, random actions drawn beforehand, autoresets inside the timed loop; best of the
   repeats. Per core = rate / threads used, where threads used is 1 unless the simulator runs
   its parallel kernel (it does from 1024 bodies on). ``single``: the same for one env made
   with ``gym.make`` (``bench_envs.single_rate``), the peers' way of running.
2. ``peer``: PyFlyt 0.29.0's fixed-wing env ``PyFlyt/Fixedwing-Waypoints-v3`` (env-steps/s,
   one env per process; its resets, on crashes under random actions, are timed too) and
   JSBSim 1.3.3's flight model (the c172x trimmed in level flight, ``FGFDMExec.run()`` steps/s).
   Both need packages that must not enter our environment (PyFlyt needs numpy < 2 and
   pybullet), so they run in ``benchmarks/.peers-venv`` (made by ``--setup``) through
   ``benchmarks/peers_child.py``. Each row also has the simulated seconds of one step and the
   simulated seconds per wall-clock second (real-time factor), since the step lengths differ.
3. ``flops`` / ``peak`` / ``kernel``: the flops of one paper-airplane body-step counted from
   ``physics/kernels.py`` and ``physics/forces.py`` (``FLOP_COUNT`` below, rule in the md),
   the machine's floating-point peak (a numba kernel of independent fused multiply-adds,
   vectorized, several accumulators, float32 and float64, 1 and 2 threads, best of many short
   calls) and the step kernel's body-steps/s at E = 16384 (serial on 1 thread, parallel on 2),
   timed alternately with the peak kernel; achieved flop/s = body-steps/s x flops per
   body-step, and its share of the peak.

Rerun (the first line once per machine: it makes the peers' venv):

    python -m benchmarks.bench_peers --setup      # python3 -m venv + pip install, pinned
    python -m benchmarks.bench_peers [--quick]    # ~5 min (--quick: under 2)
    python -m benchmarks.bench_peers --md-only    # rebuild the md and png from the CSV

Timings are disturbed by anything else running on the machine; everything compared is
measured in the same run, and the ratios matter more than the absolute numbers.
"""

from __future__ import annotations

import json
import os
import subprocess
import time
from pathlib import Path

import gymnasium as gym
import numba
import numpy as np
from numba import njit, prange

import fluidsim_envs  # noqa: F401  (registers the envs)
from benchmarks.bench_envs import actions_for, single_rate, stepping
from benchmarks.bench_kernel import DT as KERNEL_DT
from benchmarks.bench_kernel import make_sim, timed_call
from benchmarks.common import (
    DOCS,
    ROOT,
    arguments,
    describe,
    interleaved_best,
    prose,
    rate_over,
    read_csv,
    sized,
    timed,
    write_csv,
)
from fluidsim_envs.physics import Craft, Ground, World
from fluidsim_envs.physics.kernels import EVALS_PER_STEP
from fluidsim_envs.scenes.paper_airplane.env import PaperAirplaneParams

HERE = Path(__file__).resolve().parent
PEERS_VENV = HERE / ".peers-venv"
PEERS_PYTHON = PEERS_VENV / "bin" / "python"
# what --setup installs: the two peers pinned, and the versions of what they need that this
# study ran with (PyFlyt 0.29.0 pins numpy < 2)
PEERS_PACKAGES = (
    "PyFlyt==0.29.0",
    "jsbsim==1.3.3",
    "pybullet==3.2.7",
    "numpy==1.26.4",
    "gymnasium==1.4.0",
)
PEERS = ("pyflyt", "jsbsim")

OURS = ("fluidsim/PaperAirplane-v0", "fluidsim/SubmarineWake-v0", "fluidsim/BoatOnStep-v0")
CARTPOLE = "CartPole-v1"
NUM_ENVS = (1, 64, 1024, 4096)
THREADS = (1, 2)
KERNEL_E = 16384
ENV_DTYPE = "float64"  # the envs' default physics dtype
FLOOR = dict(restitution=0.5, friction=0.5)  # PaperAirplane-v0's Ground
COLUMNS = (
    "section",
    "subject",
    "dtype",
    "num_envs",
    "numba_threads",
    "threads_used",
    "value",
    "unit",
    "per_core",
    "step_s",
    "sim_s_per_wall_s_per_core",
    "note",
)

# Flops of one body-step of the paper airplane (symplectic Euler, World(): air only, no wake,
# no swell), counted from the source of kernels._evaluate / _symplectic_euler and forces.py. Rule:
# +, -, *, / and sqrt count 1 each; min, max, negation, loads, stores and copies count 0;
# a fused multiply-add counts 2 (its multiply and its add, as written); an operation on
# values that are the same for every body of the loop (hoisted by the compiler: HALF * h,
# rho_water - rho_air, 1/m) counts 0. Each entry: (part, per, flops, what it is made of).
FLOP_COUNT = (
    (
        "plate",
        "sample",
        114,
        "offset to world 15, normal to world 15, v - v_air 3, _flow 24 (water fraction 4, "
        "density 2, v + w x r - frac du 18), plate_force 42 (speed_clamp 8, v.n 5, k 5, c 2, "
        "components 12, clamp_force 10), _add_force 15 (force 3, r x F and sum 12)",
    ),
    (
        "control plate",
        "sample",
        114,
        "as a plate, its normal the per-env deflected one (the deflection, cos/sin and "
        "Rodrigues, runs once per sim.step call, not per step: not counted)",
    ),
    (
        "cylinder",
        "sample",
        115,
        "offset 15, axis 15, v - v_air 3, _flow 24, cylinder_force 43 (speed_clamp 8, v.a 5, "
        "v_perp 6, |v_perp| 6, k 5, components 3, clamp_force 10), _add_force 15",
    ),
    (
        "buoyancy",
        "sample",
        38,
        "offset 15, height 1, water_fraction 3, buoyancy_force 4, _add_force 15 (as written, "
        "with zero x and y force); the paper airplane has none",
    ),
    (
        "rotation",
        "body",
        330,
        "_omega_row 92 (quat_to_matrix 47, world_omega 45), quat_rate 24, _rotate_by_omega "
        "214 (world_omega 45, _midpoint_turn 156, _normalize_quat 13)",
    ),
    (
        "integration",
        "body",
        29,
        "external force 6, F/m and gravity 4, kick (v, L) 12, drift (x) 6, clock 1",
    ),
)


# --------------------------------------------------------------------------------------------
# the peers' venv


def setup() -> None:
    """Make ``benchmarks/.peers-venv`` with the peers, pinned (never our own venv)."""
    if not PEERS_PYTHON.exists():
        subprocess.run(["python3", "-m", "venv", str(PEERS_VENV)], check=True)
    pip = [str(PEERS_PYTHON), "-m", "pip", "install", "--disable-pip-version-check"]
    subprocess.run([*pip, "--upgrade", "pip"], check=True)
    subprocess.run([*pip, *PEERS_PACKAGES], check=True)
    print(f"peers installed in {PEERS_VENV}")


def run_peer(peer: str, seconds: float, repeats: int) -> dict:
    """Run ``peers_child.py`` for one peer in the peers' venv; its result, or why not."""
    if not PEERS_PYTHON.exists():
        return {"error": f"no {PEERS_VENV.relative_to(ROOT)}: run with --setup first"}
    cmd = [str(PEERS_PYTHON), str(HERE / "peers_child.py"), peer, str(seconds), str(repeats)]
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)
    except subprocess.TimeoutExpired:
        return {"error": "timed out after 300 s"}
    for line in out.stdout.splitlines():
        if line.startswith("RESULT "):
            return json.loads(line[len("RESULT ") :])
    tail = (out.stderr or out.stdout).strip().splitlines()[-3:]
    return {"error": f"exit {out.returncode}: " + " | ".join(tail)}


# --------------------------------------------------------------------------------------------
# vector envs


def step_period(venv) -> float:
    """Simulated seconds of one env-step (one action)."""
    inner = venv.unwrapped
    if hasattr(inner, "params"):
        return float(inner.params.dt * inner.params.substeps)
    return float(inner.tau)  # CartPole


def vector_rates(env_id: str, num_envs: int, threads, seconds: float, repeats: int) -> dict:
    """Best env-steps/s for each numba thread count, timed alternately on one vector env;
    also the threads the step actually uses and the step's simulated seconds."""
    venv = gym.make_vec(env_id, num_envs=num_envs, vectorization_mode="vector_entry_point")
    acts = actions_for(venv.action_space, 16, np.random.default_rng(0))
    venv.reset(seed=0)
    sim = getattr(venv.unwrapped, "sim", None)
    parallel = bool(sim is not None and sim.parallel)
    run = stepping(venv, acts)
    for t in threads:  # warm-up: compile or load from the cache, start the threads
        numba.set_num_threads(t)
        run()
    rate = dict.fromkeys(threads, lambda: rate_over(run, seconds))
    best = interleaved_best(rate, repeats, best=max, before=numba.set_num_threads)
    period = step_period(venv)
    venv.close()
    return {t: {"rate": r, "used": t if parallel else 1, "step_s": period} for t, r in best.items()}


# --------------------------------------------------------------------------------------------
# the floating-point peak and the kernel's share of it

CHAINS, DEPTH, LANES = 8, 16, 64  # independent accumulators x FMAs each x vectorized lanes
FLOPS_PER_REP = 2 * CHAINS * DEPTH * LANES  # per thread and repetition


def _peak_kernel():
    """``fma(x, m, c, reps)``: each of ``x.shape[0]`` threads runs, ``reps`` times over 64
    lanes (the loop the compiler vectorizes), 8 independent chains of 16 ``a = a * m + c``
    written out (fused by the ``contract`` flag), so that the FMA units never wait."""
    body = [
        "def fma(x, m, c, reps):",
        "    for t in prange(x.shape[0]):",
        "        for _ in range(reps):",
        f"            for i in range({LANES}):",
    ]
    body += [f"                a{k} = x[t, {k}, i]" for k in range(CHAINS)]
    body += [f"                a{k} = a{k} * m + c" for _ in range(DEPTH) for k in range(CHAINS)]
    body += [f"                x[t, {k}, i] = a{k}" for k in range(CHAINS)]
    scope = {"prange": prange}
    exec("\n".join(body), scope)  # noqa: S102  (generated straight-line code, no input)
    return njit(parallel=True, error_model="numpy", fastmath={"contract"})(scope["fma"])


def peak_and_kernel(target_s: float, repeats: int) -> list[dict]:
    """Peak flop/s of the FMA kernel and body-steps/s of the paper airplane's step kernel at
    E = 16384, float32 and float64, 1 thread (serial kernel) and 2 (parallel), each the best
    of ``repeats`` calls of about ``target_s``, all configurations timed in turn per repeat."""
    fma = _peak_kernel()
    jobs = []
    for dtype in ("float32", "float64"):
        for threads in THREADS:
            numba.set_num_threads(threads)
            x = np.ones((threads, CHAINS, LANES), dtype=dtype)
            m, c = x.dtype.type(0.999), x.dtype.type(0.001)  # a -> 1: stays finite
            fma(x, m, c, 1)  # compile
            reps = sized(lambda n, x=x, m=m, c=c: fma(x, m, c, n), target_s, probe=1000)

            def peak_call(x=x, m=m, c=c, reps=reps):
                return timed(lambda: fma(x, m, c, reps))

            work = FLOPS_PER_REP * reps * threads
            jobs.append(("peak", "fma", dtype, 0, threads, peak_call, work))

            kind = "parallel" if threads > 1 else "serial"
            sim, controls = make_sim(KERNEL_E, dtype, kind)
            timed_call(sim, controls, 1)  # warm-up
            steps = max(1, round(target_s / timed_call(sim, controls, 10) * 10))

            def kernel_call(sim=sim, controls=controls, steps=steps):
                return timed_call(sim, controls, steps)

            work = KERNEL_E * steps
            jobs.append(("kernel", "paper_airplane", dtype, KERNEL_E, threads, kernel_call, work))
            if dtype != ENV_DTYPE:
                continue
            # the same over PaperAirplane-v0's floor: contact runs per env and step
            sim, controls = make_sim(KERNEL_E, dtype, kind, world=World(ground=Ground(**FLOOR)))
            timed_call(sim, controls, 1)
            steps = max(1, round(target_s / timed_call(sim, controls, 10) * 10))

            def floor_call(sim=sim, controls=controls, steps=steps):
                return timed_call(sim, controls, steps)

            work = KERNEL_E * steps
            jobs.append(
                ("kernel", "paper_airplane+floor", dtype, KERNEL_E, threads, floor_call, work)
            )
    best = interleaved_best(
        dict(enumerate(job[5] for job in jobs)),
        repeats,
        before=lambda j: numba.set_num_threads(jobs[j][4]),
    )
    rows = []
    for (section, subject, dtype, n, threads, _, work), t in zip(jobs, best.values(), strict=True):
        unit = "flop/s" if section == "peak" else "body-steps/s"
        rows.append(
            dict(
                section=section,
                subject=subject,
                dtype=dtype,
                num_envs=n,
                numba_threads=threads,
                threads_used=threads,
                value=work / t,
                unit=unit,
                per_core=work / t / threads,
            )
        )
    return rows


_PA = PaperAirplaneParams()
# the env's physics per action, in words: "4 rk2 steps of 1/120 s (8 force evaluations)"
PA_STEPS = (
    f"{_PA.substeps} {_PA.integrator} steps of 1/{round(1 / _PA.dt)} s "
    f"({_PA.substeps * EVALS_PER_STEP[_PA.integrator]} force evaluations of a 13-sample body)"
)


def flops_per_body_step(craft_name: str = "paper_airplane") -> tuple[int, dict]:
    """The craft's flops per body-step from ``FLOP_COUNT``, and its samples of each kind."""
    craft = Craft.load(craft_name)
    counts = {
        "plate": sum(p.hinge_axis is None for p in craft.plates),
        "control plate": sum(p.hinge_axis is not None for p in craft.plates),
        "cylinder": len(craft.cylinders),
        "buoyancy": len(craft.buoyancy),
        "rotation": 1,
        "integration": 1,
    }
    if craft.thrusters:
        raise ValueError(f"{craft_name}: thrusters are not in FLOP_COUNT")
    return sum(counts[part] * f for part, _, f, _ in FLOP_COUNT), counts


# --------------------------------------------------------------------------------------------
# the CSV, the chart and the md


def cell(row: dict, k: str):
    x = row.get(k, "")
    if k in ("value", "per_core", "sim_s_per_wall_s_per_core") and isinstance(x, float):
        return f"{x:.6g}"
    return x


def read_rows(path: Path) -> tuple[list[str], list[dict]]:
    machine, rows = read_csv(path)
    for row in rows:
        for k in ("value", "per_core", "step_s", "sim_s_per_wall_s_per_core"):
            row[k] = float(row[k]) if row[k] not in ("", None) else None
        for k in ("num_envs", "numba_threads", "threads_used"):
            row[k] = int(row[k]) if row[k] not in ("", None) else None
    return machine, rows


def short(env_id: str) -> str:
    return env_id.split("/")[-1]


def plot(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    colors = dict(zip((*OURS, CARTPOLE), ("C0", "C1", "C2", "C7"), strict=True))
    vec = [r for r in rows if r["section"] == "vector"]
    for env_id in (*OURS, CARTPOLE):
        for t in THREADS:
            sel = [r for r in vec if r["subject"] == env_id and r["numba_threads"] == t]
            if not sel:
                continue
            n = [r["num_envs"] for r in sel]
            style = dict(color=colors[env_id], ls="-" if t == 1 else "--", marker="o")
            label = f"{short(env_id)}, {t} thread{'s' * (t > 1)}"
            axes[0].plot(n, [r["per_core"] for r in sel], label=label, **style)
            axes[1].plot(n, [r["sim_s_per_wall_s_per_core"] for r in sel], label=label, **style)
    peers = [r for r in rows if r["section"] == "peer" and r["note"] != "steps only"]
    for r, color in zip(peers, ("C3", "C4"), strict=False):
        label = f"{r['subject']} ({r['unit'].split('/')[0]}, 1 process)"
        if r["unit"] == "env-steps/s":
            axes[0].axhline(r["per_core"], color=color, ls=":", label=label)
        axes[1].axhline(r["sim_s_per_wall_s_per_core"], color=color, ls=":", label=label)
    axes[0].set_ylabel("env-steps per second per core")
    axes[1].set_ylabel("simulated seconds per wall second per core")
    for ax in axes:
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("num_envs (one vector env)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_title("Env-steps per core (solid: 1 numba thread, dashed: 2)")
    axes[1].set_title("Real-time factor per core")
    axes[1].legend(fontsize=7, loc="lower right", handlelength=3.5)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(f"wrote {path}")


def fmt(x: float) -> str:
    if x >= 100:
        return f"{x:,.0f}"
    return f"{x:.3g}"


def rfmt(x: float) -> str:
    """A ratio: two significant digits, at least one decimal below 10."""
    return f"{x:.2f}" if x < 1 else f"{x:.1f}" if x < 10 else f"{x:,.0f}"


def page(path: Path | None = None) -> str:
    """docs/bench_peers.md from the CSV at ``path`` (default docs/bench_peers.csv) alone:
    ``python -m benchmarks.report --check`` compares the page with it."""
    path = DOCS / "bench_peers.csv" if path is None else path
    if not path.is_file():
        return "(no docs/bench_peers.csv yet: run python -m benchmarks.bench_peers)\n"
    machine, rows = read_rows(path)
    return markdown(machine, rows, path.name)


def summary_markdown(path: Path | None = None) -> str:
    """docs/benchmarks.md's paragraph on the peers, from the CSV at ``path`` (default
    docs/bench_peers.csv): our vector envs per core at the largest batch on one thread, the
    peers, the real-time factors and the kernel's share of the measured peak."""
    path = DOCS / "bench_peers.csv" if path is None else path
    if not path.is_file():
        return "(no docs/bench_peers.csv yet: run python -m benchmarks.bench_peers)"
    _, rows = read_rows(path)
    n = NUM_ENVS[-1]
    ours = {
        r["subject"]: r
        for r in rows
        if r["section"] == "vector" and r["subject"] in OURS
        and r["num_envs"] == n and r["numba_threads"] == 1
    }  # fmt: skip
    peer = {r["subject"]: r for r in rows if r["section"] == "peer" and r["note"] != "steps only"}
    flops = next(r["value"] for r in rows if r["section"] == "flops" and r["subject"] == "total")
    get = {(r["section"], r["subject"], r["dtype"], r["numba_threads"]): r["value"] for r in rows}
    shares = []
    for dtype in ("float32", "float64"):
        one = get[("peak", "fma", dtype, 1)]
        for t in THREADS:
            peak = max(get[("peak", "fma", dtype, t)], t * one)
            shares.append(get[("kernel", "paper_airplane", dtype, t)] * flops / peak)
    rates = sorted(r["per_core"] for r in ours.values())
    dart = ours[OURS[0]]
    pyflyt, jsbsim = peer["pyflyt"], peer["jsbsim"]
    return prose(
        f"Per core, our vector envs run {rates[0] / 1e3:.0f}-{rates[-1] / 1e3:.0f}k env-steps/s "
        f"at {n} envs on one thread, PyFlyt's fixed-wing env {pyflyt['per_core']:,.0f} and "
        f"JSBSim's c172x {jsbsim['per_core'] / 1e3:.0f}k FDM steps "
        f"({jsbsim['sim_s_per_wall_s_per_core']:,.0f} simulated seconds per wall second, "
        f"against the paper airplane's {dart['sim_s_per_wall_s_per_core']:,.0f}), and the dart's "
        f"kernel reaches {100 * min(shares):.0f}-{100 * max(shares):.0f}% of the measured "
        f"floating-point peak ({flops:,.0f} flops per symplectic Euler body-step)."
    )


def write_md(machine: list[str], rows: list[dict], path: Path, csv_name: str) -> None:
    path.write_text(markdown(machine, rows, csv_name))
    print(f"wrote {path}")


def markdown(machine: list[str], rows: list[dict], csv_name: str) -> str:
    """The section file: what, how, the tables and their reading, from the CSV's rows."""
    get = {
        (r["section"], r["subject"], r["dtype"], r["num_envs"], r["numba_threads"], r["note"]): r
        for r in rows
    }
    vec = {
        (r["subject"], r["num_envs"], r["numba_threads"]): r
        for r in rows
        if r["section"] == "vector"
    }
    single = {r["subject"]: r for r in rows if r["section"] == "single"}
    peer_rows = [r for r in rows if r["section"] == "peer"]
    peers = {r["subject"]: r for r in peer_rows if r["note"] != "steps only"}
    peer_steps_only = {r["subject"]: r for r in peer_rows if r["note"] == "steps only"}
    flops = [r for r in rows if r["section"] == "flops"]
    total = next(r for r in flops if r["subject"] == "total")
    L = []
    L.append("## Throughput against peers")
    L.append("")
    L.append(
        f"Written by `python -m benchmarks.bench_peers` (`--quick` for a shorter run); numbers "
        f"from [{csv_name}]({csv_name}), [chart](bench_peers.png). One run on this machine (its "
        "load average at the start below: anything else running lowers the absolute rates, "
        "most the 2-thread rows); what is compared was measured side by side in that run."
    )
    L.append("")
    L.extend(f"    {line}" for line in machine)
    L.append("")
    L.append("### What and how")
    L.append("")
    L.append(
        "- **Env-steps per second** (one action of one sub-env): each vector env made with "
        '`gym.make_vec(id, num_envs=n, vectorization_mode="vector_entry_point")`, reset with a '
        "seed, stepped with random actions drawn beforehand; autoresets happen inside the timed "
        "loop, as in training. The 1- and 2-thread runs of one (env, n) alternate on one "
        "vector env (`numba.set_num_threads`); each figure is the best of the repeats. "
        "**Per core** = rate / threads used: 1, unless the simulator runs its parallel kernel "
        "(from 1024 bodies on), then the numba thread count. CartPole-v1 is gymnasium's own "
        "vector env (numpy, one thread): four numbers of state, so its rate is close to what "
        "the Gymnasium API itself costs."
    )
    L.append(
        "- **Peers**, one env per process (they are single-threaded, so their rate is their "
        "rate per core), run in child processes from `benchmarks/.peers-venv` (made by "
        "`--setup`: PyFlyt needs numpy < 2 and pybullet, which must not enter our environment). "
        "PyFlyt: `PyFlyt/Fixedwing-Waypoints-v3`, the fixed-wing id that 0.29.0 registers, "
        "random actions, its resets (a crash or leaving the dome ends an episode within a few "
        "seconds of random flying) inside the timed loop; JSBSim: the c172x it ships, at "
        "3000 ft and 100 kt, engine running, trimmed in level flight (`do_trim(1)`), then "
        "`FGFDMExec.run()` in a loop (no gymnasium env: FDM steps). "
        "**Real-time factor** = steps/s x simulated seconds per step, per core: the step "
        "lengths differ (table below)."
    )
    L.append("")
    L.append("### Our envs and CartPole: env-steps per second per core")
    L.append("")
    L.append(
        "Ratio: per core over CartPole-v1's per core at the same num_envs. Threads used in "
        "brackets where it differs from the numba thread count."
    )
    L.append("")
    head = "| env | step (s) | numba threads |" + "".join(f" n = {n} |" for n in NUM_ENVS)
    L.append(head)
    L.append("|---|---:|---:|" + "---:|" * len(NUM_ENVS))
    for env_id in (*OURS, CARTPOLE):
        for t in THREADS:
            if (env_id, NUM_ENVS[0], t) not in vec:
                continue
            cells = []
            for n in NUM_ENVS:
                r = vec[(env_id, n, t)]
                cp = vec[(CARTPOLE, n, 1)]["per_core"]
                used = "" if r["threads_used"] == t else f" [{r['threads_used']}]"
                ratio = "" if env_id == CARTPOLE else f" (x{r['per_core'] / cp:.3g})"
                cells.append(f" {fmt(r['per_core'])}{used}{ratio} |")
            step = vec[(env_id, NUM_ENVS[0], t)]["step_s"]
            L.append(f"| {short(env_id)} | {step:.4g} | {t} |" + "".join(cells))
    L.append("")

    def best_vec(env_id):
        return max((r for k, r in vec.items() if k[0] == env_id), key=lambda r: r["per_core"])

    L.append("### Peers: per core, step lengths and real-time factors")
    L.append("")
    L.append("| simulator | run | steps/s per core | step (s) | simulated s per wall s per core |")
    L.append("|---|---|---:|---:|---:|")
    for env_id in (*OURS, CARTPOLE):
        b = best_vec(env_id)
        L.append(
            f"| {short(env_id)} | vector, best: n = {b['num_envs']}, "
            f"{b['numba_threads']} thread(s) | {fmt(b['per_core'])} | {b['step_s']:.4g} | "
            f"{fmt(b['sim_s_per_wall_s_per_core'])} |"
        )
        if env_id in single:
            s = single[env_id]
            L.append(
                f"| {short(env_id)} | single env (`gym.make`) | {fmt(s['per_core'])} | "
                f"{s['step_s']:.4g} | {fmt(s['sim_s_per_wall_s_per_core'])} |"
            )
    for name, r in peers.items():
        if r["value"] is None:
            L.append(f"| {name} | could not run: {r['note']} | | | |")
            continue
        L.append(
            f"| {name} | {r['note']} | {fmt(r['per_core'])} ({r['unit']}) | "
            f"{r['step_s']:.4g} | {fmt(r['sim_s_per_wall_s_per_core'])} |"
        )
        if name in peer_steps_only:
            s = peer_steps_only[name]
            L.append(
                f"| {name} | the same, time in resets left out | {fmt(s['per_core'])} | "
                f"{s['step_s']:.4g} | {fmt(s['sim_s_per_wall_s_per_core'])} |"
            )
    L.append("")

    L.append("### Flops per body-step and the share of the machine's peak")
    L.append("")
    L.append(
        "Counted by reading `_evaluate`, `_symplectic_euler` and the helpers they "
        "inline in `physics/kernels.py`, `physics/rotation.py` and `physics/forces.py`, for "
        "`World()` (air only: no wake, no swell, calm). Rule: +, -, *, / and sqrt count 1 "
        "each; min, max, negation, loads and stores 0; a fused multiply-add 2 (the source's "
        "multiply and add); operations on values that are the same for every body of a loop "
        "(`HALF * h`, `rho_water - rho_air`, `1/m`, hoisted by the compiler) 0. The count is "
        "of the source as written: the compiler may share a few repeated products (squares "
        "of the quaternion in `quat_to_matrix`), and the min/max/compare instructions of the "
        "clamps cost issue slots without counting as flops."
    )
    L.append("")
    L.append("| part | per | flops | made of | paper airplane has |")
    L.append("|---|---|---:|---|---:|")
    for r in flops:
        if r["subject"] == "total":
            continue
        per, count, made_of = r["note"].split(";", 2)
        made_of = made_of.strip().replace("|", "\\|")  # |v_perp| inside a table cell
        L.append(f"| {r['subject']} | {per} | {fmt(r['value'])} | {made_of} | {count} |")
    L.append(f"| **paper airplane, one body-step** | | **{fmt(total['value'])}** | | |")
    L.append("")
    L.append(
        f"Peak: a numba kernel of independent fused multiply-adds (8 accumulator chains of 16 "
        f"FMAs written out, vectorized over 64 lanes, 2 flops per FMA). Kernel: "
        f"`Simulator(Craft.load('paper_airplane'), World(), num_envs={KERNEL_E}, "
        f"dt={KERNEL_DT:.6g}, dtype=...)`, `sim.step(controls, steps=k)` from a glide; the "
        "serial kernel on 1 thread, the parallel one on 2. Peak and kernel calls of about "
        "0.1 s alternate, best of the repeats. With another job on the machine the 2-thread "
        "peak can come out below twice the 1-thread one (a busy second core): the share "
        "on 2 threads is taken of the larger of the two, the measured 2-thread peak and "
        "twice the 1-thread peak, so that a busy core does not flatter it."
    )
    L.append("")
    L.append(
        "| dtype | threads | peak measured (GFLOP/s) | peak used (GFLOP/s) | "
        "kernel (M body-steps/s) | kernel (GFLOP/s) | share of peak |"
    )
    L.append("|---|---:|---:|---:|---:|---:|---:|")
    shares = {}
    for dtype in ("float32", "float64"):
        one = get[("peak", "fma", dtype, 0, 1, "")]["value"]
        for t in THREADS:
            p = get[("peak", "fma", dtype, 0, t, "")]["value"]
            peak = max(p, t * one)
            k = get[("kernel", "paper_airplane", dtype, KERNEL_E, t, "")]
            achieved = k["value"] * total["value"]
            shares[(dtype, t)] = achieved / peak
            L.append(
                f"| {dtype} | {t} | {p / 1e9:.1f} | {peak / 1e9:.1f} | {k['value'] / 1e6:.1f} | "
                f"{achieved / 1e9:.1f} | {100 * achieved / peak:.0f}% |"
            )
    L.append("")
    floor = {
        t: get[("kernel", "paper_airplane+floor", ENV_DTYPE, KERNEL_E, t, "")]["value"]
        for t in THREADS
    }
    bare = {
        t: get[("kernel", "paper_airplane", ENV_DTYPE, KERNEL_E, t, "")]["value"] for t in THREADS
    }
    L.append(
        f"The same kernel over PaperAirplane-v0's floor (`World(ground=Ground(restitution=0.5, "
        f"friction=0.5))`, {ENV_DTYPE}, as the env runs it): "
        + ", ".join(
            f"{floor[t] / 1e6:.2f} M body-steps/s on {t} thread{'s' * (t > 1)} "
            f"(x{bare[t] / floor[t]:.1f} slower than without the floor)"
            for t in THREADS
        )
        + ". Contact runs as scalar code per environment after every step (kernels.py), "
        f"{100 * (1 - floor[1] / bare[1]):.0f}% of the step's time on 1 thread (an "
        "environment with nothing near the floor skips it after a distance test; a glide "
        "that lands pays for it while it slides and rests)."
    )
    L.append("")

    # the reading: every number here comes from the rows above
    pa, cp = "fluidsim/PaperAirplane-v0", CARTPOLE
    pa1, cp1 = vec[(pa, 1, 1)], vec[(cp, 1, 1)]
    pab, cpb = best_vec(pa), best_vec(cp)
    L.append("### Reading")
    L.append("")
    L.append(
        f"- **Against CartPole.** At one env our paper airplane's vector env does "
        f"{fmt(pa1['per_core'])} env-steps/s and CartPole's {fmt(cp1['per_core'])}: at small "
        "batches both are dominated by the per-call cost of Python and the Gymnasium API, not "
        f"by physics. With the batch, CartPole (no physics: a few numpy operations on "
        f"[n] arrays) grows to {fmt(cpb['per_core'])} per core at n = {cpb['num_envs']}; the "
        f"paper airplane to {fmt(pab['per_core'])} per core (n = {pab['num_envs']}, "
        f"{pab['numba_threads']} numba thread(s)), x{pab['per_core'] / cpb['per_core']:.2g} "
        f"of CartPole's best, for {PA_STEPS} in each "
        "env-step (CartPole: one Euler step of four numbers), and PaperAirplane-v0's step "
        "also runs contact with its floor (below). Per simulated "
        "second the "
        f"airplane does {fmt(pab['sim_s_per_wall_s_per_core'])} s per wall second per core, "
        f"CartPole {fmt(cpb['sim_s_per_wall_s_per_core'])}."
    )
    two = [
        (e, n, vec[(e, n, 2)]["value"] / vec[(e, n, 1)]["value"])
        for e in OURS
        for n in NUM_ENVS
        if n >= 1024 and vec[(e, n, 2)]["threads_used"] == 2
    ]
    k2 = {
        d: get[("kernel", "paper_airplane", d, KERNEL_E, 2, "")]["value"]
        / get[("kernel", "paper_airplane", d, KERNEL_E, 1, "")]["value"]
        for d in ("float32", "float64")
    }
    text = (
        "- **Threads.** Below 1024 bodies the simulator runs its serial kernel, so a second "
        "numba thread changes nothing there (the same code: the 1- and 2-thread figures differ "
        "by noise only). From 1024 bodies the parallel kernel runs the physics on 2 threads, "
        "while the env's own Python and numpy work (observations, rewards, resets) stays on "
        "one. In this run the 2-thread rate over the 1-thread rate (totals, not per core) was "
        + ", ".join(f"x{q:.2f} ({short(e)}, n = {n})" for e, n, q in two)
        + f"; for the bare kernel at E = {KERNEL_E}: x{k2['float32']:.2f} (float32), "
        f"x{k2['float64']:.2f} (float64)."
    )
    if min(q for *_, q in two) < 1.0 or min(k2.values()) < 1.0:
        best2 = max(max(q for *_, q in two), *k2.values())
        text += (
            " Below x1, 2 threads did less than 1, which an idle machine would not give: the "
            "other job kept one of the two cores busy, more at some moments than at others "
            f"(the best of these ratios, timed minutes apart, is x{best2:.2f}), and the "
            "parallel kernel splits the blocks evenly, so a call waits for the thread that "
            "shares its core. These rows show what a second thread gave on a shared machine, "
            "not how the code scales on an idle one (the README's kernel table comes from a "
            "quieter run)."
        )
    L.append(text)
    pf = peers.get("pyflyt")
    if pf and pf["value"] is not None:
        pfs = peer_steps_only.get("pyflyt", pf)
        ps = single.get(pa)
        L.append(
            f"- **PyFlyt** steps its fixed-wing at {fmt(pf['per_core'])} env-steps/s per "
            f"core with its resets ({fmt(pfs['per_core'])} without them), with the same "
            f"action period as our paper airplane ({pf['step_s']:.4g} s: 8 physics steps of "
            f"1/240 s in PyFlyt, {PA_STEPS} in ours). Our paper airplane is "
            f"x{ps['per_core'] / pf['per_core']:.0f} "
            f"faster as one `gym.make` env (the same way of running) and "
            f"x{pab['per_core'] / pf['per_core']:,.0f} faster per core as a vector env. "
            "PyFlyt steps pybullet (a general rigid-body engine with collision detection, "
            "loading a URDF model) and computes its five lifting surfaces' forces in Python "
            "and numpy at every physics step; ours is one compiled call per action for 13 "
            "flat-plate samples. The single-env ratio shows that the gap is not only "
            "batching; the two models differ (PyFlyt's surfaces have lift slopes, stall "
            "angles and drag coefficients; ours are flat plates), so this compares speed, not "
            "fidelity."
        )
    js = peers.get("jsbsim")
    if js and js["value"] is not None:
        rtf_js = js["sim_s_per_wall_s_per_core"]
        rtf_vec, rtf_one = pab["sim_s_per_wall_s_per_core"], single[pa]["sim_s_per_wall_s_per_core"]
        L.append(
            f"- **JSBSim** runs the c172x at {fmt(js['per_core'])} FDM steps/s per core "
            f"(steps of {js['step_s']:.4g} s): {fmt(js['sim_s_per_wall_s_per_core'])} "
            "simulated seconds per wall second, a complete aircraft model (tables of "
            "aerodynamic coefficients, engine and propeller, landing gear, atmosphere, flight "
            "control system) in C++, one aircraft per call. Our paper airplane does "
            f"{fmt(rtf_vec)} simulated seconds per wall second per core as a vector env "
            f"(x{rfmt(rtf_vec / rtf_js)}) and {fmt(rtf_one)} as one `gym.make` env "
            f"(x{rfmt(rtf_one / rtf_js)}), "
            "where one env pays the Gymnasium API per action and JSBSim has no such layer "
            "(there is no gymnasium env in the jsbsim package)."
        )
    f32, f64 = shares[("float32", 2)], shares[("float64", 2)]
    L.append(
        f"- **Share of the peak.** At E = {KERNEL_E} on 2 threads the step kernel reaches "
        f"{100 * f32:.0f}% of the measured FMA peak in float32 and {100 * f64:.0f}% in float64 "
        f"(1 thread: {100 * shares[('float32', 1)]:.0f}% and {100 * shares[('float64', 1)]:.0f}%"
        "). "
        + (
            "The 2-thread shares are low mostly because the kernel's second thread shared "
            "its core with other work (see Threads); the 1-thread shares are the kernel's own. "
            if f32 < 0.8 * shares[("float32", 1)] or f64 < 0.8 * shares[("float64", 1)]
            else "The kernel keeps its share on 2 threads: it scales with the cores. "
        )
        + "The peak is every floating-point instruction an FMA (2 flops). The kernel's "
        "mix is not: counted by hand from the source, assuming the compiler fuses every "
        "multiply that feeds an add, a plate's 114 flops take about 83 vector instructions "
        "(1.4 flops each), two of them divisions and two square roots (slower units), beside "
        "the min/max of the clamps (instructions that count no flops) and the loads and "
        "stores of the scratch rows (about 20 rows read and 6 updated per sample). So even "
        "a perfectly scheduled kernel would stay well below the peak; how the rest of the gap "
        "divides between these causes was not measured here."
    )
    L.append("")
    return "\n".join(L) + "\n"


# --------------------------------------------------------------------------------------------


def main() -> None:
    parser = arguments(__doc__, "shorter, noisier runs", "bench_peers.csv")
    parser.add_argument("--setup", action="store_true", help="make the peers' venv and exit")
    parser.add_argument("--md-only", action="store_true", help="rebuild md and png from the CSV")
    args = parser.parse_args()
    png, md = args.out.with_suffix(".png"), args.out.with_suffix(".md")
    if args.setup:
        setup()
        return
    if args.md_only:
        machine, rows = read_rows(args.out)
        plot(rows, png)
        write_md(machine, rows, md, args.out.name)
        return
    # seconds per timed run and repeats: envs, peers, peak/kernel (calls of ~target s)
    if args.quick:
        seconds, repeats, peer_s, peer_rep, target_s, k_rep = 0.15, 2, 0.4, 2, 0.04, 6
    else:
        seconds, repeats, peer_s, peer_rep, target_s, k_rep = 1.0, 5, 2.0, 5, 0.1, 30
    t_start = time.perf_counter()
    machine = describe()
    rows: list[dict] = []

    for env_id in (*OURS, CARTPOLE):
        threads = THREADS if env_id != CARTPOLE else (1,)
        for n in NUM_ENVS:
            for t, r in vector_rates(env_id, n, threads, seconds, repeats).items():
                per_core = r["rate"] / r["used"]
                rows.append(
                    dict(
                        section="vector",
                        subject=env_id,
                        num_envs=n,
                        numba_threads=t,
                        threads_used=r["used"],
                        value=r["rate"],
                        unit="env-steps/s",
                        per_core=per_core,
                        step_s=r["step_s"],
                        sim_s_per_wall_s_per_core=per_core * r["step_s"],
                    )
                )
                print(
                    f"vector {short(env_id):18s} n={n:5d} threads={t} (used {r['used']}) "
                    f"{r['rate']:14,.0f} env-steps/s, {per_core:14,.0f} per core",
                    flush=True,
                )
    print(f"[{time.perf_counter() - t_start:.0f} s] single envs", flush=True)
    numba.set_num_threads(1)
    for env_id in (*OURS, CARTPOLE):
        rate = single_rate(env_id, seconds, repeats)
        env = gym.make(env_id)
        period = step_period(env)
        env.close()
        rows.append(
            dict(
                section="single",
                subject=env_id,
                num_envs=1,
                numba_threads=1,
                threads_used=1,
                value=rate,
                unit="env-steps/s",
                per_core=rate,
                step_s=period,
                sim_s_per_wall_s_per_core=rate * period,
                note="gym.make",
            )
        )
        print(f"single {short(env_id):18s} {rate:14,.0f} env-steps/s", flush=True)

    print(f"[{time.perf_counter() - t_start:.0f} s] peers", flush=True)
    for peer in PEERS:
        res = run_peer(peer, peer_s, peer_rep)
        if "error" in res:
            rows.append(dict(section="peer", subject=peer, note=res["error"]))
            print(f"peer {peer}: could not run: {res['error']}", flush=True)
            continue
        unit = "env-steps/s" if peer == "pyflyt" else "fdm-steps/s"
        what = f"{res['what']} ({peer} {res['version']}), 1 process"
        base = dict(
            section="peer",
            subject=peer,
            num_envs=1,
            numba_threads=1,
            threads_used=1,
            unit=unit,
            step_s=res["step_s"],
        )
        rows.append(
            dict(
                base,
                value=res["rate"],
                per_core=res["rate"],
                sim_s_per_wall_s_per_core=res["rate"] * res["step_s"],
                note=what,
            )
        )
        if "rate_steps_only" in res:
            rows.append(
                dict(
                    base,
                    value=res["rate_steps_only"],
                    per_core=res["rate_steps_only"],
                    sim_s_per_wall_s_per_core=res["rate_steps_only"] * res["step_s"],
                    note="steps only",
                )
            )
        print(f"peer {peer}: {json.dumps(res)}", flush=True)

    print(f"[{time.perf_counter() - t_start:.0f} s] peak and kernel", flush=True)
    flops, counts = flops_per_body_step()
    for part, per, f, made_of in FLOP_COUNT:
        rows.append(
            dict(
                section="flops",
                subject=part,
                value=float(f),
                unit="flop",
                note=f"{per};{counts[part]};{made_of}",
            )
        )
    rows.append(
        dict(
            section="flops",
            subject="total",
            value=float(flops),
            unit="flop",
            note="paper_airplane per body-step",
        )
    )
    for r in peak_and_kernel(target_s, k_rep):
        rows.append(r)
        print(
            f"{r['section']:6s} {r['dtype']} threads={r['numba_threads']} "
            f"{r['value']:14,.0f} {r['unit']}",
            flush=True,
        )
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)

    write_csv(args.out, COLUMNS, [[cell(r, k) for k in COLUMNS] for r in rows], machine)
    print(f"wrote {args.out}")
    machine, rows = read_rows(args.out)  # the md and the chart use the CSV's numbers only
    plot(rows, png)
    write_md(machine, rows, md, args.out.name)
    print(f"total {time.perf_counter() - t_start:.0f} s")


if __name__ == "__main__":
    main()
