"""The ground: the user's :class:`Ground` (a plane or a height field) and its height and normal
under a point, for the narrow phase and the scenes."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numba import njit

from .. import checks as CK
from ..forces import ONE, ZERO
from ..jit import INLINE as _INLINE
from ..jit import JIT as _JIT
from .tables import (
    C_GE,
    C_GINV,
    C_GMU,
    C_GROUND,
    C_GTOP,
    C_GX0,
    C_GY0,
    C_GZ,
    GROUND_FIELD,
    GROUND_PLANE,
    NCPRM,
)

# --------------------------------------------------------------------------------------------
# the ground


@dataclass(frozen=True)
class Ground:
    """A solid ground under the bodies: a plane at ``height_m``, or with ``heights_m`` a
    height field (terrain) on top of it.

    Args:
        height_m: the plane's height (m), or the field's base.
        heights_m: optional grid of heights (m) ``[ny, nx]`` (both >= 2) added to
            ``height_m``: ``heights_m[j][k]`` at ``x = origin_m[0] + k * spacing_m``,
            ``y = origin_m[1] + j * spacing_m``; bilinear between the nodes (the normal from
            its gradient), and flat beyond the edges (the edge's height continues).
        spacing_m: the grid's spacing (> 0).
        origin_m: the (x, y) of ``heights_m[0][0]``.
        restitution: the ground's restitution in [0, 1] (a contact takes the geometric mean
            with the craft's).
        friction: the ground's Coulomb friction coefficient (>= 0), combined the same way.

    Examples:
        >>> ramp = Ground(heights_m=[[0.0, 1.0], [0.0, 1.0]], spacing_m=2.0)
        >>> ramp.height(np.array([1.0, 5.0]), np.array([0.5, 0.5])).tolist()
        [0.5, 1.0]
    """

    height_m: float = 0.0
    heights_m: Any = None
    spacing_m: float = 1.0
    origin_m: tuple[float, float] = (0.0, 0.0)
    restitution: float = 0.5
    friction: float = 0.5
    _field: np.ndarray = field(default=None, repr=False, compare=False)  # type: ignore[assignment]

    def __post_init__(self) -> None:
        for key, bounds in (
            ("height_m", {}),
            ("restitution", {"ge": 0.0, "le": 1.0}),
            ("friction", {"ge": 0.0}),
            ("spacing_m", {"gt": 0.0}),
        ):  # stored as floats, whatever number type was given
            object.__setattr__(self, key, CK.number("Ground", key, getattr(self, key), **bounds))
        object.__setattr__(self, "origin_m", CK.vector("Ground", "origin_m", self.origin_m, 2))
        if self.heights_m is None:
            grid = np.zeros((1, 1))
        else:
            grid = CK.array("Ground", "heights_m", self.heights_m).copy()
            if grid.ndim != 2 or min(grid.shape) < 2:
                raise ValueError(
                    f"Ground: heights_m must be a grid [ny, nx] with ny, nx >= 2, got shape "
                    f"{grid.shape}"
                )
            object.__setattr__(self, "heights_m", tuple(map(tuple, grid.tolist())))
        grid.setflags(write=False)
        object.__setattr__(self, "_field", grid)

    @property
    def kind(self) -> int:
        return GROUND_PLANE if self.heights_m is None else GROUND_FIELD

    def height(self, x, y) -> np.ndarray:
        """The ground's height (m) at horizontal points (x, y): float64 arrays, broadcast."""
        return self._sample(x, y)[0]

    def normal(self, x, y) -> np.ndarray:
        """The ground's unit upward normal ``[..., 3]`` at (x, y)."""
        return np.moveaxis(self._sample(x, y)[1:], 0, -1)

    def _sample(self, x, y) -> np.ndarray:
        xs, ys = np.broadcast_arrays(np.asarray(x, np.float64), np.asarray(y, np.float64))
        out = np.empty((4, xs.size))
        ground_points(
            np.ascontiguousarray(xs).ravel(), np.ascontiguousarray(ys).ravel(), self.params(),
            self._field, out,
        )  # fmt: skip
        return out.reshape((4, *xs.shape))

    def params(self, dtype=np.float64) -> np.ndarray:
        """The ground's slots of the contact parameters (the rest zero)."""
        p = np.zeros(NCPRM)
        p[C_GROUND] = self.kind
        p[C_GZ] = self.height_m
        p[C_GX0], p[C_GY0] = self.origin_m
        p[C_GINV] = 1.0 / self.spacing_m
        p[C_GE] = self.restitution
        p[C_GMU] = self.friction
        p[C_GTOP] = self.height_m + (self._field.max() if self.heights_m is not None else 0.0)
        return p.astype(dtype)

    def field_table(self, dtype=np.float64) -> np.ndarray:
        """The height grid as the kernels read it ([1, 1] zeros for a plane)."""
        return np.ascontiguousarray(self._field, dtype=dtype)


@njit(**_INLINE)
def ground_at(x, y, cprm, grid):
    """Height and unit upward normal ``(h, nx, ny, nz)`` of the ground under (x, y)."""
    h = cprm[C_GZ]
    if cprm[C_GROUND] != GROUND_FIELD:
        return h, ZERO * h, ZERO * h, ONE + ZERO * h
    inv = cprm[C_GINV]
    ny, nx = grid.shape
    fx = (x - cprm[C_GX0]) * inv
    fy = (y - cprm[C_GY0]) * inv
    # flat beyond the edges: the coordinate clamped, and no slope across the clamped axis
    inx = ONE if ZERO <= fx <= nx - 1 else ZERO
    iny = ONE if ZERO <= fy <= ny - 1 else ZERO
    fx = min(max(fx, ZERO), nx - 1)
    fy = min(max(fy, ZERO), ny - 1)
    k = min(int(fx), nx - 2)
    j = min(int(fy), ny - 2)
    tx, ty = fx - k, fy - j
    h00, h01 = grid[j, k], grid[j, k + 1]
    h10, h11 = grid[j + 1, k], grid[j + 1, k + 1]
    h += (h00 * (ONE - tx) + h01 * tx) * (ONE - ty) + (h10 * (ONE - tx) + h11 * tx) * ty
    gx = ((h01 - h00) * (ONE - ty) + (h11 - h10) * ty) * inv * inx
    gy = ((h10 - h00) * (ONE - tx) + (h11 - h01) * tx) * inv * iny
    s = ONE / math.sqrt(ONE + gx * gx + gy * gy)
    return h, -gx * s, -gy * s, s


@njit(**_JIT)
def ground_points(x, y, cprm, grid, out):
    """``out[4, N]``: height and normal of the ground at N points (the kernel's formula)."""
    for i in range(x.shape[0]):
        h, nx, ny, nz = ground_at(x[i], y[i], cprm, grid)
        out[0, i], out[1, i], out[2, i], out[3, i] = h, nx, ny, nz
