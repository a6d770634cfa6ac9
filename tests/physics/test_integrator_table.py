"""The integrators are one table (``physics/integrators.py``): every row has a branch in the
kernel, and a name or id that is not in the table is refused, never run as another method."""

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Simulator, World
from fluidsim_envs.physics import integrators as IT
from fluidsim_envs.physics import kernels as K

BALL = Craft(name="ball", mass_kg=1.0, inertia_kgm2=(0.4, 0.5, 0.6))


@pytest.mark.parametrize("method", IT.TABLE, ids=lambda m: m.name)
def test_every_row_has_its_own_branch(method):
    # a constant force from rest: x = a t^2 (1/2 + (share - 1/2) dt / t)... exactly what the
    # row's drift share says for one step: x1 = share dt^2 a. A row without a branch leaves
    # the state untouched; a row run by another branch gets another share.
    sim = Simulator(BALL, World(gravity_mps2=0.0), num_envs=1, dt=0.1, integrator=method.name)
    sim.set_external_force((2.0, 0.0, 0.0))
    sim.reset(ang_vel=(0.3, -0.2, 0.5))
    sim.step()
    np.testing.assert_allclose(sim.pos[0, 0, 0], method.drift_share * 0.1**2 * 2.0, atol=1e-15)
    np.testing.assert_allclose(sim.lin_vel[0, 0, 0], 0.2, rtol=1e-15)
    assert not np.array_equal(sim.quat[0, 0], [1.0, 0.0, 0.0, 0.0])  # it turned


def test_the_table_is_consistent():
    assert [m.id for m in IT.TABLE] == list(range(len(IT.TABLE)))
    assert K.INTEGRATORS == {m.name: m.id for m in IT.TABLE}
    for m in IT.TABLE:
        assert len(m.stage_times) == m.evals_per_step and 0.0 <= m.drift_share <= 1.0


@pytest.mark.parametrize("bad", ["rk3", "RK4", "", 7, -1, None])
def test_unknown_names_and_ids_raise(bad):
    with pytest.raises(ValueError, match="integrator"):
        if isinstance(bad, int):
            IT.get(bad)
        else:
            Simulator(BALL, integrator=bad)


def test_the_kernel_refuses_an_id_without_a_branch():
    sim = Simulator(BALL, num_envs=1)
    sim._method = len(IT.TABLE)  # what a new row without a kernel branch would pass
    with pytest.raises(ValueError, match="unknown integrator id"):
        sim.step()


def test_every_method_is_described_for_users():
    doc = Simulator.__doc__
    for m in IT.TABLE:
        assert f"``{m.name}`` [{m.evals_per_step}]" in doc, m.name
