"""Hairer's table on the Kepler orbit: how each integrator's errors grow with t and shrink with dt.

The seed quotes the table of Hairer, Lubich and Wanner (Geometric Numerical Integration, 2nd
ed. 2006, I.2.3, the Kepler problem) for three methods: the error in the energy H, in the
angular momentum L and in the solution (global error) after time t, at step h:

    explicit Euler     H: O(t h)   L: O(t h)   global: O(t^2 h)
    symplectic Euler   H: O(h)     L: 0        global: O(t h)
    implicit midpoint  H: O(h^2)   L: 0        global: O(t h^2)

This study measures the same three errors for every shipped integrator on the same orbit (GM
= 1, eccentricity 0.6, from the pericentre (1 - e, 0) at speed sqrt((1 + e)/(1 - e)): energy
-1/2, angular momentum 0.8, period 2 pi; ``World(central_gravity_m3s2=1)``), one environment
in float64 through the real :class:`Simulator`, over ``ORBITS`` orbits at two steps h and
h / 2 (h = 0.002; explicit Euler and the accurate Euler, which lose the orbit within a few
orbits there, at h = 1e-4). Each error is
the largest over a window of orbits ``[2^k, 2^(k+1))`` (sampled every 0.05 time units: the
energy error peaks at each pericentre passage, which lasts about 0.5), so that an error that
oscillates within an orbit is not mistaken for one that grows:

- ``growth``: the slope of log(error) against log(t) over the windows from the 2nd orbit on
  where the error is still small (below 0.1; 0.5 for the global error, against an orbit of
  size 1): 0 bounded, 1 linear, 2 quadratic. An error at rounding level (below 1e-11
  throughout) is reported as ``rounding``: the method keeps that quantity exactly.
- ``order``: log2 of the error at h over the error at h / 2, in the window of orbits 32-63
  (or the last window both runs reached).

Writes ``docs/study_hairer.csv`` and ``docs/study_hairer.png`` (errors against time, one panel
per quantity, for h)::

    python -m benchmarks.study_hairer            # a few minutes on 2 cores
    python -m benchmarks.study_hairer --quick    # 64 orbits, into build/study_quick
"""

from __future__ import annotations

import math

import numpy as np

from benchmarks.common import arguments, describe, fmt, out_dir, write_csv
from fluidsim_envs.physics import INTEGRATORS, Craft, Simulator, World

E = 0.6  # eccentricity
ORBITS = 512
DTS = (0.002, 0.001)
# the methods that lose the orbit within a few orbits at DTS (their energy error grows like t h)
# are followed at steps small enough to keep it for a while
FINE_DTS = {"explicit_euler": (1e-4, 5e-5), "accurate_euler": (1e-4, 5e-5)}


def dts(method: str) -> tuple[float, float]:
    """The two steps h, h / 2 a method is followed at."""
    return FINE_DTS.get(method, DTS)


SAMPLE_S = 0.05  # time between samples: the pericentre passage lasts about 0.5
QUANTITIES = ("energy", "angular_momentum", "global")
SMALL = {"energy": 0.1, "angular_momentum": 0.1, "global": 0.5}
ROUNDING = 1e-11
ORDER_WINDOW = 5  # orbits [32, 64)
HAIRER = {  # (H, L, global): growth in t, order in h; None where the table says 0
    "explicit_euler": ("t h", "t h", "t^2 h"),
    "symplectic_euler": ("h", "0", "t h"),
    "implicit_midpoint": ("h^2", "0", "t h^2"),
}


def kepler_exact(t: float) -> np.ndarray:
    """Position at time t on the orbit (Kepler's equation E - e sin E = t by Newton)."""
    m = math.fmod(t, 2 * math.pi)
    ecc = m
    for _ in range(50):
        ecc -= (ecc - E * math.sin(ecc) - m) / (1 - E * math.cos(ecc))
    return np.array([math.cos(ecc) - E, math.sqrt(1 - E * E) * math.sin(ecc), 0.0])


def orbit(integrator: str, dt: float, orbits: int) -> dict[str, np.ndarray]:
    """The largest error of each quantity in each window of orbits [2^k, 2^(k+1)) (NaN once
    the orbit is lost: unbound, or the simulation flagged)."""
    planet = Craft(name="planet", mass_kg=1.0, inertia_kgm2=(1.0, 1.0, 1.0))
    world = World(gravity_mps2=0.0, central_gravity_m3s2=1.0)
    sim = Simulator(planet, world, dt=dt, integrator=integrator)
    sim.reset(pos=(1 - E, 0.0, 0.0), lin_vel=(0.0, math.sqrt((1 + E) / (1 - E)), 0.0))
    windows = int(math.log2(orbits)) + 1
    worst = {q: np.zeros(windows) for q in QUANTITIES}
    every = round(SAMPLE_S / dt)
    n = round(orbits * 2 * math.pi / dt / every)
    lost = False
    for k in range(1, n + 1):
        sim.step(steps=every)
        t = k * every * dt
        w = int(math.log2(max(t / (2 * math.pi), 1.0)))
        if w >= windows:
            break
        x, v = sim.pos[0, 0], sim.lin_vel[0, 0]
        energy = 0.5 * v @ v - 1.0 / math.sqrt(x @ x)
        errs = {
            "energy": abs(energy / -0.5 - 1.0),
            "angular_momentum": abs((x[0] * v[1] - x[1] * v[0]) / math.sqrt(1 - E * E) - 1.0),
            "global": float(np.linalg.norm(x - kepler_exact(t))),
        }
        lost = lost or energy >= 0.0 or bool(sim.diverged[0])
        for q in QUANTITIES:
            worst[q][w] = math.nan if lost else max(worst[q][w], errs[q])
        if lost:
            for q in QUANTITIES:
                worst[q][w:] = math.nan
            break
    return worst


def growth(errors: np.ndarray, quantity: str) -> str:
    """The slope of log error against log t over the windows from orbit 2 where the error is
    small (see the module docstring), or ``rounding``."""
    ok = np.isfinite(errors)
    if ok.any() and np.nanmax(errors) < ROUNDING:
        return "rounding"
    t = 2.0 ** (np.arange(errors.size) + 0.5)  # each window's middle orbit
    keep = ok & (np.arange(errors.size) >= 1) & (errors < SMALL[quantity]) & (errors > 0)
    if keep.sum() < 3:
        return "lost"
    return f"{np.polyfit(np.log(t[keep]), np.log(errors[keep]), 1)[0]:.2f}"


def order(coarse: np.ndarray, fine: np.ndarray) -> float:
    """log2(error at h / error at h/2) in the window of orbits 32-63, or the last both
    reached (NaN where either is at rounding level or lost)."""
    both = np.nonzero(np.isfinite(coarse) & np.isfinite(fine))[0]
    if both.size == 0:
        return math.nan
    w = min(ORDER_WINDOW, both[-1])
    if min(coarse[w], fine[w]) < ROUNDING:
        return math.nan
    return math.log2(coarse[w] / fine[w])


def chart(runs: dict, path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(16, 5.2), sharex=True)
    for ax, q in zip(axes, QUANTITIES, strict=True):
        for m in INTEGRATORS:
            h = dts(m)[0]
            err = runs[m, h][q]
            t = 2.0 ** (np.arange(err.size) + 0.5)
            style = "-" if m in HAIRER else "--"
            ax.loglog(t, np.maximum(err, 1e-17), style, marker=".", label=f"{m} (h = {h:g})")
        ax.set_title(f"{q.replace('_', ' ')} error")
        ax.set_xlabel("orbits (window middle)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("largest error in the window")
    axes[2].legend(fontsize=7, loc="lower right")
    fig.suptitle("Kepler orbit, e = 0.6: Hairer's table measured (solid: the table's methods)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    parser = arguments(__doc__, "64 orbits, into build/study_quick")
    args = parser.parse_args()
    machine = describe()
    out = out_dir(args.out, args.quick)
    orbits = 64 if args.quick else ORBITS
    runs = {}
    for m in INTEGRATORS:
        for dt in dts(m):
            runs[m, dt] = orbit(m, dt, orbits)
            print(m, dt, {q: growth(runs[m, dt][q], q) for q in QUANTITIES}, flush=True)
    rows = []
    for m in INTEGRATORS:
        claims = HAIRER.get(m, ("", "", ""))
        h, h2 = dts(m)
        for q, claim in zip(QUANTITIES, claims, strict=True):
            coarse, fine = runs[m, h][q], runs[m, h2][q]
            last = np.nonzero(np.isfinite(coarse))[0]
            rows.append(
                (
                    m,
                    fmt(h),
                    q,
                    claim,
                    growth(coarse, q),
                    fmt(order(coarse, fine)),
                    fmt(coarse[min(ORDER_WINDOW, last[-1])] if last.size else math.nan),
                    fmt(coarse[last[-1]] if last.size else math.nan),
                    2 ** int(last[-1]) if last.size else 0,
                )
            )
    header = (
        "integrator", "h", "quantity", "hairer", "growth", "order", "error_32_orbits",
        "error_last_window", "last_window_orbit",
    )  # fmt: skip
    path = write_csv(out / "study_hairer.csv", header, rows, machine)
    chart(runs, out / "study_hairer.png")
    print("wrote", path)


if __name__ == "__main__":
    main()


def markdown(path=None) -> str:
    """docs/study.md's table from the study's CSV (``benchmarks.report`` writes it): per
    integrator, each error's growth in t and order in h, beside Hairer's table."""
    from benchmarks.common import DOCS, read_csv

    path = DOCS / "study_hairer.csv" if path is None else path
    if not path.is_file():
        return "(no docs/study_hairer.csv yet: run python -m benchmarks.study_hairer)"
    _, rows = read_csv(path)
    by = {(r["integrator"], r["quantity"]): r for r in rows}
    names = {"energy": "H", "angular_momentum": "L", "global": "global"}

    def cell(r: dict) -> str:
        g, o = r["growth"], r["order"]
        grown = {"rounding": "exact (rounding)", "lost": "orbit lost"}.get(g, f"t^{g}")
        order = "" if o == "nan" or g == "lost" else f", h^{float(o):.1f}"
        return f"{grown}{order} ({float(r['error_32_orbits']):.2g})"

    head = " | ".join(f"{n} error" for n in names.values())
    lines = [
        f"| integrator | {head} | Hairer's table |",
        "|---|---|---|---|---|",
    ]
    for m in dict.fromkeys(r["integrator"] for r in rows):
        claim = ", ".join(
            f"{n}: {by[m, q]['hairer']}" for q, n in names.items() if by[m, q]["hairer"]
        )
        lines.append(f"| {m} | " + " | ".join(cell(by[m, q]) for q in names) + f" | {claim} |")
    lines.append("")
    lines.append(
        "Growth: the slope of log(error) against log(t) over windows of orbits where the error "
        "is still small (0 bounded, 1 linear, 2 quadratic); order: log2 of the error at h over "
        "h / 2 at 32-63 orbits; in brackets the error there; "
        f"h = {DTS[0]}, explicit and accurate Euler "
        f"{FINE_DTS['explicit_euler'][0]:g}. From docs/study_hairer.csv "
        "(`python -m benchmarks.study_hairer`)."
    )
    return "\n".join(lines)
