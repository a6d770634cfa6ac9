"""The submarine scene's crafts (issue 6): the lead ``submarine`` and the agent's ``uuv``.

Each check compares the simulated craft with a closed form computed from the craft's own data:
hydrostatic balance (Archimedes), the roll period of a body righted by its metacentric height
(the compound pendulum, e.g. Newman, Marine Hydrodynamics, 1977, section 6.10, without added
mass, which this model does not carry), the top speed where thrust equals the head-on drag
``1/2 rho A v^2``, and the sign of every control."""

import math

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Simulator, World
from fluidsim_envs.physics.forces import thrust_control
from fluidsim_envs.physics.kernels import quat_matrices

WORLD = World(water=True)
DEPTH = -1000.0  # deep: both crafts are a little light and rise slowly during a test
# seconds for a maneuver to show: about 10 s for the UUV, 60 s for the 773 t submarine
MANEUVER_S = {"uuv": 8.0, "submarine": 60.0}


def parts(craft):
    volume = sum(b.volume_m3 for b in craft.buoyancy)
    height = np.mean([b.offset_m[2] for b in craft.buoyancy])  # center of buoyancy above CG
    thrust = sum(t.max_thrust_n for t in craft.thrusters)
    (nose,) = [p for p in craft.plates if p.normal == (1.0, 0.0, 0.0)]
    return volume, height, thrust, nose.area_m2


def euler(sim):
    """Roll, pitch (nose up), heading (left positive) of body 0 [E] each, radians."""
    rot = quat_matrices(np.ascontiguousarray(sim.quat[:, 0]))
    x, y = rot[:, :, 0], rot[:, :, 1]
    return (
        np.arctan2(y[:, 2], rot[:, 2, 2]),
        np.arcsin(np.clip(x[:, 2], -1, 1)),
        np.arctan2(x[:, 1], x[:, 0]),
    )


@pytest.mark.parametrize("name", MANEUVER_S)
def test_hydrostatic_balance(name):
    """Net vertical force at rest, fully submerged, is rho g V - m g (Archimedes), and it is
    small: near-neutral buoyancy, slightly positive."""
    craft = Craft.load(name)
    volume, _, _, _ = parts(craft)
    sim = Simulator(craft, WORLD)
    sim.reset(pos=(0.0, 0.0, DEPTH))
    force, torque = sim.wrench()
    weight = craft.mass_kg * WORLD.gravity_mps2
    expected = WORLD.water_density_kgm3 * WORLD.gravity_mps2 * volume - weight
    assert force[0, 0, 2] - weight == pytest.approx(expected, rel=1e-9)
    assert 0.0 < expected < 0.005 * weight
    np.testing.assert_allclose(torque, 0.0, atol=1e-6 * weight)


@pytest.mark.parametrize("name", MANEUVER_S)
def test_roll_period_from_metacentric_height(name):
    """Released at 5 degrees of heel in still water, the craft rolls with the period
    2 pi sqrt(Ixx / (B h)) of a body of buoyancy B righted at height h above its CG."""
    craft = Craft.load(name)
    volume, h, _, _ = parts(craft)
    buoy = WORLD.water_density_kgm3 * WORLD.gravity_mps2 * volume
    period = 2 * math.pi * math.sqrt(craft.inertia_kgm2[0] / (buoy * h))
    dt = period / 400
    phi0 = math.radians(5.0)
    sim = Simulator(craft, WORLD, dt=dt, integrator="rk4")
    sim.reset(pos=(0.0, 0.0, DEPTH), quat=(math.cos(phi0 / 2), math.sin(phi0 / 2), 0.0, 0.0))
    roll = []
    for _ in range(1000):
        sim.step()
        roll.append(euler(sim)[0][0])
    roll = np.array(roll)
    up = np.flatnonzero((roll[:-1] < 0) & (roll[1:] >= 0))  # upward zero crossings
    t = (up + roll[up] / (roll[up] - roll[up + 1])) * dt
    measured = np.mean(np.diff(t))
    assert measured == pytest.approx(period, rel=0.01)
    # no growth; only the fins' (and sail's) quadratic drag on the rolling motion damps it
    last = np.max(np.abs(roll[-len(roll) // 3 :]))
    assert 0.3 * phi0 < last <= phi0


@pytest.mark.parametrize("name", MANEUVER_S)
def test_top_speed_where_thrust_meets_drag(name):
    """Full thrust, level: the speed settles where thrust = 1/2 rho A_nose v^2 (the hull's
    cross-flow samples feel no axial flow)."""
    craft = Craft.load(name)
    _, _, thrust, area = parts(craft)
    v_top = math.sqrt(2 * thrust / (WORLD.water_density_kgm3 * area))
    sim = Simulator(craft, WORLD, dt=0.02)
    sim.reset(pos=(0.0, 0.0, DEPTH), lin_vel=(0.9 * v_top, 0.0, 0.0))
    controls = np.zeros((1, 3))
    controls[0, 0] = 1.0
    sim.step(controls, steps=int(5 * MANEUVER_S[name] / 0.02))
    assert np.linalg.norm(sim.lin_vel[0, 0]) == pytest.approx(v_top, rel=0.01)
    roll, pitch, heading = euler(sim)
    assert abs(heading[0]) < 1e-6 and abs(roll[0]) < 1e-6


@pytest.mark.parametrize("name", MANEUVER_S)
def test_control_signs(name):
    """At cruising speed, +1 rudder turns the nose right and +1 planes pitch the nose up (far
    more than the slow pitch-up that the slight positive buoyancy gives on its own)."""
    craft = Craft.load(name)
    _, _, thrust, area = parts(craft)
    v = 0.6 * math.sqrt(2 * thrust / (WORLD.water_density_kgm3 * area))
    sim = Simulator(craft, WORLD, num_envs=3, dt=0.02)
    sim.reset(pos=(0.0, 0.0, DEPTH), lin_vel=(v, 0.0, 0.0))
    controls = np.array([[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    prop = craft.thrusters[0]  # a quarter ahead: what the channel's 0 gave before control 0
    lo, hi = prop.min_thrust_n, prop.max_thrust_n  # meant no thrust
    controls[:, craft.control_names.index(prop.control)] = thrust_control((lo + hi) / 2, lo, hi)
    sim.step(controls, steps=int(MANEUVER_S[name] / 0.02))
    roll, pitch, heading = euler(sim)
    assert heading[1] < -math.radians(1) and abs(heading[1]) > 10 * abs(heading[0])
    assert pitch[2] - pitch[0] > math.radians(1) and pitch[2] > 5 * abs(pitch[0])
