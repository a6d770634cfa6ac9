"""Tracer particles and macro particles in the submarine's wake (fluidsim_envs.physics.tracers)."""

import math

import numba
import numpy as np
import pytest

from fluidsim_envs.physics import WakeField
from fluidsim_envs.physics.tracers import (
    MacroParticles,
    SpatialHash,
    Tracers,
    default_box,
    sample_macro,
)

IDENTITY = (1.0, 0.0, 0.0, 0.0)
# one Lamb-Oseen vortex on the hull's axis behind the screws, nothing else
VORTEX = WakeField(displacement=False, noise=0.0, screws=1)
STILL = WakeField(displacement=False, vortices=False, noise=0.0)
WIDE_BOX = ((-200.0, 50.0), (-20.0, 20.0), (-20.0, 20.0))


def yaw_quat(deg):
    h = math.radians(deg) / 2
    return (math.cos(h), 0.0, 0.0, math.sin(h))


def rotation(q):
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def vortex_at(wake, xi, speed):
    """Circulation and core radius of the single screw vortex ``xi`` meters aft of the
    screws, from WakeField's documented model (Gamma = circulation speed radius, ramped in
    over one radius, e-folding over decay_length; core growing linearly)."""
    b = wake.radius_m
    t = min(max(xi / b, 0.0), 1.0)
    decay = 2.0 * wake.length_m if wake.decay_length_m is None else wake.decay_length_m
    core0 = 0.25 * b if wake.core_radius_m is None else wake.core_radius_m
    gamma = wake.circulation * b * speed * t * t * (3 - 2 * t) * math.exp(-xi / decay)
    return gamma, core0 + wake.core_growth * xi


def test_still_water_tracers_do_not_move():
    """With every part of the wake off the water is still: a tracer stays where it is, except
    the ones the box leaves behind, which re-enter at the far face (so the box stays full)."""
    tr = Tracers(STILL, count=400)
    tr.reset((0, 0, -30), IDENTITY, (4.0, 0, 0), np.random.default_rng(1))
    before = tr.positions.copy()
    dt, moved = 0.5, 0
    for k in range(1, 21):
        tr.advance(dt, (4.0 * dt * k, 0, -30), IDENTITY, (4.0, 0, 0))
        moved += tr.recycled
    after = tr.positions
    stayed = np.all(after == before, axis=1)
    lo, hi = np.array(default_box(STILL)).T
    # the hull travelled 40 m: the tracers within 40 m of the aft face were put back in
    behind = before[:, 0] < lo[0] + 40.0
    assert moved == np.count_nonzero(behind) > 0
    assert np.array_equal(stayed, ~behind)
    assert np.all(tr.speeds == 0.0)
    local = after - (40.0, 0, -30)
    assert np.all((local >= lo) & (local <= hi))
    # the x-coordinate wraps: the re-entered ones fill the front 40 m
    np.testing.assert_allclose(after[behind, 0], before[behind, 0] + (hi[0] - lo[0]), rtol=1e-12)


def test_tracers_stay_in_the_box_of_a_turning_hull():
    """Recycling works in the hull's frame: whichever face a tracer leaves by as the hull
    turns, it is put back inside the box."""
    wake = WakeField()
    tr = Tracers(wake, count=1000, parallel=False)
    lo, hi = np.array(default_box(wake)).T
    pos, vel, yaw, dt = np.zeros(3), np.zeros(3), 0.0, 0.5
    tr.reset(pos, yaw_quat(yaw), (6.0, 0, 0), np.random.default_rng(8))
    recycled = 0
    for _ in range(60):
        yaw += 3.0  # degrees per step: a full half-turn
        vel = 6.0 * np.array([math.cos(math.radians(yaw)), math.sin(math.radians(yaw)), 0.0])
        pos = pos + vel * dt
        tr.advance(dt, pos, yaw_quat(yaw), vel)
        recycled += tr.recycled
        local = (tr.positions - pos) @ rotation(yaw_quat(yaw))
        assert np.all((local >= lo - 1e-9) & (local <= hi + 1e-9))
    assert recycled > 300


def test_one_advance_is_the_midpoint_rule_on_the_field():
    """x1 = x0 + dt u(x0 + dt/2 u(x0, t0), t0 + dt/2), the hull moving at its velocity with a
    fixed heading over the step and given at its end; u from WakeField.velocity."""
    wake = WakeField()
    quat = yaw_quat(30.0)
    vel = np.array([4.0, 2.0, -0.5])
    pos_end = np.array([3.0, -2.0, -40.0])
    # in the hull's frame: from ahead of the bow to far behind, around the hull
    local = np.random.default_rng(5).uniform((-100, -8, -8), (25, 8, 8), (300, 3))
    x0 = pos_end + local @ rotation(quat).T
    tr = Tracers(wake, count=300, box_m=WIDE_BOX)
    tr.reset(pos_end, quat, vel, np.random.default_rng(6), positions=x0)
    dt, noise = 0.2, (0.3, 1.2, -2.0)
    tr.advance(dt, pos_end, quat, vel, noise)
    k1 = wake.velocity(x0, pos_end - vel * dt, quat, vel, noise)
    k2 = wake.velocity(x0 + 0.5 * dt * k1, pos_end - 0.5 * vel * dt, quat, vel, noise)
    assert tr.recycled == 0
    assert np.abs(k2).max() > 0.5  # the step did move them
    np.testing.assert_allclose(tr.positions, x0 + dt * k2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(tr.speeds, np.linalg.norm(k2, axis=1), rtol=1e-12)


def test_tracer_circles_a_vortex_core_with_second_order_drift():
    """The vortex's velocity is azimuthal, so the exact path keeps its distance to the axis
    (and its x) even as the circulation decays aft; the midpoint rule's radial drift shrinks
    about 4x when the step is halved (second order; first order would give 2x)."""
    speed, r0 = 3.0, 0.6
    x_screws = -VORTEX.length_m / 2
    start = np.array([[x_screws - 10.0, r0, 0.0]])
    gamma, core = vortex_at(VORTEX, 10.0, speed)
    period = 2 * math.pi * r0 / (gamma / (2 * math.pi * r0) * -math.expm1(-((r0 / core) ** 2)))

    def drift(dt):
        tr = Tracers(VORTEX, count=1, box_m=WIDE_BOX)
        tr.reset((0, 0, 0), IDENTITY, (speed, 0, 0), np.random.default_rng(0), positions=start)
        turned, angle = 0.0, 0.0
        for k in range(1, round(period / dt) + 1):
            tr.advance(dt, (speed * dt * k, 0, 0), IDENTITY, (speed, 0, 0))
            p = tr.positions[0]
            new = math.atan2(p[2], p[1])
            turned += (new - angle + math.pi) % (2 * math.pi) - math.pi
            angle = new
        assert p[0] == start[0, 0]
        return abs(math.hypot(p[1], p[2]) - r0), turned

    coarse, turned = drift(period / 200)
    fine, _ = drift(period / 400)
    assert turned > math.pi  # counterclockwise about +x, most of a turn (Gamma decays aft)
    assert coarse < 2e-4 * r0
    assert fine < coarse / 3.5  # -> 4 as dt -> 0 (3.7, 3.9 at 100 and 200 steps a turn)


def test_spatial_hash_finds_the_brute_force_pairs():
    rng = np.random.default_rng(11)
    for offset, cell in ((0.0, 1.0), (-1.0e4, 0.7), (3.3e5, 2.5), (1.0e7, 1.0)):
        centers = offset + cell * rng.uniform(-5, 5, (600, 3))
        radii = cell * rng.uniform(0.05, 1.0, 600)
        points = offset + cell * rng.uniform(-6, 6, (3000, 3))
        got = SpatialHash(cell, centers, radii).pairs(points)
        d2 = np.sum((points[:, None, :] - centers[None, :, :]) ** 2, axis=2)
        expected = np.argwhere(d2 < radii**2)  # sorted by point, then sphere
        assert len(expected) > 500
        np.testing.assert_array_equal(got, expected)


def test_hash_blend_is_the_weighted_rigid_motion():
    """One sphere: v + omega x r inside, 0 outside. Two: the (1 - d^2/R^2)^2 weighted mean."""
    centers = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    radii = np.array([1.5, 0.8])
    lin = np.array([[1.0, 2.0, 3.0], [-1.0, 0.5, 0.0]])
    ang = np.array([[0.0, 0.0, 2.0], [1.0, -1.0, 0.5]])
    h = SpatialHash(1.5, centers, radii)
    p = np.array([[-0.5, 0.3, 0.2], [0.6, 0.1, -0.1], [0.0, 2.0, 0.0]])
    got = h.blend(p, lin, ang)
    r = p[:, None, :] - centers[None]
    d2 = np.sum(r**2, axis=2)
    w = np.where(d2 < radii**2, (1 - d2 / radii**2) ** 2, 0.0)
    v = lin[None] + np.cross(ang[None], r)
    expected = np.einsum("pm,pmk->pk", w, v) / np.maximum(w.sum(1), 1e-300)[:, None]
    assert w[0, 1] == 0 and w[1, 1] > 0  # point 0 in one sphere, point 1 in both
    np.testing.assert_allclose(got, expected, rtol=1e-13, atol=1e-15)
    assert np.all(got[2] == 0.0)


@pytest.mark.parametrize("yaw", [0.0, 90.0])
def test_macro_angular_velocity_at_a_vortex_core(yaw):
    """On the axis of a Lamb-Oseen vortex, v_theta = Gamma/(2 pi r) (1 - exp(-r^2/rc^2)), the
    vorticity is Gamma/(pi rc^2) and a macro particle there spins at half of it about the
    hull's axis, Gamma/(2 pi rc^2), with no velocity of its own."""
    speed, xi = 2.0, 12.0
    q = yaw_quat(yaw)
    axis = np.array([math.cos(math.radians(yaw)), math.sin(math.radians(yaw)), 0.0])
    center = (-VORTEX.length_m / 2 - xi) * axis + (1.0, 2.0, -30.0)
    lin, ang = sample_macro(VORTEX, center[None], (1.0, 2.0, -30.0), q, speed * axis)
    gamma, core = vortex_at(VORTEX, xi, speed)
    assert gamma > 1.0
    np.testing.assert_allclose(ang[0], gamma / (2 * math.pi * core**2) * axis, rtol=1e-5, atol=1e-7)
    np.testing.assert_allclose(lin[0], 0.0, atol=1e-12)


def test_macro_lattice_covers_the_box_and_follows_the_hull():
    wake = WakeField()
    box = default_box(wake)
    m = MacroParticles(wake, box, 300)
    assert 200 <= m.count <= 400
    m.sample((5.0, 0.0, -20.0), yaw_quat(90.0), (0.0, 3.0, 0.0))
    np.testing.assert_allclose(m.centers[:, 0] - 5.0, -m.local[:, 1], atol=1e-12)
    np.testing.assert_allclose(m.centers[:, 1], m.local[:, 0], atol=1e-12)
    # every point of the box is in some sphere
    lo, hi = np.array(box).T
    local = lo + np.random.default_rng(2).random((5000, 3)) * (hi - lo)
    d2 = np.sum((local[:, None] - m.local[None]) ** 2, axis=2)
    assert np.all(d2.min(axis=1) < m.radius_m**2)


def test_macro_advance_is_the_midpoint_rule_on_the_blend():
    """With macro particles the field is sampled once at the interval's midpoint, and the
    blend moves with the hull: at time t it is read at x - u (t - t_mid)."""
    wake = WakeField()
    vel = np.array([5.0, 0.0, 0.0])
    x0 = np.random.default_rng(3).uniform((-70, -8, -58), (25, 8, -42), (500, 3))
    tr = Tracers(wake, count=500, macro=200)
    tr.reset((0, 0, -50), IDENTITY, vel, np.random.default_rng(4), positions=x0)
    dt = 0.1
    tr.advance(dt, vel * dt + (0, 0, -50), IDENTITY, vel)
    m = tr.macro
    k1 = m.velocity(x0 - vel * (-0.5 * dt))
    k2 = m.velocity(x0 + 0.5 * dt * k1)
    assert tr.recycled == 0
    assert np.abs(k2).max() > 0.5
    np.testing.assert_allclose(tr.positions, x0 + dt * k2, rtol=0, atol=1e-12)
    state = tr.macro_state
    assert state.centers.shape == state.lin_vel.shape == state.ang_vel.shape == (m.count, 3)


def test_macro_blend_follows_the_field():
    """The blend is a smoothed copy of the field: over the box it correlates with it."""
    wake = WakeField()
    m = MacroParticles(wake, default_box(wake), 2000)
    m.sample((0, 0, 0), IDENTITY, (5.0, 0, 0))
    lo, hi = np.array(default_box(wake)).T
    pts = lo + np.random.default_rng(4).random((4000, 3)) * (hi - lo)
    exact = wake.velocity(pts, (0, 0, 0), IDENTITY, (5.0, 0, 0))
    approx = m.velocity(pts)
    corr = np.sum(exact * approx) / math.sqrt(np.sum(exact**2) * np.sum(approx**2))
    assert corr > 0.8


@pytest.mark.parametrize("macro", [0, 150])
def test_same_seed_same_tracers_any_thread_count(macro):
    """Recycling draws from the tracers' own generator, seeded at reset: the same seed gives
    bit-identical tracers, serial or parallel, on 1 thread or all of numba's."""
    wake = WakeField()

    def run(parallel, threads):
        numba.set_num_threads(threads)
        tr = Tracers(wake, count=700, macro=macro, parallel=parallel)
        tr.reset((0, 0, -40), yaw_quat(10), (6.0, 1.0, 0), np.random.default_rng(42))
        recycled = 0
        for k in range(1, 41):
            tr.advance(0.25, (6.0 * 0.25 * k, 0.25 * k, -40), yaw_quat(10), (6.0, 1.0, 0))
            recycled += tr.recycled
        return tr.positions.copy(), tr.speeds.copy(), recycled

    try:
        first, speeds, recycled = run(False, 1)
        assert recycled > 50
        for parallel, threads in ((False, 1), (True, 1), (True, numba.config.NUMBA_NUM_THREADS)):
            again, again_speeds, _ = run(parallel, threads)
            np.testing.assert_array_equal(again, first)
            np.testing.assert_array_equal(again_speeds, speeds)
    finally:
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)


def test_bad_inputs_are_named():
    wake = WakeField()
    for count in (0, -3, 2.5, True):
        with pytest.raises(ValueError, match="count must be an integer > 0"):
            Tracers(wake, count=count)
    with pytest.raises(ValueError, match="macro must be an integer >= 0"):
        Tracers(wake, macro=-1)
    with pytest.raises(ValueError, match=r"box_m must have shape \[3, 2\]"):
        Tracers(wake, box_m=(1.0, 2.0))
    with pytest.raises(ValueError, match="lo < hi"):
        Tracers(wake, box_m=((0, 1), (0, 1), (1, 0)))
    with pytest.raises(TypeError, match="wake must be a WakeField"):
        Tracers(None)
    tr = Tracers(wake, count=10)
    with pytest.raises(RuntimeError, match="reset"):
        tr.advance(0.1, (0, 0, 0), IDENTITY, (1, 0, 0))
    with pytest.raises(TypeError, match="rng must be a numpy Generator"):
        tr.reset((0, 0, 0), IDENTITY, (1, 0, 0), 7)
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match=r"sub_pos must have shape \[3\]"):
        tr.reset((0, 0), IDENTITY, (1, 0, 0), rng)
    with pytest.raises(ValueError, match=r"positions must have shape \(10, 3\)"):
        tr.reset((0, 0, 0), IDENTITY, (1, 0, 0), rng, positions=np.zeros((9, 3)))
    tr.reset((0, 0, 0), IDENTITY, (1, 0, 0), rng)
    for dt in (math.nan, math.inf, 0.0, -0.1):
        with pytest.raises(ValueError, match="dt must be a finite number > 0"):
            tr.advance(dt, (0, 0, 0), IDENTITY, (1, 0, 0))
    with pytest.raises(ValueError, match="substeps must be an integer > 0"):
        tr.advance(0.1, (0, 0, 0), IDENTITY, (1, 0, 0), substeps=0)
    with pytest.raises(ValueError, match="sub_lin_vel has non-finite"):
        tr.advance(0.1, (0, 0, 0), IDENTITY, (np.nan, 0, 0))
    with pytest.raises(ValueError, match=r"sub_quat must have shape \[4\]"):
        tr.advance(0.1, (0, 0, 0), (1, 0, 0), (1, 0, 0))
    with pytest.raises(ValueError, match="radii must be finite and > 0"):
        SpatialHash(1.0, np.zeros((2, 3)), (1.0, -1.0))
    with pytest.raises(ValueError, match=r"points must have shape \[N, 3\]"):
        SpatialHash(1.0, np.zeros((2, 3)), 0.5).pairs(np.zeros((4, 2)))
    with pytest.raises(ValueError, match="cell_size_m must be a finite number > 0"):
        SpatialHash(0.0, np.zeros((2, 3)), 0.5)
