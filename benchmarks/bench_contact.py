"""What contact costs (physics/contact.py): the step kernel on scenes that touch, against the
same bodies falling free in the same run.

Scenes, each at E = 4096 environments (float64, symplectic Euler, dt = 1/120, the parallel
kernel on all threads), already settled before timing so that every contact is live:

- a box resting on the ground (one face patch), and the same box falling with no ground;
- a ball rolling on a height field (one point contact);
- three boxes stacked (three ground tests, three pairs, two of them touching), with 1 and
  with 4 velocity passes;
- a box and two balls in a heap (four touching pairs).

For each: body-steps per second (the best of ``--repeats`` calls of ~0.3 s each) and the
time a contact-resolving body-step takes over a free one.

Writes ``docs/bench_contact.csv`` (machine in ``#`` lines).

    python -m benchmarks.bench_contact [--quick]
"""

from __future__ import annotations

import numpy as np

from benchmarks.common import arguments, best_of, describe, sized, write_csv
from fluidsim_envs.physics import Craft, Ground, Shape, Simulator, World

NUM_ENVS = 4096
DT = 1.0 / 120.0


def box(name="box", half=0.25, mass=2.0):
    inertia = mass / 3.0 * 2 * half**2
    return Craft(
        name=name,
        mass_kg=mass,
        inertia_kgm2=(inertia,) * 3,
        shapes=[Shape("b", "box", half_extents_m=(half,) * 3)],
        restitution=0.3,
        friction=0.6,
    )


def ball(name="ball", radius=0.2, mass=1.0):
    return Craft(
        name=name,
        mass_kg=mass,
        inertia_kgm2=(0.4 * mass * radius**2,) * 3,
        shapes=[Shape("s", "sphere", radius_m=radius)],
        restitution=0.3,
        friction=0.6,
    )


def scenes():
    hills = Ground(heights_m=np.sin(np.linspace(0, 6, 32))[None, :].repeat(32, 0) * 0.5)
    stack = [box("a"), box("b"), box("c")]
    start = [[0.0, 0.0, 0.25], [0.03, 0.0, 0.75], [-0.03, 0.015, 1.25]]
    return {
        "box falling, no ground": ([box()], World(), [[0.0, 0.0, 1e4]], "free"),
        "box resting on the ground": ([box()], World(ground=Ground()), [[0, 0, 0.25]], ""),
        "ball rolling on a height field": (
            [ball()],
            World(ground=hills),
            [[3.0, 5.0, 1.0]],
            "",
        ),
        "stack of 3 boxes, 1 pass": (stack, World(ground=Ground()), start, ""),
        "stack of 3 boxes, 4 passes": (
            stack,
            World(ground=Ground(), contact_passes=4),
            start,
            "",
        ),
        "box and two balls in a heap": (
            [box("a"), ball("b"), ball("c")],
            World(ground=Ground()),
            [[0.0, 0.0, 0.25], [0.1, 0.0, 0.7], [-0.15, 0.05, 1.1]],
            "",
        ),
    }


def rate(crafts, world, start, seconds: float, repeats: int) -> float:
    sim = Simulator(crafts, world, num_envs=NUM_ENVS, dt=DT, parallel=True)
    sim.reset(pos=np.asarray(start)[None])
    sim.step(steps=240)  # compile, settle
    state = [np.array(a) for a in (sim.pos, sim.quat, sim.lin_vel, sim.ang_vel)]
    steps = sized(lambda n: sim.step(steps=n), seconds, probe=4)
    best = best_of(lambda: sim.step(steps=steps), repeats, lambda: sim.reset(*state), warmup=False)
    return NUM_ENVS * len(crafts) * steps / best


def main() -> None:
    parser = arguments(__doc__, "shorter, noisier runs", "bench_contact.csv")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    seconds, repeats = (0.1, 1) if args.quick else (0.3, args.repeats)

    machine = describe()
    rows = []
    free = None
    for label, (crafts, world, start, kind) in scenes().items():
        r = rate(crafts, world, start, seconds, repeats)
        ns = 1e9 / r
        free = ns if kind == "free" else free
        extra = ns - free
        rows.append((label, len(crafts), r, ns, extra))
        print(f"{label:32s} B={len(crafts)} {r:14,.0f} body-steps/s {ns:7.0f} ns (+{extra:.0f})")
    out = write_csv(
        args.out,
        ("scene", "bodies", "body_steps_per_s", "ns_per_body_step", "ns_over_free"),
        [(label, b, f"{r:.1f}", f"{ns:.1f}", f"{extra:.1f}") for label, b, r, ns, extra in rows],
        machine,
    )
    print(f"\nwrote {out}")


if __name__ == "__main__":
    main()
