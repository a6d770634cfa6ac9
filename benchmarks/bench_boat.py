"""What the speedboat's physics costs, part by part: the step kernel on the speedboat craft with
all its samples, and with each group left out, so that the cost split between the hull's
bottom plates (lift), their skin friction, its buoyancy columns and the rest reads off one
table; the one-sided bottom and the first hull (forward-facing friction plates, issue 20's
"before"); and the whole craft in two-wave swell (the surface height under every sample).

For each variant: body-steps per second of ``Simulator.step(controls, steps=k)`` at
E = 4096 environments (float64, symplectic Euler, the parallel kernel on all threads; the
boats planing at 15 m/s), the best of ``--repeats`` calls of ~0.3 s each, the variants timed
in turn each repeat. The share of a group is the time it adds to a body-step over the
variant without it.

Writes ``docs/bench_boat.csv`` (machine in ``#`` lines).

    python -m benchmarks.bench_boat [--quick]
"""

from __future__ import annotations

import tomllib
from dataclasses import replace

import numpy as np

from benchmarks.common import arguments, describe, interleaved_best, sized, timed, write_csv
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
    # the variants that leave samples out leave the craft's groups out too (a group naming a
    # sample that is gone is refused: Craft.groups)
    bare = replace(craft, groups=())
    first = VHull(friction="plates", one_sided_bottom=False)
    return {
        "full": craft,
        "without bottom plates": replace(bare, plates=drop_bottom),
        "without skin friction": replace(craft, plates=tuple(smooth(p) for p in craft.plates)),
        "without buoyancy": replace(bare, buoyancy=()),
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
            bare, plates=tuple(p for p in craft.plates if p.name in controls), buoyancy=()
        ),
    }


def timer(craft: Craft, seconds: float, world: World | None = None):
    """A call that times one ``sim.step(controls, steps)`` of ``craft``'s boats (reset before,
    untimed) and returns body-steps per second; ``steps`` sized to take about ``seconds``."""
    sim = Simulator(craft, world or World(water=True), num_envs=NUM_ENVS, dt=DT)
    controls = np.zeros((NUM_ENVS, len(sim.control_names)))
    controls[:, 0] = 0.4  # 1800 N ahead
    controls[:, 2] = -1.0

    def reset():
        sim.reset(pos=(0.0, 0.0, 0.3), lin_vel=(15.0, 0.0, 0.0))

    reset()
    sim.step(controls)  # compile / warm
    steps = sized(lambda n: sim.step(controls, steps=n), seconds, probe=4)
    return lambda: NUM_ENVS * steps / timed(lambda: sim.step(controls, steps=steps), reset)


def main() -> None:
    parser = arguments(__doc__, "shorter, noisier runs", "bench_boat.csv")
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    seconds, repeats = (0.1, 1) if args.quick else (0.3, args.repeats)

    machine = describe()
    craft = Craft.load("speedboat")
    crafts = variants(craft)
    # the whole craft in two-wave swell: the surface height under every sample
    swell = World(water=True, swell=[(0.3, 30.0, 45.0), (0.15, 12.0, -60.0)])
    calls = {label: timer(c, seconds) for label, c in crafts.items()}
    calls["full, in two-wave swell"] = timer(craft, seconds, swell)
    crafts["full, in two-wave swell"] = craft
    # the variants in turn each repeat (a, b, c, a, b, ...), the best of each: a change of
    # load on a shared machine hits them alike
    best = interleaved_best(calls, repeats, best=max)
    rows = []
    for label, r in best.items():
        c = crafts[label]
        n = len(c.plates) + len(c.buoyancy) + len(c.thrusters)
        rows.append((label, n, r))
        print(f"{label:40s} {n:3d} samples {r:14,.0f} body-steps/s {1e9 / r:8.0f} ns/body-step")
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
