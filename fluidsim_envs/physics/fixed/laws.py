"""The integer step, once: the arithmetic, the force laws and one body's step in fixed point.

Every function here is numba-compiled (``@njit``, int64 arithmetic) for the batch kernel
(``kernel.py``) and, from the same source, run as plain Python on Python integers by the
reference (``reference.py``, which rebinds these functions' code to plain functions). Python
integers never overflow and never round, so the kernel equals the reference bit for bit only
if no int64 operation here ever wraps and nothing is computed in floating point: what
``tests/physics/test_fixed.py`` checks. Only ``+ - * // >> << & abs min max`` on integers
appear below; no ``/``, no float constant.

Numbers are fixed point with ``f`` fraction bits (``prm[P_F]``): the integer ``n`` stands for
``n / 2**f`` in the craft's units (``format.py``). Every operation is named after the float
code it mirrors; the force laws are ``forces.py``'s, in the order ``kernels._evaluate`` calls
them, and the step is ``kernels._symplectic_euler`` (kick, drift, the midpoint turn,
normalization). The control surfaces are deflected in integers too, once per call
(:func:`body_inputs`: ``kernels._deflect`` with :func:`sincos`), from the controls rounded
to ``ANGLE_BITS``.

What differs from the float laws, and why: ``eff (v . n) / |v|`` is taken as ``eff ((v . n)
/ |v|)`` (a ratio of at most 1 rounds better than ``1 / |v|``); the clamps leave a value
alone below their limit (the float laws multiply it by exactly 1); the center-of-mass shift
and the per-environment factors (``Simulator.set_mass_properties``, ``set_sample_scale``)
are not offered, so the samples sit at the craft's offsets with the craft's sizes.

Rounding and ranges (``format.py`` documents the formats):

- ``qmul(a, b, s)`` is ``floor((a b + 2**(s-1)) / 2**s)``: the product rounded to nearest,
  ties toward +infinity (round half up), by adding half before the arithmetic right shift.
  32-bit words (``|a|, |b| < 2**31``) multiply directly in int64. 64-bit words are split at
  bit s, ``|a| = ah 2**s + al`` with ``0 <= al < 2**s``, and the product's magnitude summed
  from ``ah bh 2**s + ah bl + al bh + (al bl + half) >> s`` (the same number), whose terms
  are >= 0 and stay inside int64 for words up to ``2**61`` and ``s <= 30``; where ``ah bh``
  alone passes the word, so does the product, which saturates. Either way the result is
  exactly the rounded product, saturated (tests/physics/test_fixed.py draws words at
  random and compares with Python's exact integers).
- ``qdiv(a, d, s)`` is ``floor((a 2**s + d // 2) / d)`` for ``d > 0`` (a 64-bit numerator is
  shifted down with its divisor until ``a 2**s`` fits).
- Every result saturates to ``[-lim, lim]`` (``prm[P_LIM]``: ``2**31 - 1`` for fixed32,
  ``2**61 - 1`` for fixed64): nothing wraps. A body with a state word at the limit, or faster
  than the speed clamp, or whose force or torque sum reached the limit, is flagged
  (:func:`body_step` returns 1), and the simulator marks its environment ``diverged``. A
  product that saturates and is then shrunk by a later factor goes unflagged: bounded, never
  wrapped.
- Square roots: :func:`isqrt`, the binary digit-by-digit integer square root (floor), exact.
  Vector lengths (:func:`norm3`, :func:`norm4`) take it of the sum of the squared words
  (scale ``2**(2f)``, so the root is in the words' scale), after shifting the words down
  until the sum fits.
"""

from __future__ import annotations

from numba import njit

_J = dict(cache=True)

STEP_BITS = 30  # fraction bits of the step constants h = dt / T and h / 2 (exact enough)
NARROW = (1 << 31) - 1  # the largest 32-bit word: a limit above it means 64-bit words

# prm[] slots (int64): the format, the world and the step, in the craft's units
P_F, P_LIM, P_G, P_RHO_AIR, P_RHO_WATER, P_WATER, P_INV_BLEND = 0, 1, 2, 3, 4, 5, 6
P_VMAX, P_FMAX, P_H, P_HH, P_PRESCALED = 7, 8, 9, 10, 11
P_AIR, P_DU = 12, 15  # air velocity (3), water minus air velocity (3)
NPRM = 18

# a body's constants bc[]: 1/m, then the inverse body inertia (xx, yy, zz, xy, xz, yz)
B_INV_MASS, B_INV_INERTIA, NBC = 0, 1, 7

# tab[]: the sample counts, then each kind's rows one after the other
T_NPLATE, T_NFLAP, T_NCYL, T_NBUOY, T_NTHR, T_HEAD = 0, 1, 2, 3, 4, 5
W_PLATE = 8  # offset (3), normal (3), area, efficiency
W_FLAP = 11  # offset (3), area, efficiency, undeflected normal (3), hinge axis (3)
W_CYL = 7  # offset (3), axis (3), area
W_BUOY = 5  # offset (3), volume, area
W_THR = 9  # offset (3), direction (3), thrust at -1, thrust at +1, control channel (-1: none)
# inp[] per environment and body, from the controls once per call (:func:`body_inputs`):
# each control surface's deflected body-frame normal (3), then each thruster's control value
ANGLE_BITS = 30  # fraction bits of the controls, the deflections (rad) and their sines
PI_A, HALF_PI_A, TWO_PI_A = 3373259426, 1686629713, 6746518852  # pi, pi/2, 2 pi at 30 bits

# state rows (state.STATE_FIELDS): position, quaternion, velocity, angular momentum
OX, OQ, OV, OL, NSTATE = 0, 3, 7, 10, 13


# --------------------------------------------------------------------------------------------
# arithmetic


@njit(**_J)
def sat(x, lim):
    """x saturated to [-lim, lim]."""
    return min(max(x, -lim), lim)


@njit(**_J)
def add(a, b, lim):
    """a + b, saturated."""
    return sat(a + b, lim)


@njit(**_J)
def sub(a, b, lim):
    """a - b, saturated."""
    return sat(a - b, lim)


@njit(**_J)
def qmul(a, b, s, lim):
    """a b / 2**s rounded half up, saturated (module docstring)."""
    half = 1 << (s - 1)
    if lim <= NARROW:  # 32-bit words: the product fits int64
        return sat((a * b + half) >> s, lim)
    # 64-bit words: the magnitudes split at bit s, P = |a| |b| summed from four partial
    # products, all >= 0; floor((a b + half) / 2**s) is (P + half) >> s for a b >= 0 and
    # -((P + half - 1) >> s) below (round half up on both sides of zero)
    neg = (a < 0) != (b < 0)
    ma, mb = abs(a), abs(b)
    ah, bh = ma >> s, mb >> s
    al, bl = ma - (ah << s), mb - (bh << s)
    if ah != 0 and bh != 0 and ah > (lim >> s) // bh:
        return -lim if neg else lim  # ah bh 2**s alone passes the word
    low = (al * bl + (half - 1 if neg else half)) >> s
    p = ((ah * bh) << s) + ah * bl + al * bh + low
    return sat(-p if neg else p, lim)


@njit(**_J)
def mul(a, b, f, lim):
    """The product of two numbers of the format (``qmul`` at the binary point)."""
    return qmul(a, b, f, lim)


@njit(**_J)
def qdiv(a, d, s, lim):
    """a 2**s / d rounded half up, for d > 0, saturated (module docstring)."""
    top = 1 << (61 - s)
    while a >= top or a <= -top:
        a >>= 1
        d >>= 1
    if d <= 0:
        return 0 if a == 0 else (lim if a > 0 else -lim)
    return sat(((a << s) + (d >> 1)) // d, lim)


@njit(**_J)
def isqrt(n):
    """floor(sqrt(n)) for 0 <= n < 2**63, digit by digit in base 4."""
    r = 0
    bit = 1 << 62
    while bit > n:
        bit >>= 2
    while bit != 0:  # branch-free: take = 1 where the digit is 1
        t = r + bit
        take = 1 if n >= t else 0
        n -= t * take
        r = (r >> 1) + bit * take
        bit >>= 2
    return r


@njit(**_J)
def norm3(x, y, z):
    """floor(|(x, y, z)|) in the words' scale (the words shifted down until the squares'
    sum fits int64, then shifted back)."""
    ax, ay, az = abs(x), abs(y), abs(z)
    m = max(ax, max(ay, az))
    k = 0
    while (m >> k) >= (1 << 30):
        k += 1
    ax, ay, az = ax >> k, ay >> k, az >> k
    return isqrt(ax * ax + ay * ay + az * az) << k


@njit(**_J)
def norm4(w, x, y, z):
    """floor(|(w, x, y, z)|), as :func:`norm3`."""
    aw, ax, ay, az = abs(w), abs(x), abs(y), abs(z)
    m = max(max(aw, ax), max(ay, az))
    k = 0
    while (m >> k) >= (1 << 30):
        k += 1
    aw, ax, ay, az = aw >> k, ax >> k, ay >> k, az >> k
    return isqrt(aw * aw + ax * ax + ay * ay + az * az) << k


@njit(**_J)
def dot3(ax, ay, az, bx, by, bz, f, lim):
    """a . b, summed left to right."""
    return add(add(mul(ax, bx, f, lim), mul(ay, by, f, lim), lim), mul(az, bz, f, lim), lim)


@njit(**_J)
def to_bits(x, s, f):
    """x with s fraction bits as f <= s fraction bits, rounded half up."""
    return x if s == f else (x + (1 << (s - f - 1))) >> (s - f)


@njit(**_J)
def sincos(t):
    """cos t and sin t of an angle t (rad), all with ``ANGLE_BITS`` fraction bits: t is
    reduced to [-pi, pi), then to r in [-pi/4, pi/4) around k quarter turns; cos r and sin r
    by their Taylor series to r^12 and r^11 in Horner form (each factor ``1 - r^2 / d`` with
    d the ratio of successive coefficients, an integer division; the truncation is below
    1e-11); then turned by k quarter turns."""
    one, half = 1 << ANGLE_BITS, 1 << (ANGLE_BITS - 1)
    t = t - ((t + PI_A) // TWO_PI_A) * TWO_PI_A
    k = (t + (HALF_PI_A >> 1)) // HALF_PI_A
    r = t - k * HALF_PI_A
    r2 = (r * r + half) >> ANGLE_BITS
    sn = one
    for d in (110, 72, 42, 20, 6):
        sn = one - ((r2 * sn + half) >> ANGLE_BITS) // d
    sn = (r * sn + half) >> ANGLE_BITS
    cs = one
    for d in (132, 90, 56, 30, 12, 2):
        cs = one - ((r2 * cs + half) >> ANGLE_BITS) // d
    k = k & 3
    if k == 0:
        return cs, sn
    if k == 1:
        return -sn, cs
    if k == 2:
        return -cs, -sn
    return sn, -cs


# --------------------------------------------------------------------------------------------
# rotations (rotation.py)


@njit(**_J)
def quat_to_matrix(qw, qx, qy, qz, f, lim):
    """``rotation.quat_to_matrix``: R of q / |q|, row-major 9-tuple (s = 2 / |q|^2)."""
    one = 1 << f
    qq = add(add(mul(qw, qw, f, lim), mul(qx, qx, f, lim), lim), mul(qy, qy, f, lim), lim)
    qq = add(qq, mul(qz, qz, f, lim), lim)
    s = qdiv(2 * one, max(qq, 1), f, lim)
    xx, yy, zz = mul(qx, qx, f, lim), mul(qy, qy, f, lim), mul(qz, qz, f, lim)
    xy, xz, yz = mul(qx, qy, f, lim), mul(qx, qz, f, lim), mul(qy, qz, f, lim)
    wx, wy, wz = mul(qw, qx, f, lim), mul(qw, qy, f, lim), mul(qw, qz, f, lim)
    return (
        sub(one, mul(s, add(yy, zz, lim), f, lim), lim),
        mul(s, sub(xy, wz, lim), f, lim),
        mul(s, add(xz, wy, lim), f, lim),
        mul(s, add(xy, wz, lim), f, lim),
        sub(one, mul(s, add(xx, zz, lim), f, lim), lim),
        mul(s, sub(yz, wx, lim), f, lim),
        mul(s, sub(xz, wy, lim), f, lim),
        mul(s, add(yz, wx, lim), f, lim),
        sub(one, mul(s, add(xx, yy, lim), f, lim), lim),
    )


@njit(**_J)
def rotate(r, x, y, z, f, lim):
    """R (x, y, z): the world vector of a body vector (``kernels._rotate``)."""
    return (
        add(add(mul(r[0], x, f, lim), mul(r[1], y, f, lim), lim), mul(r[2], z, f, lim), lim),
        add(add(mul(r[3], x, f, lim), mul(r[4], y, f, lim), lim), mul(r[5], z, f, lim), lim),
        add(add(mul(r[6], x, f, lim), mul(r[7], y, f, lim), lim), mul(r[8], z, f, lim), lim),
    )


@njit(**_J)
def world_omega(r, lx, ly, lz, bc, f, lim):
    """``rotation.world_omega``: w = R I^-1 R^T L, I^-1 the body's ``bc[B_INV_INERTIA:]``."""
    k = B_INV_INERTIA
    ixx, iyy, izz, ixy, ixz, iyz = bc[k], bc[k + 1], bc[k + 2], bc[k + 3], bc[k + 4], bc[k + 5]
    bx = add(add(mul(r[0], lx, f, lim), mul(r[3], ly, f, lim), lim), mul(r[6], lz, f, lim), lim)
    by = add(add(mul(r[1], lx, f, lim), mul(r[4], ly, f, lim), lim), mul(r[7], lz, f, lim), lim)
    bz = add(add(mul(r[2], lx, f, lim), mul(r[5], ly, f, lim), lim), mul(r[8], lz, f, lim), lim)
    wx = add(add(mul(ixx, bx, f, lim), mul(ixy, by, f, lim), lim), mul(ixz, bz, f, lim), lim)
    wy = add(add(mul(ixy, bx, f, lim), mul(iyy, by, f, lim), lim), mul(iyz, bz, f, lim), lim)
    wz = add(add(mul(ixz, bx, f, lim), mul(iyz, by, f, lim), lim), mul(izz, bz, f, lim), lim)
    return rotate(r, wx, wy, wz, f, lim)


@njit(**_J)
def quat_rate(qw, qx, qy, qz, wx, wy, wz, f, lim):
    """``rotation.quat_rate``: dq/dt = 1/2 [0, w] (x) q."""
    h = 1 << (f - 1)  # 1/2
    a = add(add(mul(wx, qx, f, lim), mul(wy, qy, f, lim), lim), mul(wz, qz, f, lim), lim)
    b = sub(add(mul(qw, wx, f, lim), mul(wy, qz, f, lim), lim), mul(wz, qy, f, lim), lim)
    c = sub(add(mul(qw, wy, f, lim), mul(wz, qx, f, lim), lim), mul(wx, qz, f, lim), lim)
    d = sub(add(mul(qw, wz, f, lim), mul(wx, qy, f, lim), lim), mul(wy, qx, f, lim), lim)
    return -mul(h, a, f, lim), mul(h, b, f, lim), mul(h, c, f, lim), mul(h, d, f, lim)


# --------------------------------------------------------------------------------------------
# the force laws (forces.py)


@njit(**_J)
def speed_clamp(vx, vy, vz, vmax, f, lim):
    """``forces.speed_clamp``: |v| and the factor min(1, vmax / |v|) (1 at rest)."""
    speed = sat(norm3(vx, vy, vz), lim)  # up to sqrt(3) words: a factor must be a word
    scale = 1 << f if speed <= vmax else qdiv(vmax, speed, f, lim)
    return speed, scale


@njit(**_J)
def clamp_force(fx, fy, fz, fmax, f, lim):
    """``forces.clamp_force``: F scaled down to |F| <= fmax (left alone below it, where the
    float law multiplies by exactly 1)."""
    size = norm3(fx, fy, fz)
    if size <= fmax:
        return fx, fy, fz
    s = qdiv(fmax, size, f, lim)
    return mul(fx, s, f, lim), mul(fy, s, f, lim), mul(fz, s, f, lim)


@njit(**_J)
def plate_force(vx, vy, vz, nx, ny, nz, rho, area, eff, vmax, fmax, f, lim):
    """``forces.plate_force``: ``k (|v| n - eff (v . n)/|v| v)``, ``k = -1/2 rho A (v . n)``
    times the clamp factor squared, then the force clamp. ``eff (v . n)/|v|`` is taken as
    ``eff ((v . n)/|v|)`` (the ratio first: it is at most 1, where ``eff (v . n)`` times
    ``1/|v|`` would round ``1/|v|``); 0 at rest, where the float law's ``v`` term is 0."""
    speed, scale = speed_clamp(vx, vy, vz, vmax, f, lim)
    vn = dot3(vx, vy, vz, nx, ny, nz, f, lim)
    k = mul(mul(mul(mul(-mul(1 << (f - 1), rho, f, lim), area, f, lim), vn, f, lim), scale, f,
                lim), scale, f, lim)  # fmt: skip
    c = mul(eff, qdiv(vn, speed, f, lim), f, lim) if speed > 0 else 0
    return clamp_force(
        mul(k, sub(mul(speed, nx, f, lim), mul(c, vx, f, lim), lim), f, lim),
        mul(k, sub(mul(speed, ny, f, lim), mul(c, vy, f, lim), lim), f, lim),
        mul(k, sub(mul(speed, nz, f, lim), mul(c, vz, f, lim), lim), f, lim),
        fmax,
        f,
        lim,
    )


@njit(**_J)
def cylinder_force(vx, vy, vz, ax, ay, az, rho, area, vmax, fmax, f, lim):
    """``forces.cylinder_force``: ``-1/2 rho A |v_perp| v_perp`` times the clamp factor
    squared, ``v_perp = v - (v . a) a``, then the force clamp."""
    _, scale = speed_clamp(vx, vy, vz, vmax, f, lim)
    va = dot3(vx, vy, vz, ax, ay, az, f, lim)
    px = sub(vx, mul(va, ax, f, lim), lim)
    py = sub(vy, mul(va, ay, f, lim), lim)
    pz = sub(vz, mul(va, az, f, lim), lim)
    cross = sat(norm3(px, py, pz), lim)
    k = mul(mul(-mul(1 << (f - 1), rho, f, lim), area, f, lim), cross, f, lim)
    k = mul(mul(k, scale, f, lim), scale, f, lim)
    return clamp_force(mul(k, px, f, lim), mul(k, py, f, lim), mul(k, pz, f, lim), fmax, f, lim)


@njit(**_J)
def water_fraction(z, water, inv_blend, f, lim):
    """``forces.water_fraction``: water * min(1, max(0, 1/2 - z inv_blend))."""
    one = 1 << f
    return mul(water, min(one, max(0, sub(1 << (f - 1), mul(z, inv_blend, f, lim), lim))), f,
               lim)  # fmt: skip


@njit(**_J)
def buoyancy_force(z, frac, water, rho_w, g, volume, area, f, lim):
    """``forces.buoyancy_force``: rho_w g (V frac + A water max(0, -z))."""
    depth = mul(mul(area, water, f, lim), max(0, -z), f, lim)
    return mul(mul(rho_w, g, f, lim), add(mul(volume, frac, f, lim), depth, lim), f, lim)


@njit(**_J)
def thrust_of(c, lo, hi, f, lim):
    """``forces.thrust_of``: hi max(c, 0) - lo min(c, 0)."""
    return sub(mul(hi, max(c, 0), f, lim), mul(lo, min(c, 0), f, lim), lim)


@njit(**_J)
def flow(prm, z0, v0x, v0y, v0z, wx, wy, wz, rx, ry, rz, f, lim):
    """``kernels._flow``: density and velocity relative to the fluid at the body point x + r
    (z0: the body's height, v0: its velocity relative to the air, w: its angular velocity)."""
    rho_a, rho_w = prm[P_RHO_AIR], prm[P_RHO_WATER]
    frac = water_fraction(add(z0, rz, lim), prm[P_WATER], prm[P_INV_BLEND], f, lim)
    rho = add(rho_a, mul(frac, sub(rho_w, rho_a, lim), f, lim), lim)
    vx = add(v0x, sub(mul(wy, rz, f, lim), mul(wz, ry, f, lim), lim), lim)
    vy = add(v0y, sub(mul(wz, rx, f, lim), mul(wx, rz, f, lim), lim), lim)
    vz = add(v0z, sub(mul(wx, ry, f, lim), mul(wy, rx, f, lim), lim), lim)
    vx = sub(vx, mul(frac, prm[P_DU], f, lim), lim)
    vy = sub(vy, mul(frac, prm[P_DU + 1], f, lim), lim)
    vz = sub(vz, mul(frac, prm[P_DU + 2], f, lim), lim)
    return vx, vy, vz, rho


@njit(**_J)
def rotate_about_axis(nx, ny, nz, hx, hy, hz, c, s, f, lim):
    """``forces.rotate_about_axis``: n c + (h x n) s + h (h . n)(1 - c)."""
    hn = dot3(hx, hy, hz, nx, ny, nz, f, lim)
    omc = sub(1 << f, c, lim)
    x = add(add(mul(nx, c, f, lim), mul(sub(mul(hy, nz, f, lim), mul(hz, ny, f, lim), lim), s,
            f, lim), lim), mul(mul(hx, hn, f, lim), omc, f, lim), lim)  # fmt: skip
    y = add(add(mul(ny, c, f, lim), mul(sub(mul(hz, nx, f, lim), mul(hx, nz, f, lim), lim), s,
            f, lim), lim), mul(mul(hy, hn, f, lim), omc, f, lim), lim)  # fmt: skip
    z = add(add(mul(nz, c, f, lim), mul(sub(mul(hx, ny, f, lim), mul(hy, nx, f, lim), lim), s,
            f, lim), lim), mul(mul(hz, hn, f, lim), omc, f, lim), lim)  # fmt: skip
    return x, y, z


@njit(**_J)
def body_inputs(ctrl, tab, mix, prm, inp):
    """One body's inputs ``inp`` from the controls ``ctrl[C]`` (``ANGLE_BITS`` fraction bits),
    as ``kernels._deflect`` and ``thrust_of``'s caller take them: each control surface's
    deflection ``theta = sum_c mix[p, c] ctrl[c]`` (``mix[p * C + c]``: rad per unit of channel
    c, ``ANGLE_BITS``), its normal turned about its hinge by theta (:func:`sincos`,
    :func:`rotate_about_axis`), then each thruster's channel value in the format (1 for a
    thruster without a channel)."""
    f, lim = prm[P_F], prm[P_LIM]
    half = 1 << (ANGLE_BITS - 1)
    C = len(ctrl)
    nflap = tab[T_NFLAP]
    at = T_HEAD + tab[T_NPLATE] * W_PLATE
    for p in range(nflap):
        theta = 0
        for c in range(C):
            theta += (mix[p * C + c] * ctrl[c] + half) >> ANGLE_BITS
        cs, sn = sincos(theta)
        nx, ny, nz = rotate_about_axis(tab[at + 5], tab[at + 6], tab[at + 7], tab[at + 8],
                                       tab[at + 9], tab[at + 10], to_bits(cs, ANGLE_BITS, f),
                                       to_bits(sn, ANGLE_BITS, f), f, lim)  # fmt: skip
        inp[3 * p], inp[3 * p + 1], inp[3 * p + 2] = nx, ny, nz
        at += W_FLAP
    at += tab[T_NCYL] * W_CYL + tab[T_NBUOY] * W_BUOY
    for p in range(tab[T_NTHR]):
        ch = tab[at + 8]
        inp[3 * nflap + p] = 1 << f if ch < 0 else to_bits(ctrl[ch], ANGLE_BITS, f)
        at += W_THR


# --------------------------------------------------------------------------------------------
# one body's step


@njit(**_J)
def evaluate(s, bc, tab, inp, prm, r, wx, wy, wz):
    """``kernels._evaluate`` for one body: the force and torque of its samples (fixed plates,
    control surfaces, cylinders, buoyancy, thrusters, in that order, each added as it comes),
    as (fx, fy, fz, tx, ty, tz) about the center of mass, world frame."""
    f, lim = prm[P_F], prm[P_LIM]
    vmax, fmax = prm[P_VMAX], prm[P_FMAX]
    z0 = s[OX + 2]
    v0x = sub(s[OV], prm[P_AIR], lim)
    v0y = sub(s[OV + 1], prm[P_AIR + 1], lim)
    v0z = sub(s[OV + 2], prm[P_AIR + 2], lim)
    Fx = Fy = Fz = Tx = Ty = Tz = 0
    vx = vy = vz = rho = 0
    at = T_HEAD
    nflap = tab[T_NFLAP]
    for kind in range(5):
        for p in range(tab[kind]):
            rx, ry, rz = rotate(r, tab[at], tab[at + 1], tab[at + 2], f, lim)
            if kind == T_NPLATE or kind == T_NFLAP or kind == T_NCYL:
                vx, vy, vz, rho = flow(prm, z0, v0x, v0y, v0z, wx, wy, wz, rx, ry, rz, f, lim)
            if kind == T_NPLATE:
                nx, ny, nz = rotate(r, tab[at + 3], tab[at + 4], tab[at + 5], f, lim)
                fx, fy, fz = plate_force(vx, vy, vz, nx, ny, nz, rho, tab[at + 6], tab[at + 7],
                                         vmax, fmax, f, lim)  # fmt: skip
                at += W_PLATE
            elif kind == T_NFLAP:
                nx, ny, nz = rotate(r, inp[3 * p], inp[3 * p + 1], inp[3 * p + 2], f, lim)
                fx, fy, fz = plate_force(vx, vy, vz, nx, ny, nz, rho, tab[at + 3], tab[at + 4],
                                         vmax, fmax, f, lim)  # fmt: skip
                at += W_FLAP
            elif kind == T_NCYL:
                ax, ay, az = rotate(r, tab[at + 3], tab[at + 4], tab[at + 5], f, lim)
                fx, fy, fz = cylinder_force(vx, vy, vz, ax, ay, az, rho, tab[at + 6], vmax, fmax,
                                            f, lim)  # fmt: skip
                at += W_CYL
            elif kind == T_NBUOY:  # the water's: no flow
                z = add(z0, rz, lim)
                frac = water_fraction(z, prm[P_WATER], prm[P_INV_BLEND], f, lim)
                fx, fy = 0, 0
                fz = buoyancy_force(z, frac, prm[P_WATER], prm[P_RHO_WATER], prm[P_G],
                                    tab[at + 3], tab[at + 4], f, lim)  # fmt: skip
                at += W_BUOY
            else:  # a thruster: a point force along its direction
                thrust = thrust_of(inp[3 * nflap + p], tab[at + 6], tab[at + 7], f, lim)
                dx, dy, dz = rotate(r, tab[at + 3], tab[at + 4], tab[at + 5], f, lim)
                fx, fy, fz = mul(thrust, dx, f, lim), mul(thrust, dy, f, lim), mul(thrust, dz, f,
                                                                                   lim)  # fmt: skip
                at += W_THR
            # kernels._add_force
            Fx, Fy, Fz = add(Fx, fx, lim), add(Fy, fy, lim), add(Fz, fz, lim)
            Tx = add(Tx, sub(mul(ry, fz, f, lim), mul(rz, fy, f, lim), lim), lim)
            Ty = add(Ty, sub(mul(rz, fx, f, lim), mul(rx, fz, f, lim), lim), lim)
            Tz = add(Tz, sub(mul(rx, fy, f, lim), mul(ry, fx, f, lim), lim), lim)
    return Fx, Fy, Fz, Tx, Ty, Tz


@njit(**_J)
def hmul(x, h, prm):
    """x h for a step constant h (``STEP_BITS`` fraction bits); the prescaled integrator
    counts time in steps (h = 1) and skips it."""
    return x if prm[P_PRESCALED] != 0 else qmul(x, h, STEP_BITS, prm[P_LIM])


@njit(**_J)
def body_step(s, bc, tab, inp, prm):
    """One symplectic Euler step of one body, in place on its state words ``s[13]``
    (``kernels._symplectic_euler``): the forces at the step's start, v += h F/m - h g,
    L += h T, x += h v, then the orientation by the explicit-midpoint turn of the new L
    (``kernels._rotate_by_omega``) and normalized. Under ``prescaled_symplectic_euler``
    (``prm[P_PRESCALED]``) the time unit is the step, so h = 1: v is the displacement per
    step, ``u += a dt^2, x += u`` (the source article's variant), with no multiplication by
    the step at all. Returns 1 where the body has a word at the limit or runs faster than
    the speed clamp (``kernels._flag_runaways``' first rule), else 0."""
    f, lim = prm[P_F], prm[P_LIM]
    h, hh = prm[P_H], prm[P_HH]
    qw, qx, qy, qz = s[OQ], s[OQ + 1], s[OQ + 2], s[OQ + 3]
    r = quat_to_matrix(qw, qx, qy, qz, f, lim)
    wx, wy, wz = world_omega(r, s[OL], s[OL + 1], s[OL + 2], bc, f, lim)
    Fx, Fy, Fz, Tx, Ty, Tz = evaluate(s, bc, tab, inp, prm, r, wx, wy, wz)
    inv_m = bc[B_INV_MASS]
    ax, ay = mul(Fx, inv_m, f, lim), mul(Fy, inv_m, f, lim)
    az = sub(mul(Fz, inv_m, f, lim), prm[P_G], lim)
    # kick, drift (kernels._kick, _drift)
    s[OV] = add(s[OV], hmul(ax, h, prm), lim)
    s[OV + 1] = add(s[OV + 1], hmul(ay, h, prm), lim)
    s[OV + 2] = add(s[OV + 2], hmul(az, h, prm), lim)
    s[OL] = add(s[OL], hmul(Tx, h, prm), lim)
    s[OL + 1] = add(s[OL + 1], hmul(Ty, h, prm), lim)
    s[OL + 2] = add(s[OL + 2], hmul(Tz, h, prm), lim)
    for k in range(3):
        s[OX + k] = add(s[OX + k], hmul(s[OV + k], h, prm), lim)
    # the turn (kernels._rotate_by_omega, _midpoint_turn), R from the step's start
    lx, ly, lz = s[OL], s[OL + 1], s[OL + 2]
    wx, wy, wz = world_omega(r, lx, ly, lz, bc, f, lim)
    dw, dx, dy, dz = quat_rate(qw, qx, qy, qz, wx, wy, wz, f, lim)
    m = quat_to_matrix(add(qw, qmul(dw, hh, STEP_BITS, lim), lim),
                       add(qx, qmul(dx, hh, STEP_BITS, lim), lim),
                       add(qy, qmul(dy, hh, STEP_BITS, lim), lim),
                       add(qz, qmul(dz, hh, STEP_BITS, lim), lim), f, lim)  # fmt: skip
    wx, wy, wz = world_omega(m, lx, ly, lz, bc, f, lim)
    dw, dx, dy, dz = quat_rate(qw, qx, qy, qz, wx, wy, wz, f, lim)
    qw, qx = add(qw, hmul(dw, h, prm), lim), add(qx, hmul(dx, h, prm), lim)
    qy, qz = add(qy, hmul(dy, h, prm), lim), add(qz, hmul(dz, h, prm), lim)
    # kernels._normalize_quat: q / |q|, |q| by the integer square root
    n = max(norm4(qw, qx, qy, qz), 1)
    s[OQ], s[OQ + 1] = qdiv(qw, n, f, lim), qdiv(qx, n, f, lim)
    s[OQ + 2], s[OQ + 3] = qdiv(qy, n, f, lim), qdiv(qz, n, f, lim)
    # a force or torque sum at the word: some sample's force saturated on the way
    flag = 0
    for x in (Fx, Fy, Fz, Tx, Ty, Tz):
        if x >= lim or x <= -lim:
            flag = 1
    for k in range(NSTATE):
        if s[k] >= lim or s[k] <= -lim:
            flag = 1
    if norm3(s[OV], s[OV + 1], s[OV + 2]) > prm[P_VMAX]:
        flag = 1
    return flag


# the functions above, callees before callers: what reference.py rebinds as plain Python
ORDER = (
    "sat", "add", "sub", "qmul", "mul", "qdiv", "isqrt", "norm3", "norm4", "dot3", "to_bits",
    "sincos", "quat_to_matrix", "rotate", "world_omega", "quat_rate", "speed_clamp", "clamp_force",
    "plate_force", "cylinder_force", "water_fraction", "buoyancy_force", "thrust_of", "flow",
    "rotate_about_axis", "body_inputs", "evaluate", "hmul", "body_step",
)  # fmt: skip
