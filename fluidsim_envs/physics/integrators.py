"""The integrators, one table: each method's name, kernel id, cost and what contact needs.

``kernels.STEPPERS`` maps each ``Integrator.id`` to its block step, a compiled function; the
step kernels take the id as a literal and compile only that integrator's step in (a kernel per
integrator); :func:`get` is the one lookup, and an unknown name or id raises. Adding a method
means a row here, its function in ``kernels.STEPPERS`` (kernels.py asserts every row has one)
and in ``kernels._integrate`` (without it the step raises), and its description in
``Simulator``'s docstring.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Integrator:
    """A time-stepping method.

    Attributes:
        name: what ``Simulator(integrator=...)`` takes.
        id: the kernel's integer code for it.
        evals_per_step: force evaluations per step (the cost, for benchmarks).
        drift_share: the share of a step's velocity change that its position update carries
            (``x1 = x0 + dt v0 + share dt^2 a`` for a constant a): what a resting contact
            undoes of the drift (``contact.py``). Symplectic Euler and the tetrahedron drift
            with the new velocity (1), explicit Euler with the old (0); velocity Verlet and
            the Runge-Kutta methods integrate a constant force exactly (1/2).
        stage_times: when in the step (fractions of dt) each force evaluation sees the
            surface and the wake.
        carries: the integrator keeps numbers of its own from one step to the next besides
            the state (the seed's methods: the last position, a prescaled velocity, the last
            acceleration): ``Simulator`` keeps them per body in ``Data.memory``
            (``state.MEMORY_FIELDS``) and they are taken afresh from the state wherever the
            state changed outside the integrator (a reset, contact, ``set_state``).
        iterative: each step solves an implicit equation by fixed-point iteration:
            ``evals_per_step`` is then the cost of one iteration, and
            ``Simulator.iterations`` counts them.
    """

    name: str
    id: int
    evals_per_step: int
    drift_share: float
    stage_times: tuple[float, ...]
    carries: bool = False
    iterative: bool = False


TABLE = (
    Integrator("explicit_euler", 0, 1, 0.0, (0.0,)),
    Integrator("symplectic_euler", 1, 1, 1.0, (0.0,)),
    Integrator("velocity_verlet", 2, 2, 0.5, (0.0, 1.0)),
    Integrator("rk2", 3, 2, 0.5, (0.0, 0.5)),
    Integrator("rk4", 4, 4, 0.5, (0.0, 0.5, 0.5, 1.0)),
    Integrator("verlet_tetra", 5, 1, 1.0, (0.0,)),
    # the seed's remaining methods (docs/seed_map.md)
    Integrator("accurate_euler", 6, 1, 0.5, (0.0,)),
    Integrator("position_verlet", 7, 1, 1.0, (0.0,), carries=True),
    Integrator("prescaled_symplectic_euler", 8, 1, 1.0, (0.0,), carries=True),
    Integrator("velocity_verlet_cached", 9, 1, 0.5, (1.0,), carries=True),
    Integrator("trapezoid_symplectic_euler", 10, 1, 1.0, (0.0,)),
    Integrator("implicit_midpoint", 11, 1, 0.5, (0.5,), iterative=True),
)
BY_NAME = {m.name: m for m in TABLE}
# the seed article's methods added after the first six (docs/seed_map.md)
SEED_METHODS = tuple(m.name for m in TABLE[6:])
BY_ID = {m.id: m for m in TABLE}
assert len(BY_ID) == len(TABLE) and all(len(m.stage_times) == m.evals_per_step for m in TABLE)

# the kernel's codes, as the compile-time constants its branches compare with
EXPLICIT_EULER, SYMPLECTIC_EULER, VELOCITY_VERLET, RK2, RK4, VERLET_TETRA = (
    BY_NAME[n].id
    for n in ("explicit_euler", "symplectic_euler", "velocity_verlet", "rk2", "rk4", "verlet_tetra")
)
ACCURATE_EULER, POSITION_VERLET, PRESCALED_SYMPLECTIC_EULER = (
    BY_NAME[n].id for n in ("accurate_euler", "position_verlet", "prescaled_symplectic_euler")
)
VELOCITY_VERLET_CACHED, TRAPEZOID_SYMPLECTIC_EULER, IMPLICIT_MIDPOINT = (
    BY_NAME[n].id
    for n in ("velocity_verlet_cached", "trapezoid_symplectic_euler", "implicit_midpoint")
)
# implicit_midpoint: a step's fixed-point iteration stops when no number of the state moves
# by more than this many units in the last place of its size (and refuses to go on past
# IMPLICIT_MAX_ITERATIONS: the step is then flagged diverged)
IMPLICIT_TOLERANCE_ULP = 4.0
IMPLICIT_MAX_ITERATIONS = 50


def get(name_or_id: str | int) -> Integrator:
    """The table's row for a name or a kernel id; anything else raises naming it."""
    row = BY_ID.get(name_or_id) if isinstance(name_or_id, int) else BY_NAME.get(name_or_id)
    if row is None:
        raise ValueError(f"unknown integrator {name_or_id!r}; choose one of {sorted(BY_NAME)}")
    return row
