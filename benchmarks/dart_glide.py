"""The paper dart's trimmed glide and phugoid with zero controls, beside the phugoid's
approximations: what docs/environments.md publishes and tests/craft/test_paper_airplane.py pins.

    python -m benchmarks.dart_glide     # writes docs/dart_glide.csv (seconds); then
    python -m benchmarks.report         # writes the text and table in docs/environments.md

Everything runs as the tests fly the dart: ``Simulator(Craft.load("paper_airplane"), World())``,
its default integrator (symplectic Euler) at the env's physics step of 1/240 s, float64.

- **Trim**: launched level at 6 m/s, 1000 m up, flown 30 s (the pitch oscillation has died
  out: speed and glide angle are constant). Trim speed V; lift L and drag D are the aero
  force (``Simulator.wrench``) across and along the flight path; glide ratio L/D; glide angle
  gamma = atan(D/L) below the horizon.
- **Phugoid, measured**: launched level 1 m/s below trim speed, flown 12 s, sampled every
  1/24 s. Each peak of the speed is located by the parabola through the sample at the peak
  and its two neighbours (:func:`speed_peaks`); the period is their mean spacing, the damping
  ratio comes from the decay of the peaks' excess over trim speed (logarithmic decrement).
- **Phugoid, linearized**: the craft's own longitudinal small-perturbation equations at trim
  (Etkin & Reid, Dynamics of Flight: Stability and Control, 3rd ed., ch. 4), states forward
  and vertical speed, pitch angle and pitch rate, with every derivative taken from the
  craft's forces by central differences of ``Simulator.wrench`` (:func:`linearized_phugoid`):
  the slower complex pair of the 4x4 system. No closed form: it says how much of the
  approximations' error is theirs and how much the measurement's (measured: period 0.03%
  and damping ratio 1.5% off it; the 1.5% is symplectic Euler's, rk4 at the same dt is
  0.02% off).
- **Approximations** (the phugoid as a point mass at constant angle of attack, so constant
  C_L and C_D): Lanchester's drag-free period (:func:`lanchester`); Etkin & Reid's phugoid
  approximation with drag, for level flight with a thrust that does not change with speed
  (:func:`etkin_reid`); and the same equations for a glide (:func:`glide_with_drag`).

Writes ``docs/dart_glide.csv``: one number a row (quantity, source, value, unit).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from .common import DOCS, read_csv, write_csv

CSV = DOCS / "dart_glide.csv"
DT = 1 / 240  # the env's physics step
SAMPLE_STEPS = 10  # one sample every 1/24 s
COLUMNS = ("quantity", "source", "value", "unit")
# the sources of docs/dart_glide.csv's phugoid rows, in the order the docs list them
SOURCES = ("measured", "linearized", "glide_with_drag", "etkin_reid", "lanchester")


def glide(craft, world, seconds: float, v0: float):
    """Zero controls from a level launch at ``v0`` (m/s), 1000 m up: the simulator at the end
    and, every 1/24 s, the time (s) and the speed (m/s)."""
    from fluidsim_envs.physics import Simulator

    sim = Simulator(craft, world, num_envs=1, dt=DT)
    sim.reset(pos=(0.0, 0.0, 1000.0), lin_vel=(v0, 0.0, 0.0))
    n = int(round(seconds / (DT * SAMPLE_STEPS)))
    t, speed = np.empty(n), np.empty(n)
    for k in range(n):
        sim.step(steps=SAMPLE_STEPS)
        t[k] = (k + 1) * DT * SAMPLE_STEPS
        speed[k] = np.linalg.norm(sim.lin_vel[0, 0])
    return sim, t, speed


def lift_and_drag(sim) -> tuple[float, float]:
    """The aero force on environment 0, body 0, across (lift) and against (drag) its velocity
    (N)."""
    force = sim.wrench()[0][0, 0]
    v = sim.lin_vel[0, 0] / np.linalg.norm(sim.lin_vel[0, 0])
    along = force @ v
    return float(np.linalg.norm(force - along * v)), float(-along)


def speed_peaks(t: np.ndarray, speed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The times and values of the local maxima of a uniformly sampled speed, each refined by
    the parabola through the sample at the maximum and its two neighbours."""
    k = np.flatnonzero((speed[1:-1] > speed[:-2]) & (speed[1:-1] >= speed[2:])) + 1
    before, at, after = speed[k - 1], speed[k], speed[k + 1]
    shift = 0.5 * (before - after) / (before - 2.0 * at + after)  # in samples, |shift| <= 1/2
    return t[k] + shift * (t[1] - t[0]), at - 0.25 * (before - after) * shift


def phugoid_of(t: np.ndarray, speed: np.ndarray, v_trim: float) -> tuple[float, float, int]:
    """Period (s) and damping ratio of the speed's oscillation about ``v_trim``, from its
    peaks (:func:`speed_peaks`), and how many peaks there were."""
    times, values = speed_peaks(t, speed)
    if len(times) < 3:
        raise ValueError(f"{len(times)} speed peaks: too few to measure a phugoid")
    period = float(np.mean(np.diff(times)))
    decrement = math.log((values[0] - v_trim) / (values[-1] - v_trim)) / (len(times) - 1)
    return period, decrement / math.hypot(2.0 * math.pi, decrement), len(times)


def damped(omega_n: float, zeta: float) -> float:
    """The period (s) of a damped oscillation of natural frequency ``omega_n`` (rad/s)."""
    return 2.0 * math.pi / (omega_n * math.sqrt(1.0 - zeta * zeta))


def lanchester(v: float, g: float) -> tuple[float, float]:
    """Lanchester's phugoid (Aerodonetics, 1908; Etkin & Reid, 3rd ed., ch. 6): no drag,
    omega_n = sqrt(2) g / V, undamped: period pi sqrt(2) V / g. (period s, damping ratio)"""
    return damped(math.sqrt(2.0) * g / v, 0.0), 0.0


def etkin_reid(v: float, g: float, drag_over_lift: float) -> tuple[float, float]:
    """Etkin & Reid's phugoid approximation with drag (Dynamics of Flight: Stability and
    Control, 3rd ed., ch. 6): omega_n = sqrt(2) g / V, zeta = C_D / (sqrt(2) C_L), for level
    flight with a thrust that does not change with speed. (period s, damping ratio)"""
    zeta = drag_over_lift / math.sqrt(2.0)
    return damped(math.sqrt(2.0) * g / v, zeta), zeta


def glide_with_drag(v: float, g: float, drag_over_lift: float) -> tuple[float, float]:
    """The same point-mass phugoid (constant angle of attack, C_L and C_D constant) for a
    glide: Etkin & Reid's longitudinal small-perturbation equations (3rd ed., ch. 4) with the
    reference flight path tilted down by the glide angle gamma = atan(C_D / C_L) (theta_0 = -gamma,
    their g sin(theta_0) terms kept), no thrust, and the phugoid approximation's constant
    angle of attack (so pitch theta moves with the flight path). Speed u and theta obey

        du/dt = -(2 g sin(gamma) / V) u - g cos(gamma) theta
        dtheta/dt = (2 g cos(gamma) / V^2) u - (g sin(gamma) / V) theta

    so omega_n = sqrt(2) g / V and zeta = 3 sin(gamma) / (2 sqrt(2)): 1.5 times Etkin & Reid's
    level-flight value for small gamma (the gravity term of the lift equation damps too). The
    same linearization as the phugoid model of glider flight with drag analysed by Sutherland
    ('The Art of Phugoid', Stony Brook MAT 331 notes), whose trim is a spiral sink for
    C_D / C_L < 2 sqrt(2): exactly where this zeta < 1. (period s, damping ratio)"""
    zeta = 3.0 * math.sin(math.atan(drag_over_lift)) / (2.0 * math.sqrt(2.0))
    return damped(math.sqrt(2.0) * g / v, zeta), zeta


def linearized_phugoid(craft, world, sim) -> tuple[float, float]:
    """Period (s) and damping ratio of the phugoid pair of the craft's longitudinal equations
    linearized about the trimmed state of ``sim`` (environment 0: wings level, flying along
    +x). States: world velocity x and z, pitch angle and pitch rate; their rates from the
    craft's own wrench (:meth:`Simulator.wrench`) and gravity, by central differences."""
    from fluidsim_envs.physics import Simulator

    quat, vel = sim.quat[0, 0], sim.lin_vel[0, 0]
    if max(abs(quat[1]), abs(quat[3]), abs(vel[1])) > 1e-9:
        raise ValueError("the trim is not wings level along +x: no longitudinal plane")
    x0 = np.array([vel[0], vel[2], 2.0 * math.atan2(quat[2], quat[0]), 0.0])
    steps = np.array([1e-4, 1e-4, 1e-5, 1e-4])  # m/s, m/s, rad, rad/s
    states = np.repeat(x0[None], 8, axis=0)
    for i in range(4):
        states[2 * i, i] += steps[i]
        states[2 * i + 1, i] -= steps[i]
    vx, vz, pitch, rate = states.T
    half, zero = 0.5 * pitch, 0.0 * pitch
    probe = Simulator(craft, world, num_envs=len(states), dt=DT)
    probe.reset(
        pos=(0.0, 0.0, 1000.0),
        quat=np.stack([np.cos(half), zero, np.sin(half), zero], 1)[:, None],
        lin_vel=np.stack([vx, zero, vz], 1)[:, None],
        ang_vel=np.stack([zero, rate, zero], 1)[:, None],
    )
    force, torque = probe.wrench()
    rates = np.stack(
        [
            force[:, 0, 0] / craft.mass_kg,
            force[:, 0, 2] / craft.mass_kg - world.gravity_mps2,
            rate,
            torque[:, 0, 1] / np.asarray(craft.inertia_tensor)[1, 1],
        ],
        axis=1,
    )
    jacobian = ((rates[0::2] - rates[1::2]) / (2.0 * steps[:, None])).T  # [rate, state]
    roots = np.linalg.eigvals(jacobian)
    slow = min((r for r in roots if r.imag > 0), key=abs)  # the phugoid: the slower pair
    return 2.0 * math.pi / slow.imag, -slow.real / abs(slow)


def measure() -> list[tuple[str, str, float, str]]:
    """Every row of docs/dart_glide.csv."""
    from fluidsim_envs.physics import Craft, World

    craft, world = Craft.load("paper_airplane"), World()
    g = world.gravity_mps2
    sim, _, _ = glide(craft, world, 30.0, v0=6.0)
    v_trim = float(np.linalg.norm(sim.lin_vel[0, 0]))
    lift, drag = lift_and_drag(sim)
    d_l = drag / lift
    _, t, speed = glide(craft, world, 12.0, v0=v_trim - 1.0)
    period, zeta, _ = phugoid_of(t, speed, v_trim)
    phugoid = {
        "measured": (period, zeta),
        "linearized": linearized_phugoid(craft, world, sim),
        "glide_with_drag": glide_with_drag(v_trim, g, d_l),
        "etkin_reid": etkin_reid(v_trim, g, d_l),
        "lanchester": lanchester(v_trim, g),
    }
    rows = [
        ("trim_speed", "measured", v_trim, "m/s"),
        ("glide_ratio", "measured", lift / drag, "1"),
        ("glide_angle", "measured", math.degrees(math.atan(d_l)), "deg"),
    ]
    for source in SOURCES:
        rows.append(("phugoid_period", source, phugoid[source][0], "s"))
        rows.append(("phugoid_damping", source, phugoid[source][1], "1"))
    return rows


def published(path: str | Path = CSV) -> dict[tuple[str, str], float]:
    """docs/dart_glide.csv's values by (quantity, source)."""
    return {(r["quantity"], r["source"]): float(r["value"]) for r in read_csv(path)[1]}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m benchmarks.dart_glide",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--out", type=Path, default=CSV, help="CSV file (default: %(default)s)")
    args = parser.parse_args(argv)
    rows = measure()
    for quantity, source, value, unit in rows:
        print(f"{quantity:16} {source:16} {value:10.4f} {unit}")
    write_csv(
        args.out,
        COLUMNS,
        ((q, s, f"{v:.6g}", u) for q, s, v, u in rows),
        [f"Simulator(Craft.load('paper_airplane'), World()), symplectic Euler, dt = {DT:.6g} s"],
    )
    print(f"written: {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
