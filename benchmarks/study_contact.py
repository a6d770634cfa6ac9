"""Contact's stability against the time step, the velocity passes and the integrator.

Four scenes on a flat ground (physics/contact.py), each one environment, float64, 10 s:

- ``box at rest``: a 0.4 m, 2 kg box dropped tilted from 0.6 m and moving sideways at
  0.5 m/s (``tests/physics/test_contact.py``); measured over its last 5 s, when it should
  lie still on a face: the larger of its largest distance from where it lies at 5 s
  (jitter, sinking or walking) and its height's error against half its side (lying
  sunk, floating, or on an edge);
- ``3-stack``: three 0.5 m, 2 kg boxes stacked, the upper two shifted 3 cm and 1.5 cm (the
  stack test): each box's largest distance from its start;
- ``heavy on light``: the same stack with a 20 kg box on two 1 kg boxes (a mass ratio of 20
  is where one projected Gauss-Seidel pass leaves a stack sinking: the solver's hard case);
- ``bounce, e = 1``: a 0.1 m ball of restitution 1 dropped from 1 m onto a ground of
  restitution 1: the tops of its bounces (the highest sampled point of each flight, every
  step) against the drop height, the highest and the last. Newton's law with e = 1 keeps
  them at 1; above 1 is energy the contact invented. (Tops, not the energy: symplectic
  Euler's energy in flight is exact only in its shadow form, 1/2 v^2 + g z - g dt v_z / 2.)

Each scene holds (the table) when its measure stays under 1 cm (the boxes; the stack boxes
must also end slower than 1 mm/s) or every top is within 10% of the drop height (the ball). The
sweep: dt from 1/1024 to 1/4 s in factors of 2; symplectic Euler (the envs' integrator) with
1, 2, 4, 8 and 16 passes (``World.contact_passes``), rk2 with 1 and 8, rk4 and velocity
Verlet with 1, and the seed's ``verlet_tetra`` with 1.

Writes ``docs/study_contact.csv`` (machine in ``#`` lines) and ``docs/study_contact.png``::

    python -m benchmarks.study_contact            # about a minute on 2 cores
    python -m benchmarks.study_contact --quick    # 4 dts, into build/study_quick/
"""

from __future__ import annotations

import dataclasses
import math
import time
from pathlib import Path

import numpy as np

from benchmarks.bench_contact import ball, box
from benchmarks.common import arguments, describe, fmt, out_dir, write_csv
from fluidsim_envs.physics import Ground, Simulator, World

G = 9.81
SECONDS = 10.0
HOLD_M = 0.01  # a box scene holds while every box stays within this of its place
HOLD_SPEED = 1e-3  # and the stack ends slower than this (m/s)
HOLD_TOP = 0.1  # the bounce holds while every top is within this of the drop height
DROP_M = 1.0  # the ball's bottom starts this high
SAMPLES = 2000  # measures at up to this many evenly spaced points per run
CONFIGS = (
    *(("symplectic_euler", p) for p in (1, 2, 4, 8, 16)),
    ("rk2", 1),
    ("rk2", 8),
    ("rk4", 1),
    ("velocity_verlet", 1),
    ("verlet_tetra", 1),
)
TILT = (math.cos(0.1), 0.6 * math.sin(0.1), 0.8 * math.sin(0.1), 0.0)  # 11.5 deg


def scenes() -> dict:
    """name: (crafts, ground, reset kwargs)."""
    stack = [[0.0, 0.0, 0.25], [0.03, 0.0, 0.75], [-0.03, 0.015, 1.25]]
    bouncy = dataclasses.replace(ball("ball", radius=0.1, mass=1.0), restitution=1.0)
    return {
        "box at rest": (
            [box("box", half=0.2)],
            Ground(),
            dict(pos=(0.0, 0.0, 0.6), quat=TILT, lin_vel=(0.5, 0.0, 0.0)),
        ),
        "3-stack": ([box(n) for n in "abc"], Ground(), dict(pos=[stack])),
        "heavy on light": (
            [box("a", mass=1.0), box("b", mass=1.0), box("c", mass=20.0)],
            Ground(),
            dict(pos=[stack]),
        ),
        "bounce, e = 1": ([bouncy], Ground(restitution=1.0), dict(pos=(0.0, 0.0, 1.1))),
    }


def run(name: str, scene, integrator: str, passes: int, dt: float) -> dict:
    """One run: the scene's measure (m, or energy / start), whether it holds, and whether the
    state stayed finite."""
    crafts, ground, reset = scene
    world = World(ground=ground, contact_passes=passes)
    sim = Simulator(crafts, world, num_envs=1, dt=dt, integrator=integrator)
    sim.reset(**reset)
    n = round(SECONDS / dt)
    bounce = name == "bounce, e = 1"
    chunks = np.diff(np.linspace(0, n, (n if bounce else min(SAMPLES, n)) + 1).round().astype(int))
    start = np.array(sim.pos[0], dtype=np.float64)
    worst, t, settled, z = 0.0, 0.0, None, []
    for k in chunks:
        sim.step(steps=int(k))
        t += k * dt
        if sim.diverged[0]:
            return dict(measure=math.inf, second=math.nan, holds=False, finite=False)
        pos = np.array(sim.pos[0], dtype=np.float64)
        if bounce:
            z.append(pos[0, 2] - crafts[0].shapes[0].radius_m)
        elif name == "box at rest":
            if t >= SECONDS / 2 - 1e-9:
                settled = pos if settled is None else settled
                half = crafts[0].shapes[0].half_extents_m[2]
                worst = max(
                    worst,
                    float(np.linalg.norm(pos - settled, axis=1).max()),
                    abs(float(pos[0, 2]) - half),
                )
        else:
            worst = max(worst, float(np.linalg.norm(pos - start, axis=1).max()))
    if bounce:  # the tops: local maxima of the sampled height
        tops = [z[j] / DROP_M for j in range(1, len(z) - 1) if z[j - 1] <= z[j] > z[j + 1]]
        if not tops:
            return dict(measure=math.nan, second=math.nan, holds=False, finite=True)
        top = max(tops, key=lambda x: abs(x - 1.0))
        return dict(
            measure=top,
            second=tops[-1],
            holds=all(abs(x - 1.0) < HOLD_TOP for x in tops),
            finite=True,
        )
    speed = float(np.abs(sim.lin_vel[0]).max())
    holds = worst < HOLD_M and (name == "box at rest" or speed < HOLD_SPEED)
    return dict(measure=worst, second=speed, holds=holds, finite=True)


def holds_up_to(dts, results) -> float:
    """The largest dt of the sweep at and below which every run held (NaN: none)."""
    best = math.nan
    for dt, r in sorted(zip(dts, results, strict=True)):
        if not r["holds"]:
            break
        best = dt
    return best


def plot(table: dict, dts, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(scenes())
    fig, axes = plt.subplots(2, 2, figsize=(12, 8.5), constrained_layout=True)
    for ax, name in zip(axes.flat, names, strict=True):
        for integrator, passes in CONFIGS:
            rs = table[name, integrator, passes]
            y = np.array([r["measure"] for r in rs], dtype=float)
            if name != "bounce, e = 1":
                y = np.maximum(y, 1e-9)
            style = {"symplectic_euler": "-", "rk2": "--", "rk4": "-.", "velocity_verlet": ":"}
            ax.loglog(
                dts,
                y,
                linestyle=style.get(integrator, (0, (1, 1))),
                marker="o" if integrator == "symplectic_euler" else "s",
                ms=3,
                lw=1.2 if integrator == "symplectic_euler" else 1.0,
                label=f"{integrator}, {passes} pass{'es' if passes > 1 else ''}",
            )
        if name == "bounce, e = 1":
            ax.axhspan(1 - HOLD_TOP, 1 + HOLD_TOP, color="green", alpha=0.08)
            ax.set_ylabel("the top furthest from the drop height / drop height")
            ax.set_yscale("linear")
        else:
            ax.axhline(HOLD_M, color="gray", lw=0.8)
            ax.set_ylabel(
                "largest move or height error, last 5 s (m)"
                if name == "box at rest"
                else "largest move of a box from its start (m)"
            )
        for dt_env, label, y in ((1 / 240, "dart", 0.02), (1 / 200, "boat", 0.07)):
            ax.axvline(dt_env, color="k", lw=0.5, alpha=0.4)
            ax.text(dt_env, y, f" {label}", transform=ax.get_xaxis_transform(), fontsize=7)
        ax.set_xlabel("dt (s)")
        ax.set_title(name, fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    axes[0, 0].legend(fontsize=7, ncol=2)
    fig.suptitle(
        f"Contact against dt, passes and integrator over {SECONDS:g} s "
        f"(boxes hold under {HOLD_M * 100:g} cm: gray line)"
    )
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main() -> None:
    parser = arguments(__doc__, "4 time steps")
    args = parser.parse_args()
    out = out_dir(args.out, args.quick)
    dts = [2.0**-k for k in ((2, 5, 7, 10) if args.quick else range(2, 11))]
    t_start = time.perf_counter()
    machine = describe()

    table, rows = {}, []
    for name, scene in scenes().items():
        for integrator, passes in CONFIGS:
            rs = [run(name, scene, integrator, passes, dt) for dt in dts]
            table[name, integrator, passes] = rs
            limit = holds_up_to(dts, rs)
            print(
                f"{name:15s} {integrator:17s} {passes:2d} pass: holds up to dt = "
                + ("none" if math.isnan(limit) else f"1/{round(1 / limit)}")
                + " | "
                + " ".join(f"{r['measure']:.2g}{'' if r['holds'] else '!'}" for r in rs)
            )
            for dt, r in zip(dts, rs, strict=True):
                rows.append(
                    (
                        name,
                        integrator,
                        passes,
                        fmt(dt),
                        fmt(float(r["measure"])),
                        fmt(float(r["second"])),
                        int(r["holds"]),
                        int(r["finite"]),
                        fmt(limit),
                    )
                )
    notes = [
        f"{SECONDS:g} s per run, 1 env, float64; measure: boxes, the largest move (m) of any box"
        " (box at rest: over the last half, from where it lay at the half, or its height's"
        " error, the larger; stacks: from the start); bounce: the top furthest from the drop"
        " height / drop height; second: end speed (m/s) of the boxes, or the last top / drop"
        " height (bounce)",
        f"holds: boxes within {HOLD_M} m (stacks also end slower than {HOLD_SPEED} m/s); bounce"
        f" tops within {HOLD_TOP:.0%}; holds_up_to_dt_s: the largest dt of the sweep at"
        " and below which every run held",
    ]
    header = (
        "scene",
        "integrator",
        "passes",
        "dt_s",
        "measure",
        "end_speed_mps_or_last_top",
        "holds",
        "finite",
        "holds_up_to_dt_s",
    )
    write_csv(out / "study_contact.csv", header, rows, [*machine, *notes])
    plot(table, dts, out / "study_contact.png")
    print(f"wrote {out}/study_contact.csv and .png in {time.perf_counter() - t_start:.0f} s")


def markdown(path=None) -> str:
    """docs/study.md's table from docs/study_contact.csv: per integrator and passes, the
    largest dt of the sweep at and below which every run of each scene held."""
    from benchmarks.common import DOCS, read_csv

    path = DOCS / "study_contact.csv" if path is None else path
    if not path.is_file():
        return "(no docs/study_contact.csv yet: run python -m benchmarks.study_contact)"
    rows = read_csv(path)[1]
    scenes_ = list(dict.fromkeys(r["scene"] for r in rows))
    limit = {(r["scene"], r["integrator"], r["passes"]): float(r["holds_up_to_dt_s"]) for r in rows}
    lines = [
        "| integrator, passes | " + " | ".join(scenes_) + " |",
        "|---|" + "---:|" * len(scenes_),
    ]
    for integrator, passes in dict.fromkeys((r["integrator"], r["passes"]) for r in rows):
        cells = [limit[name, integrator, passes] for name in scenes_]
        text = ["never" if math.isnan(x) else f"1/{round(1 / x)} s" for x in cells]
        lines.append(f"| {integrator}, {passes} | " + " | ".join(text) + " |")
    return "\n".join(lines)


if __name__ == "__main__":
    main()
