"""The speedboat's hull, built from its lines: a V-bottom planing runabout cut into stations.

``speedboat.toml`` is generated from :class:`VHull` by ``python -m fluidsim_envs.craft.hull``
(and ``speedboat_ittc.toml`` from ``HULLS``; a test checks that the shipped files match), so
that their samples (91 and 75) follow from a few
dimensions a naval architect would give: length, chine beam, deadrise, center of gravity.

How the hull becomes samples (body frame at the center of gravity, x forward, y left, z up):

- Bottom: ``stations`` slices from the transom to the bow; each slice's V bottom is cut into
  ``strips`` flat plates per side, at the deadrise angle, normal pointing out of the hull.
  Each plate carries ``F = -1/2 rho A |v| (v . n) n`` (``efficiency = 0``: a plate's force is
  normal to it, so the pressure drag is lift x tan(trim), as in a real planing bottom). The
  plates in water lift the hull; as it rises fewer of them are wet, which is all the planing
  model there is: no planing formula. Two corrections of the bare flat plate, both from
  planing-surface data. A plate's lift per unit area is sin(alpha) cos^2(beta), 2.3 times
  what a planing bottom develops at 3 degrees of trim, lambda 1.4 and 18 degrees of
  deadrise (Savitsky 1964: C_L0 = tau^1.1 (0.012 lambda^0.5 + ...) per b^2, tau in degrees,
  less his deadrise correction), so the plates' area is ``lift_factor`` of the geometric
  area. And the pressure falls to zero at the transom where
  the flow leaves the hull (the Kutta condition), so within ``transom_taper_m`` of it the
  area falls off as the square root of the distance, as thin-wing pressure does near a
  trailing edge. With both, the steady trim and resistance sit within 1.1 degrees and 2.1%
  of Savitsky's method from 12 m/s (Fn_V 3.8) up to where the method holds, 16.5 m/s
  (tests/craft/test_speedboat.py).
- Buoyancy: an area sample at each bottom plate's centre with the plate's plan area. Its
  force ``rho g A depth`` is the weight of the water column between the bottom and the
  surface, so the samples together displace the hull's immersed volume (vertical sides above
  the chine).
- Skin friction. ``speedboat`` (``friction = "plates"``, the default, BoatOnStep-v0's):
  under each strip one plate facing forward of area ``friction_cf * wetted area``, friction
  against forward motion only, at one ``C_f``. ``speedboat_ittc`` (``friction = "ittc1957"``,
  issue 20): each bottom plate's own shear along
  its plane on its geometric wetted area, ``C_f`` from the ITTC-1957 line at
  ``Re = |v| friction_length_m / nu`` plus Savitsky's roughness allowance 0.0004, so a wet
  plate feels ``1/2 rho C_f S |v_t| v_t`` against its sliding in any direction (a
  sideslipping hull too), a dry one the air's. Beside Savitsky's method at common
  speeds (``python -m benchmarks.study_savitsky``, docs/study_savitsky_grid.csv) the trim is
  the same (rms error 0.786 against 0.785 deg planing) and the resistance closer (R/W rms
  error 2.5% against 3.3% planing, largest 6.5% against 7.5%), at a cost: a dearer body-step
  (docs/study_savitsky.md's cost table, from docs/bench_boat.csv).
- The bottom stays two-sided (``one_sided_bottom = False``). One-sided plates (issue 20: a
  plate that moves away from its normal side gives nothing) change no steady run: every wet
  bottom plate meets the water there (the study's one-sided hulls match to 1e-4 deg). In
  motion they take away the bottom's damping on the rising side: hard over at 15 m/s the
  one-sided hull's heel swings between -9 and +18 degrees (seconds 4-8 of the turn,
  docs/study_savitsky_turn.csv) where the two-sided hulls hold 6-9, and heave and pitch die
  more slowly. So the option is there, measured, and off.
- Topsides (side plates), a skeg, the stem (the bow above the chines, which ploughs when
  buried), the rudder and trim tabs (control surfaces), a windscreen (air drag), and the
  propeller below the transom, its thrust line below the CG as on an outboard.
- Collision (for buoys and other bodies, not the water): a box over the prismatic run and
  one over the bow, up to the sheer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from pathlib import Path

from ..physics import checks as CK


@dataclass(frozen=True)
class VHull:
    """Main dimensions of a V-bottom runabout. Lengths in m, from the transom or the keel."""

    name: str = "speedboat"
    length_m: float = 5.0  # transom to stem along the keel
    chine_beam_m: float = 1.8  # beam at the chines, constant over the run
    deadrise_deg: float = 18.0  # at the transom and over the run (prismatic aft body)
    run_m: float = 3.0  # prismatic from the transom to here, then the bow
    bow_beam_m: float = 0.5  # chine beam at the stem
    bow_rise_m: float = 0.8  # keel rises by this much from the end of the run to the stem
    bow_deadrise_deg: float = 35.0  # deadrise at the stem
    freeboard_m: float = 0.85  # sheer above the keel
    mass_kg: float = 1000.0  # boat, engine, fuel and two people
    lcg_m: float = 1.6  # center of gravity ahead of the transom
    vcg_m: float = 0.45  # center of gravity above the keel
    gyradius_m: tuple = (0.62, 1.25, 1.30)  # roll, pitch, yaw radii of gyration
    stations: int = 8
    strips: int = 2  # bottom plates per side per station
    lift_factor: float = 0.4  # bottom plates' hydrodynamic area over their geometric area
    transom_taper_m: float = 1.5  # lift falls as sqrt(distance) to 0 at the transom (Kutta)
    friction_cf: float = 0.0029  # ITTC-1957 at Re ~ 3e7 (0.0025) + roughness 0.0004
    # the bottom's skin friction and sidedness (issue 20): "plates" (forward-facing friction
    # plates of area friction_cf x wetted area, the first hull) or "ittc1957" (the bottom
    # plates' own skin friction on their geometric area, C_f from the ITTC-1957 line at
    # Re = |v| friction_length_m / nu, plus roughness_cf)
    friction: str = "plates"
    friction_length_m: float = 3.0  # ~ the mean wetted length lambda b planing (lambda ~ 1.7)
    roughness_cf: float = 0.0004  # the roughness allowance Savitsky (1964) adds
    one_sided_bottom: bool = False  # True: bottom plates push only when the water meets them
    # past any speed or turn it makes on or in the water, each with room to spare (the fuzz's
    # fastest, at full power in a steep sea: 22 m/s and 422 deg/s): a runaway
    runaway_speed_mps: float = 60.0
    runaway_rate_dps: float = 2000.0
    max_thrust_n: float = 4500.0  # ~150 hp outboard, static
    min_thrust_n: float = -1500.0  # astern
    rudder_area_m2: float = 0.2
    max_rudder_deg: float = 35.0
    tab_area_m2: float = 0.035  # per tab; two tabs
    max_tab_deg: float = 15.0  # trailing edge down from flush
    skeg_area_m2: float = 0.06

    def __post_init__(self) -> None:
        """Types and signs, each named: a bad dimension would otherwise fail deep in the
        geometry (a float station count in range(), a string in a product)."""
        CK.plain_fields(self)
        if not isinstance(self.name, str):
            raise ValueError(f"VHull: name must be a string, got {CK.show(self.name)}")
        if self.friction not in ("plates", "ittc1957"):
            raise ValueError(
                f"VHull: friction must be 'plates' or 'ittc1957', got {CK.show(self.friction)}"
            )
        if not isinstance(self.one_sided_bottom, bool):
            raise ValueError(
                f"VHull: one_sided_bottom must be True or False, got "
                f"{CK.show(self.one_sided_bottom)}"
            )
        signs = {
            "min_thrust_n": {"le": 0.0},
            "transom_taper_m": {"ge": 0.0},
            "roughness_cf": {"ge": 0.0},
        }
        for f in fields(self):
            if f.name in ("name", "gyradius_m", "friction", "one_sided_bottom"):
                continue
            if f.name in ("stations", "strips"):
                CK.number("VHull", f.name, getattr(self, f.name), ge=1, integer=True)
            elif f.name in ("deadrise_deg", "bow_deadrise_deg"):
                CK.number("VHull", f.name, getattr(self, f.name), gt=0.0, lt=90.0)
            else:
                CK.number("VHull", f.name, getattr(self, f.name), **signs.get(f.name, {"gt": 0.0}))
        radii = CK.vector("VHull", "gyradius_m", self.gyradius_m)
        for i, r in enumerate(radii):
            CK.number("VHull", f"gyradius_m[{i}]", r, gt=0.0)
        if self.run_m >= self.length_m:
            raise ValueError(
                f"VHull: run_m ({self.run_m!r}) must be shorter than length_m ({self.length_m!r})"
            )

    def station(self, s: float) -> tuple[float, float, float]:
        """Chine half-beam, keel height above the transom keel, deadrise (rad) at distance s
        ahead of the transom."""
        t = max(0.0, (s - self.run_m) / (self.length_m - self.run_m))
        half = 0.5 * (self.chine_beam_m + t * t * (self.bow_beam_m - self.chine_beam_m))
        rise = self.bow_rise_m * t * t
        beta = math.radians(self.deadrise_deg + t * (self.bow_deadrise_deg - self.deadrise_deg))
        return half, rise, beta

    def samples(self) -> dict:
        """The craft as the dict ``Craft.from_dict`` takes."""
        x0, z0 = -self.lcg_m, -self.vcg_m  # transom and keel in the body frame
        ds = self.length_m / self.stations
        plates, buoyancy = [], []

        def r(v: float) -> float:
            return round(v, 5)

        for k in range(self.stations):
            s = (k + 0.5) * ds
            half, rise, beta = self.station(s)
            # the keel's slope here tilts the bottom normal forward near the bow
            slope = (self.station(s + 1e-4)[1] - self.station(s - 1e-4)[1]) / 2e-4
            width = half / self.strips  # plan width of one strip
            for j in range(self.strips):
                y = (j + 0.5) * width
                z = z0 + rise + y * math.tan(beta)
                area = ds * width / math.cos(beta)
                taper = 1.0
                if self.transom_taper_m > 0.0:
                    taper = min(1.0, math.sqrt(s / self.transom_taper_m))
                for side, sy in (("port", 1.0), ("starboard", -1.0)):
                    n = (slope, sy * math.sin(beta), -math.cos(beta))
                    norm = math.sqrt(sum(c * c for c in n))
                    name = f"bottom_{k}_{side}_{j}"
                    plate = dict(
                        name=name,
                        offset_m=[r(x0 + s), r(sy * y), r(z)],
                        normal=[r(c / norm) for c in n],
                        area_m2=r(self.lift_factor * taper * area),
                        efficiency=0.0,
                    )
                    if self.one_sided_bottom:
                        plate["one_sided"] = True
                    if self.friction == "ittc1957":
                        plate.update(
                            friction_coefficient=self.roughness_cf,
                            friction_line="ittc1957",
                            friction_length_m=self.friction_length_m,
                            friction_area_m2=r(area),
                        )
                    plates.append(plate)
                    buoyancy.append(
                        dict(
                            name=f"volume_{k}_{side}_{j}",
                            offset_m=[r(x0 + s), r(sy * y), r(z)],
                            kind="area",
                            area_m2=r(ds * width),
                        )
                    )
                if self.friction != "plates":
                    continue
                plates.append(
                    dict(
                        name=f"friction_{k}_{j}",
                        offset_m=[r(x0 + s), 0.0, r(z)],
                        normal=[1.0, 0.0, 0.0],
                        area_m2=r(self.friction_cf * 2 * area),
                        efficiency=0.0,
                    )
                )

        # topsides, fore and aft, each side: lateral plane when heeled or sliding
        chine = z0 + 0.5 * self.chine_beam_m * math.tan(math.radians(self.deadrise_deg))
        side_h = self.freeboard_m - (chine - z0)
        for name, frac, length in (("aft", 0.25, 0.5), ("fore", 0.7, 0.4)):
            half = self.station(frac * self.length_m)[0]
            for side, sy in (("port", 1.0), ("starboard", -1.0)):
                plates.append(
                    dict(
                        name=f"topside_{name}_{side}",
                        offset_m=[
                            r(x0 + frac * self.length_m),
                            r(sy * half),
                            r(chine + 0.5 * side_h),
                        ],
                        normal=[0.0, sy, 0.0],
                        area_m2=r(length * self.length_m * side_h),
                        efficiency=0.0,
                    )
                )
        plates += [
            dict(
                name="skeg",
                offset_m=[r(x0 + 0.4), 0.0, r(z0 - 0.08)],
                normal=[0.0, 1.0, 0.0],
                area_m2=self.skeg_area_m2,
                efficiency=0.8,
            ),
            dict(
                name="windscreen",
                offset_m=[r(x0 + 0.55 * self.length_m), 0.0, r(z0 + self.freeboard_m + 0.3)],
                normal=[1.0, 0.0, 0.0],
                area_m2=0.9,  # frontal area ~1.8 m^2, Cd ~0.5
                efficiency=0.0,
            ),
            # the bow above the chines: dry unless the bow buries, then it ploughs (the
            # scene calls it stuffing when this point goes under)
            dict(
                name="stem",
                offset_m=[r(x0 + self.length_m - 0.1), 0.0, r(z0 + self.freeboard_m)],
                normal=[1.0, 0.0, 0.0],
                area_m2=0.25,  # ~0.5 m^2 of bow, Cd ~0.5
                efficiency=0.0,
            ),
            dict(
                name="rudder",
                offset_m=[r(x0 - 0.35), 0.0, r(z0 - 0.25)],
                normal=[0.0, 1.0, 0.0],
                area_m2=self.rudder_area_m2,
                efficiency=0.85,
                hinge_axis=[0.0, 0.0, 1.0],
            ),
        ]
        # trim tabs: the base normal is the tab at half deflection, so that the channel's
        # [-1, 1] spans flush (0 deg) to fully down (max_tab_deg)
        mid = math.radians(0.5 * self.max_tab_deg)
        for side, sy in (("port", 1.0), ("starboard", -1.0)):
            y = 0.3 * self.chine_beam_m
            z = z0 + y * math.tan(math.radians(self.deadrise_deg))
            plates.append(
                dict(
                    name=f"tab_{side}",
                    offset_m=[r(x0 - 0.1), r(sy * y), r(z - 0.01)],
                    normal=[r(math.sin(mid)), 0.0, r(-math.cos(mid))],
                    area_m2=self.tab_area_m2,
                    efficiency=0.0,
                    hinge_axis=[0.0, -1.0, 0.0],
                )
            )

        # collision: a box over the prismatic run, and one over the bow at its mid-length
        # beam and keel height (up to the sheer): what a buoy or another hull meets
        top = z0 + self.freeboard_m
        bow_len = self.length_m - self.run_m
        bow_half, bow_rise, _ = self.station(self.run_m + 0.5 * bow_len)
        shapes = [
            dict(
                name="hull_run",
                kind="box",
                center_m=[r(x0 + 0.5 * self.run_m), 0.0, r(0.5 * (z0 + top))],
                half_extents_m=[r(0.5 * self.run_m), r(0.5 * self.chine_beam_m),
                                r(0.5 * self.freeboard_m)],
            ),
            dict(
                name="hull_bow",
                kind="box",
                center_m=[r(x0 + self.run_m + 0.5 * bow_len), 0.0,
                          r(0.5 * (z0 + bow_rise + top))],
                half_extents_m=[r(0.5 * bow_len), r(bow_half),
                                r(0.5 * (self.freeboard_m - bow_rise))],
            ),
        ]  # fmt: skip

        m, (kx, ky, kz) = self.mass_kg, self.gyradius_m
        # named sets of samples (Simulator.set_sample_scale): the planing bottom, its displaced
        # volume, the skin friction, the topsides
        groups = {
            "bottom": [p["name"] for p in plates if p["name"].startswith("bottom")],
            **(
                {"friction": [p["name"] for p in plates if p["name"].startswith("friction")]}
                if self.friction == "plates"
                else {}
            ),
            "hull_volume": [b["name"] for b in buoyancy],
            "topsides": [p["name"] for p in plates if p["name"].startswith("topside")],
        }
        return dict(
            name=self.name,
            description=(
                f"V-bottom planing runabout, {self.length_m} m, {self.chine_beam_m} m chine "
                f"beam, {self.deadrise_deg} deg deadrise, {self.mass_kg / 1000:g} t"
            ),
            mass_kg=m,
            inertia_kgm2=[r(m * kx * kx), r(m * ky * ky), r(m * kz * kz)],
            runaway_speed_mps=self.runaway_speed_mps,
            runaway_rate_dps=self.runaway_rate_dps,
            groups=groups,
            plates=plates,
            buoyancy=buoyancy,
            shapes=shapes,
            thrusters=[
                dict(
                    name="propeller",
                    offset_m=[r(x0 - 0.3), 0.0, r(z0 - 0.3)],
                    direction=[1.0, 0.0, 0.0],
                    max_thrust_n=self.max_thrust_n,
                    min_thrust_n=self.min_thrust_n,
                    control="throttle",
                )
            ],
            controls=[
                dict(name="throttle"),
                # +1: trailing edge to starboard, bow turns to starboard (right)
                dict(
                    name="rudder",
                    max_deflection_deg=self.max_rudder_deg,
                    surfaces=[dict(sample="rudder", gain=1.0)],
                ),
                # -1: tabs flush, +1: fully down (bow down)
                dict(
                    name="trim_tabs",
                    max_deflection_deg=0.5 * self.max_tab_deg,
                    surfaces=[dict(sample="tab_port"), dict(sample="tab_starboard")],
                ),
            ],
        )


def _toml_value(v) -> str:
    if isinstance(v, str):
        return '"' + v.replace('"', '\\"') + '"'
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + " }"
    return repr(float(v)) if isinstance(v, float) else str(v)


def to_toml(data: dict, header: str) -> str:
    """The craft dict as a TOML file (tables of arrays for the parts)."""
    lines = [f"# {line}".rstrip() for line in header.strip().splitlines()]
    for key, v in data.items():
        if not isinstance(v, list) or not v or not isinstance(v[0], dict):
            lines.append(f"{key} = {_toml_value(v)}")
    for key, v in data.items():
        if isinstance(v, list) and v and isinstance(v[0], dict):
            for item in v:
                lines += ["", f"[[{key}]]"]
                lines += [f"{k} = {_toml_value(x)}" for k, x in item.items()]
    return "\n".join(lines) + "\n"


HEADER = """\
GENERATED by `python -m fluidsim_envs.craft.hull` from VHull(): edit the dimensions there.
A 5 m V-bottom planing runabout (about 1 t with engine, fuel and two people): bottom plates
at the deadrise angle along 8 stations (the planing lift), area-buoyancy samples under them
(the displaced volume), skin-friction plates, topsides, skeg, rudder, trim tabs and an
outboard propeller; two collision boxes (run and bow). Origin at the center of gravity;
x forward, y left, z up."""
HEADER_ITTC = """\
GENERATED by `python -m fluidsim_envs.craft.hull` from VHull(name="speedboat_ittc",
friction="ittc1957"): edit the dimensions there. The speedboat's hull with its bottom plates'
own skin friction on the ITTC-1957 line instead of forward-facing friction plates (closer to
Savitsky's resistance, friction in any direction, a dearer body-step: docs/study_savitsky.md).
A 5 m V-bottom planing runabout (about 1 t with engine, fuel and two people): bottom plates
at the deadrise angle along 8 stations (the planing lift and its skin friction), area-buoyancy
samples under them (the displaced volume), topsides, skeg, rudder, trim tabs and an outboard
propeller; two collision boxes (run and bow). Origin at the center of gravity; x forward,
y left, z up."""
# the shipped hulls: the first (BoatOnStep-v0's) and the one with ITTC-1957 skin friction
HULLS = {
    "speedboat": VHull(),
    "speedboat_ittc": VHull(name="speedboat_ittc", friction="ittc1957"),
}


def speedboat_toml(hull: VHull | None = None) -> str:
    hull = hull or VHull()
    return to_toml(hull.samples(), HEADER_ITTC if hull.friction == "ittc1957" else HEADER)


if __name__ == "__main__":
    for name, hull in HULLS.items():
        out = Path(__file__).with_name(f"{name}.toml")
        out.write_text(speedboat_toml(hull))
        print(f"wrote {out}")
