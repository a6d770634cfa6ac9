"""Fluid-sample forces: flat plate and cylinder against their defining formulas (the seed's
flat-plate model, F = -1/2 rho A (v|v| . n) n, with drag removed by efficiency; Hoerner's
cross-flow principle for cylinders), control deflection, buoyancy, thrust and divergence."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fluidsim_envs.physics import (
    Buoyancy,
    Control,
    Craft,
    Cylinder,
    Plate,
    Simulator,
    Surface,
    Thruster,
    World,
)
from fluidsim_envs.physics.forces import cylinder_force, plate_force, thrust_control

RHO, AREA, VMAX, FMAX = 1.225, 0.5, 1e3, 1e12


def plate(v, n, efficiency=0.0):
    return np.array(plate_force(*v, *n, RHO, AREA, efficiency, VMAX, FMAX))


def stream(speed, alpha):
    """Flow at angle of attack alpha onto a plate with normal +z: v relative to the plate."""
    return np.array([speed * np.cos(alpha), 0.0, -speed * np.sin(alpha)])


def test_plate_force_along_normal_scaling_v2_and_sin_alpha():
    n = (0.0, 0.0, 1.0)
    for alpha in np.radians([1.0, 5.0, 20.0, 60.0, 90.0]):
        f = plate(stream(10.0, alpha), n)
        assert f[0] == pytest.approx(0.0, abs=1e-12) and f[1] == 0.0  # along the normal
        assert f[2] == pytest.approx(0.5 * RHO * AREA * 100.0 * np.sin(alpha), rel=1e-12)
        assert plate(stream(20.0, alpha), n)[2] == pytest.approx(4 * f[2], rel=1e-12)
    assert np.all(plate(stream(10.0, 0.0), n) == 0.0)  # edge-on: no force
    assert np.all(plate((0.0, 0.0, 0.0), n) == 0.0)  # at rest: finite, zero


def test_plate_efficiency_removes_the_drag_component():
    v = stream(10.0, np.radians(10.0))
    for eff in (0.0, 0.5, 1.0):
        f = plate(v, (0.0, 0.0, 1.0), eff)
        drag = -f @ v / np.linalg.norm(v)
        bare = -plate(v, (0.0, 0.0, 1.0)) @ v / np.linalg.norm(v)
        assert drag == pytest.approx((1 - eff) * bare, rel=1e-12, abs=1e-12)
    f = plate(v, (0.0, 0.0, 1.0), 1.0)
    assert abs(f @ v) < 1e-12 * np.linalg.norm(f) * 10  # efficiency 1: pure lift


def test_cylinder_cross_flow_force():
    axis = (1.0, 0.0, 0.0)
    for alpha in np.radians([0.0, 10.0, 45.0, 90.0]):
        v = stream(10.0, alpha)
        f = np.array(cylinder_force(*v, *axis, RHO, AREA, VMAX, FMAX))
        assert f[0] == pytest.approx(0.0, abs=1e-12)  # nothing along the axis
        assert f[2] == pytest.approx(0.5 * RHO * AREA * (10.0 * np.sin(alpha)) ** 2, rel=1e-12)


def test_velocity_and_force_clamps():
    f = np.array(plate_force(1e6, 0.0, -1e6, 0.0, 0.0, 1.0, RHO, AREA, 0.0, 100.0, 1e12))
    assert np.linalg.norm(f) == pytest.approx(0.5 * RHO * AREA * 100.0**2 * np.sqrt(0.5), rel=1e-9)
    f = np.array(plate_force(0.0, 0.0, -50.0, 0.0, 0.0, 1.0, RHO, AREA, 0.0, 100.0, 7.0))
    assert np.linalg.norm(f) == pytest.approx(7.0, rel=1e-12)


def one_step_force(craft, world, controls=None, lin_vel=(0.0, 0.0, 0.0), pos=(0, 0, 0)):
    """The force and torque on a body, read back from one explicit-Euler step."""
    dt = 1e-3
    sim = Simulator(craft, world, num_envs=1, dt=dt, integrator="explicit_euler")
    sim.reset(pos=pos, lin_vel=lin_vel)
    sim.step(controls)
    force = craft.mass_kg * (sim.lin_vel[0, 0] - np.asarray(lin_vel)) / dt
    return force, sim.angular_momentum()[0, 0] / dt


def test_simulator_applies_plate_force_in_wind_at_its_offset():
    wing = Plate("wing", (0.0, 0.5, 0.0), (0.0, 0.0, 1.0), AREA, efficiency=0.3)
    craft = Craft(name="w", mass_kg=2.0, inertia_kgm2=(1, 1, 1), plates=(wing,))
    wind = (-10.0 * np.cos(0.2), 0.0, 10.0 * np.sin(0.2))  # the body sees stream(10, 0.2)
    force, torque = one_step_force(craft, World(gravity_mps2=0.0, wind_mps=wind))
    expected = plate(stream(10.0, 0.2), (0, 0, 1), 0.3)
    np.testing.assert_allclose(force, expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(torque, np.cross((0.0, 0.5, 0.0), expected), rtol=1e-12, atol=1e-12)


def test_control_deflection_rotates_the_normal():
    flap = Plate("flap", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), AREA, hinge_axis=(0.0, 1.0, 0.0))
    craft = Craft(
        name="f",
        mass_kg=1.0,
        inertia_kgm2=(1, 1, 1),
        plates=(flap,),
        controls=(Control("elevator", 20.0, (Surface("flap", -1.0),)),),
    )
    world = World(gravity_mps2=0.0)
    for action in (-1.0, 0.0, 0.5, 1.0):
        force, _ = one_step_force(craft, world, [[action]], lin_vel=(10.0, 0.0, 0.0))
        theta = np.radians(-20.0 * action)  # gain -1
        normal = (np.sin(theta), 0.0, np.cos(theta))  # +z turned about +y by theta
        np.testing.assert_allclose(force, plate((10.0, 0.0, 0.0), normal), rtol=1e-12, atol=1e-12)


def test_buoyancy_volume_and_thrust():
    craft = Craft(
        name="b",
        mass_kg=100.0,
        inertia_kgm2=(1, 1, 1),
        buoyancy=(Buoyancy("tank", (1.0, 0.0, 0.0), "volume", volume_m3=0.2),),
        thrusters=(
            Thruster("prop", (0.0, 0.0, -0.5), (1.0, 0.0, 0.0), 300.0, -100.0, control="throttle"),
        ),
        controls=(Control("throttle"),),
    )
    world = World(water=True, surface_blend_m=0.1)
    # deep: full buoyancy 1025 * 9.81 * 0.2 at x = 1 m (a pitching torque), and throttle 0.5
    # gives half the 300 N ahead
    force, torque = one_step_force(craft, world, [[0.5]], pos=(0.0, 0.0, -5.0))
    lift = 1025.0 * 9.81 * 0.2
    np.testing.assert_allclose(force, (150.0, 0.0, lift - 100.0 * 9.81), rtol=1e-12)
    np.testing.assert_allclose(
        torque,
        np.cross((1, 0, 0), (0, 0, lift)) + np.cross((0, 0, -0.5), (150.0, 0, 0)),
        rtol=1e-12,
        atol=1e-9,
    )
    # throttle 0: no thrust; -1: the 100 N astern; -0.25 a quarter of it
    for c, thrust in ((0.0, 0.0), (-1.0, -100.0), (-0.25, -25.0)):
        force, _ = one_step_force(craft, world, [[c]], pos=(0.0, 0.0, -5.0))
        assert force[0] == thrust
        assert thrust_control(thrust, -100.0, 300.0) == c
    # half in the surface layer: half the buoyancy; in the air: none
    assert one_step_force(craft, world, [[-1.0]])[0][2] == pytest.approx(lift / 2 - 981.0)
    assert one_step_force(craft, world, [[-1.0]], pos=(0, 0, 1))[0][2] == pytest.approx(-981.0)


def test_divergence_is_flagged_not_hidden():
    """An absurd spin overflows the orientation update: that env is flagged (the env layer
    ends its episode) while its neighbour steps on unaffected."""
    box = Craft(name="box", mass_kg=1.0, inertia_kgm2=(1.0, 2.0, 3.0))
    sim = Simulator(box, World(), num_envs=2, dt=0.01)
    sim.reset(ang_vel=[[[1e200, 0.0, 0.0]], [[0.0, 0.0, 1.0]]])
    assert not sim.diverged.any()
    sim.step(steps=3)
    assert sim.diverged.tolist() == [True, False]
    assert np.all(np.isfinite(sim.quat[1]))
    sim.reset(env_ids=[0])
    assert not sim.diverged.any()


def test_runaway_beyond_the_speed_clamp_is_flagged():
    """The paper airplane at three times its stability limit (docs/study.md: 57 ms under
    symplectic Euler) runs away; the clamps keep it finite, so the flag is its speed passing
    max_fluid_speed_mps (outside the fluid model). The same dart at its default dt, and a
    body just under the clamp, are not flagged."""
    dart = Craft.load("paper_airplane")
    world = World()
    sim = Simulator(dart, world, num_envs=2, dt=0.171)
    sim.reset(pos=(0.0, 0.0, 100.0), lin_vel=(6.0, 0.0, 0.0))
    flagged = False
    for _ in range(40):
        sim.step()
        flagged |= bool(sim.diverged[0])
        if flagged:
            break
    assert flagged and np.all(np.isfinite(sim.pos))
    assert np.linalg.norm(sim.lin_vel[0, 0]) > world.max_fluid_speed_mps
    calm = Simulator(dart, world, num_envs=1, dt=1 / 240)
    calm.reset(pos=(0.0, 0.0, 100.0), lin_vel=(6.0, 0.0, 0.0))
    calm.step(steps=480)
    assert not calm.diverged.any()
    box = Craft(name="box", mass_kg=1.0, inertia_kgm2=(1.0, 1.0, 1.0))
    fast = Simulator(box, World(gravity_mps2=0.0), num_envs=1, dt=0.01)
    fast.reset(lin_vel=(0.99 * world.max_fluid_speed_mps, 0.0, 0.0))
    fast.step()
    assert not fast.diverged.any()


def test_cylinder_in_simulator_and_several_bodies():
    rod = Craft(
        name="rod",
        mass_kg=1.0,
        inertia_kgm2=(1, 1, 1),
        cylinders=(Cylinder("c", (0, 0, 0), (1, 0, 0), AREA),),
    )
    plane = Craft.load("paper_airplane")
    sim = Simulator(
        [rod, plane], World(gravity_mps2=0.0), num_envs=3, dt=1e-3, integrator="explicit_euler"
    )
    assert sim.control_names == (
        "paper_airplane.aileron",
        "paper_airplane.elevator",
        "paper_airplane.rudder",
    )
    assert sim.pos.shape == (3, 2, 3) and sim.quat.shape == (3, 2, 4)
    sim.reset(lin_vel=[[3.0, 4.0, 0.0], [6.0, 0.0, 0.0]])
    sim.step(np.zeros((3, 3)))
    dv = (sim.lin_vel[:, 0] - (3.0, 4.0, 0.0)) / 1e-3
    f = np.array(cylinder_force(3.0, 4.0, 0.0, 1.0, 0.0, 0.0, RHO, AREA, 156.0, 1e7))
    np.testing.assert_allclose(dv, np.broadcast_to(f, (3, 3)), rtol=1e-12, atol=1e-12)
    assert sim.kinetic_energy().shape == (3, 2)


finite = st.floats(-1e6, 1e6, allow_nan=False)


@settings(max_examples=300)
@given(
    v=st.tuples(finite, finite, finite),
    n=st.tuples(finite, finite, finite),
    eff=st.floats(0.0, 1.0),
)
def test_forces_stay_finite_and_clamped_for_any_flow(v, n, eff):
    """Property: whatever the relative velocity and orientation, the force is finite and within
    the clamp (the seed's robustness argument for clamping)."""
    norm = np.linalg.norm(n)
    if norm < 1e-6:
        return
    n = tuple(np.asarray(n) / norm)
    fmax = 1e5
    for f in (
        plate_force(*v, *n, 1025.0, 2.0, eff, 156.0, fmax),
        cylinder_force(*v, *n, 1025.0, 2.0, 156.0, fmax),
    ):
        f = np.asarray(f)
        assert np.all(np.isfinite(f))
        assert np.linalg.norm(f) <= fmax * (1 + 1e-12)
