"""A spherical marker buoy, built from its radius and weight: the course marks of BoatOnStep-v0
when they are floating bodies (``buoy_bodies=True``).

``buoy.toml`` is generated from :class:`MarkerBuoy` by ``python -m fluidsim_envs.craft.buoy``
(a test checks that the shipped file matches). Body frame at the center of gravity, which
ballast puts ``ballast_drop_m`` below the sphere's center; x forward, y left, z up.

How the sphere becomes samples, so that it floats where Archimedes puts it:

- It floats with its bottom ``h`` under the surface, where the spherical cap of height h
  displaces its mass: ``rho pi h^2 (3 r - h) / 3 = m``. Four area-buoyancy samples share the
  waterplane area at that draft, ``A = pi (2 r h - h^2)``, at the depth ``d = m / (rho A)``
  under the waterline: together they hold the weight at exactly that draft, with the heave
  stiffness ``rho g A`` of the real waterplane. They sit on a circle of radius ``a / sqrt 2``
  (a the waterplane's radius), which gives the waterplane's second moment ``pi a^4 / 4``:
  its righting in roll and pitch for small angles.
- Drag across the water: a vertical cylinder sample at the immersed cap's middle, of area
  ``drag_cd`` times the cap's side profile (a circular segment). Heave and roll damping
  (what the waves a bobbing buoy makes carry away): four horizontal plates beside the
  buoyancy samples, sharing ``heave_damping_area_m2``.
- Mooring: not a sample. A scene holds the buoy near its anchor with a horizontal spring of
  stiffness ``m (2 pi / mooring_period_s)^2`` (``Simulator.set_external_force``): a slack
  chain's catenary pulls back about linearly for small drifts.
- Collision: one sphere of the buoy's radius at the sphere's center.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from ..physics import checks as CK
from .hull import to_toml

WATER_DENSITY_KGM3 = 1025.0  # World's default sea water: the draft is computed for it
RING = ((1, 0), (0, 1), (-1, 0), (0, -1))  # the samples' places on the waterplane circle


@dataclass(frozen=True)
class MarkerBuoy:
    """Dimensions of a ballasted spherical buoy (m, kg)."""

    name: str = "buoy"
    radius_m: float = 0.4
    mass_kg: float = 40.0  # foam sphere, ballast and chain shackle
    ballast_drop_m: float = 0.15  # center of gravity below the sphere's center
    gyradius_m: float = 0.3
    drag_cd: float = 0.5  # a sphere's drag coefficient, subcritical
    heave_damping_area_m2: float = 0.4  # about the waterplane: a flat bottom, Cd ~ 1
    mooring_period_s: float = 6.0  # sway period on its chain
    restitution: float = 0.3  # a foam-filled buoy against a hull
    friction: float = 0.3

    def __post_init__(self) -> None:
        CK.plain_fields(self)  # NumPy scalars as Python numbers, each then checked
        if not isinstance(self.name, str):
            raise ValueError(f"MarkerBuoy: name must be a string, got {CK.show(self.name)}")
        for key in ("radius_m", "mass_kg", "gyradius_m", "drag_cd", "mooring_period_s"):
            CK.number("MarkerBuoy", key, getattr(self, key), gt=0.0)
        for key in ("ballast_drop_m", "heave_damping_area_m2", "friction"):
            CK.number("MarkerBuoy", key, getattr(self, key), ge=0.0)
        CK.number("MarkerBuoy", "restitution", self.restitution, ge=0.0, le=1.0)
        if not 0.0 <= self.ballast_drop_m < self.radius_m:
            raise ValueError(
                f"MarkerBuoy: ballast_drop_m must lie in [0, radius_m), got {self.ballast_drop_m!r}"
            )
        full = WATER_DENSITY_KGM3 * 4.0 / 3.0 * math.pi * self.radius_m**3
        if self.mass_kg >= full:
            raise ValueError(
                f"MarkerBuoy: mass_kg {self.mass_kg} sinks a sphere of radius {self.radius_m} m "
                f"(it displaces at most {full:.1f} kg)"
            )

    @classmethod
    def scaled(cls, radius_m: float) -> MarkerBuoy:
        """The default buoy made geometrically similar at ``radius_m``: lengths scale with
        the radius, mass with its cube, areas with its square (so it floats as deep, in
        proportion, and sways on its chain with the same period)."""
        base = cls()
        k = radius_m / base.radius_m
        return cls(
            radius_m=radius_m,
            mass_kg=base.mass_kg * k**3,
            ballast_drop_m=base.ballast_drop_m * k,
            gyradius_m=base.gyradius_m * k,
            heave_damping_area_m2=base.heave_damping_area_m2 * k**2,
        )

    @property
    def draft_m(self) -> float:
        """Depth h of the sphere's bottom under the surface at rest: the cap of height h
        displaces the mass (solved by bisection; the cap's volume rises with h)."""
        r, target = self.radius_m, self.mass_kg / WATER_DENSITY_KGM3
        lo, hi = 0.0, 2.0 * r
        for _ in range(80):
            h = 0.5 * (lo + hi)
            lo, hi = (h, hi) if math.pi * h * h * (3.0 * r - h) / 3.0 < target else (lo, h)
        return 0.5 * (lo + hi)

    @property
    def waterline_m(self) -> float:
        """Height of the waterline above the center of gravity at rest (body frame z)."""
        return self.ballast_drop_m - self.radius_m + self.draft_m

    @property
    def mooring_stiffness_npm(self) -> float:
        return self.mass_kg * (2.0 * math.pi / self.mooring_period_s) ** 2

    def samples(self) -> dict:
        """The craft as the dict ``Craft.from_dict`` takes."""
        r, h, m = self.radius_m, self.draft_m, self.mass_kg

        def rnd(v: float) -> float:
            return round(v, 6)

        a2 = 2.0 * r * h - h * h  # the waterplane's radius squared
        area = math.pi * a2
        z_sample = self.waterline_m - m / (WATER_DENSITY_KGM3 * area)
        ring = math.sqrt(a2 / 2.0)
        # the immersed cap seen from the side: a circular segment of height h
        c = r - h
        segment = r * r * math.acos(c / r) - c * math.sqrt(a2)
        z_bottom = self.ballast_drop_m - r  # the sphere's lowest point
        k = m * self.gyradius_m**2
        return dict(
            name=self.name,
            description=(
                f"spherical marker buoy, {2 * r:g} m, {m:g} kg, draft {h:.3f} m in sea water"
            ),
            mass_kg=m,
            inertia_kgm2=[rnd(k), rnd(k), rnd(k)],
            restitution=self.restitution,
            friction=self.friction,
            plates=[
                dict(
                    name=f"damping_{j}",
                    offset_m=[rnd(x * ring), rnd(y * ring), rnd(z_sample)],
                    normal=[0.0, 0.0, 1.0],
                    area_m2=rnd(self.heave_damping_area_m2 / 4.0),
                    efficiency=0.0,
                )
                for j, (x, y) in enumerate(RING)
            ],
            cylinders=[
                dict(
                    name="drag",
                    offset_m=[0.0, 0.0, rnd(z_bottom + 0.5 * h)],
                    axis=[0.0, 0.0, 1.0],
                    area_m2=rnd(self.drag_cd * segment),
                )
            ],
            buoyancy=[
                dict(
                    name=f"waterplane_{j}",
                    offset_m=[rnd(x * ring), rnd(y * ring), rnd(z_sample)],
                    kind="area",
                    area_m2=rnd(area / 4.0),
                )
                for j, (x, y) in enumerate(RING)
            ],
            shapes=[
                dict(
                    name="sphere",
                    kind="sphere",
                    center_m=[0.0, 0.0, rnd(self.ballast_drop_m)],
                    radius_m=r,
                )
            ],
        )


HEADER = """\
GENERATED by `python -m fluidsim_envs.craft.buoy` from MarkerBuoy(): edit the dimensions there.
A 0.8 m spherical marker buoy, ballasted: four area-buoyancy samples share the waterplane at
its Archimedes draft, a drag cylinder over the immersed cap, heave-damping plates, and a
collision sphere. Moored by the scene (a horizontal spring to its anchor). Origin at the
center of gravity; x forward, y left, z up."""


def buoy_toml(buoy: MarkerBuoy | None = None) -> str:
    return to_toml((buoy or MarkerBuoy()).samples(), HEADER)


if __name__ == "__main__":
    out = Path(__file__).with_name("buoy.toml")
    out.write_text(buoy_toml())
    print(f"wrote {out}")
