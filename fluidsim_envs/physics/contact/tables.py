"""The contact tables' layouts (shapes, per-body materials, parameters) and how a craft and
a ground are packed into them."""

from __future__ import annotations

import numpy as np

TWO_THIRDS = np.float32(2.0 / 3.0)
PAIR_ENERGY_BOUND = 1.1  # the seed's: two bodies' kinetic energy may rise 10% before scaling

# shape table rows (field-major, one environment's [NSHAPE, n_shapes] of the [E, NSHAPE,
# n_shapes] table): kind, center (3, from the center of mass, body frame), size (3: a sphere's
# radius then zeros, or a box's half extents), reach (the center's distance plus the extent)
SPHERE, BOX = 0, 1
SH_KIND, SH_CENTER, SH_SIZE, SH_REACH = 0, 1, 4, 7
NSHAPE = 8
# per-body contact table (one environment's [B, NCBODY] of [E, B, NCBODY]): restitution,
# friction, reach (m) of all its shapes
CB_RESTITUTION, CB_FRICTION, CB_REACH = 0, 1, 2
NCBODY = 3
# contact parameters [NCPRM]
C_ON, C_GROUND, C_GZ, C_GX0, C_GY0, C_GINV = 0, 1, 2, 3, 4, 5
C_GE, C_GMU, C_REST_SPEED, C_UNDRIFT, C_PAIR_BOUND, C_PASSES, C_MARGIN = 6, 7, 8, 9, 10, 11, 12
C_GTOP = 13  # the ground's highest point: a body whose reach is clear above it touches nothing
C_G, C_DT = 14, 15  # gravity (m/s^2) and the time step: an impact's speed at the surface
NCPRM = 16
GROUND_NONE, GROUND_PLANE, GROUND_FIELD = 0, 1, 2


# --------------------------------------------------------------------------------------------
# packing


def shape_rows(craft) -> list[tuple]:
    """The rows of a craft's collision shapes (``SH_*`` columns), in the craft's order."""
    rows = []
    for s in craft.shapes:
        size = (s.radius_m, 0.0, 0.0) if s.kind == "sphere" else s.half_extents_m
        rows.append((SPHERE if s.kind == "sphere" else BOX, *s.center_m, *size, s.reach_m))
    return rows


def material_row(craft) -> tuple:
    """A craft's ``CB_*`` row: restitution, friction, the reach of all its shapes."""
    reach = max((s.reach_m for s in craft.shapes), default=0.0)
    return (craft.restitution, craft.friction, reach)


def params(crafts, ground, dt: float, gravity: float, passes: int, drift_share: float):
    """The contact parameters ``cprm[NCPRM]`` (float64; ``drift_share``: the integrator's
    ``integrators.Integrator.drift_share``) and the ground's grid (float64)."""
    prm = ground.params() if ground is not None else np.zeros(NCPRM)
    has_shapes = any(c.shapes for c in crafts)
    prm[C_ON] = 1.0 if has_shapes and (ground is not None or len(crafts) > 1) else 0.0
    # below this approach speed a contact is resting: no bounce (gravity's gain in 2 steps)
    prm[C_REST_SPEED] = 2.0 * gravity * dt
    prm[C_UNDRIFT] = drift_share * dt  # what a resting body's drift is undone by (collide)
    prm[C_G] = gravity
    prm[C_DT] = dt
    # points this close above a surface join a touching pair's contact (gravity's fall in 2
    # steps): the margin that keeps resting faces from rocking
    prm[C_MARGIN] = 2.0 * gravity * dt * dt
    prm[C_PAIR_BOUND] = PAIR_ENERGY_BOUND
    prm[C_PASSES] = passes
    grid = ground.field_table(np.float64) if ground is not None else np.zeros((1, 1))
    return prm, grid
