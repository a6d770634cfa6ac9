"""Flight qualities of the shipped paper dart (issue 4): trim glide, phugoid, static stability
on both sides of the neutral point, control signs, and finite forces from any attitude.

Expected values come from the craft's own forces (``Simulator.wrench``), from the formula
named in each test, or from what the docs publish (docs/dart_glide.csv, which
``python -m benchmarks.dart_glide`` writes); nothing is a tuned constant of the test."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from benchmarks import dart_glide as ref
from fluidsim_envs.physics import Craft, Simulator, World
from fluidsim_envs.physics.kernels import quat_matrices

DT = 1 / 240  # the env's default physics step
G = 9.81


@pytest.fixture(scope="module")
def craft():
    return Craft.load("paper_airplane")


@pytest.fixture(scope="module")
def trimmed(craft):
    """30 s of :func:`glide` from the default launch: the trimmed glide (not to be stepped)."""
    return glide(craft, 30.0)


def body_rates(sim):
    """Angular velocity in the body frame [E, 3]: p (roll, + right wing down), q (+ nose
    down: y points left), r (+ nose left)."""
    rot = quat_matrices(np.ascontiguousarray(sim.quat[:, 0]))
    return np.einsum("eji,ej->ei", rot, sim.ang_vel[:, 0])


def pitch_deg(quat):
    """Nose-up angle of the body x axis above the horizon [E]."""
    w, x, y, z = np.moveaxis(quat, -1, 0)
    return np.degrees(np.arcsin(np.clip(2 * (x * z - w * y), -1, 1)))


def glide(craft, seconds, v0=6.0, **reset):
    """Fly with zero controls from a level launch; sample every 1/24 s."""
    sim = Simulator(craft, World(), num_envs=1, dt=DT)
    sim.reset(pos=(0.0, 0.0, 1000.0), lin_vel=(v0, 0.0, 0.0), **reset)
    t, rows = [], []
    for k in range(int(seconds * 24)):
        sim.step(steps=10)
        v = sim.lin_vel[0, 0]
        t.append((k + 1) / 24)
        rows.append((np.linalg.norm(v), math.atan2(-v[2], math.hypot(v[0], v[1]))))
    return sim, np.array(t), np.array(rows)


def test_geometry_is_a_folded_a4_dart(craft):
    """A few grams and 0.015-0.025 m^2 of wing (issue 4), the seed's list of samples."""
    assert 0.002 <= craft.mass_kg <= 0.01
    wing = sum(p.area_m2 for p in craft.plates if p.name.endswith("wing"))
    assert 0.015 <= wing <= 0.025
    names = {s.name for s in (*craft.plates, *craft.cylinders)}
    for part in ("left_wing", "right_wing", "fuselage_front", "fuselage_rear", "fin",
                 "left_stabilizer", "right_stabilizer", "left_aileron", "right_aileron",
                 "rudder", "left_elevator", "right_elevator"):  # fmt: skip
        assert part in names
    assert craft.control_names == ("aileron", "elevator", "rudder")


def test_trimmed_glide_at_the_force_balance(craft, trimmed):
    """Zero controls from a level launch: the pitch oscillation dies out and speed and glide
    angle become constant. In a steady glide lift and drag balance weight, so the glide
    angle is atan(D/L) (e.g. Anderson, Introduction to Flight, 6.7), with L and D the aero
    force across and along the flight path. Trim speed and glide ratio stay within 5% of
    what docs/environments.md publishes (from docs/dart_glide.csv)."""
    sim, t, rows = trimmed
    speed, gamma = rows[:, 0], rows[:, 1]
    late = t > 25.0
    assert np.ptp(speed[late]) < 1e-3 * speed[-1]
    assert np.ptp(gamma[late]) < 1e-4
    early = (t > 1.0) & (t < 6.0)
    assert np.ptp(speed[early]) > 100 * np.ptp(speed[late])  # there was an oscillation
    assert abs(body_rates(sim)[0, 1]) < 1e-4

    force, torque = sim.wrench()
    v = sim.lin_vel[0, 0] / np.linalg.norm(sim.lin_vel[0, 0])
    drag = -force[0, 0] @ v
    lift = np.linalg.norm(force[0, 0] - (force[0, 0] @ v) * v)
    assert gamma[-1] == pytest.approx(math.atan2(drag, lift), abs=1e-4)
    assert np.linalg.norm(force[0, 0]) == pytest.approx(craft.mass_kg * G, rel=1e-3)
    assert np.abs(torque[0, 0]).max() < 1e-6
    published = ref.published()
    assert speed[-1] == pytest.approx(published[("trim_speed", "measured")], rel=0.05)
    assert lift / drag == pytest.approx(published[("glide_ratio", "measured")], rel=0.05)


def test_phugoid_matches_the_approximations_with_drag(craft, trimmed):
    """The phugoid after a level launch 1 m/s below trim speed V: period and damping ratio
    from the speed's peaks (``benchmarks.dart_glide.phugoid_of``), against

    - the point-mass phugoid with drag in the glide: Etkin & Reid's longitudinal
      small-perturbation equations (Dynamics of Flight: Stability and Control, 3rd ed.,
      ch. 4) at constant angle of attack, about a flight path tilted down by the glide
      angle gamma = atan(C_D/C_L): omega_n = sqrt(2) g / V, zeta = 3 sin(gamma) / (2 sqrt(2))
      (``benchmarks.dart_glide.glide_with_drag``). Measured: period 5.1% longer, damping
      9.9% lower; allowed 6% and 12%.
    - Etkin & Reid's phugoid approximation with drag (ch. 6; level flight, thrust
      independent of speed): omega_n = sqrt(2) g / V, zeta = C_D / (sqrt(2) C_L). Measured:
      period 6.8% longer; allowed 8%. (Its damping ratio is 24% low: in a glide gravity,
      not a constant thrust, balances drag. Lanchester's drag-free period is 8.3% short.)
    - the craft's own longitudinal equations linearized about the trim (derivatives from
      its forces, ``benchmarks.dart_glide.linearized_phugoid``): measured 0.03% and 1.5%
      off (the 1.5% is symplectic Euler's: with rk4 at the same dt, 0.02%); allowed 0.5%
      and 3%. So what the approximations miss is their own: the coupling with the short
      period (the angle-of-attack freedom they drop).

    C_D/C_L is the trim's drag over lift from the craft's forces. The issue's ceiling for an
    approximation with drag is 10%."""
    sim, _, rows = trimmed
    v_trim = rows[-1, 0]
    lift, drag = ref.lift_and_drag(sim)
    _, t, rows = glide(craft, 12.0, v0=v_trim - 1.0)
    period, zeta, peaks = ref.phugoid_of(t, rows[:, 0], v_trim)
    assert peaks >= 3

    glide_period, glide_zeta = ref.glide_with_drag(v_trim, G, drag / lift)
    assert abs(glide_period / period - 1) < 0.06
    assert abs(glide_zeta / zeta - 1) < 0.12
    er_period, _ = ref.etkin_reid(v_trim, G, drag / lift)
    assert abs(er_period / period - 1) < 0.08
    lin_period, lin_zeta = ref.linearized_phugoid(craft, World(), sim)
    assert abs(lin_period / period - 1) < 0.005
    assert abs(lin_zeta / zeta - 1) < 0.03


def pitch_moment_slope(craft, speed, alphas):
    """Nose-up moment about the CG against angle of attack, from the craft's own forces."""
    sim = Simulator(craft, World(), num_envs=len(alphas))
    half = -alphas / 2  # nose up = rotation about -y
    sim.reset(
        pos=(0.0, 0.0, 10.0),
        quat=np.stack([np.cos(half), 0 * half, np.sin(half), 0 * half], 1)[:, None],
        lin_vel=(speed, 0.0, 0.0),
    )
    _, torque = sim.wrench()
    moment = -torque[:, 0, 1]
    return np.polyfit(alphas, moment, 1)[0], moment


def pivot_rig(craft):
    """A wind-tunnel pitch rig: the body turns freely about its CG but cannot translate
    (huge mass, inertia kept, no gravity); air blows from ahead at 6 m/s."""
    rig = Craft(
        name="rig",
        mass_kg=1e9,
        inertia_kgm2=craft.inertia_kgm2,
        plates=craft.plates,
        cylinders=craft.cylinders,
    )
    return rig


@pytest.mark.parametrize("side", ["ahead", "behind"])
def test_pitch_stability_flips_at_the_neutral_point(craft, side):
    """The neutral point is the CG position where dM/dalpha = 0 (Etkin & Reid, 2.3); it is
    found here from the craft's own moment slope, which is linear in the CG position. With
    the CG 10 mm ahead of it a pitch disturbance on the pitch rig dies out; 10 mm behind it
    the same disturbance grows (static instability)."""
    alphas = np.radians(np.linspace(-3.0, 3.0, 7))
    s0, _ = pitch_moment_slope(craft, 6.0, alphas)
    s1, _ = pitch_moment_slope(craft.with_center_of_mass((-0.01, 0.0, 0.0)), 6.0, alphas)
    assert s0 < 0  # the shipped dart is statically stable
    x_np = -0.01 * s0 / (s0 - s1)  # CG shift (m, forward +) at which the slope vanishes
    assert -0.08 < x_np < -0.005  # behind the CG, within the airframe
    shifted = craft.with_center_of_mass((x_np + (0.01 if side == "ahead" else -0.01), 0, 0))
    slope, _ = pitch_moment_slope(shifted, 6.0, np.radians(np.linspace(-3.0, 3.0, 7)))
    assert (slope < 0) == (side == "ahead")

    # equilibrium angle: the zero of the moment curve; disturb it by 1 degree
    alphas = np.radians(np.linspace(-30, 30, 601))
    _, moment = pitch_moment_slope(shifted, 6.0, alphas)
    k = np.flatnonzero(np.diff(np.sign(moment)))[0]
    a_eq = alphas[k] - moment[k] * (alphas[k + 1] - alphas[k]) / (moment[k + 1] - moment[k])
    sim = Simulator(pivot_rig(shifted), World(gravity_mps2=0.0), num_envs=1, dt=DT)
    sim.set_wind((-6.0, 0.0, 0.0))
    a0 = a_eq + math.radians(1.0)
    sim.reset(quat=(math.cos(-a0 / 2), 0.0, math.sin(-a0 / 2), 0.0))
    history = []
    for _ in range(240):
        sim.step(steps=2)
        history.append(pitch_deg(sim.quat[0, 0]) - math.degrees(a_eq))
    history = np.abs(np.array(history))
    if side == "ahead":
        assert history[-60:].max() < 0.1  # damped back to equilibrium within 2 s
    else:
        assert history.max() > 10.0  # diverged away from equilibrium


@pytest.mark.parametrize(
    ("channel", "axis", "sign", "what"),
    [
        (1, 1, -1, "up elevator pitches the nose up"),
        (0, 0, +1, "right aileron rolls right"),
        (2, 2, -1, "right rudder yaws the nose right"),
    ],
)
def test_controls_do_what_a_pilot_expects(craft, channel, axis, sign, what):
    """From the trimmed glide, half deflection for 0.2 s turns the body the pilot's way
    (body rates: p + right wing down, q + nose down, r + nose left)."""
    sim, _, rows = glide(craft, 20.0)
    controls = np.zeros((1, 3))
    controls[0, channel] = 0.5
    before = body_rates(sim)[0, axis]
    sim.step(controls, steps=48)
    assert sign * (body_rates(sim)[0, axis] - before) > 0.3, what


@settings(max_examples=25)
@given(
    quat=arrays(np.float64, (32, 4), elements=st.floats(-1, 1)),
    rates=arrays(np.float64, (32, 3), elements=st.floats(-60, 60)),
    vel=arrays(np.float64, (32, 3), elements=st.floats(-40, 40)),
    controls=arrays(np.float64, (32, 3), elements=st.floats(-1, 1)),
)
def test_any_attitude_rate_and_speed_stays_finite(craft, quat, rates, vel, controls):
    """Inverted, stalled, tail-sliding, tumbling: from random attitudes, rates up to 60 rad/s
    and speeds up to 70 m/s, forces stay finite and within the head-on plate bound, and 2 s
    of flight at the env's default dt stay finite."""
    quat[np.linalg.norm(quat, axis=1) < 1e-3] = (1.0, 0.0, 0.0, 0.0)
    sim = Simulator(craft, World(), num_envs=32, dt=DT)
    sim.reset(pos=(0, 0, 100), quat=quat[:, None], lin_vel=vel[:, None], ang_vel=rates[:, None])
    force, torque = sim.wrench(controls)
    assert np.isfinite(force).all() and np.isfinite(torque).all()
    # no sample can push harder than a plate of all the area head-on at the fastest point
    reach = max(np.linalg.norm(s.offset_m) for s in (*craft.plates, *craft.cylinders))
    area = sum(s.area_m2 for s in (*craft.plates, *craft.cylinders))
    fastest = np.linalg.norm(vel, axis=1) + np.linalg.norm(rates, axis=1) * reach
    bound = 0.5 * World().air_density_kgm3 * area * fastest**2
    assert (np.linalg.norm(force[:, 0], axis=1) <= bound * (1 + 1e-9) + 1e-12).all()
    sim.step(controls, steps=480)
    assert not sim.diverged.any()
    assert np.isfinite(sim.pos).all() and np.isfinite(sim.ang_vel).all()
    assert np.abs(sim.ang_vel).max() < 200.0
