"""Matching a rigid body with four particles (issue 3): the tetrahedron reproduces mass,
center of mass and inertia tensor exactly (to rounding), for any physically possible tensor,
and refuses impossible ones; particle velocities carry the body's momentum and angular
momentum exactly. The identity used: for point masses, I = tr(S) 1 - S with S the second
moment (e.g. Goldstein, Classical Mechanics, 3rd ed., sec. 5.3)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fluidsim_envs.physics import Craft
from fluidsim_envs.physics.reference.tetra import match_inertia, momenta, particle_velocities


def inertia_of(masses, positions):
    """sum m_i (|r_i|^2 1 - r_i r_i^T): the inertia tensor of point masses."""
    pairs = zip(masses, positions, strict=True)
    return sum(m * (r @ r * np.eye(3) - np.outer(r, r)) for m, r in pairs)


def rotation(q):
    q = np.asarray(q, dtype=float)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


# a physically possible tensor: a non-negative second moment S (eigenvalues s, two of them
# positive: one alone is a rod, with no moment about its axis) gives principal moments
# I_i = s_j + s_k, which satisfy the triangle inequality; turned to random axes, so full
# tensors are covered
second_moments = st.lists(st.floats(0.0, 1e3), min_size=3, max_size=3).filter(
    lambda s: sorted(s)[1] > 1e-3
)
quaternions = st.lists(st.floats(-1.0, 1.0), min_size=4, max_size=4).filter(
    lambda q: np.linalg.norm(q) > 0.1
)


@settings(max_examples=300)
@given(mass=st.floats(1e-3, 1e6), s=second_moments, q=quaternions)
def test_match_is_exact_for_any_possible_tensor(mass, s, q):
    s = np.array(s)
    moments = s.sum() - s
    R = rotation(q)
    tensor = R @ np.diag(moments) @ R.T
    tensor = 0.5 * (tensor + tensor.T)
    pos, m = match_inertia(mass, tensor)
    assert pos.shape == (4, 3) and m.shape == (4,)
    assert m.sum() == pytest.approx(mass, rel=1e-15)
    scale = np.abs(pos).max() + 1e-300
    np.testing.assert_allclose((m[:, None] * pos).sum(axis=0), 0.0, atol=1e-14 * mass * scale)
    np.testing.assert_allclose(inertia_of(m, pos), tensor, rtol=0, atol=1e-12 * moments.max())


def test_principal_moments_and_a_shipped_craft():
    pos, m = match_inertia(2.0, (1.0, 2.0, 2.5))
    np.testing.assert_allclose(inertia_of(m, pos), np.diag([1.0, 2.0, 2.5]), atol=1e-14)
    craft = Craft.load("speedboat")
    pos, m = match_inertia(craft.mass_kg, craft.inertia_tensor)
    np.testing.assert_allclose(inertia_of(m, pos), craft.inertia_tensor, rtol=1e-13)


def test_a_flat_body_gives_a_flat_tetrahedron():
    """A thin plate in the x-y plane: Iz = Ix + Iy (the triangle inequality's edge)."""
    pos, m = match_inertia(1.0, (1.0, 4.0, 5.0))
    np.testing.assert_allclose(pos[:, 2], 0.0, atol=1e-15)
    np.testing.assert_allclose(inertia_of(m, pos), np.diag([1.0, 4.0, 5.0]), atol=1e-14)


@pytest.mark.parametrize(
    "mass,tensor,message",
    [
        (1.0, (1.0, 1.0, 3.0), "triangle inequality"),
        (1.0, (1.0, -1.0, 1.0), "positive definite"),
        (1.0, (0.0, 1.0, 1.0), "positive definite"),
        (1.0, [[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], "symmetric"),
        (1.0, (1.0, float("nan"), 1.0), "finite"),
        (1.0, (1.0, 2.0), "3 principal moments"),
        (0.0, (1.0, 1.0, 1.0), "mass_kg must be > 0"),
        (-2.0, (1.0, 1.0, 1.0), "mass_kg must be > 0"),
        (float("inf"), (1.0, 1.0, 1.0), "mass_kg must be a finite"),
    ],
)
def test_impossible_bodies_are_refused_with_the_reason(mass, tensor, message):
    with pytest.raises(ValueError, match=message):
        match_inertia(mass, tensor)


@settings(max_examples=100)
@given(
    s=second_moments,
    q=quaternions,
    v=st.lists(st.floats(-50, 50), min_size=3, max_size=3),
    w=st.lists(st.floats(-50, 50), min_size=3, max_size=3),
)
def test_particle_velocities_carry_momentum_and_angular_momentum(s, q, v, w):
    """In the world frame, for a body turned by R: the particles at R r_i moving at
    v + w x (R r_i) have momentum m v and angular momentum R I R^T w."""
    mass = 3.0
    s = np.array(s)
    body_inertia = np.diag(s.sum() - s)
    R = rotation(q)
    pos, m = match_inertia(mass, body_inertia)
    world = pos @ R.T
    vel = particle_velocities(world, v, w)
    p, L = momenta(m, world, vel)
    np.testing.assert_allclose(p, mass * np.array(v), rtol=1e-13, atol=1e-12)
    expected = R @ body_inertia @ R.T @ np.array(w)
    np.testing.assert_allclose(L, expected, rtol=1e-12, atol=1e-11 * (1 + np.abs(expected).max()))


def test_old_import_paths_still_work():
    """The helpers moved to physics.reference; physics.tetra keeps ``match_inertia`` (and
    physics.savitsky the Savitsky model) importable for one release."""
    from fluidsim_envs.physics import savitsky as old_savitsky
    from fluidsim_envs.physics import tetra as old_tetra
    from fluidsim_envs.physics.reference import savitsky

    assert old_tetra.match_inertia is match_inertia
    assert old_savitsky.savitsky is savitsky.savitsky
