"""Tracer particles in the submarine's wake: what a viewer sees of the flow.

The wake (:mod:`.wake`) is a velocity field, not a state, so nothing has to be integrated for
the physics. Particles that make it visible are integrated only when someone looks (logging,
rendering): :class:`Tracers` keeps a few thousand massless points in a box that travels with
the hull and moves each with the water's velocity there (still water + wake, world frame: a
tracer far from the hull stays where it is). When the hull has left a tracer behind the box,
the tracer is put back in at the opposite face, so the box stays evenly filled.

Two ways to get a tracer's velocity, same integrator (the midpoint rule):

- ``macro=0`` (default): the field itself, :func:`.wake.wake_at`, twice per substep.
- ``macro=M``: the seed's "macro particles". About M spheres on a lattice fixed in the hull
  frame each sample the field once per :meth:`Tracers.advance` (velocity at the center, and
  angular velocity = half the curl there, by central differences); a tracer takes the blend
  ``sum w (v + omega x r) / sum w`` of the spheres that contain it, ``w = (1 - d^2/R^2)^2``,
  found through a uniform-grid spatial hash (:class:`SpatialHash`). The field is then
  evaluated 7 M times per advance whatever the number of tracers; the blend smooths the flow
  on the lattice's scale (vortex cores narrower than the lattice spacing come out wider
  and weaker). Measured (benchmarks/bench_wake.py): a blend costs about as much as one
  evaluation of this closed-form field, so here the macro path is the seed's idea shown,
  not a saving; it pays only for a field much dearer than its hash lookup.

Time: :meth:`Tracers.advance` takes the submarine's state at the end of the interval (now)
and assumes it moved at that velocity with that heading during the interval, so the field at
time ``t`` is the field of a hull at ``sub_pos + sub_lin_vel (t - now)``.

Determinism: positions come from the generator passed to :meth:`Tracers.reset`; recycling
draws from a generator the tracers derive from it and own. Kernels write only their own
particle's slots, so results do not depend on the thread count.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit, prange

from . import checks as CK
from .wake import WakeField, source_row, source_tuple, wake_at, wake_velocity_batch

_JIT = dict(cache=True, error_model="numpy", fastmath={"contract"})
_INLINE = dict(_JIT, inline="always")

PARALLEL_MIN = 1024  # tracers from which the kernels run on numba's threads by default
FD_STEP = 1e-3  # central-difference step for the curl, as a fraction of the hull radius
_PAD = 1.0 + 1e-9  # widens a hash query by a hair so rounding never drops a neighbour cell


# --------------------------------------------------------------------------------------------
# spatial hash (uniform grid cells hashed into a power-of-two table, built by counting sort)

_BITS = 0x1FFFFF  # 21 bits of each cell coordinate in a cell's key
_GOLDEN = -7046029254386353131  # 0x9E3779B97F4A7C15 as a signed 64-bit integer
D_R2, D_INV_R2 = 3, 4  # per-sphere row of the hash's data: center x, y, z, then R^2, 1/R^2


@njit(**_INLINE)
def _key(ix, iy, iz):
    """One integer per grid cell. Cells 2^21 apart share a key, but never two cells that one
    query visits, and a sphere so far away fails the distance test anyway."""
    return (ix & _BITS) | ((iy & _BITS) << 21) | ((iz & _BITS) << 42)


@njit(**_INLINE)
def _slot(key, mask):
    """Table slot of a cell key (multiplicative hashing)."""
    h = key * _GOLDEN
    return (h ^ (h >> 29)) & mask


@njit(**_INLINE)
def _cell_of(x, inv_cell):
    return np.int64(math.floor(x * inv_cell))


@njit(**_JIT)
def _build_hash(centers, r2, inv_cell, mask, start, count, keys, order, data):
    """Counting sort of the spheres by table slot: entries ``start[s] : start[s] + count[s]``
    hold slot s's spheres, in ascending index: their cell key, their index in ``order`` and
    their center and radius in ``data`` (contiguous, so a query reads one run of memory)."""
    count[:] = 0
    for j in range(centers.shape[0]):
        k = _key(
            _cell_of(centers[j, 0], inv_cell),
            _cell_of(centers[j, 1], inv_cell),
            _cell_of(centers[j, 2], inv_cell),
        )
        keys[j] = k  # unsorted for now
        count[_slot(k, mask)] += 1
    acc = 0
    for s in range(mask + 1):
        start[s] = acc
        acc += count[s]
    cursor = start.copy()
    unsorted = keys.copy()
    for j in range(centers.shape[0]):
        s = _slot(unsorted[j], mask)
        q = cursor[s]
        cursor[s] += 1
        keys[q] = unsorted[j]
        order[q] = j
        data[q, 0], data[q, 1], data[q, 2] = centers[j, 0], centers[j, 1], centers[j, 2]
        data[q, D_R2] = r2[j]
        data[q, D_INV_R2] = 1.0 / r2[j]


@njit(**_INLINE)
def _query_range(p, inv_cell, reach):
    """First and last grid cell along one axis that can hold a sphere containing p."""
    return _cell_of(p - reach, inv_cell), _cell_of(p + reach, inv_cell)


@njit(**_JIT)
def _blend_at(px, py, pz, hp, mask, start, count, keys, data, motion):
    """Velocity at p of the spheres that contain it, each moving rigidly (``motion`` rows:
    v, omega): sum w (v + omega x r) / sum w with w = (1 - d^2/R^2)^2 (smooth, zero at the
    rim). Zero where no sphere reaches."""
    if not (math.isfinite(px) and math.isfinite(py) and math.isfinite(pz)):
        return 0.0, 0.0, 0.0
    inv, reach = hp[0], hp[1]
    x0, x1 = _query_range(px, inv, reach)
    y0, y1 = _query_range(py, inv, reach)
    z0, z1 = _query_range(pz, inv, reach)
    wsum = vx = vy = vz = 0.0
    for cx in range(x0, x1 + 1):
        for cy in range(y0, y1 + 1):
            for cz in range(z0, z1 + 1):
                k = _key(cx, cy, cz)
                s = _slot(k, mask)
                for q in range(start[s], start[s] + count[s]):
                    if keys[q] != k:
                        continue  # another cell hashed to the same slot
                    dx = px - data[q, 0]
                    dy = py - data[q, 1]
                    dz = pz - data[q, 2]
                    d2 = dx * dx + dy * dy + dz * dz
                    if d2 < data[q, D_R2]:
                        t = 1.0 - d2 * data[q, D_INV_R2]
                        w = t * t
                        wsum += w
                        vx += w * (motion[q, 0] + motion[q, 4] * dz - motion[q, 5] * dy)
                        vy += w * (motion[q, 1] + motion[q, 5] * dx - motion[q, 3] * dz)
                        vz += w * (motion[q, 2] + motion[q, 3] * dy - motion[q, 4] * dx)
    if wsum > 0.0:
        return vx / wsum, vy / wsum, vz / wsum
    return 0.0, 0.0, 0.0


@njit(**_JIT)
def _blend_batch(points, hp, mask, start, count, keys, data, motion, out):
    for i in range(points.shape[0]):
        v = _blend_at(
            points[i, 0], points[i, 1], points[i, 2], hp, mask, start, count, keys, data, motion
        )
        out[i, 0], out[i, 1], out[i, 2] = v[0], v[1], v[2]


@njit(**_JIT)
def _hash_pairs(points, hp, mask, start, count, keys, order, data, offset, out):
    """Count the spheres containing each point into ``offset[i + 1]`` (``out`` empty), or
    write the (point, sphere) pairs from ``offset[i]`` on (``out`` sized by the counts)."""
    fill = out.shape[0] > 0
    inv, reach = hp[0], hp[1]
    for i in range(points.shape[0]):
        px, py, pz = points[i, 0], points[i, 1], points[i, 2]
        x0, x1 = _query_range(px, inv, reach)
        y0, y1 = _query_range(py, inv, reach)
        z0, z1 = _query_range(pz, inv, reach)
        n = 0
        for cx in range(x0, x1 + 1):
            for cy in range(y0, y1 + 1):
                for cz in range(z0, z1 + 1):
                    k = _key(cx, cy, cz)
                    s = _slot(k, mask)
                    for q in range(start[s], start[s] + count[s]):
                        if keys[q] != k:
                            continue
                        dx = px - data[q, 0]
                        dy = py - data[q, 1]
                        dz = pz - data[q, 2]
                        if dx * dx + dy * dy + dz * dz < data[q, D_R2]:
                            if fill:
                                out[offset[i] + n, 0] = i
                                out[offset[i] + n, 1] = order[q]
                            n += 1
        if not fill:
            offset[i + 1] = n


def _points(name, value) -> np.ndarray:
    a = np.asarray(value, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name} must have shape [N, 3], got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} has non-finite values")
    return np.ascontiguousarray(a)


def _positive(name, value, integer=False) -> float:
    return CK.number("Tracers", name, value, gt=0, integer=integer)


class SpatialHash:
    """Spheres binned in a uniform grid whose cells are hashed into a table, for "which
    spheres contain this point" in constant time.

    A query visits the cells within the largest radius of the point (with radii <= the cell
    size: its own cell and the 26 around it; with radii <= half of it, 8 cells) and keeps the
    spheres whose own cell is the one visited (so a table collision never counts a sphere
    twice) and that contain the point.

    Args:
        cell_size_m: grid spacing (radii above it work, at the cost of visiting more cells).
        centers: [M, 3] sphere centers (world frame).
        radii: [M] or a scalar, sphere radii (> 0).
    """

    def __init__(self, cell_size_m: float, centers, radii) -> None:
        self.cell_size_m = _positive("cell_size_m", cell_size_m)
        c = _points("centers", centers)
        m = c.shape[0]
        if m == 0:
            raise ValueError("centers must hold at least one sphere, got 0")
        r = np.asarray(radii, dtype=np.float64)
        if r.shape not in ((), (m,)):
            raise ValueError(f"radii must be a scalar or have shape [{m}], got {r.shape}")
        if not np.all(np.isfinite(r)) or np.any(r <= 0):
            raise ValueError(f"radii must be finite and > 0, got {radii!r}")
        self.radii = np.array(np.broadcast_to(r, (m,)))
        size = 16
        while size < 2 * m:
            size *= 2
        self._mask = size - 1
        self._hp = np.array([1.0 / self.cell_size_m, float(self.radii.max()) * _PAD])
        self._start = np.empty(size, np.int64)
        self._count = np.empty(size, np.int64)
        self._keys = np.empty(m, np.int64)
        self._order = np.empty(m, np.int64)
        self._data = np.empty((m, 5))
        self._motion = np.zeros((m, 6))  # v, omega of each sphere, in the hash's order
        self.centers = np.empty((m, 3))
        self.update(c)

    def update(self, centers) -> None:
        """Move the spheres (same count and radii) and bin them again."""
        c = _points("centers", centers)
        if c.shape != self.centers.shape:
            raise ValueError(f"centers must have shape {self.centers.shape}, got {c.shape}")
        self.centers[:] = c
        self._build()

    def _build(self) -> None:
        _build_hash(
            self.centers,
            self.radii**2,
            self._hp[0],
            self._mask,
            self._start,
            self._count,
            self._keys,
            self._order,
            self._data,
        )

    def _set_motion(self, lin_vel, ang_vel) -> None:
        np.take(lin_vel, self._order, axis=0, out=self._motion[:, :3])
        np.take(ang_vel, self._order, axis=0, out=self._motion[:, 3:])

    def _table(self):
        return self._hp, self._mask, self._start, self._count, self._keys

    def pairs(self, points) -> np.ndarray:
        """[K, 2] (point index, sphere index) of every sphere strictly containing a point,
        sorted by point then sphere."""
        p = _points("points", points)
        offset = np.zeros(p.shape[0] + 1, np.int64)
        args = (*self._table(), self._order, self._data)
        _hash_pairs(p, *args, offset, np.empty((0, 2), np.int64))
        np.cumsum(offset, out=offset)
        out = np.empty((offset[-1], 2), np.int64)
        if len(out):
            _hash_pairs(p, *args, offset, out)
        return out[np.lexsort((out[:, 1], out[:, 0]))]

    def blend(self, points, lin_vel, ang_vel) -> np.ndarray:
        """[N, 3] velocity at points of spheres moving rigidly (``lin_vel``, ``ang_vel`` [M, 3]
        about their centers), blended by ``(1 - d^2/R^2)^2``; zero outside every sphere."""
        p = _points("points", points)
        for name, a in (("lin_vel", lin_vel), ("ang_vel", ang_vel)):
            if _points(name, a).shape != self.centers.shape:
                raise ValueError(f"{name} must have shape {self.centers.shape}, got {np.shape(a)}")
        self._set_motion(np.asarray(lin_vel, np.float64), np.asarray(ang_vel, np.float64))
        out = np.empty_like(p)
        _blend_batch(p, *self._table(), self._data, self._motion, out)
        return out


# --------------------------------------------------------------------------------------------
# macro particles: spheres that sample the field (velocity and half its curl)


@njit(**_JIT)
def _sample_spheres(centers, src, wprm, h, lin, ang):
    """lin[j] = field at centers[j]; ang[j] = half its curl there (central differences of
    step h along the world axes: six more evaluations)."""
    s = source_tuple(src)
    inv = 0.5 / h
    for j in range(centers.shape[0]):
        x, y, z = centers[j, 0], centers[j, 1], centers[j, 2]
        v = wake_at(x, y, z, s, wprm)
        xp = wake_at(x + h, y, z, s, wprm)
        xm = wake_at(x - h, y, z, s, wprm)
        yp = wake_at(x, y + h, z, s, wprm)
        ym = wake_at(x, y - h, z, s, wprm)
        zp = wake_at(x, y, z + h, s, wprm)
        zm = wake_at(x, y, z - h, s, wprm)
        lin[j, 0], lin[j, 1], lin[j, 2] = v[0], v[1], v[2]
        # omega = curl / 2 = ((dvz/dy - dvy/dz), (dvx/dz - dvz/dx), (dvy/dx - dvx/dy)) / 2
        ang[j, 0] = 0.5 * ((yp[2] - ym[2]) - (zp[1] - zm[1])) * inv
        ang[j, 1] = 0.5 * ((zp[0] - zm[0]) - (xp[2] - xm[2])) * inv
        ang[j, 2] = 0.5 * ((xp[1] - xm[1]) - (yp[0] - ym[0])) * inv


def _box(box_m) -> tuple[np.ndarray, np.ndarray]:
    b = np.asarray(box_m, dtype=np.float64)
    if b.shape != (3, 2):
        raise ValueError(f"box_m must have shape [3, 2] ((lo, hi) per body axis), got {b.shape}")
    if not np.all(np.isfinite(b)) or np.any(b[:, 0] >= b[:, 1]):
        raise ValueError(f"box_m must be finite with lo < hi on every axis, got {b.tolist()}")
    return np.ascontiguousarray(b[:, 0]), np.ascontiguousarray(b[:, 1])


def default_box(wake: WakeField) -> tuple[tuple[float, float], ...]:
    """Body-frame box (lo, hi per axis) of the tracers: from two hull lengths behind the
    center to a quarter length ahead of the bow, three radii either side."""
    L, R = wake.length_m, wake.radius_m
    return ((-2.0 * L, 0.75 * L), (-3.0 * R, 3.0 * R), (-3.0 * R, 3.0 * R))


class MacroParticles:
    """About ``count`` spheres on a lattice fixed in the hull frame, filling ``box_m``.

    The spacing is as even as the box allows; the radius, ``sqrt((hx^2 + hy^2 + hz^2) / 3)``,
    reaches past the half-diagonal of a lattice cell, so every point of the box lies in at
    least one sphere with a weight of 1/16 or more. Their hash has cells of two radii, so a
    query visits 8 cells. After :meth:`sample`: ``centers``, ``lin_vel``, ``ang_vel`` [M, 3]
    (world frame) and ``radius_m``.
    """

    def __init__(self, wake: WakeField, box_m, count: int) -> None:
        if not isinstance(wake, WakeField):
            raise TypeError(f"wake must be a WakeField, got {wake!r}")
        count = _positive("count", count, integer=True)
        lo, hi = _box(box_m)
        size = hi - lo
        h = (np.prod(size) / count) ** (1.0 / 3.0)
        n = np.maximum(1, np.rint(size / h)).astype(np.int64)
        step = size / n
        axes = [lo[k] + (np.arange(n[k]) + 0.5) * step[k] for k in range(3)]
        self.local = np.stack([g.ravel() for g in np.meshgrid(*axes, indexing="ij")], axis=1)
        self.radius_m = float(np.sqrt(np.sum(step**2) / 3.0))
        self.count = len(self.local)
        self.fd_step_m = FD_STEP * wake.radius_m
        self._wprm = wake.params()
        self.centers = self.local.copy()
        self.lin_vel = np.zeros_like(self.local)
        self.ang_vel = np.zeros_like(self.local)
        self.hash = SpatialHash(2.0 * self.radius_m, self.local, self.radius_m)

    def sample(self, sub_pos, sub_quat, sub_lin_vel, noise_offset=(0.0, 0.0, 0.0)) -> None:
        """Place the lattice at the hull's pose and sample the field on it."""
        self._sample_src(source_row(sub_pos, sub_quat, sub_lin_vel, noise_offset))

    def _sample_src(self, src: np.ndarray) -> None:
        np.matmul(self.local, src[3:12].reshape(3, 3).T, out=self.centers)
        self.centers += src[:3]
        self.hash.update(self.centers)
        _sample_spheres(self.centers, src, self._wprm, self.fd_step_m, self.lin_vel, self.ang_vel)
        self.hash._set_motion(self.lin_vel, self.ang_vel)

    def velocity(self, points) -> np.ndarray:
        """[N, 3] blended velocity of the spheres at world points (see the module docstring)."""
        return self.hash.blend(points, self.lin_vel, self.ang_vel)


def sample_macro(wake: WakeField, centers, sub_pos, sub_quat, sub_lin_vel, noise_offset=(0, 0, 0)):
    """(lin_vel, ang_vel) [M, 3] of macro particles at world ``centers`` [M, 3]: the field
    there and half its curl (central differences, step ``FD_STEP`` hull radii)."""
    if not isinstance(wake, WakeField):
        raise TypeError(f"wake must be a WakeField, got {wake!r}")
    c = _points("centers", centers)
    src = source_row(sub_pos, sub_quat, sub_lin_vel, noise_offset)
    lin, ang = np.empty_like(c), np.empty_like(c)
    _sample_spheres(c, src, wake.params(), FD_STEP * wake.radius_m, lin, ang)
    return lin, ang


# --------------------------------------------------------------------------------------------
# tracers


@njit(**_INLINE)
def _src_at(src, t):
    """Source tuple of a hull that keeps its velocity and heading for time t (t < 0: earlier)."""
    return (
        src[0] + src[12] * t, src[1] + src[13] * t, src[2] + src[14] * t,
        src[3], src[4], src[5], src[6], src[7], src[8], src[9], src[10], src[11],
        src[12], src[13], src[14], src[15], src[16], src[17],
    )  # fmt: skip


@njit(**_INLINE)
def _outside(px, py, pz, src, lo, hi):
    """Whether world point p lies outside the body-frame box (lo, hi) of the hull ``src``
    (NaN counts as outside)."""
    dx, dy, dz = px - src[0], py - src[1], pz - src[2]
    x = src[3] * dx + src[6] * dy + src[9] * dz
    y = src[4] * dx + src[7] * dy + src[10] * dz
    z = src[5] * dx + src[8] * dy + src[11] * dz
    return not (lo[0] <= x <= hi[0] and lo[1] <= y <= hi[1] and lo[2] <= z <= hi[2])


@njit(**_JIT)
def _exact_one(i, pos, speed, outside, src, wprm, dt, substeps, lo, hi):
    """Midpoint rule with the field itself over ``substeps`` substeps that end now."""
    h = dt / substeps
    px, py, pz = pos[i, 0], pos[i, 1], pos[i, 2]
    bx = by = bz = 0.0
    for k in range(substeps):
        t0 = -(substeps - k) * h
        ax, ay, az = wake_at(px, py, pz, _src_at(src, t0), wprm)
        qx, qy, qz = px + 0.5 * h * ax, py + 0.5 * h * ay, pz + 0.5 * h * az
        bx, by, bz = wake_at(qx, qy, qz, _src_at(src, t0 + 0.5 * h), wprm)
        px += h * bx
        py += h * by
        pz += h * bz
    pos[i, 0], pos[i, 1], pos[i, 2] = px, py, pz
    speed[i] = math.sqrt(bx * bx + by * by + bz * bz)
    outside[i] = _outside(px, py, pz, src, lo, hi)


@njit(**_JIT)
def _macro_one(i, pos, speed, outside, src, dt, substeps, lo, hi, tab):
    """Midpoint rule with the macro blend. The spheres were sampled for the hull at time
    -dt/2; the hull-fixed field at time t at p is the field at -dt/2 at p moved back by the
    hull's travel in between, ``u (t + dt/2)``. ``tab``: the hash's arrays and motion."""
    hp, mask, start, count, keys, data, motion = tab
    h = dt / substeps
    px, py, pz = pos[i, 0], pos[i, 1], pos[i, 2]
    ux, uy, uz = src[12], src[13], src[14]
    bx = by = bz = 0.0
    for k in range(substeps):
        s0 = -(substeps - k) * h + 0.5 * dt  # time since the sampling
        ax, ay, az = _blend_at(
            px - ux * s0, py - uy * s0, pz - uz * s0, hp, mask, start, count, keys, data, motion
        )
        s1 = s0 + 0.5 * h
        qx, qy, qz = (
            px + 0.5 * h * ax - ux * s1,
            py + 0.5 * h * ay - uy * s1,
            pz + 0.5 * h * az - uz * s1,
        )
        bx, by, bz = _blend_at(qx, qy, qz, hp, mask, start, count, keys, data, motion)
        px += h * bx
        py += h * by
        pz += h * bz
    pos[i, 0], pos[i, 1], pos[i, 2] = px, py, pz
    speed[i] = math.sqrt(bx * bx + by * by + bz * bz)
    outside[i] = _outside(px, py, pz, src, lo, hi)


@njit(**_JIT)
def _exact_serial(pos, speed, outside, src, wprm, dt, substeps, lo, hi):
    """Advect every tracer with the field on the calling thread."""
    for i in range(pos.shape[0]):
        _exact_one(i, pos, speed, outside, src, wprm, dt, substeps, lo, hi)


@njit(parallel=True, **_JIT)
def _exact_parallel(pos, speed, outside, src, wprm, dt, substeps, lo, hi):
    """Advect every tracer with the field, spread over numba's threads."""
    for i in prange(pos.shape[0]):
        _exact_one(i, pos, speed, outside, src, wprm, dt, substeps, lo, hi)


@njit(**_JIT)
def _macro_serial(pos, speed, outside, src, dt, substeps, lo, hi, tab):
    """Advect every tracer with the macro particles on the calling thread."""
    for i in range(pos.shape[0]):
        _macro_one(i, pos, speed, outside, src, dt, substeps, lo, hi, tab)


@njit(parallel=True, **_JIT)
def _macro_parallel(pos, speed, outside, src, dt, substeps, lo, hi, tab):
    """Advect every tracer with the macro particles, spread over numba's threads."""
    for i in prange(pos.shape[0]):
        _macro_one(i, pos, speed, outside, src, dt, substeps, lo, hi, tab)


@njit(**_JIT)
def _recycle(pos, idx, src, lo, hi, u):
    """Put tracers ``idx`` (ascending) back in the box, tracer idx[k] with the uniform draws
    ``u[k]``. In the body frame, the axis it left by most (relative to the box size) wraps
    around to the opposite face; the other two coordinates are drawn afresh. A non-finite
    tracer is drawn afresh on all three."""
    loc = np.empty(3)
    for k in range(idx.shape[0]):
        i = idx[k]
        dx, dy, dz = pos[i, 0] - src[0], pos[i, 1] - src[1], pos[i, 2] - src[2]
        loc[0] = src[3] * dx + src[6] * dy + src[9] * dz
        loc[1] = src[4] * dx + src[7] * dy + src[10] * dz
        loc[2] = src[5] * dx + src[8] * dy + src[11] * dz
        axis, worst = -1, 0.0
        if math.isfinite(loc[0]) and math.isfinite(loc[1]) and math.isfinite(loc[2]):
            for a in range(3):
                excess = max(lo[a] - loc[a], loc[a] - hi[a]) / (hi[a] - lo[a])
                if excess > worst:
                    axis, worst = a, excess
        for a in range(3):
            size = hi[a] - lo[a]
            if a == axis:
                wrapped = loc[a] - size * math.floor((loc[a] - lo[a]) / size)
                loc[a] = min(max(wrapped, lo[a]), hi[a])
            else:
                loc[a] = lo[a] + u[k, a] * size
        for a in range(3):
            pos[i, a] = src[a] + src[3 + 3 * a] * loc[0] + src[4 + 3 * a] * loc[1]
            pos[i, a] += src[5 + 3 * a] * loc[2]


class MacroState(NamedTuple):
    """The macro particles of the last advance (world frame, at the interval's midpoint)."""

    centers: np.ndarray
    radius_m: float
    lin_vel: np.ndarray
    ang_vel: np.ndarray


class Tracers:
    """Passive particles that show the wake: advected with the water, kept in a box around
    the hull (see the module docstring).

    Args:
        wake: the field that moves them.
        count: number of tracers.
        box_m: body-frame box ((lo, hi) along x, y, z, meters from the hull's center) that
            holds them; default :func:`default_box`.
        macro: 0 (default): advect with the field itself; M > 0: with about M macro particles
            (:class:`MacroParticles`).
        parallel: spread the tracers over numba's threads (same results); default: from
            ``PARALLEL_MIN`` tracers on (below, starting the threads costs more than it saves,
            and much more when other processes hold the cores).

    Examples:
        >>> import numpy as np
        >>> from fluidsim_envs.physics import WakeField
        >>> tr = Tracers(WakeField(), count=500)
        >>> tr.reset((0, 0, -50), (1, 0, 0, 0), (5, 0, 0), np.random.default_rng(0))
        >>> for k in range(10):
        ...     tr.advance(0.1, (5 * 0.1 * (k + 1), 0, -50), (1, 0, 0, 0), (5, 0, 0))
        >>> tr.positions.shape, tr.speeds.shape
        ((500, 3), (500,))
    """

    def __init__(
        self,
        wake: WakeField,
        count: int = 2000,
        box_m=None,
        macro: int = 0,
        parallel: bool | None = None,
    ) -> None:
        if not isinstance(wake, WakeField):
            raise TypeError(f"wake must be a WakeField, got {wake!r}")
        self.wake = wake
        self.count = _positive("count", count, integer=True)
        self._lo, self._hi = _box(default_box(wake) if box_m is None else box_m)
        self.box_m = tuple(zip(self._lo.tolist(), self._hi.tolist(), strict=True))
        if isinstance(macro, bool) or not isinstance(macro, (int, np.integer)) or macro < 0:
            raise ValueError(f"macro must be an integer >= 0, got {macro!r}")
        self.macro = MacroParticles(wake, self.box_m, macro) if macro else None
        self.parallel = self.count >= PARALLEL_MIN if parallel is None else bool(parallel)
        self._wprm = wake.params()
        self._pos = np.zeros((self.count, 3))
        self._speed = np.zeros(self.count)
        self._outside = np.zeros(self.count, np.bool_)
        self._rng: np.random.Generator | None = None
        self.recycled = 0  # tracers put back in the box by the last advance

    # ---- state -----------------------------------------------------------------------------

    @property
    def positions(self) -> np.ndarray:
        """[count, 3] world positions (a read-only view that the next advance updates)."""
        self._check_reset()
        v = self._pos.view()
        v.flags.writeable = False
        return v

    @property
    def speeds(self) -> np.ndarray:
        """[count] water speed at each tracer, for coloring: the midpoint velocity of its last
        substep (free, and within half a substep of the speed where it now is), or the field
        at its position after a reset or a recycle."""
        self._check_reset()
        v = self._speed.view()
        v.flags.writeable = False
        return v

    @property
    def macro_state(self) -> MacroState | None:
        """The macro particles of the last advance, for drawing them (views that the next
        advance overwrites); None without."""
        m = self.macro
        return None if m is None else MacroState(m.centers, m.radius_m, m.lin_vel, m.ang_vel)

    def _check_reset(self) -> None:
        if self._rng is None:
            raise RuntimeError("Tracers: call reset() first")

    # ---- evolution -------------------------------------------------------------------------

    def reset(
        self,
        sub_pos,
        sub_quat,
        sub_lin_vel,
        rng: np.random.Generator,
        noise_offset=(0, 0, 0),
        positions=None,
    ) -> None:
        """Scatter the tracers uniformly over the box around the hull (none inside the hull)
        with ``rng``, or put them at ``positions`` [count, 3] (world frame: a dye line, a
        test); either way take a generator for later recycling from ``rng``."""
        if not isinstance(rng, np.random.Generator):
            raise TypeError(f"rng must be a numpy Generator, got {rng!r}")
        src = source_row(sub_pos, sub_quat, sub_lin_vel, noise_offset)
        if positions is not None:
            pos = _points("positions", positions)
            if pos.shape != self._pos.shape:
                raise ValueError(f"positions must have shape {self._pos.shape}, got {pos.shape}")
            self._pos[:] = pos
        else:
            lo, hi = self._lo, self._hi
            a, b = 0.5 * self.wake.length_m, self.wake.radius_m
            loc = lo + rng.random((self.count, 3)) * (hi - lo)
            for _ in range(100):  # redraw those inside the hull (a box inside it: give up)
                inside = (loc[:, 0] / a) ** 2 + (loc[:, 1] ** 2 + loc[:, 2] ** 2) / b**2 < 1.0
                n = int(np.count_nonzero(inside))
                if n == 0:
                    break
                loc[inside] = lo + rng.random((n, 3)) * (hi - lo)
            self._pos[:] = src[:3] + loc @ src[3:12].reshape(3, 3).T
        self._rng = np.random.default_rng(rng.integers(0, 2**63 - 1))
        self._speed[:] = self._field_speed(self._pos, src)
        self.recycled = 0

    def _field_speed(self, points, src) -> np.ndarray:
        vel = np.empty_like(points)
        wake_velocity_batch(points, src, self._wprm, vel)
        return np.sqrt(np.sum(vel**2, axis=1))

    def advance(
        self, dt, sub_pos, sub_quat, sub_lin_vel, noise_offset=(0, 0, 0), substeps: int = 1
    ) -> None:
        """Move every tracer with the water over the ``dt`` seconds that end now, the hull
        being at ``sub_pos`` / ``sub_quat`` / ``sub_lin_vel`` now (see the module docstring),
        in ``substeps`` midpoint steps; then put those left out of the box back in."""
        self._check_reset()
        dt = _positive("dt", dt)
        substeps = _positive("substeps", substeps, integer=True)
        src = source_row(sub_pos, sub_quat, sub_lin_vel, noise_offset)
        state = (self._pos, self._speed, self._outside, src)
        if self.macro is None:
            kernel = _exact_parallel if self.parallel else _exact_serial
            kernel(*state, self._wprm, dt, substeps, self._lo, self._hi)
        else:
            m = self.macro
            mid = src.copy()
            mid[:3] -= 0.5 * dt * src[12:15]
            m._sample_src(mid)
            table = (*m.hash._table(), m.hash._data, m.hash._motion)
            kernel = _macro_parallel if self.parallel else _macro_serial
            kernel(*state, dt, substeps, self._lo, self._hi, table)
        idx = np.flatnonzero(self._outside)
        self.recycled = len(idx)
        if len(idx):
            u = self._rng.random((len(idx), 3))
            _recycle(self._pos, idx, src, self._lo, self._hi, u)
            self._speed[idx] = self._field_speed(self._pos[idx], src)
