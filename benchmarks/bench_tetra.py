"""Where the Verlet tetrahedron degrades: the torque-free intermediate-axis body (I = 1, 2, 3,
spun about the middle axis with a 1% wobble) for 2 s, at two time steps and a range of spin
rates, integrated as a tetrahedron (no switch), as a tetrahedron switching to the rigid turn
above ``World.tetra_rigid_spin_rad`` (0.05 rad per step, the default), and rigidly (symplectic
Euler). For each: the largest relative energy error and the relative error of the body-frame
angular momentum at the end against Euler's equations solved at tight tolerance (scipy), the
tumbling's phase. World angular momentum is the state: all keep it to rounding.

Writes ``docs/tetra_spin.csv`` and ``docs/tetra_spin.png`` (error against |w| dt, log-log).

    python -m benchmarks.bench_tetra
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from benchmarks.common import DOCS, write_csv
from fluidsim_envs.physics import Craft, Simulator, World
from fluidsim_envs.physics.kernels import quat_matrices

INERTIA = np.array([1.0, 2.0, 3.0])
BODY = Craft(name="racket", mass_kg=1.0, inertia_kgm2=tuple(INERTIA))
SECONDS = 2.0
SPINS = (0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0)
STEPS = (1 / 100, 1 / 400)
METHODS = {
    "tetrahedron": ("verlet_tetra", math.inf),
    "tetrahedron, switched": ("verlet_tetra", 0.05),
    "rigid (symplectic Euler)": ("symplectic_euler", 0.05),
}


def reference(w0: np.ndarray) -> np.ndarray:
    """Body-frame angular momentum after SECONDS, from Euler's equations."""

    def rhs(_, w):
        i1, i2, i3 = INERTIA
        return [
            (i2 - i3) / i1 * w[1] * w[2],
            (i3 - i1) / i2 * w[2] * w[0],
            (i1 - i2) / i3 * w[0] * w[1],
        ]

    sol = solve_ivp(rhs, (0, SECONDS), w0, method="DOP853", rtol=1e-12, atol=1e-12)
    return INERTIA * sol.y[:, -1]


def run(integrator: str, switch: float, w0: np.ndarray, dt: float) -> tuple[float, float]:
    sim = Simulator(
        BODY,
        World(gravity_mps2=0.0, tetra_rigid_spin_rad=switch),
        num_envs=1,
        dt=dt,
        integrator=integrator,
    )
    sim.reset(ang_vel=w0)  # identity attitude: body frame = world frame at t = 0
    e0 = sim.kinetic_energy()[0, 0]
    worst = 0.0
    for _ in range(int(round(SECONDS / dt))):
        sim.step()
        worst = max(worst, abs(sim.kinetic_energy()[0, 0] / e0 - 1.0))
    rot = quat_matrices(np.ascontiguousarray(sim.quat[0]))[0]
    body_l = rot.T @ sim.angular_momentum()[0, 0]
    ref = reference(w0)
    return worst, float(np.linalg.norm(body_l - ref) / np.linalg.norm(ref))


def main() -> None:
    rows = []
    for dt in STEPS:
        for spin in SPINS:
            w0 = np.array([0.01 * spin, spin, 0.01 * spin])
            for label, (integrator, switch) in METHODS.items():
                de, dl = run(integrator, switch, w0, dt)
                rows.append((label, dt, spin, spin * dt, de, dl))
                print(f"dt {dt:.4f} |w| dt {spin * dt:7.4f} {label:26s} dE {de:.2e} dL {dl:.2e}")
    docs = DOCS
    write_csv(
        docs / "tetra_spin.csv",
        ("method", "dt_s", "spin_rad_s", "spin_per_step_rad", "energy_err", "l_err"),
        [(r[0], f"{r[1]:.6g}", r[2], f"{r[3]:.6g}", f"{r[4]:.4e}", f"{r[5]:.4e}") for r in rows],
    )

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    styles = {"tetrahedron": "o-", "tetrahedron, switched": "s--", "rigid (symplectic Euler)": "^:"}
    for ax, col, name in (
        (axes[0], 4, "max |energy error| / E"),
        (axes[1], 5, "body L error / |L|"),
    ):
        for label in METHODS:
            for dt in STEPS:
                pts = [(r[3], max(r[col], 1e-16)) for r in rows if r[0] == label and r[1] == dt]
                x, y = zip(*pts, strict=True)
                ax.loglog(x, y, styles[label], label=f"{label}, dt = 1/{round(1 / dt)} s")
        ax.axvline(0.05, color="gray", lw=0.8)
        ax.set_xlabel("|w| dt (rad per step)")
        ax.set_ylabel(name)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle("Intermediate-axis spin, 2 s: the tetrahedron degrades with the turn per step")
    fig.savefig(docs / "tetra_spin.png", dpi=110)
    print(f"wrote {docs / 'tetra_spin.csv'} and tetra_spin.png")


if __name__ == "__main__":
    main()
