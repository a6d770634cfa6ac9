"""Simulator.sample_flows: what each sample meets, read from the force loops' own values.

Checked against the rigid-body closed form for the velocity of a point of a body
(``v_point = v + omega x r``, so the inflow is ``wind - v_point``, turned into the body frame by
the transpose of its rotation), against the forces ``sample_forces`` records (a plate's pressure
times its area is the force against its normal), against the surface layer's blend of
densities, and for bit-for-bit independence: reading the samples leaves the trajectory as it
was, and the serial and parallel kernels agree.
"""

import numpy as np
import pytest

from fluidsim_envs.physics import SENSE_FIELDS, Craft, Simulator, World
from fluidsim_envs.physics.rotation import quat_to_matrix

E = 70  # two blocks of environments (kernels.BLOCK = 64)
F = {name: j for j, name in enumerate(SENSE_FIELDS)}
WIND = np.array([3.0, -1.0, 0.5])


def _flying(rng, parallel=None, world=None) -> Simulator:
    sim = Simulator(Craft.load("paper_airplane"), world or World(wind_mps=tuple(WIND)),
                    num_envs=E, parallel=parallel)  # fmt: skip
    sim.reset(
        pos=rng.normal(0.0, 0.3, (E, 3)) + [0.0, 0.0, 5.0],
        quat=rng.normal(size=(E, 4)) * [1.0, 0.3, 0.3, 1.0],
        lin_vel=rng.normal(0.0, 2.0, (E, 3)) + [7.0, 0.0, 0.0],
        ang_vel=rng.normal(0.0, 1.0, (E, 3)),
    )
    return sim


def _plates(craft: Craft):
    """Names and body normals of the craft's plates without a control (not deflected)."""
    driven = {s.sample for c in craft.controls for s in c.surfaces}
    unit = [
        (p.name, np.asarray(p.normal, dtype=float)) for p in craft.plates if p.name not in driven
    ]
    return [(name, n / np.linalg.norm(n)) for name, n in unit]


def test_inflow_is_the_wind_relative_to_the_moving_point_in_the_body_frame():
    sim = _flying(np.random.default_rng(0))
    plates = _plates(sim.crafts[0])
    names = [n for n, _ in plates]
    flows = sim.sample_flows(names)
    assert flows.shape == (E, len(names), len(SENSE_FIELDS)) and flows.dtype == np.float64
    order = [p.name for p in sim.crafts[0].plates]
    for e in (0, 41, E - 1):
        points, _, _ = sim.sample_forces(env_index=e)
        rot = np.asarray(quat_to_matrix(*sim.quat[e, 0])).reshape(3, 3)
        for j, (name, normal) in enumerate(plates):
            r = points[order.index(name)] - sim.pos[e, 0]
            inflow = WIND - (sim.lin_vel[e, 0] + np.cross(sim.ang_vel[e, 0], r))
            body = rot.T @ inflow
            got = flows[e, j]
            # float64 rounding of a few products of terms of about 10 m/s: 1e-13 measured
            np.testing.assert_allclose(got[:3], body, rtol=0.0, atol=1e-12)
            assert got[F["inflow_normal_mps"]] == pytest.approx(body @ normal, abs=1e-12)
            assert got[F["density_kgm3"]] == sim.world.air_density_kgm3
            assert got[F["height_m"]] == pytest.approx(points[order.index(name)][2], abs=1e-12)


def test_pressure_times_area_is_the_force_against_the_normal():
    sim = _flying(np.random.default_rng(1))
    craft = sim.crafts[0]
    plates = _plates(craft)
    flows = sim.sample_flows([n for n, _ in plates])
    order = [p.name for p in craft.plates]
    area = {p.name: p.area_m2 for p in craft.plates}
    for e in (3, 66):
        _, forces, _ = sim.sample_forces(env_index=e)
        rot = np.asarray(quat_to_matrix(*sim.quat[e, 0])).reshape(3, 3)
        for j, (name, normal) in enumerate(plates):
            against = -forces[order.index(name)] @ (rot @ normal)
            scale = max(np.abs(forces[order.index(name)]).max(), 1e-6)
            assert flows[e, j, F["pressure_pa"]] * area[name] == pytest.approx(
                against, abs=1e-12 * scale / area[name]
            )


def test_density_blends_across_the_surface_layer():
    """A floating hull's samples: water below the surface layer, air above it, and across
    it the layer's linear blend (forces.water_fraction) at each sample's own height."""
    world = World(water=True)
    craft = Craft.load("speedboat")
    sim = Simulator(craft, world, num_envs=4)
    sim.reset(pos=[[0.0, 0.0, z] for z in (-0.3, 0.0, 0.1, 0.5)])
    names = [p.name for p in craft.plates]
    flows = sim.sample_flows(names)
    height = flows[..., F["height_m"]]
    blend = world.surface_blend_m
    frac = np.clip(0.5 - height / blend, 0.0, 1.0)
    rho_a, rho_w = world.air_density_kgm3, world.water_density_kgm3
    np.testing.assert_allclose(flows[..., F["density_kgm3"]], rho_a + frac * (rho_w - rho_a),
                               rtol=1e-14)  # fmt: skip
    assert (height < -blend).any() and (height > blend).any()  # both sides are exercised
    offsets = np.array([p.offset_m for p in craft.plates])
    z0 = np.array([-0.3, 0.0, 0.1, 0.5])[:, None]
    np.testing.assert_allclose(height, z0 + offsets[None, :, 2], atol=1e-12)  # level hull


def test_reading_leaves_the_trajectory_bit_identical_and_kernels_agree():
    runs = []
    for parallel, read in ((False, False), (False, True), (True, True)):
        sim = _flying(np.random.default_rng(2), parallel=parallel)
        sim.set_actuators(0.05, 5.0)  # the deflected surfaces' path too
        controls = np.random.default_rng(3).uniform(-1.0, 1.0, (E, len(sim.control_names)))
        reads = []
        for _ in range(5):
            sim.step(controls, steps=3)
            if read:
                reads.append(sim.sample_flows(["left_aileron", "fin", "left_wing"]).copy())
        runs.append((sim.pos.copy(), sim.quat.copy(), sim.lin_vel.copy(), reads))
    for pos, quat, vel, _ in runs[1:]:
        assert np.array_equal(pos, runs[0][0]) and np.array_equal(quat, runs[0][1])
        assert np.array_equal(vel, runs[0][2])
    assert all(np.array_equal(a, b) for a, b in zip(runs[1][3], runs[2][3], strict=True))


@pytest.mark.parametrize(
    "samples, body, match",
    [
        (["left_wing", "no_such_plate"], 0, r"unknown samples \['no_such_plate'\]"),
        ([], 0, "non-empty list"),
        ("left_wing", 0, "non-empty list of sample names, got 'left_wing'"),
        (["fin", "fin"], 0, "named twice"),
        (["fin"], 3, "body"),
        (["hull_fore", "propeller"], 0, r"\['propeller'\] are thrusters"),
    ],
)
def test_bad_samples_are_named(samples, body, match):
    craft = "uuv" if "propeller" in samples else "paper_airplane"
    sim = Simulator(Craft.load(craft), World(), num_envs=2)
    with pytest.raises(ValueError, match=match):
        sim.sample_flows(samples, body=body)


def test_some_environments_read_as_in_a_full_read():
    sim = _flying(np.random.default_rng(4))
    names = ["left_wing", "fin", "left_elevator"]
    full = sim.sample_flows(names).copy()
    ids = np.array([66, 3, 64])  # both blocks, out of order
    np.testing.assert_array_equal(sim.sample_flows(names, env_ids=ids), full[ids])
