"""The bad-input table stays whole: at least the 197 inputs issue 22 tried."""

import importlib
import pathlib


def test_the_table_holds_at_least_197_rows():
    here = pathlib.Path(__file__).parent
    rows = []
    for path in sorted(here.glob("test_*.py")):
        if path.stem == "test_count":
            continue
        module = importlib.import_module(f"tests.bad_inputs.{path.stem}")
        rows += list(module.ROWS)
    ids = [r.id for r in rows]
    assert len(set(ids)) == len(ids), "row ids must be distinct across the table"
    assert len(rows) >= 197, f"the bad-input table has {len(rows)} rows, fewer than 197"
