"""Say so while numba compiles our kernels: a first step after an install (or a changed
kernel) can wait a minute or more for the compiler, and silence reads as a hang.

numba broadcasts a ``"numba:compile"`` event only when a kernel is neither in memory nor in
its on-disk cache (``cache=True``), so a warm start prints nothing. The first compile of a
process prints one line saying what happens and how to pay it ahead; each outermost compile
that took long prints its time. Lines go to stderr; ``FLUIDSIM_QUIET=1`` silences them.
"""

from __future__ import annotations

import os
import sys
import time

from numba.core import event

SLOW_S = 3.0  # an outermost compile at least this long gets its own line
FIRST_STEP = "19-37 s"  # an env's cold first step (docs/bench_compile.csv; tests/test_readme.py)


class CompileNotice(event.Listener):
    """Listens to numba's compile events for the kernels of this package."""

    def __init__(self, stream=None, slow_s: float = SLOW_S) -> None:
        self.stream = stream
        self.slow_s = slow_s
        self.told = False
        self.depth = 0  # nested compiles: a kernel compiling the non-inlined ones it calls
        self.started = 0.0

    def on_start(self, ev) -> None:
        if not _ours(ev):
            return
        if self.depth == 0:
            self.started = time.perf_counter()
            if not self.told:
                self.told = True
                self._say(
                    "fluidsim-envs: compiling the physics kernels (once after an install or an "
                    f"update, {FIRST_STEP} per env on 2 cores; cached afterwards; "
                    "`python -m fluidsim_envs.warmup` compiles them ahead) ..."
                )
        self.depth += 1

    def on_end(self, ev) -> None:
        if not _ours(ev):
            return
        self.depth -= 1
        took = time.perf_counter() - self.started
        if self.depth == 0 and took >= self.slow_s:
            self._say(f"  compiled {ev.data['dispatcher'].py_func.__name__} in {took:.0f} s")

    def _say(self, line: str) -> None:
        if os.environ.get("FLUIDSIM_QUIET", "") in ("", "0"):
            print(line, file=self.stream or sys.stderr, flush=True)


def _ours(ev) -> bool:
    dispatcher = (ev.data or {}).get("dispatcher")
    module = getattr(getattr(dispatcher, "py_func", None), "__module__", "") or ""
    return module.startswith(__package__ + ".")


NOTICE = CompileNotice()
_installed = []


def install() -> None:
    """Listen for the rest of the process (once; importing the package calls this)."""
    if not _installed:
        event.register("numba:compile", NOTICE)
        _installed.append(NOTICE)


__all__ = ["NOTICE", "SLOW_S", "CompileNotice", "install"]
