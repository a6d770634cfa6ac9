"""Every v1 knob's declared range, per craft, is one the env holds: docs/ranges.csv
(``python -m benchmarks.ranges``) measured each end of each range and every corner of the
physics knobs at the ranges declared now, and none of them lost 1% of its episodes to
divergence."""

from __future__ import annotations

import pytest

from benchmarks import ranges as R
from benchmarks.common import read_csv


@pytest.fixture(scope="module")
def table() -> list[dict]:
    return read_csv(R.CSV)[1]


@pytest.mark.parametrize("env_id", R.v1_envs())
def test_each_declared_range_was_measured_and_holds(table, env_id):
    rows = {(r["knob"], r["end"]): r for r in table if r["env"] == env_id}
    expected = [(knob, end) for knob, end, _ in R.cases(env_id)]
    assert sorted(rows) == sorted(expected), "the table is of other ranges: run the benchmark"
    for knob, end, kwargs in R.cases(env_id):
        row = rows[knob, end]
        if knob != "corner":  # the end measured is the end declared
            assert row["value"] == str(kwargs[knob]), (knob, end, row["value"])
        assert int(row["episodes"]) >= 64
        assert float(row["rate"]) < R.LIMIT, f"{env_id} {knob} {end}: {row['rate']}"
        assert int(row["nonfinite"]) == 0
