"""Where every number of the physics state lives: the one layout that the integrators, contact,
the scene kernels and the viewers import.

Two layouts, both declared here as (name, width) lists and turned into row numbers:

- ``STATE_FIELDS``: a rigid body's state, 13 numbers in the world frame: position x, quaternion
  q (w, x, y, z; body -> world), linear velocity v and angular momentum L about the center of
  mass. ``Simulator`` stores it as ``st[NSTATE, B, E]``; ``st[OX + k, b, e]`` is body b's x_k
  in environment e.
- ``SCRATCH_FIELDS``: the rows of a block's scratch ``S[row * BLOCK + i]`` (``kernels.py``),
  one row per number and ``BLOCK`` environments per row, so that the loops over a block run
  over environments innermost and vectorize. The state rows come first; ``STATE + OX`` is
  where contact and the integrators find a body's position.
- ``MEMORY_FIELDS``: what an integrator that ``carries`` numbers from step to step
  (``integrators.Integrator.carries``) keeps per body, ``Data.memory[NMEMORY, B, E]``: the
  state as its last step left it (a state that differs from it was changed from outside: the
  carried numbers are then taken afresh from the state) and the carried numbers themselves.
- ``BODY_FIELDS``: the per-environment body constants ``body[E, B, NBODY]`` (mass, inverse
  inertia, second moment, center-of-mass shift), which ``Simulator.set_mass_properties`` sets
  per environment.
"""

from __future__ import annotations

from .surface import MAX_WAVES
from .wake import NSRC


def rows(fields: tuple[tuple[str, int], ...]) -> tuple[dict[str, int], int]:
    """The first row of each field of a (name, width) list, and the total width."""
    first, at = {}, 0
    for name, width in fields:
        first[name] = at
        at += width
    return first, at


STATE_FIELDS = (("position", 3), ("quaternion", 4), ("velocity", 3), ("angular_momentum", 3))
_STATE, NSTATE = rows(STATE_FIELDS)
OX, OQ, OV, OL = (_STATE[n] for n in ("position", "quaternion", "velocity", "angular_momentum"))

BODY_FIELDS = (
    ("mass", 1),  # kg
    ("inv_inertia", 6),  # inverse body inertia tensor (xx, yy, zz, xy, xz, yz), 1/(kg m^2)
    # S = tr(I)/2 1 - I (xx, yy, zz, xy, xz, yz): a matched tetrahedron's sum m_i r_i r_i^T
    ("second_moment", 6),
    # the center of mass's shift from the craft's (body frame, m): the force loops take each
    # sample's offset as the craft's offset minus this (0 for the craft's own balance)
    ("com_shift", 3),
    # the speed (m/s) and turn rate (rad/s) past which the body has run away (the craft's,
    # Craft.runaway_speed_mps / runaway_rate_dps; inf: only the fluid clamp says)
    ("runaway", 2),
)
_BODY, NBODY = rows(BODY_FIELDS)
B_MASS, B_INV_INERTIA, B_SECOND_MOMENT, B_COM_SHIFT, B_RUNAWAY = (_BODY[n] for n, _ in BODY_FIELDS)

MEMORY_FIELDS = (
    ("end", NSTATE),  # the state as the integrator's last step left it
    # position_verlet: the last position (3); prescaled_symplectic_euler: the velocity times
    # dt, a displacement per step (3); velocity_verlet_cached: the last step's dv/dt and dL/dt
    ("carry", 6),
)
_MEMORY, NMEMORY = rows(MEMORY_FIELDS)

BLOCK = 64  # environments per block: a multiple of the SIMD width, scratch fits in L1/L2
SCRATCH_FIELDS = (
    ("state", NSTATE),  # the state being stepped
    ("start", NSTATE),  # the state at the step's start (Runge-Kutta)
    ("rk_sum", NSTATE),  # RK4's k1 + 2 k2 + 2 k3 + k4
    ("deriv", NSTATE),  # the derivative of the state rows (forces, torques, rates)
    ("rot", 9),  # the rotation matrix R, row-major
    ("omega", 3),  # the world angular velocity
    ("fluid", 6),  # the environment's air velocity, then water minus air velocity
    ("own_water", 3),  # with a wake or orbital velocities: the env's own water minus air
    ("source", NSRC),  # with a wake: the wake source (wake.source_row)
    ("height", 1),  # the body's z minus the surface height under the current sample
    ("sample_x", 1),  # with swell: the current sample's world x
    ("sample_y", 1),  # and y
    ("sample_z", 1),  # with orbital velocities: its depth below the moving surface (<= 0)
    ("phase", MAX_WAVES),  # with swell: each wave's time phase at the step's start
    # a recording (sample_forces, sample_flows): the current sample's rows (kernels.R_SENSE),
    # copied out after its loop, so that the loop writes only rows of the scratch
    ("record", 13),
    ("body", NBODY),  # the environment's body constants (BODY_FIELDS)
    ("memory", NMEMORY),  # a carrying integrator's memory (MEMORY_FIELDS), loaded per call
    ("stale", 1),  # 1 where the state changed outside the integrator since its last step
    ("iterations", 1),  # implicit_midpoint: the most iterations a step of this call took
    ("change", 2),  # implicit_midpoint: the iterate's largest changes, two and one back
)
_ROW, ROWS = rows(SCRATCH_FIELDS)
STATE, START, RK_SUM, DERIV, ROT, OMEGA = (
    _ROW[n] for n in ("state", "start", "rk_sum", "deriv", "rot", "omega")
)
FLUID, OWN_WATER, SOURCE, HEIGHT = (_ROW[n] for n in ("fluid", "own_water", "source", "height"))
SAMPLE_X, SAMPLE_Y, PHASE, BODY = (_ROW[n] for n in ("sample_x", "sample_y", "phase", "body"))
SAMPLE_Z = _ROW["sample_z"]
MEMORY, STALE, ITERATIONS, CHANGE = (_ROW[n] for n in ("memory", "stale", "iterations", "change"))
RECORD, RECORD_ROWS = _ROW["record"], dict(SCRATCH_FIELDS)["record"]
END, CARRY = MEMORY + _MEMORY["end"], MEMORY + _MEMORY["carry"]
