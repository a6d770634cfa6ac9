"""The physics and the scripted pilots, without training (``make pilots``): a paper dart
thrown from 10 m glides to the floor, a buoy dropped into water settles at its waterline, and
on each scene of ``SCENES`` (PaperAirplane-v0, SubmarineWake-v0, BoatOnStep-v0) its scripted
pilot, a random policy and idle controls fly 256 seeded episodes.

    python -m fluidsim_envs.demo [--episodes N] [--seed S]
"""

from __future__ import annotations

import numpy as np

from fluidsim_envs.physics import Buoyancy, Craft, Plate, Simulator, World


def glide() -> None:
    sim = Simulator(Craft.load("paper_airplane"), World(), num_envs=1, dt=1 / 240)
    sim.reset(pos=(0.0, 0.0, 10.0), lin_vel=(6.0, 0.0, 0.0))
    print("paper_airplane thrown at 6 m/s from 10 m (zero controls)")
    print(f"{'t (s)':>6} {'x (m)':>7} {'z (m)':>7} {'speed (m/s)':>12}")
    t = 0.0
    while sim.pos[0, 0, 2] > 0.0 and t < 20.0:
        print(
            f"{t:6.2f} {sim.pos[0, 0, 0]:7.2f} {sim.pos[0, 0, 2]:7.2f} "
            f"{np.linalg.norm(sim.lin_vel[0, 0]):12.2f}"
        )
        sim.step(steps=60)
        t += 0.25


def float_buoy() -> None:
    # a 1 m x 1 m x 0.5 m box of 200 kg: four area samples at its bottom corners (the water's
    # pressure on 0.25 m^2 each) and damping plates; it floats 200 / (1025 * 1) = 0.195 m deep
    corners = [(x, y, -0.25) for x in (-0.5, 0.5) for y in (-0.5, 0.5)]
    buoy = Craft(
        name="buoy",
        mass_kg=200.0,
        inertia_kgm2=(20.8, 20.8, 33.3),
        buoyancy=tuple(
            Buoyancy(f"corner{i}", c, "area", area_m2=0.25) for i, c in enumerate(corners)
        ),
        plates=(Plate("bottom", (0.0, 0.0, -0.25), (0.0, 0.0, 1.0), 1.0),),
    )
    sim = Simulator(buoy, World(water=True), num_envs=1, dt=1 / 120)
    sim.reset(pos=(0.0, 0.0, 0.5))
    print("\nbuoy (200 kg, 1 m^2 footprint) dropped from 0.5 m; rest draft 0.195 m")
    print(f"{'t (s)':>6} {'bottom z (m)':>13}")
    for k in range(13):
        print(f"{k * 0.5:6.1f} {sim.pos[0, 0, 2] - 0.25:13.3f}")
        sim.step(steps=60)


def scenes(num_envs: int = 256, seed: int = 0) -> None:
    """Each registered scene's demo: its scripted pilot against random and idle controls."""
    from fluidsim_envs.scenes import SCENES

    for scene in SCENES.values():
        scene.demo(num_envs=num_envs, seed=seed)


def main(argv: list[str] | None = None) -> None:
    import argparse

    parser = argparse.ArgumentParser(
        prog="python -m fluidsim_envs.demo",
        description=__doc__.split("\n\n")[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--episodes", type=int, default=256, help="seeded episodes per policy")
    parser.add_argument("--seed", type=int, default=0, help="seed of the episodes")
    args = parser.parse_args(argv)
    if args.episodes < 1:
        parser.error(f"--episodes must be at least 1, got {args.episodes}")
    glide()
    float_buoy()
    scenes(num_envs=args.episodes, seed=args.seed)


if __name__ == "__main__":
    main()
