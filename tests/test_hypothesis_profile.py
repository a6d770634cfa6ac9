"""The Hypothesis profile that tests/conftest.py loads for every property test."""

import importlib
import pkgutil
import sys

from hypothesis import given, settings
from hypothesis import strategies as st

drawn = []


@settings(max_examples=20)
@given(st.floats(-1e3, 1e3), st.integers(-100, 100))
def _draw(x, n):
    drawn.append((x, n))


def test_property_tests_are_derandomized():
    """The profile holds for every property test, and a test draws the same examples each
    time it runs."""
    assert settings.default.derandomize
    assert settings.default.database is None and settings.default.deadline is None
    runs = []
    for _ in range(2):
        drawn.clear()
        _draw()
        runs.append(list(drawn))
    assert runs[0] == runs[1] and len(set(runs[0])) > 10


@settings(max_examples=1)
@given(st.none())
def test_the_whole_project_is_imported_before_a_property_test_draws(_):
    """Hypothesis mixes constants from the project's imported modules into its draws, so
    conftest imports every module first: a property test then draws the same examples
    whichever tests ran before it (alone, in the whole suite, on either ``-n 2`` worker)."""
    missing = []
    for package in ("fluidsim_envs", "benchmarks"):
        root = importlib.import_module(package)
        for info in pkgutil.walk_packages(root.__path__, f"{package}."):
            if info.name not in sys.modules:
                missing.append(info.name)
    assert not missing
