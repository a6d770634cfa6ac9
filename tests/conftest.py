"""Suite-wide fixtures, and the Hypothesis profile every property test runs under."""

import importlib
import pkgutil

import pytest
from hypothesis import settings
from numba.core import event as _numba_event

# Property tests are derandomized: each draws the same examples on every run (seeded from a
# hash of the test), so a failure in CI is a failure on every machine and a pass is not luck.
# No example database (nothing replayed from, or written to, .hypothesis/examples), no
# deadline (the first example may compile numba kernels). Each test sets its own max_examples.
settings.register_profile("fluidsim", derandomize=True, database=None, deadline=None)
settings.load_profile("fluidsim")

# the project's own modules, whose constants Hypothesis mixes into what it draws
PROJECT_PACKAGES = ("fluidsim_envs", "benchmarks")


def project_modules() -> list[str]:
    """Every module of :data:`PROJECT_PACKAGES`, by name."""
    names = []
    for package in PROJECT_PACKAGES:
        root = importlib.import_module(package)
        names += [m.name for m in pkgutil.walk_packages(root.__path__, f"{package}.")]
    return names


def pytest_collection_modifyitems(items):
    """Where property tests will run, the whole project is imported before the first one
    draws. Hypothesis mixes in constants found in the local modules imported so far, so a
    derandomized test would otherwise draw other examples when the tests before it had
    imported more of the project: another selection of tests, or another share of them on a
    ``pytest -n 2`` worker (measured: the dart's property test drew different examples alone
    and after tests/physics/test_tetra.py and tests/scenes/test_registry.py)."""
    if any(getattr(getattr(item, "obj", None), "is_hypothesis_test", False) for item in items):
        for name in project_modules():
            importlib.import_module(name)


# test folders that run the physics under many integrators
_MANY_INTEGRATORS = {"physics", "craft"}


@pytest.fixture(autouse=True)
def _one_kernel_for_many_integrators(request, monkeypatch):
    """Where tests run every integrator, one step kernel shared by all six (``Simulator``'s
    ``shared_kernel``) instead of a kernel per integrator, compiled for each: a cold run of
    the suite compiles about half as much (per integrator it took 934 s on 2 cores, against
    the 10 minutes allowed). The envs' tests keep the default, the kernel their users run;
    tests/physics/test_integrator_table.py checks that both give the same states, bit for
    bit."""
    if request.path.parent.name in _MANY_INTEGRATORS:
        monkeypatch.setenv("FLUIDSIM_SHARED_KERNEL", "1")


# ---- where the suite's compile time goes ----------------------------------------------------


class _CompileLog(_numba_event.Listener):
    """With ``FLUIDSIM_COMPILE_LOG=DIR``, each worker appends one line per outermost compile of
    the project's kernels to ``DIR/<worker>.tsv``: the test, the kernel, its argument types'
    hash and the seconds (how the suite's cold time was cut: which kernels compile, how often,
    and on which worker)."""

    def __init__(self, folder: str) -> None:
        import os
        import time

        self.time, self.depth, self.t0, self.test = time, 0, 0.0, ""
        worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
        os.makedirs(folder, exist_ok=True)
        self.out = open(os.path.join(folder, f"{worker}.tsv"), "a")  # noqa: SIM115
        _numba_event.register("numba:compile", self)

    def on_start(self, ev) -> None:
        if self.depth == 0:
            self.t0 = self.time.perf_counter()
        self.depth += 1

    def on_end(self, ev) -> None:
        self.depth -= 1
        d = ev.data["dispatcher"]
        mod = getattr(d.py_func, "__module__", "")
        if self.depth == 0 and mod.startswith("fluidsim_envs"):
            took = self.time.perf_counter() - self.t0
            sig = hash(str(ev.data.get("args")))
            self.out.write(f"{self.test}\t{mod}.{d.py_func.__name__}\t{sig}\t{took:.1f}\n")
            self.out.flush()


def pytest_configure(config):
    import os

    folder = os.environ.get("FLUIDSIM_COMPILE_LOG")
    if folder:
        config._compile_log = _CompileLog(folder)


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_setup(item):
    log = getattr(item.config, "_compile_log", None)
    if log is not None:
        log.test = item.nodeid
