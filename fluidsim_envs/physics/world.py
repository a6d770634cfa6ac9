"""The world a craft moves in: gravity, two fluids, the water surface, the stability clamps."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import checks as CK
from .contact import Ground
from .craft import Vec3
from .surface import SwellWave, coerce_swell, surface_heights, swell_table


@dataclass(frozen=True)
class World:
    """Gravity along -z; air above the water surface and, with ``water=True``, water below it.

    The surface is flat at z = 0 (calm water, the default) or, with ``swell``, the sum of a
    few linear deep-water waves (``physics/surface.py``): each environment's surface moves
    with its own clock (:meth:`Simulator.set_clock`), and every sample's water fraction and
    buoyancy depth are taken from the surface height under it. By default the swell moves
    the surface only; with ``wave_orbital_velocity`` the water under it moves too, each
    wave's linear deep-water orbital velocity at every sample, decaying with depth below the
    moving surface (``kernels._sea_rows``).

    Args:
        gravity_mps2: magnitude of gravity (>= 0), acting along -z.
        central_gravity_m3s2: GM (>= 0) of a point mass at the world origin pulling every
            body with ``-GM x / |x|^3`` besides the uniform gravity (0, the default: none): an
            orbit, the test problem of geometric integration, for the study's Kepler problem.
        air_density_kgm3: the air's density (> 0).
        water_density_kgm3: the water's density (> 0).
        water: whether there is water below z = 0 (otherwise air everywhere, no buoyancy).
        wind_mps: uniform air velocity (world frame).
        current_mps: uniform water velocity (world frame).
        swell: waves on the surface, at most 4: :class:`SwellWave` s, or tuples
            ``(amplitude_m, wavelength_m, direction_deg, phase_rad)`` or dicts with those keys
            (direction and phase optional), each of steepness ``2 pi a / wavelength <= 0.3``;
            needs ``water=True``. Empty (default): calm water, at no cost.
        surface_blend_m: thickness of the layer around the surface across which a sample's density,
            fluid velocity and volume buoyancy blend linearly from air to water; 0 gives a sharp
            surface. A blend keeps forces continuous when samples cross the surface.
        max_fluid_speed_mps: clamp on each sample's speed relative to the fluid (the seed's
            350 mph); keeps forces finite whatever the state.
        max_sample_force_n: clamp on each sample's force magnitude.
        ground: a solid :class:`~fluidsim_envs.physics.contact.Ground` (a plane or a height
            field) that bodies with collision shapes (``Craft.shapes``) touch; None (default):
            none. Bodies of one environment with shapes also touch each other.
        contact_passes: passes over an environment's contacts per step (>= 1). One is the
            seed's method; a resting stack settles its contacts over several steps then, and
            more passes settle them within the step (contact.py).
        tetra_rigid_spin_rad: with ``integrator="verlet_tetra"``, a body that turns more than
            this angle in one step (|w| dt, radians) turns as a rigid body for that step: the
            tetrahedron's straight particle paths misrepresent fast turns (its energy error
            passes the rigid turn's near 0.05-0.1: tests/physics/test_tetra_integrator.py,
            docs/tetra_spin.png); ``math.inf``: never.

        wave_orbital_velocity: whether the swell moves the water too (default False: the
            surface only, as before this option).

    Examples:
        >>> import numpy as np
        >>> world = World(water=True, swell=[(0.5, 40.0, 90.0)])  # 0.5 m, 40 m, toward +y
        >>> world.swell[0].period_s(world.gravity_mps2) > 5.0
        True
        >>> np.round(world.surface_height([0.0, 10.0], [0.0, 10.0], 0.0), 12)  # crest; node
        array([0.5, 0. ])
    """

    gravity_mps2: float = 9.81
    central_gravity_m3s2: float = 0.0
    air_density_kgm3: float = 1.225
    water_density_kgm3: float = 1025.0
    water: bool = False
    wind_mps: Vec3 = (0.0, 0.0, 0.0)
    current_mps: Vec3 = (0.0, 0.0, 0.0)
    surface_blend_m: float = 0.05
    max_fluid_speed_mps: float = 156.0
    max_sample_force_n: float = 1.0e7
    tetra_rigid_spin_rad: float = 0.05
    swell: tuple[SwellWave, ...] = ()
    ground: Ground | None = None
    contact_passes: int = 1
    wave_orbital_velocity: bool = False

    def __post_init__(self) -> None:
        for key, bound in (
            ("gravity_mps2", "ge"),
            ("central_gravity_m3s2", "ge"),
            ("air_density_kgm3", "gt"),
            ("water_density_kgm3", "gt"),
            ("surface_blend_m", "ge"),
            ("max_fluid_speed_mps", "gt"),
            ("max_sample_force_n", "gt"),
        ):  # stored as floats: a NumPy scalar checks alike but would reach numba as its type
            value = CK.number("World", key, getattr(self, key), **{bound: 0.0})
            object.__setattr__(self, key, value)
        spin = self.tetra_rigid_spin_rad  # inf allowed: never switch
        spin = CK.number("World", "tetra_rigid_spin_rad", spin, gt=0, finite=False)
        object.__setattr__(self, "tetra_rigid_spin_rad", spin)
        object.__setattr__(self, "water", CK.flag("World", "water", self.water))
        orbital = CK.flag("World", "wave_orbital_velocity", self.wave_orbital_velocity)
        object.__setattr__(self, "wave_orbital_velocity", orbital)
        for key in ("wind_mps", "current_mps"):
            object.__setattr__(self, key, CK.vector("World", key, getattr(self, key)))
        swell = coerce_swell(self.swell)
        if swell and not self.water:
            raise ValueError(
                f"World: swell needs water=True (got water={self.water!r} with swell {swell!r})"
            )
        object.__setattr__(self, "swell", swell)
        passes = CK.number("World", "contact_passes", self.contact_passes, ge=1, integer=True)
        object.__setattr__(self, "contact_passes", passes)
        if self.ground is not None and not isinstance(self.ground, Ground):
            raise ValueError(f"World: ground must be a Ground or None, got {CK.show(self.ground)}")

    def swell_table(self) -> np.ndarray:
        """The swell as the kernels read it: a new float64 array ``[n_waves, 5]`` of rows
        ``(amplitude, kx, ky, omega, phase)`` (``physics/surface.py``); ``[0, 5]`` in calm
        water."""
        return swell_table(self.swell, self.gravity_mps2)

    def surface_height(self, x, y, t) -> np.ndarray:
        """Height of the water surface above z = 0 (m) at horizontal points (x, y) and times t
        (s); the arguments broadcast, the result is a float64 array of their shape (zeros in
        calm water). The same formula the kernels use (``surface.surface_height``)."""
        xs, ys, ts = np.broadcast_arrays(*(np.asarray(v, dtype=np.float64) for v in (x, y, t)))
        out = np.zeros(xs.shape, dtype=np.float64)
        if self.swell:  # contiguous copies of the broadcast views (which may repeat values)
            flat = [np.ascontiguousarray(v).ravel() for v in (xs, ys, ts)]
            surface_heights(*flat, self.swell_table(), out.ravel())
        return out
