"""Model cost: what each part of the physics costs per scene, and what leaving it out changes.

Two levels, each measured side by side in one run (costs of the variants of one subject are
timed in interleaved repeats, so that other work on the machine hits them alike):

**Craft level** (``Simulator`` only; the env's default integrator and dt, rk2, float64). For each
shipped craft and a fixed open-loop maneuver, the craft is rebuilt with one group of fluid
samples left out at a time (``dataclasses.replace`` on the loaded ``Craft``, plates by name
prefix as in ``benchmarks/bench_boat.py``; a control surface that is left out is also dropped
from its control channel, which stays, so the control array keeps its shape):

- ``paper_airplane`` in ``World()``: thrown level at 6 m/s, 10 m up, rolled 10 deg, elevator
  +0.1, for 6 s at dt = 1/120 s. Groups: wings, stabilizers, fin, nose plate, fuselage
  cylinders, control surfaces (ailerons, elevators, rudder). Scene quantities: glide ratio
  (horizontal distance over height lost) and airspeed at the end.
- ``speedboat`` in ``World(water=True)``: full throttle, rudder 0.1, from rest at its floating
  height and trim (``hydrostatics.static_float``) for 10 s at dt = 1/100 s. Groups: bottom
  plates, skin-friction plates, topsides, skeg/stem/windscreen, control surfaces (rudder, trim
  tabs), buoyancy columns. Scene quantities: top speed (horizontal) and trim at the end.
- ``uuv`` in ``World(water=True)``: thrust 0.7 (84 N ahead), rudder 0.3, dive planes -0.2 from
  rest 10 m down, for 10 s at dt = 1/20 s. Groups: hull cylinders, nose plate, rudder fins,
  dive planes, buoyancy volumes. Scene quantities: depth change and heading change.
- ``buoy`` (BoatOnStep-v0's buoy body) in ``World(water=True)``: released 0.1 m below its
  floating height and moving sideways at 0.5 m/s (as a hull's knock leaves it), for 4 s at
  dt = 1/100 s. Groups: damping plates, drag cylinder, waterplane (buoyancy) samples. Scene
  quantities: heave left in the last second (largest distance from the floating height) and
  the drift (horizontal distance covered).

Cost: wall time per body-step of ``sim.step(controls, steps=100)`` from the maneuver's start
at E = 1024 environments on one thread (the serial kernel, as ``docs/study.md``: on a shared
2-core machine one thread is the least disturbed), the minimum over ``--repeats`` (40) interleaved
repeats; reported in ns and as a share of the full craft's cost. Change: one environment run
through the maneuver, its final position (m) and attitude (deg, the angle of the relative
rotation) against the full craft's, and the scene quantities.

The paper airplane's floor (PaperAirplane-v0 has no parameter to turn it off): the dart in
``World(ground=Ground(0.5, 0.5))`` (the env's world) against ``World()``, thrown level at
6 m/s from 4 m with elevator +0.1: the cost per body-step (same method) over the first second
(airborne) and over the whole 6 s (touchdown near 2.5 s, then sliding and at rest), and how far
the resting dart lies from where the floorless one passes its resting height.

**Scene level** (the vector envs). Task metrics: ``evaluation.first_episodes`` with the scene's
scripted pilot, one episode in each of ``--episodes`` seeded sub-envs (seed 0) per variant;
per-step info (SubmarineWake-v0's ``station_distance_m``, BoatOnStep-v0's ``hit_buoy``) is
gathered through a thin proxy of the vector env. Cost: env-steps per second at 1024 envs with
random actions (drawn beforehand), as ``benchmarks/bench_envs.py`` measures it, the best of
``--repeats`` interleaved runs of ``--seconds`` each; every env runs its default kernel choice
(the parallel kernel at 1024 envs, both threads). Variants: SubmarineWake-v0 with and without
its wake, and with sub-env 0 rendered (``render_mode="rgb_array"``, one frame, so that its
tracers are advanced every step: bench_envs' "+tracers"); BoatOnStep-v0 calm, in a one-wave
swell (0.2 m amplitude, 40 m long, from 45 deg: the swell of ``fluidsim_envs/demo.py``) and
with ``buoy_bodies=True``; PaperAirplane-v0 as shipped.

Writes ``docs/study_model_cost.csv`` (one number a row: part, subject, variant, quantity,
value, unit; the machine in ``#`` lines) and ``docs/study_model_cost.png``, and prints the
markdown tables that ``docs/study_model_cost.md`` quotes::

    python -m benchmarks.study_model_cost            # full size, about 70 s on 2 cores
    python -m benchmarks.study_model_cost --quick    # 20 s, into build/study_quick
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numba
import numpy as np

from benchmarks.bench_envs import actions_for, stepping
from benchmarks.common import (
    arguments,
    describe,
    interleaved_best,
    load_average,
    out_dir,
    prose,
    rate_over,
    timed,
    write_csv,
)
from fluidsim_envs.controllers import BoatOnStepPilot, PaperAirplanePilot, SubmarineWakePilot
from fluidsim_envs.envs import BoatOnStepVectorEnv, PaperAirplaneVectorEnv, SubmarineWakeVectorEnv
from fluidsim_envs.evaluation import first_episodes
from fluidsim_envs.physics import Craft, Ground, Simulator, World
from fluidsim_envs.physics.hydrostatics import static_float
from fluidsim_envs.physics.kernels import quat_matrices

COST_ENVS = 1024
COST_STEPS = 100
RATE_ENVS = 1024
SWELL = ((0.2, 40.0, 45.0),)  # demo.py's: 0.4 m crest to trough, 40 m long

# ---- craft level ----------------------------------------------------------------------------


def without(craft: Craft, prefixes: tuple[str, ...]) -> Craft:
    """``craft`` with every plate, cylinder and buoyancy sample whose name starts with one of
    ``prefixes`` left out; control channels keep their names but lose the surfaces left out."""

    def keep(samples):
        return tuple(s for s in samples if not s.name.startswith(prefixes))

    plates, cylinders = keep(craft.plates), keep(craft.cylinders)
    names = {s.name for s in plates + cylinders}
    controls = tuple(
        replace(c, surfaces=tuple(s for s in c.surfaces if s.sample in names))
        for c in craft.controls
    )
    return replace(
        craft,
        plates=plates,
        cylinders=cylinders,
        buoyancy=keep(craft.buoyancy),
        controls=controls,
        groups=(),  # a group naming a sample left out is refused (Craft.groups)
    )


def samples(craft: Craft) -> int:
    return len(craft.plates) + len(craft.cylinders) + len(craft.buoyancy) + len(craft.thrusters)


def quat_about(axis: int, angle: float) -> tuple:
    q = [math.cos(angle / 2), 0.0, 0.0, 0.0]
    q[1 + axis] = math.sin(angle / 2)
    return tuple(q)


INTEGRATOR = "rk2"  # the envs' (docs/study.md, Reading)


@dataclass
class Case:
    """A craft, its world and maneuver, its groups and the scene quantities."""

    name: str
    craft: Craft
    world: World
    dt: float
    seconds: float
    start: dict
    controls: tuple
    groups: dict  # label -> name prefixes left out
    quantities: Callable  # history -> {name: (value, unit)}

    def variants(self) -> dict[str, Craft]:
        out = {"full": self.craft}
        for label, prefixes in self.groups.items():
            out[f"without {label}"] = without(self.craft, prefixes)
        return out

    def control_array(self, num_envs: int):
        if not self.controls:
            return None
        return np.tile(np.asarray(self.controls, dtype=np.float64), (num_envs, 1))


def heading_deg(q) -> float:
    r = quat_matrices(np.ascontiguousarray(np.asarray(q, dtype=np.float64)[None]))[0]
    return math.degrees(math.atan2(r[1, 0], r[0, 0]))


def pitch_deg(q) -> float:
    r = quat_matrices(np.ascontiguousarray(np.asarray(q, dtype=np.float64)[None]))[0]
    return math.degrees(math.asin(max(-1.0, min(1.0, r[2, 0]))))


def airplane_quantities(h: dict) -> dict:
    p, v = h["pos"], h["vel"]
    run = float(np.hypot(*(p[-1, :2] - p[0, :2])))
    drop = float(p[0, 2] - p[-1, 2])
    ratio = run / drop if drop > 0 else math.inf
    return {"glide_ratio": (ratio, "1"), "final_speed": (float(np.linalg.norm(v[-1])), "m/s")}


def boat_quantities(h: dict) -> dict:
    top = float(np.hypot(h["vel"][:, 0], h["vel"][:, 1]).max())
    return {"top_speed": (top, "m/s"), "final_trim": (pitch_deg(h["quat"][-1]), "deg")}


def uuv_quantities(h: dict) -> dict:
    turn = heading_deg(h["quat"][-1]) - heading_deg(h["quat"][0])
    turn = (turn + 180.0) % 360.0 - 180.0
    depth = float(h["pos"][0, 2] - h["pos"][-1, 2])  # + deeper
    return {"depth_change": (depth, "m"), "heading_change": (turn, "deg")}


def buoy_quantities(rest_z: float):
    def q(h: dict) -> dict:
        last = h["t"] >= h["t"][-1] - 1.0
        z = h["pos"][last, 2]
        return {
            "heave_left": (float(np.abs(z - rest_z).max()), "m"),
            "drift": (float(np.hypot(*(h["pos"][-1, :2] - h["pos"][0, :2]))), "m"),
        }

    return q


def cases() -> list[Case]:
    boat = Craft.load("speedboat")
    boat_z, boat_trim = static_float(boat)
    buoy = Craft.load("buoy")
    buoy_z, _ = static_float(buoy)
    water = World(water=True)
    return [
        Case(
            "paper_airplane",
            Craft.load("paper_airplane"),
            World(),
            1 / 120,
            6.0,
            dict(pos=(0.0, 0.0, 10.0), lin_vel=(6.0, 0.0, 0.0), quat=quat_about(0, 0.1745)),
            (0.0, 0.1, 0.0),
            {
                "wings": ("left_wing", "right_wing"),
                "stabilizers": ("left_stabilizer", "right_stabilizer"),
                "fin": ("fin",),
                "nose plate": ("nose",),
                "fuselage cylinders": ("fuselage",),
                "control surfaces": ("left_aileron", "right_aileron", "left_elevator")
                + ("right_elevator", "rudder"),
            },
            airplane_quantities,
        ),
        Case(
            "speedboat",
            boat,
            water,
            1 / 100,
            10.0,
            dict(pos=(0.0, 0.0, boat_z), quat=quat_about(1, -boat_trim)),
            (1.0, 0.1, 0.0),
            {
                "bottom plates": ("bottom",),
                "friction plates": ("friction",),
                "topsides": ("topside",),
                "skeg, stem, windscreen": ("skeg", "stem", "windscreen"),
                "control surfaces": ("rudder", "tab_"),
                "buoyancy columns": ("volume",),
            },
            boat_quantities,
        ),
        Case(
            "uuv",
            Craft.load("uuv"),
            water,
            1 / 20,
            10.0,
            dict(pos=(0.0, 0.0, -10.0)),
            (0.7, 0.3, -0.2),  # 84 N: what 0.6 gave before control 0 was no thrust
            {
                "hull cylinders": ("hull",),
                "nose plate": ("nose",),
                "rudder fins": ("upper_fin", "lower_fin"),
                "dive planes": ("port_plane", "starboard_plane"),
                "buoyancy volumes": ("fore_volume", "aft_volume"),
            },
            uuv_quantities,
        ),
        Case(
            "buoy",
            buoy,
            water,
            1 / 100,
            4.0,
            dict(pos=(0.0, 0.0, buoy_z - 0.1), lin_vel=(0.5, 0.0, 0.0)),
            (),
            {
                "damping plates": ("damping",),
                "drag cylinder": ("drag",),
                "waterplane buoyancy": ("waterplane",),
            },
            buoy_quantities(buoy_z),
        ),
    ]


def trajectory(craft: Craft, case: Case, world: World | None = None, seconds=None) -> dict:
    """One environment through the maneuver: history of t, pos, quat, lin_vel every 0.05 s."""
    sim = Simulator(
        craft, world or case.world, num_envs=1, dt=case.dt, integrator=INTEGRATOR, parallel=False
    )
    sim.reset(**case.start)
    ctrl = case.control_array(1)
    chunk = max(1, round(0.05 / case.dt))
    n = round((seconds or case.seconds) / case.dt)
    t, pos, quat, vel = [0.0], [sim.pos[0, 0].copy()], [sim.quat[0, 0].copy()], []
    vel.append(sim.lin_vel[0, 0].copy())
    done = 0
    while done < n:
        k = min(chunk, n - done)
        sim.step(ctrl, steps=k)
        done += k
        t.append(done * case.dt)
        pos.append(sim.pos[0, 0].copy())
        quat.append(sim.quat[0, 0].copy())
        vel.append(sim.lin_vel[0, 0].copy())
    return {"t": np.array(t), "pos": np.array(pos), "quat": np.array(quat), "vel": np.array(vel)}


def attitude_deg(q, q_ref) -> float:
    """Angle of the rotation between two attitudes (deg): 4 atan(|q - q_ref| / |q + q_ref|),
    stable near zero."""
    q, q_ref = np.asarray(q), np.asarray(q_ref) * (1.0 if np.dot(q, q_ref) >= 0 else -1.0)
    return math.degrees(4.0 * math.atan2(np.linalg.norm(q - q_ref), np.linalg.norm(q + q_ref)))


def interleaved_costs(sims: dict, start: dict, ctrl, repeats: int, steps: int) -> dict:
    """ns per body-step of ``step(ctrl, steps)`` for each simulator, min over repeats taken in
    turn (variant a, b, c, a, b, c, ...), so that a change of load hits them alike."""
    for sim in sims.values():
        sim.reset(**start)
        sim.step(ctrl, steps=1)  # load the kernel

    def call(sim):
        return lambda: timed(lambda: sim.step(ctrl, steps=steps), lambda: sim.reset(**start))

    best = interleaved_best({label: call(sim) for label, sim in sims.items()}, repeats)
    return {k: 1e9 * v / (steps * COST_ENVS * sims[k].num_bodies) for k, v in best.items()}


def craft_level(repeats: int, rows: list) -> None:
    for case in cases():
        variants = case.variants()
        sims = {
            label: Simulator(c, case.world, COST_ENVS, case.dt, INTEGRATOR, parallel=False)
            for label, c in variants.items()
        }
        ns = interleaved_costs(sims, case.start, case.control_array(COST_ENVS), repeats, COST_STEPS)
        ref = trajectory(case.craft, case)
        print(f"\n{case.name} (dt = 1/{round(1 / case.dt)} s, {case.seconds:g} s maneuver)")
        for label, craft in variants.items():
            h = ref if label == "full" else trajectory(craft, case)
            finite = bool(np.isfinite(h["pos"]).all() and np.isfinite(h["quat"]).all())
            dpos = float(np.linalg.norm(h["pos"][-1] - ref["pos"][-1])) if finite else math.nan
            datt = attitude_deg(h["quat"][-1], ref["quat"][-1]) if finite else math.nan
            q = case.quantities(h) if finite else {}
            out = [
                ("samples", samples(craft), "1"),
                ("ns_per_body_step", ns[label], "ns"),
                ("share_of_full_cost", ns[label] / ns["full"], "1"),
                ("final_pos_diff", dpos, "m"),
                ("final_att_diff", datt, "deg"),
            ] + [(k, v, u) for k, (v, u) in q.items()]
            for quantity, value, unit in out:
                rows.append(("craft", case.name, label, quantity, value, unit))
            qs = "  ".join(f"{k} {v:8.3f} {u}" for k, (v, u) in q.items()) or "diverged"
            print(
                f"  {label:30s} {samples(craft):3d} {ns[label]:7.1f} ns "
                f"{ns[label] / ns['full']:6.1%}  dpos {dpos:8.3f} m  datt {datt:7.2f} deg  {qs}"
            )


def floor_level(repeats: int, rows: list) -> None:
    """The paper airplane with and without the env's floor, at the Simulator level."""
    dart = Craft.load("paper_airplane")
    worlds = {"floor": World(ground=Ground(restitution=0.5, friction=0.5)), "no floor": World()}
    case = Case("paper_airplane", dart, World(), 1 / 120, 6.0, {}, (0.0, 0.1, 0.0), {}, None)
    case.start = dict(pos=(0.0, 0.0, 4.0), lin_vel=(6.0, 0.0, 0.0))
    ctrl = case.control_array(COST_ENVS)
    sims = {
        k: Simulator(dart, w, COST_ENVS, case.dt, INTEGRATOR, parallel=False)
        for k, w in worlds.items()
    }
    windows = {"airborne 1 s": round(1 / case.dt), "glide and landing 6 s": round(6 / case.dt)}
    ns = {
        name: interleaved_costs(sims, case.start, ctrl, repeats, steps)
        for name, steps in windows.items()
    }
    h = {k: trajectory(dart, case, w) for k, w in worlds.items()}
    landed, free = h["floor"], h["no floor"]
    rest_z = landed["pos"][-1, 2]
    below = np.nonzero(free["pos"][:, 2] <= rest_z)[0]
    print(f"\npaper_airplane floor contact (from 4 m, 6 s; rests at z = {rest_z:.3f} m)")
    for window in windows:
        for k in worlds:
            r = ns[window][k] / ns[window]["no floor"]
            rows.append(
                ("floor", "paper_airplane", k, f"ns_per_body_step, {window}", ns[window][k], "ns")
            )
            rows.append(("floor", "paper_airplane", k, f"cost_vs_no_floor, {window}", r, "1"))
            print(f"  {window:22s} {k:9s} {ns[window][k]:7.1f} ns  x{r:.3f}")
    if below.size:
        i = below[0]
        z0, z1 = free["pos"][i - 1, 2], free["pos"][i, 2]
        f = (z0 - rest_z) / (z0 - z1)
        cross = free["pos"][i - 1] + f * (free["pos"][i] - free["pos"][i - 1])
        slide = float(np.hypot(*(landed["pos"][-1, :2] - cross[:2])))
        t_cross = free["t"][i - 1] + f * (free["t"][i] - free["t"][i - 1])
        rows.append(("floor", "paper_airplane", "floor", "rest_vs_floorless_crossing", slide, "m"))
        rows.append(("floor", "paper_airplane", "no floor", "crossing_time", t_cross, "s"))
        print(
            f"  rests {slide:.2f} m from where the floorless dart passes z = {rest_z:.3f} m "
            f"(at {t_cross:.2f} s)"
        )


# ---- scene level ----------------------------------------------------------------------------


class Gather:
    """A vector env seen by ``first_episodes``, summing per-step info entries over each
    sub-env's first episode (``sums[key]``, ``steps``) on the way."""

    def __init__(self, venv, keys: tuple[str, ...]) -> None:
        self.venv, self.keys, self.num_envs = venv, keys, venv.num_envs
        self.sums = {k: np.zeros(venv.num_envs) for k in keys}
        self.steps = np.zeros(venv.num_envs)
        self.done = np.zeros(venv.num_envs, dtype=bool)

    def reset(self, **kwargs):
        self.done[:] = False
        self.steps[:] = 0.0
        for s in self.sums.values():
            s[:] = 0.0
        return self.venv.reset(**kwargs)

    def step(self, actions):
        obs, reward, terminated, truncated, info = self.venv.step(actions)
        ended = terminated | truncated
        running = ~self.done
        for k in self.keys:
            value = np.where(ended, info["final_info"][k], info[k]) if ended.any() else info[k]
            self.sums[k][running] += np.asarray(value, dtype=np.float64)[running]
        self.steps[running] += 1
        self.done |= ended
        return obs, reward, terminated, truncated, info


def episodes(make, pilot, keys: tuple[str, ...], n: int) -> tuple[dict, Gather]:
    g = Gather(make(n), keys)
    r = first_episodes(g, pilot(g.venv), seed=0)
    g.venv.close()
    return r, g


def interleaved_rates(makers: dict, seconds: float, repeats: int) -> dict:
    """env-steps/s at RATE_ENVS of each variant on 1 and on all numba threads, keyed
    ``(scene, label, threads)``, best of repeats taken in turn."""
    built = {}
    for label, (make, watch) in makers.items():
        venv = make(RATE_ENVS)
        acts = actions_for(venv.action_space, 16, np.random.default_rng(0))
        venv.reset(seed=0)
        if watch:  # one frame of sub-env 0 starts its tracers; steps then advance them
            venv._frame(0)
        run = stepping(venv, acts)
        run()  # compile / warm
        built[label] = (venv, run)
    threads = sorted({1, numba.config.NUMBA_NUM_THREADS})
    calls = {
        (*label, k): lambda run=run: rate_over(run, seconds)
        for k in threads
        for label, (_, run) in built.items()
    }
    best = interleaved_best(
        calls, repeats, best=max, before=lambda key: numba.set_num_threads(key[-1])
    )
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    for venv, _ in built.values():
        venv.close()
    return best


def scene_level(n_episodes: int, seconds: float, repeats: int, rows: list) -> None:
    sub, boat, dart = "SubmarineWake-v0", "BoatOnStep-v0", "PaperAirplane-v0"
    makers = {
        (sub, "wake (default)"): (lambda n: SubmarineWakeVectorEnv(num_envs=n), False),
        (sub, "wake=False"): (lambda n: SubmarineWakeVectorEnv(num_envs=n, wake=False), False),
        (sub, "wake, +tracers of sub-env 0"): (
            lambda n: SubmarineWakeVectorEnv(num_envs=n, render_mode="rgb_array"),
            True,
        ),
        (boat, "calm (default)"): (lambda n: BoatOnStepVectorEnv(num_envs=n), False),
        (boat, "swell"): (lambda n: BoatOnStepVectorEnv(num_envs=n, swell=SWELL), False),
        (boat, "buoy_bodies=True"): (
            lambda n: BoatOnStepVectorEnv(num_envs=n, buoy_bodies=True),
            False,
        ),
        (dart, "floor (default)"): (lambda n: PaperAirplaneVectorEnv(num_envs=n), False),
    }
    rates = interleaved_rates(makers, seconds, repeats)
    default = {sub: "wake (default)", boat: "calm (default)", dart: "floor (default)"}
    print(f"\nenv-steps/s at {RATE_ENVS} envs (random actions)")
    for (scene, label, k), r in rates.items():
        ratio = r / rates[(scene, default[scene], k)]
        t = f"{k} thread" + ("s" if k > 1 else "")
        rows.append(("scene", scene, label, f"env_steps_per_s, {t}", r, "1/s"))
        rows.append(("scene", scene, label, f"rate_vs_default, {t}", ratio, "1"))
        print(f"  {t:9s} {scene:18s} {label:30s} {r:12,.0f}  x{ratio:.3f}")

    def add(scene, label, quantity, value, unit="1"):
        rows.append(("scene", scene, label, quantity, float(value), unit))

    print(f"\npilot, one episode in each of {n_episodes} seeded sub-envs (seed 0)")
    for label, wake in (("wake (default)", True), ("wake=False", False)):
        t0 = time.perf_counter()
        r, g = episodes(
            lambda n, w=wake: SubmarineWakeVectorEnv(num_envs=n, wake=w),
            lambda v: SubmarineWakePilot(),
            ("station_distance_m",),
            n_episodes,
        )
        err = g.sums["station_distance_m"] / np.maximum(g.steps, 1)
        crash = 1.0 - r["truncated"].mean()
        add(sub, label, "return_mean", r["return"].mean())
        add(sub, label, "success", r["success"].mean())
        add(sub, label, "on_station_fraction", r["on_station_fraction"].mean())
        add(sub, label, "station_error_mean", err.mean(), "m")
        add(sub, label, "crash_or_lost", crash)
        print(
            f"  {sub} {label:16s} return {r['return'].mean():7.1f}  success "
            f"{r['success'].mean():6.1%}  on station {r['on_station_fraction'].mean():6.1%}  "
            f"station error {err.mean():5.2f} m  crash {crash:5.1%}  "
            f"({time.perf_counter() - t0:.1f} s)"
        )
    for label, kwargs in (
        ("calm (default)", {}),
        ("swell", {"swell": SWELL}),
        ("buoy_bodies=True", {"buoy_bodies": True}),
    ):
        t0 = time.perf_counter()
        r, g = episodes(
            lambda n, kw=kwargs: BoatOnStepVectorEnv(num_envs=n, **kw),
            lambda v: BoatOnStepPilot(),
            ("hit_buoy",),
            n_episodes,
        )
        crash = r["capsized"] | r["bow_stuffed"] | r["left_course"] | r["physics_diverged"]
        hit = g.sums["hit_buoy"] > 0
        planed = r["time_to_plane_s"][r["time_to_plane_s"] >= 0.0]
        add(boat, label, "return_mean", r["return"].mean())
        add(boat, label, "success", r["success"].mean())
        add(boat, label, "gates_passed_mean", r["gates_passed"].mean())
        add(boat, label, "porpoising_fraction", r["porpoising_fraction"].mean())
        add(boat, label, "crash", crash.mean())
        add(boat, label, "episodes_hitting_a_buoy", hit.mean())
        add(boat, label, "buoy_contact_steps_mean", g.sums["hit_buoy"].mean())
        add(boat, label, "time_to_plane_mean", planed.mean() if planed.size else math.nan, "s")
        print(
            f"  {boat} {label:16s} return {r['return'].mean():7.1f}  success "
            f"{r['success'].mean():6.1%}  gates {r['gates_passed'].mean():5.2f}  porpoising "
            f"{r['porpoising_fraction'].mean():6.1%}  crash {crash.mean():5.1%}  hit a buoy "
            f"{hit.mean():6.1%}  ({time.perf_counter() - t0:.1f} s)"
        )
    t0 = time.perf_counter()
    r, _ = episodes(
        lambda n: PaperAirplaneVectorEnv(num_envs=n),
        lambda v: PaperAirplanePilot(v.num_envs, dt=v.params.dt * v.params.substeps),
        (),
        n_episodes,
    )
    label = "floor (default)"
    add(dart, label, "return_mean", r["return"].mean())
    add(dart, label, "landed", r["landed"].mean())
    add(dart, label, "success", r["success"].mean())
    add(dart, label, "miss_mean", r["distance_m"].mean(), "m")
    print(
        f"  {dart} {label:16s} return {r['return'].mean():7.2f}  landed {r['landed'].mean():6.1%}"
        f"  success {r['success'].mean():6.1%}  miss {r['distance_m'].mean():5.2f} m  "
        f"({time.perf_counter() - t0:.1f} s)"
    )


# ---- output ---------------------------------------------------------------------------------


def fmt(x) -> str:
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if not math.isfinite(x):
        return "nan"
    return f"{x:.6g}"


def write_rows(path: Path, machine: list[str], rows: list) -> None:
    write_csv(
        path,
        ("part", "subject", "variant", "quantity", "value", "unit"),
        [(*row[:4], fmt(row[4]), row[5]) for row in rows],
        machine,
    )


def lookup(rows: list) -> dict:
    return {(r[0], r[1], r[2], r[3]): r[4] for r in rows}


def markdown(rows: list) -> str:
    """The tables docs/study_model_cost.md quotes."""
    v = lookup(rows)
    out = []
    for case in cases():
        qs = [r[3] for r in rows if r[:3] == ("craft", case.name, "full")][5:]
        out.append(f"\n{case.name}\n")
        head = "| left out | samples | ns per body-step | share of full | position diff (m) "
        head += "| attitude diff (deg) | " + " | ".join(qs) + " |"
        out.append(head)
        out.append("|---" + "|---:" * (5 + len(qs)) + "|")
        for label in case.variants():
            k = ("craft", case.name, label)
            cells = [
                str(int(v[(*k, "samples")])),
                f"{v[(*k, 'ns_per_body_step')]:.1f}",
                f"{100 * v[(*k, 'share_of_full_cost')]:.0f}%",
                f"{v[(*k, 'final_pos_diff')]:.3g}",
                f"{v[(*k, 'final_att_diff')]:.3g}",
            ] + [f"{v[(*k, q)]:.3g}" if (*k, q) in v else "diverged" for q in qs]
            name = "nothing (full)" if label == "full" else label.removeprefix("without ")
            out.append(f"| {name} | " + " | ".join(cells) + " |")
    scene_rows = [r for r in rows if r[0] == "scene"]
    for scene in dict.fromkeys(r[1] for r in scene_rows):
        labels = list(dict.fromkeys(r[2] for r in scene_rows if r[1] == scene))
        qs = list(dict.fromkeys(r[3] for r in scene_rows if r[1] == scene))
        out.append(f"\n{scene}\n")
        out.append("| variant | " + " | ".join(qs) + " |")
        out.append("|---" + "|---:" * len(qs) + "|")
        for label in labels:
            cells = [
                f"{v[('scene', scene, label, q)]:.4g}" if ("scene", scene, label, q) in v else ""
                for q in qs
            ]
            out.append(f"| {label} | " + " | ".join(cells) + " |")
    floor = [r for r in rows if r[0] == "floor"]
    out.append("\npaper_airplane floor\n")
    out.extend(f"| {r[2]} | {r[3]} | {r[4]:.4g} {r[5]} |" for r in floor)
    return "\n".join(out)


def plot(rows: list, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    v = lookup(rows)
    crafts = cases()
    fig = plt.figure(figsize=(16, 9.5))
    grid = fig.add_gridspec(2, len(crafts), height_ratios=(1.0, 0.9))
    for i, case in enumerate(crafts):
        ax = fig.add_subplot(grid[0, i])
        labels = list(case.variants())
        share = [100 * v[("craft", case.name, lb, "share_of_full_cost")] for lb in labels]
        dpos = [v[("craft", case.name, lb, "final_pos_diff")] for lb in labels]
        y = np.arange(len(labels))[::-1]
        ax.barh(y, share, color=["0.4"] + ["tab:blue"] * (len(labels) - 1))
        for yi, s, d in zip(y, share, dpos, strict=True):
            note = "" if d == 0 else ("diverged" if not math.isfinite(d) else f"Δpos {d:.3g} m")
            ax.text(s + 1, yi, note, va="center", fontsize=8)
        ax.set_yticks(y, [lb.removeprefix("without ") for lb in labels], fontsize=8)
        ax.set_xlim(0, 150)
        ax.axvline(100, color="0.6", lw=0.8, ls=":")
        ns = v[("craft", case.name, "full", "ns_per_body_step")]
        ax.set_title(f"{case.name}: full {ns:.0f} ns/body-step", fontsize=10)
        ax.set_xlabel("cost with the group left out (% of full)")
    ax = fig.add_subplot(grid[1, :])
    scene = [r for r in rows if r[0] == "scene" and r[3].startswith("env_steps")]
    variants = list(dict.fromkeys((r[1], r[2]) for r in scene))
    threads = list(dict.fromkeys(r[3].removeprefix("env_steps_per_s, ") for r in scene))
    x = np.arange(len(variants))
    width = 0.8 / len(threads)
    for j, t in enumerate(threads):
        rate = [v[("scene", sc, lb, f"env_steps_per_s, {t}")] for sc, lb in variants]
        xs = x + (j - (len(threads) - 1) / 2) * width
        ax.bar(xs, rate, width, label=t, color=("tab:blue", "tab:orange", "tab:green")[j % 3])
        for xi, r in zip(xs, rate, strict=True):
            ax.text(xi, r * 1.05, f"{r / 1e3:,.0f}k", ha="center", fontsize=7)
    ax.set_yscale("log")
    ax.set_xticks(x, [f"{sc}\n{lb}" for sc, lb in variants], fontsize=8)
    ax.set_ylabel(f"env-steps/s at {RATE_ENVS} envs")
    ax.legend(fontsize=8, loc="lower left")
    key = ("floor", "paper_airplane", "floor", "cost_vs_no_floor, glide and landing 6 s")
    ax.set_title(
        "scenes: env-steps/s of each variant (random actions, interleaved repeats); "
        f"the dart's floor contact costs x{v.get(key, math.nan):.2f} per body-step over a "
        "6 s glide and landing (Simulator level)",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main() -> None:
    parser = arguments(__doc__, "64 episodes, fewer repeats")
    parser.add_argument("--episodes", type=int, default=256)
    parser.add_argument("--repeats", type=int, default=40, help="craft-level cost repeats")
    parser.add_argument("--seconds", type=float, default=1.0, help="per env-steps/s run")
    parser.add_argument("--rate-repeats", type=int, default=3)
    args = parser.parse_args()
    out = out_dir(args.out, args.quick)
    if args.quick:
        n_episodes, repeats, seconds, rate_repeats = 64, 3, 0.3, 1
    else:
        n_episodes, repeats = args.episodes, args.repeats
        seconds, rate_repeats = args.seconds, args.rate_repeats

    t_start = time.perf_counter()
    machine = describe()
    rows: list = []
    craft_level(repeats, rows)
    floor_level(max(3, repeats // 3), rows)
    scene_level(n_episodes, seconds, rate_repeats, rows)
    machine.append(load_average("end"))
    write_rows(out / "study_model_cost.csv", machine, rows)
    plot(rows, out / "study_model_cost.png")
    print(markdown(rows))
    print(
        f"\nwrote {out / 'study_model_cost.csv'}, {out / 'study_model_cost.png'} "
        f"in {time.perf_counter() - t_start:.0f} s"
    )


# ---- the docs' tables (docs/study_model_cost.md, from the CSV) -------------------------------

# the craft tables' own columns: quantity -> title
QUANTITY_TITLES = {
    "glide_ratio": "glide ratio", "final_speed": "final speed (m/s)",
    "top_speed": "top speed (m/s)", "final_trim": "final trim (°)",
    "depth_change": "depth change (m)", "heading_change": "heading change (°)",
    "heave_left": "heave left (m)", "drift": "drift (m)",
}  # fmt: skip
# the scene tables: scene -> (column title, quantity, format) after the rates
SCENE_COLUMNS = {
    "SubmarineWake-v0": (
        ("return", "return_mean", ".1f"), ("success", "success", "%"),
        ("time on station", "on_station_fraction", "%"),
        ("mean station error (m)", "station_error_mean", ".2f"),
        ("crash or lost", "crash_or_lost", "%0"),
    ),
    "BoatOnStep-v0": (
        ("return", "return_mean", ".1f"), ("success", "success", "%"),
        ("gates passed", "gates_passed_mean", ".2f"),
        ("porpoising", "porpoising_fraction", "%"), ("crash", "crash", "%"),
        ("episodes touching a buoy", "episodes_hitting_a_buoy", "%"),
        ("buoy contact steps", "buoy_contact_steps_mean", ".2f"),
    ),
}  # fmt: skip


def _csv_rows(path=None) -> list | None:
    from benchmarks.common import DOCS, read_csv

    path = DOCS / "study_model_cost.csv" if path is None else path
    if not path.is_file():
        return None
    return [(r["part"], r["subject"], r["variant"], r["quantity"], float(r["value"]), r["unit"])
            for r in read_csv(path)[1]]  # fmt: skip


def _g3(x: float) -> str:
    """Three significant digits, trailing zeros kept (0.100), a bare 0 for zero."""
    if x == 0:
        return "0"
    if not math.isfinite(x):
        return "diverged"
    return f"{x:#.3g}".rstrip(".")


def craft_markdown(craft: str) -> str:
    """One craft's table: each group left out, its cost and what it changes."""
    rows = _csv_rows()
    if rows is None:
        return "(no docs/study_model_cost.csv yet: run python -m benchmarks.study_model_cost)"
    v = lookup(rows)
    variants = list(dict.fromkeys(r[2] for r in rows if r[:2] == ("craft", craft)))
    qs = [r[3] for r in rows if r[:3] == ("craft", craft, "full")][5:]
    lines = [
        "| left out | samples | ns per body-step | share of full | position diff (m) | "
        "attitude diff (°) | " + " | ".join(QUANTITY_TITLES.get(q, q) for q in qs) + " |",
        "|---|" + "---:|" * (5 + len(qs)),
    ]
    for label in variants:
        k = ("craft", craft, label)
        cells = [
            f"{v[(*k, 'samples')]:.0f}",
            f"{v[(*k, 'ns_per_body_step')]:.1f}",
            f"{100 * v[(*k, 'share_of_full_cost')]:.0f}%",
            _g3(v[(*k, "final_pos_diff")]),
            _g3(v[(*k, "final_att_diff")]),
        ] + [_g3(v[(*k, q)]) if (*k, q) in v else "diverged" for q in qs]
        name = "nothing (full)" if label == "full" else label.removeprefix("without ")
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def floor_markdown() -> str:
    """The dart's floor contact: ns per body-step with and without the floor, per window."""
    rows = _csv_rows()
    if rows is None:
        return "(no docs/study_model_cost.csv yet: run python -m benchmarks.study_model_cost)"
    v = lookup(rows)
    windows = {"airborne 1 s": "first 1 s, airborne",
               "glide and landing 6 s": "whole 6 s: glide, touchdown, slide, rest"}  # fmt: skip
    lines = [
        "| window | floor (ns per body-step) | no floor | floor / no floor |",
        "|---|---:|---:|---:|",
    ]
    for key, name in windows.items():
        floor = v[("floor", "paper_airplane", "floor", f"ns_per_body_step, {key}")]
        bare = v[("floor", "paper_airplane", "no floor", f"ns_per_body_step, {key}")]
        ratio = v[("floor", "paper_airplane", "floor", f"cost_vs_no_floor, {key}")]
        lines.append(f"| {name} | {floor:.1f} | {bare:.1f} | {ratio:.2f} |")
    crossing = v[("floor", "paper_airplane", "no floor", "crossing_time")]
    rest = v[("floor", "paper_airplane", "floor", "rest_vs_floorless_crossing")]
    lines += [
        "",
        f"Without the floor the dart passes its resting height at {crossing:.2f} s; with it, "
        f"the dart comes to rest {rest:.2f} m from that point (bounce and slide).",
    ]
    return "\n".join(lines)


def scene_markdown(scene: str) -> str:
    """One scene's table: env-steps/s of each variant on 1 and 2 threads and the pilot's
    task metrics."""
    rows = _csv_rows()
    if rows is None:
        return "(no docs/study_model_cost.csv yet: run python -m benchmarks.study_model_cost)"
    v = lookup(rows)
    cols = SCENE_COLUMNS[scene]
    variants = list(dict.fromkeys(r[2] for r in rows if r[:2] == ("scene", scene)))
    lines = [
        "| variant | env-steps/s, 1 thread | vs default | 2 threads | "
        + " | ".join(title for title, _, _ in cols)
        + " |",
        "|---|" + "---:|" * (3 + len(cols)),
    ]

    def rate(x: float) -> str:
        return f"{float(f'{x:.4g}'):,.0f}"

    for label in variants:
        k = ("scene", scene, label)
        one = v.get((*k, "env_steps_per_s, 1 thread"), math.nan)
        cells = [
            rate(one), f"{v.get((*k, 'rate_vs_default, 1 thread'), math.nan):.3g}",
            rate(v.get((*k, "env_steps_per_s, 2 threads"), math.nan)),
        ]  # fmt: skip
        for _, q, form in cols:
            x = v.get((*k, q))
            if x is None:
                cells.append("")
            elif form.startswith("%"):
                cells.append(f"{100 * x:.{form[1:] or '1'}f}%")
            else:
                cells.append(f"{x:{form}}")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def dart_markdown() -> str:
    """PaperAirplane-v0 as shipped: its rate and its pilot's task metrics."""
    rows = _csv_rows()
    if rows is None:
        return "(no docs/study_model_cost.csv yet: run python -m benchmarks.study_model_cost)"
    v = lookup(rows)
    k = ("scene", "PaperAirplane-v0", "floor (default)")
    one, two = (float(f"{v[(*k, f'env_steps_per_s, {t}')]:.4g}") for t in ("1 thread", "2 threads"))
    return prose(
        f"**PaperAirplane-v0** (as shipped, with its floor): {one:,.0f} env-steps/s on one "
        f"thread ({two:,.0f} on two); pilot return {v[(*k, 'return_mean')]:.2f}, landed "
        f"{100 * v[(*k, 'landed')]:.1f}%, success {100 * v[(*k, 'success')]:.1f}%, mean miss "
        f"{v[(*k, 'miss_mean')]:.2f} m."
    )


def paper_airplane_markdown() -> str:
    return craft_markdown("paper_airplane")


def speedboat_markdown() -> str:
    return craft_markdown("speedboat")


def uuv_markdown() -> str:
    return craft_markdown("uuv")


def buoy_markdown() -> str:
    return craft_markdown("buoy")


def submarine_markdown() -> str:
    return scene_markdown("SubmarineWake-v0")


def boat_markdown() -> str:
    return scene_markdown("BoatOnStep-v0")


if __name__ == "__main__":
    main()
