"""The speedboat beside Savitsky's (1964) planing method, for each way of building its hull.

For each hull variant (``fluidsim_envs.craft.hull.VHull``) the boat runs from rest at its
floating height and trim (``hydrostatics.static_float``) at a constant thrust, tabs flush,
rudder amidships, for ``SECONDS`` at dt = 1/200 s (symplectic Euler, the Simulator's default),
one environment per thrust over a sweep from 0 to the engine's 4.5 kN. Over the last
``WINDOW_S``: the mean and peak-to-peak trim; at the end the speed. The resistance is the
steady thrust, so R/W = thrust / weight (the propeller's line is the body's x axis: at 2-5 deg
of trim its horizontal part is 0.1-0.4% less, which this ratio ignores, as the tests do).

Reference: Savitsky's general method (``physics.reference.savitsky``: D. Savitsky,
"Hydrodynamic Design of Planing Hulls", Marine Technology 1(1), 1964) for a prismatic hull
of the boat's chine beam, deadrise, weight, LCG and VCG, thrust 0.3 m below the keel, at each
run's speed; a row counts where the method is valid there (``PlaningState.in_range``: Cv,
trim, lambda, deadrise within the data it was fitted to, chines wet). The transition
(pre-planing to planing) region is marked from 1 to 3.5 in volumetric Froude number
Fn_V = V / sqrt(g Vol^(1/3)): planing hulls have less resistance than displacement hulls
above Fn_V = 1, and plane fully around Fn_V 3-3.5 (Radojcic et al., "Resistance Prediction
for Hard Chine Hulls in the Pre-Planing Regime", Polish Maritime Research 2(82), 2014).

Porpoising: a run whose trim swings by more than ``PORPOISE_PTP_DEG`` over the window
porpoises. Beside it, the published stability limit of prismatic planing surfaces (Day and
Haag 1952, as Savitsky 1964 charts it: critical trim against sqrt(C_L_beta / 2) for deadrise
0, 10 and 20 deg). The chart's numbers used here are the cubic fits of that chart in
OpenPlaning (github.com/elcf/python-openplaning, ``openplaning.py``,
``PlaningBoat.check_porpoising``), valid for sqrt(C_L_beta / 2) in [0.13, 0.30], deadrise
0-20 deg; our 18 deg interpolates the three curves quadratically in deadrise, as it does. For
this boat the chart's range is 5.7-13.2 m/s: the rows outside it are extrapolations, marked.

Writes ``docs/study_savitsky.csv`` (one row per hull and thrust), ``docs/study_savitsky_grid.csv``
(each hull interpolated to common speeds every 0.5 m/s where Savitsky is valid, so that the
hulls are compared at the same speeds) and ``docs/study_savitsky.png`` (trim and R/W against
speed beside Savitsky, the transition shaded), and prints each hull's errors against Savitsky
(the numbers the docs and tests/craft/test_speedboat.py quote; also in the CSVs' ``#`` lines).
And ``docs/study_savitsky_turn.csv``: each hull hard over at 15 m/s (:func:`hard_turn`), the
dynamic check that decided against the one-sided bottom::

    python -m benchmarks.study_savitsky            # about 2 minutes on 2 cores
    python -m benchmarks.study_savitsky --quick    # fewer thrusts, into build/study_quick
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import replace

import numpy as np

from benchmarks.common import (
    DOCS,
    arguments,
    describe,
    fmt,
    out_dir,
    prose,
    read_csv,
    write_csv,
)
from fluidsim_envs.craft.hull import HULLS as SHIPPED
from fluidsim_envs.craft.hull import VHull, speedboat_toml
from fluidsim_envs.physics import Craft, Simulator, World
from fluidsim_envs.physics.forces import thrust_control
from fluidsim_envs.physics.hydrostatics import static_float
from fluidsim_envs.physics.kernels import quat_matrices
from fluidsim_envs.physics.reference.savitsky import PrismaticHull, of_hull, savitsky

DT = 1 / 200
SECONDS, WINDOW_S = 45.0, 3.0
PORPOISE_PTP_DEG = 0.5  # the trim's swing over the window above which a run porpoises
FNV_TRANSITION = (1.0, 3.5)  # Radojcic et al. 2014
WORLD = World(water=True)

HULLS = {  # name -> hull lines: the first hull (speedboat), each rule of issue 20 alone, both
    "friction plates": VHull(friction="plates", one_sided_bottom=False),
    "one-sided": VHull(friction="plates", one_sided_bottom=True),
    "ittc friction": VHull(friction="ittc1957", one_sided_bottom=False),
    "one-sided + ittc friction": VHull(friction="ittc1957", one_sided_bottom=True),
}
# the shipped hulls: speedboat (BoatOnStep-v0's) and speedboat_ittc
assert HULLS["friction plates"] == SHIPPED["speedboat"]
assert replace(HULLS["ittc friction"], name="speedboat_ittc") == SHIPPED["speedboat_ittc"]

# Day and Haag's porpoising limits as Savitsky (1964) charts them: critical trim (deg) as a
# cubic in x = sqrt(C_L_beta / 2), per deadrise (deg), as fitted by OpenPlaning (module doc)
PORPOISING_FITS = {
    0.0: (-376.37, 329.74, -38.485, 1.3415),
    10.0: (-356.05, 314.36, -41.674, 3.5786),
    20.0: (-254.51, 239.65, -23.936, 3.0195),
}
PORPOISING_X_RANGE = (0.13, 0.30)


def critical_trim_deg(x: float, deadrise_deg: float) -> float:
    """Day and Haag's critical trim at x = sqrt(C_L_beta / 2): the three fitted curves, then
    a quadratic through them in deadrise (Lagrange on 0, 10, 20 deg)."""
    b = list(PORPOISING_FITS)
    t = [np.polyval(PORPOISING_FITS[d], x) for d in b]
    out = 0.0
    for i in range(3):
        w = 1.0
        for j in range(3):
            if j != i:
                w *= (deadrise_deg - b[j]) / (b[i] - b[j])
        out += w * t[i]
    return float(out)


def craft_of(hull: VHull) -> Craft:
    return Craft.from_dict(tomllib.loads(speedboat_toml(hull)), f"VHull {hull.friction}")


def wetted_length_m(hull: VHull, pos_z: np.ndarray, quat: np.ndarray) -> np.ndarray:
    """Mean wetted length [E] (m): the average of the keel's and the chine's wetted lengths
    (Savitsky's lambda times the beam), each from the transom to where that line of the hull
    (with its rise toward the bow) comes out of the water; ``pos_z`` [E], ``quat`` [E, 4]."""
    s = np.linspace(0.0, hull.length_m, 501)
    rot = quat_matrices(np.ascontiguousarray(quat))
    wet = []
    for side in (0.0, 1.0):  # keel, port chine
        pts = []
        for x in s:
            half, rise, beta = hull.station(x)
            pts.append((x - hull.lcg_m, side * half, rise + side * half * math.tan(beta)))
        pts = np.array(pts) - (0.0, 0.0, hull.vcg_m)
        z = pos_z[:, None] + np.einsum("ej,nj->en", rot[:, 2, :], pts)
        wet.append(np.where(z < 0.0, s[None, :], 0.0).max(axis=1))
    return 0.5 * (wet[0] + wet[1])


def steady_runs(craft: Craft, thrust_n: np.ndarray, hull: VHull) -> dict[str, np.ndarray]:
    """Speed, mean trim, the trim's peak-to-peak and the CG's mean rise from its floating
    height over the last window, and the wetted length at the end, each [E]."""
    E = len(thrust_n)
    (prop,) = craft.thrusters
    sim = Simulator(craft, WORLD, num_envs=E, dt=DT)
    height, trim = static_float(craft)
    sim.reset(pos=(0.0, 0.0, height), quat=(math.cos(trim / 2), 0.0, -math.sin(trim / 2), 0.0))
    ctrl = np.zeros((E, 3))
    ctrl[:, 0] = thrust_control(thrust_n, prop.min_thrust_n, prop.max_thrust_n)
    ctrl[:, 2] = -1.0  # tabs flush
    n, window = int(round(SECONDS / DT)), int(round(WINDOW_S / DT))
    sim.step(ctrl, steps=n - window)
    trims, heights = [], []
    for _ in range(window // 4):
        sim.step(ctrl, steps=4)
        rot = quat_matrices(np.ascontiguousarray(sim.quat[:, 0]))
        trims.append(np.degrees(np.arcsin(np.clip(rot[:, 2, 0], -1, 1))))
        heights.append(sim.pos[:, 0, 2].copy())
    trims = np.array(trims)
    return dict(
        speed=np.linalg.norm(sim.lin_vel[:, 0], axis=1),
        trim=trims.mean(axis=0),
        trim_ptp=np.ptp(trims, axis=0),
        cg_rise=np.mean(heights, axis=0) - height,
        wetted=wetted_length_m(hull, sim.pos[:, 0, 2], sim.quat[:, 0]),
    )


HEADER = (
    "hull", "thrust_n", "speed_mps", "cv", "fnv", "region", "trim_deg", "trim_ptp_deg",
    "porpoising", "savitsky_in_range", "savitsky_trim_deg", "trim_error_deg", "rw",
    "savitsky_rw", "rw_error_rel", "sqrt_cl_half", "critical_trim_deg", "chart_range",
    "cg_rise_m", "wetted_length_m",
)  # fmt: skip


def _savitsky(ref: PrismaticHull, speed: float):
    """Savitsky's state at ``speed``, or None where it has no equilibrium (or at rest)."""
    if speed < 0.5:
        return None
    try:
        return savitsky(ref, speed)
    except ValueError:
        return None


def rows_of(name: str, hull: VHull, thrust: np.ndarray) -> list[tuple]:
    runs = steady_runs(craft_of(hull), thrust, hull)
    ref, weight = of_hull(hull), hull.mass_kg * WORLD.gravity_mps2
    vol = hull.mass_kg / WORLD.water_density_kgm3
    g, rho, b = WORLD.gravity_mps2, WORLD.water_density_kgm3, hull.chine_beam_m
    rows = []
    for t, v, trim, ptp, rise, wet in zip(
        thrust, *(runs[k] for k in ("speed", "trim", "trim_ptp", "cg_rise", "wetted")), strict=True
    ):
        v = float(v)
        fnv = v / math.sqrt(g * vol ** (1 / 3))
        lo, hi = FNV_TRANSITION
        region = "displacement" if fnv < lo else ("transition" if fnv <= hi else "planing")
        rw = float(t) / weight
        s = _savitsky(ref, v)
        ok = bool(s is not None and s.in_range)
        x = math.sqrt(weight / (0.5 * rho * v * v * b * b) / 2) if v > 0.5 else math.inf
        in_chart = PORPOISING_X_RANGE[0] <= x <= PORPOISING_X_RANGE[1]
        crit = critical_trim_deg(x, hull.deadrise_deg) if math.isfinite(x) else math.nan
        nan = math.nan
        rows.append((
            name, float(t), v, v / math.sqrt(g * b), fnv, region, float(trim), float(ptp),
            bool(ptp > PORPOISE_PTP_DEG), ok, s.trim_deg if ok else nan,
            float(trim) - s.trim_deg if ok else nan, rw, s.resistance_over_weight if ok else nan,
            rw / s.resistance_over_weight - 1.0 if ok else nan, x, crit, in_chart,
            float(rise), float(wet),
        ))  # fmt: skip
    return rows


TURN_HEADER = ("hull", "heel_min_deg", "heel_max_deg", "yaw_rate_mean_rps", "yaw_rate_ptp_rps")


def hard_turn(name: str, craft: Craft) -> tuple:
    """Hard over to starboard at 15 m/s (1.8 kN, tabs flush: tests/craft/test_speedboat.py's
    turn), after 3 s straight: heel (starboard down +) and yaw rate over seconds 4-8 of the
    turn, sampled every 0.05 s. A steady turn holds its heel; a hull that lost its roll
    damping swings."""
    (prop,) = craft.thrusters
    sim = Simulator(craft, WORLD, num_envs=1, dt=DT)
    sim.reset(pos=(0.0, 0.0, 0.3), lin_vel=(15.0, 0.0, 0.0))
    ctrl = np.zeros((1, 3))
    ctrl[:, 0] = thrust_control(np.array([1800.0]), prop.min_thrust_n, prop.max_thrust_n)
    ctrl[:, 2] = -1.0
    sim.step(ctrl, steps=int(round(3.0 / DT)))
    ctrl[:, 1] = 1.0
    sim.step(ctrl, steps=int(round(4.0 / DT)))
    heel, yaw = [], []
    for _ in range(80):
        sim.step(ctrl, steps=10)
        rot = quat_matrices(np.ascontiguousarray(sim.quat[:, 0]))[0]
        heel.append(math.degrees(math.atan2(rot[2, 1], rot[2, 2])))
        yaw.append(float(sim.ang_vel[0, 0, 2]))
    return (name, min(heel), max(heel), float(np.mean(yaw)), float(np.ptp(yaw)))


GRID_MPS = np.arange(3.5, 18.01, 0.5)  # the common speeds the hulls are compared at
GRID_HEADER = (
    "hull", "speed_mps", "fnv", "region", "trim_deg", "savitsky_trim_deg", "trim_error_deg",
    "rw", "savitsky_rw", "rw_error_rel",
)  # fmt: skip


def on_grid(name: str, hull: VHull, rows: list[tuple]) -> list[tuple]:
    """The hull's steady trim and R/W against speed (linear between its runs) at the speeds of
    ``GRID_MPS`` where Savitsky's method is valid and the runs bracket the speed: every hull
    compared at the same speeds (the thrust sweep lands each hull at different ones, and the
    error changes fast with speed)."""
    steady = sorted((r for r in rows if r[0] == name and not r[8]), key=lambda r: r[2])
    v = np.array([r[2] for r in steady])
    trim, rw = np.array([r[6] for r in steady]), np.array([r[12] for r in steady])
    vol = hull.mass_kg / WORLD.water_density_kgm3
    out = []
    for speed in GRID_MPS:
        s = _savitsky(of_hull(hull), float(speed))
        if s is None or not s.in_range or not v[0] <= speed <= v[-1]:
            continue
        fnv = speed / math.sqrt(WORLD.gravity_mps2 * vol ** (1 / 3))
        lo, hi = FNV_TRANSITION
        region = "displacement" if fnv < lo else ("transition" if fnv <= hi else "planing")
        t, r = float(np.interp(speed, v, trim)), float(np.interp(speed, v, rw))
        out.append((
            name, float(speed), fnv, region, t, s.trim_deg, t - s.trim_deg, r,
            s.resistance_over_weight, r / s.resistance_over_weight - 1.0,
        ))  # fmt: skip
    return out


def grid_summary(grid: list[tuple]) -> dict[str, float]:
    """RMS and largest errors on the common speeds: all valid ones, and the planing ones."""
    out = {}
    for label, keep in (("valid", lambda r: True), ("planing", lambda r: r[3] == "planing")):
        sel = [r for r in grid if keep(r)]
        te, re = np.array([r[6] for r in sel]), np.array([r[9] for r in sel])
        out[f"{label}_n"] = len(sel)
        out[f"{label}_trim_rms_deg"] = float(np.sqrt(np.mean(te**2))) if sel else math.nan
        out[f"{label}_trim_max_deg"] = float(np.max(np.abs(te))) if sel else math.nan
        out[f"{label}_rw_rms"] = float(np.sqrt(np.mean(re**2))) if sel else math.nan
        out[f"{label}_rw_max"] = float(np.max(np.abs(re))) if sel else math.nan
    return out


def summary(rows: list[tuple]) -> dict[str, float]:
    """Errors against Savitsky over the valid, steady rows: all of them and the planing ones."""
    out = {}
    for label, keep in (("valid", lambda r: True), ("planing", lambda r: r[5] == "planing")):
        sel = [r for r in rows if r[9] and not r[8] and keep(r)]
        te = np.array([r[11] for r in sel])
        re = np.array([r[14] for r in sel])
        out[f"{label}_n"] = len(sel)
        out[f"{label}_trim_rms_deg"] = float(np.sqrt(np.mean(te**2))) if sel else math.nan
        out[f"{label}_trim_max_deg"] = float(np.max(np.abs(te))) if sel else math.nan
        out[f"{label}_rw_rms"] = float(np.sqrt(np.mean(re**2))) if sel else math.nan
        out[f"{label}_rw_max"] = float(np.max(np.abs(re))) if sel else math.nan
    porpoise = [r for r in rows if r[8] and r[2] > 10.0]
    out["porpoising_onset_mps"] = min((r[2] for r in porpoise), default=math.nan)
    return out


def plot(rows: list[tuple], path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_t, ax_r) = plt.subplots(1, 2, figsize=(12, 4.6))
    hull = next(iter(HULLS.values()))
    vol = hull.mass_kg / WORLD.water_density_kgm3
    fnv_scale = math.sqrt(WORLD.gravity_mps2 * vol ** (1 / 3))
    speeds = np.arange(3.0, 30.01, 0.1)
    ref = [_savitsky(of_hull(hull), float(v)) for v in speeds]
    valid = np.array([s is not None and s.in_range for s in ref])
    for ax, key, sim_col in ((ax_t, "trim_deg", 6), (ax_r, "resistance_over_weight", 12)):
        ys = np.array([math.nan if s is None else getattr(s, key) for s in ref])
        ax.plot(speeds, np.where(valid, ys, np.nan), "k-", lw=2.5, label="Savitsky 1964 (valid)")
        ax.plot(speeds, np.where(valid, np.nan, ys), "k:", lw=1, label="Savitsky, outside range")
        lo, hi = (f * fnv_scale for f in FNV_TRANSITION)
        ax.axvspan(lo, hi, color="0.9", zorder=0, label="transition (Fn_V 1-3.5)")
        for name in HULLS:
            sel = [r for r in rows if r[0] == name]
            v = np.array([r[2] for r in sel])
            y = np.array([r[sim_col] for r in sel])
            (line,) = ax.plot(v, y, ".-", label=name)
            por = np.array([r[8] for r in sel])
            ax.plot(v[por], y[por], "x", color=line.get_color(), ms=8)
        ax.set_xlabel("speed (m/s)")
    ax_t.set_ylabel("running trim (deg)   (x: porpoising, mean trim)")
    ax_r.set_ylabel("resistance / weight")
    ax_t.set_ylim(0, 8)
    ax_r.set_ylim(0, 0.5)
    ax_t.legend(fontsize=7)
    fig.suptitle(
        "Speedboat steady runs beside Savitsky's method (python -m benchmarks.study_savitsky)"
    )
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main() -> None:
    parser = arguments(__doc__, "every other thrust, into build/study_quick")
    args = parser.parse_args()
    out = out_dir(args.out, args.quick)
    machine = describe()
    thrust = np.arange(0.0, 4501.0, 200.0 if args.quick else 100.0)
    rows, grid, turns, notes = [], [], [], []
    for name, hull in HULLS.items():
        turns.append(hard_turn(name, craft_of(hull)))
        print("hard turn: heel {1:.1f} to {2:.1f} deg, yaw rate {3:.3f} rad/s (swing {4:.3f})"
              .format(*turns[-1]))  # fmt: skip
        hull_rows = rows_of(name, hull, thrust)
        rows += hull_rows
        grid += on_grid(name, hull, hull_rows)
        s, g = summary(hull_rows), grid_summary([r for r in grid if r[0] == name])
        line = (
            f"{name}: at the runs' own speeds, {s['valid_n']} steady valid rows: trim error rms "
            f"{s['valid_trim_rms_deg']:.3f} deg, R/W rms {s['valid_rw_rms']:.3f}; on the common "
            f"speeds ({g['valid_n']}): trim rms {g['valid_trim_rms_deg']:.3f} max "
            f"{g['valid_trim_max_deg']:.3f} deg, R/W rms {g['valid_rw_rms']:.3f} max "
            f"{g['valid_rw_max']:.3f}; planing (Fn_V > 3.5, {g['planing_n']}): trim rms "
            f"{g['planing_trim_rms_deg']:.3f} max {g['planing_trim_max_deg']:.3f} deg, R/W rms "
            f"{g['planing_rw_rms']:.3f} max {g['planing_rw_max']:.3f}; porpoising from "
            f"{s['porpoising_onset_mps']:.1f} m/s"
        )
        print(line, flush=True)
        notes.append(line)
    path = write_csv(
        out / "study_savitsky.csv", HEADER, [[fmt(c) for c in r] for r in rows], [*machine, *notes]
    )
    write_csv(
        out / "study_savitsky_grid.csv",
        GRID_HEADER,
        [[fmt(c) for c in r] for r in grid],
        [*machine, *notes],
    )
    write_csv(
        out / "study_savitsky_turn.csv", TURN_HEADER, [[fmt(c) for c in r] for r in turns], machine
    )
    plot(rows, out / "study_savitsky.png")
    print(f"wrote {path}, study_savitsky_grid.csv, study_savitsky_turn.csv, study_savitsky.png")


# ---- the docs -------------------------------------------------------------------------------

# how the docs name each hull (the first two: the shipped ones)
LABELS = {
    "friction plates": "friction plates (first: `speedboat`)",
    "one-sided": "one-sided",
    "ittc friction": "ITTC friction (`speedboat_ittc`)",
    "one-sided + ittc friction": "one-sided + ITTC friction",
}
# the thrusts (N) of docs/environments.md's table of the shipped hull's steady runs
STEADY_TABLE_N = (0, 600, 900, 1200, 1500, 1800, 2100, 3000)


def _read(name: str) -> list[dict] | None:
    path = DOCS / name
    if not path.is_file():
        return None
    rows = read_csv(path)[1]
    for r in rows:
        for k, x in r.items():
            if x in ("True", "False"):
                r[k] = x == "True"
            elif k not in ("hull", "region"):
                r[k] = float(x)
    return rows


def _num(x: float, digits: int) -> str:
    """``x`` to ``digits`` decimals, a bare 0 where it rounds to zero, blank where NaN."""
    if math.isnan(x):
        return ""
    return "0" if abs(x) < 0.5 * 10.0**-digits else f"{x:.{digits}f}"


def steady_markdown() -> str:
    """docs/environments.md's table: the shipped hull's steady runs at some thrusts beside
    Savitsky's trim and R/W (blank where his method is not valid), from
    docs/study_savitsky.csv; the largest trim in bold."""
    rows = _read("study_savitsky.csv")
    if rows is None:
        return "(no docs/study_savitsky.csv yet: run python -m benchmarks.study_savitsky)"
    runs = {r["thrust_n"]: r for r in rows if r["hull"] == "friction plates"}
    peak = max(r["trim_deg"] for r in runs.values() if not r["porpoising"])
    lines = [
        "| thrust (N) | speed (m/s) | FnV | trim (deg) | Savitsky | R/W | Savitsky | CG rise (m) "
        "| wetted length (m) |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for thrust in STEADY_TABLE_N:
        r = runs[float(thrust)]
        trim = _num(r["trim_deg"], 2)
        trim = f"**{trim}**" if r["trim_deg"] == peak else trim
        trim += " (porpoising)" if r["porpoising"] else ""
        cells = (
            _num(r["speed_mps"], 1), _num(r["fnv"], 2), trim, _num(r["savitsky_trim_deg"], 2),
            _num(r["rw"], 3), _num(r["savitsky_rw"], 3), _num(r["cg_rise_m"], 3),
            _num(r["wetted_length_m"], 2),
        )  # fmt: skip
        lines.append(f"| {thrust} | " + " | ".join(cells) + " |")
    lines += [
        "",
        prose(
            "(Savitsky blank: outside his method's range there; porpoising: the trim swings "
            f"more than {PORPOISE_PTP_DEG} deg over the last {WINDOW_S:g} s. From "
            "[study_savitsky.csv](study_savitsky.csv), `python -m benchmarks.study_savitsky`.)"
        ),
    ]
    return "\n".join(lines)


def grid_markdown() -> str:
    """docs/study_savitsky.md's table of each hull's errors against Savitsky on the common
    speeds (docs/study_savitsky_grid.csv) and its porpoising onset (study_savitsky.csv)."""
    grid, rows = _read("study_savitsky_grid.csv"), _read("study_savitsky.csv")
    if grid is None or rows is None:
        return "(no docs/study_savitsky_grid.csv yet: run python -m benchmarks.study_savitsky)"
    cols = ("hull", "speed_mps", "fnv", "region", "trim_deg", "savitsky_trim_deg",
            "trim_error_deg", "rw", "savitsky_rw", "rw_error_rel")  # fmt: skip
    assert cols == GRID_HEADER
    lines = [
        "| hull | trim rms, all valid (deg) | R/W rms, all valid | trim rms, planing (deg) "
        "| trim max, planing | R/W rms, planing | R/W max, planing | porpoising from |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name in dict.fromkeys(r["hull"] for r in grid):
        g = grid_summary([tuple(r[c] for c in cols) for r in grid if r["hull"] == name])
        onset = min(
            (r["speed_mps"] for r in rows if r["hull"] == name and r["porpoising"]
             and r["speed_mps"] > 10.0),
            default=math.nan,
        )  # fmt: skip
        lines.append(
            f"| {LABELS.get(name, name)} | {g['valid_trim_rms_deg']:.3f} | "
            f"{100 * g['valid_rw_rms']:.1f}% | {g['planing_trim_rms_deg']:.3f} | "
            f"{g['planing_trim_max_deg']:.3f} | {100 * g['planing_rw_rms']:.1f}% | "
            f"{100 * g['planing_rw_max']:.1f}% | {onset:.1f} m/s |"
        )
    n = {k: sum(1 for r in grid if r["hull"] == next(iter(LABELS)) and k(r))
         for k in (lambda r: True, lambda r: r["region"] == "planing")}  # fmt: skip
    total, planing = n.values()
    note = (
        f"Planing is Fn_V above {FNV_TRANSITION[1]} ({total} common speeds in all, {planing} "
        f"planing); the transition (shaded on the chart) is Fn_V {FNV_TRANSITION[0]:g} to "
        f"{FNV_TRANSITION[1]}: planing hulls beat displacement hulls above Fn_V = "
        f"{FNV_TRANSITION[0]:g} and plane fully around 3-3.5 (Radojcic et al., Polish Maritime "
        "Research 2(82), 2014)."
    )
    lines += ["", prose(note)]
    return "\n".join(lines)


def turn_markdown() -> str:
    """docs/study_savitsky.md's table of each hull hard over at 15 m/s, from
    docs/study_savitsky_turn.csv."""
    turns = _read("study_savitsky_turn.csv")
    if turns is None:
        return "(no docs/study_savitsky_turn.csv yet: run python -m benchmarks.study_savitsky)"
    lines = [
        "| hull | heel (deg) | yaw rate mean (rad/s) | yaw rate swing (rad/s) |",
        "|---|---|---:|---:|",
    ]
    for r in turns:
        label = LABELS.get(r["hull"], r["hull"]).replace("first: ", "")
        lines.append(
            f"| {label} | {r['heel_min_deg']:.1f} to {r['heel_max_deg']:.1f} | "
            f"{r['yaw_rate_mean_rps']:.3f} | {r['yaw_rate_ptp_rps']:.3f} |"
        )
    return "\n".join(lines)


if __name__ == "__main__":
    main()
