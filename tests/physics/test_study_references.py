"""The accuracy study's exact torque-free solution against Euler's equations integrated by scipy.

``benchmarks/study_accuracy.py`` scores the integrators against ``torque_free_exact``: the
body-frame angular velocity of a free rigid body by Jacobi elliptic functions (Landau &
Lifshitz, Mechanics, section 37). Here it is checked against scipy's ``solve_ivp`` (DOP853 at
tight tolerance) for spins about the major and the minor axis, both senses, and inertia given
in any order.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from benchmarks import study_accuracy as study


def euler_equations(inertia, w0, t):
    i1, i2, i3 = inertia

    def rhs(_, w):
        return [
            (i2 - i3) / i1 * w[1] * w[2],
            (i3 - i1) / i2 * w[2] * w[0],
            (i1 - i2) / i3 * w[0] * w[1],
        ]

    sol = solve_ivp(rhs, (0.0, t[-1]), w0, method="DOP853", rtol=1e-13, atol=1e-13, t_eval=t)
    return sol.y.T


@pytest.mark.parametrize(
    "inertia, w0",
    [
        ((1.0, 2.0, 3.0), (1.0, 1.5, 1.2)),  # the study's case: major axis, m = 0.49
        ((1.0, 2.0, 3.0), (-1.0, -1.5, -1.2)),  # the other sense
        ((1.0, 2.0, 3.0), (2.0, 0.5, -0.3)),  # about the minor axis
        ((3.0, 1.0, 2.0), (0.4, -2.0, 1.0)),  # inertia not sorted (an odd permutation)
        ((2.0, 3.0, 1.0), (0.3, -0.2, 1.5)),  # an even permutation
    ],
)
def test_torque_free_exact_matches_solve_ivp(inertia, w0):
    t = np.linspace(0.0, 20.0, 801)
    exact = study.torque_free_exact(inertia, w0, t)
    np.testing.assert_allclose(exact, euler_equations(inertia, w0, t), rtol=0, atol=1e-8)
    # and it keeps both invariants (2E and |L|^2) along the way
    inertia = np.asarray(inertia)
    w0 = np.asarray(w0)
    np.testing.assert_allclose((inertia * exact**2).sum(1), (inertia * w0**2).sum(), rtol=1e-12)
    np.testing.assert_allclose(
        ((inertia * exact) ** 2).sum(1), ((inertia * w0) ** 2).sum(), rtol=1e-12
    )


def test_torque_free_exact_is_a_proper_elliptic_motion():
    """The study's spin is far from both limits (a steady spin and the separatrix): its
    components swing through most of their range."""
    t = np.linspace(0.0, 10.0, 2001)
    w = study.torque_free_exact(study.TF_INERTIA, study.TF_W0, t)
    assert w[:, 0].min() < -0.9 and w[:, 0].max() > 0.9  # w1 = A1 cn: changes sign
    assert w[:, 1].min() < -1.0 and w[:, 1].max() > 1.0  # w2 = A2 sn: changes sign
    assert np.all(w[:, 2] > 0)  # w3 = A3 dn: keeps its sign


def test_torque_free_exact_rejects_degenerate_spins():
    with pytest.raises(ValueError, match="principal moments"):
        study.torque_free_exact((1.0, 1.0, 3.0), (1.0, 1.0, 1.0), [0.0, 1.0])
    with pytest.raises(ValueError, match="steady spin"):
        study.torque_free_exact((1.0, 2.0, 3.0), (0.0, 0.0, 2.0), [0.0, 1.0])
