"""Integrators against closed forms: the projectile, the buoyancy spring and the free rigid body."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from fluidsim_envs.physics import INTEGRATORS, Buoyancy, Craft, Simulator, World
from fluidsim_envs.physics.kernels import quat_matrices

G = 9.81
BOX = Craft(name="box", mass_kg=1.0, inertia_kgm2=(1.0, 2.0, 3.0))


# ---- projectile ------------------------------------------------------------------------------
# Discrete closed forms of each method on x'' = -g from rest, after n steps of h (the seed
# article's integrator table: symplectic Euler gives 4.95405 m and 9.81 m/s at h = 1/100,
# n = 100; explicit Euler 4.85595 m; the second- and higher-order methods the exact 4.905 m).
PROJECTILE = {
    "explicit_euler": lambda n, h: -G * h * h * n * (n - 1) / 2,
    "symplectic_euler": lambda n, h: -G * h * h * n * (n + 1) / 2,
    "velocity_verlet": lambda n, h: -G * (n * h) ** 2 / 2,
    "rk2": lambda n, h: -G * (n * h) ** 2 / 2,
    "rk4": lambda n, h: -G * (n * h) ** 2 / 2,
    "verlet_tetra": lambda n, h: -G * h * h * n * (n + 1) / 2,  # symplectic Euler's kick, drift
    # the seed's table: "more accurate" Euler and its velocity Verlet give 4.905 m; the
    # velocity-less Verlet and its prescaled NSV are symplectic Euler's 4.95405 m
    "accurate_euler": lambda n, h: -G * (n * h) ** 2 / 2,
    "position_verlet": lambda n, h: -G * h * h * n * (n + 1) / 2,
    "prescaled_symplectic_euler": lambda n, h: -G * h * h * n * (n + 1) / 2,
    "velocity_verlet_cached": lambda n, h: -G * (n * h) ** 2 / 2,
    "trapezoid_symplectic_euler": lambda n, h: -G * h * h * n * (n + 1) / 2,
    "implicit_midpoint": lambda n, h: -G * (n * h) ** 2 / 2,  # exact for a constant force
}
# float32: the largest error in units of the result's last place (measured, then doubled).
# The velocity-less Verlet rounds worst: its velocity is a difference of positions, x - x_old,
# which keeps 1/100 of x's digits; the seed's own float32 run printed 9.810033 m/s for it
# (tests/physics/test_seed_integrators.py reproduces the seed's numbers)
# The prescaled NSV's velocity u / dt magnifies u's last place a hundredfold (measured 8.4)
F32_ULPS = {"position_verlet": 80, "prescaled_symplectic_euler": 20}


@pytest.mark.parametrize("integrator", sorted(INTEGRATORS))
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_projectile_matches_discrete_closed_form(integrator, dtype):
    sim = Simulator(
        BOX, World(gravity_mps2=G), num_envs=3, dt=0.01, integrator=integrator, dtype=dtype
    )
    sim.reset()
    sim.step(steps=100)
    z, vz = sim.pos[:, 0, 2], sim.lin_vel[:, 0, 2]
    expected = PROJECTILE[integrator](100, 0.01)
    if dtype == np.float64:
        np.testing.assert_allclose(z, expected, rtol=0, atol=1e-9)
        np.testing.assert_allclose(vz, -9.81, rtol=0, atol=1e-9)
    else:  # 100 float32 additions: a few ulp of the result
        ulps = F32_ULPS.get(integrator, 8)
        ulp = np.spacing(np.float32(abs(expected)))
        assert np.all(np.abs(z - expected) <= ulps * ulp), (z, expected, ulp)
        assert np.all(np.abs(vz + 9.81) <= ulps * np.spacing(np.float32(9.81)))
    if integrator == "symplectic_euler":
        assert round(float(z[0]), 5) == -4.95405


# ---- buoyancy spring ---------------------------------------------------------------------------
# An area buoyancy sample at the center of mass is a linear spring k = rho g A around the
# waterline depth m / (rho A): a harmonic oscillator of period 2 pi sqrt(m / k).
RHO = 1025.0
AREA = 0.01
FLOAT = Craft(
    name="float",
    mass_kg=1.0,
    inertia_kgm2=(1.0, 1.0, 1.0),
    buoyancy=(Buoyancy("hull", (0.0, 0.0, 0.0), "area", area_m2=AREA),),
)
K_SPRING = RHO * G * AREA
Z_EQ = -FLOAT.mass_kg / (RHO * AREA)
OMEGA = np.sqrt(K_SPRING / FLOAT.mass_kg)


def spring_run(integrator, dt, steps, amplitude=0.02, record_every=1):
    sim = Simulator(
        FLOAT, World(water=True, water_density_kgm3=RHO), num_envs=1, dt=dt, integrator=integrator
    )
    sim.reset(pos=(0.0, 0.0, Z_EQ + amplitude))
    z, v = [], []
    for _ in range(steps // record_every):
        sim.step(steps=record_every)
        z.append(sim.pos[0, 0, 2])
        v.append(sim.lin_vel[0, 0, 2])
    z, v = np.array(z) - Z_EQ, np.array(v)
    energy = 0.5 * FLOAT.mass_kg * v**2 + 0.5 * K_SPRING * z**2
    return z, energy, 0.5 * K_SPRING * amplitude**2


def test_buoyancy_spring_period():
    dt = 1e-3
    z, _, _ = spring_run("rk4", dt, 4000)
    t = dt * (np.arange(len(z)) + 1)
    up = np.nonzero((z[:-1] < 0) & (z[1:] >= 0))[0]
    crossings = t[up] - dt * z[up + 1] / (z[up + 1] - z[up])  # linear interpolation
    period = np.mean(np.diff(crossings))
    assert period == pytest.approx(2 * np.pi / OMEGA, rel=1e-4)


def test_symplectic_euler_energy_bounded_explicit_euler_grows():
    dt = 0.01
    steps = int(1000 * 2 * np.pi / OMEGA / dt)  # 1000 periods
    _, energy, e0 = spring_run("symplectic_euler", dt, steps, record_every=7)
    drift = np.abs(energy / e0 - 1)
    # symplectic Euler: the error oscillates, bounded by O(omega dt), with no secular growth
    assert drift.max() < OMEGA * dt
    tenth = len(drift) // 10
    assert drift[-tenth:].max() < 1.05 * drift[:tenth].max()

    # explicit Euler amplifies each step by |1 + i omega dt|: energy grows as (1 + (w dt)^2)^n
    n = 300
    _, energy, e0 = spring_run("explicit_euler", dt, n)
    assert energy[-1] / e0 == pytest.approx((1 + (OMEGA * dt) ** 2) ** n, rel=1e-6)
    assert energy[-1] / e0 > 10


# ---- torque-free rigid body: the intermediate-axis (tennis racket) flip ----
I_BODY = np.array([1.0, 2.0, 3.0])
W0 = np.array([0.02, 2.0, 0.02])  # body frame, mostly about the intermediate axis


def euler_reference(t_end):
    """Euler's equations in the body frame, solved at tight tolerance (scipy solve_ivp)."""

    def rhs(_, w):
        i1, i2, i3 = I_BODY
        return [
            (i2 - i3) / i1 * w[1] * w[2],
            (i3 - i1) / i2 * w[2] * w[0],
            (i1 - i2) / i3 * w[0] * w[1],
        ]

    return solve_ivp(
        rhs, (0, t_end), W0, method="DOP853", rtol=1e-12, atol=1e-12, dense_output=True
    )


def first_flip(t, wy):
    i = np.nonzero(np.sign(wy) != np.sign(wy[0]))[0][0]
    return t[i - 1] + (t[i] - t[i - 1]) * wy[i - 1] / (wy[i - 1] - wy[i])


def body_rates(sim):
    rot = quat_matrices(np.ascontiguousarray(sim.quat[0]))[0]
    return rot.T @ sim.ang_vel[0, 0]


def spin(integrator, dt, t_end):
    sim = Simulator(BOX, World(gravity_mps2=0.0), num_envs=1, dt=dt, integrator=integrator)
    sim.reset(ang_vel=W0)  # identity attitude: body = world frame at t = 0
    e0, l0 = sim.kinetic_energy()[0, 0], sim.angular_momentum()[0, 0]
    n = int(round(t_end / dt))
    wy, energy, mom = np.empty(n), np.empty(n), np.empty((n, 3))
    for k in range(n):
        sim.step()
        wy[k] = body_rates(sim)[1]
        energy[k] = sim.kinetic_energy()[0, 0]
        mom[k] = sim.angular_momentum()[0, 0]
    return dt * (np.arange(n) + 1), wy, energy / e0 - 1, np.abs(mom - l0).max()


# Largest |energy error| over 10 s at dt = 1/100 (measured, with headroom), and the error in
# the flip time (reference 5.46 s). Explicit Euler gains energy every step (about 4% here): it
# fails. Symplectic Euler and velocity Verlet turn the orientation with an explicit-midpoint
# step (second order), so their energy error stays ~1e-5 and returns to ~1e-7 after the flip;
# RK2 and RK4 are accurate at their order but not conservative over long times. The Verlet
# tetrahedron's turn (its particles' drift, the shape refitted) is as good at |w| dt = 0.02;
# tests/physics/test_tetra_integrator.py follows it to fast spins, where it degrades.
ENERGY_TOL = {
    "explicit_euler": 0.1,
    "symplectic_euler": 5e-5,
    "velocity_verlet": 5e-5,
    "rk2": 1e-5,
    "rk4": 5e-9,
    "verlet_tetra": 5e-5,
    # without torque the seed's Euler and Verlet variants turn as symplectic Euler does (their
    # differences are in the kicks); the trapezoid turn measured 3.2e-5, the implicit
    # midpoint 1.7e-5 (and 1e-9 after the flip: it conserves the quadratic invariants)
    "accurate_euler": 5e-5,
    "position_verlet": 5e-5,
    "prescaled_symplectic_euler": 5e-5,
    "velocity_verlet_cached": 5e-5,
    "trapezoid_symplectic_euler": 5e-5,
    "implicit_midpoint": 5e-5,
}
FLIP_TOL = {
    "explicit_euler": 0.05,
    "symplectic_euler": 2e-3,
    "velocity_verlet": 2e-3,
    "rk2": 2e-3,
    "rk4": 1e-6,
    "verlet_tetra": 2e-3,
    "accurate_euler": 2e-3,  # measured 3.4e-4, as symplectic Euler
    "position_verlet": 2e-3,
    "prescaled_symplectic_euler": 2e-3,
    "velocity_verlet_cached": 2e-3,
    "trapezoid_symplectic_euler": 2e-3,  # measured 2.5e-4
    "implicit_midpoint": 2e-3,  # measured 1.3e-4
}


@pytest.mark.parametrize("integrator", sorted(INTEGRATORS))
def test_tennis_racket_flip_and_invariants(integrator):
    t_end = 10.0
    ref = euler_reference(t_end)
    tr = np.linspace(0, t_end, 20001)
    t_flip_ref = first_flip(tr, ref.sol(tr)[1])
    assert 4.0 < t_flip_ref < 7.0  # the reference itself flips inside the window

    t, wy, de, dl = spin(integrator, 0.01, t_end)
    assert dl < 1e-12  # world angular momentum is the state: conserved to rounding
    assert np.abs(de).max() < ENERGY_TOL[integrator]
    assert abs(first_flip(t, wy) - t_flip_ref) < FLIP_TOL[integrator]
    if integrator == "explicit_euler":
        assert de[-1] > 0.01  # the documented failure: it gains energy


def test_explicit_euler_fails_where_symplectic_holds():
    """The known failure: explicit Euler's energy error at dt = 1/100 is far above the others."""
    errs = {m: np.abs(spin(m, 0.01, 5.0)[2]).max() for m in ("explicit_euler", "rk4")}
    assert errs["explicit_euler"] > 100 * errs["rk4"]


def kepler_run(integrator, dt, orbits):
    """The Kepler problem of Hairer, Lubich and Wanner (Geometric Numerical Integration, I.2.3):
    GM = 1, eccentricity 0.6, from the pericentre q = (1 - e, 0) with p = (0, sqrt((1+e)/(1-e)));
    energy -1/2, angular momentum sqrt(1 - e^2), period 2 pi. Returns the largest relative
    energy error in each orbit (sampled every 10 steps: the error peaks near the pericentre)
    and the final angular momentum error."""
    e = 0.6
    point = Craft(name="planet", mass_kg=1.0, inertia_kgm2=(1.0, 1.0, 1.0))
    world = World(gravity_mps2=0.0, central_gravity_m3s2=1.0)
    sim = Simulator(point, world, dt=dt, integrator=integrator)
    sim.reset(pos=(1 - e, 0.0, 0.0), lin_vel=(0.0, math.sqrt((1 + e) / (1 - e)), 0.0))
    chunks = round(2 * math.pi / dt / 10)
    worst = []
    for _ in range(orbits):
        err = 0.0
        for _ in range(chunks):
            sim.step(steps=10)
            x, v = sim.pos[0, 0], sim.lin_vel[0, 0]
            err = max(err, abs((0.5 * v @ v - 1.0 / np.linalg.norm(x)) / -0.5 - 1.0))
        worst.append(err)
    L = np.cross(sim.pos[0, 0], sim.lin_vel[0, 0])[2]
    return np.array(worst), abs(L / math.sqrt(1 - e * e) - 1.0)


def test_kepler_orbit_symplectic_euler_bounded_explicit_euler_drifts():
    """GNI chapter I (Figure 2.2 and its discussion): symplectic Euler keeps the energy error
    bounded over many orbits and the angular momentum of a central force exactly (to
    rounding); explicit Euler's energy drifts away orbit after orbit."""
    se, se_L = kepler_run("symplectic_euler", 0.005, 40)
    ee, _ = kepler_run("explicit_euler", 0.005, 40)
    assert se_L < 1e-12  # a central force: exact in symplectic Euler
    # bounded (1.4% at this dt, peaking at each pericentre passage), with no drift
    assert se.max() < 0.02 and se[-10:].max() < 1.01 * se[:10].max()
    assert ee[-1] > 0.8 and ee[-1] > 1.5 * ee[4] and ee[-10:].min() >= ee[:10].max()  # drifts
    rk4, rk4_L = kepler_run("rk4", 0.005, 10)
    assert rk4.max() < 1e-6 and rk4_L < 1e-6
