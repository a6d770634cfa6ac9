"""The fixed-point formats, the unit scale factors and the packing of crafts into integers.

The format. ``fixed32`` and ``fixed64`` hold every number as an integer word ``n`` standing
for ``n / 2**f`` (``f = fraction_bits``; the source article's is 14, ``1 << 14 == 1.0``) in
the craft's units. ``fixed32``'s words are 32-bit: ``|n| <= 2**31 - 1``; products are taken
in 64 bits and shifted back. ``fixed64``'s words are int64 limited to ``|n| <= 2**61 - 1``
(two guard bits: a product split at the binary point sums partial products that then stay
inside int64, ``laws.qmul``). Both take ``1 <= f <= 30``: the word must hold 1.0 (fixed32:
``2**30 < 2**31``), and the split product is exact for ``f <= 30``. Every operation rounds
half up and saturates (``laws.py``); a body with a saturated state word is flagged
``diverged``.

Units. A 5 g dart's inertia (7e-6 kg m^2) is 0.11 counts in Q14 SI, zero; a 773 t
submarine's buoyancy (7.6 MN) needs 37 bits. So each simulator counts in units of length,
mass and time chosen for its crafts (:func:`derive_units`, the first craft's):

- length ``L``: the power of two nearest the craft's reach (the farthest sample from the
  center of mass, or its radius of gyration if larger);
- mass ``M``: the power of two nearest its mass;
- time ``T``: the power of two nearest ``sqrt(L / g)`` (the time to fall about its own size;
  g = 9.81 without gravity), at least dt's next power of two (so ``h = dt / T <= 1``); under
  ``prescaled_symplectic_euler`` the step itself, ``T = dt``: velocities are then
  displacements per step, forces ``F dt^2``, as the source article's variant stores them.

Powers of two make every conversion of a craft number exact up to the final rounding. With
them, mass and length are O(1), gravity between 1/2 and 2, forces near the weight O(1):
the values the format resolves best. ``units=`` overrides any of the three
(``{"length_m": ..., "mass_kg": ..., "time_s": ...}``).

Packing (:func:`pack`) converts every number of the crafts and the world to the format.
A value that passes the word, or a size that rounds to zero (a mass, an inertia, an area,
a volume, a thrust, gravity, a density, the step), is refused with an error naming the
value, the craft and the format. The clamps (``World.max_fluid_speed_mps``,
``max_sample_force_n``) and a sharp surface's ``1/blend`` (``surface_blend_m = 0``) saturate
at the word instead: a clamp beyond the format's range clamps nothing the format can hold
anyway, and a saturated ``1/blend`` is still a step.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .. import checks as CK
from .. import model as M
from ..craft import Craft
from ..world import World
from . import laws as LW

FORMATS = ("fixed32", "fixed64")
LIMITS = {"fixed32": (1 << 31) - 1, "fixed64": (1 << 61) - 1}
MIN_FRACTION_BITS, MAX_FRACTION_BITS = 1, 30
INTEGRATORS = ("symplectic_euler", "prescaled_symplectic_euler")
MAX_MIX_RAD = 4.0  # a deflection per unit of a channel: its product with a control fits int64


@dataclass(frozen=True)
class Format:
    """A fixed-point format: its name (``fixed32`` or ``fixed64``) and fraction bits."""

    name: str
    fraction_bits: int

    @property
    def lim(self) -> int:
        """The largest word magnitude."""
        return LIMITS[self.name]

    @property
    def largest(self) -> float:
        """The largest number the format holds, in the craft's units."""
        return self.lim / 2.0**self.fraction_bits

    def __str__(self) -> str:
        return f"{self.name} with {self.fraction_bits} fraction bits"


def fixed_format(dtype, fraction_bits) -> Format:
    """The format of ``dtype`` (``"fixed32"``, ``"fixed64"``) with ``fraction_bits``;
    anything else raises naming it."""
    if dtype not in FORMATS:
        raise ValueError(f"Simulator: unknown fixed-point dtype {CK.show(dtype)}; choose {FORMATS}")
    try:
        f = CK.number("Simulator", "fraction_bits", fraction_bits, integer=True)
    except ValueError:
        f = None
    if f is None or not MIN_FRACTION_BITS <= f <= MAX_FRACTION_BITS:
        raise ValueError(
            f"Simulator: fraction_bits must be an integer in [{MIN_FRACTION_BITS}, "
            f"{MAX_FRACTION_BITS}] for {dtype} (its word must hold 1.0, 2**fraction_bits, "
            f"and a product split at the binary point must stay exact), got "
            f"{CK.show(fraction_bits)}"
        )
    return Format(dtype, int(f))


@dataclass(frozen=True)
class Units:
    """What one unit of length (m), mass (kg) and time (s) is in a fixed-point simulator."""

    length_m: float
    mass_kg: float
    time_s: float

    def scale(self, length: int = 0, mass: int = 0, time: int = 0) -> float:
        """The SI size of one unit of a quantity of dimension L^length M^mass T^time."""
        return self.length_m**length * self.mass_kg**mass * self.time_s**time


def _pow2(x: float) -> float:
    return 2.0 ** round(math.log2(x))


def craft_reach(craft: Craft) -> float:
    """The craft's size for its length unit: its farthest sample from the center of mass,
    or its largest radius of gyration if that is larger (a craft without samples)."""
    parts = (*craft.plates, *craft.cylinders, *craft.buoyancy, *craft.thrusters)
    far = max((math.hypot(*p.offset_m) for p in parts), default=0.0)
    gyration = math.sqrt(float(np.max(np.linalg.eigvalsh(craft.inertia_tensor))) / craft.mass_kg)
    return max(far, gyration)


def derive_units(craft: Craft, world: World, dt: float, prescaled: bool) -> Units:
    """The units a craft is counted in (module docstring)."""
    length = _pow2(craft_reach(craft))
    mass = _pow2(craft.mass_kg)
    if prescaled:
        return Units(length, mass, float(dt))
    g = world.gravity_mps2 if world.gravity_mps2 > 0 else 9.81
    time = max(_pow2(math.sqrt(length / g)), 2.0 ** math.ceil(math.log2(dt)))
    return Units(length, mass, time)


def coerce_units(units, derived: Units, prescaled: bool, dt: float) -> Units:
    """``units=``: None (the derived ones), a :class:`Units`, or a dict overriding some of
    ``length_m``, ``mass_kg``, ``time_s``; each > 0. The prescaled integrator counts time in
    steps: a time unit other than dt is refused."""
    if units is None:
        return derived
    if isinstance(units, Units):
        units = {"length_m": units.length_m, "mass_kg": units.mass_kg, "time_s": units.time_s}
    if not isinstance(units, dict):
        raise ValueError(
            f"Simulator: units must be None, a Units or a dict with keys length_m, mass_kg, "
            f"time_s, got {CK.show(units)}"
        )
    valid = ("length_m", "mass_kg", "time_s")
    unknown = [k for k in units if k not in valid]
    if unknown:
        raise ValueError(f"Simulator: unknown units key(s) {unknown}; valid keys are {valid}")
    values = {k: CK.number("Simulator", f"units.{k}", v, gt=0.0) for k, v in units.items()}
    if prescaled and "time_s" in values and values["time_s"] != dt:
        raise ValueError(
            f"Simulator: prescaled_symplectic_euler counts time in steps (units.time_s = dt = "
            f"{dt}), got units.time_s = {values['time_s']!r}"
        )
    return Units(**{k: values.get(k, getattr(derived, k)) for k in valid})


class FixedModel(NamedTuple):
    """What the integer kernel reads (int64 arrays)."""

    prm: np.ndarray  # [laws.NPRM]
    bc: np.ndarray  # [B, laws.NBC]
    tab: np.ndarray  # [B, n] each body's sample table (laws.T_*, W_*)
    mix: np.ndarray  # [B, n_flap * C] rad per unit of each channel (laws.ANGLE_BITS)
    n_inp: int  # the inputs' width per body (laws.body_inputs)


class _Packer:
    """Converts numbers to words, naming what it refuses."""

    def __init__(self, fmt: Format, units: Units, craft: str) -> None:
        self.fmt, self.units, self.craft = fmt, units, craft

    def __call__(self, value, what: str, si: str, dims=(0, 0, 0), nonzero=False, saturate=False):
        value = float(value)
        scale = self.units.scale(*dims)
        exact = value / scale * 2.0**self.fmt.fraction_bits
        lim = self.fmt.lim
        if abs(exact) > lim:
            if saturate:
                return lim if exact > 0 else -lim
            raise ValueError(
                f"Simulator: {self.fmt} cannot hold {self.craft} {what} = {value:.6g} {si}: "
                f"it is {value / scale:.4g} units of {scale:.4g} {si}, above the format's "
                f"largest {self.fmt.largest:.4g} (units {self._units()}; pass units= or fewer "
                f"fraction_bits)"
            )
        word = math.floor(exact + 0.5)
        if nonzero and value != 0.0 and word == 0:
            raise ValueError(
                f"Simulator: {self.fmt} rounds {self.craft} {what} = {value:.6g} {si} to zero: "
                f"its smallest step is {scale / 2.0**self.fmt.fraction_bits:.4g} {si} (units "
                f"{self._units()}; pass units= or more fraction_bits)"
            )
        return word

    def offset(self, part) -> list[int]:
        """A sample's offset from the center of mass, as words."""
        return [
            self(v, f"{part.name}.offset_m[{k}]", "m", LENGTH) for k, v in enumerate(part.offset_m)
        ]

    def unit(self, part, key: str) -> list[int]:
        """A sample's unit vector ``key``, as words."""
        return [
            self(v, f"{part.name}.{key}[{k}]", "", NONE) for k, v in enumerate(getattr(part, key))
        ]

    def _units(self) -> str:
        u = self.units
        return f"{u.length_m:g} m, {u.mass_kg:g} kg, {u.time_s:g} s"


# the inverse inertia's entries, as model.body_rows orders them
INERTIA_PAIRS = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))
LENGTH, AREA, VOLUME, NONE = (1, 0, 0), (2, 0, 0), (3, 0, 0), (0, 0, 0)
SPEED, ACCEL, FORCE = (1, 0, -1), (1, 0, -2), (1, 1, -2)
DENSITY, MOMENTUM = (-3, 1, 0), (2, 1, -1)


def pack(
    crafts: Sequence[Craft], world: World, dt: float, fmt: Format, units: Units, prescaled: bool
) -> FixedModel:
    """Every number of the crafts, the world and the step in the format (module docstring)."""
    f = fmt.fraction_bits
    bcs, tabs, mixes = [], [], []
    offsets = np.cumsum([0] + [len(c.control_names) for c in crafts])
    C = int(offsets[-1])
    for b, craft in enumerate(crafts):
        q = _Packer(fmt, units, f"craft {craft.name!r}")
        q(craft.mass_kg, "mass_kg", "kg", (0, 1, 0), nonzero=True)  # what the user wrote
        bc = [q(1.0 / craft.mass_kg, "1/mass_kg", "1/kg", (0, -1, 0), nonzero=True)]
        moments = np.linalg.eigvalsh(craft.inertia_tensor)
        for i, moment in enumerate(moments):
            q(moment, f"inertia_kgm2 principal moment {i}", "kg m^2", (2, 1, 0), nonzero=True)
        inv = np.linalg.inv(craft.inertia_tensor)
        for name, (i, j) in zip(("xx", "yy", "zz", "xy", "xz", "yz"), INERTIA_PAIRS, strict=True):
            bc.append(q(inv[i, j], f"inverse inertia {name}", "1/(kg m^2)", (-2, -1, 0)))
        bcs.append(bc)
        flap_names = M.is_flap(craft)
        plates = [p for p in craft.plates if p.name not in flap_names]
        flap_plates = [p for p in craft.plates if p.name in flap_names]
        offset = q.offset
        unit = q.unit

        tab = [len(plates), len(flap_plates), len(craft.cylinders), len(craft.buoyancy),
               len(craft.thrusters)]  # fmt: skip
        for p in plates:
            tab += offset(p) + unit(p, "normal")
            tab += [q(p.area_m2, f"{p.name}.area_m2", "m^2", AREA, nonzero=True)]
            tab += [q(p.efficiency, f"{p.name}.efficiency", "", NONE)]
        for p in flap_plates:
            tab += offset(p)
            tab += [q(p.area_m2, f"{p.name}.area_m2", "m^2", AREA, nonzero=True)]
            tab += [q(p.efficiency, f"{p.name}.efficiency", "", NONE)]
            tab += unit(p, "normal") + unit(p, "hinge_axis")
        for c in craft.cylinders:
            tab += offset(c) + unit(c, "axis")
            tab += [q(c.area_m2, f"{c.name}.area_m2", "m^2", AREA, nonzero=True)]
        for s in craft.buoyancy:
            tab += offset(s)
            tab += [q(s.volume_m3 or 0.0, f"{s.name}.volume_m3", "m^3", VOLUME, nonzero=True)]
            tab += [q(s.area_m2 or 0.0, f"{s.name}.area_m2", "m^2", AREA, nonzero=True)]
        for t in craft.thrusters:
            tab += offset(t) + unit(t, "direction")
            tab += [q(t.min_thrust_n, f"{t.name}.min_thrust_n", "N", FORCE, nonzero=True)]
            tab += [q(t.max_thrust_n, f"{t.name}.max_thrust_n", "N", FORCE, nonzero=True)]
            channel = t.control is not None and int(offsets[b]) + craft.control_names.index(
                t.control
            )
            tab += [-1 if t.control is None else channel]
        tabs.append(tab)
        drive = M.surface_mix(craft)
        rows = []
        for p in flap_plates:  # each surface's deflection per unit of every body's channels
            row = np.zeros(C)
            row[offsets[b] : offsets[b + 1]] = drive[p.name]
            for c, rad in enumerate(row):
                if abs(rad) > MAX_MIX_RAD:
                    raise ValueError(
                        f"Simulator: fixed point takes a control surface's deflection up to "
                        f"{MAX_MIX_RAD} rad per unit of a channel, got {rad:.6g} rad for craft "
                        f"{craft.name!r} surface {p.name!r} on channel {c}"
                    )
            rows += [math.floor(rad * 2.0**LW.ANGLE_BITS + 0.5) for rad in row]
        mixes.append(rows)
    width = max(len(t) for t in tabs)
    tab = np.zeros((len(crafts), width), dtype=np.int64)
    for b, t in enumerate(tabs):
        tab[b, : len(t)] = t
    mix = np.zeros((len(crafts), max(len(m) for m in mixes)), dtype=np.int64)
    for b, m in enumerate(mixes):
        mix[b, : len(m)] = m
    n_inp = max(3 * int(t[LW.T_NFLAP]) + int(t[LW.T_NTHR]) for t in tabs)
    wq = _Packer(fmt, units, "world")
    prm = np.zeros(LW.NPRM, dtype=np.int64)
    prm[LW.P_F], prm[LW.P_LIM] = f, fmt.lim
    prm[LW.P_G] = wq(world.gravity_mps2, "gravity_mps2", "m/s^2", ACCEL, nonzero=True)
    prm[LW.P_RHO_AIR] = wq(world.air_density_kgm3, "air_density_kgm3", "kg/m^3", DENSITY, True)
    # the water's numbers only where there is water (without, every sample's water fraction
    # is 0 and they are never used: a dart is not refused for the sea's density)
    if world.water:
        prm[LW.P_WATER] = 1 << f
        rho_w = world.water_density_kgm3
        prm[LW.P_RHO_WATER] = wq(rho_w, "water_density_kgm3", "kg/m^3", DENSITY, True)
        blend = 1.0 / world.surface_blend_m if world.surface_blend_m > 0 else math.inf
        sharp = math.isinf(blend)
        prm[LW.P_INV_BLEND] = (
            fmt.lim if sharp else wq(blend, "1/surface_blend_m", "1/m", (-1, 0, 0), True)
        )
    prm[LW.P_VMAX] = wq(world.max_fluid_speed_mps, "max_fluid_speed_mps", "m/s", SPEED,
                        True, True)  # fmt: skip
    prm[LW.P_FMAX] = wq(world.max_sample_force_n, "max_sample_force_n", "N", FORCE, True, True)
    for k in range(3):
        air, water = world.wind_mps[k], world.current_mps[k]
        prm[LW.P_AIR + k] = wq(air, f"wind_mps[{k}]", "m/s", SPEED)
        if world.water:
            du = wq(water - air, f"current_mps[{k}] - wind_mps[{k}]", "m/s", SPEED)
            prm[LW.P_DU + k] = du
    h = dt / units.time_s
    step_q = _Packer(Format(fmt.name, LW.STEP_BITS), Units(1.0, 1.0, 1.0), "the step")
    prm[LW.P_H] = step_q(h, "dt / units.time_s", "", nonzero=True)
    prm[LW.P_HH] = step_q(0.5 * h, "dt / units.time_s / 2", "", nonzero=True)
    prm[LW.P_PRESCALED] = 1 if prescaled else 0

    return FixedModel(prm=prm, bc=np.asarray(bcs, dtype=np.int64), tab=tab, mix=mix,
                      n_inp=max(n_inp, 1))  # fmt: skip
