"""One-sided plates and skin friction (issue 20), against their closed forms.

- The seed's rule, "don't process fluid interaction if the surface points away from the
  velocity": a one-sided plate gives exactly nothing while it moves away from its normal side
  (v . n <= 0, v relative to the fluid) and exactly the two-sided plate's force while it
  moves toward it.
- Skin friction along the plate's plane (the seed's surface drag, the velocity projected on
  the sample's plane): ``F = -1/2 rho C_f A |v_t| v_t``; in a pure tangential flow that is
  ``1/2 rho C_f A v^2`` against the motion.
- The ITTC-1957 model-ship correlation line, ``C_f = 0.075 / (log10 Re - 2)^2`` (ITTC, 8th
  International Towing Tank Conference, Madrid 1957; ITTC Recommended Procedure
  7.5-02-02-02): at Re = 1e7 it is 0.075 / 25 = 0.003 exactly.

The kernel's forces are read with ``Simulator.sample_forces``: the same loops as a step.
Tolerances: the measured error times 1.5 (``forces.ittc1957`` over Re 1e5-1e10: at most
1.6e-15 relative in float64 and 2.9e-7 in float32; ``forces.log_branch_free``: 2.0e-15).
"""

import math

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Plate, Simulator, World
from fluidsim_envs.physics.forces import (
    INV_NU_WATER_HI,
    INV_NU_WATER_LO,
    NU_WATER_M2S,
    RE_MIN,
    friction_force,
    ittc1957,
    log_branch_free,
    plate_force,
)

RHO, AREA, VMAX, FMAX = 1025.0, 0.5, 1e3, 1e12
F32 = np.float32
INV_NU = 1.0 / NU_WATER_M2S  # seawater at 15 deg C (forces.py names its source)


@pytest.mark.parametrize("eff", [0.0, 0.6])
def test_one_sided_plate_acts_only_toward_its_normal_side(eff):
    rng = np.random.default_rng(3)
    n = np.array([0.0, 0.36, -0.933])
    n /= np.linalg.norm(n)
    for v in rng.normal(0.0, 5.0, (200, 3)):
        two = np.array(plate_force(*v, *n, RHO, AREA, eff, VMAX, FMAX))
        one = np.array(plate_force(*v, *n, RHO, AREA, eff, VMAX, FMAX, 1.0))
        if v @ n > 0.0:  # pressed on its wet face: the two-sided force, bit for bit
            assert np.array_equal(one, two)
            assert two @ n < 0.0  # pushed back, along -n
        else:
            assert np.all(one == 0.0)
    # the default (and 0) is the two-sided plate, bit for bit
    v = (1.0, -2.0, 3.0)
    assert plate_force(*v, *n, RHO, AREA, eff, VMAX, FMAX) == plate_force(
        *v, *n, RHO, AREA, eff, VMAX, FMAX, 0.0
    )


def test_friction_in_tangential_flow_is_half_rho_cf_a_v_squared():
    n = (0.0, 0.0, -1.0)
    for v in ((7.0, 0.0, 0.0), (3.0, -4.0, 0.0), (-12.5, 0.0, 0.0)):
        f = np.array(friction_force(*v, *n, RHO, INV_NU, AREA, 0.003, 0.0, 0.0, VMAX, FMAX))
        speed = np.linalg.norm(v)
        want = -0.5 * RHO * 0.003 * AREA * speed * np.asarray(v)
        np.testing.assert_allclose(f, want, rtol=1e-15, atol=0.0)
    # oblique: only the tangential part, nothing along the normal
    v = np.array([6.0, 0.0, -8.0])
    f = np.array(friction_force(*v, *n, RHO, INV_NU, AREA, 0.003, 0.0, 0.0, VMAX, FMAX))
    assert f[2] == 0.0
    np.testing.assert_allclose(f, (-0.5 * RHO * 0.003 * AREA * 36.0, 0.0, 0.0), rtol=1e-15)
    # normal flow and rest: none
    assert friction_force(0.0, 0.0, 5.0, *n, RHO, 1e6, AREA, 0.003, 1.0, 2.0, VMAX, FMAX) == (
        0.0,
        0.0,
        0.0,
    )


@pytest.mark.parametrize("re", [1e5, 1e6, 1e7, 3.3e7, 1e8, 1e9])
def test_ittc1957_line(re):
    want = 0.075 / (math.log10(re) - 2.0) ** 2
    assert ittc1957(re) == pytest.approx(want, rel=2.4e-15)
    want32 = 0.075 / (math.log10(float(F32(re))) - 2.0) ** 2  # at the float32 Re
    assert ittc1957(F32(re)) == pytest.approx(want32, rel=4.4e-7)
    assert log_branch_free(re) == pytest.approx(math.log(re), rel=3e-15)
    if re == 1e7:
        assert ittc1957(re) == pytest.approx(0.003, rel=2.4e-15)  # 0.075 / (7 - 2)^2


def test_the_kernels_inverse_viscosity_pair_is_the_waters():
    assert float(INV_NU_WATER_HI) + float(INV_NU_WATER_LO) == pytest.approx(INV_NU, rel=1e-15)


def test_ittc1957_below_its_range_is_held_at_re_min():
    assert ittc1957(10.0) == ittc1957(0.0) == ittc1957(float(RE_MIN))
    assert ittc1957(float(RE_MIN)) == pytest.approx(0.075 / 9.0, rel=2.4e-15)


def _sim(plate, pos, lin_vel, dtype=np.float64):
    craft = Craft(name="p", mass_kg=1.0, inertia_kgm2=(1, 1, 1), plates=(plate,))
    sim = Simulator(craft, World(water=True, gravity_mps2=0.0), num_envs=1, dtype=dtype)
    sim.reset(pos=pos, lin_vel=lin_vel)
    return sim.sample_forces()[1][0]


def test_kernel_one_sided_bottom_plate():
    bottom = Plate("b", (0.0, 0.0, 0.0), (0.0, 0.0, -1.0), AREA, one_sided=True)
    both = Plate("b", (0.0, 0.0, 0.0), (0.0, 0.0, -1.0), AREA)
    deep = (0.0, 0.0, -3.0)
    sinking = (2.0, 0.0, -1.0)
    np.testing.assert_array_equal(_sim(bottom, deep, sinking), _sim(both, deep, sinking))
    assert _sim(bottom, deep, sinking)[2] == pytest.approx(0.5 * RHO * AREA * math.sqrt(5.0))
    rising = (2.0, 0.0, 1.0)  # the -512 N per m^2 of suction a two-sided bottom gives at 1 m/s
    assert _sim(both, deep, (0.0, 0.0, 1.0))[2] == pytest.approx(-0.5 * RHO * AREA)
    assert np.all(_sim(bottom, deep, rising) == 0.0)


# measured: 1.1e-15 (float64) and 3.8e-8 (float32) relative; tolerances 1.5 times that
@pytest.mark.parametrize("dtype, rtol", [(np.float64, 1.7e-15), (np.float32, 5.8e-8)])
def test_kernel_skin_friction_constant_and_ittc(dtype, rtol):
    deep, v = (0.0, 0.0, -3.0), (9.0, 0.0, 0.0)
    flat = dict(name="b", offset_m=(0.0, 0.0, 0.0), normal=(0.0, 0.0, -1.0), area_m2=AREA)
    f = _sim(Plate(**flat, friction_coefficient=0.004), deep, v, dtype)
    np.testing.assert_allclose(f, (-0.5 * RHO * 0.004 * AREA * 81.0, 0, 0), rtol=rtol, atol=0)
    # the ITTC line on its own wetted area, at Re = 9 m/s x 1.3 m / nu_water, plus 0.0004
    plate = Plate(
        **flat,
        friction_coefficient=0.0004,
        friction_line="ittc1957",
        friction_length_m=1.3,
        friction_area_m2=2.0,
        one_sided=True,
    )
    re = 9.0 * 1.3 * INV_NU
    cf = 0.075 / (math.log10(re) - 2.0) ** 2 + 0.0004
    f = _sim(plate, deep, v, dtype)
    np.testing.assert_allclose(f, (-0.5 * RHO * cf * 2.0 * 81.0, 0, 0), rtol=rtol, atol=0)
    # one-sided: a rising bottom has no pressure but keeps its skin friction (Re on |v|)
    re = math.sqrt(82.0) * 1.3 * INV_NU
    cf = 0.075 / (math.log10(re) - 2.0) ** 2 + 0.0004
    f = _sim(plate, deep, (9.0, 0.0, 1.0), dtype)
    np.testing.assert_allclose(f, (-0.5 * RHO * cf * 2.0 * 81.0, 0, 0), rtol=rtol, atol=0)
