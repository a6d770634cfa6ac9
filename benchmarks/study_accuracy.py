"""Accuracy against cost: work-precision diagrams of the shipped integrators.

Every problem runs through the real :class:`Simulator`, so what is measured is the shipped
kernels. For each problem, integrator (every row of ``integrators.TABLE``), dtype (float64,
float32) and time
step dt of a sweep, one environment is run over the problem's interval and its error measured:

- ``projectile``: free fall from the origin at v0 = (3, 0, 4) m/s; error: position error at
  t = 2 s against x0 + v0 t - g t^2 / 2 (m).
- ``spring``: a 1 kg body carrying one 0.01 m^2 area buoyancy sample in water (no drag),
  released 2 cm above its waterline depth: a harmonic oscillator with omega^2 = rho g A / m
  (10.03 rad/s; ``tests/physics/test_integrators.py``); errors after 50 periods: the phase
  error (rad) and the largest relative energy error over the run (sampled 200 times).
- ``torque_free``: a free rigid body, inertia (1, 2, 3) kg m^2, spun at (1.0, 1.5, 1.2) rad/s
  (body frame; near the major axis, modulus m = k^2 = 0.49): errors at t = 10 s of the body-frame
  angular velocity (relative) and of the kinetic energy (relative), against the exact
  solution by Jacobi elliptic functions (:func:`torque_free_exact`; Landau & Lifshitz,
  Mechanics, section 37), itself checked here against scipy's ``solve_ivp`` to 1e-8.
- ``paper_airplane``: the shipped dart in ``World()`` launched level at 6 m/s, 10 m up, with
  the elevator held at +0.3, for 2 s; ``speedboat``: full throttle from rest at its floating
  height and trim (``hydrostatics.static_float``) for 5 s in ``World(water=True)``; ``uuv``:
  thrust 0.7 (84 N ahead), rudder 0.3, dive planes -0.2 from rest 10 m down for 5 s. Errors:
  final position (m) and attitude angle (rad) against rk4 at 1/64 of the env's default dt in
  float64; that reference is checked against rk4 at 1/128 (the difference goes in the CSV).

Cost: wall time per body-step of ``sim.step(controls, steps=100)`` at E = 1024 environments of
the same problem, at the problem's nominal dt, on one thread (the serial kernel: the machine
these runs share has 2 cores, and one thread is the least disturbed by other work; the
parallel kernel divides it by up to the thread count), minimum over 15 repeats, per (problem,
integrator, dtype); plus force evaluations per step (``kernels.EVALS_PER_STEP``; the
implicit midpoint's is per iteration). A run's cost is its number of steps times the cost per
body-step: the x axis of the diagrams (microseconds of compute per body to cover the
problem's interval).

- ``kepler``: a point mass about GM = 1 (``World(central_gravity_m3s2=1)``) on the orbit of
  eccentricity 0.6 of Hairer, Lubich and Wanner (GNI, chapter I), 10 orbits: position against
  Kepler's equation, energy and angular momentum (``benchmarks/study_hairer.py`` follows
  their growth over 512 orbits).

Writes ``docs/study_accuracy.csv`` (errors), ``docs/study_cost.csv`` (cost per body-step) and
``docs/study_accuracy.png`` (the first six methods) and ``docs/study_accuracy_seed.png`` (the
seed's remaining methods beside symplectic Euler and rk2) (machine description in ``#`` lines
at the top of each CSV)::

    python -m benchmarks.study_accuracy            # full size, under a minute on 2 cores
    python -m benchmarks.study_accuracy --quick    # fewer dts and repeats, into build/study_quick
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.special import ellipj, ellipkinc

from benchmarks.common import arguments, best_of, describe, fmt, out_dir, write_csv
from fluidsim_envs.physics import INTEGRATORS, Buoyancy, Craft, Simulator, World
from fluidsim_envs.physics import integrators as IT
from fluidsim_envs.physics.hydrostatics import static_float
from fluidsim_envs.physics.kernels import EVALS_PER_STEP, quat_matrices

G = 9.81
METHODS = tuple(INTEGRATORS)  # explicit_euler, symplectic_euler, velocity_verlet, rk2, rk4, ...
DTYPES = {"float64": np.float64, "float32": np.float32}

# ---- the torque-free rigid body: exact solution ---------------------------------------------


def torque_free_exact(inertia, w0, t) -> np.ndarray:
    """Body-frame angular velocity [len(t), 3] (rad/s) of a torque-free rigid body.

    Euler's equations ``I1 dw1/dt = (I2 - I3) w2 w3`` (and cyclic) solved by Jacobi elliptic
    functions (Landau & Lifshitz, Mechanics, section 37): with energy E and angular momentum M
    and ``I1 < I2 < I3``, for ``M^2 > 2 E I2`` (a spin about the major axis, wobbling)

        w1 = A1 cn(tau), w2 = A2 sn(tau), w3 = s A3 dn(tau),  tau = lam t + tau0,

    ``A1^2 = (2 E I3 - M^2) / (I1 (I3 - I1))``, ``A2^2 = (2 E I3 - M^2) / (I2 (I3 - I2))``,
    ``A3^2 = (M^2 - 2 E I1) / (I3 (I3 - I1))``, modulus
    ``m = k^2 = (I2 - I1)(2 E I3 - M^2) / ((I3 - I2)(M^2 - 2 E I1))``; for ``M^2 < 2 E I2``
    (about the minor axis) the roles of axes 1 and 3 swap. The phase tau0 comes from the
    initial (w1, w2) through the incomplete elliptic integral, the rate lam (with its sign)
    from Euler's equations at t = 0.

    Args:
        inertia: principal moments (I1, I2, I3), distinct, any order (kg m^2).
        w0: body-frame angular velocity at t = 0 (rad/s); not an equilibrium (not along an
            axis) and not on the separatrix ``M^2 = 2 E I2``.
        t: times (s), array-like.
    """
    inertia = np.asarray(inertia, dtype=np.float64)
    w0 = np.asarray(w0, dtype=np.float64)
    t = np.atleast_1d(np.asarray(t, dtype=np.float64))
    order = np.argsort(inertia)
    i1, i2, i3 = inertia[order]
    if not (i1 < i2 < i3):
        raise ValueError(f"torque_free_exact: principal moments must differ, got {inertia}")
    w = w0[order]
    e2 = float(np.sum(inertia * w0**2))  # 2 E
    m2 = float(np.sum((inertia * w0) ** 2))  # M^2
    # the axis ordered by size is an even or odd permutation of the body axes: an odd one
    # reverses the sign of Euler's equations (time runs backwards in the sorted frame)
    parity = 1.0 if np.linalg.det(np.eye(3)[order]) > 0 else -1.0
    if m2 > e2 * i2:  # about the major axis: (cn, sn, dn) on axes (1, 2, 3)
        a, b, c = 0, 1, 2
        ia, ib, ic = i1, i2, i3
        amp = (
            math.sqrt((e2 * i3 - m2) / (i1 * (i3 - i1))),
            math.sqrt((e2 * i3 - m2) / (i2 * (i3 - i2))),
            math.sqrt((m2 - e2 * i1) / (i3 * (i3 - i1))),
        )
        m = (i2 - i1) * (e2 * i3 - m2) / ((i3 - i2) * (m2 - e2 * i1))
    elif m2 < e2 * i2:  # about the minor axis: (cn, sn, dn) on axes (3, 2, 1)
        a, b, c = 2, 1, 0
        ia, ib, ic = i3, i2, i1
        amp = (
            math.sqrt((m2 - e2 * i1) / (i3 * (i3 - i1))),
            math.sqrt((m2 - e2 * i1) / (i2 * (i2 - i1))),
            math.sqrt((e2 * i3 - m2) / (i1 * (i3 - i1))),
        )
        m = (i3 - i2) * (m2 - e2 * i1) / ((i2 - i1) * (e2 * i3 - m2))
    else:
        raise ValueError("torque_free_exact: w0 lies on the separatrix M^2 = 2 E I2")
    if amp[0] == 0.0 or amp[1] == 0.0:
        raise ValueError("torque_free_exact: w0 is a steady spin about a principal axis")
    sign_c = 1.0 if w[c] >= 0 else -1.0
    phi0 = math.atan2(w[b] / amp[1], w[a] / amp[0])  # the amplitude am(tau0)
    tau0 = float(ellipkinc(phi0, m))
    # d w_a / dt = (I_b - I_c) / I_a w_b w_c (times parity) = -A_a sn dn lam
    lam = -parity * (ib - ic) / ia * amp[1] * sign_c * amp[2] / amp[0]
    if (a, c) == (2, 0):  # Euler's equation for axis 3 reads (I1 - I2) / I3 w1 w2
        lam = -lam
    sn, cn, dn, _ = ellipj(lam * t + tau0, m)
    out = np.empty((t.size, 3))
    out[:, a] = amp[0] * cn
    out[:, b] = amp[1] * sn
    out[:, c] = sign_c * amp[2] * dn
    res = np.empty_like(out)
    res[:, order] = out
    return res


def euler_solve_ivp(inertia, w0, t) -> np.ndarray:
    """Euler's equations (body frame) by scipy's DOP853 at rtol = atol = 1e-13: [len(t), 3]."""
    i1, i2, i3 = np.asarray(inertia, dtype=np.float64)

    def rhs(_, w):
        return [
            (i2 - i3) / i1 * w[1] * w[2],
            (i3 - i1) / i2 * w[2] * w[0],
            (i1 - i2) / i3 * w[0] * w[1],
        ]

    t = np.atleast_1d(np.asarray(t, dtype=np.float64))
    sol = solve_ivp(rhs, (0.0, t[-1]), w0, method="DOP853", rtol=1e-13, atol=1e-13, t_eval=t)
    return sol.y.T


# ---- problems --------------------------------------------------------------------------------


def attitude_error(q, q_ref) -> float:
    """Angle (rad) of the rotation between two unit quaternions: the chord between them (on
    the same hemisphere) is 2 sin(angle / 4); accurate to rounding at small angles, where
    2 acos(q . q_ref) is not (its floor is ~1e-8)."""
    q = np.asarray(q, dtype=np.float64) / np.linalg.norm(q)
    q_ref = np.asarray(q_ref, dtype=np.float64) / np.linalg.norm(q_ref)
    chord = np.linalg.norm(q - math.copysign(1.0, float(np.dot(q, q_ref))) * q_ref)
    return 4.0 * math.asin(min(1.0, chord / 2.0))


@dataclass
class Problem:
    """One study problem: how to build its simulator, start it, drive it and score it."""

    name: str
    craft: Craft
    world: World
    seconds: float
    nominal_dt: float  # the env's default dt, or a typical one for the synthetic problems
    start: dict  # Simulator.reset keyword arguments
    controls: tuple = ()
    dts: tuple = ()  # the sweep for the work-precision diagram
    metrics: tuple = ("pos_err_m",)
    reference: dict = field(default_factory=dict)  # filled for the crafts

    def make(self, integrator: str, dt: float, dtype=np.float64, num_envs: int = 1, world=None):
        sim = Simulator(
            self.craft,
            self.world if world is None else world,
            num_envs=num_envs,
            dt=dt,
            integrator=integrator,
            dtype=dtype,
        )
        sim.reset(**self.start)
        return sim

    def control_array(self, num_envs: int):
        if not self.controls:
            return None
        return np.tile(np.asarray(self.controls, dtype=np.float64), (num_envs, 1))

    def steps(self, dt: float) -> int:
        return max(1, round(self.seconds / dt))


FLOAT_AREA, RHO = 0.01, 1025.0
FLOAT = Craft(
    name="float",
    mass_kg=1.0,
    inertia_kgm2=(1.0, 1.0, 1.0),
    buoyancy=(Buoyancy("hull", (0.0, 0.0, 0.0), "area", area_m2=FLOAT_AREA),),
)
K_SPRING = RHO * G * FLOAT_AREA
OMEGA = math.sqrt(K_SPRING / FLOAT.mass_kg)
Z_EQ = -FLOAT.mass_kg / (RHO * FLOAT_AREA)
AMPLITUDE = 0.02
SPRING_SECONDS = 50 * 2 * math.pi / OMEGA

TF_INERTIA = (1.0, 2.0, 3.0)
TF_W0 = (1.0, 1.5, 1.2)
V0 = (3.0, 0.0, 4.0)


KEPLER_E = 0.6  # eccentricity; GM = 1, semi-major axis 1, period 2 pi (GNI, chapter I)
KEPLER_ORBITS = 10


def kepler_exact(t: float) -> np.ndarray:
    """Position at time t on the orbit that starts at the pericentre (1 - e, 0): Kepler's
    equation E - e sin E = t (mean motion 1) solved by Newton's method."""
    e = KEPLER_E
    m = math.fmod(t, 2 * math.pi)
    ecc = m if e < 0.8 else math.pi
    for _ in range(50):
        ecc -= (ecc - e * math.sin(ecc) - m) / (1 - e * math.cos(ecc))
    return np.array([math.cos(ecc) - e, math.sqrt(1 - e * e) * math.sin(ecc), 0.0])


def spring_energy(z, v) -> np.ndarray:
    """Energy (J) of the buoyancy spring about its equilibrium (linear spring)."""
    return 0.5 * FLOAT.mass_kg * np.asarray(v) ** 2 + 0.5 * K_SPRING * (np.asarray(z) - Z_EQ) ** 2


def pow2(lo: int, hi: int) -> tuple:
    return tuple(2.0**-k for k in range(lo, hi + 1))


def problems(quick: bool = False) -> list[Problem]:
    """The study's problems (``quick``: fewer time steps in each sweep)."""
    boat = Craft.load("speedboat")
    height, trim = static_float(boat)
    out = [
        Problem(
            "projectile",
            Craft(name="ball", mass_kg=1.0, inertia_kgm2=(0.4, 0.4, 0.4)),
            World(gravity_mps2=G),
            2.0,
            1 / 100,
            dict(lin_vel=V0),
            dts=pow2(2, 11),
        ),
        Problem(
            "spring",
            FLOAT,
            World(water=True, water_density_kgm3=RHO),
            SPRING_SECONDS,
            1 / 100,
            dict(pos=(0.0, 0.0, Z_EQ + AMPLITUDE)),
            dts=pow2(3, 12),
            metrics=("phase_err_rad", "energy_err"),
        ),
        Problem(
            "torque_free",
            Craft(name="box", mass_kg=1.0, inertia_kgm2=TF_INERTIA),
            World(gravity_mps2=0.0),
            10.0,
            1 / 100,
            dict(ang_vel=TF_W0),
            dts=pow2(3, 12),
            metrics=("omega_err", "energy_err"),
        ),
        Problem(
            "paper_airplane",
            Craft.load("paper_airplane"),
            World(),
            2.0,
            1 / 240,
            dict(pos=(0.0, 0.0, 10.0), lin_vel=(6.0, 0.0, 0.0)),
            controls=(0.0, 0.3, 0.0),
            dts=tuple(2.0**k / 240 for k in range(-4, 4)),
            metrics=("pos_err_m", "att_err_rad"),
        ),
        Problem(
            "speedboat",
            boat,
            World(water=True),
            5.0,
            1 / 200,
            dict(
                pos=(0.0, 0.0, height),
                quat=(math.cos(trim / 2), 0.0, -math.sin(trim / 2), 0.0),
            ),
            controls=(1.0, 0.0, 0.0),
            dts=tuple(2.0**k / 200 for k in range(-4, 4)),
            metrics=("pos_err_m", "att_err_rad"),
        ),
        Problem(
            "uuv",
            Craft.load("uuv"),
            World(water=True),
            5.0,
            1 / 50,
            dict(pos=(0.0, 0.0, -10.0)),
            controls=(0.7, 0.3, -0.2),  # 84 N: what 0.6 gave before control 0 was no thrust
            dts=tuple(2.0**k / 50 for k in range(-5, 3)),
            metrics=("pos_err_m", "att_err_rad"),
        ),
    ]
    e = KEPLER_E
    out.insert(
        3,
        Problem(
            "kepler",
            Craft(name="planet", mass_kg=1.0, inertia_kgm2=(1.0, 1.0, 1.0)),
            World(gravity_mps2=0.0, central_gravity_m3s2=1.0),
            KEPLER_ORBITS * 2 * math.pi,
            1 / 100,
            dict(pos=(1 - e, 0.0, 0.0), lin_vel=(0.0, math.sqrt((1 + e) / (1 - e)), 0.0)),
            dts=pow2(4, 13),
            metrics=("pos_err_m", "energy_err", "angmom_err"),
        ),
    )
    if quick:
        for p in out:
            p.dts = p.dts[::3]
    return out


def body_omega(sim) -> np.ndarray:
    rot = quat_matrices(np.ascontiguousarray(sim.quat[0]))[0]
    return rot.T @ sim.ang_vel[0, 0]


def run(
    p: Problem,
    integrator: str,
    dt: float,
    dtype=np.float64,
    world=None,
    samples: int = 0,
    stop: bool = True,
):
    """Run one environment over the problem's interval: final (pos, quat, lin_vel, body omega,
    kinetic energy), the time reached, and, with ``samples``, the state's history
    ``[samples, 7]`` (t, z, v_z, |v|, |w|, kinetic energy, |x|) sampled at chunk ends, up to
    the first sample flagged diverged (``stop=False``: on to the end; ``flagged_s`` is the
    first flagged sample's time, NaN if none)."""
    sim = p.make(integrator, dt, dtype, 1, world)
    n = p.steps(dt)
    ctrl = p.control_array(1)
    hist = []
    flagged = math.nan
    if samples:
        chunks = np.diff(np.linspace(0, n, min(samples, n) + 1).round().astype(int))
        done = 0
        for k in chunks:
            sim.step(ctrl, steps=int(k))
            done += int(k)
            v, w = sim.lin_vel[0, 0].astype(np.float64), sim.ang_vel[0, 0].astype(np.float64)
            hist.append(
                (
                    done * dt,
                    float(sim.pos[0, 0, 2]),
                    float(v[2]),
                    float(np.linalg.norm(v)),
                    float(np.linalg.norm(w)),
                    float(sim.kinetic_energy()[0, 0]),
                    float(np.linalg.norm(sim.pos[0, 0].astype(np.float64))),
                )
            )
            if sim.diverged[0] and math.isnan(flagged):
                flagged = done * dt
            if sim.diverged[0] and stop:
                break
    else:
        sim.step(ctrl, steps=n)
    return {
        "pos": sim.pos[0, 0].astype(np.float64),
        "quat": sim.quat[0, 0].astype(np.float64),
        "vel": sim.lin_vel[0, 0].astype(np.float64),
        "omega_body": body_omega(sim).astype(np.float64),
        "ke": float(sim.kinetic_energy()[0, 0]),
        "t": n * dt,
        "diverged": bool(sim.diverged[0]),
        "flagged_s": flagged,
        "hist": np.array(hist),
    }


def errors(p: Problem, r: dict) -> dict:
    """The problem's error metrics for one run (NaN where the run diverged)."""
    t = r["t"]
    if p.name == "projectile":
        exact = np.asarray(V0) * t + np.array([0.0, 0.0, -0.5 * G * t * t])
        return {"pos_err_m": float(np.linalg.norm(r["pos"] - exact))}
    if p.name == "spring":
        h = r["hist"]
        e0 = 0.5 * K_SPRING * AMPLITUDE**2
        energy = spring_energy(h[:, 1], h[:, 2])
        z, v = r["pos"][2] - Z_EQ, r["vel"][2]
        phase = math.atan2(-v / OMEGA, z)  # z = a cos(omega t), v = -a omega sin(omega t)
        err = (phase - OMEGA * t + math.pi) % (2 * math.pi) - math.pi
        return {"phase_err_rad": abs(err), "energy_err": float(np.max(np.abs(energy / e0 - 1)))}
    if p.name == "kepler":  # at the end: energy -1/2, angular momentum sqrt(1 - e^2)
        x, v = r["pos"], r["vel"]
        energy = 0.5 * v @ v - 1.0 / np.linalg.norm(x)
        return {
            "pos_err_m": float(np.linalg.norm(x - kepler_exact(t))),
            "energy_err": abs(energy / -0.5 - 1.0),
            "angmom_err": abs(np.cross(x, v)[2] / math.sqrt(1 - KEPLER_E**2) - 1.0),
        }
    if p.name == "torque_free":
        w_ref = torque_free_exact(TF_INERTIA, TF_W0, [t])[0]
        e0 = float(np.sum(np.asarray(TF_INERTIA) * np.asarray(TF_W0) ** 2)) / 2
        return {
            "omega_err": float(np.linalg.norm(r["omega_body"] - w_ref) / np.linalg.norm(w_ref)),
            "energy_err": abs(r["ke"] / e0 - 1),
        }
    ref = p.reference
    return {
        "pos_err_m": float(np.linalg.norm(r["pos"] - ref["pos"])),
        "att_err_rad": attitude_error(r["quat"], ref["quat"]),
    }


def craft_reference(p: Problem) -> float:
    """Fill ``p.reference`` with rk4 at nominal dt / 64 (float64); return its distance (m) to
    rk4 at nominal dt / 128, the reference's own error estimate."""
    fine = run(p, "rk4", p.nominal_dt / 64)
    finer = run(p, "rk4", p.nominal_dt / 128)
    p.reference = fine
    return max(
        float(np.linalg.norm(fine["pos"] - finer["pos"])),
        attitude_error(fine["quat"], finer["quat"]),
    )


def check_torque_free_reference() -> float:
    """The Jacobi solution against solve_ivp over the problem's 10 s; assert 1e-8."""
    t = np.linspace(0.0, 10.0, 401)
    diff = float(
        np.abs(
            torque_free_exact(TF_INERTIA, TF_W0, t) - euler_solve_ivp(TF_INERTIA, TF_W0, t)
        ).max()
    )
    assert diff < 1e-8, f"Jacobi solution disagrees with solve_ivp by {diff:.3e}"
    return diff


def cost_ns(p: Problem, integrator: str, dtype, num_envs: int, repeats: int, steps: int = 100):
    """Wall time per body-step (ns) of ``step(steps=100)`` at ``num_envs`` on one thread (the
    serial kernel), min over repeats."""
    sim = Simulator(
        p.craft, p.world, num_envs, p.nominal_dt, integrator, dtype=dtype, parallel=False
    )
    sim.reset(**p.start)
    ctrl = p.control_array(num_envs)
    sim.step(ctrl, steps=1)  # compile or load the kernel
    best = best_of(
        lambda: sim.step(ctrl, steps=steps), repeats, lambda: sim.reset(**p.start), warmup=False
    )
    return 1e9 * best / (steps * num_envs * sim.num_bodies)


# ---- main ------------------------------------------------------------------------------------


# the two charts: the first six methods, and the seed's remaining ones beside symplectic Euler
# and rk2 (one chart of twelve lines is unreadable)
FIRST = ("explicit_euler", "symplectic_euler", "velocity_verlet", "rk2", "rk4", "verlet_tetra")
SEED = ("symplectic_euler", "rk2", *IT.SEED_METHODS)
CHARTS = {"study_accuracy.png": FIRST, "study_accuracy_seed.png": SEED}
assert set(FIRST) | set(SEED) == set(METHODS), "a method in no chart"


def plot(rows: list[dict], probs: list[Problem], path: Path, methods=FIRST) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = [(p, m) for p in probs for m in p.metrics]
    labels = {
        "pos_err_m": "final position error (m)",
        "att_err_rad": "final attitude error (rad)",
        "phase_err_rad": "phase error after 50 periods (rad)",
        "energy_err": "relative energy error",
        "omega_err": "body angular velocity error (relative)",
        "angmom_err": "relative angular momentum error",
    }
    ncol = 3
    nrow = -(-len(panels) // ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(5 * ncol, 3.9 * nrow), constrained_layout=True)
    colors = dict(zip(methods, plt.rcParams["axes.prop_cycle"].by_key()["color"], strict=False))
    markers = dict(zip(methods, "ovs^Dx<>ph", strict=False))
    for ax, (p, metric) in zip(axes.flat, panels, strict=False):
        for m in methods:
            for dname, style in (("float64", "-"), ("float32", ":")):
                pts = [
                    (r["cost_us"], max(r[metric], 1e-17))
                    for r in rows
                    if r["problem"] == p.name
                    and r["integrator"] == m
                    and r["dtype"] == dname
                    and math.isfinite(r[metric])
                ]
                if not pts:
                    continue
                x, y = zip(*sorted(pts), strict=True)
                ax.loglog(
                    x,
                    y,
                    style,
                    marker=markers[m],
                    ms=3.5,
                    color=colors[m],
                    label=f"{m}" if dname == "float64" else None,
                )
        ax.set_title(f"{p.name}: {metric}", fontsize=10)
        ax.set_xlabel("compute per body over the interval (us)")
        ax.set_ylabel(labels[metric])
        ax.grid(True, which="both", alpha=0.3)
    for ax in list(axes.flat)[len(panels) :]:
        ax.axis("off")
    axes.flat[0].plot([], [], "k-", label="float64")
    axes.flat[0].plot([], [], "k:", label="float32")
    axes.flat[0].legend(fontsize=7)
    fig.suptitle(
        "Work-precision: error against cost (steps x measured ns per body-step, E = 1024, "
        "1 thread); one point per dt"
    )
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main() -> None:
    parser = arguments(__doc__, "fewer dts and repeats")
    parser.add_argument("--repeats", type=int, default=15, help="timing repeats (min taken)")
    parser.add_argument("--envs", type=int, default=1024, help="batch for the cost timing")
    args = parser.parse_args()
    out = out_dir(args.out, args.quick)
    repeats = 2 if args.quick else args.repeats
    num_envs = 256 if args.quick else args.envs
    t_start = time.perf_counter()
    machine = describe()
    diff = check_torque_free_reference()
    print(f"torque-free: Jacobi solution vs solve_ivp, max |dw| over 10 s = {diff:.2e} rad/s")
    probs = problems(args.quick)
    notes = [f"torque_free: Jacobi vs solve_ivp max |dw| {diff:.3e} rad/s"]
    for p in probs:
        if p.name in ("paper_airplane", "speedboat", "uuv"):
            conv = craft_reference(p)
            notes.append(
                f"{p.name}: reference rk4 dt {p.nominal_dt / 64:.6g} s; "
                f"distance to rk4 at dt/128: {conv:.3e} (m or rad)"
            )
            print(notes[-1])

    cost = {}
    cost_rows = []
    for p in probs:
        for m in METHODS:
            for dname, dtype in DTYPES.items():
                ns = cost_ns(p, m, dtype, num_envs, repeats)
                cost[p.name, m, dname] = ns
                cost_rows.append(
                    (p.name, m, dname, num_envs, fmt(p.nominal_dt), EVALS_PER_STEP[m], f"{ns:.2f}")
                )
                print(f"cost {p.name:15s} {m:17s} {dname}: {ns:8.2f} ns/body-step")

    rows = []
    for p in probs:
        for m in METHODS:
            for dname, dtype in DTYPES.items():
                for dt in p.dts:
                    samples = 200 if p.name == "spring" else 0
                    r = run(p, m, dt, dtype, samples=samples)
                    bad = r["diverged"] or not np.all(np.isfinite(r["pos"]))
                    errs = {k: math.nan for k in p.metrics} if bad else errors(p, r)
                    n = p.steps(dt)
                    row = {
                        "problem": p.name,
                        "integrator": m,
                        "dtype": dname,
                        "dt_s": dt,
                        "steps": n,
                        "evals_per_step": EVALS_PER_STEP[m],
                        "ns_per_body_step": cost[p.name, m, dname],
                        "cost_us": n * cost[p.name, m, dname] / 1e3,
                        "diverged": bad,
                        **{
                            k: math.nan
                            for k in (
                                "pos_err_m",
                                "att_err_rad",
                                "phase_err_rad",
                                "energy_err",
                                "omega_err",
                                "angmom_err",
                            )
                        },
                        **errs,
                    }
                    rows.append(row)
                shown = [
                    r
                    for r in rows
                    if r["problem"] == p.name and r["integrator"] == m and r["dtype"] == dname
                ]
                print(
                    f"{p.name:15s} {m:17s} {dname}: {p.metrics[0]} "
                    + " ".join(f"{r[p.metrics[0]]:.1e}" for r in shown)
                )
    header = tuple(rows[0])
    write_csv(
        out / "study_accuracy.csv",
        header,
        [tuple(fmt(r[k]) for k in header) for r in rows],
        [*machine, *notes],
    )
    write_csv(
        out / "study_cost.csv",
        (
            "problem",
            "integrator",
            "dtype",
            "num_envs",
            "dt_s",
            "evals_per_step",
            "ns_per_body_step",
        ),
        cost_rows,
        machine,
    )
    for name, methods in CHARTS.items():
        plot(rows, probs, out / name, methods)
    print(
        f"wrote {out}/study_accuracy.csv, study_cost.csv, {', '.join(CHARTS)} "
        f"in {time.perf_counter() - t_start:.0f} s"
    )


if __name__ == "__main__":
    main()


def cost_markdown(path: Path | None = None) -> str:
    """docs/study.md's cost table from docs/study_cost.csv (``benchmarks.report`` writes it):
    ns per body-step, float64 / float32, an integrator a row and a problem a column."""
    from benchmarks.common import DOCS, read_csv

    path = DOCS / "study_cost.csv" if path is None else path
    if not path.is_file():
        return "(no docs/study_cost.csv yet: run python -m benchmarks.study_accuracy)"
    comments, rows = read_csv(path)
    ns = {(r["problem"], r["integrator"], r["dtype"]): float(r["ns_per_body_step"]) for r in rows}
    evals = {r["integrator"]: r["evals_per_step"] for r in rows}
    samples = {p.name: p.craft.num_samples for p in problems()}
    names = list(dict.fromkeys(r["problem"] for r in rows))
    head = " | ".join(f"{p} ({samples[p]})" for p in names)
    lines = [
        f"| integrator | evaluations per step | {head} |",
        "|---|---:|" + "---:|" * len(names),
    ]
    for m in dict.fromkeys(r["integrator"] for r in rows):
        cells = " | ".join(f"{ns[p, m, 'float64']:.1f} / {ns[p, m, 'float32']:.1f}" for p in names)
        per = " per iteration" if m == "implicit_midpoint" else ""
        lines.append(f"| {m} | {evals[m]}{per} | {cells} |")
    load = next((c for c in comments if c.startswith("load average")), "")
    lines += ["", f"From docs/study_cost.csv (`python -m benchmarks.study_accuracy`; {load})."]
    return "\n".join(lines)
