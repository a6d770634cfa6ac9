"""Orbital velocity of the swell (World(wave_orbital_velocity=True), kernels._sea_rows)
against linear deep-water theory (Airy; e.g. Dean and Dalrymple, "Water wave mechanics for
engineers and scientists", 1991, ch. 4): under eta = a cos(theta) the water moves at
a omega e^(k z) (cos theta along the wave, sin theta up), a omega on the surface. Read from
the forces on two probe plates at rest (normals x and z, no drag removed):
F = 1/2 rho A u |u| along each normal. Tolerance: rounding (measured 1e-12 relative)."""

import math

import pytest

from fluidsim_envs.physics import Craft, Plate, Simulator, World

A_M, WAVELENGTH_M, RHO, AREA = 0.3, 25.0, 1000.0, 0.01


def probe_sim(orbital=True, phase=0.4):
    craft = Craft(
        name="probe",
        mass_kg=1.0,
        inertia_kgm2=(1.0, 1.0, 1.0),
        plates=(
            Plate("px", (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), AREA, efficiency=0.0),
            Plate("pz", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), AREA, efficiency=0.0),
        ),
    )
    swell = [(A_M, WAVELENGTH_M, 0.0, phase)]
    world = World(water=True, water_density_kgm3=RHO, surface_blend_m=0.0, swell=swell,
                  wave_orbital_velocity=orbital)  # fmt: skip
    return Simulator(craft, world, num_envs=1), world


def water_velocity(sim):
    _, forces, _ = sim.sample_forces()
    fx, fz = forces[0, 0], forces[1, 2]
    speed = math.sqrt(math.hypot(fx, fz) / (0.5 * RHO * AREA))
    return fx / (0.5 * RHO * AREA * speed), fz / (0.5 * RHO * AREA * speed)


@pytest.mark.parametrize("depth_m", [1e-6, 0.5, 2.0, 6.0])  # 1e-6: in the water, at the top
@pytest.mark.parametrize("t", [0.0, 0.7, 1.9, 3.1])
def test_orbital_velocity_is_airys(depth_m, t):
    sim, world = probe_sim()
    k = 2 * math.pi / WAVELENGTH_M
    omega = math.sqrt(world.gravity_mps2 * k)
    eta = float(world.surface_height(0.0, 0.0, t))
    sim.set_clock(t)
    sim.reset(pos=(0.0, 0.0, eta - depth_m))  # depth_m below the moving surface
    theta = 0.4 - omega * t
    speed = A_M * omega * math.exp(-k * depth_m)
    ux, uz = water_velocity(sim)
    assert ux == pytest.approx(speed * math.cos(theta), rel=1e-9, abs=1e-12)
    assert uz == pytest.approx(speed * math.sin(theta), rel=1e-9, abs=1e-12)
    if depth_m < 1e-3:  # at the surface: a omega, the surface's own speed
        assert math.hypot(ux, uz) == pytest.approx(A_M * omega, rel=1e-6)


def test_without_the_option_the_water_stays_still():
    sim, world = probe_sim(orbital=False)
    sim.set_clock(0.7)
    sim.reset(pos=(0.0, 0.0, -1.0))
    _, forces, _ = sim.sample_forces()
    assert not forces.any()


def test_the_option_needs_a_flag():
    with pytest.raises(ValueError, match="wave_orbital_velocity"):
        World(water=True, wave_orbital_velocity="yes")
