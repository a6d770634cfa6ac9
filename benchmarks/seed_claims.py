"""The seed article's claims about integrators, each against the studies' CSVs.

``markdown()`` is docs/seed_map.md's table between the ``seed-claims`` markers
(``python -m benchmarks.report`` writes it): each claim, the numbers that test it and the
verdict those numbers give, read from

- ``docs/study_accuracy.csv`` and ``docs/study_cost.csv`` (``python -m benchmarks.study_accuracy``):
  errors of each integrator over the dt sweep of each problem, cost per body-step;
- ``docs/study_stability.csv``, ``docs/study_stability_modes.csv``
  (``python -m benchmarks.study_stability``): the largest bounded dt, explicit Euler's energy;
- ``docs/env_stability.csv`` (``python -m benchmarks.env_stability``): each env's step limit;
- ``docs/study_hairer.csv`` (``python -m benchmarks.study_hairer``): the Kepler orbit's errors.

The verdicts are computed, not written: a claim is *held* where every number agrees with it,
*refuted* where none does, and *held only for* the cases that do otherwise.
"""

from __future__ import annotations

import math

from .common import DOCS, read_csv

CRAFTS = {"paper_airplane": 1 / 240, "speedboat": 1 / 200, "uuv": 1 / 50}  # nominal dt (s)


def _rows(name: str) -> list[dict]:
    return read_csv(DOCS / name)[1]


def _error(acc, problem, method, dt, metric="pos_err_m") -> float:
    """The float64 error of ``method`` on ``problem`` at ``dt`` (relative match: the CSV keeps
    6 digits)."""
    for r in acc:
        if (r["problem"], r["integrator"], r["dtype"]) == (problem, method, "float64") and (
            abs(float(r["dt_s"]) / dt - 1.0) < 1e-5
        ):
            return float(r[metric])
    raise KeyError(f"study_accuracy.csv has no {problem} {method} at dt {dt}")


def _verdict(ok: dict[str, bool]) -> str:
    good = [k for k, v in ok.items() if v]
    if len(good) == len(ok):
        return "**held**"
    if not good:
        return "**refuted**"
    return f"**held only for** {', '.join(good)}"


def _ratios(acc, better, worse, dt_better, dt_worse) -> dict[str, float]:
    """``worse``'s position error over ``better``'s on each craft (``better`` at its nominal dt
    times ``dt_better``, ``worse`` times ``dt_worse``)."""
    out = {}
    for craft, dt in CRAFTS.items():
        b = _error(acc, craft, better, dt * dt_better)
        w = _error(acc, craft, worse, dt * dt_worse)
        out[craft] = w / b if b > 0 else math.inf
    return out


def _show(ratios: dict[str, float]) -> str:
    return ", ".join(f"{craft} {r:.3g}x" for craft, r in ratios.items())


def claims() -> list[tuple[str, str, str]]:
    """(claim, what the CSVs say, verdict) for each claim the CSVs can test."""
    acc = _rows("study_accuracy.csv")
    cost = {(r["problem"], r["integrator"], r["dtype"]): float(r["ns_per_body_step"])
            for r in _rows("study_cost.csv")}  # fmt: skip
    stab = {(r["problem"], r["integrator"], r["dtype"]): float(r["dt_bounded_s"])
            for r in _rows("study_stability.csv")}  # fmt: skip
    env = {(r["env"], r["integrator"]): float(r["dt_limit_s"]) for r in _rows("env_stability.csv")}
    hairer = {(r["integrator"], r["quantity"]): r for r in _rows("study_hairer.csv")}
    modes = _rows("study_stability_modes.csv")
    out = []

    # explicit Euler against NSV
    c_ee, c_se = (
        cost["paper_airplane", m, "float64"] for m in ("explicit_euler", "symplectic_euler")
    )
    s_ee, s_se = (stab["spring", m, "float64"] for m in ("explicit_euler", "symplectic_euler"))
    e_ee, e_se = (_error(acc, "spring", m, 1 / 128, "energy_err")
                  for m in ("explicit_euler", "symplectic_euler"))  # fmt: skip
    out.append(
        (
            "NSV (symplectic Euler) costs what explicit Euler does, with much greater stability "
            "and accuracy; there is no reason to use explicit Euler",
            f"cost on the dart {c_se:.0f} against {c_ee:.0f} ns per body-step; the spring's "
            f"largest bounded dt {s_se:.3g} against {s_ee:.3g} s; its energy error at dt = 1/128 s "
            f"{e_se:.2g} against {e_ee:.2g}",
            _verdict({"stability": s_se > s_ee, "accuracy": e_se < e_ee}),
        )
    )
    grow = [r for r in modes if r["chart"] == "euler_spring" and r["case"] == "explicit_euler"
            and r["quantity"] == "energy_ratio_end"]  # fmt: skip
    if grow:
        worst = max(float(r["value"]) for r in grow)
        out.append(
            (
                "Explicit Euler gains energy (Hairer's Figure 1.2)",
                f"on the buoyancy spring its energy grew up to {worst:.3g} times before the body "
                "left the water (docs/study_stability_euler_spring.png)",
                _verdict({"energy": worst > 1.0}),
            )
        )
    # the seed's velocity Verlet against NSV, on the crafts at their nominal dt
    vv = _ratios(acc, "velocity_verlet_cached", "symplectic_euler", 1, 1)
    out.append(
        (
            "The velocity Verlet variant (one evaluation per step) is even more accurate than NSV",
            f"NSV's position error over the variant's at each craft's nominal dt: {_show(vv)}",
            _verdict({k: r > 1.0 for k, r in vv.items()}),
        )
    )
    # RK2 and RK4 against the symplectic methods at the same cost
    rk = _ratios(acc, "rk2", "symplectic_euler", 2, 1)
    out.append(
        (
            "RK2 and RK4 are less accurate than the symplectic methods",
            "NSV's position error over rk2's at the same compute (rk2 at twice the dt): "
            + _show(rk),
            _verdict({k: r < 1.0 for k, r in rk.items()}),
        )
    )
    half = _ratios(acc, "rk2", "symplectic_euler", 1, 0.5)
    quarter = _ratios(acc, "rk4", "symplectic_euler", 1, 0.25)
    out.append(
        (
            "NSV at 1/2 and 1/4 of the step does about what RK2 and RK4 do",
            f"NSV at dt/2 over rk2 at dt: {_show(half)}; NSV at dt/4 over rk4 at dt: "
            f"{_show(quarter)} (position errors; within 2x counts as about the same)",
            _verdict({k: 0.5 <= half[k] <= 2.0 and 0.5 <= quarter[k] <= 2.0 for k in CRAFTS}),
        )
    )
    # the implicit midpoint against symplectic Euler on the Kepler orbit
    im, se = hairer["implicit_midpoint", "energy"], hairer["symplectic_euler", "energy"]
    img, seg = hairer["implicit_midpoint", "global"], hairer["symplectic_euler", "global"]
    out.append((
        "The implicit midpoint drifts much more than symplectic Euler on the Kepler orbit",
        f"at 32-63 orbits (h = 0.002): energy error {float(im['error_32_orbits']):.2g} against "
        f"{float(se['error_32_orbits']):.2g}, global error {float(img['error_32_orbits']):.2g} "
        f"against {float(seg['error_32_orbits']):.2g}",
        _verdict({"energy": float(im["error_32_orbits"]) > float(se["error_32_orbits"]),
                  "global": float(img["error_32_orbits"]) > float(seg["error_32_orbits"])}),
    ))  # fmt: skip
    # NSV's stability at dt = 1/30 s in the envs
    limits = {
        e.split("/")[1]: env[e, "symplectic_euler"] for e, m in env if m == "symplectic_euler"
    }
    out.append(
        (
            "Symplectic Euler is extremely stable, even at dt = 1/30 s",
            "each env's measured step limit under its fuzz: "
            + ", ".join(f"{e} {v:.3g} s" for e, v in limits.items()),
            _verdict({e: v >= 1 / 30 for e, v in limits.items()}),
        )
    )
    return out


def markdown() -> str:
    try:
        rows = claims()
    except (FileNotFoundError, KeyError) as err:
        return f"(the studies' CSVs are not complete yet: {err})"
    lines = ["| the article says | the studies measured | verdict |", "|---|---|---|"]
    lines += [f"| {a} | {b} | {c} |" for a, b, c in rows]
    lines.append("")
    lines.append(
        "Written by `python -m benchmarks.report` from docs/study_accuracy.csv, study_cost.csv, "
        "study_stability.csv, study_stability_modes.csv, env_stability.csv and "
        "study_hairer.csv (`benchmarks/seed_claims.py`)."
    )
    return "\n".join(lines)
