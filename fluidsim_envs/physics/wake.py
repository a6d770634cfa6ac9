"""The submarine's wake: a cheap fluid-velocity field from a few blended closed forms.

The seed's "spatial field" idea: instead of solving the flow, every point looks up its fluid
velocity in a handful of analytic functions of its position relative to the moving hull, all
scaled with the hull's speed. Three parts, each a standard closed form:

- **Displacement** (near the hull): the potential flow of the hull moving through still water.
  The hull is a prolate spheroid (semi-axes ``a = length/2``, ``b = radius``); its flow is
  written as point dipoles on the axis, one per slice of the spheroid, each carrying its slice's
  share of the volume (slender-body theory: the dipole density is proportional to the section
  area). The total dipole moment is the spheroid's exact one, ``V (1 + k) U / (4 pi)`` with
  Lamb's added-mass coefficients ``k`` (axial and lateral), so the far field is exact and falls
  off like ``1/r^3``; with one dipole and ``length = 2 radius`` the field is the exact flow
  around a sphere. Inside a dipole's core (the local hull radius) the singular ``1/r^3`` is
  replaced by the continuous interior continuation, so the field is finite in the hull.
- **Screw vortices** (behind the stern): one (``screws=1``) or two counter-rotating Lamb-Oseen
  vortices trailing aft from the screws along the hull axis. Circulation
  ``Gamma = circulation * speed * radius`` ramps in over one radius behind the screws and decays
  with distance; the core grows linearly; a pair drifts across the axis at the speed each
  vortex induces on the other (``Gamma / (2 pi d)``), integrated along the decaying wake.
- **Turbulence** (farther back): smooth value noise, fixed in the water (frozen turbulence:
  a point that keeps pace with the hull sees it change at the hull's speed), inside an envelope
  that starts at the stern, widens and decays aft.

Every part is linear in the hull's speed. The field is in the hull's frame: it swings with the
hull when it turns (a trailing wake that remembers the path would need state; this scene does
not need it).

The scalar :func:`wake_at` is the one implementation: :meth:`WakeField.velocity`, the step
kernel (fluid samples subtract it from their velocity) and the scene's sensor all call it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
from numba import njit

from . import checks as CK

_INLINE = dict(cache=True, error_model="numpy", inline="always", fastmath={"contract"})
_JIT = dict(cache=True, error_model="numpy", fastmath={"contract"})

MAX_DIPOLES = 32

# wprm[] slots (a float array in the simulation dtype; the kernels read it)
(
    W_ON,
    W_A,
    W_B,
    W_NDIP,
    W_C_AX,
    W_C_LAT,
    W_SCREWS,
    W_SCREW_X,
    W_SCREW_Y,
    W_GAMMA,
    W_CORE,
    W_CORE_GROWTH,
    W_DECAY,
    W_DRIFT,
    W_NOISE,
    W_NOISE_INV_SCALE,
    W_NOISE_DECAY,
    W_WAKE_GROWTH,
    W_DISPLACEMENT,
    W_VORTICES,
) = range(20)
W_DIP = 24  # then MAX_DIPOLES triples: axial position, volume share, core radius
NWPRM = W_DIP + 3 * MAX_DIPOLES


@dataclass(frozen=True)
class WakeField:
    """The flow around a submarine moving through still water (see the module docstring).

    Args:
        length_m, radius_m: the hull, a prolate spheroid centered on the submarine's center
            of mass, axis along its body x (``length_m >= 2 radius_m``).
        screws: 1 (one vortex on the axis) or 2 (a counter-rotating pair).
        screw_spacing_m: distance between the two screws (default: one radius).
        screw_x_m: body-x position of the screws (default: the stern, ``-length/2``).
        circulation: vortex strength ``Gamma / (speed * radius)`` (dimensionless).
        core_radius_m: vortex core radius at the screws (default: a quarter radius).
        core_growth: core radius gained per meter aft.
        decay_length_m: e-folding length of the circulation aft of the screws
            (default: two hull lengths).
        pair_sense: +1: the pair turns so that it drifts toward body -z; -1: toward +z.
        noise: turbulence amplitude as a fraction of the speed.
        noise_scale_m: size of the turbulent eddies (default: one radius).
        noise_decay_m: e-folding length of the turbulence aft of the stern
            (default: three hull lengths).
        wake_growth: widening of the turbulent wake per meter aft (its radius starts at
            the hull radius).
        dipoles: number of axial dipoles carrying the displacement flow (1 to 32). About
            twice length / radius keeps the flow within 4% of the speed of the exact
            spheroid's down to a tenth of a radius off the hull; 8 on this default hull is
            as good from two radii out (0.5%) at a third of the cost
            (tests/physics/test_wake.py).
        displacement, vortices: switch those parts on or off (turbulence: ``noise=0``).

    Examples:
        >>> import numpy as np
        >>> from fluidsim_envs.physics import WakeField
        >>> wake = WakeField(length_m=2.0, radius_m=1.0, dipoles=1, screws=1, circulation=0.0,
        ...                  noise=0.0)                      # a sphere: exact potential flow
        >>> u = wake.velocity([[3.0, 0, 0], [0, 3.0, 0]], (0, 0, 0), (1, 0, 0, 0), (2.0, 0, 0))
        >>> np.round(u / 2.0 * 27, 6)    # ahead: a^3/r^3 U forward; beside: -a^3/(2 r^3) U
        array([[ 1. ,  0. ,  0. ],
               [-0.5,  0. ,  0. ]])
    """

    length_m: float = 40.0
    radius_m: float = 3.0
    screws: int = 2
    screw_spacing_m: float | None = None
    screw_x_m: float | None = None
    circulation: float = 1.0
    core_radius_m: float | None = None
    core_growth: float = 0.02
    decay_length_m: float | None = None
    pair_sense: int = 1
    noise: float = 0.1
    noise_scale_m: float | None = None
    noise_decay_m: float | None = None
    wake_growth: float = 0.05
    dipoles: int = 24
    displacement: bool = True
    vortices: bool = True

    def __post_init__(self) -> None:
        CK.plain_fields(self)  # NumPy scalars as Python numbers: one kernel type each

        def number(key, **bound):
            if getattr(self, key) is not None or key in ("length_m", "radius_m"):
                CK.number("WakeField", key, getattr(self, key), **bound)

        number("length_m", gt=0.0)
        number("radius_m", gt=0.0)
        if self.length_m < 2.0 * self.radius_m:
            raise ValueError(
                f"WakeField: length_m ({self.length_m!r}) must be at least twice radius_m "
                f"({self.radius_m!r}): the hull is a prolate spheroid"
            )
        for key in (
            "screw_spacing_m", "core_radius_m", "noise_scale_m", "decay_length_m",
            "noise_decay_m",
        ):  # fmt: skip
            number(key, gt=0.0)  # None: derived from the hull's size
        number("screw_x_m")
        for key in ("circulation", "core_growth", "noise", "wake_growth"):
            number(key, ge=0.0)
        CK.number("WakeField", "screws", self.screws, ge=1, le=2, integer=True)
        CK.choice("WakeField", "pair_sense", self.pair_sense, (1, -1))  # an int: not True
        CK.number("WakeField", "dipoles", self.dipoles, ge=1, le=MAX_DIPOLES, integer=True)
        for key in ("displacement", "vortices"):
            CK.flag("WakeField", key, getattr(self, key))

    # ---- derived quantities ----------------------------------------------------------------

    @property
    def volume_m3(self) -> float:
        """The hull's volume, 4/3 pi a b^2."""
        return 4.0 / 3.0 * math.pi * 0.5 * self.length_m * self.radius_m**2

    def added_mass_coefficients(self) -> tuple[float, float]:
        """Lamb's added-mass coefficients (axial, lateral) of the prolate spheroid.

        Lamb, Hydrodynamics (6th ed., 1932), section 115: with eccentricity
        ``e = sqrt(1 - b^2/a^2)``, ``alpha0 = 2 (1 - e^2) / e^3 (atanh(e) - e)``,
        ``beta0 = 1/e^2 - (1 - e^2) / e^3 atanh(e)``, ``k1 = alpha0 / (2 - alpha0)``,
        ``k2 = beta0 / (2 - beta0)``. A sphere has 1/2 and 1/2.
        """
        a, b = 0.5 * self.length_m, self.radius_m
        e = math.sqrt(max(0.0, 1.0 - (b / a) ** 2))
        if e < 1e-4:  # series limit: the formulas cancel catastrophically
            return 0.5, 0.5
        at = math.atanh(e)
        alpha0 = 2.0 * (1.0 - e * e) / e**3 * (at - e)
        beta0 = 1.0 / (e * e) - (1.0 - e * e) / e**3 * at
        return alpha0 / (2.0 - alpha0), beta0 / (2.0 - beta0)

    def params(self, dtype=np.float64) -> np.ndarray:
        """The parameter array the kernels read (slots ``W_*`` of this module)."""
        a, b = 0.5 * self.length_m, self.radius_m
        k1, k2 = self.added_mass_coefficients()
        w = np.zeros(NWPRM)
        w[W_ON] = 1.0
        w[W_A], w[W_B] = a, b
        w[W_C_AX] = self.volume_m3 * (1.0 + k1) / (4.0 * math.pi)
        w[W_C_LAT] = self.volume_m3 * (1.0 + k2) / (4.0 * math.pi)
        # dipoles at the slice midpoints; each carries its slice's share of the volume
        K = self.dipoles
        edges = np.linspace(-a, a, K + 1)
        share = np.diff(edges - edges**3 / (3.0 * a * a)) / (4.0 * a / 3.0)
        mid = 0.5 * (edges[:-1] + edges[1:])
        local_r = b * np.sqrt(np.maximum(1.0 - (mid / a) ** 2, 0.0))
        # at least 3/4 of a slice; one dipole stands for the whole hull: its core is the
        # circumscribed sphere (radius a; the exact sphere when a = b)
        core = np.maximum(local_r, 0.75 * (2.0 * a / K)) if K > 1 else np.full(1, a)
        w[W_NDIP] = K
        w[W_DIP : W_DIP + 3 * K] = np.stack([mid, share, core], axis=1).ravel()
        w[W_SCREWS] = self.screws
        w[W_SCREW_X] = -a if self.screw_x_m is None else self.screw_x_m
        spacing = b if self.screw_spacing_m is None else self.screw_spacing_m
        w[W_SCREW_Y] = 0.5 * spacing if self.screws == 2 else 0.0
        # signed circulation of the (port) vortex about +x: a pair turns by pair_sense
        w[W_GAMMA] = self.circulation * b * (self.pair_sense if self.screws == 2 else 1)
        w[W_CORE] = 0.25 * b if self.core_radius_m is None else self.core_radius_m
        w[W_CORE_GROWTH] = self.core_growth
        w[W_DECAY] = 2.0 * self.length_m if self.decay_length_m is None else self.decay_length_m
        # pair drift: each vortex moves at Gamma / (2 pi spacing); over the decaying wake the
        # speed cancels and the drift is geometric (see wake_at)
        w[W_DRIFT] = -w[W_GAMMA] / (2.0 * math.pi * spacing) if self.screws == 2 else 0.0
        w[W_NOISE] = self.noise
        w[W_NOISE_INV_SCALE] = 1.0 / (b if self.noise_scale_m is None else self.noise_scale_m)
        w[W_NOISE_DECAY] = 3.0 * self.length_m if self.noise_decay_m is None else self.noise_decay_m
        w[W_WAKE_GROWTH] = self.wake_growth
        w[W_DISPLACEMENT] = 1.0 if self.displacement else 0.0
        w[W_VORTICES] = 1.0 if self.vortices else 0.0
        return w.astype(dtype)

    def replace(self, **changes) -> WakeField:
        """A copy with some parameters changed (validated again)."""
        names = {f.name for f in fields(self)}
        bad = sorted(set(changes) - names)
        if bad:
            raise ValueError(f"WakeField: unknown parameter(s) {bad}; valid: {sorted(names)}")
        return WakeField(**{**{n: getattr(self, n) for n in names}, **changes})

    # ---- evaluation ------------------------------------------------------------------------

    def velocity(
        self, points, sub_pos, sub_quat, sub_lin_vel, noise_offset=(0.0, 0.0, 0.0)
    ) -> np.ndarray:
        """Fluid velocity [N, 3] (m/s, world frame) at world points [N, 3].

        ``sub_pos`` [3], ``sub_quat`` [4] (w, x, y, z; body -> world) and ``sub_lin_vel`` [3]
        are the submarine's center and motion through the water; ``noise_offset`` [3] shifts
        the turbulence (in eddies) so that episodes can differ.
        """
        pts = CK.array("WakeField.velocity", "points", points)
        if pts.ndim == 1:
            pts = pts[None]
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise ValueError(
                f"WakeField.velocity: points must have shape [N, 3], got shape "
                f"{list(np.shape(points))}: {CK.show(points)}"
            )
        src = source_row(sub_pos, sub_quat, sub_lin_vel, noise_offset)
        out = np.empty_like(pts)
        wake_velocity_batch(pts, src, self.params(), out)
        return out


def source_row(sub_pos, sub_quat, sub_lin_vel, noise_offset=(0.0, 0.0, 0.0)) -> np.ndarray:
    """A submarine's state as the [NSRC] row the kernels read: position, rotation matrix
    (body -> world, row-major), velocity, noise offset. Validates its input."""
    p = _vec("sub_pos", sub_pos, 3)
    q = _vec("sub_quat", sub_quat, 4)
    v = _vec("sub_lin_vel", sub_lin_vel, 3)
    o = _vec("noise_offset", noise_offset, 3)
    n = float(np.linalg.norm(q))
    if n < 1e-12:
        raise ValueError(f"sub_quat must be non-zero, got {CK.show(sub_quat)}")
    w, x, y, z = q / n
    rot = (
        1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
        2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
        2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y),
    )  # fmt: skip
    return np.concatenate([p, rot, v, o])


NSRC = 18  # source row: pos 3, rotation 9, velocity 3, noise offset 3


def _vec(name, value, n) -> np.ndarray:
    a = CK.real_array("wake source", name, value)
    if a.shape != (n,):
        raise ValueError(f"{name} must have shape [{n}], got {list(a.shape)}: {CK.show(value)}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} has non-finite values: {CK.show(value)}")
    return a


# --------------------------------------------------------------------------------------------
# the field (scalar code: branches allowed; callers pass scalars, never the scratch array)


@njit(**_INLINE)
def _smoothstep(t):
    """0 below 0, 1 above 1, C1 in between."""
    t = min(max(t, 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


@njit(**_INLINE)
def _dipole(dx, dy, dz, mx, my, mz, core):
    """Velocity at offset d of a point dipole of moment m (the flow of a sphere of radius a
    moving at U has m = a^3 U / 2): (3 (m.d) d / r^5 - m / r^3), continued inside the core
    radius by (3 (m.d) d / c^5 - m / c^3) so that it stays finite and continuous."""
    r2 = dx * dx + dy * dy + dz * dz
    c2 = core * core
    if r2 >= c2:
        inv_r2 = 1.0 / r2
        inv_r3 = inv_r2 / math.sqrt(r2)
        s = 3.0 * (mx * dx + my * dy + mz * dz) * inv_r2 * inv_r3
    else:
        inv_r3 = 1.0 / (c2 * core)
        s = 3.0 * (mx * dx + my * dy + mz * dz) * inv_r3 / c2
    return s * dx - mx * inv_r3, s * dy - my * inv_r3, s * dz - mz * inv_r3


@njit(**_INLINE)
def _lamb_oseen(dy, dz, gamma, core):
    """Velocity (vy, vz) at cross-plane offset (dy, dz) of a Lamb-Oseen vortex of
    circulation gamma about +x: v_theta = gamma / (2 pi r) (1 - exp(-r^2 / core^2))."""
    r2 = dy * dy + dz * dz
    s = r2 / (core * core)
    # (1 - exp(-s)) / r^2 written to stay finite on the axis
    g = -math.expm1(-s) / r2 if s > 1e-6 else (1.0 - 0.5 * s) / (core * core)
    k = gamma / (2.0 * math.pi) * g
    return -k * dz, k * dy


@njit(**_INLINE)
def _hash(ix, iy, iz, channel):
    """A value in [-1, 1] for an integer lattice point (an integer mix; no tables)."""
    h = (ix * 73856093) ^ (iy * 19349663) ^ (iz * 83492791) ^ (channel * 2654435761)
    h &= 0xFFFFFFFF
    h ^= h >> 16
    h = (h * 0x7FEB352D) & 0xFFFFFFFF
    h ^= h >> 15
    h = (h * 0x846CA68B) & 0xFFFFFFFF
    h ^= h >> 16
    return h * (2.0 / 4294967295.0) - 1.0


@njit(**_INLINE)
def _fade(t):
    """Quintic fade 6t^5 - 15t^4 + 10t^3: C2 value noise."""
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)


@njit(**_JIT)
def value_noise(x, y, z, channel):
    """Smooth value noise in [-1, 1] at (x, y, z) (lattice spacing 1), one channel."""
    fx, fy, fz = math.floor(x), math.floor(y), math.floor(z)
    ix, iy, iz = np.int64(fx), np.int64(fy), np.int64(fz)
    u, v, w = _fade(x - fx), _fade(y - fy), _fade(z - fz)
    acc = 0.0
    for c in range(8):
        dx, dy, dz = c & 1, (c >> 1) & 1, (c >> 2) & 1
        wx = u if dx else 1.0 - u
        wy = v if dy else 1.0 - v
        wz = w if dz else 1.0 - w
        acc += wx * wy * wz * _hash(ix + dx, iy + dy, iz + dz, channel)
    return acc


@njit(**_JIT)
def wake_at(px, py, pz, src, wprm):
    """Fluid velocity (world frame) of the wake at world point (px, py, pz).

    ``src`` is the submarine's source row as a tuple of NSRC scalars (see :func:`source_row`),
    ``wprm`` the parameter array of :meth:`WakeField.params`. Zero when ``wprm[W_ON] == 0``.
    """
    if wprm[W_ON] == 0.0:
        return 0.0, 0.0, 0.0
    (sx, sy, sz, r0, r1, r2, r3, r4, r5, r6, r7, r8, ux, uy, uz, ox, oy, oz) = src
    # the point and the velocity in the hull frame (R^T)
    dx, dy, dz = px - sx, py - sy, pz - sz
    x = r0 * dx + r3 * dy + r6 * dz
    y = r1 * dx + r4 * dy + r7 * dz
    z = r2 * dx + r5 * dy + r8 * dz
    hux = r0 * ux + r3 * uy + r6 * uz
    huy = r1 * ux + r4 * uy + r7 * uz
    huz = r2 * ux + r5 * uy + r8 * uz
    speed = math.sqrt(ux * ux + uy * uy + uz * uz)
    vx = vy = vz = 0.0

    if wprm[W_DISPLACEMENT] != 0.0:
        mx, my, mz = wprm[W_C_AX] * hux, wprm[W_C_LAT] * huy, wprm[W_C_LAT] * huz
        for k in range(int(wprm[W_NDIP])):
            xk, share, core = wprm[W_DIP + 3 * k], wprm[W_DIP + 3 * k + 1], wprm[W_DIP + 3 * k + 2]
            ax, ay, az = _dipole(x - xk, y, z, share * mx, share * my, share * mz, core)
            vx += ax
            vy += ay
            vz += az

    xi = wprm[W_SCREW_X] - x  # distance aft of the screws
    if wprm[W_VORTICES] != 0.0 and xi > 0.0 and wprm[W_GAMMA] != 0.0:
        decay = wprm[W_DECAY]
        fade = math.exp(-xi / decay)
        gamma = wprm[W_GAMMA] * speed * _smoothstep(xi / wprm[W_B]) * fade
        core = wprm[W_CORE] + wprm[W_CORE_GROWTH] * xi
        if wprm[W_SCREWS] == 1.0:
            ay, az = _lamb_oseen(y, z, gamma, core)
            vy += ay
            vz += az
        else:
            # mutual drift: integral over the wake of (Gamma(xi) / (2 pi d)) / speed
            zc = wprm[W_DRIFT] * decay * (1.0 - fade)
            yc = wprm[W_SCREW_Y]
            ay, az = _lamb_oseen(y - yc, z - zc, gamma, core)  # port: gamma about +x
            by, bz = _lamb_oseen(y + yc, z - zc, -gamma, core)  # starboard: -gamma
            vy += ay + by
            vz += az + bz

    xs = -wprm[W_A] - x  # distance aft of the stern
    amp = wprm[W_NOISE] * speed
    if amp != 0.0 and xs > 0.0:
        width = wprm[W_B] + wprm[W_WAKE_GROWTH] * xs
        zc = wprm[W_DRIFT] * wprm[W_DECAY] * (1.0 - math.exp(-max(xi, 0.0) / wprm[W_DECAY]))
        rho2 = (y * y + (z - zc) * (z - zc)) / (width * width)
        env = amp * _smoothstep(0.5 * xs / wprm[W_B]) * math.exp(-xs / wprm[W_NOISE_DECAY] - rho2)
        if env > 1e-9 * amp:
            s = wprm[W_NOISE_INV_SCALE]
            qx, qy, qz = px * s + ox, py * s + oy, pz * s + oz
            # world-frame turbulence, frozen in the water
            wx = env * value_noise(qx, qy, qz, 1)
            wy = env * value_noise(qx, qy, qz, 2)
            wz = env * value_noise(qx, qy, qz, 3)
            return (
                r0 * vx + r1 * vy + r2 * vz + wx,
                r3 * vx + r4 * vy + r5 * vz + wy,
                r6 * vx + r7 * vy + r8 * vz + wz,
            )
    return r0 * vx + r1 * vy + r2 * vz, r3 * vx + r4 * vy + r5 * vz, r6 * vx + r7 * vy + r8 * vz


@njit(**_JIT)
def source_tuple(src):
    """The source row as the tuple :func:`wake_at` takes."""
    return (
        src[0], src[1], src[2], src[3], src[4], src[5], src[6], src[7], src[8],
        src[9], src[10], src[11], src[12], src[13], src[14], src[15], src[16], src[17],
    )  # fmt: skip


@njit(**_JIT)
def wake_velocity_batch(points, src, wprm, out):
    """out[N, 3] = wake velocity at points[N, 3] of one submarine (source row ``src``)."""
    s = source_tuple(src)
    for j in range(points.shape[0]):
        v = wake_at(points[j, 0], points[j, 1], points[j, 2], s, wprm)
        out[j, 0] = v[0]
        out[j, 1] = v[1]
        out[j, 2] = v[2]
