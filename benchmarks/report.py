"""The docs' tables of envs and results, written from the registry and the committed
evaluation CSVs.

    python -m benchmarks.report            # writes docs/envs.csv and the tables
    python -m benchmarks.report --check    # exit 1 if any is out of date (the tests run it)

One row per registered env (:data:`fluidsim_envs.scenes.SCENES`): its observation and action
sizes, control rate and horizon (from the env's default parameters), what success means (the
scene's ``success``, with its numbers), and the success rate and mean return, each with its
95% bootstrap interval, of the planner (oracle), the tuned pilot and trained PPO from
``docs/eval_<scene>_ppo.csv`` (what ``fluidsim-evaluate RUN --episodes 256`` wrote for the
shipped PPO config's run, every baseline beside it; blank where no such file exists). The
README's table sits between the two ``envs-table`` markers, and docs/training.md's table of
every policy in those CSVs between the ``ppo-results`` markers, and docs/environments.md's
table of every env parameter (its default and what it may be, from each parameter class's
``RANGES``: ``scenes/limits.py``) between the ``params-table`` markers, and docs/reliability.md's
fuzz and kill tables from docs/fuzz.csv and docs/kill_resume.csv between the ``fuzz-table``
and ``kill-table`` markers, and docs/environments.md's trim and phugoid of the paper dart from
docs/dart_glide.csv (``python -m benchmarks.dart_glide``) between the ``dart-glide`` markers,
and docs/study.md's fixed-point tables from docs/study_fixed.csv between the ``fixed-table``
markers (``benchmarks.study_fixed.markdown``), its cost table from docs/study_cost.csv
between the ``cost-table`` markers (``benchmarks.study_accuracy.cost_markdown``), and
Hairer's table from docs/study_hairer.csv
between the ``hairer-table`` markers (``benchmarks.study_hairer.markdown``), and
docs/seed_map.md's verdicts on the seed article's claims from the studies' CSVs between the
``seed-claims`` markers (``benchmarks.seed_claims``), and docs/training.md's split of PPO's
wall time from docs/bench_training.csv between the ``training-split`` markers
(``benchmarks.bench_training.markdown``), the grid of settings tried from
docs/bench_training_grid.csv between the ``training-grid`` markers
(``benchmarks.bench_training.grid_markdown``) and the wall-clock retune's scores from
docs/training_wallclock.csv between the ``training-wallclock`` markers
(``benchmarks.train_wallclock.markdown``); none is edited by hand.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from . import (
    bench_training,
    seed_claims,
    study_accuracy,
    study_fixed,
    study_hairer,
    train_wallclock,
)
from .common import DOCS, ROOT, read_csv, write_csv

CSV = DOCS / "envs.csv"
README = ROOT / "README.md"
TRAINING = DOCS / "training.md"
BEGIN = "<!-- envs-table: written by `python -m benchmarks.report` from docs/envs.csv -->"
END = "<!-- /envs-table -->"
RESULTS_BEGIN = (
    "<!-- ppo-results: written by `python -m benchmarks.report` from docs/eval_*_ppo.csv -->"
)
RESULTS_END = "<!-- /ppo-results -->"
SPLIT_BEGIN = (
    "<!-- training-split: written by `python -m benchmarks.report` from docs/bench_training.csv -->"
)
SPLIT_END = "<!-- /training-split -->"
GRID_BEGIN = (
    "<!-- training-grid: written by `python -m benchmarks.report` from "
    "docs/bench_training_grid.csv -->"
)
GRID_END = "<!-- /training-grid -->"
WALLCLOCK_BEGIN = (
    "<!-- training-wallclock: written by `python -m benchmarks.report` from "
    "docs/training_wallclock.csv -->"
)
WALLCLOCK_END = "<!-- /training-wallclock -->"
ENVIRONMENTS = DOCS / "environments.md"
PARAMS_BEGIN = (
    "<!-- params-table: written by `python -m benchmarks.report` from each scene's RANGES -->"
)
PARAMS_END = "<!-- /params-table -->"
RELIABILITY = DOCS / "reliability.md"
FUZZ_CSV = DOCS / "fuzz.csv"
FUZZ_BEGIN = "<!-- fuzz-table: written by `python -m benchmarks.report` from docs/fuzz.csv -->"
FUZZ_END = "<!-- /fuzz-table -->"
KILL_CSV = DOCS / "kill_resume.csv"
KILL_BEGIN = (
    "<!-- kill-table: written by `python -m benchmarks.report` from docs/kill_resume.csv -->"
)
KILL_END = "<!-- /kill-table -->"
STUDY = DOCS / "study.md"
FIXED_BEGIN = (
    "<!-- fixed-table: written by `python -m benchmarks.report` from docs/study_fixed.csv -->"
)
FIXED_END = "<!-- /fixed-table -->"
HAIRER_BEGIN = (
    "<!-- hairer-table: written by `python -m benchmarks.report` from docs/study_hairer.csv -->"
)
HAIRER_END = "<!-- /hairer-table -->"
COST_BEGIN = (
    "<!-- cost-table: written by `python -m benchmarks.report` from docs/study_cost.csv -->"
)
COST_END = "<!-- /cost-table -->"
CLAIMS_BEGIN = (
    "<!-- seed-claims: written by `python -m benchmarks.report` from docs/study_*.csv -->"
)
CLAIMS_END = "<!-- /seed-claims -->"
SEED_MAP = DOCS / "seed_map.md"
DART_BEGIN = (
    "<!-- dart-glide: written by `python -m benchmarks.report` from docs/dart_glide.csv -->"
)
DART_END = "<!-- /dart-glide -->"
# docs/dart_glide.csv's phugoid sources, as the table names them
DART_SOURCES = {
    "measured": "measured (speed peaks after a level launch 1 m/s below trim)",
    "linearized": "the craft's longitudinal equations linearized at trim, from its own forces",
    "glide_with_drag": "point mass with drag, in the glide: ζ = 3 sin γ / (2√2)",
    "etkin_reid": "Etkin & Reid with drag, level flight: ζ = C_D / (√2 C_L)",
    "lanchester": "Lanchester, drag-free: ζ = 0",
}
# the policies of an evaluation CSV (fluidsim-evaluate's rows) in the tables, by row name
POLICIES = ("trained PPO", "planner (oracle)", "tuned pilot", "hand-set pilot", "random")
# the README's table: (column title, row name, envs.csv key)
README_POLICIES = (
    ("planner (oracle)", "planner (oracle)", "planner"),
    ("tuned pilot", "tuned pilot", "pilot"),
    ("PPO (one seed)", "trained PPO", "ppo"),
)

COLUMNS = (
    "env_id", "summary", "observations", "actions", "action_names", "control_hz",
    "horizon_steps", "horizon_s", "success",
    *(f"{key}_{m}" for _, _, key in README_POLICIES
      for m in ("success", "success_lo", "success_hi", "return", "return_lo", "return_hi")),
    "evaluated_episodes",
)  # fmt: skip


def scene_slug(env_id: str) -> str:
    """``fluidsim/PaperAirplane-v0`` -> ``paper_airplane`` (the scene's package name)."""
    name = env_id.split("/")[1].rsplit("-v", 1)[0]
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


def _scores(env_id: str) -> dict[str, str]:
    """Each README policy's success rate and mean return, with their intervals, from the
    env's evaluation CSV."""
    path = DOCS / f"eval_{scene_slug(env_id)}_ppo.csv"
    if not path.is_file():
        return {}
    by = {r["policy"]: r for r in read_csv(path)[1]}
    out = {}
    for _, policy, key in README_POLICIES:
        if policy not in by:
            continue
        row = by[policy]
        for mine, theirs in (("success", "success_rate"), ("return", "return_mean")):
            for tail in ("", "_lo", "_hi"):
                out[f"{key}_{mine}{tail}"] = row.get(f"{theirs}{tail}", "")
        out["evaluated_episodes"] = row["episodes"]
    return out


def rows() -> list[dict[str, str]]:
    from fluidsim_envs.scenes import SCENES

    out = []
    for env_id, scene in SCENES.items():
        p = scene.params_cls()
        period_s = p.dt * p.substeps
        row = {
            "env_id": env_id,
            "summary": scene.summary,
            "observations": str(scene.vector_cls.obs_dim),
            "actions": str(len(scene.vector_cls.action_names)),
            "action_names": " ".join(scene.vector_cls.action_names),
            "control_hz": f"{1.0 / period_s:g}",
            "horizon_steps": str(p.max_episode_steps),
            "horizon_s": f"{p.max_episode_steps * period_s:g}",
            "success": scene.success_text(p),
        }
        out.append({c: {**row, **_scores(env_id)}.get(c, "") for c in COLUMNS})
    return out


def _interval(mean: str, lo: str, hi: str, percent: bool) -> str:
    """``mean [lo, hi]`` (the 95% interval, where the CSV has one)."""
    if not mean:
        return "n/a"
    form = (lambda x: f"{100.0 * float(x):.0f}") if percent else (lambda x: f"{float(x):.1f}")
    unit = "%" if percent else ""
    return f"{form(mean)}{unit} [{form(lo)}, {form(hi)}]" if lo and hi else f"{form(mean)}{unit}"


def markdown(table: list[dict[str, str]]) -> str:
    """The README's table: one row per env."""
    titles = " | ".join(title for title, _, _ in README_POLICIES)
    lines = [
        f"| env | task | obs | actions | control | horizon | success means | {titles} |",
        "|---|---|---:|---|---:|---:|---|" + "---:|" * len(README_POLICIES),
    ]
    for r in table:
        cells = [
            _interval(*(r[f"{key}_success{t}"] for t in ("", "_lo", "_hi")), percent=True)
            for _, _, key in README_POLICIES
        ]
        lines.append(
            f"| `{r['env_id']}` | {r['summary']} | {r['observations']} | {r['actions']}: "
            f"{r['action_names'].replace(' ', ', ')} | {r['control_hz']} Hz | "
            f"{r['horizon_s']} s | {r['success']} | " + " | ".join(cells) + " |"
        )
    return "\n".join(lines)


def results_markdown() -> str:
    """docs/training.md's table: each env's PPO run against every baseline, the mean return
    and success rate of each with its 95% interval."""
    from fluidsim_envs.scenes import SCENES

    lines = [
        "| env | policy | return [95% interval] | success [95% interval] |",
        "|---|---|---:|---:|",
    ]
    for env_id in SCENES:
        path = DOCS / f"eval_{scene_slug(env_id)}_ppo.csv"
        if not path.is_file():
            continue
        by = {r["policy"]: r for r in read_csv(path)[1]}
        for p in POLICIES:
            if p not in by:
                continue
            r = by[p]
            ret = _interval(r["return_mean"], r.get("return_mean_lo"), r.get("return_mean_hi"),
                            percent=False)  # fmt: skip
            success = _interval(
                r["success_rate"], r.get("success_rate_lo"), r.get("success_rate_hi"), True
            )
            lines.append(f"| {env_id.split('/')[1]} | {p} | {ret} | {success} |")
    return "\n".join(lines)


def params_markdown() -> str:
    """Every env parameter: its default and the values it may take (scenes/limits.py)."""
    import dataclasses

    from fluidsim_envs.physics.kernels import INTEGRATORS
    from fluidsim_envs.scenes import SCENES
    from fluidsim_envs.scenes import limits as LIM

    lines = []
    for env_id, scene in SCENES.items():
        own = env_id.split("/")[1]
        cls = scene.params_cls
        steps = ", ".join(f"{m} {dt:g}" for m, dt in LIM.DT_LIMIT_S.get(own, {}).items())
        lines += [f"**{own}** (`{cls.__name__}`)", "", "| parameter | default | allowed |"]
        lines.append("|---|---|---|")
        for f in dataclasses.fields(cls):
            rule = cls.RANGES.get(f.name)
            if rule is not None:
                allowed = rule.text()
            elif f.name == "integrator":
                allowed = ", ".join(sorted(INTEGRATORS))
            elif f.name == "dtype":
                allowed = "float32, float64"
            elif isinstance(f.default, bool):
                allowed = "True, False"
            else:
                allowed = "see the class docstring"
            if f.name == "dt" and steps:
                allowed += f"; at most (s): {steps}"
            lines.append(f"| `{f.name}` | `{f.default!r}` | {allowed} |")
        lines.append("")
    return "\n".join(lines).rstrip()


def fuzz_markdown() -> str:
    """docs/fuzz.csv as a table: each case's steps, divergence rate and the checks."""
    if not FUZZ_CSV.is_file():
        return "(no docs/fuzz.csv yet: run python -m benchmarks.fuzz)"
    comments, table = read_csv(FUZZ_CSV)
    lines = [
        "| env | parameters | dtype | integrator | dt (s) | env-steps | episodes | diverged "
        "| non-finite | unflagged runaways | max \\|reward\\| |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in table:
        lines.append(
            f"| {r['env'].split('/')[1]} | {r['params']} | {r['dtype']} | {r['integrator']} "
            f"| {float(r['dt_s']):.4g} | {int(r['env_steps']):,} | {int(r['episodes']):,} "
            f"| {float(r['divergence_rate']):.3%} | {r['nonfinite']} "
            f"| {r['unflagged_runaways']} | {float(r['max_reward']):.3g} |"
        )
    steps = sum(int(r["env_steps"]) for r in table)
    command = next((c[len("command: ") :] for c in comments if c.startswith("command: ")), "")
    lines += ["", f"{steps:,} env-steps in all (`{command}`)."]
    return "\n".join(lines)


def kill_markdown() -> str:
    """docs/kill_resume.csv by kind of kill: trials, those that passed every check, and the
    timesteps lost (the run's checkpoint interval beside them)."""
    if not KILL_CSV.is_file():
        return "(no docs/kill_resume.csv yet: run python -m benchmarks.kill_resume)"
    comments, table = read_csv(KILL_CSV)
    lines = [
        "| kill | trials | passed every check | resumed past a damaged checkpoint (this "
        "trial's or an earlier one's) "
        "| timesteps lost: mean | max |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for phase in dict.fromkeys(r["phase"] for r in table):
        rows = [r for r in table if r["phase"] == phase]
        lost = [int(r["lost_timesteps"]) for r in rows]
        passed = sum(r["checks_passed"] == "True" for r in rows)
        skipped = sum(int(r["skipped"]) > 0 for r in rows)
        lines.append(
            f"| {phase} | {len(rows)} | {passed} | {skipped} | {sum(lost) / len(lost):.0f} "
            f"| {max(lost)} |"
        )
    summary = next((c for c in comments if c.startswith("summary: ")), "")
    command = next((c[len("command: ") :] for c in comments if c.startswith("command: ")), "")
    lines += ["", f"{summary[len('summary: ') :]} (`{command}`)."]
    return "\n".join(lines)


def dart_markdown() -> str:
    """docs/dart_glide.csv as a sentence (the dart's trim) and a table (its phugoid against
    each approximation, each off the measured value by so much)."""
    from .dart_glide import CSV as DART_CSV
    from .dart_glide import published

    if not DART_CSV.is_file():
        return "(no docs/dart_glide.csv yet: run python -m benchmarks.dart_glide)"
    v = published(DART_CSV)
    period, zeta = v[("phugoid_period", "measured")], v[("phugoid_damping", "measured")]

    def off(value: float, measured: float) -> str:
        return f"{100.0 * (value / measured - 1.0):+.1f}%" if value else ""

    lines = [
        f"With zero controls the dart glides trimmed at {v[('trim_speed', 'measured')]:.2f} m/s "
        f"and {v[('glide_ratio', 'measured')]:.2f}:1 ({v[('glide_angle', 'measured')]:.1f}° "
        "below the horizon). Its phugoid beside the craft's own linearized equations and three "
        "approximations, each with ω_n = √2 g / V (they differ in the damping ratio ζ; "
        "`python -m benchmarks.dart_glide`, [dart_glide.csv](dart_glide.csv)):",
        "",
        "| phugoid | period (s) | off by | damping ratio | off by |",
        "|---|---:|---:|---:|---:|",
    ]
    for source, name in DART_SOURCES.items():
        p, z = v[("phugoid_period", source)], v[("phugoid_damping", source)]
        mine = source == "measured"
        lines.append(
            f"| {name} | {p:.3f} | {'' if mine else off(p, period)} | {z:.3f} "
            f"| {'' if mine else off(z, zeta)} |"
        )
    return "\n".join(lines)


def training_page() -> str:
    """docs/training.md with its generated tables: the PPO results, where PPO's wall time
    goes (``benchmarks.bench_training.markdown``) and the wall-clock retune's old-against-new
    scores (``benchmarks.train_wallclock.markdown``)."""
    text = TRAINING.read_text()
    for begin, end, block in (
        (RESULTS_BEGIN, RESULTS_END, results_markdown()),
        (SPLIT_BEGIN, SPLIT_END, bench_training.markdown()),
        (GRID_BEGIN, GRID_END, bench_training.grid_markdown()),
        (WALLCLOCK_BEGIN, WALLCLOCK_END, train_wallclock.markdown()),
    ):
        text = with_block(text, begin, end, block, TRAINING)
    return text


def study_page() -> str:
    """docs/study.md with its generated tables: the cost per body-step, Hairer's table, fixed
    point."""
    text = STUDY.read_text()
    for begin, end, block in (
        (COST_BEGIN, COST_END, study_accuracy.cost_markdown()),
        (HAIRER_BEGIN, HAIRER_END, study_hairer.markdown()),
        (FIXED_BEGIN, FIXED_END, study_fixed.markdown()),
    ):
        text = with_block(text, begin, end, block, STUDY)
    return text


def with_block(text: str, begin: str, end: str, block: str, where: Path) -> str:
    """``text`` with what lies between the markers ``begin`` and ``end`` replaced."""
    if begin not in text or end not in text:
        raise SystemExit(f"{where}: the markers {begin!r} ... {end!r} are missing")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    return f"{head}{begin}\n{block}\n{end}{tail}"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m benchmarks.report",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--check", action="store_true", help="only check, write nothing")
    args = parser.parse_args(argv)
    table = rows()
    pages = {
        README: with_block(README.read_text(), BEGIN, END, markdown(table), README),
        TRAINING: training_page(),
        ENVIRONMENTS: with_block(
            with_block(
                ENVIRONMENTS.read_text(), PARAMS_BEGIN, PARAMS_END, params_markdown(), ENVIRONMENTS
            ),
            DART_BEGIN,
            DART_END,
            dart_markdown(),
            ENVIRONMENTS,
        ),
        RELIABILITY: with_block(
            with_block(RELIABILITY.read_text(), FUZZ_BEGIN, FUZZ_END, fuzz_markdown(), RELIABILITY),
            KILL_BEGIN,
            KILL_END,
            kill_markdown(),
            RELIABILITY,
        ),
        STUDY: study_page(),
        SEED_MAP: with_block(
            SEED_MAP.read_text(), CLAIMS_BEGIN, CLAIMS_END, seed_claims.markdown(), SEED_MAP
        ),
    }
    if args.check:
        _, on_disk = read_csv(CSV) if CSV.is_file() else ([], [])
        checks = [("docs/envs.csv", on_disk == table)]
        checks += [(p.relative_to(ROOT), text == p.read_text()) for p, text in pages.items()]
        stale = [str(name) for name, ok in checks if not ok]
        if stale:
            print(f"out of date: {', '.join(stale)}; run python -m benchmarks.report")
            return 1
        return 0
    write_csv(CSV, COLUMNS, ([r[c] for c in COLUMNS] for r in table))
    for path, text in pages.items():
        path.write_text(text)
    print(markdown(table))
    print(results_markdown())
    print(
        f"written: {CSV.relative_to(ROOT)}, README.md, docs/training.md, docs/environments.md, "
        "docs/reliability.md, docs/study.md, docs/seed_map.md"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
