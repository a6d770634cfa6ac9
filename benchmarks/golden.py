"""Golden trajectories: a fixed set of simulations and env rollouts, recorded to an ``.npz``,
so that a refactor can show it did not move the physics, bit for bit.

    python -m benchmarks.golden record before.npz     # on the old commit
    python -m benchmarks.golden record after.npz      # on the new one, same machine
    python -m benchmarks.golden compare before.npz after.npz

It imports nothing else from ``benchmarks/``, so that on a commit older than this file (or than
``benchmarks/`` being a package) a copy of it runs as a plain script:
``python /tmp/golden.py record before.npz`` from that checkout.

Only the public API is used (``Simulator``, ``gym.make_vec``), so the same file runs on both
sides of a change of internals. Covered: every shipped craft under every integrator (float64,
and float32 for two), a batch crossing a kernel block boundary (70 envs), contact (a 3-stack
on a ground and a sphere on a height field), swell, the submarine's wake, several bodies per
env, a held external force, ``wrench`` and ``sample_forces``, and the three envs' vector
rollouts (observations, rewards, flags) with random actions, v0 and v1 at each level. Float
results are compared bit for bit: they are reproducible on one machine kind (the kernels
compile for the host).
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

INTEGRATORS = [
    "explicit_euler",
    "symplectic_euler",
    "velocity_verlet",
    "rk2",
    "rk4",
    "verlet_tetra",
]
try:  # the seed's methods (issue 20), where this commit has them
    from fluidsim_envs.physics.integrators import SEED_METHODS

    INTEGRATORS += list(SEED_METHODS)
except ImportError:
    pass
CRAFTS = {  # name -> (water, start height, speed)
    "paper_airplane": (False, 10.0, 6.0),
    "speedboat": (True, 0.1, 8.0),
    "submarine": (True, -20.0, 3.0),
    "uuv": (True, -5.0, 1.5),
    "buoy": (True, 0.0, 0.5),
}


def _state(sim):
    return np.concatenate(
        [
            sim.pos,
            sim.quat,
            sim.lin_vel,
            sim.ang_vel,
            sim.diverged[:, None, None].repeat(sim.num_bodies, 1).astype(sim.pos.dtype),
        ],
        axis=-1,
    )


def _random_start(rng, n, b, z, speed):
    return dict(
        pos=rng.uniform(-1, 1, (n, b, 3)) * (3, 3, 0.3) + (0, 0, z),
        quat=np.array([1.0, 0, 0, 0]) + rng.normal(0, 0.15, (n, b, 4)),
        lin_vel=np.array([speed, 0, 0]) + rng.normal(0, 0.5, (n, b, 3)),
        ang_vel=rng.normal(0, 0.5, (n, b, 3)),
    )


def _run(sim, rng, start, calls=10, steps=4):
    sim.reset(**start)
    n_ch = len(sim.control_names)
    out = []
    for _ in range(calls):
        ctrl = rng.uniform(-1, 1, (sim.num_envs, n_ch)) if n_ch else None
        sim.step(ctrl, steps=steps)
        out.append(_state(sim))
    return np.stack(out)


def physics_cases():
    from fluidsim_envs.physics import Craft, Ground, Shape, Simulator, WakeField, World
    from fluidsim_envs.physics.surface import SwellWave, irregular_sea

    cases = {}
    for name, (water, z, speed) in CRAFTS.items():
        craft = Craft.load(name)
        world = World(water=water, wind_mps=(0.5, -1.0, 0.0) if not water else (0, 0, 0))
        for integ in INTEGRATORS:
            dtypes = [np.float64] + ([np.float32] if integ in ("rk2", "symplectic_euler") else [])
            for dtype in dtypes:
                rng = np.random.default_rng(11)
                sim = Simulator(
                    craft, world, num_envs=70, dt=1 / 120, integrator=integ, dtype=dtype
                )
                key = f"{name}/{integ}/{np.dtype(dtype).name}"
                cases[key] = _run(sim, rng, _random_start(rng, 70, 1, z, speed))
        # wrench and sample forces at a random state
        rng = np.random.default_rng(5)
        sim = Simulator(craft, world, num_envs=70, dt=1 / 120, integrator="rk2")
        sim.reset(**_random_start(rng, 70, 1, z, speed))
        n_ch = len(sim.control_names)
        ctrl = rng.uniform(-1, 1, (70, n_ch)) if n_ch else None
        f, t = sim.wrench(ctrl)
        cases[f"{name}/wrench"] = np.concatenate([f, t], -1)
        pts, frc, body = sim.sample_forces(ctrl, env_index=67)
        cases[f"{name}/sample_forces"] = np.concatenate([pts, frc, body[:, None]], -1)

    # contact: a 3-stack of boxes on a plane, and spheres on a height field
    box = Craft(
        name="box",
        mass_kg=1.0,
        inertia_kgm2=(1 / 6, 1 / 6, 1 / 6),
        shapes=[Shape("b", "box", half_extents_m=(0.5, 0.5, 0.5))],
    )
    heavy = Craft(
        name="heavy",
        mass_kg=20.0,
        inertia_kgm2=(20 / 6, 20 / 6, 20 / 6),
        shapes=[Shape("b", "box", half_extents_m=(0.5, 0.5, 0.5))],
    )
    for integ in INTEGRATORS:
        sim = Simulator(
            [box, box, heavy], World(ground=Ground()), num_envs=3, dt=1 / 128, integrator=integ
        )
        sim.reset(
            pos=np.array([[0, 0, 0.5], [0.05, 0.02, 1.52], [-0.03, 0.0, 2.6]])[None],
            quat=(1, 0, 0, 0),
        )
        rng = np.random.default_rng(2)
        cases[f"contact/stack/{integ}"] = _run(
            sim,
            rng,
            dict(
                pos=np.array([[0, 0, 0.5], [0.05, 0.02, 1.52], [-0.03, 0.0, 2.6]])[None]
                + rng.normal(0, 0.01, (3, 3, 3)),
                quat=np.array([1.0, 0, 0, 0]) + rng.normal(0, 0.02, (3, 3, 4)),
            ),
            calls=40,
            steps=4,
        )
    ball = Craft(
        name="ball",
        mass_kg=2.0,
        inertia_kgm2=(0.08, 0.08, 0.08),
        restitution=0.7,
        shapes=[
            Shape("s", "sphere", radius_m=0.3),
            Shape("c", "box", center_m=(0.2, 0, 0), half_extents_m=(0.2, 0.1, 0.1)),
        ],
    )
    hx = np.linspace(-10, 10, 21)
    heights = 0.3 * np.sin(hx[:, None] * 0.7) * np.cos(hx[None, :] * 0.4)
    try:
        ground = Ground(heights_m=heights, spacing_m=1.0, origin_m=(-10.0, -10.0), restitution=0.6)
    except TypeError:
        ground = Ground(restitution=0.6)
    sim = Simulator([ball, ball], World(ground=ground), num_envs=66, dt=1 / 240, integrator="rk2")
    rng = np.random.default_rng(3)
    cases["contact/field"] = _run(
        sim,
        rng,
        dict(
            pos=rng.uniform(-3, 3, (66, 2, 3)) * (1, 1, 0) + (0, 0, 1.5),
            lin_vel=rng.normal(0, 2, (66, 2, 3)),
            ang_vel=rng.normal(0, 2, (66, 2, 3)),
        ),
        calls=60,
        steps=4,
    )

    # swell under the boat, with buoys (several bodies), and a held external force
    boat, buoy = Craft.load("speedboat"), Craft.load("buoy")
    world = World(
        water=True, swell=[SwellWave(0.4, 12.0, 30.0, 0.3), SwellWave(0.15, 5.0, -70.0, 1.1)]
    )
    for integ in ("symplectic_euler", "rk2", "rk4"):
        sim = Simulator([boat, buoy, buoy], world, num_envs=65, dt=1 / 100, integrator=integ)
        rng = np.random.default_rng(4)
        sim.set_clock(rng.uniform(0, 30, 65))
        sim.set_external_force((0, 50.0, 0), (0, 0, 20.0), env_ids=np.arange(0, 65, 3))
        cases[f"swell/{integ}"] = _run(sim, rng, _random_start(rng, 65, 3, 0.1, 6.0))
        cases[f"swell/{integ}/clock"] = sim.clock.copy()

    # an irregular sea whose water moves (BoatOnStep-v1's: orbital velocities), in both
    # precisions: the sea's loops round each wave into the scratch in float32
    sea = World(water=True, swell=irregular_sea(0.3, 2.5, spread_deg=30.0),
                wave_orbital_velocity=True)  # fmt: skip
    for dtype in (np.float64, np.float32):
        sim = Simulator(boat, sea, num_envs=65, dt=1 / 100, integrator="rk2", dtype=dtype)
        rng = np.random.default_rng(6)
        sim.set_clock(rng.uniform(0, 30, 65))
        cases[f"sea/orbital/{np.dtype(dtype).name}"] = _run(
            sim, rng, _random_start(rng, 65, 1, 0.1, 6.0)
        )

    # the wake: the uuv behind a moving submarine source
    wake = WakeField(length_m=20.0, radius_m=2.0, noise=0.3)
    uuv = Craft.load("uuv")
    for integ in ("symplectic_euler", "rk2", "rk4"):
        for dtype in (np.float64, np.float32):
            sim = Simulator(
                uuv,
                World(water=True),
                num_envs=67,
                dt=1 / 20,
                integrator=integ,
                wake=wake,
                dtype=dtype,
            )
            rng = np.random.default_rng(6)
            start = _random_start(rng, 67, 1, -5.0, 1.5)
            start["pos"] = start["pos"] + (-8.0, 0, 0)
            sim.reset(**start)
            sim.set_wake_source(
                pos=rng.normal(0, 1, (67, 3)) + (0, 0, -5),
                quat=(1, 0, 0, 0),
                lin_vel=(2.0, 0, 0),
                noise_offset=rng.normal(0, 1, (67, 3)),
            )
            out = []
            for _ in range(10):
                sim.step(rng.uniform(-1, 1, (67, len(sim.control_names))), steps=2)
                out.append(_state(sim))
            cases[f"wake/{integ}/{np.dtype(dtype).name}"] = np.stack(out)
    return cases


SCENE_NAMES = ("PaperAirplane", "BoatOnStep", "SubmarineWake")


def env_cases():
    import gymnasium as gym

    import fluidsim_envs  # noqa: F401

    cases = {}
    runs = [(f"fluidsim/{name}-v0", {}) for name in SCENE_NAMES]
    # v1 at each level: every knob of hard (the sea's orbital velocities, turbulence,
    # currents), the sensors' noise and the probes' columns
    runs += [
        (f"fluidsim/{name}-v1", {"difficulty": level})
        for name in SCENE_NAMES
        for level in ("easy", "standard", "hard")
    ]
    for env_id, kwargs in runs:
        venv = gym.make_vec(env_id, num_envs=9, vectorization_mode="vector_entry_point", **kwargs)
        obs, _ = venv.reset(seed=123)
        rng = np.random.default_rng(9)
        rows = [np.concatenate([obs.astype(np.float64), np.zeros((9, 3))], 1)]
        for _ in range(300):
            a = rng.uniform(-1, 1, venv.action_space.shape).astype(np.float32)
            obs, r, term, trunc, _ = venv.step(a)
            rows.append(
                np.concatenate(
                    [obs.astype(np.float64), np.stack([r, term, trunc], 1).astype(np.float64)], 1
                )
            )
        venv.close()
        level = f"/{kwargs['difficulty']}" if kwargs else ""
        cases[f"env/{env_id}{level}"] = np.stack(rows)
    return cases


def record(path):
    cases = physics_cases()
    cases.update(env_cases())
    np.savez_compressed(path, **{k.replace("/", "|"): v for k, v in cases.items()})
    print(f"recorded {len(cases)} cases to {path}")


def compare(a_path, b_path):
    a, b = np.load(a_path), np.load(b_path)
    bad = 0
    new = sorted(set(b.files) - set(a.files))
    if new:  # cases the later commit added (a new integrator): nothing to compare them with
        print(f"{len(new)} cases only in {b_path}, not compared: {', '.join(new[:4])} ...")
    for key in sorted(set(a.files) & set(b.files)) + sorted(set(a.files) - set(b.files)):
        if key not in b.files:
            print(f"MISSING {key}")
            bad += 1
            continue
        x, y = a[key], b[key]
        same = x.shape == y.shape and np.array_equal(x.view(np.uint8), y.view(np.uint8))
        if not same:
            bad += 1
            diff = np.nanmax(np.abs(x - y)) if x.shape == y.shape else "shape"
            print(f"DIFF {key.replace('|', '/')}: max |diff| {diff}")
    print(f"{len(a.files) - bad} of {len(a.files)} cases bit-identical")
    return bad == 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        description=__doc__.splitlines()[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    sub = parser.add_subparsers(dest="command", required=True)
    rec = sub.add_parser("record", help="run the cases and save them to an .npz")
    rec.add_argument("path")
    cmp = sub.add_parser("compare", help="exit 1 unless the two recordings are bit-identical")
    cmp.add_argument("before")
    cmp.add_argument("after")
    args = parser.parse_args(argv)
    if args.command == "record":
        record(args.path)
        return 0
    return 0 if compare(args.before, args.after) else 1


if __name__ == "__main__":
    sys.exit(main())
