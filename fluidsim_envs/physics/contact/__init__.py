"""Contact: bodies against the ground and against each other, built on the seed's idea.

The package by concern: ``tables`` (the layouts and packing), ``ground`` (the user's
:class:`Ground`), ``bodies`` (a body's state in the step kernel's scratch), ``narrow`` (each
touching pair's patch), ``solver`` (impulses, passes, the energy bound; :func:`collide`).

The seed article carries a body as a tetrahedron of four Verlet particles
(``reference/tetra.py``). A contact pushes the penetrating point out along the contact
normal; spread over the particles with the point's barycentric weights, the push deforms
the tetrahedron locally, and the shape is restored by the rigid motion that keeps the
particles' momentum and angular momentum; kinetic energy is then corrected so that contact
invents none.

Restoring the tetrahedron after a push is a linear map with a closed form: particle impulses
``beta_i J`` (weights summing to 1 that reproduce the point, ``sum beta_i r_i = r``) carry
momentum ``J`` and angular momentum ``r x J``, so the restored body moves exactly as under
an impulse ``J`` at the point (``tests/physics/test_contact.py`` checks it), and a push of
position restores to the same with position for velocity (the fit's turn to first order).
This module applies the closed form, which also serves flat bodies (a paper dart), whose
flat tetrahedron cannot hold points off its plane.

Where the seed's one pass of point pushes fell short of the tests (a ball's push sized by
the particles' effective mass is a sixth of what stops it; a box resting on four corners,
pushed corner by corner, tips and walks; stacks sink), this departs from it, in the way
rigid-body engines do:

- Each touching pair (a body and the ground, or two bodies) is one contact over its patch:
  the depth-weighted mean of its touching points (box corners under the ground; a sphere's
  nearest point; for two boxes, the incident face clipped to the reference face), their
  spread in the contact plane (an ellipse: a face, an edge's segment, or a point), and the
  deepest depth. Points within a small margin above the surface (gravity's fall in two
  steps) count, so that a face resting tilted by a hair is still a face.
- ``_open``: an impact (approaching faster than gravity's gain in two steps) is pushed out
  along the normal by its depth, mass-weighted between two bodies (the seed's split), and
  aims to leave at ``-e`` times its approach; a resting contact aims at no approach.
- ``_pass``, ``C_PASSES`` times over all contacts (projected Gauss-Seidel, warm-started from
  the last step's impulses): the patch's six impulses (push, friction along two axes,
  torques about two axes, twist) solved together for the motion the contact aims at, then
  clamped: push >= 0, friction within ``mu`` times the push (Coulomb; the rest re-solved
  with the friction held), the center of pressure inside the patch, twist within the
  friction of a pressed disc.
- ``_close``: after an impact, the pair's kinetic energy may not exceed its value before,
  times 1 against the ground and ``PAIR_ENERGY_BOUND`` = 1.1 between two bodies (the seed's
  bound); beyond it, the motion about the pair's center of mass is scaled back.
- A resting body is then put back along its step's drift by the velocity its contacts
  took away (``x += dt dv``), instead of being pushed out along the normal: friction that
  holds it also holds its place (a push along a sloped normal walks it downhill).

Materials: a contact's restitution and friction are the geometric means of the two
materials' (the craft's ``restitution`` and ``friction``, and the :class:`Ground`'s), so a
pair of like materials keeps its own values. Not modelled: edge-across-edge box contacts,
continuous collision (a body faster than its size per step can pass through a thin one).

Under every integrator: a resting body's drift is undone by the integrator's own share of
it (``kernels.DRIFT_SHARE``), and an impact against the ground leaves with the speed the
body met the surface with, found from the integrator's own free-flight energy (``_open``),
so that boxes rest and stack, and a ball of restitution 1 keeps its bounce height, whatever
the integrator and dt (``docs/study.md``, Contact).
"""

from __future__ import annotations

from .ground import (
    Ground,
    ground_at,
    ground_points,
)
from .solver import (
    NW,
    NWARM,
    W_A,
    W_B,
    W_E1,
    W_E2,
    W_F1,
    W_F2,
    W_GOAL,
    W_IMPACT,
    W_J,
    W_KE0,
    W_L1,
    W_L2,
    W_MU,
    W_N,
    W_ON,
    W_P,
    W_REST,
    W_SEEN,
    W_T1,
    W_T2,
    W_TW,
    W_V0,
    W_W0,
    WARM_FACTOR,
    collide,
    may_touch,
    num_pairs,
)
from .tables import (
    BOX,
    C_DT,
    C_G,
    C_GE,
    C_GINV,
    C_GMU,
    C_GROUND,
    C_GTOP,
    C_GX0,
    C_GY0,
    C_GZ,
    C_MARGIN,
    C_ON,
    C_PAIR_BOUND,
    C_PASSES,
    C_REST_SPEED,
    C_UNDRIFT,
    CB_FRICTION,
    CB_REACH,
    CB_RESTITUTION,
    GROUND_FIELD,
    GROUND_NONE,
    GROUND_PLANE,
    NCBODY,
    NCPRM,
    NSHAPE,
    PAIR_ENERGY_BOUND,
    SH_CENTER,
    SH_KIND,
    SH_REACH,
    SH_SIZE,
    SPHERE,
    TWO_THIRDS,
    material_row,
    params,
    shape_rows,
)

__all__ = [
    "BOX",
    "CB_FRICTION",
    "CB_REACH",
    "CB_RESTITUTION",
    "C_DT",
    "C_G",
    "C_GE",
    "C_GINV",
    "C_GMU",
    "C_GROUND",
    "C_GTOP",
    "C_GX0",
    "C_GY0",
    "C_GZ",
    "C_MARGIN",
    "C_ON",
    "C_PAIR_BOUND",
    "C_PASSES",
    "C_REST_SPEED",
    "C_UNDRIFT",
    "GROUND_FIELD",
    "GROUND_NONE",
    "GROUND_PLANE",
    "Ground",
    "NCBODY",
    "NCPRM",
    "NSHAPE",
    "NW",
    "NWARM",
    "PAIR_ENERGY_BOUND",
    "SH_CENTER",
    "SH_KIND",
    "SH_REACH",
    "SH_SIZE",
    "SPHERE",
    "TWO_THIRDS",
    "WARM_FACTOR",
    "W_A",
    "W_B",
    "W_E1",
    "W_E2",
    "W_F1",
    "W_F2",
    "W_GOAL",
    "W_IMPACT",
    "W_J",
    "W_KE0",
    "W_L1",
    "W_L2",
    "W_MU",
    "W_N",
    "W_ON",
    "W_P",
    "W_REST",
    "W_SEEN",
    "W_T1",
    "W_T2",
    "W_TW",
    "W_V0",
    "W_W0",
    "collide",
    "ground_at",
    "ground_points",
    "material_row",
    "may_touch",
    "num_pairs",
    "params",
    "shape_rows",
]
