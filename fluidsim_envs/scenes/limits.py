"""What each scene's parameters may be: their ranges, declared once, and the physics step limit.

**Ranges.** A scene's parameter dataclass declares ``RANGES``, one entry per numeric field:
a :class:`Bound` (a number, or an integer, within inclusive bounds) or a :class:`Span` (a
(low, high) pair drawn per episode, each end within the bounds). :func:`check_params`
enforces them, ``docs/environments.md``'s parameter tables are written from them
(``benchmarks/report.py``) and ``tests/bad_inputs/test_params.py`` tries every field past
each end.

**The step limit.** Past an integrator's stability limit the fluid forces' own damping
makes a craft oscillate with a growing amplitude until the clamps hold it: finite, and wrong.
The runaway check (``Simulator.diverged``) ends such an episode, but an env that accepts such
a ``dt`` hands the learner mostly ended episodes. So each scene refuses a ``dt`` above the
largest one at which none of the episodes of the bisection's fuzz runs diverged
(``benchmarks/env_stability.py``: adversarial actions, parameters at the ends of their
ranges, 2e5 env-steps a run), per integrator, in :data:`DT_LIMIT_S`: a v1 at ``hard`` (the
level that moves the air and water most), at most its v0's, whichever level it flies;
``docs/env_stability.csv`` holds the measurement and ``tests/scenes/test_limits.py`` keeps
this table equal to it. A limit, not a margin: a longer fuzz (docs/fuzz.csv) finds rare,
flagged divergences at exactly the limit with the parameters at their extremes.

:func:`unchecked` lifts the step limit inside a ``with`` block: only for measuring it.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import threading
from collections.abc import Mapping

from ..physics import checks as CK


@dataclasses.dataclass(frozen=True)
class Bound:
    """A number in [lo, hi] (None: unbounded that way); ``integer``: an int."""

    lo: float | None = None
    hi: float | None = None
    integer: bool = False

    def check(self, own: str, key: str, value):
        return CK.number(own, key, value, ge=self.lo, le=self.hi, integer=self.integer)

    def text(self) -> str:
        kind = "integer" if self.integer else "number"
        return f"{kind} in [{_g(self.lo, '-inf')}, {_g(self.hi, 'inf')}]"


@dataclasses.dataclass(frozen=True)
class Span:
    """A (low, high) pair with lo <= low <= high <= hi, drawn uniformly per episode."""

    lo: float
    hi: float

    def check(self, own: str, key: str, value):
        return CK.value_range(own, key, value, ge=self.lo, le=self.hi)

    def text(self) -> str:
        return f"(low, high) within [{_g(self.lo)}, {_g(self.hi)}]"


def _g(x, none: str = "") -> str:
    return none if x is None else f"{x:g}"


def check_params(params, own: str, ranges: Mapping[str, Bound | Span]) -> None:
    """Check every field of the frozen dataclass ``params`` named in ``ranges`` (storing a
    span as a tuple of floats); a field of ``params`` that is a number and has no range is a
    programming error, caught on the first construction. NumPy scalars (np.float32(0.01),
    np.int64(4)) are stored first as the Python numbers they hold: the simulator and the
    kernels then see one type per parameter."""
    CK.plain_fields(params)
    for key, rule in ranges.items():
        value = rule.check(own, key, getattr(params, key))
        if isinstance(rule, Span):
            object.__setattr__(params, key, value)
    for f in dataclasses.fields(params):
        if f.name not in ranges and isinstance(f.default, (int, float, tuple)):
            if not isinstance(f.default, bool) and f.name not in NOT_NUMBERS:
                raise AssertionError(f"{own}: parameter {f.name} has no declared range")


# fields that hold something else than a number or a span (checked by their scene)
NOT_NUMBERS = frozenset({"swell"})

# what every scene's stepping takes alike: physics steps per action, actions per episode
SUBSTEPS = Bound(1, 1000, integer=True)
EPISODE_STEPS = Bound(1, 10**7, integer=True)

# reward weights: a term's weight beyond 1000 is a unit mistake (the largest default is 100),
# and an unbounded one makes every reward inf (1e308)
WEIGHT = Bound(0.0, 1000.0)

# The largest dt (s) with no diverged episode in the fuzz, by scene and integrator (a v1: at
# hard, at most its v0's)
# (python -m benchmarks.env_stability; docs/env_stability.csv).
DT_LIMIT_S: dict[str, dict[str, float]] = {
    "PaperAirplane-v0": {
        "explicit_euler": 0.01,
        "symplectic_euler": 0.0098,
        "velocity_verlet": 0.024,
        "rk2": 0.016,
        "rk4": 0.025,
        "verlet_tetra": 0.01,
        "accurate_euler": 0.012,
        "position_verlet": 0.0098,
        "prescaled_symplectic_euler": 0.0098,
        "velocity_verlet_cached": 0.011,
        "trapezoid_symplectic_euler": 0.01,
        "implicit_midpoint": 0.003,
    },
    "SubmarineWake-v0": {
        "explicit_euler": 0.015,
        "symplectic_euler": 0.087,
        "velocity_verlet": 0.11,
        "rk2": 0.071,
        "rk4": 0.12,
        "verlet_tetra": 0.09,
        "accurate_euler": 0.064,
        "position_verlet": 0.087,
        "prescaled_symplectic_euler": 0.087,
        "velocity_verlet_cached": 0.1,
        "trapezoid_symplectic_euler": 0.087,
        "implicit_midpoint": math.nan,
    },
    "BoatOnStep-v0": {
        "explicit_euler": 0.047,
        "symplectic_euler": 0.05,
        "velocity_verlet": 0.05,
        "rk2": 0.05,
        "rk4": 0.05,
        "verlet_tetra": 0.05,
        "accurate_euler": 0.05,
        "position_verlet": 0.05,
        "prescaled_symplectic_euler": 0.05,
        "velocity_verlet_cached": 0.05,
        "trapezoid_symplectic_euler": 0.05,
        "implicit_midpoint": 0.018,
    },
    "PaperAirplane-v1": {
        "explicit_euler": 0.0072,
        "symplectic_euler": 0.0085,
        "velocity_verlet": 0.017,
        "rk2": 0.011,
        "rk4": 0.02,
        "verlet_tetra": 0.0083,
        "accurate_euler": 0.0093,
        "position_verlet": 0.0085,
        "prescaled_symplectic_euler": 0.0085,
        "velocity_verlet_cached": 0.0098,
        "trapezoid_symplectic_euler": 0.0083,
        "implicit_midpoint": 0.0026,
    },
    "SubmarineWake-v1": {
        "explicit_euler": 0.011,
        "symplectic_euler": 0.083,
        "velocity_verlet": 0.11,
        "rk2": 0.071,
        "rk4": 0.12,
        "verlet_tetra": 0.082,
        "accurate_euler": 0.064,
        "position_verlet": 0.083,
        "prescaled_symplectic_euler": 0.083,
        "velocity_verlet_cached": 0.1,
        "trapezoid_symplectic_euler": 0.078,
        "implicit_midpoint": math.nan,
    },
    "BoatOnStep-v1": {
        "explicit_euler": 0.04,
        "symplectic_euler": 0.05,
        "velocity_verlet": 0.05,
        "rk2": 0.047,
        "rk4": 0.05,
        "verlet_tetra": 0.05,
        "accurate_euler": 0.05,
        "position_verlet": 0.05,
        "prescaled_symplectic_euler": 0.05,
        "velocity_verlet_cached": 0.05,
        "trapezoid_symplectic_euler": 0.05,
        "implicit_midpoint": 0.015,
    },
}

_STATE = threading.local()


@contextlib.contextmanager
def unchecked():
    """Within the block, scenes accept a ``dt`` past :data:`DT_LIMIT_S` (how the limit is
    measured); nothing else is lifted."""
    before = getattr(_STATE, "off", False)
    _STATE.off = True
    try:
        yield
    finally:
        _STATE.off = before


def check_step(own: str, dt: float, integrator: str, scene: str) -> None:
    """Refuse a ``dt`` above the scene's measured stability limit for ``integrator``."""
    limit = DT_LIMIT_S.get(scene, {}).get(integrator)
    if limit is None or getattr(_STATE, "off", False) or dt <= limit:
        return
    if math.isnan(limit):
        raise ValueError(
            f"{own}: integrator {integrator!r} diverged in this env's fuzz at every step tried "
            "(down to an eighth of the default: docs/env_stability.csv); choose another"
        )
    raise ValueError(
        f"{own}: dt must be <= {limit:g} s with integrator {integrator!r} (its stability "
        f"limit in this env, measured by fuzzing: docs/env_stability.csv), got {dt!r}"
    )
