"""Demo (the README's main command until training lands): a paper dart thrown from 10 m
glides to the floor, a buoy dropped into water settles at its waterline, and on
PaperAirplane-v0 the scripted pilot, a random policy and idle controls fly 256 seeded throws;
the same for SubmarineWake-v0 and BoatOnStep-v0.

    python -m fluidsim_envs.demo
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


def fly_task(num_envs: int = 256, seed: int = 0) -> None:
    from fluidsim_envs.controllers import PaperAirplanePilot
    from fluidsim_envs.envs import PaperAirplaneVectorEnv
    from fluidsim_envs.evaluation import first_episodes, random_policy, zero_policy

    venv = PaperAirplaneVectorEnv(num_envs=num_envs)
    dt = venv.params.dt * venv.params.substeps
    print(f"\nPaperAirplane-v0: {num_envs} throws (seed {seed}), one episode each")
    print(f"{'policy':>14} {'return':>15} {'landed':>7} {'success':>8} {'miss (m)':>9}")
    for name, policy in (
        ("scripted pilot", PaperAirplanePilot(num_envs, dt=dt)),
        ("random", random_policy(venv, seed)),
        ("zero controls", zero_policy(venv)),
    ):
        r = first_episodes(venv, policy, seed=seed)
        print(
            f"{name:>14} {r['return'].mean():7.2f} +- {r['return'].std():5.2f} "
            f"{r['landed'].mean():7.1%} {r['success'].mean():8.1%} {r['distance_m'].mean():9.2f}"
        )


def hold_station(num_envs: int = 256, seed: int = 0) -> None:
    from fluidsim_envs.controllers import SubmarineWakePilot
    from fluidsim_envs.envs import SubmarineWakeVectorEnv
    from fluidsim_envs.evaluation import first_episodes, random_policy, zero_policy

    print(f"\nSubmarineWake-v0: {num_envs} episodes (seed {seed}), one each, 60 s")
    print(f"{'policy':>14} {'return':>17} {'on station':>11} {'success':>8} {'crash':>6}")
    for name, wake, policy in (
        ("scripted pilot", True, SubmarineWakePilot()),
        ("  (no wake)", False, SubmarineWakePilot()),
        ("random", True, None),
        ("zero controls", True, None),
    ):
        venv = SubmarineWakeVectorEnv(num_envs=num_envs, wake=wake)
        if policy is None:
            policy = random_policy(venv, seed) if name == "random" else zero_policy(venv)
        r = first_episodes(venv, policy, seed=seed)
        crash = 1.0 - r["truncated"].mean()
        print(
            f"{name:>14} {r['return'].mean():8.1f} +- {r['return'].std():5.1f} "
            f"{r['on_station_fraction'].mean():11.1%} {r['success'].mean():8.1%} {crash:6.1%}"
        )


def run_course(num_envs: int = 256, seed: int = 0) -> None:
    from fluidsim_envs.controllers import BoatOnStepPilot
    from fluidsim_envs.envs import BoatOnStepVectorEnv
    from fluidsim_envs.evaluation import first_episodes, random_policy, zero_policy

    print(f"\nBoatOnStep-v0: {num_envs} courses (seed {seed}), one episode each, 60 s at most")
    print(
        f"{'policy':>14} {'return':>15} {'gates':>6} {'success':>8} {'porpoise':>9} "
        f"{'crash':>6} {'to plane (s)':>13}"
    )
    swell = ((0.2, 40.0, 45.0),)  # 0.4 m crest to trough, 40 m long
    for name, waves, policy in (
        ("scripted pilot", (), BoatOnStepPilot()),
        ("  (in swell)", swell, BoatOnStepPilot()),
        ("random", (), None),
        ("zero controls", (), None),
    ):
        venv = BoatOnStepVectorEnv(num_envs=num_envs, swell=waves)
        if policy is None:
            policy = random_policy(venv, seed) if name == "random" else zero_policy(venv)
        r = first_episodes(venv, policy, seed=seed)
        crash = r["capsized"] | r["bow_stuffed"] | r["left_course"] | r["physics_diverged"]
        planed = r["time_to_plane_s"][r["time_to_plane_s"] >= 0.0]
        to_plane = planed.mean() if planed.size else float("nan")
        print(
            f"{name:>14} {r['return'].mean():7.1f} +- {r['return'].std():5.1f} "
            f"{r['gates_passed'].mean():6.2f} {r['success'].mean():8.1%} "
            f"{r['porpoising_fraction'].mean():9.1%} {crash.mean():6.1%} "
            f"{to_plane:13.1f}"
        )


if __name__ == "__main__":
    glide()
    float_buoy()
    fly_task()
    hold_station()
    run_course()
