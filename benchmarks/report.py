"""The docs' tables of numbers, each written from a committed CSV (or the env registry)
between two markers, so that no number in README.md or docs/*.md is edited by hand.

    python -m benchmarks.report            # writes docs/envs.csv and every block
    python -m benchmarks.report --check    # exit 1 if any is out of date (the tests run it)
    python -m benchmarks.report --list     # every block: page, marker, source, renderer

What it writes is :data:`BLOCKS`, one line per block (the single list: ``--list`` prints it):
the page, the marker's name, the source the marker names and the function that renders it,
as ``module:function`` in this package (imported when called). A block lies between
``<!-- NAME: written by `python -m benchmarks.report` from SOURCE -->`` and
``<!-- /NAME -->``; the function returns the text between the two lines. :data:`PAGES` are
pages written whole from a CSV by their benchmark (``bench_peers``), checked the same way;
:data:`PAGE_SETS` are folders of pages written whole (one page per env, ``env_pages``), a
page there that its renderer no longer writes being out of date too.

To add a table: write ``markdown()`` (or ``<what>_markdown()``) in the benchmark that writes
the CSV, returning the table from the CSV alone (a note in brackets where the CSV is missing);
put the two marker lines where the table goes; add its :class:`Block` line to ``BLOCKS``;
run ``python -m benchmarks.report``.

The README's table of envs (``envs-table``) is also kept as docs/envs.csv: one row per
registered env (:data:`fluidsim_envs.scenes.SCENES`), its observation and action sizes,
control rate and horizon (from the env's default parameters), what success means (the scene's
``success``, with its numbers), and the success rate and mean return, each with its 95%
bootstrap interval, of the planner (oracle), the tuned pilot and trained PPO from
``docs/eval_<scene>_ppo.csv`` (what ``fluidsim-evaluate RUN --episodes 256`` wrote for the
shipped PPO config's run, every baseline beside it; blank where no such file exists).
"""

from __future__ import annotations

import argparse
import functools
import importlib
import math
import re
import sys
from dataclasses import dataclass
from pathlib import Path

from .common import DOCS, ROOT, read_csv, write_csv

CSV = DOCS / "envs.csv"
WRITER = "python -m benchmarks.report"


@dataclass(frozen=True)
class Block:
    """A block of ``page`` (relative to the repository root) between the markers ``name``,
    rendered by ``render`` (``module:function`` of this package) from ``source``."""

    page: str
    name: str
    source: str
    render: str

    @property
    def begin(self) -> str:
        return f"<!-- {self.name}: written by `{WRITER}` from {self.source} -->"

    @property
    def end(self) -> str:
        return f"<!-- /{self.name} -->"

    def text(self) -> str:
        module, function = self.render.split(":")
        return getattr(importlib.import_module(f"benchmarks.{module}"), function)()


# every block this command writes, by page (one line each: keep it so, merges stay simple)
BLOCKS = (
    Block(
        "README.md", "front-table", "docs/envs.csv and docs/results.csv", "report:front_markdown"
    ),
    Block("docs/environments.md", "envs-table", "docs/envs.csv", "report:envs_markdown"),
    Block("docs/data.md", "data-files", "docs/*.csv", "report:data_markdown"),
    Block("docs/training.md", "ppo-results", "docs/eval_*_ppo.csv", "report:results_markdown"),
    Block("docs/environments.md", "dart-glide", "docs/dart_glide.csv", "report:dart_markdown"),
    Block("docs/environments.md", "params-table", "each scene's RANGES", "report:params_markdown"),
    Block("docs/environments.md", "v1-levels", "each v1 scene's LEVELS", "report:levels_markdown"),
    Block(
        "docs/environments.md", "v1-sensors", "each v1 scene's SENSORS", "report:sensors_markdown"
    ),  # fmt: skip
    Block("docs/environments.md", "v1-pilots", "docs/study_levels.csv", "study_levels:markdown"),
    Block("docs/environments.md", "v1-ppo", "docs/study_v1_ppo.csv", "study_v1_ppo:markdown"),
    Block(
        "docs/training.md",
        "v1-ppo-floor",
        "docs/study_v1_ppo_easy.csv",
        "study_v1_ppo:easy_markdown",
    ),
    Block("docs/environments.md", "v1-reward", "docs/reward_terms.csv", "reward_terms:markdown"),
    Block("docs/training.md", "sweep-races", "docs/sweep_*.csv", "sweep_envs:markdown"),
    Block(
        "docs/training.md",
        "sweep-trial",
        "docs/bench_sweep_trial.csv",
        "bench_sweep_trial:markdown",
    ),
    Block("docs/reliability.md", "fuzz-table", "docs/fuzz.csv", "report:fuzz_markdown"),
    Block("docs/reliability.md", "fuzz-v1-table", "docs/fuzz_v1.csv", "report:fuzz_v1_markdown"),
    Block("docs/reliability.md", "kill-table", "docs/kill_resume.csv", "report:kill_markdown"),
    Block("docs/reliability.md", "ranges-table", "docs/ranges.csv", "ranges:markdown"),
    Block("docs/reliability.md", "witness-table", "docs/fuzz_witness.csv", "witness:markdown"),
    Block("docs/study.md", "cost-table", "docs/study_cost.csv", "study_accuracy:cost_markdown"),
    Block(
        "docs/baselines.md", "planner-budget", "docs/study_planner.csv", "study_planner:markdown"
    ),
    Block("docs/study.md", "hairer-table", "docs/study_hairer.csv", "study_hairer:markdown"),
    Block("docs/study.md", "fixed-table", "docs/study_fixed.csv", "study_fixed:markdown"),
    Block("docs/benchmarks.md", "kernel-table", "docs/bench_kernel.csv", "bench_kernel:markdown"),
    Block("docs/benchmarks.md", "env-table", "docs/bench_envs.csv", "bench_envs:markdown"),
    Block("docs/benchmarks.md", "levels-table", "docs/bench_levels.csv", "bench_levels:markdown"),
    Block("docs/study.md", "float32-table", "docs/study_float32.csv", "study_float32:markdown"),
    Block("docs/physics.md", "wake-table", "docs/study_wake*.csv", "study_wake:markdown"),
    Block(
        "docs/training.md", "training-split", "docs/bench_training.csv", "bench_training:markdown"
    ),
    Block(
        "docs/training.md",
        "training-grid",
        "docs/bench_training_grid.csv",
        "bench_training:grid_markdown",
    ),
    Block(
        "docs/training.md",
        "training-wallclock",
        "docs/training_wallclock.csv",
        "train_wallclock:markdown",
    ),
    Block(
        "docs/training.md",
        "training-wallclock-v1",
        "docs/training_wallclock_v1.csv",
        "train_wallclock:markdown_v1",
    ),
    Block(
        "docs/benchmarks.md", "kernel-cost", "docs/bench_kernel.csv", "bench_kernel:cost_markdown"
    ),
    Block(
        "docs/benchmarks.md",
        "peers-summary",
        "docs/bench_peers.csv",
        "bench_peers:summary_markdown",
    ),
    Block(
        "docs/environments.md",
        "savitsky-steady",
        "docs/study_savitsky.csv",
        "study_savitsky:steady_markdown",
    ),
    Block(
        "docs/study_savitsky.md",
        "savitsky-errors",
        "docs/study_savitsky_grid.csv",
        "study_savitsky:grid_markdown",
    ),
    Block(
        "docs/study_savitsky.md",
        "savitsky-turn",
        "docs/study_savitsky_turn.csv",
        "study_savitsky:turn_markdown",
    ),
    Block(
        "docs/study_savitsky.md",
        "savitsky-cost",
        "docs/bench_boat.csv",
        "bench_boat:rules_markdown",
    ),
    Block(
        "docs/study.md", "stability-table", "docs/study_stability.csv", "study_stability:markdown"
    ),
    Block("docs/study.md", "contact-table", "docs/study_contact.csv", "study_contact:markdown"),
    Block(
        "docs/study.md",
        "env-integrators-table",
        "docs/study_env_integrators.csv",
        "study_env_integrators:markdown",
    ),
    Block(
        "docs/study.md",
        "defaults-table",
        "docs/study_stability.csv, study_accuracy.csv",
        "study_stability:defaults_markdown",
    ),
    Block(
        "docs/study_model_cost.md",
        "cost-paper-airplane",
        "docs/study_model_cost.csv",
        "study_model_cost:paper_airplane_markdown",
    ),
    Block(
        "docs/study_model_cost.md",
        "cost-speedboat",
        "docs/study_model_cost.csv",
        "study_model_cost:speedboat_markdown",
    ),
    Block(
        "docs/study_model_cost.md",
        "cost-uuv",
        "docs/study_model_cost.csv",
        "study_model_cost:uuv_markdown",
    ),
    Block(
        "docs/study_model_cost.md",
        "cost-buoy",
        "docs/study_model_cost.csv",
        "study_model_cost:buoy_markdown",
    ),
    Block(
        "docs/study_model_cost.md",
        "cost-floor",
        "docs/study_model_cost.csv",
        "study_model_cost:floor_markdown",
    ),
    Block(
        "docs/study_model_cost.md",
        "cost-submarine",
        "docs/study_model_cost.csv",
        "study_model_cost:submarine_markdown",
    ),
    Block(
        "docs/study_model_cost.md",
        "cost-boat",
        "docs/study_model_cost.csv",
        "study_model_cost:boat_markdown",
    ),
    Block(
        "docs/study_model_cost.md",
        "cost-dart",
        "docs/study_model_cost.csv",
        "study_model_cost:dart_markdown",
    ),
    Block("docs/seed_map.md", "seed-claims", "docs/study_*.csv", "seed_claims:markdown"),
    Block("README.md", "zoo-gifs", "docs/zoo_*.gif", "zoo:gifs_markdown"),
    Block("docs/zoo.md", "zoo-table", "zoo/*/evaluation.csv", "env_pages:zoo_markdown"),
    Block("docs/zoo.md", "zoo-gifs", "docs/zoo_*.gif", "env_pages:zoo_gifs_markdown"),
)
# pages written whole by their benchmark from its CSV: page -> renderer (``module:function``)
PAGES = {
    "docs/ablation.md": "ablation:page",
    "docs/bench_peers.md": "bench_peers:page",
    "docs/results.md": "results:page",
}
# folders of pages written whole from the registry: folder -> renderer (``module:function``,
# returning {page: text}); the folder's every *.md is the renderer's
PAGE_SETS = {
    "docs/envs": "env_pages:pages",
}

# docs/dart_glide.csv's phugoid sources, as the table names them
DART_SOURCES = {
    "measured": "measured (speed peaks after a level launch 1 m/s below trim)",
    "linearized": "the craft's longitudinal equations linearized at trim, from its own forces",
    "glide_with_drag": "point mass with drag, in the glide: ζ = 3 sin γ / (2√2)",
    "etkin_reid": "Etkin & Reid with drag, level flight: ζ = C_D / (√2 C_L)",
    "lanchester": "Lanchester, drag-free: ζ = 0",
}
# the policies of an evaluation CSV (fluidsim-evaluate's rows) in the tables, by row name
# ("planner (oracle)": fluidsim-evaluate's planner before issue 44, in the v0 CSVs, where an
# episode has no noise to come and it was the planner of today)
POLICIES = (
    "trained PPO", "planner", "planner (oracle)", "tuned pilot", "v0-tuned pilot",
    "hand-set pilot", "random",
)  # fmt: skip
# the README's table: (column title, row name, envs.csv key)
README_POLICIES = (
    ("planner", "planner", "planner"),
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
    """``fluidsim/PaperAirplane-v0`` -> ``paper_airplane`` (the scene's package name), a later
    version with its number (``paper_airplane_v1``): each version's results are its own."""
    name, version = env_id.split("/")[1].rsplit("-v", 1)
    slug = re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()
    return slug if version == "0" else f"{slug}_v{version}"


def _scores(env_id: str) -> dict[str, str]:
    """Each README policy's success rate and mean return, with their intervals, from the
    env's evaluation CSV."""
    path = DOCS / f"eval_{scene_slug(env_id)}_ppo.csv"
    if not path.is_file():
        return {}
    by = {r["policy"]: r for r in read_csv(path)[1]}
    by.setdefault("planner", by.get("planner (oracle)"))  # the v0 CSVs' name of it
    out = {}
    for _, policy, key in README_POLICIES:
        if by.get(policy) is None:
            continue
        row = by[policy]
        for mine, theirs in (("success", "success_rate"), ("return", "return_mean")):
            for tail in ("", "_lo", "_hi"):
                out[f"{key}_{mine}{tail}"] = row.get(f"{theirs}{tail}", "")
        out["evaluated_episodes"] = row["episodes"]
    return out


@functools.cache
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


def envs_markdown() -> str:
    """The README's table of envs (:func:`rows`)."""
    return markdown(rows())


def data_markdown() -> str:
    """Every table under docs/ (linked) with the command its ``# command:`` line names."""
    lines = ["| table | written by |", "|---|---|"]
    for path in sorted(DOCS.glob("*.csv")):
        comments, _ = read_csv(path)
        command = next((c[len("command: ") :] for c in comments if c.startswith("command: ")), "")
        lines.append(
            f"| [{path.name}]({path.name}) | "
            + (f"`{command}`" if command else "(its page says)")
            + " |"
        )
    return "\n".join(lines)


def front_markdown() -> str:
    """The README's table: each v1 env (task, observation and action sizes) and, at each
    level, its best trained policy (the highest IQM return over its runs) beside its best
    scripted pilot (the highest mean return), from docs/results.csv: the IQM and the mean
    over runs, each with its 95% interval, and the worst run."""
    from benchmarks import results

    _, table = read_csv(results.CSV)
    envs = {r["env_id"]: r for r in rows()}
    baselines = (*results.BASELINES, *results.LEGACY.values())
    lines = [
        "| env | task | obs | actions | level | best trained: IQM return [95% CI] "
        "| its mean [95% CI] | its worst run | best pilot: mean return [95% CI] |",
        "|---|---|---:|---|---|---|---|---|---|",
    ]
    for env in dict.fromkeys(r["env"] for r in table):
        e = envs[f"fluidsim/{env}"]
        first = (
            f"`{e['env_id']}` | {e['summary']} | {e['observations']} | {e['actions']}: "
            f"{e['action_names'].replace(' ', ', ')}"
        )
        for level in dict.fromkeys(r["level"] for r in table if r["env"] == env):
            here = [r for r in table if (r["env"], r["level"]) == (env, level)]
            trained = [r for r in here if r["policy"] not in baselines]
            pilots = [r for r in here if r["policy"] in results.PILOTS]
            if not trained or not pilots:
                continue
            best = max(trained, key=lambda r: float(r["iqm"]))
            pilot = max(pilots, key=lambda r: float(r["mean"]))
            lines.append(
                f"| {first} | {level} | {best['policy']} ({best['runs']} runs): "
                f"**{_ci(best, 'iqm')}** | {_ci(best, 'mean')} | "
                f"{float(best['worst']):.1f} ({best['worst_run']}) | "
                f"{pilot['policy']}: {_ci(pilot, 'mean')} |"
            )
            first = " | | | "
    return "\n".join(lines)


def _ci(row: dict[str, str], key: str) -> str:
    """``row[key] [lo, hi]`` to one decimal."""
    return f"{float(row[key]):.1f} [{float(row[key + '_lo']):.1f}, {float(row[key + '_hi']):.1f}]"


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
    from fluidsim_envs.scenes import SCENES

    lines = []
    for env_id, scene in SCENES.items():
        own = env_id.split("/")[1]
        lines += [f"**{own}** (`{scene.params_cls.__name__}`)", "", params_table(scene), ""]
    return "\n".join(lines).rstrip()


def params_table(scene) -> str:
    """One scene's parameters (a :class:`~fluidsim_envs.scenes.Scene`): each one's default and
    the values it may take, the step limits of its integrators beside ``dt``."""
    import dataclasses

    from fluidsim_envs.physics.kernels import INTEGRATORS
    from fluidsim_envs.scenes import limits as LIM

    cls = scene.params_cls
    steps = ", ".join(  # nan: it held at no step tried, refused at any
        f"{m} {'refused' if math.isnan(dt) else f'{dt:g}'}"
        for m, dt in LIM.DT_LIMIT_S.get(scene.id.split("/")[1], {}).items()
    )
    lines = ["| parameter | default | allowed |", "|---|---|---|"]
    for f in dataclasses.fields(cls):
        rule = cls.RANGES.get(f.name) or getattr(cls, "KNOB_RANGES", {}).get(f.name)
        if f.name == "difficulty":
            allowed = "easy, standard, hard"
        elif f.name == "actuators":
            allowed = "True, False (None: the level's)"
        elif rule is not None:
            allowed = rule.text()
        elif f.name == "integrator":
            allowed = ", ".join(sorted(INTEGRATORS))
        elif f.name == "dtype":
            allowed = "float32, float64"
        elif f.name in getattr(cls, "CHOICES", {}):
            allowed = ", ".join(cls.CHOICES[f.name])
        elif isinstance(f.default, bool):
            allowed = "True, False"
        else:
            allowed = "see the class docstring"
        if f.name == "dt" and steps:
            allowed += f"; at most (s): {steps}"
        if f.default is None and rule is not None:
            allowed += " (None: the level's)"
        lines.append(f"| `{f.name}` | `{f.default!r}` | {allowed} |")
    return "\n".join(lines)


def _v1_modules():
    """Each v1 scene's id and its module (LEVELS, SENSORS)."""
    import importlib

    from fluidsim_envs.scenes import SCENES

    return [
        (env_id, importlib.import_module(scene.vector_cls.__module__))
        for env_id, scene in SCENES.items()
        if scene.version == 1
    ]


def level_cell(value) -> str:
    """A knob's value as the level tables print it (a range as ``low to high``)."""
    if isinstance(value, bool) or isinstance(value, str):
        return str(value)
    return f"{value[0]:g} to {value[1]:g}" if isinstance(value, tuple) else f"{value:g}"


def levels_markdown() -> str:
    """Each v1 knob's value at each level, per scene (scenes/<scene>/v1.py's LEVELS over
    realism.Knobs' defaults)."""
    import dataclasses

    from fluidsim_envs.scenes.realism import LEVELS

    modules = _v1_modules()
    base = {}  # every knob of any scene, at its default
    for _, m in modules:
        base.update({k: v for k, v in dataclasses.asdict(m.KNOBS()).items() if k not in base})
    head = " | ".join(f"{e.split('/')[1]} {lv}" for e, _ in modules for lv in LEVELS[1:])
    lines = [f"| knob | easy | {head} |", "|---|---" + "|---" * 2 * len(modules) + "|"]

    for knob, default in base.items():
        cells = []
        for _, m in modules:
            own = dataclasses.asdict(m.KNOBS())
            for lv in LEVELS[1:]:
                cells.append(level_cell({**own, **m.LEVELS[lv]}[knob]) if knob in own else "-")
        lines.append(f"| `{knob}` | {level_cell(default)} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def sensors_markdown() -> str:
    """Each v1 scene's instruments: the columns they read, their noise, bias, resolution and
    the hardware the numbers come from (at ``sensor_scale`` 1)."""
    from fluidsim_envs.scenes.sensors import table_rows

    lines = [
        "| env | instrument | columns | noise | bias (time) | resolution | hardware |",
        "|---|---|---|---:|---:|---:|---|",
    ]
    for env_id, m in _v1_modules():
        for row in table_rows(m.SENSORS):
            lines.append(f"| {env_id.split('/')[1]} | " + " | ".join(row) + " |")
    return "\n".join(lines)


def fuzz_v1_markdown() -> str:
    """docs/fuzz_v1.csv (the v1 envs at hard) as :func:`fuzz_markdown`'s table."""
    return fuzz_markdown("fuzz_v1.csv")


def fuzz_markdown(name: str = "fuzz.csv") -> str:
    """docs/fuzz.csv (or ``name``) as a table: each case's steps, divergence rate and the
    checks."""
    if not (DOCS / name).is_file():
        return f"(no docs/{name} yet: run python -m benchmarks.fuzz)"
    comments, table = read_csv(DOCS / name)
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
    if not (DOCS / "kill_resume.csv").is_file():
        return "(no docs/kill_resume.csv yet: run python -m benchmarks.kill_resume)"
    comments, table = read_csv(DOCS / "kill_resume.csv")
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


def with_block(text: str, begin: str, end: str, block: str, where: Path) -> str:
    """``text`` with what lies between the markers ``begin`` and ``end`` replaced; a block
    whose begin marker is indented (inside a list item) is indented as deep."""
    if begin not in text or end not in text:
        raise SystemExit(f"{where}: the markers {begin!r} ... {end!r} are missing")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    indent = head[head.rfind("\n") + 1 :]
    if indent.strip():
        indent = ""
    block = "\n".join(f"{indent}{line}" if line else line for line in block.split("\n"))
    return f"{head}{begin}\n{block}\n{indent}{end}{tail}"


def pages() -> dict[Path, str]:
    """Every page this command writes, as it should read."""
    out = {}
    for block in BLOCKS:
        path = ROOT / block.page
        text = out.get(path, path.read_text() if path.is_file() else "")
        out[path] = with_block(text, block.begin, block.end, block.text(), path)
    for page, render in PAGES.items():
        module, function = render.split(":")
        out[ROOT / page] = getattr(importlib.import_module(f"benchmarks.{module}"), function)()
    for render in PAGE_SETS.values():
        module, function = render.split(":")
        written = getattr(importlib.import_module(f"benchmarks.{module}"), function)()
        out.update({ROOT / page: text for page, text in written.items()})
    return out


def orphans(written: dict[Path, str]) -> list[Path]:
    """The pages in a :data:`PAGE_SETS` folder that its renderer no longer writes."""
    return [
        path
        for folder in PAGE_SETS
        for path in sorted((ROOT / folder).glob("*.md"))
        if path not in written
    ]


def _reads(path: Path) -> str | None:
    return path.read_text() if path.is_file() else None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog=f"{WRITER}",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--check", action="store_true", help="only check, write nothing")
    parser.add_argument("--list", action="store_true", help="list the blocks and pages")
    args = parser.parse_args(argv)
    if args.list:
        for b in BLOCKS:
            print(f"{b.page:24s} {b.name:22s} {b.source:34s} {b.render}")
        for page, render in PAGES.items():
            print(f"{page:24s} {'(whole page)':22s} {'':34s} {render}")
        for folder, render in PAGE_SETS.items():
            print(
                f"{folder + '/*.md':24s} {'(whole pages)':22s} {'the scene registry':34s} {render}"
            )
        return 0
    table = rows()
    written = pages()
    if args.check:
        _, on_disk = read_csv(CSV) if CSV.is_file() else ([], [])
        checks = [("docs/envs.csv", on_disk == table)]
        checks += [(p.relative_to(ROOT), text == _reads(p)) for p, text in written.items()]
        checks += [(p.relative_to(ROOT), False) for p in orphans(written)]
        stale = [str(name) for name, ok in checks if not ok]
        if stale:
            print(f"out of date: {', '.join(stale)}; run {WRITER}")
            return 1
        return 0
    write_csv(CSV, COLUMNS, ([r[c] for c in COLUMNS] for r in table))
    changed = [p for p, text in written.items() if text != _reads(p)]
    for path in changed:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(written[path])
    for path in orphans(written):  # a scene no longer registered
        path.unlink()
        changed.append(path)
    names = ", ".join(str(p.relative_to(ROOT)) for p in changed) or "nothing changed"
    print(f"written: {CSV.relative_to(ROOT)}; {names}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
