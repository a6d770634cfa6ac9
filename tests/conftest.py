"""Suite-wide fixtures."""

import pytest

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
