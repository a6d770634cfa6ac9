"""A rigid body as four point masses: the tetrahedron the seed article carries bodies as.

Four particles reproduce a body's mass, center of mass and inertia tensor exactly when their
second moment equals the body's. For point masses ``m_i`` at ``r_i`` (from the center of
mass) the second moment is ``S = sum m_i r_i r_i^T`` and the inertia tensor is
``I = tr(S) 1 - S``, so the body's ``S = tr(I)/2 1 - I``. Its eigenvalues are
``(I_j + I_k - I_i) / 2``: non-negative exactly when the principal moments satisfy the
triangle inequality, which every real mass distribution does. Equal masses ``m/4`` on the
vertices ``v_i`` of a regular tetrahedron of circumradius 1 have ``sum v_i = 0`` and
``sum v_i v_i^T = 4/3 1``; mapping them by ``A`` with ``A A^T = 3 S / m`` (the symmetric
square root) gives ``sum (m/4) A v_i v_i^T A^T = S``: the body's inertia, to rounding.

Particle velocities ``v + w x r_i`` carry the body's momentum ``m v`` (the particles are
centered) and angular momentum ``sum m_i r_i x (w x r_i) = I w`` exactly.

This module is the matching and the conversions, in NumPy; the Verlet integration of the
particles, their contacts and the switching to a rigid integrator build on it.
"""

from __future__ import annotations

import math

import numpy as np

# a regular tetrahedron centered at the origin, circumradius 1: sum v = 0, sum v v^T = 4/3 I
_S = 1.0 / math.sqrt(3.0)
VERTICES = np.array(
    [[_S, _S, _S], [_S, -_S, -_S], [-_S, _S, -_S], [-_S, -_S, _S]], dtype=np.float64
)


def second_moment(inertia_tensor) -> np.ndarray:
    """The second moment ``S = tr(I)/2 1 - I`` of the mass distribution with inertia tensor
    I about its center of mass (both 3x3, kg m^2)."""
    inertia = np.asarray(inertia_tensor, dtype=np.float64)
    return 0.5 * np.trace(inertia) * np.eye(3) - inertia


def match_inertia(mass_kg: float, inertia_tensor) -> tuple[np.ndarray, np.ndarray]:
    """Four particles with the body's mass, center of mass and inertia tensor.

    Args:
        mass_kg: the body's mass (> 0).
        inertia_tensor: its inertia tensor about the center of mass, body frame: a symmetric
            3x3 (full tensors allowed) or the 3 principal moments.

    Returns:
        ``(positions [4, 3]`` relative to the center of mass, body frame, ``masses [4])``:
        ``sum m_i = mass``, ``sum m_i r_i = 0`` and ``sum m_i (|r_i|^2 1 - r_i r_i^T)``
        equals the tensor to rounding.

    Raises:
        ValueError: a mass that is not positive, a tensor that is not symmetric or not
        positive definite, or principal moments that break the triangle inequality
        (I1 + I2 >= I3): no mass distribution has them.

    Examples:
        >>> pos, m = match_inertia(2.0, (1.0, 2.0, 2.5))
        >>> m.tolist()
        [0.5, 0.5, 0.5, 0.5]
        >>> inertia = sum(mi * (r @ r * np.eye(3) - np.outer(r, r)) for mi, r in zip(m, pos))
        >>> np.allclose(inertia, np.diag([1.0, 2.0, 2.5]), rtol=0, atol=1e-14)
        True
    """
    if not (isinstance(mass_kg, (int, float, np.floating)) and math.isfinite(mass_kg)):
        raise ValueError(f"match_inertia: mass_kg must be a finite number, got {mass_kg!r}")
    if mass_kg <= 0.0:
        raise ValueError(f"match_inertia: mass_kg must be > 0, got {mass_kg!r}")
    inertia = np.asarray(inertia_tensor, dtype=np.float64)
    if inertia.shape == (3,):
        inertia = np.diag(inertia)
    if inertia.shape != (3, 3) or not np.all(np.isfinite(inertia)):
        raise ValueError(
            "match_inertia: inertia_tensor must be 3 principal moments or a finite 3x3 "
            f"tensor, got {inertia_tensor!r}"
        )
    scale = np.abs(inertia).max()
    if not np.allclose(inertia, inertia.T, rtol=1e-12, atol=1e-12 * scale):
        raise ValueError(f"match_inertia: inertia_tensor must be symmetric, got {inertia.tolist()}")
    inertia = 0.5 * (inertia + inertia.T)
    moments, axes = np.linalg.eigh(inertia)
    if moments[0] <= 0.0:
        raise ValueError(
            f"match_inertia: inertia_tensor must be positive definite; its principal moments "
            f"are {moments.tolist()}"
        )
    # the second moment's eigenvalues, (I_j + I_k - I_i) / 2, in the same axes
    s = 0.5 * moments.sum() - moments
    if s.min() < -1e-12 * moments.max():
        i = int(np.argmin(s))
        j, k = (n for n in range(3) if n != i)
        raise ValueError(
            f"match_inertia: principal moments {moments.tolist()} break the triangle "
            f"inequality ({moments[j]:.6g} + {moments[k]:.6g} < {moments[i]:.6g}): no mass "
            "distribution has them"
        )
    s = np.maximum(s, 0.0)  # a flat body (equality) gives a flat tetrahedron
    root = (axes * np.sqrt(3.0 * s / mass_kg)) @ axes.T  # symmetric, A A^T = 3 S / m
    positions = VERTICES @ root.T
    return positions, np.full(4, 0.25 * mass_kg)


def particle_velocities(positions, lin_vel, ang_vel) -> np.ndarray:
    """Velocities [4, 3] of the particles at ``positions`` (relative to the center of mass,
    in the frame of the velocities) of a body moving at ``lin_vel`` and spinning at
    ``ang_vel``: ``v + w x r_i``."""
    r = np.asarray(positions, dtype=np.float64)
    return np.asarray(lin_vel, dtype=np.float64) + np.cross(np.asarray(ang_vel, float), r)


def momenta(masses, positions, velocities) -> tuple[np.ndarray, np.ndarray]:
    """Linear momentum (kg m/s) and angular momentum about the particles' center of mass
    (kg m^2/s) of point masses at ``positions`` moving at ``velocities`` ([4, 3] each)."""
    m = np.asarray(masses, dtype=np.float64)
    r = np.asarray(positions, dtype=np.float64)
    v = np.asarray(velocities, dtype=np.float64)
    center = (m[:, None] * r).sum(axis=0) / m.sum()
    p = (m[:, None] * v).sum(axis=0)
    v_center = p / m.sum()
    angular = (m[:, None] * np.cross(r - center, v - v_center)).sum(axis=0)
    return p, angular
