"""Contact: bodies against the ground and against each other, built on the seed's idea.

The seed article carries a body as a tetrahedron of four Verlet particles (``tetra.py``). A
contact pushes the penetrating point out along the contact normal; spread over the particles
with the point's barycentric weights, the push deforms the tetrahedron locally, and the shape
is restored by the rigid motion that keeps the particles' momentum and angular momentum;
kinetic energy is then corrected so that contact invents none.

Restoring the tetrahedron after a push is a linear map with a closed form: particle impulses
``beta_i J`` (weights summing to 1 that reproduce the point, ``sum beta_i r_i = r``) carry
momentum ``J`` and angular momentum ``r x J``, so the restored body moves exactly as under
an impulse ``J`` at the point (``tests/physics/test_contact.py`` checks it), and a push of
position restores to the same with position for velocity (the fit's turn to first order).
This module applies the closed form, which also serves flat bodies (a paper dart), whose
flat tetrahedron cannot hold points off its plane.

Where the seed's one pass of point pushes fell short of the tests (a ball's push sized by
the particles' effective mass is a sixth of what stops it; a box resting on four corners,
pushed corner by corner, tips and walks; stacks sink), this departs from it, in the way
rigid-body engines do:

- Each touching pair (a body and the ground, or two bodies) is one contact over its patch:
  the depth-weighted mean of its touching points (box corners under the ground; a sphere's
  nearest point; for two boxes, the incident face clipped to the reference face), their
  spread in the contact plane (an ellipse: a face, an edge's segment, or a point), and the
  deepest depth. Points within a small margin above the surface (gravity's fall in two
  steps) count, so that a face resting tilted by a hair is still a face.
- ``_open``: an impact (approaching faster than gravity's gain in two steps) is pushed out
  along the normal by its depth, mass-weighted between two bodies (the seed's split), and
  aims to leave at ``-e`` times its approach; a resting contact aims at no approach.
- ``_pass``, ``C_PASSES`` times over all contacts (projected Gauss-Seidel, warm-started from
  the last step's impulses): the patch's six impulses (push, friction along two axes,
  torques about two axes, twist) solved together for the motion the contact aims at, then
  clamped: push >= 0, friction within ``mu`` times the push (Coulomb; the rest re-solved
  with the friction held), the center of pressure inside the patch, twist within the
  friction of a pressed disc.
- ``_close``: after an impact, the pair's kinetic energy may not exceed its value before,
  times 1 against the ground and ``PAIR_ENERGY_BOUND`` = 1.1 between two bodies (the seed's
  bound); beyond it, the motion about the pair's center of mass is scaled back.
- A resting body is then put back along its step's drift by the velocity its contacts
  took away (``x += dt dv``), instead of being pushed out along the normal: friction that
  holds it also holds its place (a push along a sloped normal walks it downhill).

Materials: a contact's restitution and friction are the geometric means of the two
materials' (the craft's ``restitution`` and ``friction``, and the :class:`Ground`'s), so a
pair of like materials keeps its own values. Not modelled: edge-across-edge box contacts,
continuous collision (a body faster than its size per step can pass through a thin one).

Under every integrator: a resting body's drift is undone by the integrator's own share of
it (``kernels.DRIFT_SHARE``), and an impact against the ground leaves with the speed the
body met the surface with, found from the integrator's own free-flight energy (``_open``),
so that boxes rest and stack, and a ball of restitution 1 keeps its bounce height, whatever
the integrator and dt (``docs/study.md``, Contact).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numba import njit

from .forces import HALF, ONE, TINY, TWO, ZERO
from .rotation import body_inv_inertia, quat_rate, quat_to_matrix, world_omega
from .state import B_MASS, OL, OQ, OV, OX, STATE

TWO_THIRDS = np.float32(2.0 / 3.0)
PAIR_ENERGY_BOUND = 1.1  # the seed's: two bodies' kinetic energy may rise 10% before scaling

# shape table rows (field-major, one environment's [NSHAPE, n_shapes] of the [E, NSHAPE,
# n_shapes] table): kind, center (3, from the center of mass, body frame), size (3: a sphere's
# radius then zeros, or a box's half extents), reach (the center's distance plus the extent)
SPHERE, BOX = 0, 1
SH_KIND, SH_CENTER, SH_SIZE, SH_REACH = 0, 1, 4, 7
NSHAPE = 8
# per-body contact table (one environment's [B, NCBODY] of [E, B, NCBODY]): restitution,
# friction, reach (m) of all its shapes
CB_RESTITUTION, CB_FRICTION, CB_REACH = 0, 1, 2
NCBODY = 3
# contact parameters [NCPRM]
C_ON, C_GROUND, C_GZ, C_GX0, C_GY0, C_GINV = 0, 1, 2, 3, 4, 5
C_GE, C_GMU, C_REST_SPEED, C_UNDRIFT, C_PAIR_BOUND, C_PASSES, C_MARGIN = 6, 7, 8, 9, 10, 11, 12
C_GTOP = 13  # the ground's highest point: a body whose reach is clear above it touches nothing
C_G, C_DT = 14, 15  # gravity (m/s^2) and the time step: an impact's speed at the surface
NCPRM = 16
GROUND_NONE, GROUND_PLANE, GROUND_FIELD = 0, 1, 2

_JIT = dict(cache=True, error_model="numpy", fastmath={"contract"})
_INLINE = dict(cache=True, error_model="numpy", inline="always", fastmath={"contract"})


# --------------------------------------------------------------------------------------------
# the ground


@dataclass(frozen=True)
class Ground:
    """A solid ground under the bodies: a plane at ``height_m``, or with ``heights_m`` a
    height field (terrain) on top of it.

    Args:
        height_m: the plane's height (m), or the field's base.
        heights_m: optional grid of heights (m) ``[ny, nx]`` (both >= 2) added to
            ``height_m``: ``heights_m[j][k]`` at ``x = origin_m[0] + k * spacing_m``,
            ``y = origin_m[1] + j * spacing_m``; bilinear between the nodes (the normal from
            its gradient), and flat beyond the edges (the edge's height continues).
        spacing_m: the grid's spacing (> 0).
        origin_m: the (x, y) of ``heights_m[0][0]``.
        restitution: the ground's restitution in [0, 1] (a contact takes the geometric mean
            with the craft's).
        friction: the ground's Coulomb friction coefficient (>= 0), combined the same way.

    Examples:
        >>> ramp = Ground(heights_m=[[0.0, 1.0], [0.0, 1.0]], spacing_m=2.0)
        >>> ramp.height(np.array([1.0, 5.0]), np.array([0.5, 0.5])).tolist()
        [0.5, 1.0]
    """

    height_m: float = 0.0
    heights_m: Any = None
    spacing_m: float = 1.0
    origin_m: tuple[float, float] = (0.0, 0.0)
    restitution: float = 0.5
    friction: float = 0.5
    _field: np.ndarray = field(default=None, repr=False, compare=False)  # type: ignore[assignment]

    def __post_init__(self) -> None:
        def number(key: str, value: Any, lo: float, hi: float = math.inf) -> float:
            ok = isinstance(value, (int, float, np.floating)) and not isinstance(value, bool)
            if not (ok and math.isfinite(value) and lo <= value <= hi):
                raise ValueError(f"Ground: {key} must be a number in [{lo}, {hi}], got {value!r}")
            return float(value)

        object.__setattr__(self, "height_m", number("height_m", self.height_m, -math.inf))
        object.__setattr__(self, "restitution", number("restitution", self.restitution, 0.0, 1.0))
        object.__setattr__(self, "friction", number("friction", self.friction, 0.0))
        spacing = number("spacing_m", self.spacing_m, 0.0)
        if spacing <= 0.0:
            raise ValueError(f"Ground: spacing_m must be > 0, got {self.spacing_m!r}")
        object.__setattr__(self, "spacing_m", spacing)
        origin = tuple(self.origin_m) if isinstance(self.origin_m, (list, tuple)) else ()
        if len(origin) != 2:
            raise ValueError(f"Ground: origin_m must be 2 numbers, got {self.origin_m!r}")
        origin = tuple(number("origin_m", v, -math.inf) for v in origin)
        object.__setattr__(self, "origin_m", origin)
        if self.heights_m is None:
            grid = np.zeros((1, 1))
        else:
            try:
                grid = np.array(self.heights_m, dtype=np.float64)
            except (TypeError, ValueError):
                raise ValueError(
                    f"Ground: heights_m must be a 2-D grid of numbers, got {self.heights_m!r}"
                ) from None
            if grid.ndim != 2 or min(grid.shape) < 2:
                raise ValueError(
                    f"Ground: heights_m must be a grid [ny, nx] with ny, nx >= 2, got shape "
                    f"{grid.shape}"
                )
            if not np.all(np.isfinite(grid)):
                raise ValueError("Ground: heights_m has non-finite values")
            object.__setattr__(self, "heights_m", tuple(map(tuple, grid.tolist())))
        grid.setflags(write=False)
        object.__setattr__(self, "_field", grid)

    @property
    def kind(self) -> int:
        return GROUND_PLANE if self.heights_m is None else GROUND_FIELD

    def height(self, x, y) -> np.ndarray:
        """The ground's height (m) at horizontal points (x, y): float64 arrays, broadcast."""
        return self._sample(x, y)[0]

    def normal(self, x, y) -> np.ndarray:
        """The ground's unit upward normal ``[..., 3]`` at (x, y)."""
        return np.moveaxis(self._sample(x, y)[1:], 0, -1)

    def _sample(self, x, y) -> np.ndarray:
        xs, ys = np.broadcast_arrays(np.asarray(x, np.float64), np.asarray(y, np.float64))
        out = np.empty((4, xs.size))
        ground_points(
            np.ascontiguousarray(xs).ravel(), np.ascontiguousarray(ys).ravel(), self.params(),
            self._field, out,
        )  # fmt: skip
        return out.reshape((4, *xs.shape))

    def params(self, dtype=np.float64) -> np.ndarray:
        """The ground's slots of the contact parameters (the rest zero)."""
        p = np.zeros(NCPRM)
        p[C_GROUND] = self.kind
        p[C_GZ] = self.height_m
        p[C_GX0], p[C_GY0] = self.origin_m
        p[C_GINV] = 1.0 / self.spacing_m
        p[C_GE] = self.restitution
        p[C_GMU] = self.friction
        p[C_GTOP] = self.height_m + (self._field.max() if self.heights_m is not None else 0.0)
        return p.astype(dtype)

    def field_table(self, dtype=np.float64) -> np.ndarray:
        """The height grid as the kernels read it ([1, 1] zeros for a plane)."""
        return np.ascontiguousarray(self._field, dtype=dtype)


@njit(**_INLINE)
def ground_at(x, y, cprm, grid):
    """Height and unit upward normal ``(h, nx, ny, nz)`` of the ground under (x, y)."""
    h = cprm[C_GZ]
    if cprm[C_GROUND] != GROUND_FIELD:
        return h, ZERO * h, ZERO * h, ONE + ZERO * h
    inv = cprm[C_GINV]
    ny, nx = grid.shape
    fx = (x - cprm[C_GX0]) * inv
    fy = (y - cprm[C_GY0]) * inv
    # flat beyond the edges: the coordinate clamped, and no slope across the clamped axis
    inx = ONE if ZERO <= fx <= nx - 1 else ZERO
    iny = ONE if ZERO <= fy <= ny - 1 else ZERO
    fx = min(max(fx, ZERO), nx - 1)
    fy = min(max(fy, ZERO), ny - 1)
    k = min(int(fx), nx - 2)
    j = min(int(fy), ny - 2)
    tx, ty = fx - k, fy - j
    h00, h01 = grid[j, k], grid[j, k + 1]
    h10, h11 = grid[j + 1, k], grid[j + 1, k + 1]
    h += (h00 * (ONE - tx) + h01 * tx) * (ONE - ty) + (h10 * (ONE - tx) + h11 * tx) * ty
    gx = ((h01 - h00) * (ONE - ty) + (h11 - h10) * ty) * inv * inx
    gy = ((h10 - h00) * (ONE - tx) + (h11 - h01) * tx) * inv * iny
    s = ONE / math.sqrt(ONE + gx * gx + gy * gy)
    return h, -gx * s, -gy * s, s


@njit(**_JIT)
def ground_points(x, y, cprm, grid, out):
    """``out[4, N]``: height and normal of the ground at N points (the kernel's formula)."""
    for i in range(x.shape[0]):
        h, nx, ny, nz = ground_at(x[i], y[i], cprm, grid)
        out[0, i], out[1, i], out[2, i], out[3, i] = h, nx, ny, nz


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


# --------------------------------------------------------------------------------------------
# contact generation


# A pair's overlap (a body and the ground, or two bodies) is resolved as one contact, as the
# seed resolves one contact per pair: the depth-weighted mean of its touching points and
# normals, as deep as the deepest. A face resting on four corners is then pushed at its
# middle, straight, not corner by corner (which would tip it and set it walking).
# Points within a small margin above the surface count too (weighted by depth plus margin),
# so that a face resting tilted by a hair is still pushed at its middle; without them the
# one edge touching takes gravity's whole step and the box rocks edge to edge for ever.
# Generators return the sums (w, w p (3), w n (3), max depth, w |p|^2), normals out of the
# second body (or the ground) into the first.


@njit(**_INLINE)
def _add(acc, d, px, py, pz, nx, ny, nz, margin):
    """Add a touching point of depth d (> -margin) to the sums ``acc``, weighted by its depth
    plus the margin: (w, w p (3), w n (3), max depth, w p p^T (xx, yy, zz, xy, xz, yz))."""
    w = d + margin
    return (
        acc[0] + w,
        acc[1] + w * px,
        acc[2] + w * py,
        acc[3] + w * pz,
        acc[4] + w * nx,
        acc[5] + w * ny,
        acc[6] + w * nz,
        max(acc[7], d),
        acc[8] + w * px * px,
        acc[9] + w * py * py,
        acc[10] + w * pz * pz,
        acc[11] + w * px * py,
        acc[12] + w * px * pz,
        acc[13] + w * py * pz,
    )


@njit(**_INLINE)
def _sum(acc, o, flip):
    """The sums of two sets of touching points, the second's normals times ``flip``."""
    return (
        acc[0] + o[0],
        acc[1] + o[1],
        acc[2] + o[2],
        acc[3] + o[3],
        acc[4] + flip * o[4],
        acc[5] + flip * o[5],
        acc[6] + flip * o[6],
        max(acc[7], o[7]),
        acc[8] + o[8],
        acc[9] + o[9],
        acc[10] + o[10],
        acc[11] + o[11],
        acc[12] + o[12],
        acc[13] + o[13],
    )


@njit(**_INLINE)
def _empty(z):
    return (z, z, z, z, z, z, z, -np.inf + z, z, z, z, z, z, z)


@njit(**_INLINE)
def _corner(shp, s, c):
    """Body-frame corner c (0-7) of box shape s."""
    sx = ONE if c & 1 else -ONE
    sy = ONE if c & 2 else -ONE
    sz = ONE if c & 4 else -ONE
    return (
        shp[SH_CENTER, s] + sx * shp[SH_SIZE, s],
        shp[SH_CENTER + 1, s] + sy * shp[SH_SIZE + 1, s],
        shp[SH_CENTER + 2, s] + sz * shp[SH_SIZE + 2, s],
    )


@njit(**_JIT)
def _ground_overlap(S, b, i, n, shp, srange, grid, cprm):
    """Body b's shapes below the ground: spheres by their lowest point, boxes by corners."""
    margin = cprm[C_MARGIN]
    x, rot = _pose(S, b, i, n)
    acc = _empty(ZERO * x[0])
    for s in range(srange[b], srange[b + 1]):
        if shp[SH_KIND, s] == SPHERE:
            c = _point(x, rot, shp[SH_CENTER, s], shp[SH_CENTER + 1, s], shp[SH_CENTER + 2, s])
            h, gx, gy, gz = ground_at(c[0], c[1], cprm, grid)
            r = shp[SH_SIZE, s]
            depth = r - (c[2] - h) * gz  # below the ground's tangent plane
            if depth > -margin:
                acc = _add(
                    acc, depth, c[0] - r * gx, c[1] - r * gy, c[2] - r * gz, gx, gy, gz, margin
                )
        else:
            for corner in range(8):
                cx, cy, cz = _corner(shp, s, corner)
                p = _point(x, rot, cx, cy, cz)
                h, gx, gy, gz = ground_at(p[0], p[1], cprm, grid)
                depth = (h - p[2]) * gz
                if depth > -margin:
                    acc = _add(acc, depth, p[0], p[1], p[2], gx, gy, gz, margin)
    return acc


@njit(**_INLINE)
def _local(rot, x, cx, cy, cz, px, py, pz):
    """Body-frame coordinates, relative to the shape center c, of the world point p."""
    dx, dy, dz = px - x[0], py - x[1], pz - x[2]
    return (
        rot[0] * dx + rot[3] * dy + rot[6] * dz - cx,
        rot[1] * dx + rot[4] * dy + rot[7] * dz - cy,
        rot[2] * dx + rot[5] * dy + rot[8] * dz - cz,
    )


@njit(**_JIT)
def _sphere_sphere(S, a, sa, b, sb, i, n, shp, margin):
    xa, ra = _pose(S, a, i, n)
    xb, rb = _pose(S, b, i, n)
    ca = _point(xa, ra, shp[SH_CENTER, sa], shp[SH_CENTER + 1, sa], shp[SH_CENTER + 2, sa])
    cb = _point(xb, rb, shp[SH_CENTER, sb], shp[SH_CENTER + 1, sb], shp[SH_CENTER + 2, sb])
    dx, dy, dz = ca[0] - cb[0], ca[1] - cb[1], ca[2] - cb[2]
    dist = math.sqrt(dx * dx + dy * dy + dz * dz)
    depth = shp[SH_SIZE, sa] + shp[SH_SIZE, sb] - dist
    acc = _empty(ZERO * dist)
    if depth <= -margin or dist <= TINY:
        return acc
    nx, ny, nz = dx / dist, dy / dist, dz / dist
    reach = shp[SH_SIZE, sb] - HALF * depth  # the middle of the overlap
    return _add(acc, depth, cb[0] + reach * nx, cb[1] + reach * ny, cb[2] + reach * nz,
                nx, ny, nz, margin)  # fmt: skip


@njit(**_JIT)
def _sphere_box(S, a, sa, b, sb, i, n, shp, margin):
    """Sphere sa of body a against box sb of body b (normal out of the box)."""
    xa, ra = _pose(S, a, i, n)
    xb, rb = _pose(S, b, i, n)
    c = _point(xa, ra, shp[SH_CENTER, sa], shp[SH_CENTER + 1, sa], shp[SH_CENTER + 2, sa])
    lx, ly, lz = _local(
        rb, xb, shp[SH_CENTER, sb], shp[SH_CENTER + 1, sb], shp[SH_CENTER + 2, sb], c[0], c[1], c[2]
    )
    hx, hy, hz = shp[SH_SIZE, sb], shp[SH_SIZE + 1, sb], shp[SH_SIZE + 2, sb]
    r = shp[SH_SIZE, sa]
    qx, qy, qz = min(max(lx, -hx), hx), min(max(ly, -hy), hy), min(max(lz, -hz), hz)
    dx, dy, dz = lx - qx, ly - qy, lz - qz
    dist = math.sqrt(dx * dx + dy * dy + dz * dz)
    if dist > TINY:  # the center outside the box: the nearest point on it
        depth = r - dist
        mx, my, mz = dx / dist, dy / dist, dz / dist
    else:  # the center inside: out through the nearest face
        fx, fy, fz = hx - abs(lx), hy - abs(ly), hz - abs(lz)
        mx, my, mz = ZERO * r, ZERO * r, ZERO * r
        if fx <= fy and fx <= fz:
            mx = ONE if lx >= ZERO else -ONE
            depth = r + fx
        elif fy <= fz:
            my = ONE if ly >= ZERO else -ONE
            depth = r + fy
        else:
            mz = ONE if lz >= ZERO else -ONE
            depth = r + fz
    acc = _empty(ZERO * r)
    if depth <= -margin:
        return acc
    nx = rb[0] * mx + rb[1] * my + rb[2] * mz
    ny = rb[3] * mx + rb[4] * my + rb[5] * mz
    nz = rb[6] * mx + rb[7] * my + rb[8] * mz
    return _add(acc, depth, c[0] - r * nx, c[1] - r * ny, c[2] - r * nz, nx, ny, nz, margin)


@njit(**_INLINE)
def _box_radius(rot, shp, s, ux, uy, uz):
    """Half the extent of box s (orientation rot) along the world unit u."""
    return (
        shp[SH_SIZE, s] * abs(rot[0] * ux + rot[3] * uy + rot[6] * uz)
        + shp[SH_SIZE + 1, s] * abs(rot[1] * ux + rot[4] * uy + rot[7] * uz)
        + shp[SH_SIZE + 2, s] * abs(rot[2] * ux + rot[5] * uy + rot[8] * uz)
    )


@njit(**_JIT)
def _box_box(S, a, sa, b, sb, i, n, shp, margin):
    """Box sa of body a against box sb of body b. The face axis (of either box) of least
    overlap gives the normal and the reference face; the other box's face that most opposes
    it (the incident face) is clipped to the reference face's rectangle: the touching
    points are the clipped polygon's corners, each as deep as it lies under the reference
    face (a face on a face, a face on an edge, corners on a face; not edge across edge)."""
    xa, ra = _pose(S, a, i, n)
    xb, rb = _pose(S, b, i, n)
    ca = _point(xa, ra, shp[SH_CENTER, sa], shp[SH_CENTER + 1, sa], shp[SH_CENTER + 2, sa])
    cb = _point(xb, rb, shp[SH_CENTER, sb], shp[SH_CENTER + 1, sb], shp[SH_CENTER + 2, sb])
    dx, dy, dz = ca[0] - cb[0], ca[1] - cb[1], ca[2] - cb[2]
    acc = _empty(ZERO * dx)
    best = np.inf
    ref, axis = 0, 0
    ux, uy, uz = ZERO * dx, ZERO * dx, ZERO * dx
    for k in range(6):
        rot = rb if k < 3 else ra
        j = k % 3
        vx, vy, vz = rot[j], rot[3 + j], rot[6 + j]
        along = dx * vx + dy * vy + dz * vz
        overlap = (
            _box_radius(ra, shp, sa, vx, vy, vz) + _box_radius(rb, shp, sb, vx, vy, vz) - abs(along)
        )
        if overlap <= -margin:
            return acc  # a separating face axis
        if overlap < best:
            best, ref, axis = overlap, k // 3, j
            sign = ONE if along >= ZERO else -ONE  # out of b toward a
            ux, uy, uz = sign * vx, sign * vy, sign * vz
    # reference box r (its face normal m points toward the incident box i)
    if ref == 0:
        rr, rs, cr, ri, si, ci, flip = rb, sb, cb, ra, sa, ca, ONE
    else:
        rr, rs, cr, ri, si, ci, flip = ra, sa, ca, rb, sb, cb, -ONE
    mx, my, mz = flip * ux, flip * uy, flip * uz
    h = shp[SH_SIZE + axis, rs]
    fx, fy, fz = cr[0] + h * mx, cr[1] + h * my, cr[2] + h * mz  # reference face center
    p1, p2 = (axis + 1) % 3, (axis + 2) % 3  # its in-plane axes and half sizes
    a1 = (rr[p1], rr[3 + p1], rr[6 + p1])
    a2 = (rr[p2], rr[3 + p2], rr[6 + p2])
    h1, h2 = shp[SH_SIZE + p1, rs], shp[SH_SIZE + p2, rs]
    # the incident face: the incident box's face whose normal most opposes m
    kbest, dbest = 0, ZERO * mx
    for q in range(3):
        d = ri[q] * mx + ri[3 + q] * my + ri[6 + q] * mz
        if abs(d) > abs(dbest):
            kbest, dbest = q, d
    s0 = -ONE if dbest > ZERO else ONE  # the face on the side facing the reference box
    q1, q2 = (kbest + 1) % 3, (kbest + 2) % 3
    gx = ci[0] + s0 * shp[SH_SIZE + kbest, si] * ri[kbest]
    gy = ci[1] + s0 * shp[SH_SIZE + kbest, si] * ri[3 + kbest]
    gz = ci[2] + s0 * shp[SH_SIZE + kbest, si] * ri[6 + kbest]
    # its 4 corners in the reference face's frame (x1, x2, depth below the face)
    poly = np.empty((8, 3), dtype=shp.dtype)
    tmp = np.empty((8, 3), dtype=shp.dtype)
    for c in range(4):
        t1 = shp[SH_SIZE + q1, si] * (ONE if c == 0 or c == 3 else -ONE)
        t2 = shp[SH_SIZE + q2, si] * (ONE if c < 2 else -ONE)
        px = gx + t1 * ri[q1] + t2 * ri[q2]
        py = gy + t1 * ri[3 + q1] + t2 * ri[3 + q2]
        pz = gz + t1 * ri[6 + q1] + t2 * ri[6 + q2]
        rx, ry, rz = px - fx, py - fy, pz - fz
        poly[c, 0] = rx * a1[0] + ry * a1[1] + rz * a1[2]
        poly[c, 1] = rx * a2[0] + ry * a2[1] + rz * a2[2]
        poly[c, 2] = -(rx * mx + ry * my + rz * mz)
    count = 4
    # clip against the four sides x1 <= h1, -x1 <= h1, x2 <= h2, -x2 <= h2 (+ the margin)
    for side in range(4):
        col = side // 2
        sg = ONE if side % 2 == 0 else -ONE
        lim = (h1 if col == 0 else h2) + margin
        out = 0
        for c in range(count):
            cur, nxt = poly[c], poly[(c + 1) % count]
            dc = sg * cur[col] - lim
            dn = sg * nxt[col] - lim
            if dc <= ZERO:
                tmp[out, 0], tmp[out, 1], tmp[out, 2] = cur[0], cur[1], cur[2]
                out += 1
            if (dc < ZERO < dn) or (dn < ZERO < dc):
                t = dc / (dc - dn)
                for m in range(3):
                    tmp[out, m] = cur[m] + t * (nxt[m] - cur[m])
                out += 1
        count = out
        for c in range(count):
            poly[c, 0], poly[c, 1], poly[c, 2] = tmp[c, 0], tmp[c, 1], tmp[c, 2]
        if count == 0:
            return acc
    for c in range(count):
        depth = poly[c, 2]
        if depth > -margin:
            # the point on the incident face: the reference face point minus the depth
            px = fx + poly[c, 0] * a1[0] + poly[c, 1] * a2[0] - depth * mx
            py = fy + poly[c, 0] * a1[1] + poly[c, 1] * a2[1] - depth * my
            pz = fz + poly[c, 0] * a1[2] + poly[c, 1] * a2[2] - depth * mz
            acc = _add(acc, depth, px, py, pz, ux, uy, uz, margin)
    return acc


@njit(**_JIT)
def _pair_overlap(S, a, b, i, n, shp, srange, margin):
    """Every shape of body a against every shape of body b (normals out of b into a)."""
    acc = _empty(ZERO * margin)
    for sa in range(srange[a], srange[a + 1]):
        for sb in range(srange[b], srange[b + 1]):
            ka, kb = shp[SH_KIND, sa], shp[SH_KIND, sb]
            if ka == SPHERE and kb == SPHERE:
                acc = _sum(acc, _sphere_sphere(S, a, sa, b, sb, i, n, shp, margin), ONE)
            elif ka == SPHERE:
                acc = _sum(acc, _sphere_box(S, a, sa, b, sb, i, n, shp, margin), ONE)
            elif kb == SPHERE:
                got = _sphere_box(S, b, sb, a, sa, i, n, shp, margin)  # normal out of a
                acc = _sum(acc, got, -ONE)
            else:
                acc = _sum(acc, _box_box(S, a, sa, b, sb, i, n, shp, margin), ONE)
    return acc


@njit(**_INLINE)
def _patch(acc, inv, px, py, pz, nx, ny, nz):
    """The touching points' spread in the contact plane: principal axes e1, e2 (unit, world,
    e2 = n x e1) and variances l1 >= l2 >= 0. The ellipse with those semi-axes squared is
    the region the contact's center of pressure may take: a point, an edge's segment, the
    ellipse inscribed in a rectangular face."""
    # an orthonormal tangent basis (t, u) of the contact plane
    if abs(nx) < 0.9:
        tx, ty, tz = ZERO * nx, -nz, ny  # n x (1, 0, 0)
    else:
        tx, ty, tz = nz, ZERO * nx, -nx  # (0, 1, 0) x n
    norm = ONE / math.sqrt(tx * tx + ty * ty + tz * tz)
    tx, ty, tz = tx * norm, ty * norm, tz * norm
    ux, uy, uz = ny * tz - nz * ty, nz * tx - nx * tz, nx * ty - ny * tx
    # the points' covariance, in the tangent basis
    cxx = acc[8] * inv - px * px
    cyy = acc[9] * inv - py * py
    czz = acc[10] * inv - pz * pz
    cxy = acc[11] * inv - px * py
    cxz = acc[12] * inv - px * pz
    cyz = acc[13] * inv - py * pz
    ctx = cxx * tx + cxy * ty + cxz * tz
    cty = cxy * tx + cyy * ty + cyz * tz
    ctz = cxz * tx + cyz * ty + czz * tz
    a = max(tx * ctx + ty * cty + tz * ctz, ZERO)
    c = max(
        ux * (cxx * ux + cxy * uy + cxz * uz)
        + uy * (cxy * ux + cyy * uy + cyz * uz)
        + uz * (cxz * ux + cyz * uy + czz * uz),
        ZERO,
    )
    b = ux * ctx + uy * cty + uz * ctz
    half = HALF * (a + c)
    root = math.sqrt(HALF * HALF * (a - c) * (a - c) + b * b)
    l1, l2 = half + root, max(half - root, ZERO)
    # the first axis: (b, l1 - a) or (l1 - c, b) in (t, u), whichever is not zero
    p1, p2 = b, l1 - a
    if abs(p1) + abs(p2) <= 1e-9 * (abs(a) + abs(c)) + TINY:
        p1, p2 = l1 - c, b
    if abs(p1) + abs(p2) <= TINY:
        p1, p2 = ONE + ZERO * a, ZERO * a
    norm = ONE / math.sqrt(p1 * p1 + p2 * p2)
    p1, p2 = p1 * norm, p2 * norm
    e1x, e1y, e1z = p1 * tx + p2 * ux, p1 * ty + p2 * uy, p1 * tz + p2 * uz
    e2x, e2y, e2z = ny * e1z - nz * e1y, nz * e1x - nx * e1z, nx * e1y - ny * e1x
    return (e1x, e1y, e1z), (e2x, e2y, e2z), l1, l2


# --------------------------------------------------------------------------------------------
# the solve: each touching pair as one contact, projected once, then velocity passes


# a contact's row in the work array W[pair, NW]
W_ON, W_A, W_B, W_P, W_N, W_E1, W_E2, W_L1, W_L2 = 0, 1, 2, 3, 6, 9, 12, 15, 16
W_GOAL, W_J, W_T1, W_T2, W_F1, W_F2, W_TW, W_MU, W_KE0, W_IMPACT = range(17, 27)
# and, in row b for body b: its velocity and spin before the contacts (recorded when its
# first contact opens), whether they are recorded, and whether it rests on something
W_V0, W_W0, W_REST, W_SEEN = 27, 30, 33, 34
NW = 35
# warm start, per environment and pair [E, num_pairs, NWARM]: the last step's accumulated
# impulses as world vectors (normal j, patch torque T (3), friction F (3), twist)
NWARM = 8
WARM_FACTOR = 1.0  # slightly less than all of it: a resting contact re-earns it each step


@njit(**_INLINE)
def num_pairs(num_bodies):
    """Rows of the work array: each body against the ground, then each pair of bodies."""
    return num_bodies + num_bodies * (num_bodies - 1) // 2


@njit(**_INLINE)
def _vec(W, k, f):
    return W[k, f], W[k, f + 1], W[k, f + 2]


@njit(**_INLINE)
def _relative(S, a, b, i, n, body, p):
    """Velocity at p and angular velocity of body a relative to b (b < 0: the ground)."""
    u, w = _motion(S, a, i, n, body, p)
    if b >= 0:
        ub, wb = _motion(S, b, i, n, body, p)
        u = (u[0] - ub[0], u[1] - ub[1], u[2] - ub[2])
        w = (w[0] - wb[0], w[1] - wb[1], w[2] - wb[2])
    return u, w


@njit(**_INLINE)
def _pair_wrench(S, a, b, i, n, body, p, jx, jy, jz, tx, ty, tz):
    """Impulse J at p and angular impulse T on a; their opposites on b."""
    _wrench(S, a, i, n, body, p, jx, jy, jz, tx, ty, tz)
    if b >= 0:
        _wrench(S, b, i, n, body, p, -jx, -jy, -jz, -tx, -ty, -tz)


@njit(**_INLINE)
def _remember(S, W, b, i, n, body):
    """Record body b's velocity and spin before any contact changes them (once per step):
    what a resting body is put back by (collide)."""
    if W[b, W_SEEN] != ZERO:
        return
    rot = _pose(S, b, i, n)[1]
    w = _omega(S, b, i, n, rot, body)
    for c in range(3):
        W[b, W_V0 + c] = S[b, i + (STATE + OV + c) * n]
        W[b, W_W0 + c] = w[c]
    W[b, W_SEEN] = ONE


@njit(**_JIT)
def _open(S, W, k, a, b, i, n, body, cbody, cprm, acc):
    """Open contact k from a pair's overlap sums: record it, push the bodies apart (stage 1)
    and set the normal velocity it aims for."""
    W[k, W_ON] = ZERO
    w = acc[0]
    if acc[7] <= ZERO or w <= ZERO:
        return
    nx, ny, nz = acc[4], acc[5], acc[6]
    norm = math.sqrt(nx * nx + ny * ny + nz * nz)
    if norm <= TINY:
        return  # opposed normals cancel: nothing to push along
    nx, ny, nz = nx / norm, ny / norm, nz / norm
    _remember(S, W, a, i, n, body)
    if b >= 0:
        _remember(S, W, b, i, n, body)
    inv = ONE / w
    px, py, pz = acc[1] * inv, acc[2] * inv, acc[3] * inv
    e1, e2, l1, l2 = _patch(acc, inv, px, py, pz, nx, ny, nz)
    ground = b < 0
    depth = acc[7]
    p = (px, py, pz)
    nrm = (nx, ny, nz)
    # materials: geometric means
    eb = cprm[C_GE] if ground else cbody[b, B_MASS]
    mub = cprm[C_GMU] if ground else cbody[b, CB_FRICTION]
    e = math.sqrt(cbody[a, B_MASS] * eb)
    un = _dot(_relative(S, a, b, i, n, body, p)[0], nrm)
    impact = -un > cprm[C_REST_SPEED]
    # 1. projection: out by the depth, mass-weighted between two bodies. A resting contact
    # is instead undone where the step moved the body (see collide); only a depth beyond
    # the margin, which that leaves, is pushed out here.
    d = depth if impact else max(depth - cprm[C_MARGIN], ZERO)
    if not impact:
        W[a, W_REST] = ONE
        if not ground:
            W[b, W_REST] = ONE
    ma = body[a, B_MASS]
    share = ONE if ground else body[b, B_MASS] / (ma + body[b, B_MASS])
    W[k, W_KE0] = _energy(S, a, i, n, body) + (ZERO if ground else _energy(S, b, i, n, body))
    # (a resting contact's push is pure translation, at the centers: pushed at the patch's
    # mean, an offset load would tip each body a little every step, and a stack would rock)
    xa = _pose(S, a, i, n)[0]
    qa = (px - xa[0], py - xa[1], pz - xa[2]) if impact else (ZERO * px, ZERO * px, ZERO * px)
    _displace(S, a, i, n, body, qa[0], qa[1], qa[2], nx, ny, nz, d * share)
    if not ground:
        xb = _pose(S, b, i, n)[0]
        qb = (px - xb[0], py - xb[1], pz - xb[2]) if impact else (ZERO * px, ZERO * px, ZERO * px)
        _displace(S, b, i, n, body, qb[0], qb[1], qb[2], -nx, -ny, -nz, d * (ONE - share))
    # the normal velocity to leave with: an impact bounces, a resting contact stays
    goal = -e * un if impact else ZERO * un
    if impact and ground:
        # Bounce with the speed it met the surface with, not the speed it reached d below
        # it: the push out by d works against gravity (g_n along the normal). The speed
        # that keeps the integrator's own free-flight energy, 1/2 v^2 + g z + c v_n with
        # c = (1/2 - share) g_n dt (exact for symplectic Euler, c = -g_n dt / 2; the true
        # energy for the Runge-Kutta methods, c = 0), across the push solves
        # u_s^2 + 2 c u_s = u^2 - 2 g_n d - 2 c u. Without it symplectic Euler lost up to
        # g u dt of energy per unit mass on a bounce and rk2 gained up to g d
        # (docs/study.md, Contact).
        g_n = cprm[C_G] * nz
        c = g_n * (HALF * cprm[C_DT] - cprm[C_UNDRIFT])
        u = -un
        u_s = -c + math.sqrt(max(c * c + u * u - TWO * g_n * d - TWO * c * u, ZERO))
        goal = e * u_s
        # the energy bound (_close) allows what the push gave (symplectic Euler's u_s can
        # pass u); lowering it by what a push took would freeze a body that a load above
        # pressed in (a heavy box on a light one fell apart)
        W[k, W_KE0] += HALF * ma * max(u_s * u_s - u * u, ZERO)
    W[k, W_ON] = ONE
    W[k, W_A], W[k, W_B] = a, b
    for c in range(3):
        W[k, W_P + c] = p[c]
        W[k, W_N + c] = nrm[c]
        W[k, W_E1 + c] = e1[c]
        W[k, W_E2 + c] = e2[c]
    W[k, W_L1], W[k, W_L2] = l1, l2
    W[k, W_GOAL] = goal
    W[k, W_MU] = math.sqrt(cbody[a, CB_FRICTION] * mub)
    W[k, W_IMPACT] = ONE if impact else ZERO
    for f in range(W_J, W_TW + 1):
        W[k, f] = ZERO


@njit(**_JIT)
def _warm_start(S, W, k, i, n, body, warm):
    """A resting contact that held last step starts from what it held (``warm``, world
    vectors), in its new frame: the passes then only correct it, and a stack settles in a
    few. Applied after every contact is opened, so that none is mistaken for an impact by
    another's warm start."""
    if W[k, W_ON] == ZERO or W[k, W_IMPACT] != ZERO or warm[k, 0] <= ZERO:
        return
    a, b = int(W[k, W_A]), int(W[k, W_B])
    p, nrm = _vec(W, k, W_P), _vec(W, k, W_N)
    e1, e2 = _vec(W, k, W_E1), _vec(W, k, W_E2)
    nx, ny, nz = nrm
    f = WARM_FACTOR
    j = f * warm[k, 0]
    t1 = f * (warm[k, 1] * e1[0] + warm[k, 2] * e1[1] + warm[k, 3] * e1[2])
    t2 = f * (warm[k, 1] * e2[0] + warm[k, 2] * e2[1] + warm[k, 3] * e2[2])
    f1 = f * (warm[k, 4] * e1[0] + warm[k, 5] * e1[1] + warm[k, 6] * e1[2])
    f2 = f * (warm[k, 4] * e2[0] + warm[k, 5] * e2[1] + warm[k, 6] * e2[2])
    tw = f * warm[k, 7]
    W[k, W_J], W[k, W_T1], W[k, W_T2] = j, t1, t2
    W[k, W_F1], W[k, W_F2], W[k, W_TW] = f1, f2, tw
    _pair_wrench(
        S, a, b, i, n, body, p,
        j * nx + f1 * e1[0] + f2 * e2[0],
        j * ny + f1 * e1[1] + f2 * e2[1],
        j * nz + f1 * e1[2] + f2 * e2[2],
        t1 * e1[0] + t2 * e2[0] + tw * nx,
        t1 * e1[1] + t2 * e2[1] + tw * ny,
        t1 * e1[2] + t2 * e2[2] + tw * nz,
    )  # fmt: skip


@njit(**_INLINE)
def _add_response(K, S, b, i, n, body, p, dirs):
    """Add body b's response to the contact's six unit impulses to K (6x6): linear along
    dirs 0-2 (n, e1, e2) at p, angular about dirs 3-5 (e1, e2, n). K[r, c] is the change of
    the relative motion measured by r (velocity at p along dir r, or spin about it) per
    unit impulse c."""
    x, rot = _pose(S, b, i, n)
    r = (p[0] - x[0], p[1] - x[1], p[2] - x[2])
    inv = body_inv_inertia(body, b)
    inv_m = ONE / body[b, B_MASS]
    # the angular effect of each impulse, c = r x a (linear) or b (angular), then I^-1 c
    c = np.empty((6, 3), dtype=K.dtype)
    ic = np.empty((6, 3), dtype=K.dtype)
    for q in range(6):
        d = (dirs[q, 0], dirs[q, 1], dirs[q, 2])
        cq = _cross(r, d) if q < 3 else d
        w = world_omega(rot, cq[0], cq[1], cq[2], inv)
        for m in range(3):
            c[q, m] = cq[m]
            ic[q, m] = w[m]
    for q in range(6):
        for m in range(6):
            v = c[q, 0] * ic[m, 0] + c[q, 1] * ic[m, 1] + c[q, 2] * ic[m, 2]
            if q < 3 and m < 3:
                v += inv_m * (
                    dirs[q, 0] * dirs[m, 0] + dirs[q, 1] * dirs[m, 1] + dirs[q, 2] * dirs[m, 2]
                )
            K[q, m] += v


@njit(**_INLINE)
def _solve6(K, rhs, use):
    """x with K x = rhs over the dimensions in ``use`` (the others zero), K symmetric
    positive definite (6x6): Cholesky on a copy."""
    L = K.copy()
    x = rhs.copy()
    for q in range(6):  # a left-out impulse: identity row, zero change
        if not use[q]:
            for m in range(6):
                L[q, m] = ZERO
                L[m, q] = ZERO
            L[q, q] = ONE
            x[q] = ZERO
    for q in range(6):  # L L^T, in the lower triangle
        for m in range(q + 1):
            v = L[q, m]
            for t in range(m):
                v -= L[q, t] * L[m, t]
            if q == m:
                L[q, q] = math.sqrt(max(v, TINY))
            else:
                L[q, m] = v / L[m, m]
    for q in range(6):
        v = x[q]
        for t in range(q):
            v -= L[q, t] * x[t]
        x[q] = v / L[q, q]
    for q in range(5, -1, -1):
        v = x[q]
        for t in range(q + 1, 6):
            v -= L[t, q] * x[t]
        x[q] = v / L[q, q]
    return x


@njit(**_JIT)
def _pass(S, W, k, i, n, body):
    """One velocity pass over contact k (stage 2, projected Gauss-Seidel): the impulse that
    makes the pair's relative motion at the patch what it should be, clamped to what the
    patch can give, added to what it gave before.

    The patch holds the pair with six impulses: a push j along n at its mean point,
    friction F along e1 and e2 there, a torque T about e1 and e2 (a push off the mean: the
    center of pressure d = n x T / j), and a twist about n. They are solved together (6x6,
    Cholesky), aiming at the normal velocity ``W_GOAL`` and no sliding, tipping or
    twisting; then clamped: j >= 0, |F| <= mu j (Coulomb), d inside the patch (the ellipse
    of its spread: an edge holds no torque about itself, a point none), |twist| <= mu j
    (2/3) R (a pressed disc of radius R). A dimension the patch cannot hold (friction
    without mu, torque without extent) is left out of the solve."""
    a, b = int(W[k, W_A]), int(W[k, W_B])
    p, nrm = _vec(W, k, W_P), _vec(W, k, W_N)
    e1, e2 = _vec(W, k, W_E1), _vec(W, k, W_E2)
    l1, l2 = W[k, W_L1], W[k, W_L2]
    mu = W[k, W_MU]
    floor = 1e-12 + ZERO * l1  # m^2: under a micron of spread, no extent
    has1 = l1 > floor
    has2 = l2 > floor and l2 > 1e-6 * l1
    radius = math.sqrt(TWO * (l1 + l2))
    dirs = np.empty((6, 3), dtype=W.dtype)
    for m in range(3):
        dirs[0, m], dirs[1, m], dirs[2, m] = nrm[m], e1[m], e2[m]
        dirs[3, m], dirs[4, m], dirs[5, m] = e1[m], e2[m], nrm[m]
    # which impulses the patch can give: push; friction; torque about e1 (needs extent
    # along e2), about e2 (extent along e1); twist (extent and friction)
    use = (True, mu > ZERO, mu > ZERO, has2, has1, has1 and mu > ZERO)
    K = np.zeros((6, 6), dtype=W.dtype)
    _add_response(K, S, a, i, n, body, p, dirs)
    if b >= 0:
        _add_response(K, S, b, i, n, body, p, dirs)
    u, w = _relative(S, a, b, i, n, body, p)
    rhs = np.empty(6, dtype=W.dtype)
    rhs[0] = W[k, W_GOAL] - _dot(u, nrm)
    rhs[1], rhs[2] = -_dot(u, e1), -_dot(u, e2)
    rhs[3], rhs[4], rhs[5] = -_dot(w, e1), -_dot(w, e2), -_dot(w, nrm)
    x = _solve6(K, rhs, use)
    # friction beyond the cone: hold it at the cone's edge and solve the rest again with it
    # fixed (a torque sized for the unclamped friction would tip the body the other way)
    j0, f10, f20 = W[k, W_J], W[k, W_F1], W[k, W_F2]
    f1, f2 = f10 + x[1], f20 + x[2]
    f = math.sqrt(f1 * f1 + f2 * f2)
    cone = mu * max(j0 + x[0], ZERO)
    if f > cone and (use[1] or use[2]):
        scale = cone / f
        d1, d2 = f1 * scale - f10, f2 * scale - f20
        for q in range(6):
            rhs[q] -= K[q, 1] * d1 + K[q, 2] * d2
        use = (True, False, False, use[3], use[4], use[5])
        x = _solve6(K, rhs, use)
        x[1], x[2] = d1, d2
    # add to what it gave, and clamp
    t10, t20, tw0 = W[k, W_T1], W[k, W_T2], W[k, W_TW]
    j = max(j0 + x[0], ZERO)
    f1, f2 = f10 + x[1], f20 + x[2]
    t1, t2, tw = t10 + x[3], t20 + x[4], tw0 + x[5]
    f = math.sqrt(f1 * f1 + f2 * f2)
    if f > mu * j:
        scale = mu * j / f
        f1, f2 = f1 * scale, f2 * scale
    if j <= TINY:
        t1, t2 = ZERO * j, ZERO * j
    else:  # the center of pressure in the patch: d1 = -T2 / j, d2 = T1 / j
        m2 = (t2 * t2 / (j * j * l1) if has1 else ZERO * j) + (
            t1 * t1 / (j * j * l2) if has2 else ZERO * j
        )
        if m2 > ONE:
            scale = ONE / math.sqrt(m2)
            t1, t2 = t1 * scale, t2 * scale
    cap = mu * j * radius * TWO_THIRDS
    tw = min(max(tw, -cap), cap)
    W[k, W_J], W[k, W_F1], W[k, W_F2] = j, f1, f2
    W[k, W_T1], W[k, W_T2], W[k, W_TW] = t1, t2, tw
    dj, df1, df2 = j - j0, f1 - f10, f2 - f20
    dt1, dt2, dtw = t1 - t10, t2 - t20, tw - tw0
    _pair_wrench(
        S, a, b, i, n, body, p,
        dj * nrm[0] + df1 * e1[0] + df2 * e2[0],
        dj * nrm[1] + df1 * e1[1] + df2 * e2[1],
        dj * nrm[2] + df1 * e1[2] + df2 * e2[2],
        dt1 * e1[0] + dt2 * e2[0] + dtw * nrm[0],
        dt1 * e1[1] + dt2 * e2[1] + dtw * nrm[1],
        dt1 * e1[2] + dt2 * e2[2] + dtw * nrm[2],
    )  # fmt: skip


@njit(**_JIT)
def _close(S, W, k, i, n, body, cprm):
    """Stage 3, after an impact: the pair's kinetic energy never above the bound times its
    value before the contact (the seed's correction), scaled back about the pair's center
    of mass."""
    if W[k, W_IMPACT] == ZERO:
        return
    a, b = int(W[k, W_A]), int(W[k, W_B])
    ground = b < 0
    ke0 = W[k, W_KE0]
    ke1 = _energy(S, a, i, n, body) + (ZERO if ground else _energy(S, b, i, n, body))
    bound = ONE if ground else cprm[C_PAIR_BOUND]
    if ke1 <= bound * ke0 or ke1 <= TINY:
        return
    if ground:
        _scale_velocities(S, a, -1, i, n, body, math.sqrt(ke0 / ke1))
        return
    ma, mb = body[a, B_MASS], body[b, B_MASS]
    vc2 = ZERO * ke1
    for c in range(3):
        vc = (ma * S[a, i + (STATE + OV + c) * n] + mb * S[b, i + (STATE + OV + c) * n]) / (ma + mb)
        vc2 += vc * vc
    bulk = HALF * (ma + mb) * vc2  # unchanged by the pair's internal impulses
    inner = max(ke1 - bulk, TINY)
    _scale_velocities(S, a, b, i, n, body, math.sqrt(max(ke0 - bulk, ZERO) / inner))


@njit(**_INLINE)
def _near_ground(S, b, i, n, cbody, cprm):
    """Whether body b's reach comes within the margin of the ground's highest point."""
    if cprm[C_GROUND] == GROUND_NONE:
        return False
    return S[b, i + (STATE + OX + 2) * n] - cbody[b, CB_REACH] <= cprm[C_GTOP] + cprm[C_MARGIN]


@njit(**_INLINE)
def _near_each_other(S, a, b, i, n, cbody, margin):
    """Whether bodies a and b are within their reaches (plus the margin) of each other."""
    dx = S[a, i + (STATE + OX) * n] - S[b, i + (STATE + OX) * n]
    dy = S[a, i + (STATE + OX + 1) * n] - S[b, i + (STATE + OX + 1) * n]
    dz = S[a, i + (STATE + OX + 2) * n] - S[b, i + (STATE + OX + 2) * n]
    reach = cbody[a, CB_REACH] + cbody[b, CB_REACH] + margin
    return dx * dx + dy * dy + dz * dz <= reach * reach


@njit(**_INLINE)
def may_touch(S, nb, i, n, cbody, cprm, warm):
    """Whether environment i needs ``collide`` this step: a body within reach of the ground's
    highest point or of another body, or a contact held last step (whose warm start must be
    forgotten if it let go). Most steps of a flying or sailing scene need nothing."""
    margin = cprm[C_MARGIN]
    for c in range(warm.shape[0]):
        if warm[c, 0] != ZERO:
            return True
    for b in range(nb):
        if _near_ground(S, b, i, n, cbody, cprm):
            return True
        for a in range(b):
            if _near_each_other(S, a, b, i, n, cbody, margin):
                return True
    return False


@njit(**_JIT)
def collide(S, nb, i, n, body, shp, srange, grid, cbody, cprm, W, warm, touch):
    """All contacts of environment i (its bodies' state in the scratch S: element k of body
    b at ``S[b, i + k * n]``; W a work array [num_pairs(nb), NW]; ``warm`` the environment's
    warm-start impulses [num_pairs(nb), NWARM], updated; ``touch`` [num_pairs(nb)] each
    pair's normal impulse, added to: the ground's on each body, then each pair of bodies).
    Each body against the ground, then every pair of bodies whose shapes' reaches overlap:
    each touching pair is one contact, opened (pushed apart, warm-started) as found; then
    ``C_PASSES`` velocity passes over them all; then the energy check of the impacts; then
    the resting bodies' positions are put back where the velocity the contacts took away
    had carried them this step."""
    for b in range(nb):  # nothing recorded yet: most bodies touch nothing most steps
        W[b, W_REST] = ZERO
        W[b, W_SEEN] = ZERO
    k = 0
    margin = cprm[C_MARGIN]
    for b in range(nb):
        W[k, W_ON] = ZERO
        if _near_ground(S, b, i, n, cbody, cprm):  # (a body clear above it is not visited)
            acc = _ground_overlap(S, b, i, n, shp, srange, grid, cprm)
            _open(S, W, k, b, -1, i, n, body, cbody, cprm, acc)
        k += 1
    for a in range(nb):
        for b in range(a + 1, nb):
            W[k, W_ON] = ZERO
            if _near_each_other(S, a, b, i, n, cbody, margin):
                acc = _pair_overlap(S, a, b, i, n, shp, srange, margin)
                _open(S, W, k, a, b, i, n, body, cbody, cprm, acc)
            k += 1
    opened = 0  # (the calls below are not inlined: skip them for the pairs apart)
    for c in range(k):
        if W[c, W_ON] != ZERO:
            opened += 1
            _warm_start(S, W, c, i, n, body, warm)
    for _ in range(int(cprm[C_PASSES]) if opened else 0):
        for c in range(k):
            if W[c, W_ON] != ZERO:
                _pass(S, W, c, i, n, body)
    for c in range(k):
        if W[c, W_ON] != ZERO:
            _close(S, W, c, i, n, body, cprm)
            touch[c] += W[c, W_J]
        _keep(W, c, warm)
    # A body at rest was carried into its support by the step's drift (symplectic Euler:
    # x += dt v, after gravity's kick) before its contacts took that velocity away: undo
    # that part of the drift, x += dt dv and the same for the turn, times the share of the
    # velocity change the integrator's drift carried (C_UNDRIFT = share dt: half for the
    # Runge-Kutta methods; undoing all of it lifts a resting body g dt^2 / 2 a step and a
    # stack walks apart). Unlike a push along the normal this moves it exactly back along
    # the way it came, so friction that holds it also holds its position (a push along a
    # sloped normal would walk it downhill).
    dt = cprm[C_UNDRIFT]
    for b in range(nb):
        if W[b, W_REST] == ZERO:
            continue
        rot = _pose(S, b, i, n)[1]
        w = _omega(S, b, i, n, rot, body)
        for c in range(3):
            S[b, i + (STATE + OX + c) * n] += dt * (S[b, i + (STATE + OV + c) * n] - W[b, W_V0 + c])
        _turn(
            S, b, i, n,
            dt * (w[0] - W[b, W_W0]),
            dt * (w[1] - W[b, W_W0 + 1]),
            dt * (w[2] - W[b, W_W0 + 2]),
        )  # fmt: skip


@njit(**_INLINE)
def _keep(W, k, warm):
    """Store contact k's accumulated impulses as world vectors for the next step's start
    (zeros when it is not touching, or bounced)."""
    if W[k, W_ON] == ZERO or W[k, W_IMPACT] != ZERO:
        if warm[k, 0] != ZERO:  # (held last step: forget it; a pair apart stays zeros)
            for f in range(NWARM):
                warm[k, f] = ZERO
        return
    e1, e2 = _vec(W, k, W_E1), _vec(W, k, W_E2)
    warm[k, 0] = W[k, W_J]
    for c in range(3):
        warm[k, 1 + c] = W[k, W_T1] * e1[c] + W[k, W_T2] * e2[c]
        warm[k, 4 + c] = W[k, W_F1] * e1[c] + W[k, W_F2] * e2[c]
    warm[k, 7] = W[k, W_TW]


# --------------------------------------------------------------------------------------------
# packing


def shape_rows(craft) -> list[tuple]:
    """The rows of a craft's collision shapes (``SH_*`` columns), in the craft's order."""
    rows = []
    for s in craft.shapes:
        size = (s.radius_m, 0.0, 0.0) if s.kind == "sphere" else s.half_extents_m
        rows.append((SPHERE if s.kind == "sphere" else BOX, *s.center_m, *size, s.reach_m))
    return rows


def material_row(craft) -> tuple:
    """A craft's ``CB_*`` row: restitution, friction, the reach of all its shapes."""
    reach = max((s.reach_m for s in craft.shapes), default=0.0)
    return (craft.restitution, craft.friction, reach)


def params(crafts, ground, dt: float, gravity: float, passes: int, drift_share: float):
    """The contact parameters ``cprm[NCPRM]`` (float64; ``drift_share``: the integrator's
    ``integrators.Integrator.drift_share``) and the ground's grid (float64)."""
    prm = ground.params() if ground is not None else np.zeros(NCPRM)
    has_shapes = any(c.shapes for c in crafts)
    prm[C_ON] = 1.0 if has_shapes and (ground is not None or len(crafts) > 1) else 0.0
    # below this approach speed a contact is resting: no bounce (gravity's gain in 2 steps)
    prm[C_REST_SPEED] = 2.0 * gravity * dt
    prm[C_UNDRIFT] = drift_share * dt  # what a resting body's drift is undone by (collide)
    prm[C_G] = gravity
    prm[C_DT] = dt
    # points this close above a surface join a touching pair's contact (gravity's fall in 2
    # steps): the margin that keeps resting faces from rocking
    prm[C_MARGIN] = 2.0 * gravity * dt * dt
    prm[C_PAIR_BOUND] = PAIR_ENERGY_BOUND
    prm[C_PASSES] = passes
    grid = ground.field_table(np.float64) if ground is not None else np.zeros((1, 1))
    return prm, grid
