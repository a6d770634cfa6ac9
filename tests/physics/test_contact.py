"""Contact (physics/contact.py): bounces, rest, stacks, collisions and friction against
closed forms, the tetrahedron's push in closed form, determinism and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, CraftError, Ground, Shape, Simulator, World
from fluidsim_envs.physics import contact as CT
from fluidsim_envs.physics.kernels import INTEGRATORS
from fluidsim_envs.physics.tetra import match_inertia

G = 9.81
ALL_INTEGRATORS = sorted(INTEGRATORS)


def ball(restitution=1.0, friction=0.5, radius=0.1, mass=1.0, name="ball"):
    inertia = 0.4 * mass * radius**2  # a solid sphere
    return Craft(
        name=name,
        mass_kg=mass,
        inertia_kgm2=(inertia,) * 3,
        shapes=[Shape("s", "sphere", radius_m=radius)],
        restitution=restitution,
        friction=friction,
    )


def box(half=(0.25, 0.25, 0.25), mass=2.0, restitution=0.3, friction=0.6, name="box"):
    hx, hy, hz = half
    inertia = mass / 3.0 * np.array([hy**2 + hz**2, hx**2 + hz**2, hx**2 + hy**2])
    return Craft(
        name=name,
        mass_kg=mass,
        inertia_kgm2=tuple(inertia),
        shapes=[Shape("b", "box", half_extents_m=half)],
        restitution=restitution,
        friction=friction,
    )


def apexes(z):
    """The local maxima of a height series (the tops of the bounces)."""
    return np.array([z[j] for j in range(1, len(z) - 1) if z[j - 1] <= z[j] > z[j + 1]])


def drop(craft, ground, dt, seconds, integrator="symplectic_euler", **reset):
    sim = Simulator(craft, World(ground=ground), num_envs=1, dt=dt, integrator=integrator)
    sim.reset(**reset)
    z = np.empty(int(round(seconds / dt)))
    for k in range(z.size):
        sim.step()
        z[k] = sim.pos[0, 0, 2]
    return sim, z


# --------------------------------------------------------------------------------------------
# bounces: the seed's single-body rule, restitution 1 keeps the energy


@pytest.mark.parametrize("integrator", ALL_INTEGRATORS)
@pytest.mark.parametrize("dt", [1 / 120, 1 / 128, 1 / 37])
def test_ball_with_restitution_one_keeps_its_bounce_height(integrator, dt):
    """Restitution 1 on a rigid floor: 20 bounces to the same height (to 1e-9: the issue asks
    for 2%), which is the drop height within the step's sampling of the top (a sample within
    dt/2 of it misses at most g dt^2 / 8). The impact leaves with the speed the ball met the
    surface with, not the speed it reached at its depth below: with the latter, symplectic
    Euler lost 3.4% per bounce at 1/128 s, and rk2 gained 17% over 10 s at 1/256 s
    (docs/study.md, Contact)."""
    _, z = drop(ball(1.0), Ground(restitution=1.0), dt, 20.0, integrator, pos=(0, 0, 1.1))
    tops = apexes(z)[:20] - 0.1  # the ball's bottom
    assert tops.size == 20
    assert np.ptp(tops) < 1e-9, tops
    assert np.abs(tops - 1.0).max() < G * dt**2 / 8, tops


def test_ball_with_restitution_half_loses_three_quarters_of_its_energy():
    """Restitution e: the rebound speed is e times the impact speed, so each bounce's height
    is e^2 = 0.25 of the one before (Newton's experimental law; the first two bounces at
    dt = 1/1000, where the step's sampling of the top costs about 1%)."""
    _, z = drop(ball(0.5), Ground(restitution=0.5), 1e-3, 3.0, pos=(0.0, 0.0, 2.1))
    tops = apexes(z)[:3] - 0.1
    ratios = tops[1:] / tops[:-1]
    np.testing.assert_allclose(ratios, 0.25, rtol=0.015)


def test_restitution_combines_as_the_geometric_mean():
    """A ball of restitution 1 on a ground of 0.25 bounces as 0.5 (sqrt(1 * 0.25))."""
    _, z = drop(ball(1.0), Ground(restitution=0.25), 1e-3, 2.0, pos=(0.0, 0.0, 2.1))
    tops = apexes(z)[:2] - 0.1
    assert abs(tops[1] / tops[0] - 0.25) < 0.01


# --------------------------------------------------------------------------------------------
# rest and stacks


@pytest.mark.parametrize("integrator", ALL_INTEGRATORS)
def test_dropped_box_comes_to_rest_without_jitter_or_sinking(integrator):
    """A box dropped tilted and moving settles on a face within 2 s, and then stays: no
    motion grows, and it neither sinks into the floor nor floats (within gravity's fall in
    one step, g dt^2 = 0.7 mm at 120 Hz), under every integrator (the drift a resting
    contact undoes is the integrator's own: kernels.DRIFT_SHARE)."""
    dt = 1 / 120
    sim = Simulator(
        box((0.2, 0.2, 0.2)), World(ground=Ground()), num_envs=1, dt=dt, integrator=integrator
    )
    q = (math.cos(0.1), 0.6 * math.sin(0.1), 0.8 * math.sin(0.1), 0.0)
    sim.reset(pos=(0.0, 0.0, 0.6), quat=q, lin_vel=(0.5, 0.0, 0.0))
    sim.step(steps=240)
    heights, speeds, spins = [], [], []
    for _ in range(8 * 120):
        sim.step()
        heights.append(sim.pos[0, 0, 2])
        speeds.append(np.linalg.norm(sim.lin_vel[0, 0, :2]))
        spins.append(np.linalg.norm(sim.ang_vel[0, 0]))
    heights = np.array(heights)
    assert np.all(np.abs(heights - 0.2) < G * dt**2 + 1e-4), (heights.min(), heights.max())
    assert heights.max() - heights.min() < 1e-5  # no jitter
    assert max(speeds) < 1e-6 and max(spins) < 1e-6


@pytest.mark.parametrize(
    "offset, integrator",
    [(0.0, "symplectic_euler"), *((0.03, m) for m in ALL_INTEGRATORS)],
)
def test_stack_of_three_boxes_stands_for_ten_seconds(offset, integrator):
    """Three boxes stacked, the middle and top shifted (a real stack is never exact), stand
    for 10 s: none slides more than 5 mm or tips more than 0.5 deg, and all end at rest.
    Under every integrator: undoing a Runge-Kutta step's drift as if it were symplectic
    Euler's lifted each resting box g dt^2 / 2 per step and this stack fell apart."""
    crafts = [box(name=n) for n in "abc"]
    dt = 1 / 120
    sim = Simulator(crafts, World(ground=Ground()), num_envs=1, dt=dt, integrator=integrator)
    start = np.array([[[0.0, 0.0, 0.25], [offset, 0.0, 0.75], [-offset, offset / 2, 1.25]]])
    sim.reset(pos=start)
    worst_tilt = 0.0
    for _ in range(10 * 120):
        sim.step()
        q = sim.quat[0]
        worst_tilt = max(
            worst_tilt, np.degrees(2 * np.arcsin(np.linalg.norm(q[:, 1:3], axis=1))).max()
        )
    moved = sim.pos[0] - start[0]
    assert np.abs(moved[:, :2]).max() < 0.005, moved
    assert np.abs(moved[:, 2]).max() < 0.005, moved[:, 2]
    assert worst_tilt < 0.5
    assert np.abs(sim.lin_vel).max() < 1e-4 and np.abs(sim.ang_vel).max() < 1e-4


@pytest.mark.parametrize("integrator", ["symplectic_euler", "rk2"])
def test_heavy_box_on_light_ones_stands_with_enough_passes(integrator):
    """20 kg on two 1 kg boxes, the hard case for projected Gauss-Seidel: with 4 velocity
    passes at 1/256 s no box moves more than 1 cm in 10 s (docs/study.md, Contact; with one
    pass the light boxes are squeezed out at any dt). Guards the impact's energy bound: one
    lowered by what a push took froze the pressed light box, and this stack fell apart."""
    crafts = [box(name="a", mass=1.0), box(name="b", mass=1.0), box(name="c", mass=20.0)]
    world = World(ground=Ground(), contact_passes=4)
    sim = Simulator(crafts, world, num_envs=1, dt=1 / 256, integrator=integrator)
    start = np.array([[[0.0, 0.0, 0.25], [0.03, 0.0, 0.75], [-0.03, 0.015, 1.25]]])
    sim.reset(pos=start)
    worst = 0.0
    for _ in range(100):
        sim.step(steps=26)
        worst = max(worst, float(np.linalg.norm(sim.pos[0] - start[0], axis=1).max()))
    assert worst < 0.01, worst


# --------------------------------------------------------------------------------------------
# two bodies: momentum kept, energy within the seed's bound


@pytest.mark.parametrize("restitution", [1.0, 0.5, 0.0])
@pytest.mark.parametrize("shape", ["sphere", "box"])
def test_head_on_collision_keeps_momentum_and_bounds_energy(restitution, shape):
    """Two equal bodies meeting head-on in free space: momentum conserved to rounding; the
    velocities after are those of Newton's law of restitution for equal masses,
    v = (1 -+ e) u / 2; kinetic energy after <= before times the bound (1.1)."""
    make = ball if shape == "sphere" else box
    kw = dict(restitution=restitution, friction=0.5)
    crafts = [make(name="a", **kw), make(name="b", **kw)]
    sim = Simulator(crafts, World(gravity_mps2=0.0), num_envs=1, dt=1 / 240)
    gap = 0.25 if shape == "sphere" else 0.55
    sim.reset(
        pos=np.array([[[-gap, 0.0, 0.0], [gap, 0.0, 0.0]]]),
        lin_vel=np.array([[[2.0, 0.0, 0.0], [-2.0, 0.0, 0.0]]]),
    )
    mass = crafts[0].mass_kg
    p0 = mass * sim.lin_vel[0].sum(axis=0)
    e0 = sim.kinetic_energy()[0].sum()
    sim.step(steps=120)
    p1 = mass * sim.lin_vel[0].sum(axis=0)
    e1 = sim.kinetic_energy()[0].sum()
    np.testing.assert_allclose(p1, p0, atol=1e-12)
    assert e1 <= CT.PAIR_ENERGY_BOUND * e0
    # equal masses, head-on: each leaves at -e times its approach speed
    np.testing.assert_allclose(
        sim.lin_vel[0, :, 0], [-2.0 * restitution, 2.0 * restitution], atol=1e-9
    )
    np.testing.assert_allclose(sim.ang_vel[0], 0.0, atol=1e-9)
    # the reported impulse between the pair is each body's change of momentum, m (1 + e) u
    assert sim.pairs.tolist() == [[0, 1]]
    np.testing.assert_allclose(sim.pair_impulse[0], [mass * (1 + restitution) * 2.0], rtol=1e-9)
    assert not sim.ground_impulse.any()


def test_glancing_sphere_collision_keeps_momentum_and_angular_momentum():
    """An off-center hit sets the spheres spinning through friction. Momentum stays what it
    was, to rounding; so does the angular momentum of the impulses, but pushing the
    overlap apart moves the centers (by the overlap, here a step's approach, 1.7 cm) across
    the line of their sliding, which shifts the orbital part: within 5%."""
    crafts = [ball(0.8, 0.4, name="a"), ball(0.8, 0.4, name="b", mass=2.0)]
    sim = Simulator(crafts, World(gravity_mps2=0.0), num_envs=1, dt=1 / 240)
    sim.reset(
        pos=np.array([[[-0.5, 0.05, 0.0], [0.5, -0.05, 0.0]]]),
        lin_vel=np.array([[[3.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]]),
    )
    masses = np.array([1.0, 2.0])

    def momenta():
        p = (masses[:, None] * sim.lin_vel[0]).sum(axis=0)
        orbital = np.cross(sim.pos[0], masses[:, None] * sim.lin_vel[0]).sum(axis=0)
        return p, orbital + sim.angular_momentum()[0].sum(axis=0)

    p0, l0 = momenta()
    sim.step(steps=120)
    p1, l1 = momenta()
    assert np.abs(sim.ang_vel[0]).max() > 0.1  # friction did spin them
    np.testing.assert_allclose(p1, p0, atol=1e-12)
    assert np.linalg.norm(l1 - l0) < 0.05 * np.linalg.norm(l0)


# --------------------------------------------------------------------------------------------
# friction


def test_sliding_box_stops_where_coulomb_friction_says():
    """A box sliding at v on a floor with friction mu decelerates at mu g: it stops after
    v^2 / (2 mu g) (here mu = 0.5, the geometric mean of 0.5 and 0.5)."""
    dt = 1 / 240
    sim = Simulator(box((0.2, 0.2, 0.1), friction=0.5), World(ground=Ground()), 1, dt)
    sim.reset(pos=(0.0, 0.0, 0.1), lin_vel=(3.0, 0.0, 0.0))
    sim.step(steps=480)
    expected = 3.0**2 / (2 * 0.5 * G)
    assert abs(sim.pos[0, 0, 0] / expected - 1.0) < 0.02, sim.pos[0, 0, 0]
    assert abs(sim.lin_vel[0, 0, 0]) < 1e-9


def test_frictionless_box_keeps_sliding():
    sim = Simulator(box(friction=0.0), World(ground=Ground()), num_envs=1, dt=1 / 120)
    sim.reset(pos=(0.0, 0.0, 0.25), lin_vel=(0.5, 0.0, 0.0))
    sim.step(steps=600)
    np.testing.assert_allclose(sim.lin_vel[0, 0], [0.5, 0.0, 0.0], atol=1e-9)


def test_box_on_a_slope_holds_below_the_friction_angle_and_slides_above_it():
    """A box on a 20 deg ramp (a height field) stays put when mu > tan 20 = 0.36, and slides
    down at g (sin - mu cos) when mu < tan 20."""
    slope = math.tan(math.radians(20.0))
    ramp = Ground(heights_m=[[0.0, 40.0 * slope]] * 2, spacing_m=40.0, origin_m=(-20.0, -20.0))
    normal = ramp.normal(0.0, 0.0)
    up = np.array([-math.sin(math.radians(20)), 0.0, math.cos(math.radians(20))])
    np.testing.assert_allclose(normal, up, atol=1e-12)
    angle = math.radians(20.0)
    q = (math.cos(-angle / 2), 0.0, math.sin(-angle / 2), 0.0)  # pitched to lie on the ramp
    for mu, moves in ((0.6, False), (0.2, True)):
        friction = mu**2 / ramp.friction  # so that the geometric mean is mu
        sim = Simulator(box(friction=friction), World(ground=ramp), num_envs=1, dt=1 / 240)
        start = np.array([0.0, 0.0, ramp.height(0.0, 0.0)]) + 0.25 * up
        sim.reset(pos=start, quat=q)
        sim.step(steps=240)
        travelled = np.linalg.norm(sim.pos[0, 0] - start)
        if moves:
            expected = 0.5 * G * (math.sin(angle) - mu * math.cos(angle)) * 1.0**2
            assert abs(travelled / expected - 1.0) < 0.05, (travelled, expected)
        else:
            assert travelled < 2e-3, travelled


# --------------------------------------------------------------------------------------------
# the seed's tetrahedron push, in closed form


def test_contact_moves_a_body_as_its_tetrahedron_pushed_and_restored():
    """The seed's picture: the impulse J a contact gives a body, split over its matched
    tetrahedron's particles by the contact point's barycentric weights (beta_i J) and
    restored by the momentum-keeping fit, changes its momentum by J and its angular momentum
    by r x J. Here a ball strikes a box off-center (no gravity, no friction, so J lies along
    the face normal and the lever arm's part along it does not matter): the box's change of
    momentum and angular momentum from the simulator equals the particles' sums."""
    crate = box(half=(0.3, 0.2, 0.25), restitution=0.6, friction=0.0, name="crate")
    shot = ball(0.6, 0.0, radius=0.1, mass=0.5, name="shot")
    sim = Simulator([crate, shot], World(gravity_mps2=0.0), num_envs=1, dt=1 / 240)
    sim.reset(
        pos=np.array([[[0.0, 0.0, 0.0], [0.5, 0.12, 0.08]]]),
        lin_vel=np.array([[[0.0, 0.0, 0.0], [-3.0, 0.0, 0.0]]]),
    )
    sim.step(steps=60)
    momentum = crate.mass_kg * sim.lin_vel[0, 0]
    spin = sim.angular_momentum()[0, 0]
    impulse = -shot.mass_kg * (sim.lin_vel[0, 1] - np.array([-3.0, 0.0, 0.0]))
    assert impulse[0] < -1.0 and np.abs(impulse[1:]).max() < 1e-12  # along the face normal
    # the particles of the box (unturned: the hit is along x, the turn small), and the
    # barycentric weights of the point the ball touched, on the face x = 0.3
    positions, _ = match_inertia(crate.mass_kg, crate.inertia_tensor)
    point = np.array([0.3, 0.12, 0.08])
    beta = np.linalg.solve(np.vstack([positions.T, np.ones(4)]), np.append(point, 1.0))
    kicks = beta[:, None] * impulse
    np.testing.assert_allclose(momentum, kicks.sum(axis=0), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(spin, np.cross(positions, kicks).sum(axis=0), rtol=1e-9, atol=1e-12)


# --------------------------------------------------------------------------------------------
# determinism, ground API, bad input


def test_same_result_for_any_batch_size_and_thread_count():
    """Environment k's trajectory is bit-identical alone, in a batch of 130, serial or on
    threads (the warm starts are per environment)."""
    rng = np.random.default_rng(5)
    starts = np.zeros((130, 2, 3))
    starts[:, 0] = [0.0, 0.0, 0.3]
    starts[:, 1, :2] = rng.uniform(-0.05, 0.05, (130, 2))
    starts[:, 1, 2] = rng.uniform(0.8, 1.2, 130)
    crafts = [box(name="a"), ball(0.7, name="b", radius=0.2)]

    def run(ids, parallel):
        sim = Simulator(crafts, World(ground=Ground()), len(ids), 1 / 120, parallel=parallel)
        sim.reset(pos=starts[ids])
        sim.step(steps=150)
        return sim.pos.copy(), sim.quat.copy()

    ids = np.arange(130)
    whole, whole_q = run(ids, parallel=True)
    serial, serial_q = run(ids, parallel=False)
    np.testing.assert_array_equal(whole, serial)
    np.testing.assert_array_equal(whole_q, serial_q)
    for k in (0, 77, 129):
        alone, alone_q = run(np.array([k]), parallel=False)
        np.testing.assert_array_equal(alone[0], whole[k])
        np.testing.assert_array_equal(alone_q[0], whole_q[k])


def test_reset_forgets_the_warm_start():
    """Resetting an environment gives the trajectory of a fresh simulator."""
    crafts = [box(name="a"), box(name="b")]
    start = np.array([[[0.0, 0.0, 0.25], [0.02, 0.0, 0.75]]])
    sim = Simulator(crafts, World(ground=Ground()), num_envs=1, dt=1 / 120)
    sim.reset(pos=start)
    sim.step(steps=50)
    sim.reset(pos=start)
    sim.step(steps=20)
    fresh = Simulator(crafts, World(ground=Ground()), num_envs=1, dt=1 / 120)
    fresh.reset(pos=start)
    fresh.step(steps=20)
    np.testing.assert_array_equal(sim.pos, fresh.pos)


def test_height_field_is_bilinear_and_flat_beyond_its_edges():
    field = Ground(height_m=1.0, heights_m=[[0.0, 2.0], [4.0, 6.0]], spacing_m=2.0)
    np.testing.assert_allclose(field.height([1.0, 0.0, 2.0], [1.0, 2.0, 0.0]), [4.0, 5.0, 3.0])
    np.testing.assert_allclose(field.height([-5.0, 9.0], [-5.0, 9.0]), [1.0, 7.0])
    n = field.normal(1.0, 1.0)  # slope (1, 2): normal (-1, -2, 1) / sqrt(6)
    np.testing.assert_allclose(n, np.array([-1.0, -2.0, 1.0]) / math.sqrt(6.0))
    np.testing.assert_allclose(field.normal(-5.0, -5.0), [0.0, 0.0, 1.0])


def test_bodies_without_shapes_pass_through_everything():
    plain = Craft(name="plain", mass_kg=1.0, inertia_kgm2=(0.1, 0.1, 0.1))
    sim = Simulator(plain, World(ground=Ground()), num_envs=1, dt=0.01)
    sim.reset(pos=(0.0, 0.0, 0.5))
    sim.step(steps=100)
    assert sim.pos[0, 0, 2] < -4.0


@pytest.mark.parametrize(
    "spec, message",
    [
        (
            dict(name="s", kind="sphere", radius_m=-0.1),
            "radius_m must be a finite number > 0, got -0.1",
        ),
        (dict(name="s", kind="sphere", radius_m=0.0), "radius_m must be a finite number > 0"),
        (dict(name="b", kind="box", half_extents_m=(0.1, -0.2, 0.1)), "half_extents_m\\[1\\]"),
        (dict(name="b", kind="box", radius_m=0.1), "kind 'box' needs half_extents_m"),
        (dict(name="c", kind="cone", radius_m=0.1), "kind must be 'sphere' or 'box'"),
    ],
)
def test_bad_shapes_are_refused_naming_the_value(spec, message):
    with pytest.raises(CraftError, match=message):
        Craft(name="x", mass_kg=1.0, inertia_kgm2=(1, 1, 1), shapes=[spec])


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(restitution=1.5), "restitution must be in \\[0, 1\\]"),
        (dict(friction=-0.1), "friction must be >= 0"),
    ],
)
def test_bad_craft_materials_are_refused(kwargs, message):
    with pytest.raises(CraftError, match=message):
        Craft(name="x", mass_kg=1.0, inertia_kgm2=(1, 1, 1), **kwargs)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(heights_m=[[0.0, 1.0]]), "ny, nx >= 2"),
        (dict(heights_m=[[0.0, float("nan")], [0.0, 0.0]]), "non-finite"),
        (dict(heights_m=[[0.0, 1.0], [0.0, 1.0]], spacing_m=0.0), "spacing_m must be .* > 0"),
        (dict(restitution=-0.5), "restitution must be a finite number in \\[0, 1\\]"),
        (dict(origin_m=(0.0,)), "origin_m must be a list of 2 numbers"),
    ],
)
def test_bad_grounds_are_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        Ground(**kwargs)


def test_bad_world_contact_options_are_refused():
    with pytest.raises(ValueError, match="contact_passes must be an integer >= 1, got 0"):
        World(contact_passes=0)
    with pytest.raises(ValueError, match="ground must be a Ground or None"):
        World(ground=0.0)


def test_shapes_load_from_toml(tmp_path):
    path = tmp_path / "crate.toml"
    path.write_text(
        'name = "crate"\nmass_kg = 2.0\ninertia_kgm2 = [0.1, 0.1, 0.1]\nrestitution = 0.2\n'
        '[[shapes]]\nname = "hull"\nkind = "box"\nhalf_extents_m = [0.2, 0.2, 0.2]\n'
        '[[shapes]]\nname = "nose"\nkind = "sphere"\nradius_m = 0.1\ncenter_m = [0.3, 0, 0]\n'
    )
    crate = Craft.load(path)
    assert [s.kind for s in crate.shapes] == ["box", "sphere"]
    assert crate.restitution == 0.2 and crate.friction == 0.5
    moved = crate.with_center_of_mass((0.1, 0.0, 0.0))
    assert moved.shapes[1].center_m == pytest.approx((0.2, 0.0, 0.0), abs=1e-16)  # 0.3 - 0.1
