"""What the speedboat's physics costs, part by part: the step kernel on the speedboat craft with
all its samples, and with each group left out, so that the cost split between the hull's
bottom plates (lift), their skin friction, its buoyancy columns and the rest reads off one
table; the one-sided bottom and the first hull (forward-facing friction plates, issue 20's
"before"); and the whole craft in two-wave swell (the surface height under every sample).

For each variant: body-steps per second of ``Simulator.step(controls, steps=k)`` at
E = 4096 environments (float64, symplectic Euler, the parallel kernel on all threads; the
boats planing at 15 m/s), the best of ``--repeats`` calls of ~0.3 s each. The share of a
group is the time it adds to a body-step over the variant without it.

Writes ``docs/bench_boat.csv`` (machine in ``#`` lines).

    python -m benchmarks.bench_boat [--quick]
"""

from __future__ import annotations

import tomllib
from dataclasses import replace

import numpy as np

from benchmarks.common import arguments, best_of, describe, sized, write_csv
from fluidsim_envs.craft.hull import VHull, speedboat_toml
from fluidsim_envs.physics import Craft, Simulator, World

NUM_ENVS = 4096
DT = 1.0 / 200.0


def variants(craft: Craft) -> dict[str, Craft]:
    """The shipped boat, each group left out ("without ...": the group's share of a
    body-step), the sample rules of issue 20 turned off one at a time, and the first hull
    (forward-facing friction plates, two-sided bottom: ``VHull(friction="plates")``)."""

    def plates(prefix: str, keep: bool):
        return tuple(p for p in craft.plates if p.name.startswith(prefix) == keep)

    def smooth(p):  # the plate without skin friction
        return replace(
            p,
            friction_coefficient=0.0,
            friction_line=None,
            friction_length_m=None,
            friction_area_m2=None,
        )

    drop_bottom = plates("bottom", keep=False)
    controls = {c for s in (craft.controls) for c in (x.sample for x in s.surfaces)}
    first = VHull(friction="plates", one_sided_bottom=False)
    return {
        "full": craft,
        "without bottom plates": replace(craft, plates=drop_bottom),
        "without skin friction": replace(craft, plates=tuple(smooth(p) for p in craft.plates)),
        "without buoyancy": replace(craft, buoyancy=()),
        "one-sided bottom": replace(
            craft,
            plates=tuple(
                replace(p, one_sided=True) if p.name.startswith("bottom") else p
                for p in craft.plates
            ),
        ),
        "first hull (friction plates, two-sided)": Craft.from_dict(
            tomllib.loads(speedboat_toml(first)), "VHull(friction='plates')"
        ),
        "thrust and control surfaces only": replace(
            craft, plates=tuple(p for p in craft.plates if p.name in controls), buoyancy=()
        ),
    }


def rate(craft: Craft, seconds: float, repeats: int, world: World | None = None) -> float:
    sim = Simulator(craft, world or World(water=True), num_envs=NUM_ENVS, dt=DT)
    controls = np.zeros((NUM_ENVS, len(sim.control_names)))
    controls[:, 0] = 0.4  # 1800 N ahead
    controls[:, 2] = -1.0

    def reset():
        sim.reset(pos=(0.0, 0.0, 0.3), lin_vel=(15.0, 0.0, 0.0))

    reset()
    sim.step(controls)  # compile / warm
    steps = sized(lambda n: sim.step(controls, steps=n), seconds, probe=4)
    best = best_of(lambda: sim.step(controls, steps=steps), repeats, reset, warmup=False)
    return NUM_ENVS * steps / best


def main() -> None:
    parser = arguments(__doc__, "shorter, noisier runs", "bench_boat.csv")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    seconds, repeats = (0.1, 1) if args.quick else (0.3, args.repeats)

    machine = describe()
    craft = Craft.load("speedboat")
    rows = []
    for label, c in variants(craft).items():
        r = rate(c, seconds, repeats)
        n = len(c.plates) + len(c.buoyancy) + len(c.thrusters)
        rows.append((label, n, r))
        print(f"{label:34s} {n:3d} samples {r:14,.0f} body-steps/s {1e9 / r:8.0f} ns/body-step")
    # the whole craft in two-wave swell: the surface height under every sample
    swell = World(water=True, swell=[(0.3, 30.0, 45.0), (0.15, 12.0, -60.0)])
    r = rate(craft, seconds, repeats, swell)
    rows.append(("full, in two-wave swell", rows[0][1], r))
    print(f"{rows[-1][0]:34s} {rows[-1][1]:3d} samples {r:14,.0f} body-steps/s {1e9 / r:8.0f} ns")
    full = 1e9 / rows[0][2]
    print("\nshare of a body-step's time")
    shares = {}
    for label, _, r in rows:
        if not label.startswith("without "):
            continue
        group = label.removeprefix("without ")
        shares[group] = (full - 1e9 / r) / full
        print(f"  {group:24s} {100 * shares[group]:5.1f}%")

    out = write_csv(
        args.out,
        ("variant", "samples", "body_steps_per_s", "ns_per_body_step", "share_of_full"),
        [
            (label, n, f"{r:.1f}", f"{1e9 / r:.1f}", f"{share:.4f}")
            for label, n, r in rows
            for share in [shares.get(label.removeprefix("without "), float("nan"))]
        ],
        machine,
    )
    print(f"\nwrote {out}")


if __name__ == "__main__":
    main()
