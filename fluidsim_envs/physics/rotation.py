"""Rigid-body kinematics as scalar numba functions: rotation matrices from quaternions, the
angular velocity from angular momentum, the quaternion rate; and the layout of a body's state.
Shared by the step kernel, the contact pass and the scene kernels (one spelling of each).

Rotations are row-major 9-tuples ``(r0..r8)`` of R (body -> world); inverse inertias are the
entries ``(xx, yy, zz, xy, xz, yz)`` of the symmetric inverse body inertia tensor.
"""

from __future__ import annotations

from numba import njit

from .forces import HALF, ONE, TWO
from .jit import INLINE as _INLINE
from .state import B_INV_INERTIA, NSTATE, OL, OQ, OV, OX  # noqa: F401  (re-exported)


@njit(**_INLINE)
def quat_to_matrix(qw, qx, qy, qz):
    """Rotation matrix (row-major 9-tuple) of q / |q|: body -> world."""
    s = TWO / (qw * qw + qx * qx + qy * qy + qz * qz)
    return (
        ONE - s * (qy * qy + qz * qz),
        s * (qx * qy - qw * qz),
        s * (qx * qz + qw * qy),
        s * (qx * qy + qw * qz),
        ONE - s * (qx * qx + qz * qz),
        s * (qy * qz - qw * qx),
        s * (qx * qz - qw * qy),
        s * (qy * qz + qw * qx),
        ONE - s * (qx * qx + qy * qy),
    )


@njit(**_INLINE)
def world_omega(rot, lx, ly, lz, inv_inertia):
    """Angular velocity w = R I_body^-1 R^T L from world angular momentum L. ``rot`` is the
    row-major 9-tuple of R, ``inv_inertia`` the entries (xx, yy, zz, xy, xz, yz) of the
    symmetric inverse body inertia tensor."""
    r0, r1, r2, r3, r4, r5, r6, r7, r8 = rot
    ixx, iyy, izz, ixy, ixz, iyz = inv_inertia
    bx = r0 * lx + r3 * ly + r6 * lz
    by = r1 * lx + r4 * ly + r7 * lz
    bz = r2 * lx + r5 * ly + r8 * lz
    wx = ixx * bx + ixy * by + ixz * bz
    wy = ixy * bx + iyy * by + iyz * bz
    wz = ixz * bx + iyz * by + izz * bz
    return (r0 * wx + r1 * wy + r2 * wz, r3 * wx + r4 * wy + r5 * wz, r6 * wx + r7 * wy + r8 * wz)


@njit(**_INLINE)
def to_body(rot, x, y, z):
    """Body-frame components R^T (x, y, z) of a world vector; ``rot`` is R row-major."""
    return (
        rot[0] * x + rot[3] * y + rot[6] * z,
        rot[1] * x + rot[4] * y + rot[7] * z,
        rot[2] * x + rot[5] * y + rot[8] * z,
    )


@njit(**_INLINE)
def quat_rate(qw, qx, qy, qz, wx, wy, wz):
    """dq/dt = 1/2 [0, w] (x) q for a world-frame angular velocity w."""
    return (
        -HALF * (wx * qx + wy * qy + wz * qz),
        HALF * (qw * wx + wy * qz - wz * qy),
        HALF * (qw * wy + wz * qx - wx * qz),
        HALF * (qw * wz + wx * qy - wy * qx),
    )


@njit(**_INLINE)
def body_inv_inertia(body, b):
    """The inverse body inertia entries (xx, yy, zz, xy, xz, yz) of body slot b of a body
    table ``body[B, NBODY]`` (one environment's rows of ``Simulator``'s ``body[E, B, NBODY]``;
    columns: ``state.BODY_FIELDS``)."""
    k = B_INV_INERTIA
    return (
        body[b, k],
        body[b, k + 1],
        body[b, k + 2],
        body[b, k + 3],
        body[b, k + 4],
        body[b, k + 5],
    )


@njit(**_INLINE)
def env_inv_inertia(body, e, b):
    """:func:`body_inv_inertia` of environment e straight from ``body[E, B, NBODY]`` (no
    view of the environment's rows: a view per environment costs a reference count in the
    scene kernels' loops)."""
    k = B_INV_INERTIA
    return (
        body[e, b, k],
        body[e, b, k + 1],
        body[e, b, k + 2],
        body[e, b, k + 3],
        body[e, b, k + 4],
        body[e, b, k + 5],
    )
