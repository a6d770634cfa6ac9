"""The kernels' named data (physics/model.py): every sample kind has its tables, every table
its documented layout, and packing a craft gives the rows its samples declare."""

import numpy as np

from fluidsim_envs.physics import Craft, Plate, Simulator, World
from fluidsim_envs.physics import model as M
from fluidsim_envs.physics.state import NBODY


def test_every_sample_kind_has_its_samples_fields():
    fields = set(M.Samples._fields)
    for kind in M.KINDS:
        assert {kind.name, f"{kind.name}_at"} <= fields, kind.name
        assert {f"{kind.name}_{suffix}" for suffix, _ in kind.geometry} <= fields, kind.name
        for size in (*kind.area, *kind.efficiency, *kind.thrust):
            assert size in kind.sizes, (kind.name, size)


def test_packed_tables_hold_each_samples_declared_rows():
    boat = Craft.load("speedboat")
    sim = Simulator([boat, Craft.load("buoy")], World(water=True), num_envs=3, dtype=np.float32)
    model = sim._model
    assert model.body.shape == (3, 2, NBODY)
    for kind in M.KINDS:
        table, at = getattr(sim._samples, kind.name), getattr(sim._samples, f"{kind.name}_at")
        samples = kind.of(boat)
        assert table.shape[0] == kind.width and at[1] == len(samples)
        for j, s in enumerate(samples):
            want = np.array([*s.offset_m, *(getattr(s, a) or 0.0 for a in kind.sizes)])
            np.testing.assert_array_equal(table[:, j], want.astype(np.float32))
    # nothing scaled: every sample reads the row of ones
    assert sim._samples.factor_row.shape == (len(M.FACTORS), boat.num_samples + 9)
    assert not sim._samples.factor_row.any()
    np.testing.assert_array_equal(sim._samples.factor, np.ones((1, 3), np.float32))


def test_samples_scaled_together_share_one_row_of_factors():
    boat = Craft.load("speedboat")
    sim = Simulator(boat, World(water=True), num_envs=4)
    sim.set_sample_scale("bottom", area=2.0, env_ids=[1])
    sim.set_sample_scale("bottom", area=[3.0, 4.0], env_ids=[2, 3])  # the same row, in place
    row, factor = sim._samples.factor_row, sim._samples.factor
    bottom = dict(boat.groups)["bottom"]
    plates = M.sample_names(boat)["plate"]  # the first kind: sample j is plate j
    j = [plates.index(n) for n in bottom]
    assert len(set(row[M.F_AREA, j])) == 1 and row[M.F_AREA, j[0]] != 0
    np.testing.assert_array_equal(factor[row[M.F_AREA, j[0]]], [1.0, 2.0, 3.0, 4.0])
    assert np.count_nonzero(row) == len(bottom)  # nothing else moved off row 0
    # part of the group scaled again: those samples get a row of their own
    sim.set_sample_scale(bottom[0], area=5.0, env_ids=[0])
    assert row[M.F_AREA, j[0]] != row[M.F_AREA, j[1]]
    factor = sim._samples.factor  # the table may have grown
    np.testing.assert_array_equal(factor[row[M.F_AREA, j[0]]], [5.0, 2.0, 3.0, 4.0])
    np.testing.assert_array_equal(factor[row[M.F_AREA, j[1]]], [1.0, 2.0, 3.0, 4.0])
    # back to the craft's values: back to row 0
    sim.set_sample_scale("all", area=1.0)
    sim.set_thrust_scale(0.5, env_ids=[3])
    sim.set_thrust_scale(1.0)
    assert not sim._samples.factor_row.any()


def test_a_group_naming_a_sample_twice_scales_only_its_members():
    plates = tuple(Plate(n, (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.1) for n in ("a", "b"))
    craft = Craft(name="c", mass_kg=1.0, inertia_kgm2=(1, 1, 1), plates=plates,
                  groups={"g": ["a", "a"]})  # fmt: skip
    sim = Simulator(craft, World(), num_envs=2)
    sim.set_sample_scale("all", area=2.0, env_ids=[0])  # a and b share a row
    sim.set_sample_scale("g", area=3.0, env_ids=[0])  # a alone: b keeps its 2
    row, factor = sim._samples.factor_row[M.F_AREA], sim._samples.factor
    np.testing.assert_array_equal(factor[row], [[3.0, 1.0], [2.0, 1.0]])
