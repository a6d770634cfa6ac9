"""The speedboat at rest in swell whose water moves (World(wave_orbital_velocity=True)): in
a long, low swell it heaves with the surface (the response at the wave's frequency over the
surface's, 1.007 measured for 120 m waves; tolerance 2%), and in waves about half its
length it heaves far less (0.38 measured at 2.6 m: the waves' pushes along the hull mostly
cancel; a rectangular waterplane of its length would cancel them entirely there). Its hull
is sampled every 0.625 m: waves shorter than 1.25 m alias onto longer ones (0.5 m waves
heave it by 0.2, 0.7 m ones excite its 0.75 s heave resonance), which no test here
claims."""

import math

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Simulator, World
from fluidsim_envs.physics.hydrostatics import static_float


def heave_ratio(wavelength_m, amplitude_m, dt=0.01):
    craft = Craft.load("speedboat")
    world = World(water=True, swell=[(amplitude_m, wavelength_m, 0.0)],
                  wave_orbital_velocity=True)  # fmt: skip
    height, trim = static_float(craft, world.water_density_kgm3, world.gravity_mps2)
    sim = Simulator(craft, world, num_envs=1, dt=dt, integrator="rk2")
    sim.reset(pos=(0.0, 0.0, height + amplitude_m), quat=(math.cos(trim / 2), 0.0,
              -math.sin(trim / 2), 0.0))  # fmt: skip
    omega = math.sqrt(world.gravity_mps2 * 2 * math.pi / wavelength_m)
    period = 2 * math.pi / omega
    steps = int(round(max(8 * period, 40.0) / period) * period / dt)
    z, eta = np.zeros(steps), np.zeros(steps)
    for k in range(steps):
        sim.step(None, steps=1)
        x, y, z[k] = sim.pos[0, 0]
        eta[k] = world.surface_height(x, y, (k + 1) * dt)
    t = dt * np.arange(1, steps + 1)[steps // 2 :]

    def amplitude(v):  # at the wave's frequency, over the second half (past the start)
        v = v[steps // 2 :] - v[steps // 2 :].mean()
        return 2 * math.hypot(np.mean(v * np.cos(omega * t)), np.mean(v * np.sin(omega * t)))

    return amplitude(z) / amplitude(eta)


def test_in_a_long_low_swell_the_hull_rides_the_surface():
    assert heave_ratio(120.0, 0.1) == pytest.approx(1.0, abs=0.02)


def test_in_waves_half_its_length_it_heaves_far_less():
    assert heave_ratio(2.6, 0.05) < 0.5
