"""Savitsky's (1964) planing-hull method: closed-form running trim and resistance.

A reference for tests and benchmarks, not part of the simulator. Savitsky reduced towing-tank
data on prismatic planing surfaces (constant beam and deadrise) to empirical formulas for lift,
wetted length, centre of pressure and friction, and balanced them against weight and thrust:
D. Savitsky, "Hydrodynamic Design of Planing Hulls", Marine Technology 1(1), 1964, pp. 71-95.

Given a hull and a speed, :func:`savitsky` finds the trim at which the pitching moment about the
centre of gravity vanishes. ``general=False`` is the paper's short form (Table 2): every force acts
through the CG, so the centre of pressure sits at the LCG. ``general=True`` is the paper's general
equilibrium (Table 1, eqs. 34-35): thrust along a line inclined ``epsilon`` to the keel and
``f`` below the CG, friction drag acting ``a = VCG - (b/4) tan(beta)`` below the CG.

Validity (the data the formulas were fitted to): 0.60 <= Cv <= 13, 2 <= trim <= 15 deg,
lambda <= 4; deadrise 10-30 deg. ``PlaningState.in_range`` also asks for wetted chines
(L_C > 0), which the lift formula assumes. Savitsky himself advises Cv >= 1 (fully planing).

Units are SI throughout. The empirical formulas take trim and deadrise in *degrees* as plain
numbers (tau**1.1, 0.0065 * beta); trigonometry uses radians. The friction line defaults to
ITTC-1957; Savitsky used Schoenherr (``friction_line="schoenherr"``), plus a roughness allowance
of 0.0004. Resistance is the horizontal drag D = W tan(tau) + D_f / cos(tau) (the paper's
Tables 1 and 2); it omits air, spray and appendage drag.

A 5 m runabout at 15 m/s (about 29 knots):

>>> hull = PrismaticHull(beam_m=1.8, deadrise_deg=18.0, mass_kg=1000.0, lcg_m=1.9)
>>> s = savitsky(hull, 15.0, general=False)
>>> round(s.trim_deg, 2), round(s.lambda_, 2), round(s.resistance_over_weight, 3), s.in_range
(2.57, 1.47, 0.209, True)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from itertools import pairwise
from numbers import Real

CV_RANGE = (0.60, 13.0)
TRIM_RANGE_DEG = (2.0, 15.0)
DEADRISE_RANGE_DEG = (10.0, 30.0)
LAMBDA_MAX = 4.0
TRIM_BRACKET_DEG = (0.5, 30.0)  # where savitsky() looks for an equilibrium


def _check(name: str, value: object, ok: Callable[[float], bool], need: str) -> None:
    """Raise ValueError naming ``name`` unless value is a finite real number with ok(value)."""
    real = isinstance(value, Real) and not isinstance(value, bool)
    if not (real and math.isfinite(value) and ok(value)):
        raise ValueError(f"{name} must be {need}, got {value!r}")


@dataclass(frozen=True)
class PrismaticHull:
    """Constant-beam, constant-deadrise planing hull. Lengths in m from the transom / keel."""

    beam_m: float  # chine beam b
    deadrise_deg: float  # beta
    mass_kg: float
    lcg_m: float  # centre of gravity ahead of the transom
    vcg_m: float = 0.0  # centre of gravity above the keel
    thrust_angle_deg: float = 0.0  # epsilon: thrust line relative to the keel, bow-up positive
    thrust_offset_m: float = 0.0  # f: thrust line's perpendicular distance below the CG

    def __post_init__(self) -> None:
        rules = {
            "beam_m": (lambda x: x > 0, "positive and finite"),
            "mass_kg": (lambda x: x > 0, "positive and finite"),
            "lcg_m": (lambda x: x > 0, "positive and finite"),
            "deadrise_deg": (lambda x: 0 <= x < 60, "in [0, 60) deg"),
            "vcg_m": (lambda x: True, "finite"),
            "thrust_angle_deg": (lambda x: -45 < x < 45, "in (-45, 45) deg"),
            "thrust_offset_m": (lambda x: True, "finite"),
        }
        for name, (ok, need) in rules.items():
            _check(f"PrismaticHull.{name}", getattr(self, name), ok, need)


@dataclass(frozen=True)
class PlaningState:
    """Savitsky's prediction at one speed and trim (SI; angles in degrees). ``in_range``: Cv,
    trim, deadrise and lambda inside the method's validity ranges, and the chines wetted."""

    speed_mps: float
    cv: float  # speed coefficient V / sqrt(g b)
    trim_deg: float
    lambda_: float  # mean wetted length / beam
    keel_wetted_length_m: float
    chine_wetted_length_m: float
    lift_coefficient_beta: float  # C_L_beta = W / (rho/2 V^2 b^2)
    lift_coefficient_zero: float  # C_L0, the flat-plate equivalent (eq. 16 inverted)
    center_of_pressure_m: float  # l_p, ahead of the transom
    mean_bottom_velocity_mps: float
    reynolds: float  # on the mean bottom velocity and mean wetted length
    friction_coefficient: float  # the friction line's C_f, without the roughness allowance
    friction_drag_n: float
    resistance_n: float  # horizontal: W tan(tau) + D_f / cos(tau)
    resistance_over_weight: float
    bow_down_moment_nm: float  # net moment about the CG; zero at equilibrium
    in_range: bool


def _bisect(fn: Callable[[float], float], lo: float, hi: float) -> float:
    """Root of fn bracketed by [lo, hi], halved until the interval stops shrinking."""
    f_lo = fn(lo)
    while True:
        mid = 0.5 * (lo + hi)
        if not lo < mid < hi:
            return mid
        f_mid = fn(mid)
        if f_mid == 0.0:
            return mid
        if (f_mid < 0.0) == (f_lo < 0.0):
            lo, f_lo = mid, f_mid
        else:
            hi = mid


def _grow(fn: Callable[[float], float], x: float) -> float:
    """Double x until fn(x) >= 0 (fn increasing), giving the upper end of a bracket."""
    while fn(x) < 0.0:
        x *= 2.0
    return x


def _cf_ittc1957(re: float) -> float:
    return 0.075 / (math.log10(re) - 2.0) ** 2


def _cf_schoenherr(re: float) -> float:
    # 0.242 / sqrt(Cf) = log10(Re Cf) has no closed form; the left side minus the right falls
    # monotonically in Cf, and [1e-5, 1] brackets its root for any ship or model Re.
    return _bisect(lambda cf: 0.242 / math.sqrt(cf) - math.log10(re * cf), 1e-5, 1.0)


FRICTION_LINES = {"ittc1957": _cf_ittc1957, "schoenherr": _cf_schoenherr}


def _state_at(
    hull: PrismaticHull,
    speed_mps: float,
    *,
    water_density_kgm3: float = 1025.0,
    kinematic_viscosity_m2s: float = 1.19e-6,
    gravity_mps2: float = 9.81,
    general: bool = True,
    friction_line: str = "ittc1957",
    roughness_allowance: float = 0.0004,
) -> Callable[[float], PlaningState]:
    """Validate the inputs and return trim_deg -> PlaningState for this hull and speed."""
    if not isinstance(hull, PrismaticHull):
        raise ValueError(f"hull must be a PrismaticHull, got {hull!r}")
    v, rho, nu, g = speed_mps, water_density_kgm3, kinematic_viscosity_m2s, gravity_mps2
    for name, x in (("speed_mps", v), ("water_density_kgm3", rho),
                    ("kinematic_viscosity_m2s", nu), ("gravity_mps2", g)):  # fmt: skip
        _check(name, x, lambda x: x > 0, "positive and finite")
    dcf = roughness_allowance
    _check("roughness_allowance", dcf, lambda x: x >= 0, "finite and >= 0")
    if friction_line not in FRICTION_LINES:
        raise ValueError(f"friction_line must be one of {sorted(FRICTION_LINES)}, "
                         f"got {friction_line!r}")  # fmt: skip
    cf_line = FRICTION_LINES[friction_line]

    b, beta, weight = hull.beam_m, hull.deadrise_deg, hull.mass_kg * g
    beta_r, eps_r = math.radians(beta), math.radians(hull.thrust_angle_deg)
    cv = v / math.sqrt(g * b)
    cl_beta = weight / (0.5 * rho * v * v * b * b)
    # Eq. (16), C_Lb = C_L0 - 0.0065 beta C_L0^0.6, rises monotonically above its turning point
    # C_L0 = (0.0039 beta)^2.5, so the inverse on that branch is unique. It needs no trim.
    k = 0.0065 * beta

    def lift16(cl0: float) -> float:
        return cl0 - k * cl0**0.6 - cl_beta

    lo = (0.6 * k) ** 2.5
    cl0 = _bisect(lift16, lo, _grow(lift16, max(cl_beta, lo, 1e-12))) if k > 0 else cl_beta
    a = hull.vcg_m - 0.25 * b * math.tan(beta_r)  # friction line below the CG

    def at(trim_deg: float) -> PlaningState:
        tau = math.radians(trim_deg)
        t11 = trim_deg**1.1

        # Eq. (15): C_L0 = tau^1.1 (0.0120 lambda^0.5 + 0.0055 lambda^2.5 / Cv^2), increasing in
        # lambda from zero, so [0, grown bound] brackets a unique wetted length.
        def lift15(lam: float) -> float:
            return t11 * (0.0120 * lam**0.5 + 0.0055 * lam**2.5 / cv**2) - cl0

        lam = _bisect(lift15, 0.0, _grow(lift15, 1.0))
        # Savitsky's pressure correction: the dynamic bottom pressure (the 0.0120 term of eq. 15)
        # slows the flow under the hull, by Bernoulli. Far outside the method the correction can
        # exceed 1; clamp it so that the trim scan stays defined there.
        vm = v * math.sqrt(max(0.0, 1.0 - 0.0120 * t11 / (math.sqrt(lam) * math.cos(tau))))
        re = vm * lam * b / nu
        cf = cf_line(max(re, 1e5))  # both lines are turbulent; below 1e5 they mean nothing
        friction = rho * vm**2 * lam * b * b * (cf + dcf) / (2.0 * math.cos(beta_r))
        drag = weight * math.tan(tau) + friction / math.cos(tau)
        # Centre of pressure, eq. (28): 75 % of the mean wetted length for dynamic lift, 33 %
        # for buoyancy, blended on (Cv / lambda)^2.
        lp = lam * b * (0.75 - 1.0 / (5.21 * cv**2 / lam**2 + 2.39))
        c = hull.lcg_m - lp  # normal force's lever arm, aft of the CG when positive
        if general:  # eq. (35): normal force, thrust and friction about the CG
            n_arm = (1.0 - math.sin(tau) * math.sin(tau + eps_r)) * c / math.cos(tau)
            f = hull.thrust_offset_m
            moment = weight * (n_arm - f * math.sin(tau)) + friction * (a - f)
        else:  # short form: thrust and friction act through the CG, N = W / cos(tau) at l_p
            moment = weight * c / math.cos(tau)
        # A vee bottom meets the water at the keel ahead of the chine; with the water rising up
        # the bottom (wave rise) the gap L_K - L_C is b tan(beta) / (pi tan(tau)).
        half_gap = b * math.tan(beta_r) / (2.0 * math.pi * math.tan(tau))
        lc = lam * b - half_gap
        in_range = (
            CV_RANGE[0] <= cv <= CV_RANGE[1]
            and TRIM_RANGE_DEG[0] <= trim_deg <= TRIM_RANGE_DEG[1]
            and DEADRISE_RANGE_DEG[0] <= beta <= DEADRISE_RANGE_DEG[1]
            and lam <= LAMBDA_MAX
            and lc > 0.0
        )
        return PlaningState(
            v, cv, trim_deg, lam, lam * b + half_gap, lc, cl_beta, cl0, lp, vm, re, cf,
            friction, drag, drag / weight, moment, bool(in_range),
        )  # fmt: skip

    return at


def savitsky_at_trim(hull: PrismaticHull, speed_mps: float, trim_deg: float, **kw) -> PlaningState:
    """Savitsky's forces at an imposed trim (not necessarily in equilibrium: see
    ``bow_down_moment_nm``), e.g. to compare with a simulated boat at its own running trim.
    Keywords as for :func:`savitsky`."""
    at = _state_at(hull, speed_mps, **kw)
    _check("trim_deg", trim_deg, lambda x: 0 < x < 90, "in (0, 90) deg")
    return at(float(trim_deg))


def of_hull(hull) -> PrismaticHull:
    """The prismatic hull Savitsky's method takes for a generated V-bottom hull
    (``craft.hull.VHull``: its chine beam, deadrise, weight and center of gravity), its thrust
    line at the propeller, 0.3 m below the keel."""
    return PrismaticHull(
        beam_m=hull.chine_beam_m,
        deadrise_deg=hull.deadrise_deg,
        mass_kg=hull.mass_kg,
        lcg_m=hull.lcg_m,
        vcg_m=hull.vcg_m,
        thrust_offset_m=hull.vcg_m + 0.3,
    )


def savitsky(
    hull: PrismaticHull,
    speed_mps: float,
    *,
    water_density_kgm3: float = 1025.0,
    kinematic_viscosity_m2s: float = 1.19e-6,
    gravity_mps2: float = 9.81,
    general: bool = True,
    friction_line: str = "ittc1957",
    roughness_allowance: float = 0.0004,
) -> PlaningState:
    """Equilibrium running trim and resistance of ``hull`` at ``speed_mps``.

    Scans TRIM_BRACKET_DEG in 0.25 deg steps for the first trim where the bow-down moment turns
    from negative to positive (a statically stable equilibrium), then bisects to machine precision.
    Raises ValueError if the bracket holds none. (At low speed the lift formulas tend to their
    buoyant limit and still give an answer: check ``in_range``.)
    """
    at = _state_at(
        hull, speed_mps, water_density_kgm3=water_density_kgm3,
        kinematic_viscosity_m2s=kinematic_viscosity_m2s, gravity_mps2=gravity_mps2,
        general=general, friction_line=friction_line, roughness_allowance=roughness_allowance,
    )  # fmt: skip

    def moment(trim_deg: float) -> float:
        return at(trim_deg).bow_down_moment_nm

    lo_deg, hi_deg = TRIM_BRACKET_DEG
    n = round((hi_deg - lo_deg) / 0.25)
    grid = [lo_deg + (hi_deg - lo_deg) * i / n for i in range(n + 1)]
    m_prev = moment(grid[0])
    for t0, t1 in pairwise(grid):
        m1 = moment(t1)
        if m_prev <= 0.0 < m1:
            return at(t0 if m_prev == 0.0 else _bisect(moment, t0, t1))
        m_prev = m1
    raise ValueError(
        f"no equilibrium trim between {lo_deg} and {hi_deg} deg at speed_mps={speed_mps!r} "
        f"({'general' if general else 'short'} form): the CG is too far forward or aft for the "
        "lift this speed needs"
    )


def savitsky_sweep(hull: PrismaticHull, speeds: Iterable[float], **kw) -> list[PlaningState]:
    """:func:`savitsky` at each speed (keywords passed through)."""
    return [savitsky(hull, float(v), **kw) for v in speeds]
