"""The kernels' named data (physics/model.py): every sample kind has its tables, every table
its documented layout, and packing a craft gives the rows its samples declare."""

import numpy as np

from fluidsim_envs.physics import Craft, Simulator, World
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
            for e in range(3):
                np.testing.assert_array_equal(table[:, j, e], want.astype(np.float32))
