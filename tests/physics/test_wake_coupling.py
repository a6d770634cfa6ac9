"""The wake inside the step kernel: fluid samples in the water feel the WakeField's velocity at
their own point, its source moves on during a step, and a Simulator without a wake is
unchanged."""

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Cylinder, Plate, Simulator, WakeField, World

WAKE = WakeField(length_m=20.0, radius_m=2.0, noise=0.3)
WORLD = World(water=True)


def probe():
    """A craft of one plate and one cylinder, far from its center (so that the field differs
    from sample to sample and from the center)."""
    return Craft(
        name="probe",
        mass_kg=50.0,
        inertia_kgm2=(5.0, 5.0, 5.0),
        plates=(Plate("p", (0.5, 0.3, 0.2), (0.3, 0.2, 1.0), 0.05, 0.5),),
        cylinders=(Cylinder("c", (-0.4, -0.3, 0.1), (1.0, 0.2, 0.0), 0.1),),
    )


def sample_points(sim):
    """World points of the probe's two samples [E, 2, 3]."""
    from fluidsim_envs.physics.kernels import quat_matrices

    rot = quat_matrices(np.ascontiguousarray(sim.quat[:, 0]))
    offsets = np.array([[0.5, 0.3, 0.2], [-0.4, -0.3, 0.1]])
    return sim.pos[:, 0, None, :] + np.einsum("eij,sj->esi", rot, offsets)


@pytest.mark.parametrize("where", [(-14.0, 1.0, -0.5), (-30.0, 0.5, 1.0), (0.0, 3.0, 0.0)])
def test_each_sample_feels_the_wake_at_its_point(where):
    """The wrench with a wake equals the sum of each sample's wrench in a uniform current equal
    to the wake velocity at that sample's point (in the vortices, the turbulence, beside the
    hull)."""
    craft = probe()
    sub = dict(
        pos=np.array([1.0, 2.0, -40.0]),
        quat=np.array([np.cos(0.2), 0.0, 0.0, np.sin(0.2)]),
        lin_vel=np.array([2.5 * np.cos(0.4), 2.5 * np.sin(0.4), 0.0]),
        noise_offset=np.array([3.0, -1.0, 7.0]),
    )
    yaw = np.array([[np.cos(0.4), -np.sin(0.4), 0.0], [np.sin(0.4), np.cos(0.4), 0.0], [0, 0, 1]])
    state = dict(
        pos=sub["pos"] + yaw @ np.asarray(where),  # ``where`` is in the submarine's frame
        quat=(0.9, 0.1, -0.2, 0.3),
        lin_vel=(1.0, -0.5, 0.2),
        ang_vel=(0.2, 0.1, -0.3),
    )
    sim = Simulator(craft, WORLD, wake=WAKE)
    sim.set_wake_source(**sub)
    sim.reset(**state)
    force, torque = sim.wrench()

    points = sample_points(sim)[0]
    local = WAKE.velocity(points, sub["pos"], sub["quat"], sub["lin_vel"], sub["noise_offset"])
    assert np.linalg.norm(local, axis=1).min() > 0.01  # the test point is in the field
    parts = []
    for k, only in enumerate(({"cylinders": ()}, {"plates": ()})):
        single = Craft(**{**craft.__dict__, **only})
        ref = Simulator(single, WORLD)
        ref.set_current(local[k])
        ref.reset(**state)
        parts.append(ref.wrench())
    np.testing.assert_allclose(force, parts[0][0] + parts[1][0], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(torque, parts[0][1] + parts[1][1], rtol=1e-12, atol=1e-12)


def test_source_moves_during_a_step():
    """While the bodies step, the source advances at its velocity: a body ahead of a
    submarine that moves toward it feels the same wake as from a source placed where the
    submarine has got to; and ``step(49)`` then ``step()`` is ``step(50)``."""
    craft = probe()
    dt = 0.01
    moving = Simulator(craft, WORLD, num_envs=1, dt=dt, wake=WAKE)
    moving.set_wake_source((0.0, 0.0, -40.0), (1, 0, 0, 0), (2.0, 0.0, 0.0))
    moving.reset(pos=(14.0, 0.5, -40.0))
    moving.step(steps=49)
    # after 49 steps the source sits at x = 0.98; one more step from there
    placed = Simulator(craft, WORLD, num_envs=1, dt=dt, wake=WAKE)
    placed.set_wake_source((2.0 * dt * 49, 0.0, -40.0), (1, 0, 0, 0), (2.0, 0.0, 0.0))
    placed.reset(pos=moving.pos, quat=moving.quat, lin_vel=moving.lin_vel, ang_vel=moving.ang_vel)
    once = Simulator(craft, WORLD, num_envs=1, dt=dt, wake=WAKE)
    once.set_wake_source((0.0, 0.0, -40.0), (1, 0, 0, 0), (2.0, 0.0, 0.0))
    once.reset(pos=(14.0, 0.5, -40.0))
    moving.step()
    placed.step()
    once.step(steps=50)
    np.testing.assert_allclose(moving.lin_vel, placed.lin_vel, rtol=1e-12, atol=1e-15)
    np.testing.assert_array_equal(moving.lin_vel, once.lin_vel)
    assert np.linalg.norm(moving.lin_vel) > 1e-3  # it was pushed


@pytest.mark.parametrize("method, order", [("rk2", 2), ("rk4", 4)])
def test_runge_kutta_keeps_its_order_behind_a_moving_wake(method, order):
    """Each stage sees the wake where its source is at the stage's time: the UUV 4 m off a
    submarine's stern, the source moving at 2 m/s, converges at the method's order (the
    error falls 2^order per halving of dt; against rk4 at dt = 1/800). A source frozen over
    each step made both first order (found by benchmarks/study_env_integrators.py)."""
    uuv = Craft.load("uuv")
    wake = WakeField(noise=0.0)

    def end(m, dt):
        sim = Simulator(uuv, World(water=True), num_envs=1, dt=dt, integrator=m, wake=wake)
        sim.reset(pos=(-25.0, 4.0, -30.0), lin_vel=(2.0, 0.0, 0.0))
        sim.set_wake_source((0.0, 0.0, -30.0), (1, 0, 0, 0), (2.0, 0.0, 0.0))
        sim.step(np.array([[0.6, 0.0, 0.0]]), steps=round(2.0 / dt))
        return sim.pos[0, 0].copy()

    ref = end("rk4", 1 / 800)
    errs = [np.linalg.norm(end(method, dt) - ref) for dt in (1 / 25, 1 / 50)]
    assert errs[1] > 0.0
    assert 2**order * 0.8 < errs[0] / errs[1] < 2**order * 1.25, errs


def test_wake_pushes_only_in_water():
    """A sample in the air feels no wake (the wake is the water's velocity)."""
    sim = Simulator(probe(), WORLD, wake=WAKE)
    sim.set_wake_source((0.0, 0.0, 1.0), (1, 0, 0, 0), (3.0, 0.0, 0.0))
    sim.reset(pos=(-12.0, 0.5, 5.0))
    force, _ = sim.wrench()
    np.testing.assert_array_equal(force, 0.0)


def test_no_wake_is_bit_identical_to_a_switched_off_wake_field():
    """A Simulator with a wake whose parts are all off steps exactly like one without a wake."""
    off = WAKE.replace(displacement=False, vortices=False, noise=0.0)
    sims = [Simulator(probe(), WORLD, num_envs=3, wake=w) for w in (None, off)]
    sims[1].set_wake_source((0.0, 0.0, -40.0), (1, 0, 0, 0), (3.0, 0.0, 0.0))
    for sim in sims:
        sim.reset(pos=(-12.0, 0.5, -39.0), lin_vel=(1.0, 0.2, 0.0), ang_vel=(0.1, 0.2, 0.3))
        sim.step(steps=50)
    np.testing.assert_array_equal(sims[0].pos, sims[1].pos)
    np.testing.assert_array_equal(sims[0].quat, sims[1].quat)


def test_set_wake_source_rejects_bad_input():
    sim = Simulator(probe(), WORLD, num_envs=2, wake=WAKE)
    with pytest.raises(ValueError, match="pos has non-finite"):
        sim.set_wake_source((0.0, np.nan, 0.0), (1, 0, 0, 0), (0, 0, 0))
    with pytest.raises(ValueError, match=r"quat of shape \(3,\) does not broadcast"):
        sim.set_wake_source((0.0, 0.0, 0.0), (1, 0, 0), (0, 0, 0))
    with pytest.raises(ValueError, match="quat must be non-zero"):
        sim.set_wake_source((0.0, 0.0, 0.0), (0, 0, 0, 0), (0, 0, 0))
    with pytest.raises(ValueError, match="env_ids"):
        sim.set_wake_source((0.0, 0.0, 0.0), (1, 0, 0, 0), (0, 0, 0), env_ids=[2])
    with pytest.raises(ValueError, match="has no wake"):
        Simulator(probe(), WORLD).set_wake_source((0, 0, 0), (1, 0, 0, 0), (0, 0, 0))
    with pytest.raises(TypeError, match="wake must be a WakeField"):
        Simulator(probe(), WORLD, wake="strong")
