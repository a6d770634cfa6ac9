"""What the speedboat's physics costs, part by part: the step kernel on the speedboat craft with
all its samples, and with each group left out, so that the cost split between the hull's
bottom plates (lift), their skin friction, its buoyancy columns and the rest reads off one
table; the hull with ITTC-1957 skin friction on its bottom plates (``speedboat_ittc``),
without it and with a one-sided bottom (issue 20's sample rules); and the whole craft in
two-wave swell (the surface height under every sample).

For each variant: body-steps per second of ``Simulator.step(controls, steps=k)`` at
E = 4096 environments (float64, symplectic Euler, the parallel kernel on all threads; the
boats planing at 15 m/s), the best of ``--repeats`` calls of ~0.3 s each, the variants timed
in turn each repeat. The share of a group is the time it adds to a body-step over the
variant without it (``share_of_base``: of the variant it is left out of).

Writes ``docs/bench_boat.csv`` (machine in ``#`` lines); :func:`rules_markdown` is
docs/study_savitsky.md's table and reading of it (``python -m benchmarks.report``).

    python -m benchmarks.bench_boat [--quick]
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from benchmarks.common import (
    DOCS,
    arguments,
    describe,
    interleaved_best,
    prose,
    read_csv,
    sized,
    timed,
    write_csv,
)
from fluidsim_envs.physics import Craft, Simulator, World

NUM_ENVS = 4096
DT = 1.0 / 200.0


def variants(craft: Craft, ittc: Craft) -> dict[str, Craft]:
    """The shipped boat (``speedboat``, BoatOnStep-v0's: forward-facing friction plates), each
    group left out ("without ...": the group's share of a body-step); and the hull with its
    bottom plates' own ITTC-1957 skin friction (``speedboat_ittc``), without that friction,
    and with a one-sided bottom (issue 20's sample rules)."""

    def smooth(p):  # the plate without skin friction
        return replace(
            p,
            friction_coefficient=0.0,
            friction_line=None,
            friction_length_m=None,
            friction_area_m2=None,
        )

    def keep(c: Craft, prefix: str, kept: bool):
        return tuple(p for p in c.plates if p.name.startswith(prefix) == kept)

    controls = {c for s in (craft.controls) for c in (x.sample for x in s.surfaces)}
    # the variants that leave samples out leave the craft's groups out too (a group naming a
    # sample that is gone is refused: Craft.groups)
    bare = replace(craft, groups=())
    return {
        "full": craft,
        "without bottom plates": replace(bare, plates=keep(craft, "bottom", False)),
        "without friction plates": replace(bare, plates=keep(craft, "friction", False)),
        "without buoyancy": replace(bare, buoyancy=()),
        "thrust and control surfaces only": replace(
            bare, plates=tuple(p for p in craft.plates if p.name in controls), buoyancy=()
        ),
        "ITTC hull": ittc,
        "ITTC hull without skin friction": replace(
            ittc, plates=tuple(smooth(p) for p in ittc.plates)
        ),
        "ITTC hull, one-sided bottom": replace(
            ittc,
            plates=tuple(
                replace(p, one_sided=True) if p.name.startswith("bottom") else p
                for p in ittc.plates
            ),
        ),
    }


def base_of(label: str) -> str | None:
    """The variant a "... without X" variant leaves X out of ("full" for "without X")."""
    if " without " in f" {label}":
        head = f" {label}".split(" without ")[0].strip()
        return head or "full"
    return None


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
    crafts = variants(craft, Craft.load("speedboat_ittc"))
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
    ns = {label: 1e9 / r for label, _, r in rows}
    print("\nshare of a body-step's time")
    shares = {}
    for label in ns:
        base = base_of(label)
        if base is not None:
            shares[label] = (ns[base] - ns[label]) / ns[base]
            print(f"  {label:40s} {100 * shares[label]:5.1f}% of {base}")

    out = write_csv(
        args.out,
        ("variant", "samples", "body_steps_per_s", "ns_per_body_step", "share_of_base"),
        [
            (label, n, f"{r:.1f}", f"{1e9 / r:.1f}", f"{share:.4f}")
            for label, n, r in rows
            for share in [shares.get(label, float("nan"))]
        ],
        machine,
    )
    print(f"\nwrote {out}")


if __name__ == "__main__":
    main()


# ---- the docs --------------------------------------------------------------------------------

# docs/study_savitsky.md's table: CSV variant -> how the table names it
RULES = {
    "full": "`speedboat` (16 friction plates, two-sided bottom)",
    "ITTC hull": "`speedboat_ittc` (ITTC skin friction on the 32 bottom plates)",
    "ITTC hull without skin friction": "the same without skin friction",
    "ITTC hull, one-sided bottom": "the same with a one-sided bottom",
}


def rules_markdown(path=None) -> str:
    """What issue 20's sample rules cost, from docs/bench_boat.csv: the table and the numbers
    docs/study_savitsky.md reads from it."""
    path = DOCS / "bench_boat.csv" if path is None else path
    if not path.is_file():
        return "(no docs/bench_boat.csv yet: run python -m benchmarks.bench_boat)"
    comments, rows = read_csv(path)
    by = {r["variant"]: r for r in rows}
    ns = {k: float(by[k]["ns_per_body_step"]) for k in RULES}
    plates = sum(p.friction_line is not None for p in Craft.load("speedboat_ittc").plates)
    load = next((c for c in comments if c.startswith("load average at start: ")), "")
    load = load.removeprefix("load average at start: ").split(",")[0]
    lines = [
        prose(
            f"`python -m benchmarks.bench_boat` ([bench_boat.csv](bench_boat.csv): the "
            f"symplectic Euler kernel stepping {NUM_ENVS} planing boats in float64 on both "
            f"threads, load average {load} at the start, the variants timed in turn, the best "
            "of 5):"
        ),
        "",
        "| variant | samples | ns per body-step |",
        "|---|---:|---:|",
        *(f"| {name} | {by[k]['samples']} | {ns[k]:.0f} |" for k, name in RULES.items()),
        "",
        prose(
            f"The ITTC hull's body-step costs {ns['ITTC hull'] / ns['full']:.2f} times the "
            f"first hull's; its skin friction is "
            f"{100 * (1 - ns['ITTC hull without skin friction'] / ns['ITTC hull']):.0f}% of it "
            f"({ns['ITTC hull'] - ns['ITTC hull without skin friction']:.0f} ns for {plates} "
            f"plates, {(ns['ITTC hull'] - ns['ITTC hull without skin friction']) / plates:.1f} "
            f"ns a plate); the one-sided bottom runs at {ns['ITTC hull, one-sided bottom']:.0f} "
            f"against {ns['ITTC hull']:.0f} ns."
        ),
    ]
    return "\n".join(lines)
