"""``integrator="verlet_tetra"`` on free bodies (issue 3, first part): the body turns as its
matched tetrahedron (four particles drifting a step, the shape restored by the best-fitting
rotation, the momenta kept), translates as symplectic Euler, and above
``World.tetra_rigid_spin_rad`` per step turns rigidly instead.

The degradation the switch exists for, measured here on the torque-free intermediate-axis
body (I = 1, 2, 3, spun about the middle axis, 2 s at dt = 0.01; benchmarks/bench_tetra.py
charts it at two steps in docs/tetra_spin.png): the largest relative energy error of the
tetrahedron is 5e-11 at |w| dt = 0.01 and 2e-6 at 0.04 (below the rigid midpoint turn's
4e-10 and 9e-6), then 3e-3 at 0.16 and about 10% at 0.4, against the rigid turn's 1e-3 and
6e-3: the particles' straight paths cut the corners of fast turns."""

import math

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Simulator, World

RACKET = Craft(name="racket", mass_kg=1.0, inertia_kgm2=(1.0, 2.0, 3.0))
DT = 0.01


def energy_error(integrator, spin, switch=math.inf, seconds=2.0):
    sim = Simulator(
        RACKET,
        World(gravity_mps2=0.0, tetra_rigid_spin_rad=switch),
        num_envs=1,
        dt=DT,
        integrator=integrator,
    )
    sim.reset(ang_vel=(0.01 * spin, spin, 0.01 * spin))
    e0, l0 = sim.kinetic_energy()[0, 0], sim.angular_momentum()[0, 0]
    worst = 0.0
    for _ in range(int(round(seconds / DT))):
        sim.step()
        worst = max(worst, abs(sim.kinetic_energy()[0, 0] / e0 - 1.0))
    assert np.array_equal(sim.angular_momentum()[0, 0], l0)  # the state: exact
    return worst


def test_tetrahedron_degrades_with_the_turn_per_step():
    spins = (1.0, 4.0, 16.0, 40.0)  # |w| dt = 0.01, 0.04, 0.16, 0.4
    tetra = [energy_error("verlet_tetra", w) for w in spins]
    rigid = [energy_error("symplectic_euler", w) for w in spins]
    assert tetra[0] < 1e-9
    assert all(b > 10 * a for a, b in zip(tetra, tetra[1:], strict=False))
    assert tetra[-1] > 0.05
    assert tetra[0] < rigid[0] and tetra[1] < rigid[1]  # slow turns: as good or better
    assert tetra[2] > 2 * rigid[2] and tetra[3] > 10 * rigid[3]  # fast turns: degraded


def test_switching_to_rigid_removes_the_degradation():
    """With the switch at 0.1 rad per step: below it the tetrahedron, bit for bit; above it
    the rigid turn, bit for bit."""
    for spin, same_as in ((4.0, "verlet_tetra"), (40.0, "symplectic_euler")):
        switched = energy_error("verlet_tetra", spin, switch=0.1)
        assert switched == energy_error(same_as, spin)


def test_translation_is_symplectic_euler():
    """A thrown, spinning box under gravity: position and velocity are symplectic Euler's."""
    runs = {}
    for integrator in ("symplectic_euler", "verlet_tetra"):
        sim = Simulator(RACKET, World(), num_envs=3, dt=DT, integrator=integrator)
        sim.reset(lin_vel=(3.0, 0.5, 4.0), ang_vel=(0.5, 1.0, -0.3))
        sim.step(steps=150)
        runs[integrator] = (sim.pos.copy(), sim.lin_vel.copy(), sim.quat.copy())
    (p0, v0, q0), (p1, v1, q1) = runs.values()
    np.testing.assert_array_equal(p0, p1)
    np.testing.assert_array_equal(v0, v1)
    assert not np.array_equal(q0, q1)  # the turn is the tetrahedron's: first order, close
    np.testing.assert_allclose(q0, q1, atol=1e-2)


def test_same_result_for_any_batch_size():
    rng = np.random.default_rng(3)
    w = rng.normal(size=(70, 1, 3)) * 5.0
    big = Simulator(RACKET, World(gravity_mps2=0.0), num_envs=70, dt=DT, integrator="verlet_tetra")
    big.reset(ang_vel=w)
    big.step(steps=50)
    one = Simulator(RACKET, World(gravity_mps2=0.0), num_envs=1, dt=DT, integrator="verlet_tetra")
    for e in (0, 63, 64, 69):
        one.reset(ang_vel=w[e])
        one.step(steps=50)
        np.testing.assert_array_equal(one.quat[0], big.quat[e])


@pytest.mark.parametrize("bad", [0.0, -0.1, float("nan"), "fast"])
def test_switch_must_be_positive(bad):
    with pytest.raises(ValueError, match="tetra_rigid_spin_rad"):
        World(tetra_rigid_spin_rad=bad)
