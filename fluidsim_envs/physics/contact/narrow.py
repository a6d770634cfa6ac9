"""The narrow phase: each touching pair's contact patch (the ground under a body's shapes,
sphere and box pairs), as the depth-weighted mean of its touching points."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..forces import HALF, ONE, TINY, ZERO
from ..jit import INLINE as _INLINE
from ..jit import JIT as _JIT
from .bodies import (
    _point,
    _pose,
)
from .ground import (
    ground_at,
)
from .tables import (
    C_MARGIN,
    SH_CENTER,
    SH_KIND,
    SH_SIZE,
    SPHERE,
)

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
