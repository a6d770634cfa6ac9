"""Stability limits of the shipped integrators, and how each one fails.

The problems are those of ``benchmarks/study_accuracy.py`` (projectile, buoyancy spring,
Kepler orbit, torque-free body, and the three crafts' maneuvers), run through the real
:class:`Simulator` in float64 and float32, one environment each.

**Largest stable dt.** A run over the problem's whole interval is *bounded* when its state
stays finite and a chosen size stays below 10 times its start (growth only: a method that
damps is stable, however inaccurate), checked after every step (runs of more than 20000
steps: at 20000 evenly spaced points; ``--quick``: 100 points):

- ``projectile``: speed against the exact solution's largest speed;
- ``spring``: the oscillator's energy about its equilibrium against its start (the body
  leaves the water at 23.8 times the start: the factor is met before that);
- ``kepler``: the orbit's semi-major axis ``a = -GM / 2E`` (from its energy E: kinetic
  plus ``-GM m/|x|``) within a factor of 10 of its start either way, and the orbit bound
  (E < 0): escaping or falling into the centre is unbounded;
- ``torque_free``: the kinetic energy within 10% of its start, either way (angular momentum
  is the state and is kept exactly, so the energy cannot leave [M^2 / 2 I3, M^2 / 2 I1],
  0.78 to 2.34 times its start here: a factor of 10 could never trip);
- the crafts: the largest speed and angular speed against those of rk4 at the env's dt / 16
  (angular speed floored at 1 rad/s).

The largest bounded dt is found by bisection on log dt between the nominal dt / 64 (which
must be bounded) and a tenth of the interval (10 steps), 10 halvings (the bracket is then
about 2% wide); the table gives the largest dt found bounded and the smallest found not.
Bisection assumes one boundary; a method can be bounded again above an unbounded dt (not
searched).

**Failure modes**, one chart each (``docs/study_stability_*.png``), their numbers in
``docs/study_stability_modes.csv``:

- ``euler_spring``: explicit Euler's energy on the spring growing as (1 + (omega dt)^2)^n;
- ``tetra_spin``: the Verlet tetrahedron's energy error against the turn per step |w| dt on
  the intermediate-axis spin, with and without the switch to the rigid turn
  (``World.tetra_rigid_spin_rad``), against symplectic Euler;
- ``stiff_spring``: a heavy area sample (omega = 100 rad/s) near omega dt = 2 for symplectic
  Euler (and rk4, whose limit is 2.83);
- ``airplane_damping``: the 5 g paper airplane's fast aerodynamic damping around symplectic
  Euler's stability limit;
- ``clamps``: the paper airplane beyond that limit with the velocity and force clamps at their
  defaults (156 m/s, 1e7 N) and effectively off (1e9 m/s, 1e18 N), over 6 s, run on past
  the step ``Simulator.diverged`` flags (where an env ends the episode; marked).

- ``seed_methods``: the seed's methods: accurate Euler's energy gain on the spring,
  ``(1 + (omega dt)^2 / 2)^n``; in float32 the velocity-less Verlet's speed lost to rounding
  far from the origin (``x - x_old`` keeps ulp(x) / dt of it), against symplectic Euler and
  the prescaled NSV; the implicit midpoint's fixed-point iterations against omega dt on the
  spring, up to where they no longer converge (flagged).

Writes ``docs/study_stability.csv``, ``docs/study_stability_modes.csv`` and the six charts
(machine description in ``#`` lines at the top of each CSV)::

    python -m benchmarks.study_stability            # full size, about a minute on 2 cores
    python -m benchmarks.study_stability --quick    # fewer halvings, into build/study_quick
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from benchmarks import study_accuracy as SA
from benchmarks.common import arguments, describe, fmt, out_dir, write_csv
from fluidsim_envs.physics import Buoyancy, Craft, Simulator, World
from fluidsim_envs.physics import integrators as IT

FACTOR = 10.0
TORQUE_FREE_BAND = 0.1  # the torque-free body's energy: bounded within 10% of its start
CRAFTS = ("paper_airplane", "speedboat", "uuv")


def peak_ratio(p: SA.Problem, r: dict, ref: dict) -> float:
    """The largest size / allowed size over the run (> 1: unbounded); inf if not finite."""
    h = r["hist"]
    if r["diverged"] or not np.all(np.isfinite(h)):
        return math.inf
    if p.name == "projectile":
        return float(h[:, 3].max() / (FACTOR * ref["speed"]))
    if p.name == "spring":
        e = SA.spring_energy(h[:, 1], h[:, 2]) / (0.5 * SA.K_SPRING * SA.AMPLITUDE**2)
        return float(e.max() / FACTOR)
    if p.name == "kepler":  # GM = 1, m = 1, a0 = 1
        energy = h[:, 5] - 1.0 / h[:, 6]
        if np.any(energy >= 0.0):
            return math.inf
        a = -0.5 / energy
        return float(np.maximum(a, 1.0 / a).max() / FACTOR)
    if p.name == "torque_free":
        return float(np.abs(h[:, 5] / ref["energy"] - 1.0).max() / TORQUE_FREE_BAND)
    return float(
        max(
            h[:, 3].max() / (FACTOR * ref["speed"]),
            h[:, 4].max() / (FACTOR * max(ref["spin"], 1.0)),
        )
    )


def reference_sizes(p: SA.Problem) -> dict:
    """The sizes the bounded test compares against."""
    if p.name == "projectile":
        t = p.seconds
        return {"speed": float(np.linalg.norm(np.asarray(SA.V0) - [0.0, 0.0, SA.G * t]))}
    if p.name == "torque_free":
        return {"energy": 0.5 * float(np.sum(np.asarray(SA.TF_INERTIA) * np.square(SA.TF_W0)))}
    if p.name in CRAFTS:
        h = SA.run(p, "rk4", p.nominal_dt / 16, samples=100)["hist"]
        return {"speed": float(h[:, 3].max()), "spin": float(h[:, 4].max())}
    return {}


def largest_bounded_dt(
    p: SA.Problem, integrator: str, ref: dict, halvings: int, dtype=np.float64, checks=20000
):
    """(largest bounded dt, smallest unbounded dt, its peak ratio, runs) by bisection on log dt;
    the first is NaN when even the lower end is unbounded, the second inf when the upper end
    is bounded."""
    lo, hi = p.nominal_dt / 64, p.seconds / 10

    def ok(dt):
        return peak_ratio(p, SA.run(p, integrator, dt, dtype, samples=checks), ref)

    runs = 2
    if ok(hi) <= 1.0:
        return hi, math.inf, runs
    if ok(lo) > 1.0:
        return math.nan, lo, runs
    for _ in range(halvings):
        mid = math.sqrt(lo * hi)
        runs += 1
        if ok(mid) <= 1.0:
            lo = mid
        else:
            hi = mid
    return lo, hi, runs


# ---- failure modes ---------------------------------------------------------------------------

STIFF_OMEGA = 100.0
STIFF = Craft(
    name="stiff_float",
    mass_kg=1.0,
    inertia_kgm2=(1.0, 1.0, 1.0),
    buoyancy=(Buoyancy("hull", (0.0, 0.0, 0.0), "area", area_m2=STIFF_OMEGA**2 / (SA.RHO * SA.G)),),
)
STIFF_Z_EQ = -SA.G / STIFF_OMEGA**2  # waterline depth m / (rho A) = g / omega^2
STIFF_AMPLITUDE = 1e-4  # a tenth of the depth: rk4's stages stay in the water at omega dt 2.9


def mode_euler_spring(probs, rows, plt, out):
    p = probs["spring"]
    e0 = 0.5 * SA.K_SPRING * SA.AMPLITUDE**2
    leave = (SA.Z_EQ / SA.AMPLITUDE) ** 2  # energy ratio at which the body leaves the water
    fig, ax = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
    for m, dt in (
        ("explicit_euler", 1 / 2000),
        ("explicit_euler", 1 / 1000),
        ("explicit_euler", 1 / 300),
        ("explicit_euler", 1 / 100),
        ("symplectic_euler", 1 / 100),
    ):
        h = SA.run(p, m, dt, samples=400)["hist"]
        e = SA.spring_energy(h[:, 1], h[:, 2]) / e0
        keep = np.concatenate([[True], e[:-1] < leave])  # up to leaving the water
        style = "-" if m == "explicit_euler" else "k-"
        (line,) = ax.semilogy(
            h[keep, 0], e[keep], style, lw=1, label=f"{m}, dt = 1/{round(1 / dt)} s"
        )
        if m == "explicit_euler":
            n = h[keep, 0] / dt
            ax.semilogy(
                h[keep, 0], (1 + (SA.OMEGA * dt) ** 2) ** n, "--", color=line.get_color(), lw=0.8
            )
        ratio = float(e[keep][-1])
        rows.append(("euler_spring", m, dt, "omega_dt", SA.OMEGA * dt))
        rows.append(("euler_spring", m, dt, "t_end_s", float(h[keep, 0][-1])))
        rows.append(("euler_spring", m, dt, "energy_ratio_end", ratio))
        rows.append(("euler_spring", m, dt, "energy_ratio_max", float(e[keep].max())))
        print(f"euler_spring {m} dt {dt:.5f}: E/E0 = {ratio:.3g} at t = {h[keep, 0][-1]:.2f} s")
    ax.axhline(leave, color="gray", lw=0.8)
    ax.text(12.0, leave / 1.35, "the body leaves the water (the spring ends)", fontsize=8)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("energy / initial energy")
    ax.set_title(
        f"Explicit Euler gains energy on the buoyancy spring (omega = {SA.OMEGA:.2f} rad/s);\n"
        "dashed: (1 + (omega dt)^2)^n",
        fontsize=10,
    )
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="center right")
    fig.savefig(out / "study_stability_euler_spring.png", dpi=100)
    plt.close(fig)


def mode_seed_methods(rows, plt, out):
    """How the seed's own methods fail: accurate Euler's energy gain on the spring, the
    velocity-less Verlet's velocity lost to rounding far from the origin, and the implicit
    midpoint's fixed-point iteration as omega dt grows."""
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8), constrained_layout=True)
    # (a) accurate Euler gains energy by 1 + (omega dt)^2 / 2 a step (its map's determinant)
    p = SA.problems()[1]
    e0 = 0.5 * SA.K_SPRING * SA.AMPLITUDE**2
    leave = (SA.Z_EQ / SA.AMPLITUDE) ** 2
    ax = axes[0]
    for m, dt in (("accurate_euler", 1 / 100), ("accurate_euler", 1 / 300),
                  ("explicit_euler", 1 / 300), ("symplectic_euler", 1 / 100)):  # fmt: skip
        h = SA.run(p, m, dt, samples=400)["hist"]
        e = SA.spring_energy(h[:, 1], h[:, 2]) / e0
        keep = np.concatenate([[True], e[:-1] < leave])
        (line,) = ax.semilogy(h[keep, 0], e[keep], lw=1, label=f"{m}, dt = 1/{round(1 / dt)} s")
        if m == "accurate_euler":
            n = h[keep, 0] / dt
            growth = (1 + 0.5 * (SA.OMEGA * dt) ** 2) ** n
            ax.semilogy(h[keep, 0], growth, "--", color=line.get_color(), lw=0.8)
        rows.append(("seed_methods", m, dt, "energy_ratio_end", float(e[keep][-1])))
        rows.append(("seed_methods", m, dt, "t_end_s", float(h[keep, 0][-1])))
    ax.set_title("accurate Euler gains energy on the spring\n(dashed: (1 + (omega dt)^2/2)^n)",
                 fontsize=10)  # fmt: skip
    ax.set_xlabel("t (s)")
    ax.set_ylabel("energy / initial energy")
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
    # (b) a body coasting at 1 m/s, x0 from the origin, float32: the velocity after 1000 steps
    ax = axes[1]
    ball = Craft(name="ball", mass_kg=1.0, inertia_kgm2=(0.4, 0.4, 0.4))
    far = np.geomspace(1.0, 1e5, 11)
    for m in ("symplectic_euler", "prescaled_symplectic_euler", "position_verlet"):
        sim = Simulator(ball, World(gravity_mps2=0.0), num_envs=far.size, dt=0.01,
                        integrator=m, dtype=np.float32)  # fmt: skip
        sim.reset(pos=np.stack([far, 0 * far, 0 * far], 1), lin_vel=(1.0, 0.0, 0.0))
        sim.step(steps=1000)
        err = np.abs(sim.lin_vel[:, 0, 0].astype(np.float64) - 1.0)
        ax.loglog(far, np.maximum(err, 1e-9), marker="o", lw=1, label=m)
        for x0, e in zip(far, err, strict=True):
            rows.append(("seed_methods", m, 0.01, f"f32_speed_err_at_{x0:.3g}_m", float(e)))
    ax.loglog(far, np.spacing(far.astype(np.float32)) / 0.01, "k:", lw=0.8,
              label="ulp(x0) / dt")  # fmt: skip
    ax.set_title("float32, 1 m/s coast for 10 s: speed error\n(floored at 1e-9)", fontsize=10)
    ax.set_xlabel("distance from the origin (m)")
    ax.set_ylabel("|v - 1| (m/s)")
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
    # (c) the implicit midpoint's iterations on the spring against omega dt
    ax = axes[2]
    world = World(water=True, water_density_kgm3=SA.RHO)
    theta = np.linspace(0.05, 2.4, 48)
    its = []
    for th in theta:
        sim = Simulator(SA.FLOAT, world, dt=th / SA.OMEGA, integrator="implicit_midpoint")
        sim.reset(pos=(0.0, 0.0, SA.Z_EQ + SA.AMPLITUDE))
        sim.step(steps=5)
        its.append(float(sim.iterations[0]))
        rows.append(("seed_methods", "implicit_midpoint", th / SA.OMEGA, "iterations", its[-1]))
        rows.append(("seed_methods", "implicit_midpoint", th / SA.OMEGA, "diverged",
                     float(sim.diverged[0])))  # fmt: skip
    its = np.array(its)
    flagged = its > IT.IMPLICIT_MAX_ITERATIONS
    ax.plot(theta[~flagged], its[~flagged], "o-", ms=3, label="iterations (most of 5 steps)")
    ax.plot(theta[flagged], np.full(flagged.sum(), IT.IMPLICIT_MAX_ITERATIONS + 1), "rx",
            label="flagged diverged")  # fmt: skip
    ax.axvline(2.0, color="gray", lw=0.8)
    ax.text(2.02, 5, "contraction omega dt / 2 = 1", fontsize=8, rotation=90)
    ax.set_title("implicit midpoint: fixed-point iterations per step\non the spring", fontsize=10)
    ax.set_xlabel("omega dt")
    ax.set_ylabel("iterations")
    ax.legend(fontsize=7)
    ax.grid(True, alpha=0.3)
    fig.savefig(out / "study_stability_seed_methods.png", dpi=100)
    plt.close(fig)


def mode_tetra_spin(rows, plt, out, quick):
    racket = Craft(name="racket", mass_kg=1.0, inertia_kgm2=(1.0, 2.0, 3.0))
    dt = 1 / 100
    turns = np.geomspace(0.005, 3.0, 7 if quick else 16)
    methods = {
        "verlet_tetra, no switch": ("verlet_tetra", math.inf),
        "verlet_tetra, switch at 0.05 rad (default)": ("verlet_tetra", 0.05),
        "symplectic_euler (rigid)": ("symplectic_euler", 0.05),
    }
    fig, ax = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
    for label, (m, switch) in methods.items():
        errs = []
        for turn in turns:
            spin = turn / dt
            w0 = (0.01 * spin, spin, 0.01 * spin)
            p = SA.Problem(
                "tetra_spin",
                racket,
                World(gravity_mps2=0.0, tetra_rigid_spin_rad=switch),
                2.0,
                dt,
                dict(ang_vel=w0),
            )
            r = SA.run(p, m, dt, samples=100)
            e0 = 0.5 * (1.0 * w0[0] ** 2 + 2.0 * w0[1] ** 2 + 3.0 * w0[2] ** 2)
            h = r["hist"]
            err = math.inf if r["diverged"] else float(np.abs(h[:, 5] / e0 - 1).max())
            errs.append(err)
            rows.append(("tetra_spin", label, dt, f"energy_err_max@turn={turn:.4g}", err))
        ax.loglog(turns, np.maximum(errs, 1e-16), "o-", ms=3, label=label)
        print(f"tetra_spin {label}: " + " ".join(f"{e:.1e}" for e in errs))
    ax.axvline(0.05, color="gray", lw=0.8)
    ax.set_xlabel("|w| dt (rad per step), dt = 1/100 s")
    ax.set_ylabel("max |energy error| / E over 2 s")
    ax.set_title("Intermediate-axis spin (I = 1, 2, 3): the tetrahedron's turn per step")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(out / "study_stability_tetra_spin.png", dpi=100)
    plt.close(fig)


def mode_stiff_spring(rows, plt, out):
    world = World(water=True, water_density_kgm3=SA.RHO)
    k = STIFF.mass_kg * STIFF_OMEGA**2
    e0 = 0.5 * k * STIFF_AMPLITUDE**2
    leave = (STIFF_Z_EQ / STIFF_AMPLITUDE) ** 2
    fig, ax = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
    for m, wdt in (
        ("symplectic_euler", 1.9),
        ("symplectic_euler", 1.99),
        ("symplectic_euler", 2.01),
        ("symplectic_euler", 2.1),
        ("rk4", 2.7),
        ("rk4", 2.9),
    ):
        dt = wdt / STIFF_OMEGA
        p = SA.Problem(
            "stiff_spring",
            STIFF,
            world,
            2.0,
            dt,
            dict(pos=(0.0, 0.0, STIFF_Z_EQ + STIFF_AMPLITUDE)),
        )
        r = SA.run(p, m, dt, samples=p.steps(dt))
        h = r["hist"]
        e = (0.5 * STIFF.mass_kg * h[:, 2] ** 2 + 0.5 * k * (h[:, 1] - STIFF_Z_EQ) ** 2) / e0
        # the true energy once out of the water: kinetic + potential with the spring one-sided
        above = h[:, 1] > 0.0
        e[above] = (
            0.5 * STIFF.mass_kg * h[above, 2] ** 2
            + STIFF.mass_kg * SA.G * h[above, 1]
            + 0.5 * k * STIFF_Z_EQ**2
        ) / e0
        ax.semilogy(h[:, 0], e, "-" if m == "rk4" else "-", lw=1, label=f"{m}, omega dt = {wdt}")
        rows.append(("stiff_spring", m, dt, "omega_dt", wdt))
        rows.append(("stiff_spring", m, dt, "energy_ratio_max", float(np.nanmax(e))))
        rows.append(("stiff_spring", m, dt, "energy_ratio_end", float(e[-1])))
        rows.append(("stiff_spring", m, dt, "finite", float(not r["diverged"])))
        rows.append(("stiff_spring", m, dt, "max_height_m", float(h[:, 1].max())))
        print(
            f"stiff_spring {m} omega dt {wdt}: E/E0 max {np.nanmax(e):.3g} end {e[-1]:.3g} "
            f"highest z {h[:, 1].max():.3g} m"
        )
    ax.axhline(leave, color="gray", lw=0.8)
    ax.text(0.02, leave * 1.3, "the body leaves the water", fontsize=8)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("energy / initial energy")
    ax.set_title(
        f"A stiff buoyancy spring: omega = {STIFF_OMEGA:.0f} rad/s,\nwaterline "
        f"{-1e3 * STIFF_Z_EQ:.2f} mm deep, released {1e3 * STIFF_AMPLITUDE:.1f} mm up"
    )
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.savefig(out / "study_stability_stiff_spring.png", dpi=100)
    plt.close(fig)


def airplane_curves(p, m, dt, world=None, stop=True):
    r = SA.run(p, m, dt, world=world, samples=min(p.steps(dt), 400), stop=stop)
    return r, r["hist"]


def mode_airplane_damping(probs, limit, rows, plt, out):
    p = probs["paper_airplane"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    for f in (None, 0.5, 0.9, 1.1, 1.5):
        dt = p.nominal_dt if f is None else f * limit
        r, h = airplane_curves(p, "symplectic_euler", dt)
        label = f"dt = {1e3 * dt:.2f} ms" + (" (env default)" if f is None else f" ({f} x limit)")
        axes[0].semilogy(h[:, 0], np.maximum(h[:, 4], 1e-6), lw=1, label=label)
        axes[1].plot(h[:, 0], h[:, 3], lw=1, label=label)
        rows.append(("airplane_damping", "symplectic_euler", dt, "max_spin_rad_s", h[:, 4].max()))
        rows.append(("airplane_damping", "symplectic_euler", dt, "max_speed_mps", h[:, 3].max()))
        rows.append(
            ("airplane_damping", "symplectic_euler", dt, "finite", float(not r["diverged"]))
        )
        print(
            f"airplane_damping dt {dt:.5f}: max |w| {h[:, 4].max():.3g} rad/s, "
            f"max |v| {h[:, 3].max():.3g} m/s"
        )
    axes[0].set_ylabel("|angular velocity| (rad/s)")
    axes[1].set_ylabel("speed (m/s)")
    for ax in axes:
        ax.set_xlabel("t (s)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle(
        "Paper airplane (5 g), symplectic Euler around its stability limit "
        f"({1e3 * limit:.2f} ms): launched level at 6 m/s, elevator +0.3"
    )
    fig.savefig(out / "study_stability_airplane_damping.png", dpi=100)
    plt.close(fig)


CLAMP_SECONDS = 6.0


def mode_clamps(probs, limit, rows, plt, out):
    p = dataclasses.replace(probs["paper_airplane"], seconds=CLAMP_SECONDS)
    worlds = {
        "clamps at defaults (156 m/s, 1e7 N)": World(),
        "clamps off (1e9 m/s, 1e18 N)": World(max_fluid_speed_mps=1e9, max_sample_force_n=1e18),
    }
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    for f in (1.5, 3.0):
        dt = f * limit
        for (label, world), style in zip(worlds.items(), ("-", "--"), strict=True):
            # on past the diverged flag (which ends an env's episode: marked x) to show
            # what the clamps alone would do
            r, h = airplane_curves(p, "symplectic_euler", dt, world, stop=False)
            name = f"{label}, dt = {1e3 * dt:.1f} ms"
            for ax, col in zip(axes, (3, 4), strict=True):
                (line,) = ax.semilogy(h[:, 0], np.maximum(h[:, col], 1e-6), style, lw=1, label=name)
                hit = np.flatnonzero(h[:, 0] >= r["flagged_s"])[:1]
                ax.plot(h[hit, 0], h[hit, col], "x", color=line.get_color(), ms=8)
            finite = bool(np.all(np.isfinite(h)))
            fin = h[np.all(np.isfinite(h), axis=1)]
            case = f"{label}; {f} x limit"
            rows.append(("clamps", case, dt, "max_speed_mps", float(fin[:, 3].max())))
            rows.append(("clamps", case, dt, "max_spin_rad_s", float(fin[:, 4].max())))
            rows.append(("clamps", case, dt, "finite", float(finite)))
            rows.append(("clamps", case, dt, "t_reached_s", float(h[-1, 0])))
            rows.append(("clamps", case, dt, "flagged_diverged_s", float(r["flagged_s"])))
            print(
                f"clamps {case}: max |v| {fin[:, 3].max():.3g}, max |w| {fin[:, 4].max():.3g}, "
                f"finite {finite}, t {h[-1, 0]:.2f}, flagged diverged at {r['flagged_s']:.3g} s"
            )
    axes[0].set_ylabel("speed (m/s)")
    axes[1].set_ylabel("|angular velocity| (rad/s)")
    for ax in axes:
        ax.set_xlabel("t (s)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle(
        f"Paper airplane beyond symplectic Euler's limit ({1e3 * limit:.1f} ms), "
        f"{CLAMP_SECONDS:g} s: what the clamps buy (x: Simulator.diverged, the env's episode ends)"
    )
    fig.savefig(out / "study_stability_clamps.png", dpi=100)
    plt.close(fig)


# ---- main ------------------------------------------------------------------------------------


def main() -> None:
    parser = arguments(__doc__, "fewer halvings and points")
    args = parser.parse_args()
    out = out_dir(args.out, args.quick)
    halvings = 4 if args.quick else 10
    t_start = time.perf_counter()
    machine = describe()
    probs = {p.name: p for p in SA.problems()}
    for name in CRAFTS:
        SA.craft_reference(probs[name])

    table = []
    limits = {}
    checks = 100 if args.quick else 20000
    for p in probs.values():
        ref = reference_sizes(p)
        for m in SA.METHODS:
            for dname, dtype in SA.DTYPES.items():
                good, bad, runs = largest_bounded_dt(p, m, ref, halvings, dtype, checks)
                limits[p.name, m, dname] = good
                table.append(
                    (
                        p.name,
                        m,
                        dname,
                        fmt(p.nominal_dt),
                        fmt(good),
                        fmt(bad),
                        fmt(good / p.nominal_dt),
                        runs,
                    )
                )
                print(
                    f"{p.name:15s} {m:17s} {dname} largest bounded dt {good:.4g} s "
                    f"(unbounded at {bad:.4g}; {good / p.nominal_dt:.3g} x nominal)"
                )
    notes = [
        f"bounded: finite and size < {FACTOR:g} x start over the run (torque_free: energy within"
        f" {TORQUE_FREE_BAND:.0%} of its start; see the module docstring), checked at up to"
        f" {checks} points per run;"
        f" bisection on log dt, {halvings} halvings, 1 env",
        "dt_unbounded_s inf: bounded at the search's upper end (a tenth of the interval); "
        "dt_bounded_s nan: unbounded already at nominal dt / 64",
    ]
    header = (
        "problem",
        "integrator",
        "dtype",
        "nominal_dt_s",
        "dt_bounded_s",
        "dt_unbounded_s",
        "bounded_over_nominal",
        "runs",
    )
    write_csv(out / "study_stability.csv", header, table, [*machine, *notes])

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows: list[tuple] = []
    mode_euler_spring(probs, rows, plt, out)
    mode_tetra_spin(rows, plt, out, args.quick)
    mode_stiff_spring(rows, plt, out)
    limit = limits["paper_airplane", "symplectic_euler", "float64"]
    mode_airplane_damping(probs, limit, rows, plt, out)
    mode_clamps(probs, limit, rows, plt, out)
    mode_seed_methods(rows, plt, out)
    write_csv(
        out / "study_stability_modes.csv",
        ("chart", "case", "dt_s", "quantity", "value"),
        [(c, m, fmt(float(dt)), q, fmt(float(v))) for c, m, dt, q, v in rows],
        machine,
    )
    print(f"wrote {out}/study_stability*.csv and 6 charts in {time.perf_counter() - t_start:.0f} s")


# ---- the docs -------------------------------------------------------------------------------

# docs/study.md's stability table: its rows (problems) and columns (the first six integrators)
TABLE_PROBLEMS = ("projectile", "spring", "kepler", "torque_free", *CRAFTS)
TABLE_INTEGRATORS = (
    "explicit_euler", "symplectic_euler", "velocity_verlet", "rk2", "rk4", "verlet_tetra",
)  # fmt: skip
# docs/study.md's Reading table: each env's craft in the studies
ENV_CRAFTS = {
    "PaperAirplane-v0": "paper_airplane",
    "BoatOnStep-v0": "speedboat",
    "SubmarineWake-v0": "uuv",
}


def markdown(path=None) -> str:
    """docs/study.md's table of the largest bounded dt, from docs/study_stability.csv (float64;
    says whether float32's limits are the same to the digits shown)."""
    from benchmarks.common import DOCS, read_csv

    path = DOCS / "study_stability.csv" if path is None else path
    if not path.is_file():
        return "(no docs/study_stability.csv yet: run python -m benchmarks.study_stability)"
    by = {(r["problem"], r["integrator"], r["dtype"]): r for r in read_csv(path)[1]}

    def cell(r: dict) -> str:
        at_ceiling = "≥ " if float(r["dt_unbounded_s"]) == math.inf else ""
        return (
            f"{at_ceiling}{float(r['dt_bounded_s']):.3g} s "
            f"({float(r['bounded_over_nominal']):.3g}×)"
        )

    lines = [
        "| problem (nominal dt) | " + " | ".join(TABLE_INTEGRATORS) + " |",
        "|---|" + "---:|" * len(TABLE_INTEGRATORS),
    ]
    same = True
    for p in TABLE_PROBLEMS:
        cells = [cell(by[p, m, "float64"]) for m in TABLE_INTEGRATORS]
        same &= cells == [cell(by[p, m, "float32"]) for m in TABLE_INTEGRATORS]
        nominal = float(by[p, TABLE_INTEGRATORS[0], "float64"]["nominal_dt_s"])
        lines.append(f"| {p} ({nominal:.4g} s) | " + " | ".join(cells) + " |")
    lines += [
        "",
        "float32 gives the same limits to the digits shown."
        if same
        else "float32's limits differ (docs/study_stability.csv's float32 rows).",
    ]
    return "\n".join(lines)


def defaults_markdown() -> str:
    """docs/study.md's Reading table: each env's default integrator and dt, its stability
    margin on the craft's maneuver (docs/study_stability.csv) and its position error over it
    (docs/study_accuracy.csv), beside the first default's (symplectic Euler at the craft's
    nominal dt)."""
    from benchmarks.common import DOCS, read_csv
    from fluidsim_envs.scenes import SCENES

    stab, acc = DOCS / "study_stability.csv", DOCS / "study_accuracy.csv"
    if not stab.is_file() or not acc.is_file():
        return "(no docs/study_stability.csv or study_accuracy.csv yet: run the studies)"
    limits = {
        (r["problem"], r["integrator"]): r for r in read_csv(stab)[1] if r["dtype"] == "float64"
    }
    sweep = [r for r in read_csv(acc)[1] if r["dtype"] == "float64"]

    def error(craft: str, integrator: str, dt: float) -> str:
        """The error at ``dt``, or at the sweep's nearest dt below it, named."""
        runs = [(float(r["dt_s"]), float(r["pos_err_m"])) for r in sweep
                if (r["problem"], r["integrator"]) == (craft, integrator)]  # fmt: skip
        below = [(d, e) for d, e in runs if d <= dt * (1 + 1e-5)]
        if not below:
            return "not in the sweep"
        d, e = max(below)
        text = f"{e:.2e}".replace("e-0", "e-")
        if math.isclose(d, dt, rel_tol=1e-5):
            return f"{text} m"
        return f"{text} m at 1/{1 / d:.0f} s (1/{1 / dt:.0f} s is not in the sweep)"

    probs = {p.name: p for p in SA.problems()}
    lines = [
        "| env | default (first default) | stability margin (this maneuver) | error of the "
        "default over the maneuver (first default) |",
        "|---|---|---|---|",
    ]
    for env_id, scene in SCENES.items():
        name = env_id.split("/")[1]
        craft = ENV_CRAFTS.get(name)
        if craft is None:
            continue
        p, first = scene.params_cls(), probs[craft]
        lim = limits[craft, p.integrator]
        bounded = float(lim["dt_bounded_s"])
        ceiling = "≥ " if float(lim["dt_unbounded_s"]) == math.inf else ""
        margin = f"{ceiling or 'limit '}{1e3 * bounded:.3g} ms, {ceiling}{bounded / p.dt:.3g}×"
        n_first = round(p.dt * p.substeps / first.nominal_dt)
        label = f"{name} ({craft})" if craft == "uuv" else name
        lines.append(
            f"| {label} | {p.integrator}, 1/{1 / p.dt:.0f} s, {p.substeps} substeps "
            f"(symplectic Euler, 1/{1 / first.nominal_dt:.0f} s, {n_first}) | {margin} | "
            f"{error(craft, p.integrator, p.dt)} after {first.seconds:g} s "
            f"({error(craft, 'symplectic_euler', first.nominal_dt)}) |"
        )
    return "\n".join(lines)


if __name__ == "__main__":
    main()
