"""The integrators are one table (``physics/integrators.py``): every row has its block step in
the kernels, a name or id that is not in the table is refused, never run as another method,
and the kernel compiled per integrator runs exactly what the shared one does."""

import numpy as np
import pytest

from fluidsim_envs.physics import Craft, Simulator, SwellWave, World
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


@pytest.mark.parametrize("bad", ["rk3", "RK4", "", 12, -1, None])
def test_unknown_names_and_ids_raise(bad):
    with pytest.raises(ValueError, match="integrator"):
        if isinstance(bad, int):
            IT.get(bad)
        else:
            Simulator(BALL, integrator=bad)


# per integrator, an id without a block step is typed with the shared step instead, which
# refuses it when it runs, like the shared kernel
@pytest.mark.parametrize("shared", [True, False], ids=["shared", "per-integrator"])
def test_the_kernel_refuses_an_id_without_a_branch(shared):
    sim = Simulator(BALL, num_envs=1, shared_kernel=shared)
    sim._method = len(IT.TABLE)  # what a new row without a kernel branch would pass
    with pytest.raises(ValueError, match="unknown integrator id"):
        sim.step()


@pytest.mark.parametrize("method", IT.TABLE, ids=lambda m: m.name)
def test_per_integrator_and_shared_kernels_agree_bit_for_bit(method):
    """The kernel compiled for one integrator (the default) and the one shared by all
    (``shared_kernel=True``) run the same block step: the same states, bit for bit, on a
    craft with every kind of sample (plates, control surfaces, cylinders, buoyancy, thrust)
    crossing the water's surface in a swell."""
    craft = Craft.load("speedboat")
    world = World(water=True, swell=(SwellWave(amplitude_m=0.2, wavelength_m=8.0),))
    runs = []
    for shared in (True, False):
        sim = Simulator(craft, world, num_envs=3, dt=0.01, integrator=method.name,
                        shared_kernel=shared)  # fmt: skip
        sim.reset(pos=[(0, 0, 0.1), (1, 0, 0.0), (2, 0, 0.3)], lin_vel=(8.0, 0.5, -0.2),
                  ang_vel=(0.2, -0.3, 0.1))  # fmt: skip
        controls = np.linspace(-1.0, 1.0, 3 * len(sim.control_names)).reshape(3, -1)
        sim.step(controls, steps=30)
        runs.append((sim.pos.copy(), sim.quat.copy(), sim.lin_vel.copy(), sim.ang_vel.copy()))
    for a, b in zip(*runs, strict=True):
        np.testing.assert_array_equal(a, b)
    assert np.all(np.isfinite(runs[0][0])) and not np.array_equal(runs[0][0][0], [[0, 0, 0.1]])


def test_every_method_is_described_for_users():
    doc = Simulator.__doc__
    for m in IT.TABLE:
        assert f"``{m.name}`` [{m.evals_per_step}]" in doc, m.name
