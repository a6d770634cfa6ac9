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
MAX_TABLE = 1_000_000  # nodes of the table model's displacement table (4 floats each)

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
    W_MODEL,
) = range(21)
W_DIP = 24  # then MAX_DIPOLES triples: axial position, volume share, core radius
NWPRM = W_DIP + 3 * MAX_DIPOLES  # the exact field's length; the table model's header follows
MODELS = ("exact", "table")  # wprm[W_MODEL] holds the index
# the table model's header (after the dipoles), then its tables
(
    W_T_X0,  # body x of the displacement table's first column
    W_T_INV_H,  # 1 / its step (the same along x and across, rho)
    W_T_NX,  # its nodes along x
    W_T_NR,  # its nodes across (rho from 0)
    W_T_EXACT,  # slot of its [NX, NR] cell flags (1: the dipole sum in the cell from there)
    W_T_G,  # slot of the vortex profile table (after the flags)
    W_T_G_INV_H,  # 1 / that table's step in s = r^2 / core^2
    W_T_G_N,  # its nodes (s from 0)
    W_T_FAR2,  # beyond the table and this squared distance: the single far-field dipole
) = range(NWPRM, NWPRM + 9)
FAR = 6.0  # that distance, in half hull lengths: the single dipole is within 3.3% there
W_TABLE = NWPRM + 12  # the displacement table: [NX, NR, 4] (F1..F4 of _displacement_table)
G_STEP = 1.0 / 64.0  # the vortex profile table's step in s
G_MAX = 32.0  # beyond it the profile is 1 / s (exp(-32) ~ 1e-14)


@dataclass(frozen=True)
class WakeField:
    """The flow around a submarine moving through still water (see the module docstring).

    Args:
        length_m: the hull's length: a prolate spheroid centered on the submarine's center
            of mass, axis along its body x (``length_m >= 2 radius_m``).
        radius_m: the hull's radius.
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
        displacement: switch the displacement flow on or off.
        vortices: switch the screws' vortices on or off (turbulence: ``noise=0``).
        model: ``"exact"`` (the default) evaluates every closed form at every point.
            ``"table"`` is the seed's spatial field taken literally, the same flow for less:
            the displacement flow (of ``dipoles`` dipoles) is read from a table in the hull's
            frame, four functions of (x, rho) interpolated bilinearly (next to the hull and
            past the table's edge: the dipole sum; far away: the single far-field dipole),
            so that its cost does not grow with ``dipoles``; the vortices' radial profile
            ``(1 - exp(-s)) / s`` is read from a table in ``s = r^2 / core^2``; the
            turbulence is the same value noise, its three channels computed together
            (:func:`value_noise3`: bit for bit the numbers of three :func:`value_noise`
            calls, which the exact model keeps). Where SubmarineWake's UUV flies it is within
            3e-5 of the hull's speed (RMS; at most 3.2e-4) of the exact field, at 0.51 of
            its cost at 8 dipoles and 0.34 at 24 (docs/study_wake.csv); what is left is
            mostly the turbulence's 24 hashed lattice corners.
        table_step_m: the displacement table's step along x and across (default: a sixth
            of the radius: a twelfth cuts the RMS error by 3 and costs SubmarineWake 5% more,
            the table four times larger); its error falls as the step squared.
        table_margin_m: the table reaches this far beyond the hull, along and across
            (default: half the hull's length).
        table_tolerance: a table cell where bilinear reading could be off by more than this
            fraction of the speed (its center and edges checked against the dipole sum when
            the table is made) gives the dipole sum instead: next to the hull, where the
            dipoles' cores meet, the table model costs what the exact one does.

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
    model: str = "exact"
    table_step_m: float | None = None
    table_margin_m: float | None = None
    table_tolerance: float = 1e-3

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
        CK.choice("WakeField", "model", self.model, MODELS)
        number("table_step_m", gt=0.0)
        number("table_margin_m", ge=0.0)
        CK.number("WakeField", "table_tolerance", self.table_tolerance, gt=0.0)
        if self.model == "table" and self._table_shape()[0] * self._table_shape()[1] > MAX_TABLE:
            nx, nr = self._table_shape()
            raise ValueError(
                f"WakeField: table_step_m ({self.table_step_m!r}) gives a table of {nx} x {nr} "
                f"nodes, more than {MAX_TABLE}: take a longer step or a smaller table_margin_m"
            )

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
        """The parameter array the kernels read (slots ``W_*`` of this module): NWPRM floats
        for the exact field; the table model appends its header and tables."""
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
        w[W_MODEL] = MODELS.index(self.model)
        if self.model == "table":
            w = self._tables(w)
        return w.astype(dtype)

    def table_step(self) -> float:
        """The table model's step (m): ``table_step_m``, by default a sixth of the radius."""
        return self.radius_m / 6.0 if self.table_step_m is None else self.table_step_m

    def _table_shape(self) -> tuple[int, int]:
        """Nodes of the displacement table along x and across (rho)."""
        h = self.table_step()
        margin = 0.5 * self.length_m if self.table_margin_m is None else self.table_margin_m
        nx = 2 * math.ceil((0.5 * self.length_m + margin) / h) + 1  # symmetric about x = 0
        nr = math.ceil((self.radius_m + margin) / h) + 1
        return nx, nr

    def _tables(self, w: np.ndarray) -> np.ndarray:
        """The table model's header and tables appended to the exact field's slots ``w``."""
        h = self.table_step()
        nx, nr = self._table_shape()
        x = (np.arange(nx) - (nx - 1) // 2) * h
        rho = np.arange(nr) * h
        K = int(w[W_NDIP])
        dip = w[W_DIP : W_DIP + 3 * K].reshape(K, 3)
        f = _f_table(x, rho, dip)
        # the cells that bilinear reading does not resolve to the tolerance (next to the hull,
        # where the dipoles' cores meet): at each cell's center and edge midpoints, the error
        # in velocity per unit speed that the F's errors can give (_displacement_table's sums)
        xm, rm = x[:-1] + 0.5 * h, rho[:-1] + 0.5 * h
        c_ax, c_lat = w[W_C_AX], w[W_C_LAT]

        def error(exact, approx, r):
            d = np.abs(exact - approx)
            return (c_ax * d[..., 0] + (c_ax + c_lat) * r * d[..., 1] + c_lat * r * r * d[..., 2]
                    + c_lat * d[..., 3])  # fmt: skip

        corners = 0.25 * (f[:-1, :-1] + f[1:, :-1] + f[:-1, 1:] + f[1:, 1:])
        center = error(_f_table(xm, rm, dip), corners, rm[None])
        along = error(_f_table(xm, rho, dip), 0.5 * (f[:-1] + f[1:]), rho[None])
        across = error(_f_table(x, rm, dip), 0.5 * (f[:, :-1] + f[:, 1:]), rm[None])
        worst = np.maximum.reduce(
            [center, along[:, :-1], along[:, 1:], across[:-1], across[1:]]
        )  # [nx - 1, nr - 1]
        exact = np.zeros((nx, nr))  # per cell, at its first corner: 1 = the dipole sum there
        exact[:-1, :-1] = worst > self.table_tolerance
        s = np.arange(int(round(G_MAX / G_STEP)) + 1) * G_STEP
        g = np.ones_like(s)
        g[1:] = -np.expm1(-s[1:]) / s[1:]  # (1 - exp(-s)) / s, 1 at s = 0
        head = np.zeros(W_TABLE - NWPRM)
        head[W_T_X0 - NWPRM] = x[0]
        head[W_T_INV_H - NWPRM] = 1.0 / h
        head[W_T_NX - NWPRM], head[W_T_NR - NWPRM] = nx, nr
        head[W_T_EXACT - NWPRM] = W_TABLE + f.size
        head[W_T_G - NWPRM] = W_TABLE + f.size + exact.size
        head[W_T_G_INV_H - NWPRM] = 1.0 / G_STEP
        head[W_T_G_N - NWPRM] = s.size
        head[W_T_FAR2 - NWPRM] = (FAR * 0.5 * self.length_m) ** 2
        return np.concatenate([w, head, f.ravel(), exact.ravel(), g])

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


def _f_table(x: np.ndarray, rho: np.ndarray, dip: np.ndarray) -> np.ndarray:
    """F1..F4 of :func:`_displacement_table` [len(x), len(rho), 4] at body x and rho, for
    the dipoles ``dip`` [K, 3] (axial position, share, core radius): :func:`_dipole`'s sum,
    per unit moment, split by direction."""
    f = np.zeros((x.size, rho.size, 4))
    for xk, share, core in dip:
        dx = (x - xk)[:, None]
        r2 = np.maximum(dx * dx + rho[None] ** 2, core * core)  # the core's continuation
        inv_r3 = 1.0 / (r2 * np.sqrt(r2))
        inv_r5 = inv_r3 / r2
        f[..., 0] += share * (3.0 * dx * dx * inv_r5 - inv_r3)
        f[..., 1] += share * 3.0 * dx * inv_r5
        f[..., 2] += share * 3.0 * inv_r5
        f[..., 3] += share * inv_r3
    return f


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


_HX, _HY, _HZ, _HC = 73856093, 19349663, 83492791, 2654435761  # the lattice hash's primes


@njit(**_INLINE)
def _mix(h):
    """Mix 32 bits (a hashed lattice point) into a value in [-1, 1]."""
    h ^= h >> 16
    h = (h * 0x7FEB352D) & 0xFFFFFFFF
    h ^= h >> 15
    h = (h * 0x846CA68B) & 0xFFFFFFFF
    h ^= h >> 16
    return h * (2.0 / 4294967295.0) - 1.0


@njit(**_INLINE)
def _hash(ix, iy, iz, channel):
    """A value in [-1, 1] for an integer lattice point (an integer mix; no tables)."""
    return _mix(((ix * _HX) ^ (iy * _HY) ^ (iz * _HZ) ^ (channel * _HC)) & 0xFFFFFFFF)


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


@njit(**_INLINE)
def _corner(a1, a2, a3, wt, hx, hy, hz):
    """Add one lattice corner, of weight ``wt`` and hashed coordinates (hx, hy, hz), to the
    three channels' sums (channels 1, 2, 3 of :func:`_hash`)."""
    h = hx ^ hy ^ hz
    return (
        a1 + wt * _mix((h ^ _HC) & 0xFFFFFFFF),
        a2 + wt * _mix((h ^ (2 * _HC)) & 0xFFFFFFFF),
        a3 + wt * _mix((h ^ (3 * _HC)) & 0xFFFFFFFF),
    )


@njit(**_INLINE)
def value_noise3(x, y, z):
    """:func:`value_noise` of channels 1, 2 and 3 at once, the same numbers bit for bit
    (tests/physics/test_wake.py): the lattice cell, the corner weights and the coordinates'
    part of the hash once, not thrice, the corners written out. A third of the time of three
    calls (benchmarks/study_wake.py)."""
    fx, fy, fz = math.floor(x), math.floor(y), math.floor(z)
    ix, iy, iz = np.int64(fx), np.int64(fy), np.int64(fz)
    u, v, w = _fade(x - fx), _fade(y - fy), _fade(z - fz)
    x0, x1 = ix * _HX, (ix + 1) * _HX
    y0, y1 = iy * _HY, (iy + 1) * _HY
    z0, z1 = iz * _HZ, (iz + 1) * _HZ
    u0, v0, w0 = 1.0 - u, 1.0 - v, 1.0 - w
    a = _corner(0.0, 0.0, 0.0, u0 * v0 * w0, x0, y0, z0)
    a = _corner(a[0], a[1], a[2], u * v0 * w0, x1, y0, z0)
    a = _corner(a[0], a[1], a[2], u0 * v * w0, x0, y1, z0)
    a = _corner(a[0], a[1], a[2], u * v * w0, x1, y1, z0)
    a = _corner(a[0], a[1], a[2], u0 * v0 * w, x0, y0, z1)
    a = _corner(a[0], a[1], a[2], u * v0 * w, x1, y0, z1)
    a = _corner(a[0], a[1], a[2], u0 * v * w, x0, y1, z1)
    return _corner(a[0], a[1], a[2], u * v * w, x1, y1, z1)


@njit(**_INLINE)
def _vortex_strength(xi, speed, fade, wprm):
    """Circulation and core radius of the screw vortices ``xi`` aft of the screws, where the
    decay factor is ``fade = exp(-xi / decay)``."""
    gamma = wprm[W_GAMMA] * speed * _smoothstep(xi / wprm[W_B]) * fade
    return gamma, wprm[W_CORE] + wprm[W_CORE_GROWTH] * xi


@njit(**_INLINE)
def _pair_z(fade, wprm):
    """How far the vortex pair has drifted along body z where the decay factor is ``fade``:
    the integral over the wake of (Gamma(xi) / (2 pi d)) / speed."""
    return wprm[W_DRIFT] * wprm[W_DECAY] * (1.0 - fade)


@njit(**_INLINE)
def _envelope(y, z, xs, zc, amp, wprm):
    """The turbulence's amplitude ``xs`` aft of the stern at (y, z) in the hull's frame, the
    wake's center drifted to ``zc``."""
    width = wprm[W_B] + wprm[W_WAKE_GROWTH] * xs
    rho2 = (y * y + (z - zc) * (z - zc)) / (width * width)
    return amp * _smoothstep(0.5 * xs / wprm[W_B]) * math.exp(-xs / wprm[W_NOISE_DECAY] - rho2)


@njit(**_INLINE)
def _dipole_sum(x, y, z, hux, huy, huz, wprm):
    """The displacement flow (hull frame) at hull-frame (x, y, z) of the hull moving at
    (hux, huy, huz): the axial dipoles' sum."""
    vx = vy = vz = 0.0
    mx, my, mz = wprm[W_C_AX] * hux, wprm[W_C_LAT] * huy, wprm[W_C_LAT] * huz
    for k in range(int(wprm[W_NDIP])):
        xk, share, core = wprm[W_DIP + 3 * k], wprm[W_DIP + 3 * k + 1], wprm[W_DIP + 3 * k + 2]
        ax, ay, az = _dipole(x - xk, y, z, share * mx, share * my, share * mz, core)
        vx += ax
        vy += ay
        vz += az
    return vx, vy, vz


@njit(**_INLINE)
def _displacement_table(x, y, z, hux, huy, huz, wprm):
    """The dipole sum of :func:`wake_at` (the displacement flow, hull frame) from the table:
    (True, vx, vy, vz), or (False, 0, 0, 0) where the dipole sum itself is wanted.

    For dipoles on the axis, a moment ``m`` and the offset ``(x - x_k, y, z)``, the sum is
    ``v_x = m_x F1 + p F2``, ``v_perp = (m_x F2 + p F3) (y, z) - m_perp F4`` with
    ``p = m_y y + m_z z`` and four functions of (x, rho) alone: ``F1 = sum s (3 dx^2 / r^5 -
    1 / r^3)``, ``F2 = sum 3 s dx / r^5``, ``F3 = sum 3 s / r^5``, ``F4 = sum s / r^3``
    (``r`` at least the core radius, as :func:`_dipole`); the table holds them on a square
    grid, read bilinearly. In the cells it does not resolve (``WakeField.table_tolerance``)
    and past its edge: the dipole sum itself; beyond ``FAR`` half lengths from the center, one
    dipole of the whole moment there. The sum differs from that by its octupole part: the
    shares' second moment (a^2 / 5) times the field's second derivative, on the axis
    6/5 (a / r)^2 of it (Batchelor 6.4 for the far field)."""
    mx, my, mz = wprm[W_C_AX] * hux, wprm[W_C_LAT] * huy, wprm[W_C_LAT] * huz
    rho = math.sqrt(y * y + z * z)
    inv_h = wprm[W_T_INV_H]
    fx = (x - wprm[W_T_X0]) * inv_h
    fr = rho * inv_h
    nr = int(wprm[W_T_NR])
    if fx >= 0.0 and fx < wprm[W_T_NX] - 1.0 and fr < nr - 1.0:
        i, j = int(fx), int(fr)
        if wprm[int(wprm[W_T_EXACT]) + i * nr + j] != 0.0:  # a cell the table does not resolve
            return False, 0.0, 0.0, 0.0
        tx, tr = fx - i, fr - j
        a = W_TABLE + 4 * (i * nr + j)  # corners a (i, j), a + 4 (i, j + 1), then row i + 1
        b = a + 4 * nr
        w00, w01 = (1.0 - tx) * (1.0 - tr), (1.0 - tx) * tr
        w10, w11 = tx * (1.0 - tr), tx * tr
        f1 = w00 * wprm[a] + w01 * wprm[a + 4] + w10 * wprm[b] + w11 * wprm[b + 4]
        f2 = w00 * wprm[a + 1] + w01 * wprm[a + 5] + w10 * wprm[b + 1] + w11 * wprm[b + 5]
        f3 = w00 * wprm[a + 2] + w01 * wprm[a + 6] + w10 * wprm[b + 2] + w11 * wprm[b + 6]
        f4 = w00 * wprm[a + 3] + w01 * wprm[a + 7] + w10 * wprm[b + 3] + w11 * wprm[b + 7]
    else:
        r2 = x * x + rho * rho
        if r2 < wprm[W_T_FAR2]:
            return False, 0.0, 0.0, 0.0
        # far: one dipole at the center (the shares sum to one)
        f4 = 1.0 / (r2 * math.sqrt(r2))
        f3 = 3.0 * f4 / r2
        f2 = f3 * x
        f1 = f2 * x - f4
    p = my * y + mz * z
    q = mx * f2 + p * f3
    return True, mx * f1 + p * f2, q * y - my * f4, q * z - mz * f4


@njit(**_INLINE)
def _profile_table(r2, core, wprm):
    """:func:`_lamb_oseen`'s ``(1 - exp(-s)) / r^2`` at ``s = r^2 / core^2`` from the table of
    ``G(s) = (1 - exp(-s)) / s`` (read linearly; ``1 / s`` past its end), over ``core^2``."""
    inv_c2 = 1.0 / (core * core)
    s = r2 * inv_c2
    t = s * wprm[W_T_G_INV_H]
    if t < wprm[W_T_G_N] - 1.0:
        k = int(t)
        g0 = wprm[int(wprm[W_T_G]) + k]
        g = g0 + (t - k) * (wprm[int(wprm[W_T_G]) + k + 1] - g0)
    else:
        g = 1.0 / s
    return g * inv_c2


@njit(**_INLINE)
def _lamb_oseen_table(dy, dz, gamma, core, wprm):
    """:func:`_lamb_oseen` with its profile read from the table (:func:`_profile_table`)."""
    k = gamma / (2.0 * math.pi) * _profile_table(dy * dy + dz * dz, core, wprm)
    return -k * dz, k * dy


@njit(**_INLINE)
def _wake_table_at(px, py, pz, src, wprm):
    """:func:`wake_at` of the table model (``WakeField(model="table")``): the displacement
    from :func:`_displacement_table` where it reads (the dipole sum elsewhere), the vortices'
    profile from :func:`_profile_table`, the turbulence from :func:`value_noise3`; the rest
    is the exact model's closed forms (the shared helpers)."""
    (sx, sy, sz, r0, r1, r2, r3, r4, r5, r6, r7, r8, ux, uy, uz, ox, oy, oz) = src
    dx, dy, dz = px - sx, py - sy, pz - sz
    x = r0 * dx + r3 * dy + r6 * dz
    y = r1 * dx + r4 * dy + r7 * dz
    z = r2 * dx + r5 * dy + r8 * dz
    speed = math.sqrt(ux * ux + uy * uy + uz * uz)
    vx = vy = vz = 0.0
    if wprm[W_DISPLACEMENT] != 0.0:
        hux = r0 * ux + r3 * uy + r6 * uz
        huy = r1 * ux + r4 * uy + r7 * uz
        huz = r2 * ux + r5 * uy + r8 * uz
        read, vx, vy, vz = _displacement_table(x, y, z, hux, huy, huz, wprm)
        if not read:
            vx, vy, vz = _dipole_sum(x, y, z, hux, huy, huz, wprm)

    xi = wprm[W_SCREW_X] - x  # distance aft of the screws
    xs = -wprm[W_A] - x  # distance aft of the stern
    amp = wprm[W_NOISE] * speed
    vortex = wprm[W_VORTICES] != 0.0 and xi > 0.0 and wprm[W_GAMMA] != 0.0
    noise = amp != 0.0 and xs > 0.0
    if vortex or noise:
        fade = math.exp(-max(xi, 0.0) / wprm[W_DECAY])  # one exp for both
        zc = _pair_z(fade, wprm)
        if vortex:
            gamma, core = _vortex_strength(xi, speed, fade, wprm)
            if wprm[W_SCREWS] == 1.0:
                ay, az = _lamb_oseen_table(y, z, gamma, core, wprm)
                vy += ay
                vz += az
            else:
                yc = wprm[W_SCREW_Y]
                ay, az = _lamb_oseen_table(y - yc, z - zc, gamma, core, wprm)
                by, bz = _lamb_oseen_table(y + yc, z - zc, -gamma, core, wprm)
                vy += ay + by
                vz += az + bz
        if noise:
            env = _envelope(y, z, xs, zc, amp, wprm)
            if env > 1e-9 * amp:
                s = wprm[W_NOISE_INV_SCALE]
                n1, n2, n3 = value_noise3(px * s + ox, py * s + oy, pz * s + oz)
                return (
                    r0 * vx + r1 * vy + r2 * vz + env * n1,
                    r3 * vx + r4 * vy + r5 * vz + env * n2,
                    r6 * vx + r7 * vy + r8 * vz + env * n3,
                )
    return r0 * vx + r1 * vy + r2 * vz, r3 * vx + r4 * vy + r5 * vz, r6 * vx + r7 * vy + r8 * vz


@njit(**_JIT)
def wake_at(px, py, pz, src, wprm):
    """Fluid velocity (world frame) of the wake at world point (px, py, pz).

    ``src`` is the submarine's source row as a tuple of NSRC scalars (see :func:`source_row`),
    ``wprm`` the parameter array of :meth:`WakeField.params`. Zero when ``wprm[W_ON] == 0``;
    the table model's (``wprm[W_MODEL] != 0``) is :func:`_wake_table_at`. This function's
    own code is the exact model's, as it always was: its sums round the same (helpers or
    branches shared with the table model made the fused multiply-adds round some 1e-15
    differently in the step kernel).
    """
    if wprm[W_ON] == 0.0:
        return 0.0, 0.0, 0.0
    if wprm[W_MODEL] != 0.0:
        return _wake_table_at(px, py, pz, src, wprm)
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
