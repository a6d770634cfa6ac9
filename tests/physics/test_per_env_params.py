"""Per-environment physical parameters (``Simulator.set_mass_properties``,
``set_sample_scale``, ``set_thrust_scale``) are physics, not bookkeeping: each is checked
against a closed form or against the same craft built whole."""

import numba
import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Ground, Simulator, World

BOX = Craft(name="box", mass_kg=2.0, inertia_kgm2=(0.3, 0.4, 0.5))


def _fly(sim, steps=60, seed=0):
    rng = np.random.default_rng(seed)
    sim.reset(
        pos=(0.0, 0.0, 6.0),
        quat=np.array([1.0, 0.0, 0.0, 0.0]) + rng.normal(0, 0.05, (sim.num_envs, 1, 4)),
        lin_vel=(5.0, 0.0, -0.5),
        ang_vel=rng.normal(0, 0.5, (sim.num_envs, 1, 3)),
    )
    out = []
    for _ in range(steps // 4):
        ctrl = rng.uniform(-1, 1, (sim.num_envs, len(sim.control_names)))
        sim.step(ctrl if ctrl.shape[1] else None, steps=4)
        out.append(np.concatenate([sim.pos, sim.quat, sim.lin_vel, sim.ang_vel], -1))
    return np.stack(out)


def test_twice_the_mass_accelerates_half_as_fast():
    # Newton's second law, a = F / m: the same force on 2 kg and on 4 kg, no gravity
    sim = Simulator(BOX, World(gravity_mps2=0.0), num_envs=2, dt=0.01)
    sim.set_mass_properties(mass_kg=4.0, env_ids=[1])
    sim.set_external_force((3.0, 0.0, -1.0))
    sim.reset()
    sim.step(steps=50)
    v = sim.lin_vel[:, 0]
    assert np.allclose(v[0], np.array([3.0, 0.0, -1.0]) / 2.0 * 0.5, rtol=1e-12)
    # the ratio is exact: both velocities are the same sums of F dt / m
    np.testing.assert_array_equal(v[1] * 2.0, v[0])
    np.testing.assert_array_equal(sim.mass_kg[:, 0], [2.0, 4.0])


def test_inertia_sets_the_spin_rate_and_keeps_angular_momentum():
    # w = I^-1 L for a body at rest orientation; L is the state and stays exact
    sim = Simulator(BOX, World(gravity_mps2=0.0), num_envs=2, dt=0.01)
    sim.set_mass_properties(inertia_kgm2=(0.6, 0.8, 1.0), env_ids=[1])
    sim.reset(ang_vel=(0.0, 0.0, 2.0))  # L = I w with each environment's own inertia
    np.testing.assert_allclose(sim.angular_momentum()[:, 0, 2], [1.0, 2.0], rtol=1e-15)
    np.testing.assert_allclose(sim.ang_vel[:, 0, 2], [2.0, 2.0], rtol=1e-15)
    sim.step(steps=100)
    np.testing.assert_allclose(sim.angular_momentum()[:, 0, 2], [1.0, 2.0], rtol=1e-15)
    np.testing.assert_allclose(sim.ang_vel[:, 0, 2], [2.0, 2.0], rtol=1e-12)


@pytest.mark.parametrize("integrator", ["symplectic_euler", "rk2", "verlet_tetra"])
def test_center_of_mass_shift_is_with_center_of_mass_bit_for_bit(integrator):
    dart = Craft.load("paper_airplane")
    shift = (-0.011, 0.002, 0.003)
    world = World(ground=Ground())
    sim = Simulator(dart, world, num_envs=3, dt=1 / 120, integrator=integrator)
    sim.set_mass_properties(center_of_mass_m=shift, env_ids=[1])
    moved = Simulator(dart.with_center_of_mass(shift), world, 3, 1 / 120, integrator)
    nominal = Simulator(dart, world, 3, 1 / 120, integrator)
    a, b, c = _fly(sim, 240), _fly(moved, 240), _fly(nominal, 240)
    assert np.all(np.isfinite(a))
    np.testing.assert_array_equal(a[:, 1], b[:, 1])
    np.testing.assert_array_equal(a[:, [0, 2]], c[:, [0, 2]])
    assert not np.array_equal(a[:, 1], c[:, 1])


def test_values_set_to_the_crafts_own_run_bit_identically():
    dart = Craft.load("paper_airplane")
    sim = Simulator(dart, World(), num_envs=70, dt=1 / 120, integrator="rk2")
    sim.set_mass_properties(dart.mass_kg, dart.inertia_tensor, (0.0, 0.0, 0.0))
    sim.set_sample_scale("all", area=1.0, efficiency=1.0)
    ref = Simulator(dart, World(), num_envs=70, dt=1 / 120, integrator="rk2")
    np.testing.assert_array_equal(_fly(sim), _fly(ref))


def test_one_environment_changed_leaves_its_neighbours_alone():
    dart = Craft.load("paper_airplane")
    sim = Simulator(dart, World(), num_envs=70, dt=1 / 120, integrator="rk2")
    sim.set_mass_properties(mass_kg=dart.mass_kg * 1.3, env_ids=[64])
    sim.set_sample_scale("control_surfaces", area=0.5, env_ids=[5])
    ref = Simulator(dart, World(), num_envs=70, dt=1 / 120, integrator="rk2")
    a, b = _fly(sim), _fly(ref)
    others = [e for e in range(70) if e not in (5, 64)]
    np.testing.assert_array_equal(a[:, others], b[:, others])
    assert not np.array_equal(a[:, 5], b[:, 5]) and not np.array_equal(a[:, 64], b[:, 64])


def _trim(sim, seconds=30.0):
    """Speed and glide angle (rad) of each environment's steady glide, averaged over the
    last 5 s of a hands-off flight from a level launch."""
    sim.reset(pos=(0.0, 0.0, 500.0), lin_vel=(6.0, 0.0, 0.0))
    speed, angle = [], []
    steps = int(seconds * 120) // 4
    for k in range(steps):
        sim.step(np.zeros((sim.num_envs, 3)), steps=4)
        if k >= steps - 150:
            v = sim.lin_vel[:, 0]
            speed.append(np.linalg.norm(v, axis=1))
            angle.append(np.arctan2(-v[:, 2], np.hypot(v[:, 0], v[:, 1])))
    return np.mean(speed, 0), np.mean(angle, 0)


def test_sample_areas_scaled_by_s_glide_at_trim_speed_over_sqrt_s():
    # steady glide: every aerodynamic force is 1/2 rho s A v^2 times a function of the
    # attitude, so s A v^2 is the same at the same attitude: v ~ 1/sqrt(s), same glide angle
    dart = Craft.load("paper_airplane")
    sim = Simulator(dart, World(), num_envs=3, dt=1 / 120, integrator="rk2")
    s = np.array([1.0, 2.0, 0.6])
    sim.set_sample_scale("all", area=s)
    speed, angle = _trim(sim)
    assert 3.0 < speed[0] < 15.0 and 0.05 < angle[0] < 0.6
    # measured: speed ratios within 2.4e-6 of 1/sqrt(s), angles within 2.4e-6 rad after a
    # 30 s glide (the phugoid's remains: it decays at a rate that depends on s)
    np.testing.assert_allclose(speed / speed[0], 1.0 / np.sqrt(s), rtol=1e-5)
    np.testing.assert_allclose(angle, angle[0], atol=1e-5)


def test_thrust_scale_scales_every_thruster_force():
    boat = Craft.load("speedboat")
    sim = Simulator(boat, World(water=True), num_envs=2, dt=0.01)
    sim.set_thrust_scale(0.5, env_ids=[1])
    ctrl = np.tile([0.7, 0.0, 0.0], (2, 1))
    prop = [i for i, n in enumerate(_names(boat)) if n == "prop"]
    f0 = sim.sample_forces(ctrl, env_index=0)[1][prop]
    f1 = sim.sample_forces(ctrl, env_index=1)[1][prop]
    np.testing.assert_allclose(f1, 0.5 * f0, rtol=1e-15)


def _names(craft):
    flaps = {s.sample for c in craft.controls for s in c.surfaces}
    plates = [p.name for p in craft.plates]
    return (
        [n for n in plates if n not in flaps]
        + [n for n in plates if n in flaps]
        + [s.name for s in craft.cylinders]
        + [s.name for s in craft.buoyancy]
        + [t.name for t in craft.thrusters]
    )


def test_efficiency_scale_of_one_sample_by_name():
    dart = Craft.load("paper_airplane")
    sim = Simulator(dart, World(), num_envs=2, dt=1 / 120)
    sim.reset(lin_vel=(6.0, 0.0, -1.0))
    name = dart.plates[0].name
    j = _names(dart).index(name)
    before = sim.sample_forces(env_index=1)[1][j]
    sim.set_sample_scale(name, efficiency=0.0, env_ids=[1])
    after = sim.sample_forces(env_index=1)[1][j]
    v = sim.lin_vel[1, 0] / np.linalg.norm(sim.lin_vel[1, 0])
    # efficiency removes the force's component along the flow; at 0 it is all there
    assert abs(after @ v) > abs(before @ v)
    np.testing.assert_allclose(np.cross(after, dart.plates[0].normal), 0.0, atol=1e-12)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda s: s.set_mass_properties(mass_kg=-1.0), "mass_kg must be positive"),
        (lambda s: s.set_mass_properties(mass_kg=np.nan), "non-finite"),
        (lambda s: s.set_mass_properties(inertia_kgm2=(1.0, 1.0, 3.0)), "triangle"),
        (lambda s: s.set_mass_properties(inertia_kgm2=(1.0, -1.0, 1.0)), "positive definite"),
        (lambda s: s.set_mass_properties(center_of_mass_m=(0, 0)), "does not broadcast"),
        (lambda s: s.set_mass_properties(mass_kg=1.0, body=1), "body 1 is not in"),
        (lambda s: s.set_mass_properties(mass_kg=1.0, env_ids=[5]), "env_ids"),
        (lambda s: s.set_sample_scale("wing", area=2.0), "unknown group 'wing'"),
        (lambda s: s.set_sample_scale("all", area=0.0), "positive factor"),
        (lambda s: s.set_sample_scale("all", efficiency=5.0), "outside \\[0, 1\\]"),
        (lambda s: s.set_thrust_scale(2.0), "no thruster"),
    ],
)
def test_bad_values_raise_naming_them(call, message):
    sim = Simulator(Craft.load("paper_airplane"), World(), num_envs=2)
    with pytest.raises(ValueError, match=message):
        call(sim)


def test_a_snapshot_carries_each_environments_craft():
    """Simulator.get_state holds each environment's mass properties and sample factors with
    its state: an environment restored into another Simulator (whose environments were scaled
    otherwise) then steps bit for bit as the original."""
    dart = Craft.load("paper_airplane")
    src = Simulator(dart, World(ground=Ground()), num_envs=3, dt=1 / 120)
    src.set_mass_properties(mass_kg=[0.004, 0.006, 0.005], center_of_mass_m=(0.01, 0.0, 0.0))
    src.set_sample_scale("control_surfaces", area=[1.0, 1.3, 0.8], efficiency=[1.0, 0.9, 0.7])
    src.reset(pos=(0.0, 0.0, 3.0), lin_vel=(6.0, 0.0, 0.0))
    src.step(steps=7)
    state = src.get_state([1])
    dst = Simulator(dart, World(ground=Ground()), num_envs=2, dt=1 / 120)
    dst.set_sample_scale("all", area=0.5, env_ids=[1])
    dst.set_state({k: np.repeat(v, 2, axis=0) for k, v in state.items()})
    np.testing.assert_array_equal(dst.mass_kg[:, 0], [0.006, 0.006])
    ctrl = np.array([[0.3, -0.5, 0.2]])
    for _ in range(40):
        src.step(np.repeat(ctrl, 3, axis=0), steps=2)
        dst.step(np.repeat(ctrl, 2, axis=0), steps=2)
    for e in (0, 1):
        np.testing.assert_array_equal(dst.pos[e], src.pos[1])
        np.testing.assert_array_equal(dst.quat[e], src.quat[1])
    assert not np.array_equal(src.pos[0], src.pos[1])  # the environments did differ


def test_a_single_environment_takes_its_own_mass_properties():
    """One environment is a batch of one: its body rows are its own, writable arrays (they
    were a read-only broadcast at E = 1, which refused this call and made numba compile every
    kernel a second time, for a read-only array type); a Ground's height grid is copied
    writable likewise (the Ground keeps its own read-only)."""
    craft = Craft.load("paper_airplane")
    one = Simulator(craft, World(), num_envs=1)
    one.set_mass_properties(mass_kg=0.006)
    assert one.mass_kg[0, 0] == 0.006
    many = Simulator(craft, World(ground=Ground()), num_envs=3)  # a ground's grid, too
    for field in ("body", "shape", "contact_body", "grid"):
        a, b = getattr(one._model, field), getattr(many._model, field)
        assert a.flags.writeable and numba.typeof(a) == numba.typeof(b), field


@pytest.mark.parametrize(
    "craft, groups",
    [
        ("paper_airplane", ("wings", "tail", "fuselage")),
        ("speedboat", ("bottom", "friction", "topsides")),
        ("uuv", ("control_surfaces",)),
    ],
)
def test_a_randomizer_writes_what_the_checked_setters_write(craft, groups):
    """Simulator.randomizer (a v1 scene's reset, physics/randomizer.py) skips the setters'
    per-call checks: the environments it writes hold the same craft, bit for bit, as the
    checked calls give (a sample in several of the groups takes the last one's, as it does
    through set_sample_scale in turn), and the neighbours it does not write keep theirs."""
    craft = Craft.load(craft)
    rng = np.random.default_rng(3)
    ids, G = np.array([0, 2]), len(groups)
    mass, inertia, density = rng.uniform(0.7, 1.3, (3, 2))
    shift, area, eff = rng.uniform(-0.01, 0.01, (2, 3)), *rng.uniform(0.6, 1.0, (2, 2, G))
    thrust = rng.uniform(0.5, 1.5, 2) if craft.thrusters else None
    checked = Simulator(craft, World(), num_envs=3)
    checked.set_mass_properties(
        mass_kg=craft.mass_kg * mass,
        inertia_kgm2=(mass * inertia)[:, None, None] * craft.inertia_tensor,
        center_of_mass_m=shift,
        env_ids=ids,
    )
    checked.set_sample_scale("all", area=density, env_ids=ids)
    for j, g in enumerate(groups):
        checked.set_sample_scale(g, area=area[:, j] * density, efficiency=eff[:, j], env_ids=ids)
    if thrust is not None:
        checked.set_thrust_scale(thrust, env_ids=ids)
    fast = Simulator(craft, World(), num_envs=3)
    randomizer = fast.randomizer(groups)
    for _ in range(2):  # the second write finds the groups on rows of their own
        randomizer.set(ids, mass, inertia, shift, density, area, eff, thrust)
    for name in ("mass_kg", "inertia_kgm2", "center_of_mass_m"):
        np.testing.assert_array_equal(getattr(checked, name), getattr(fast, name), err_msg=name)
    a, b = checked.get_state(), fast.get_state()
    for key in a:  # the body rows and collision shapes travel in the model: stepped below
        np.testing.assert_array_equal(a[key], b[key], err_msg=key)
    np.testing.assert_array_equal(_fly(checked, 16), _fly(fast, 16))
    with pytest.raises(ValueError, match="mass_scale must be positive, got"):
        randomizer.set(ids, -mass, inertia, shift, density, area, eff, thrust)
    with pytest.raises(ValueError, match="efficiency .* outside \\[0, 1\\]"):
        randomizer.set(ids, mass, inertia, shift, density, area, -eff, thrust)
