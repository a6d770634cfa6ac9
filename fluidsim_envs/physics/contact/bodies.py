"""A body's state as contact sees it in the step kernel's scratch (position, rotation, velocity,
spin), and the impulses, pushes and turns contact applies to it."""

from __future__ import annotations

import math

from numba import njit

from ..forces import HALF, ONE, ZERO
from ..jit import INLINE as _INLINE
from ..rotation import body_inv_inertia, quat_rate, quat_to_matrix, world_omega
from ..state import B_MASS, OL, OQ, OV, OX, STATE

# --------------------------------------------------------------------------------------------
# a body's state in the step kernel's scratch: element k of body b is S[b, i + (STATE + k) * n]


@njit(**_INLINE)
def _pose(S, b, i, n):
    x = (S[b, i + (STATE + OX) * n], S[b, i + (STATE + OX + 1) * n], S[b, i + (STATE + OX + 2) * n])
    rot = quat_to_matrix(
        S[b, i + (STATE + OQ) * n],
        S[b, i + (STATE + OQ + 1) * n],
        S[b, i + (STATE + OQ + 2) * n],
        S[b, i + (STATE + OQ + 3) * n],
    )
    return x, rot


@njit(**_INLINE)
def _point(x, rot, px, py, pz):
    """World position of the body-frame point p."""
    return (
        x[0] + rot[0] * px + rot[1] * py + rot[2] * pz,
        x[1] + rot[3] * px + rot[4] * py + rot[5] * pz,
        x[2] + rot[6] * px + rot[7] * py + rot[8] * pz,
    )


@njit(**_INLINE)
def _omega(S, b, i, n, rot, body):
    return world_omega(
        rot,
        S[b, i + (STATE + OL) * n],
        S[b, i + (STATE + OL + 1) * n],
        S[b, i + (STATE + OL + 2) * n],
        body_inv_inertia(body, b),
    )


@njit(**_INLINE)
def _energy(S, b, i, n, body):
    """Kinetic energy of body b: 1/2 m v.v + 1/2 L.w."""
    rot = _pose(S, b, i, n)[1]
    w = _omega(S, b, i, n, rot, body)
    v0, v1, v2 = (
        S[b, i + (STATE + OV) * n],
        S[b, i + (STATE + OV + 1) * n],
        S[b, i + (STATE + OV + 2) * n],
    )
    l0, l1, l2 = (
        S[b, i + (STATE + OL) * n],
        S[b, i + (STATE + OL + 1) * n],
        S[b, i + (STATE + OL + 2) * n],
    )
    return HALF * (
        body[b, B_MASS] * (v0 * v0 + v1 * v1 + v2 * v2) + l0 * w[0] + l1 * w[1] + l2 * w[2]
    )


@njit(**_INLINE)
def _inv_mass(S, b, i, n, body, rx, ry, rz, ux, uy, uz):
    """The body's inverse effective mass for a push along u at r from its center:
    1/m + (r x u) . I_world^-1 (r x u)."""
    rot = _pose(S, b, i, n)[1]
    cx, cy, cz = ry * uz - rz * uy, rz * ux - rx * uz, rx * uy - ry * ux
    w = world_omega(rot, cx, cy, cz, body_inv_inertia(body, b))
    return ONE / body[b, B_MASS] + cx * w[0] + cy * w[1] + cz * w[2]


@njit(**_INLINE)
def _impulse(S, b, i, n, body, rx, ry, rz, jx, jy, jz):
    """An impulse J at r (from the center): v += J / m, L += r x J."""
    inv_m = ONE / body[b, B_MASS]
    S[b, i + (STATE + OV) * n] += jx * inv_m
    S[b, i + (STATE + OV + 1) * n] += jy * inv_m
    S[b, i + (STATE + OV + 2) * n] += jz * inv_m
    S[b, i + (STATE + OL) * n] += ry * jz - rz * jy
    S[b, i + (STATE + OL + 1) * n] += rz * jx - rx * jz
    S[b, i + (STATE + OL + 2) * n] += rx * jy - ry * jx


@njit(**_INLINE)
def _displace(S, b, i, n, body, rx, ry, rz, ux, uy, uz, dist):
    """Move the body's point at r by ``dist`` along the unit u, as the tetrahedron pushed
    there and restored does: a positional impulse P = dist / k(u) moves the center by P / m
    and turns the body by I_world^-1 (r x P) (first order; the quaternion renormalized).
    Momenta are kept."""
    if dist <= ZERO:
        return
    p = dist / _inv_mass(S, b, i, n, body, rx, ry, rz, ux, uy, uz)
    rot = _pose(S, b, i, n)[1]
    inv_m = ONE / body[b, B_MASS]
    S[b, i + (STATE + OX) * n] += p * ux * inv_m
    S[b, i + (STATE + OX + 1) * n] += p * uy * inv_m
    S[b, i + (STATE + OX + 2) * n] += p * uz * inv_m
    cx, cy, cz = ry * uz - rz * uy, rz * ux - rx * uz, rx * uy - ry * ux
    t = world_omega(rot, p * cx, p * cy, p * cz, body_inv_inertia(body, b))
    _turn(S, b, i, n, t[0], t[1], t[2])


@njit(**_INLINE)
def _turn(S, b, i, n, tx, ty, tz):
    """Turn body b by the small world rotation vector t (first order; renormalized)."""
    qw, qx = S[b, i + (STATE + OQ) * n], S[b, i + (STATE + OQ + 1) * n]
    qy, qz = S[b, i + (STATE + OQ + 2) * n], S[b, i + (STATE + OQ + 3) * n]
    dq = quat_rate(qw, qx, qy, qz, tx, ty, tz)
    qw, qx, qy, qz = qw + dq[0], qx + dq[1], qy + dq[2], qz + dq[3]
    s = ONE / math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    S[b, i + (STATE + OQ) * n] = qw * s
    S[b, i + (STATE + OQ + 1) * n] = qx * s
    S[b, i + (STATE + OQ + 2) * n] = qy * s
    S[b, i + (STATE + OQ + 3) * n] = qz * s


@njit(**_INLINE)
def _scale_velocities(S, a, b, i, n, body, s):
    """Scale the bodies' velocities (and spins) by s about their common center of mass
    (b < 0: body a alone, about rest)."""
    ma = body[a, B_MASS]
    mb = body[b, B_MASS] if b >= 0 else ZERO * ma
    for k in range(3):
        va = S[a, i + (STATE + OV + k) * n]
        vb = S[b, i + (STATE + OV + k) * n] if b >= 0 else ZERO * va
        vc = (ma * va + mb * vb) / (ma + mb) if b >= 0 else ZERO * va
        S[a, i + (STATE + OV + k) * n] = vc + s * (va - vc)
        S[a, i + (STATE + OL + k) * n] *= s
        if b >= 0:
            S[b, i + (STATE + OV + k) * n] = vc + s * (vb - vc)
            S[b, i + (STATE + OL + k) * n] *= s


@njit(**_INLINE)
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(**_INLINE)
def _cross(a, b):
    return a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]


@njit(**_INLINE)
def _motion(S, b, i, n, body, p):
    """Body b's velocity at the world point p and its angular velocity."""
    x, rot = _pose(S, b, i, n)
    w = _omega(S, b, i, n, rot, body)
    r = (p[0] - x[0], p[1] - x[1], p[2] - x[2])
    wr = _cross(w, r)
    v = (
        S[b, i + (STATE + OV) * n] + wr[0],
        S[b, i + (STATE + OV + 1) * n] + wr[1],
        S[b, i + (STATE + OV + 2) * n] + wr[2],
    )
    return v, w


@njit(**_INLINE)
def _wrench(S, b, i, n, body, p, jx, jy, jz, tx, ty, tz):
    """An impulse J at the world point p and an angular impulse T on body b."""
    x = _pose(S, b, i, n)[0]
    rx, ry, rz = p[0] - x[0], p[1] - x[1], p[2] - x[2]
    _impulse(S, b, i, n, body, rx, ry, rz, jx, jy, jz)
    S[b, i + (STATE + OL) * n] += tx
    S[b, i + (STATE + OL + 1) * n] += ty
    S[b, i + (STATE + OL + 2) * n] += tz
