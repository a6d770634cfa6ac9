"""The plain-Python integer reference: ``laws.py``'s functions run by the interpreter on
Python integers (no numba, no NumPy in the arithmetic).

:func:`plain_laws` rebinds each compiled function's source code (``laws.ORDER``) to a plain
function whose globals are the plain functions and ``laws``' constants, so the reference
performs the kernel's operations in the kernel's order. Python integers are exact and
unbounded: where the compiled int64 arithmetic wrapped, lost a bit or went through a float,
the two differ, and :func:`run` is how a test finds out (tests/physics/test_fixed.py). Its
driver is its own: lists of Python ints, one environment and one body at a time.
"""

from __future__ import annotations

import types

from . import laws as LW


def plain_laws() -> types.SimpleNamespace:
    """``laws.py``'s functions as plain Python functions calling each other."""
    compiled = sorted(k for k, v in vars(LW).items() if hasattr(v, "py_func"))
    assert compiled == sorted(LW.ORDER), f"laws.ORDER must list {compiled}"  # none compiled
    space = {k: v for k, v in vars(LW).items() if isinstance(v, int) and not isinstance(v, bool)}
    for name in LW.ORDER:
        code = getattr(LW, name).py_func.__code__
        space[name] = types.FunctionType(code, space, name)
    return types.SimpleNamespace(**{name: space[name] for name in LW.ORDER})


def _ints(array) -> list:
    """A NumPy int array as nested lists of Python ints."""
    return [int(x) for x in array] if array.ndim == 1 else [_ints(a) for a in array]


def run(state, model, controls, steps: int) -> tuple[list, list]:
    """``steps`` steps of every environment from ``state[E, B, 13]`` (words) with
    ``model`` (``format.FixedModel``) holding ``controls[E, C]`` (``laws.ANGLE_BITS``
    fraction bits: ``FixedSimulator.fixed_controls``): the final words as nested lists of
    Python ints, and each environment's divergence flag (0/1) over the run."""
    laws = plain_laws()
    st, bc, tab, mix, ctrl, prm = (
        _ints(a) for a in (state, model.bc, model.tab, model.mix, controls, model.prm)
    )
    flags = []
    for e in range(len(st)):
        inp = [[0] * model.n_inp for _ in st[e]]
        for b in range(len(st[e])):
            laws.body_inputs(ctrl[e], tab[b], mix[b], prm, inp[b])
        flag = 0
        for _ in range(steps):
            for b in range(len(st[e])):
                flag |= laws.body_step(st[e][b], bc[b], tab[b], inp[b], prm)
        flags.append(flag)
    for word in (w for env in st for body in env for w in body):
        assert type(word) is int, f"the reference left a {type(word).__name__} in the state"
    return st, flags
