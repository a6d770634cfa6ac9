"""Integrators in the envs: symplectic Euler at dt against rk2 at 2 dt, with the scripted pilots.

``benchmarks/study_accuracy.py`` found rk2 at twice the dt 94-281 times more accurate than the
envs' first default (symplectic Euler at dt) for the same compute, on one mild maneuver per craft
with no contact, calm water and fixed controls. This study asks the same question of the
envs themselves, with their contact (the paper dart landing on its floor, the boat hitting
floating buoy bodies), swell, scripted routes and closed-loop pilots.

Scenes (each env's default parameters except where named):

- ``paper_airplane``: PaperAirplane-v0 (the dart lands on a solid floor: ground contact);
- ``submarine_wake``: SubmarineWake-v0;
- ``submarine_nowake``: SubmarineWake-v0 with ``wake=False``, a control (this study found
  the wake's source frozen over each step's stages, which left rk2 first order behind it:
  fixed in ``physics/kernels.py``);
- ``boat_on_step``: BoatOnStep-v0 (calm water);
- ``boat_swell``: BoatOnStep-v0 with ``swell=SWELL`` (0.3 m waves 30 m long toward 45 deg and
  0.15 m, 12 m toward -60 deg, the swell of ``tests/envs/test_boat_on_step_env.py``);
- ``boat_buoys``: BoatOnStep-v0 with ``buoy_bodies=True`` (twelve moored buoy bodies the hull
  can hit: body-body contact).

Physics configurations, set through the env's ``integrator``, ``dt`` and ``substeps`` so that
the action period (``dt * substeps``) stays the env's; ``dt`` and ``n`` are the envs' first
defaults, symplectic Euler at 1/240 s x 8 (airplane), 1/200 s x 10 (boat) and 1/50 s x 5
(submarine). The envs now default to the rk2 line this study recommended (``env_default``):

- ``symplectic_euler, dt``: the first default (1 force evaluation per step, n per action);
- ``rk2, 2 dt``: n / 2 substeps, the same n force evaluations per action. Where n is odd
  (SubmarineWake-v0: n = 5) rk2 cannot take exactly twice the dt; it is run at the two
  nearest whole substep counts instead, ``rk2, 5/2 dt`` (2 substeps: 4 evaluations, 0.8 times
  the compute) and ``rk2, 5/3 dt`` (3 substeps: 6 evaluations, 1.2 times);
- ``rk4, 4 dt``: n / 4 substeps, where n divides by 4 (PaperAirplane-v0 only);
- ``symplectic_euler, dt/2``: 2 n substeps, twice the compute: a yardstick;
- ``rk4, dt/4``: 4 n substeps, float64: the reference.

For each scene and configuration, E episodes (``--episodes``, 256 by default) run in one
vector env of E sub-envs reset with the same seed (sub-env i gets the same draws, launch,
course, route, wind and swell phase, in every configuration), no autoreset; a sub-env's first
episode is its result (later episodes in that sub-env are run but ignored).

1. Closed loop: the env's scripted pilot (``fluidsim_envs.rl.evaluate.scripted_pilot``) flies
   every configuration. Reported: mean and std of the episode return, the success rate, the
   mean episode length (actions), the count of each way the episodes ended (the termination
   flags of the final info, ``truncated`` and ``physics_diverged``; for the boat ``finished``
   is the course run through, and ``hit_buoy_episodes`` counts episodes with any step touching
   a buoy), and the share of episodes whose success flag agrees with the reference's.
2. Open loop: the reference run's pilot actions are recorded per episode and replayed,
   exactly, in every other configuration from the same reset seeds. The error is the distance
   (m) between the craft's (body 0) position and the reference's after the same number of
   actions, at fixed horizons of sim time (1, 3, 10 and 30 s) and at the end of the shorter
   of the two episodes; median and 90th percentile over episodes. An episode that has ended
   in either run before a horizon drops out of it (``n_*`` columns: how many remain); one that
   diverged in either run drops out of the end horizon too. ``open_loop_length_differs``
   counts the replayed episodes that ended after a different number of actions than the
   reference's (touchdown, a capsize or the last gate a step earlier or later). Two checks
   on the reference, on the first ``--check-envs`` sub-envs (same seeds): replaying its own
   actions in the reference configuration must reproduce it exactly (determinism), and
   replaying them with rk4 at dt/8 estimates the reference's own error (printed and written
   as ``#`` notes).
3. Speed: env-steps per second of each configuration's closed-loop run (E sub-envs times the
   vector steps, over the wall time after the first step, pilot included), a single
   measurement on a shared 2-core machine: indicative only. The Simulator picks its serial
   or parallel kernel by E x bodies (parallel from 1024: only ``boat_buoys`` at E = 256).

Writes ``docs/study_env_integrators.csv`` (one row per scene and configuration; ``#`` lines
describing the machine, the method and the checks) and ``docs/study_env_integrators.png``
(each configuration's compute, force evaluations per action, against its position error, one
panel per scene: :func:`plot`), and prints a table; :func:`markdown` is docs/study.md's table
(``python -m benchmarks.report`` writes it)::

    python -m benchmarks.study_env_integrators           # 256 episodes: 284 s on 2 shared cores
    python -m benchmarks.study_env_integrators --quick   # 8 episodes, ~30 s, into build/study_quick
    python -m benchmarks.study_env_integrators --plot-only   # the chart again from the CSV
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from benchmarks.common import DOCS, arguments, describe, out_dir, read_csv, write_csv
from fluidsim_envs.envs import BoatOnStepVectorEnv, PaperAirplaneVectorEnv, SubmarineWakeVectorEnv
from fluidsim_envs.physics.kernels import EVALS_PER_STEP
from fluidsim_envs.rl.evaluate import scripted_pilot

SWELL = ((0.3, 30.0, 45.0), (0.15, 12.0, -60.0))
HORIZONS_S = (1.0, 3.0, 10.0, 30.0)
BOAT_CRASHES = ("capsized", "bow_stuffed", "left_course")
REASON_COLUMNS = (
    "landed",
    "crashed",
    "out_of_arena",
    "hit_hull",
    "hit_floor",
    "lost_lead",
    *BOAT_CRASHES,
    "finished",
    "truncated",
    "physics_diverged",
    "hit_buoy_episodes",
)


@dataclass
class Scene:
    name: str
    env_id: str
    cls: type
    base: tuple[float, int]  # symplectic Euler's dt and substeps: the envs' first defaults
    kwargs: dict = field(default_factory=dict)
    reasons: tuple[str, ...] = ()  # boolean keys of the final info: how an episode ended

    def params(self):
        return self.cls.Params(**self.kwargs)


@dataclass(frozen=True)
class Config:
    label: str
    integrator: str
    dt: float
    substeps: int
    reference: bool = False
    dtype: str = "float64"  # the physics' precision (benchmarks/study_float32.py)

    def evals_per_action(self) -> int:
        return EVALS_PER_STEP[self.integrator] * self.substeps


SCENES = [
    Scene(
        "paper_airplane",
        "fluidsim/PaperAirplane-v0",
        PaperAirplaneVectorEnv,
        (1 / 240, 8),
        reasons=("landed", "crashed", "out_of_arena"),
    ),
    Scene(
        "submarine_wake",
        "fluidsim/SubmarineWake-v0",
        SubmarineWakeVectorEnv,
        (1 / 50, 5),
        reasons=("hit_hull", "hit_floor", "lost_lead"),
    ),
    Scene(  # a control, not a default: the same scene without the lead's wake
        "submarine_nowake",
        "fluidsim/SubmarineWake-v0",
        SubmarineWakeVectorEnv,
        (1 / 50, 5),
        dict(wake=False),
        reasons=("hit_hull", "hit_floor", "lost_lead"),
    ),
    Scene(
        "boat_on_step",
        "fluidsim/BoatOnStep-v0",
        BoatOnStepVectorEnv,
        (1 / 200, 10),
        reasons=BOAT_CRASHES,
    ),
    Scene(
        "boat_swell",
        "fluidsim/BoatOnStep-v0",
        BoatOnStepVectorEnv,
        (1 / 200, 10),
        dict(swell=SWELL),
        reasons=BOAT_CRASHES,
    ),
    Scene(
        "boat_buoys",
        "fluidsim/BoatOnStep-v0",
        BoatOnStepVectorEnv,
        (1 / 200, 10),
        dict(buoy_bodies=True),
        reasons=BOAT_CRASHES,
    ),
]


def configs(scene: Scene) -> list[Config]:
    """The configurations of the study about the scene's symplectic Euler baseline."""
    dt, n = scene.base
    out = [Config("symplectic_euler, dt", "symplectic_euler", dt, n)]
    if n % 2 == 0:
        out.append(Config("rk2, 2 dt", "rk2", 2 * dt, n // 2))
    else:  # the two whole substep counts either side of n / 2, same action period
        for k in (n // 2, n // 2 + 1):
            if k >= 1:
                out.append(Config(f"rk2, {n}/{k} dt", "rk2", dt * n / k, k))
    if n % 4 == 0:
        out.append(Config("rk4, 4 dt", "rk4", 4 * dt, n // 4))
    out.append(Config("symplectic_euler, dt/2", "symplectic_euler", dt / 2, 2 * n))
    out.append(Config("rk4, dt/4 (reference)", "rk4", dt / 4, 4 * n, reference=True))
    return out


def make_env(scene: Scene, cfg: Config, num_envs: int):
    """The scene's vector env with the configuration's physics (no autoreset)."""
    return scene.cls(
        num_envs=num_envs,
        autoreset=False,
        integrator=cfg.integrator,
        dt=cfg.dt,
        substeps=cfg.substeps,
        dtype=cfg.dtype,
        **scene.kwargs,
    )


def craft_pos(venv) -> np.ndarray:
    return np.array(venv.sim.pos[:, 0], dtype=np.float64)


# ---- the runs ---------------------------------------------------------------------------------


def run_episodes(scene: Scene, cfg: Config, num_envs: int, seed: int, replay=None) -> dict:
    """Every sub-env's first episode after ``reset(seed=seed)``, flown by the scripted pilot
    (``replay`` None) or replaying ``replay = (actions [T, E, n], lengths [E])``: each sub-env
    takes its recorded actions for its recorded length, zeros after (its episode ends first,
    or it is ignored from then on).

    Returns arrays [E] (return, length, success, diverged, truncated, and each reason), the
    actions [T, E, n] and craft positions [T, E, 3] after each vector step, and the timing.
    """
    venv = make_env(scene, cfg, num_envs)
    E = num_envs
    pilot = scripted_pilot(scene.env_id, venv) if replay is None else None
    obs, _ = venv.reset(seed=seed)
    if pilot is not None and hasattr(pilot, "reset"):
        pilot.reset()
    out = {
        "return": np.zeros(E),
        "length": np.zeros(E, dtype=np.int64),
        "success": np.zeros(E, dtype=bool),
        "truncated": np.zeros(E, dtype=bool),
        "physics_diverged": np.zeros(E, dtype=bool),
        "finished": np.zeros(E, dtype=bool),
        "hit_buoy_episodes": np.zeros(E, dtype=bool),
        **{k: np.zeros(E, dtype=bool) for k in scene.reasons},
    }
    done = np.zeros(E, dtype=bool)
    actions, positions = [], []
    t_first = None
    t0 = time.perf_counter()
    k = 0
    while not done.all():
        if replay is None:
            a = np.asarray(pilot(obs), dtype=np.float64)
        else:
            rec, lengths = replay
            if k >= len(rec):
                break  # every recorded episode is over; the rest ended later in this run
            a = np.where((k < lengths)[:, None], rec[k], 0.0)
        actions.append(a.copy())
        obs, reward, terminated, truncated, info = venv.step(a)
        if k == 0:
            t_first = time.perf_counter()
        k += 1
        positions.append(craft_pos(venv))
        live = ~done
        out["return"][live] += reward[live]
        ended = terminated | truncated
        newly = ended & live
        if newly.any():
            out["length"][newly] = k
            out["truncated"][newly] = truncated[newly]
            out["physics_diverged"][newly] = info["physics_diverged"][newly]
            out["success"][newly] = np.asarray(info["success"], dtype=bool)[newly]
            for key in scene.reasons:
                out[key][newly] = np.asarray(info[key], dtype=bool)[newly]
            if scene.cls is BoatOnStepVectorEnv:
                crashed = np.zeros(E, dtype=bool)
                for key in BOAT_CRASHES:
                    crashed |= np.asarray(info[key], dtype=bool)
                fin = terminated & ~crashed & ~info["physics_diverged"]
                out["finished"][newly] = fin[newly]
                out["hit_buoy_episodes"][newly] = info["episode_terms"]["buoy"][newly] < 0
            done |= newly
        if ended.any():  # keep the ended sub-envs stepping (their later episodes are ignored)
            obs, _ = venv.reset(options={"env_ids": np.flatnonzero(ended)})
            if pilot is not None and hasattr(pilot, "reset"):
                pilot.reset(ended)
    wall = time.perf_counter() - (t_first if t_first is not None else t0)
    out["length"][~done] = k  # a replay stopped at the end of the recording
    venv.close()
    out["actions"] = np.array(actions)
    out["pos"] = np.array(positions)
    out["vector_steps"] = k
    out["env_steps_per_s"] = E * (k - 1) / wall if k > 1 and wall > 0 else math.nan
    return out


def position_errors(run: dict, ref: dict, step_s: float) -> dict:
    """Craft position distance to the reference at each horizon and at the end of the shorter
    episode: median, 90th percentile and count of the episodes that reach it."""
    E = len(ref["length"])
    common = np.minimum(run["length"][:E], ref["length"])
    res = {}
    steps_avail = min(len(run["pos"]), len(ref["pos"]))
    for h in HORIZONS_S:
        k = round(h / step_s)
        ids = np.flatnonzero(common >= k) if k <= steps_avail else np.array([], dtype=int)
        d = (
            np.linalg.norm(run["pos"][k - 1, ids] - ref["pos"][k - 1, ids], axis=1)
            if ids.size
            else []
        )
        res[f"{h:g}s"] = summarize_errors(d)
    ok = ~(run["physics_diverged"][:E] | ref["physics_diverged"])
    ids = np.flatnonzero(ok & (common >= 1))
    d = np.linalg.norm(run["pos"][common[ids] - 1, ids] - ref["pos"][common[ids] - 1, ids], axis=1)
    res["end"] = summarize_errors(d)
    return res


def summarize_errors(d) -> tuple[float, float, int]:
    d = np.asarray(d, dtype=np.float64)
    if d.size == 0:
        return (math.nan, math.nan, 0)
    if not np.all(np.isfinite(d)):
        d = np.where(np.isfinite(d), d, np.inf)
    return (float(np.median(d)), float(np.quantile(d, 0.9)), int(d.size))


# ---- output -----------------------------------------------------------------------------------


def fmt(x) -> str:
    if isinstance(x, float):
        return "" if math.isnan(x) else f"{x:.6g}"
    return str(x)


def short(x: float) -> str:
    return "-" if math.isnan(x) else f"{x:.1e}"


def print_scene(scene: Scene, rows: list[dict]) -> None:
    keys = [k for k in REASON_COLUMNS if any(r.get(k, "") != "" for r in rows)]
    abbrev = {
        "landed": "land",
        "crashed": "crash",
        "out_of_arena": "out",
        "hit_hull": "hull",
        "hit_floor": "floor",
        "lost_lead": "lost",
        "capsized": "capsz",
        "bow_stuffed": "stuff",
        "left_course": "left",
        "finished": "fin",
        "truncated": "trunc",
        "physics_diverged": "div",
        "hit_buoy_episodes": "buoyhit",
    }
    hz = [f"{h:g}s" for h in HORIZONS_S] + ["end"]
    kw = ", ".join(f"{k}={v}" for k, v in scene.kwargs.items())
    print(
        f"\n== {scene.name} ({scene.env_id}{', ' + kw if kw else ''}), {rows[0]['episodes']} "
        f"episodes, action period {rows[0]['action_period_s']:.4g} s"
    )
    print(
        f"{'closed loop':24s} {'ev/a':>4s} {'return':>16s} {'succ':>5s} {'agree':>5s} "
        f"{'len':>6s} " + " ".join(f"{abbrev[k]:>7s}" for k in keys) + f" {'steps/s':>8s}"
    )
    for r in rows:
        print(
            f"{r['config']:24s} {r['evals_per_action']:4d} "
            f"{r['return_mean']:8.2f}±{r['return_std']:<7.2f} {r['success_rate']:5.3f} "
            f"{r['success_agree']:5.3f} {r['length_mean']:6.1f} "
            + " ".join(f"{r.get(k, ''):>7}" for k in keys)
            + f" {r['env_steps_per_s']:8.0f}"
        )
    print(
        f"{'open loop: err (m)':24s} {'len!=':>5s} "
        + " ".join(f"{'@' + h + ' median/p90 (n)':>24s}" for h in hz)
    )
    for r in rows:
        if r["reference"]:
            continue
        print(
            f"{r['config']:24s} "
            + f"{r['open_loop_length_differs']:>5d} "
            + " ".join(
                f"{short(r[f'err_{h}_median_m']) + ' / ' + short(r[f'err_{h}_p90_m']):>18s}"
                f" ({r[f'n_{h}']:>3d})"
                for h in hz
            )
        )


# ---- main -------------------------------------------------------------------------------------


def main() -> None:
    parser = arguments(__doc__, "8 episodes, into build/")
    parser.add_argument("--episodes", type=int, default=None, help="episodes (sub-envs)")
    parser.add_argument("--check-envs", type=int, default=None, help="sub-envs of the checks")
    parser.add_argument("--seed", type=int, default=0, help="reset seed of the episodes")
    parser.add_argument("--scenes", default=None, help="comma-separated subset of the scenes")
    parser.add_argument("--plot-only", action="store_true", help="redraw the chart from the CSV")
    args = parser.parse_args()
    out = out_dir(args.out, args.quick)
    if args.plot_only:
        plot(read_rows(out / "study_env_integrators.csv"), out / "study_env_integrators.png")
        return
    episodes = args.episodes or (8 if args.quick else 256)
    check_envs = min(episodes, args.check_envs or (4 if args.quick else 32))
    scenes = SCENES
    if args.scenes:
        wanted = args.scenes.split(",")
        unknown = sorted(set(wanted) - {s.name for s in SCENES})
        if unknown:
            parser.error(f"unknown scene(s) {unknown}; valid: {[s.name for s in SCENES]}")
        scenes = [s for s in SCENES if s.name in wanted]
    t_start = time.perf_counter()
    machine = describe()
    notes = [
        f"method: {episodes} episodes per scene and configuration (vector env, reset seed "
        f"{args.seed}, no autoreset, first episode per sub-env), float64; closed loop with the "
        "env's scripted pilot; open loop replays the reference (rk4 at dt/4) run's pilot "
        "actions; err_*: craft (body 0) position distance to the reference (m) after "
        f"{', '.join(f'{h:g}' for h in HORIZONS_S)} s of sim time and at the end of the "
        "shorter episode, median / 90th percentile over the episodes that reach it (n_*); "
        "see the module docstring of benchmarks/study_env_integrators.py",
        "env_steps_per_s: one closed-loop run (pilot included, after its first step) on a "
        "shared 2-core machine, another job running: indicative only",
        f"swell of boat_swell: {SWELL} (amplitude_m, wavelength_m, direction_deg)",
        "submarine_wake: 5 substeps do not halve, so rk2 runs at 5/2 dt (0.8x the compute) "
        "and 5/3 dt (1.2x)",
        "env_default: the configuration the env now defaults to",
    ]
    rows = []
    for scene in scenes:
        p = scene.params()
        step_s = float(p.dt) * int(p.substeps)
        cfgs = configs(scene)
        ref_cfg = next(c for c in cfgs if c.reference)
        t_scene = time.perf_counter()
        ref = run_episodes(scene, ref_cfg, episodes, args.seed)
        replay = (ref["actions"], ref["length"])

        # the checks on the reference: determinism, and its own error (rk4 at dt/8)
        sub = (ref["actions"][:, :check_envs], ref["length"][:check_envs])
        ref_sub = {
            k: (v[:check_envs] if k != "pos" else v[:, :check_envs])
            for k, v in ref.items()
            if k in ("pos", "length", "physics_diverged")
        }
        again = run_episodes(scene, ref_cfg, check_envs, args.seed, replay=sub)
        same = bool(np.array_equal(again["length"], ref_sub["length"])) and all(
            np.array_equal(again["pos"][:n, i], ref_sub["pos"][:n, i], equal_nan=True)
            for i, n in enumerate(ref_sub["length"])  # within the episode only
        )
        finer_cfg = Config("rk4, dt/8", "rk4", ref_cfg.dt / 2, ref_cfg.substeps * 2)
        finer = run_episodes(scene, finer_cfg, check_envs, args.seed, replay=sub)
        conv = position_errors(finer, ref_sub, step_s)
        notes.append(
            f"{scene.name}: reference replay of its own actions reproduces it exactly: {same}; "
            f"rk4 at dt/8 against it (same actions, {check_envs} episodes), median / p90 (m): "
            + ", ".join(f"@{h} {short(v[0])} / {short(v[1])}" for h, v in conv.items() if v[2])
        )
        print(notes[-1])
        if not same:
            print(f"WARNING: {scene.name}: replaying the reference's actions did not reproduce it")

        scene_rows = []
        for cfg in cfgs:
            closed = ref if cfg.reference else run_episodes(scene, cfg, episodes, args.seed)
            opened = (
                ref
                if cfg.reference
                else run_episodes(scene, cfg, episodes, args.seed, replay=replay)
            )
            errs = position_errors(opened, ref, step_s)
            row = {
                "scene": scene.name,
                "env_id": scene.env_id,
                "env_kwargs": ";".join(f"{k}={v}" for k, v in scene.kwargs.items()),
                "config": cfg.label,
                "integrator": cfg.integrator,
                "dt_s": cfg.dt,
                "substeps": cfg.substeps,
                "evals_per_action": cfg.evals_per_action(),
                "action_period_s": step_s,
                "episodes": episodes,
                "reference": cfg.reference,
                "env_default": (cfg.integrator, cfg.substeps) == (p.integrator, p.substeps)
                and math.isclose(cfg.dt, p.dt),
                "return_mean": float(np.mean(closed["return"])),
                "return_std": float(np.std(closed["return"])),
                "success_rate": float(np.mean(closed["success"])),
                "success_agree": float(np.mean(closed["success"] == ref["success"])),
                "length_mean": float(np.mean(closed["length"])),
                **{k: "" for k in REASON_COLUMNS},
                "truncated": int(closed["truncated"].sum()),
                "physics_diverged": int(closed["physics_diverged"].sum()),
                **{k: int(closed[k].sum()) for k in scene.reasons},
                "open_loop_diverged": int(opened["physics_diverged"].sum()),
                # open loop: episodes whose length (actions) differs from the reference's
                "open_loop_length_differs": int(np.sum(opened["length"] != ref["length"])),
            }
            if scene.cls is BoatOnStepVectorEnv:
                row["finished"] = int(closed["finished"].sum())
                row["hit_buoy_episodes"] = int(closed["hit_buoy_episodes"].sum())
            for h, (med, p90, n) in errs.items():
                row[f"err_{h}_median_m"] = med
                row[f"err_{h}_p90_m"] = p90
                row[f"n_{h}"] = n
            row["env_steps_per_s"] = closed["env_steps_per_s"]
            scene_rows.append(row)
        print_scene(scene, scene_rows)
        print(f"({scene.name}: {time.perf_counter() - t_scene:.0f} s)")
        rows += scene_rows

    header = list(dict.fromkeys(k for r in rows for k in r))
    path = out / "study_env_integrators.csv"
    write_csv(path, header, [[fmt(r.get(k, "")) for k in header] for r in rows], machine + notes)
    plot(read_rows(path), out / "study_env_integrators.png")
    print(f"wrote {path} and its chart in {time.perf_counter() - t_start:.0f} s")


# ---- the docs -----------------------------------------------------------------------------------

# docs/study.md's table: each scene's label there, and whether it shows the dt/2 yardstick
TABLE_SCENES = {
    "paper_airplane": ("PaperAirplane-v0", True),
    "submarine_wake": ("SubmarineWake-v0", True),
    "submarine_nowake": ("(wake off)", False),
    "boat_on_step": ("BoatOnStep-v0", True),
    "boat_swell": ("(two-wave swell)", False),
    "boat_buoys": ("(buoy bodies)", False),
}
INTEGRATOR_NAMES = {"symplectic_euler": "symplectic Euler", "rk2": "rk2", "rk4": "rk4"}


def read_rows(path) -> list[dict]:
    """The CSV's rows, numbers as floats (NaN where blank), flags as bools."""
    rows = read_csv(path)[1]
    for r in rows:
        for k, x in r.items():
            if x in ("True", "False"):
                r[k] = x == "True"
            elif k not in ("scene", "env_id", "env_kwargs", "config", "integrator"):
                try:
                    r[k] = float(x) if x != "" else math.nan
                except ValueError:
                    pass
    return rows


def sci(x: float) -> str:
    """An error as the table shows it: 2 digits, ``1.5e-2`` below 0.1."""
    if math.isnan(x):
        return ""
    if x < 0.1:
        return f"{x:.1e}".replace("e-0", "e-")
    return f"{x:.2f}" if x < 1 else f"{x:.1f}" if x < 10 else f"{x:.0f}"


def markdown(path=None) -> str:
    """docs/study.md's table from docs/study_env_integrators.csv: per scene the first default,
    the env's default (bold) and symplectic Euler at half the dt (the yardstick, main scenes
    only): force evaluations per action, the open-loop position error against the reference
    (median / 90th percentile) at 1, 3 and 10 s and at the episode's end, and the pilot's
    closed-loop success."""
    path = DOCS / "study_env_integrators.csv" if path is None else path
    if not path.is_file():
        return "(no docs/study_env_integrators.csv yet: run the study: module docstring)"
    rows = read_rows(path)
    hz = ("1s", "3s", "10s", "end")
    lines = [
        "| scene | configuration | evaluations per action | error at 1 s (m) | at 3 s | at 10 s "
        "| at episode end | pilot success |",
        "|---|---|---:|---:|---:|---:|---:|---:|",
    ]
    for scene, (label, yardstick) in TABLE_SCENES.items():
        mine = [r for r in rows if r["scene"] == scene]
        first = next((r for r in mine if r["config"] == "symplectic_euler, dt"), None)
        if first is None:
            continue
        shown = [first, *(r for r in mine if r["env_default"])]
        if yardstick:
            shown += [r for r in mine if r["config"] == "symplectic_euler, dt/2"]
        for i, r in enumerate(shown):
            name = f"{INTEGRATOR_NAMES[r['integrator']]}, 1/{1 / r['dt_s']:.0f} s"
            name = f"**{name}**" if r["env_default"] and yardstick else name
            errs = [
                f"{sci(r[f'err_{h}_median_m'])} / {sci(r[f'err_{h}_p90_m'])}"
                if r[f"n_{h}"] > 0 else ""
                for h in hz
            ]  # fmt: skip
            lines.append(
                f"| {label if i == 0 else ''} | {name} | {r['evals_per_action']:.0f} | "
                + " | ".join(errs)
                + f" | {100 * r['success_rate']:.1f}% |"
            )
    return "\n".join(lines)


def plot(rows: list[dict], path) -> None:
    """Compute (force evaluations per action) against the open-loop position error, one panel
    per scene: each configuration's median error at 1 s (filled) and at the episode's end
    (open), the bar up to the 90th percentile; the env's default ringed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scenes_ = list(dict.fromkeys(r["scene"] for r in rows))
    cols = 3
    fig, axes = plt.subplots(
        math.ceil(len(scenes_) / cols), cols, figsize=(15, 4.2 * math.ceil(len(scenes_) / cols)),
        squeeze=False,
    )  # fmt: skip
    colors = {"symplectic_euler": "tab:blue", "rk2": "tab:orange", "rk4": "tab:green"}
    for ax, scene in zip(axes.flat, scenes_, strict=False):
        for r in (r for r in rows if r["scene"] == scene and not r["reference"]):
            x, c = r["evals_per_action"], colors.get(r["integrator"], "k")
            for h, face in (("1s", c), ("end", "none")):
                med, p90 = r[f"err_{h}_median_m"], r[f"err_{h}_p90_m"]
                if not (med > 0):
                    continue
                ax.errorbar(x, med, yerr=[[0.0], [max(p90 - med, 0.0)]], fmt="o", color=c,
                            mfc=face, ms=7, capsize=3)  # fmt: skip
            if r["env_default"] and r["err_1s_median_m"] > 0:
                ax.plot(x, r["err_1s_median_m"], "o", ms=15, mfc="none", mec="k")
            ax.annotate(r["config"], (x, r["err_1s_median_m"]), fontsize=7,
                        xytext=(6, -3), textcoords="offset points")  # fmt: skip
        label = TABLE_SCENES.get(scene, (scene,))[0]
        ax.set_title(f"{scene}: {label}" if label != scene else scene, fontsize=10)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        evals = sorted({r["evals_per_action"] for r in rows if r["scene"] == scene})
        ax.set_xticks(evals, [f"{x:.0f}" for x in evals])
        ax.minorticks_off()
        ax.set_xlabel("force evaluations per action (compute)")
        ax.set_ylabel("position error vs reference (m)")
        ax.grid(True, which="both", alpha=0.3)
    for ax in list(axes.flat)[len(scenes_) :]:
        ax.axis("off")
    handles = [
        plt.Line2D([], [], color=c, marker="o", ls="", label=m) for m, c in colors.items()
    ] + [
        plt.Line2D([], [], color="0.3", marker="o", ls="", label="median at 1 s (bar: p90)"),
        plt.Line2D([], [], color="0.3", marker="o", mfc="none", ls="",
                   label="median at episode end"),
        plt.Line2D([], [], color="k", marker="o", ms=12, mfc="none", ls="", label="env default"),
    ]  # fmt: skip
    fig.legend(handles=handles, loc="lower center", ncol=6, fontsize=8)
    fig.suptitle(
        "Integrators in the envs: compute against open-loop error, pilot actions replayed "
        "(python -m benchmarks.study_env_integrators)"
    )
    fig.tight_layout(rect=(0, 0.04, 1, 0.97))
    fig.savefig(path, dpi=100)
    plt.close(fig)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
