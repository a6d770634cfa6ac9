"""The one-time line while numba compiles our kernels (fluidsim_envs/compiling.py)."""

import io

import numba
from numba.core import event

import fluidsim_envs  # noqa: F401  (installs the package's listener)
from fluidsim_envs import compiling


def _kernel(module: str):
    def add_one(x):
        return x + 1

    add_one.__module__ = module
    return numba.njit(add_one)  # no cache: it compiles at its first call


def test_a_cold_compile_of_our_kernel_says_so_once_with_its_time():
    out = io.StringIO()
    notice = compiling.CompileNotice(stream=out, slow_s=0.0)
    with event.install_listener("numba:compile", notice):
        assert _kernel("fluidsim_envs.physics.fake")(1) == 2
        assert _kernel("fluidsim_envs.physics.fake")(2.0) == 3.0
    lines = out.getvalue().splitlines()
    assert lines[0].startswith("fluidsim-envs: compiling the physics kernels")
    assert "python -m fluidsim_envs.warmup" in lines[0]
    assert [line.split(" in ")[0] for line in lines[1:]] == ["  compiled add_one"] * 2
    assert sum("compiling the physics kernels" in line for line in lines) == 1


def test_other_packages_kernels_and_quiet_mode_say_nothing(monkeypatch):
    out = io.StringIO()
    notice = compiling.CompileNotice(stream=out, slow_s=0.0)
    with event.install_listener("numba:compile", notice):
        _kernel("someone_else.kernels")(1)
        monkeypatch.setenv("FLUIDSIM_QUIET", "1")
        _kernel("fluidsim_envs.physics.fake")(1)
    assert out.getvalue() == ""


def test_importing_the_package_installs_the_listener():
    assert compiling._installed == [compiling.NOTICE]
