"""The submarine's wake: where its time goes, and the table model's cost against its error
where SubmarineWake's UUV flies.

    python -m benchmarks.study_wake            # docs/study_wake.csv, study_wake_env.csv, .png
    python -m benchmarks.study_wake --quick    # a shorter, noisier run into build/study_quick

The points are where the UUV's seven wake-feeling samples (its plates and cylinders) are when
it holds station: the station box of SubmarineWake-v0's parameters (x in
``station_behind_m``, |y| in ``station_side_m`` to either side, z in ``station_up_m``, in
the lead's frame; the lead's stern is at x = -20 m), the UUV level, within
``start_heading_deg`` of the lead's heading (region ``station``), and the same box grown by
``start_error_m`` on each axis, where episodes start (region ``start``). The lead moves
along its x at 2 m/s through still water, its turbulence shifted by a random offset; every
error is the length of the velocity difference over that speed (the field is linear in it).

1. ``parts`` (docs/study_wake.csv): nanoseconds per evaluation of ``wake_velocity_batch``
   over the station points, for each part of the field alone (``displacement``,
   ``vortices``, ``turbulence``), all of them (``all``), none of them (``none``: the hull
   frame and the loop) and no wake (``off``: the loop), exact and table model, at the
   env's 8 dipoles.
2. ``field`` (same file): the whole field, exact at 8 (the env's) and 24 dipoles, and the
   table model at table steps of a third, a sixth (the default) and a twelfth of the hull
   radius, with its RMS and largest error against the exact field of the same dipoles in
   each region.
3. ``env`` (docs/study_wake_env.csv): SubmarineWake-v0's env-steps per second through
   ``gym.make_vec(..., vectorization_mode="vector_entry_point")`` with the exact wake, the
   table model (``wake_model="table"``) and no wake (``wake=False``) at 1024 and 4096 envs,
   on one of numba's threads and on all of them (on a machine shared with other work, the
   parallel kernel's threads wait for each other and the one-thread figures are the steadier
   ones), and per second of CPU time (numba's threads together). The markdown table also
   gives the share of a step's time that the wake adds, table over exact.

Costs are the best of several repeats, the subjects taken in turn each repeat
(:func:`benchmarks.common.interleaved_best`), so that a change of load hits them alike; the
field's are measured in the thread's CPU time (``time.thread_time``), which the other
processes on a shared machine disturb far less than the wall clock. The load average at
the start and the end is in the CSVs' ``#`` lines.
"""

from __future__ import annotations

import time

import gymnasium as gym
import numba
import numpy as np

from benchmarks.common import (
    DOCS,
    arguments,
    describe,
    fmt,
    interleaved_best,
    load_average,
    out_dir,
    read_csv,
    write_csv,
)
from fluidsim_envs.physics import Craft, WakeField
from fluidsim_envs.physics.wake import source_row, wake_velocity_batch

SPEED = 2.0  # m/s: the lead's speed along its x
ENV_ID = "fluidsim/SubmarineWake-v0"
DIPOLES = 8  # SubmarineWake-v0's
STEPS = (3.0, 6.0, 12.0)  # table steps: the hull radius over these
PARTS = {
    "off": None,
    "none": dict(displacement=False, vortices=False, noise=0.0),
    "displacement": dict(vortices=False, noise=0.0),
    "vortices": dict(displacement=False, noise=0.0),
    "turbulence": dict(displacement=False, vortices=False),
    "all": dict(),
}
HEADER = (
    "section", "model", "dipoles", "table_step_m", "parts", "ns_per_eval", "cost_vs_exact",
    "rms_err_station", "max_err_station", "rms_err_start", "max_err_start",
)  # fmt: skip
ENV_HEADER = (
    "num_envs", "threads", "wake", "env_steps_per_s", "env_steps_per_cpu_s", "speed_vs_exact",
)  # fmt: skip


def scene_wake(**changes) -> WakeField:
    """SubmarineWake-v0's WakeField (its default parameters), with changes."""
    from fluidsim_envs.scenes.submarine_wake.env import SubmarineWakeParams

    return SubmarineWakeParams().wake_field().replace(**changes)


def flight_points(n: int, grow: float, seed: int = 0) -> np.ndarray:
    """The UUV's wake-feeling samples [7 n, 3] in the lead's frame, the UUV's center drawn
    uniformly over the station box grown by ``grow`` (m) on each axis."""
    from fluidsim_envs.scenes.submarine_wake.env import SubmarineWakeParams

    p = SubmarineWakeParams()
    rng = np.random.default_rng(seed)
    craft = Craft.load("uuv")
    arms = np.array([s.offset_m for s in (*craft.plates, *craft.cylinders)])
    x = rng.uniform(p.station_behind_m[0] - grow, p.station_behind_m[1] + grow, n)
    side = rng.uniform(p.station_side_m[0] - grow, p.station_side_m[1] + grow, n)
    y = np.where(rng.random(n) < 0.5, 1.0, -1.0) * side
    z = rng.uniform(p.station_up_m[0] - grow, p.station_up_m[1] + grow, n)
    yaw = np.radians(p.start_heading_deg) * rng.uniform(-1.0, 1.0, n)
    c, s = np.cos(yaw), np.sin(yaw)
    ax, ay = arms[:, 0], arms[:, 1]
    px = x[:, None] + c[:, None] * ax - s[:, None] * ay
    py = y[:, None] + s[:, None] * ax + c[:, None] * ay
    pz = z[:, None] + arms[None, :, 2]
    return np.stack([px, py, pz], axis=-1).reshape(-1, 3)


SOURCE = source_row((0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0), (SPEED, 0.0, 0.0), (517.3, 91.9, 4.1))


def field(prm: np.ndarray, pts: np.ndarray) -> np.ndarray:
    out = np.empty_like(pts)
    wake_velocity_batch(pts, SOURCE, prm, out)
    return out


def errors(approx: np.ndarray, exact: np.ndarray) -> tuple[float, float]:
    """RMS and largest |approx - exact| over the hull's speed."""
    e = np.linalg.norm(approx - exact, axis=1) / SPEED
    return float(np.sqrt(np.mean(e * e))), float(e.max())


def eval_seconds(prm: np.ndarray, pts: np.ndarray):
    """A timed call for interleaved_best: seconds of this thread's CPU per evaluation."""
    out = np.empty_like(pts)

    def run() -> float:
        t0 = time.thread_time()
        wake_velocity_batch(pts, SOURCE, prm, out)
        return (time.thread_time() - t0) / len(pts)

    return run


def measure_field(n: int, repeats: int) -> list[tuple]:
    """Rows of sections ``parts`` and ``field``."""
    station, start = flight_points(n, 0.0, seed=1), flight_points(n, 4.0, seed=2)
    subjects, meta = {}, {}
    for model in ("exact", "table"):
        for part, kw in PARTS.items():
            if kw is None:
                prm = scene_wake(model=model).params()
                prm[0] = 0.0  # W_ON: no wake
            else:
                prm = scene_wake(model=model, **kw).params()
            subjects["parts", model, part] = prm
            meta["parts", model, part] = (model, DIPOLES, "", part, kw)
    radius = scene_wake().radius_m
    for dipoles in (DIPOLES, 24):
        subjects["field", "exact", dipoles] = scene_wake(dipoles=dipoles).params()
        meta["field", "exact", dipoles] = ("exact", dipoles, "", "all", {"dipoles": dipoles})
        for k in STEPS:
            h = radius / k
            key = ("field", "table", dipoles, k)
            subjects[key] = scene_wake(dipoles=dipoles, model="table", table_step_m=h).params()
            meta[key] = ("table", dipoles, fmt(h), "all", {"dipoles": dipoles})
    for prm in subjects.values():  # compile once, outside the timing
        field(prm, station[:10])
    calls = {key: eval_seconds(prm, station) for key, prm in subjects.items()}
    best = interleaved_best(calls, repeats)
    exact_ns = best["field", "exact", DIPOLES] * 1e9
    rows = []
    for key, prm in subjects.items():
        model, dipoles, step, parts, kw = meta[key]
        if kw is None or model == "exact":
            errs = (0.0, 0.0, 0.0, 0.0)
        else:
            ref = scene_wake(**kw).params()
            errs = errors(field(prm, station), field(ref, station))
            errs += errors(field(prm, start), field(ref, start))
        ns = best[key] * 1e9
        rows.append((key[0], model, dipoles, step, parts, fmt(ns), fmt(ns / exact_ns))
                    + tuple(fmt(e) for e in errs))  # fmt: skip
        print(f"{key[0]:6s} {model:6s} {dipoles:3d} {step:>6s} {parts:13s} {ns:8.1f} ns "
              f"x{ns / exact_ns:5.2f}  rms {errs[0]:.2e} max {errs[1]:.2e} (station)  "
              f"rms {errs[2]:.2e} max {errs[3]:.2e} (start)", flush=True)  # fmt: skip
    return rows


def _best_pair(a, b):
    """The better (wall, CPU) rates of two, each taken alone."""
    if not isinstance(a, tuple):
        return b
    return max(a[0], b[0]), max(a[1], b[1])


def measure_env(sizes, seconds: float, repeats: int, counts) -> list[tuple]:
    """Rows of docs/study_wake_env.csv, on each count of numba's threads in ``counts``."""
    rows = []
    threads = numba.config.NUMBA_NUM_THREADS
    for n in sizes:
        calls = env_calls(n, seconds)
        for t in dict.fromkeys(counts):
            numba.set_num_threads(t)
            best = interleaved_best(calls, repeats, best=_best_pair)
            for kind, (wall, cpu) in best.items():
                ratio = wall / best["exact"][0]
                rows.append((n, t, kind, fmt(wall), fmt(cpu), fmt(ratio)))
                print(f"env {n:5d} {t} thread(s) {kind:6s} {wall:12,.0f} env-steps/s  "
                      f"{cpu:12,.0f} per CPU-s  x{ratio:.2f}", flush=True)  # fmt: skip
        numba.set_num_threads(threads)
        for venv in calls.venvs:
            venv.close()
    return rows


class env_calls(dict):
    """kind -> a timed call returning (wall, CPU) env-steps per second of SubmarineWake-v0
    with that wake; ``venvs`` to close afterwards."""

    KINDS = {"exact": {}, "table": {"wake_model": "table"}, "none": {"wake": False}}

    def __init__(self, num_envs: int, seconds: float) -> None:
        super().__init__()
        self.venvs = []
        rng = np.random.default_rng(0)
        for kind, kw in self.KINDS.items():
            venv = gym.make_vec(
                ENV_ID, num_envs=num_envs, vectorization_mode="vector_entry_point", **kw
            )
            venv.reset(seed=0)
            acts = [rng.uniform(-1, 1, venv.action_space.shape) for _ in range(8)]
            for a in acts:  # warm-up: compile, caches
                venv.step(a)
            self.venvs.append(venv)
            self[kind] = self._run(venv, acts, num_envs, seconds)

    @staticmethod
    def _run(venv, acts, num_envs, seconds):
        def run() -> tuple[float, float]:
            steps, t0, c0 = 0, time.perf_counter(), time.process_time()
            while (wall := time.perf_counter() - t0) < seconds:
                for a in acts:
                    venv.step(a)
                steps += len(acts) * num_envs
            return steps / wall, steps / max(time.process_time() - c0, 1e-9)

        return run


def chart(rows: list[dict], env_rows: list[dict], path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a0, a1, a2) = plt.subplots(1, 3, figsize=(17, 5.2))
    field_rows = [r for r in rows if r["section"] == "field"]
    for r in field_rows:
        ns = float(r["ns_per_eval"])
        if r["model"] == "exact":
            a0.axvline(ns, color="k", ls="--" if r["dipoles"] == str(DIPOLES) else ":", lw=1)
            a0.text(ns, 0.5, f" exact, {r['dipoles']} dipoles", rotation=90, fontsize=8,
                    transform=a0.get_xaxis_transform())  # fmt: skip
            continue
        label = f"table {r['dipoles']} dip, step {float(r['table_step_m']):g} m"
        (line,) = a0.loglog([ns], [float(r["rms_err_station"])], "o", label=f"{label}: RMS")
        a0.loglog([ns], [float(r["max_err_station"])], "^", color=line.get_color())
    a0.set_xscale("linear")
    a0.set_xlim(0.0, 1.1 * max(float(r["ns_per_eval"]) for r in field_rows))
    a0.set_xlabel("ns per evaluation (CPU)")
    a0.set_ylabel("error / hull speed at the station (o RMS, ^ largest)")
    a0.set_title("cost against error (exact field = 0)")
    a0.grid(True, which="both", alpha=0.3)
    a0.legend(fontsize=7)

    parts = [r for r in rows if r["section"] == "parts"]
    names = list(dict.fromkeys(r["parts"] for r in parts))
    x = np.arange(len(names))
    for k, model in enumerate(("exact", "table")):
        ns = [float(r["ns_per_eval"]) for n in names for r in parts
              if r["parts"] == n and r["model"] == model]  # fmt: skip
        a1.bar(x + (k - 0.5) * 0.4, ns, 0.4, label=model)
    a1.set_xticks(x, names, rotation=20)
    a1.set_ylabel("ns per evaluation (CPU)")
    a1.set_title(f"where the time goes ({DIPOLES} dipoles; each part alone)")
    a1.legend()
    a1.grid(True, axis="y", alpha=0.3)

    cases = list(dict.fromkeys((r["num_envs"], r["threads"]) for r in env_rows))
    kinds = list(dict.fromkeys(r["wake"] for r in env_rows))
    x = np.arange(len(cases))
    for k, kind in enumerate(kinds):
        rate = [float(r["env_steps_per_s"]) for c in cases for r in env_rows
                if (r["num_envs"], r["threads"]) == c and r["wake"] == kind]  # fmt: skip
        a2.bar(x + (k - 1) * 0.27, rate, 0.27, label=f"wake: {kind}")
    a2.set_xticks(x, [f"{n} envs\n{t} thread(s)" for n, t in cases])
    a2.set_ylabel("env-steps per second (wall)")
    a2.set_title("SubmarineWake-v0")
    a2.legend()
    a2.grid(True, axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def markdown(path=None, env_path=None) -> str:
    """docs/physics.md's tables from the study's CSVs (``benchmarks.report`` writes them)."""
    path = DOCS / "study_wake.csv" if path is None else path
    env_path = DOCS / "study_wake_env.csv" if env_path is None else env_path
    if not path.is_file() or not env_path.is_file():
        return "(no docs/study_wake.csv yet: run python -m benchmarks.study_wake)"
    notes, rows = read_csv(path)
    env_notes, env_rows = read_csv(env_path)
    load = "; ".join(dict.fromkeys(n for n in notes + env_notes if n.startswith("load average")))

    def g(v: str) -> str:
        return f"{float(v):.1e}"

    lines = [
        "| model | dipoles | table step (m) | ns / evaluation | of exact | RMS error | "
        "largest error | RMS error (start box) | largest error (start box) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        if r["section"] != "field":
            continue
        exact = r["model"] == "exact"
        errs = ["(reference)"] * 4 if exact else [
            g(r[k]) for k in ("rms_err_station", "max_err_station", "rms_err_start",
                              "max_err_start")
        ]  # fmt: skip
        lines.append(
            f"| {r['model']} | {r['dipoles']} | {r['table_step_m'] or '-'} | "
            f"{float(r['ns_per_eval']):.0f} | {float(r['cost_vs_exact']):.2f} | "
            + " | ".join(errs)
            + " |"
        )
    lines += ["", "| part alone | exact (ns) | table (ns) |", "|---|---:|---:|"]
    parts = {(r["parts"], r["model"]): float(r["ns_per_eval"]) for r in rows
             if r["section"] == "parts"}  # fmt: skip
    for name in dict.fromkeys(p for p, _ in parts):
        lines.append(f"| {name} | {parts[name, 'exact']:.0f} | {parts[name, 'table']:.0f} |")
    lines += [
        "",
        "| envs | threads | exact wake (env-steps/s) | table wake | no wake | table / exact | "
        "wake's cost, table / exact |",
        "|---:|---:|---:|---:|---:|---:|---:|",
    ]
    env = {(r["num_envs"], r["threads"], r["wake"]): float(r["env_steps_per_s"])
           for r in env_rows}  # fmt: skip
    for n, th in dict.fromkeys((r["num_envs"], r["threads"]) for r in env_rows):
        e, t, o = env[n, th, "exact"], env[n, th, "table"], env[n, th, "none"]
        share = (1 / t - 1 / o) / (1 / e - 1 / o)  # the time the wake adds to a step
        lines.append(f"| {n} | {th} | {e:,.0f} | {t:,.0f} | {o:,.0f} | {t / e:.2f} | {share:.2f} |")
    lines += [
        "",
        "Errors: |table - exact| over the hull's speed at the UUV's wake-feeling samples on "
        "station (the start box: grown by the start error). Costs: best of interleaved "
        "repeats, CPU time per evaluation; env-steps: wall clock, best of interleaved repeats; "
        "the wake's cost: the time it adds to an env-step (1 / rate - 1 / rate without it), "
        "table over exact. On a machine shared with other work the two-thread rows are the "
        "less steady (the parallel kernel's threads wait for each other). "
        f"{load}. From docs/study_wake.csv and docs/study_wake_env.csv "
        "(`python -m benchmarks.study_wake`).",
    ]
    return "\n".join(lines)


def main() -> None:
    parser = arguments(__doc__, "fewer points, repeats and envs, into build/study_quick")
    args = parser.parse_args()
    machine = describe()
    out = out_dir(args.out, args.quick)
    threads = numba.config.NUMBA_NUM_THREADS
    if args.quick:
        n, repeats, sizes, seconds, env_repeats, counts = 1000, 2, (256,), 0.1, 1, (1,)
    else:
        n, repeats, sizes, seconds, env_repeats, counts = 20000, 7, (1024, 4096), 1.5, 5, None
    rows = measure_field(n, repeats)
    env_rows = measure_env(sizes, seconds, env_repeats, counts or (1, threads))
    end = [load_average("end")]
    path = write_csv(out / "study_wake.csv", HEADER, rows, machine + end)
    env_path = write_csv(out / "study_wake_env.csv", ENV_HEADER, env_rows, machine + end)
    _, r = read_csv(path)
    _, e = read_csv(env_path)
    chart(r, e, out / "study_wake.png")
    print("wrote", path, env_path, out / "study_wake.png")


if __name__ == "__main__":
    main()
