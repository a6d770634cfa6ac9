"""Fixed point against float64: the error of each shipped craft's maneuver for fraction bits
8 to 30, where the source article's Q14 fails and why, and the cost per body-step.

    python -m benchmarks.study_fixed            # docs/study_fixed.csv, docs/study_fixed.png
    python -m benchmarks.study_fixed --quick    # fewer fraction bits, into build/study_quick

Accuracy. Each shipped craft flies a fixed maneuver of 2 s at dt = 1/120 s from one start,
holding one set of controls (below), through ``Simulator(dtype="fixed64" | "fixed32",
fraction_bits=f)`` for f = 8..30, under ``symplectic_euler`` and
``prescaled_symplectic_euler``, in the units derived from the craft
(``physics/fixed/format.py``); the reference is the float64 Simulator with the same
integrator at the same dt. The error is the final position's distance (m)
and the angle of the relative rotation between the final attitudes (deg). A run is
``refused`` where packing the craft refuses a value (the CSV's note says which),
``diverged`` where a state word saturated or the body passed the speed clamp. The source
article's own setting, Q14 in SI units (``units`` = 1 m, 1 kg, 1 s), is run for each craft
and format too (rows with ``units = si``).

- ``paper_airplane`` (air): thrown level at 6 m/s, 20 m up, aileron 0.2, elevator 0.3,
  rudder -0.1.
- ``speedboat`` (water): at 8 m/s on the surface, throttle 0.8, rudder 0.2, trim tabs 0.
- ``buoy`` (water): released 0.1 m high, tilted 11 deg, turning at 0.2 rad/s.
- ``uuv`` (water): 5 m down at 1.5 m/s, thrust 0.8, rudder 0.3, dive planes -0.4.
- ``submarine`` (water): 20 m down at 3 m/s, throttle 0.6, rudder 0.2, planes -0.2.

Cost: wall time per body-step of ``sim.step(controls, steps=50)`` at E = 1024 on one thread
(the serial kernels), best of ``--repeats`` (10) interleaved repeats, for the dart and the
boat in float64, float32, fixed32 (Q14) and fixed64 (Q24), symplectic Euler.
"""

from __future__ import annotations

import math
import re
import time
from pathlib import Path

import numpy as np

from fluidsim_envs.physics import Craft, Simulator, World

from .common import (
    DOCS,
    arguments,
    describe,
    interleaved_best,
    load_average,
    out_dir,
    read_csv,
    write_csv,
)

DT, STEPS = 1.0 / 120.0, 240
SI = {"length_m": 1.0, "mass_kg": 1.0, "time_s": 1.0}
AIR, WATER = World(), World(water=True)
MANEUVERS = {
    "paper_airplane": (AIR, dict(pos=(0, 0, 20), lin_vel=(6, 0, 0)), (0.2, 0.3, -0.1)),
    "speedboat": (WATER, dict(pos=(0, 0, 0), lin_vel=(8, 0, 0)), (0.8, 0.2, 0.0)),
    "buoy": (WATER, dict(pos=(0, 0, 0.1), quat=(0.995, 0.0998, 0, 0), ang_vel=(0.2, 0.1, 0)), ()),
    "uuv": (WATER, dict(pos=(0, 0, -5), lin_vel=(1.5, 0, 0)), (0.8, 0.3, -0.4)),
    "submarine": (WATER, dict(pos=(0, 0, -20), lin_vel=(3, 0, 0)), (0.6, 0.2, -0.2)),
}
INTEGRATORS = ("symplectic_euler", "prescaled_symplectic_euler")
HEADER = ["kind", "craft", "integrator", "format", "fraction_bits", "units", "status",
          "pos_err_m", "att_err_deg", "ns_per_body_step", "note"]  # fmt: skip


def attitude_deg(q1: np.ndarray, q2: np.ndarray) -> float:
    """The angle (deg) of the rotation between two attitudes (largest over bodies)."""
    q1 = q1 / np.linalg.norm(q1, axis=-1, keepdims=True)
    q2 = q2 / np.linalg.norm(q2, axis=-1, keepdims=True)
    c = np.clip(np.abs(np.sum(q1 * q2, axis=-1)), 0.0, 1.0)
    return float(np.degrees(2.0 * np.arccos(c)).max())


def _run(craft: Craft, world: World, init: dict, controls, **kwargs):
    sim = Simulator(craft, world, 1, DT, **kwargs)
    sim.reset(**init)
    sim.step(np.asarray([controls], dtype=float).reshape(1, -1), steps=STEPS)
    return sim


def accuracy_rows(bits_range) -> list[list]:
    rows = []
    for name, (world, init, controls) in MANEUVERS.items():
        craft = Craft.load(name)
        for method in INTEGRATORS:
            ref = _run(craft, world, init, controls, integrator=method)
            settings = [(fmt, f, "auto") for fmt in ("fixed64", "fixed32") for f in bits_range]
            settings += [(fmt, 14, "si") for fmt in ("fixed32", "fixed64")]
            for fmt, f, units in settings:
                kwargs = dict(integrator=method, dtype=fmt, fraction_bits=f)
                if units == "si":
                    kwargs["units"] = dict(SI, time_s=DT) if method != INTEGRATORS[0] else SI
                status, pos_err, att_err, note = "ok", math.nan, math.nan, ""
                try:
                    sim = _run(craft, world, init, controls, **kwargs)
                except ValueError as err:
                    status, note = "refused", str(err).removeprefix("Simulator: ")
                else:
                    pos_err = float(np.linalg.norm(sim.pos - ref.pos, axis=-1).max())
                    att_err = attitude_deg(sim.quat, ref.quat)
                    if sim.diverged.any():
                        status = "diverged"
                    u = sim.units
                    note = f"units {u.length_m:g} m, {u.mass_kg:g} kg, {u.time_s:.6g} s"
                rows.append(["accuracy", name, method, fmt, f, units, status, pos_err, att_err,
                             math.nan, note])  # fmt: skip
                line = f"{name:15s} {method[:9]:9s} {fmt} Q{f:<2d} {units:4s} {status:8s} "
                print(line + f"pos {pos_err:9.3g} m  att {att_err:9.3g} deg  {note[:60]}")
    return rows


def cost_rows(repeats: int) -> list[list]:
    rows = []
    E, steps = 1024, 50
    settings = {
        "float64": dict(dtype=np.float64),
        "float32": dict(dtype=np.float32),
        "fixed32": dict(dtype="fixed32", fraction_bits=14),
        "fixed64": dict(dtype="fixed64", fraction_bits=24),
    }
    for name in ("paper_airplane", "speedboat"):
        world, init, controls = MANEUVERS[name]
        craft = Craft.load(name)
        sims = {}
        for key, kwargs in settings.items():
            sim = Simulator(craft, world, E, DT, parallel=False, **kwargs)
            sim.reset(**init)
            sims[key] = sim
        ctrl = np.tile(np.asarray(controls, dtype=float), (E, 1))

        def call(sim, init=init, ctrl=ctrl):
            def timed():
                sim.reset(**init)
                t0 = time.perf_counter()
                sim.step(ctrl, steps=steps)
                return time.perf_counter() - t0

            return timed

        for sim in sims.values():
            call(sim)()  # compile or load
        best = interleaved_best({k: call(s) for k, s in sims.items()}, repeats)
        for key, seconds in best.items():
            f = settings[key].get("fraction_bits", "")
            ns = seconds / (E * steps) * 1e9
            rows.append(["cost", name, "symplectic_euler", key, f, "auto", "ok", math.nan,
                         math.nan, ns, f"E = {E}, {steps} steps, one thread"])  # fmt: skip
            print(f"cost {name:15s} {key}: {ns:8.1f} ns per body-step", flush=True)
    return rows


def chart(rows: list[list], path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    crafts = list(MANEUVERS)
    fig, axes = plt.subplots(2, 3, figsize=(15, 8.5))
    styles = {
        ("fixed64", INTEGRATORS[0]): ("C0", "-", "o"),
        ("fixed32", INTEGRATORS[0]): ("C1", "--", "s"),
        ("fixed64", INTEGRATORS[1]): ("C2", "-", "^"),
        ("fixed32", INTEGRATORS[1]): ("C3", "--", "v"),
    }
    for ax, name in zip(axes.ravel(), crafts, strict=False):
        for (fmt, method), (color, ls, marker) in styles.items():
            sel = [r for r in rows if r[0] == "accuracy" and r[1] == name and r[2] == method
                   and r[3] == fmt and r[5] == "auto"]  # fmt: skip
            ok = [r for r in sel if r[6] == "ok"]
            label = f"{fmt}, {'prescaled' if method != INTEGRATORS[0] else 'symplectic'}"
            ax.semilogy([r[4] for r in ok], [max(r[7], 1e-12) for r in ok], ls=ls, color=color,
                        marker=marker, ms=4, label=label)  # fmt: skip
            bad = [r for r in sel if r[6] != "ok"]
            ax.plot([r[4] for r in bad], [1e2] * len(bad), ls="none", marker="x", color=color)
        ax.axvline(14, color="grey", lw=0.8, ls=":")
        ax.set_title(f"{name}: 2 s against float64")
        ax.set_xlabel("fraction bits (x at top: refused or diverged)")
        ax.set_ylabel("position error (m)")
        ax.set_ylim(1e-10, 3e2)
        ax.grid(True, which="both", alpha=0.3)
    axes[0, 0].legend(fontsize=8)
    ax = axes.ravel()[-1]
    cost = [r for r in rows if r[0] == "cost"]
    labels = [f"{r[1].split('_')[0]}\n{r[3]}" for r in cost]
    ax.bar(range(len(cost)), [r[9] for r in cost], color=["C0", "C1", "C2", "C3"] * 2)
    ax.set_xticks(range(len(cost)), labels, fontsize=8)
    ax.set_yscale("log")
    ax.set_ylabel("ns per body-step (one thread)")
    ax.set_title("cost: float64, float32, fixed32 Q14, fixed64 Q24")
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def _short(note: str) -> str:
    """What a refusal refused, from its message: ``inertia_kgm2 ... rounds to 0``."""
    match = re.search(r"(rounds|cannot hold) (?:craft '[\w]+'|world) (.+?) = ([-\d.e+]+)", note)
    if not match:
        return note[:40]
    verb, what, value = match.groups()
    return f"{what} = {value} {'rounds to 0' if verb == 'rounds' else 'overflows'}"


def markdown(path=DOCS / "study_fixed.csv") -> str:
    """docs/study.md's tables from the study's CSV (``benchmarks.report`` writes them)."""
    if not Path(path).is_file():
        return "(no docs/study_fixed.csv yet: run python -m benchmarks.study_fixed)"
    comments, rows = read_csv(path)
    acc = [r for r in rows if r["kind"] == "accuracy"]
    lines = [
        "| craft | integrator | fixed32 Q14: position / attitude error | fixed64: fewest bits "
        "for < 1 mm | fixed32: most bits that run | Q14 in SI units (the source's) |",
        "|---|---|---|---:|---:|---|",
    ]
    for craft in dict.fromkeys(r["craft"] for r in acc):
        for method in INTEGRATORS:
            sel = [r for r in acc if r["craft"] == craft and r["integrator"] == method]

            def one(fmt, bits, units, sel=sel):
                return next(r for r in sel if r["format"] == fmt and int(r["fraction_bits"]) ==
                            bits and r["units"] == units)  # fmt: skip

            def said(r):
                if r["status"] == "refused":
                    return f"refused: {_short(r['note'])}"
                err = f"{float(r['pos_err_m']):.3g} m / {float(r['att_err_deg']):.3g} deg"
                return err + (" (diverged)" if r["status"] == "diverged" else "")

            auto = [r for r in sel if r["units"] == "auto" and r["status"] == "ok"]
            fine = [int(r["fraction_bits"]) for r in auto
                    if r["format"] == "fixed64" and float(r["pos_err_m"]) < 1e-3]  # fmt: skip
            runs = [int(r["fraction_bits"]) for r in auto if r["format"] == "fixed32"]
            lines.append(
                f"| {craft} | {method.replace('_symplectic_euler', '')} "
                f"| {said(one('fixed32', 14, 'auto'))} | {min(fine) if fine else '-'} "
                f"| {max(runs) if runs else '-'} | {said(one('fixed32', 14, 'si'))} |"
            )
    cost = [r for r in rows if r["kind"] == "cost"]
    kinds = list(dict.fromkeys(r["format"] for r in cost))
    lines += ["", "| ns per body-step (one thread) | " + " | ".join(kinds) + " |",
              "|---|" + "---:|" * len(kinds)]  # fmt: skip
    for craft in dict.fromkeys(r["craft"] for r in cost):
        ns = {r["format"]: float(r["ns_per_body_step"]) for r in cost if r["craft"] == craft}
        lines.append(f"| {craft} | " + " | ".join(f"{ns[k]:.0f}" for k in kinds) + " |")
    command = next((c[len("command: ") :] for c in comments if c.startswith("command: ")), "")
    lines += ["", f"From docs/study_fixed.csv (`{command}`)."]
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = arguments(__doc__, "fraction bits 8, 14, 20, 30 only; 2 cost repeats")
    parser.add_argument("--repeats", type=int, default=10)
    args = parser.parse_args(argv)
    machine = describe()
    bits = (8, 14, 20, 30) if args.quick else range(8, 31)
    t0 = time.perf_counter()
    rows = accuracy_rows(bits)
    rows += cost_rows(2 if args.quick else args.repeats)
    out = out_dir(args.out, args.quick)
    notes = [*machine, load_average(), f"run time: {time.perf_counter() - t0:.0f} s"]
    write_csv(out / "study_fixed.csv", HEADER, rows, notes)
    chart(rows, out / "study_fixed.png")
    print(
        f"wrote {out / 'study_fixed.csv'} and study_fixed.png in {time.perf_counter() - t0:.0f} s"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
