"""The solver: each touching pair as one contact, opened (impacts and pushes out), warm-started,
solved in projected Gauss-Seidel passes, and closed (the energy bound); the per-environment
entry points :func:`may_touch` and :func:`collide`."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..forces import HALF, ONE, TINY, TWO, ZERO
from ..jit import INLINE as _INLINE
from ..jit import JIT as _JIT
from ..rotation import body_inv_inertia, world_omega
from ..state import B_MASS, OV, OX, STATE
from .bodies import (
    _cross,
    _displace,
    _dot,
    _energy,
    _motion,
    _omega,
    _pose,
    _scale_velocities,
    _turn,
    _wrench,
)
from .narrow import (
    _ground_overlap,
    _pair_overlap,
    _patch,
)
from .tables import (
    C_DT,
    C_G,
    C_GE,
    C_GMU,
    C_GROUND,
    C_GTOP,
    C_MARGIN,
    C_PAIR_BOUND,
    C_PASSES,
    C_REST_SPEED,
    C_UNDRIFT,
    CB_FRICTION,
    CB_REACH,
    CB_RESTITUTION,
    GROUND_NONE,
    TWO_THIRDS,
)

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
    eb = cprm[C_GE] if ground else cbody[b, CB_RESTITUTION]
    mub = cprm[C_GMU] if ground else cbody[b, CB_FRICTION]
    e = math.sqrt(cbody[a, CB_RESTITUTION] * eb)
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
def _near_ground(S, b, i, n, reach, cprm):
    """Whether body b's reach comes within the margin of the ground's highest point."""
    if cprm[C_GROUND] == GROUND_NONE:
        return False
    return S[b, i + (STATE + OX + 2) * n] - reach <= cprm[C_GTOP] + cprm[C_MARGIN]


@njit(**_INLINE)
def _near_each_other(S, a, b, i, n, reach_a, reach_b, margin):
    """Whether bodies a and b are within their reaches (plus the margin) of each other."""
    dx = S[a, i + (STATE + OX) * n] - S[b, i + (STATE + OX) * n]
    dy = S[a, i + (STATE + OX + 1) * n] - S[b, i + (STATE + OX + 1) * n]
    dz = S[a, i + (STATE + OX + 2) * n] - S[b, i + (STATE + OX + 2) * n]
    reach = reach_a + reach_b + margin
    return dx * dx + dy * dy + dz * dz <= reach * reach


@njit(**_INLINE)
def may_touch(S, nb, i, n, e, contact_body, cprm, warm):
    """Whether environment e (slot i of the scratch S) needs ``collide`` this step: a body
    within reach of the ground's highest point or of another body, or a contact held last
    step (whose warm start must be forgotten if it let go). Most steps of a flying or sailing
    scene need nothing. Reads ``contact_body[E, B, NCBODY]`` and ``warm[E, pairs, NWARM]``
    at e, without a view of e's rows (a view per environment and step costs a reference
    count: 15% of the dart's env step at E = 64)."""
    margin = cprm[C_MARGIN]
    for c in range(warm.shape[1]):
        if warm[e, c, 0] != ZERO:
            return True
    for b in range(nb):
        if _near_ground(S, b, i, n, contact_body[e, b, CB_REACH], cprm):
            return True
        for a in range(b):
            reach_a, reach_b = contact_body[e, a, CB_REACH], contact_body[e, b, CB_REACH]
            if _near_each_other(S, a, b, i, n, reach_a, reach_b, margin):
                return True
    return False


@njit(**_JIT)
def collide(S, nb, i, n, body, shp, srange, grid, cbody, cprm, W, warm, touch, pairs):
    """All contacts of environment i (its bodies' state in the scratch S: element k of body
    b at ``S[b, i + k * n]``; W a work array [num_pairs(nb), NW]; ``warm`` the environment's
    warm-start impulses [num_pairs(nb), NWARM], updated; ``touch`` [num_pairs(nb)] each
    pair's normal impulse, added to: the ground's on each body, then each pair of bodies).
    Each body against the ground, then every pair of bodies whose shapes' reaches overlap:
    each touching pair is one contact, opened (pushed apart, warm-started) as found; then
    ``C_PASSES`` velocity passes over them all; then the energy check of the impacts; then
    the resting bodies' positions are put back where the velocity the contacts took away
    had carried them this step. ``pairs``: None when no two bodies can touch (one body per
    environment): the pairs' loop is then pruned when numba compiles (with the pair tests
    it holds, about 5 s of a cold first step)."""
    for b in range(nb):  # nothing recorded yet: most bodies touch nothing most steps
        W[b, W_REST] = ZERO
        W[b, W_SEEN] = ZERO
    # not ``k = 0``: numba types a call while k is still the literal 0, and compiles _open
    # (7-9 s) for that signature too before k settles to int64 (docs/bench_compile.csv)
    k = np.int64(0)
    ground = np.int64(-1)  # the ground's body index, typed like b (the literal: _open twice)
    margin = cprm[C_MARGIN]
    for b in range(nb):
        W[k, W_ON] = ZERO
        if _near_ground(S, b, i, n, cbody[b, CB_REACH], cprm):  # (clear above: not visited)
            acc = _ground_overlap(S, b, i, n, shp, srange, grid, cprm)
            _open(S, W, k, b, ground, i, n, body, cbody, cprm, acc)
        k += 1
    if pairs is not None:
        for a in range(nb):
            for b in range(a + 1, nb):
                W[k, W_ON] = ZERO
                reach_a, reach_b = cbody[a, CB_REACH], cbody[b, CB_REACH]
                if _near_each_other(S, a, b, i, n, reach_a, reach_b, margin):
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
