"""The docs' tables of envs and results, written from the registry and the committed
evaluation CSVs.

    python -m benchmarks.report            # writes docs/envs.csv and the tables
    python -m benchmarks.report --check    # exit 1 if any is out of date (the tests run it)

One row per registered env (:data:`fluidsim_envs.scenes.SCENES`): its observation and action
sizes, control rate and horizon (from the env's default parameters), what success means (the
scene's ``success``, with its numbers), and the scripted pilot's and trained PPO's success
rate and mean return from ``docs/eval_<scene>_ppo.csv`` (what ``fluidsim-evaluate RUN
--episodes 256`` wrote for the shipped PPO config's run; blank where no such file exists).
The README's table sits between the two ``envs-table`` markers, and docs/training.md's table
of PPO against the baselines (return mean +- std and success of each policy in those CSVs)
between the ``ppo-results`` markers; neither is edited by hand.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

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
POLICIES = ("trained PPO", "scripted pilot", "random")  # the table's columns
# each column's row in the evaluation CSVs: the first of these names present (the scripted
# pilot's row is "tuned pilot" since fluidsim-evaluate added the other baselines)
ROW_NAMES = {"scripted pilot": ("tuned pilot", "scripted pilot")}


def _policy_row(by: dict[str, dict], policy: str) -> dict | None:
    """``policy``'s row of an evaluation CSV (rows ``by`` name), or None."""
    return next((by[n] for n in ROW_NAMES.get(policy, (policy,)) if n in by), None)


COLUMNS = (
    "env_id", "summary", "observations", "actions", "action_names", "control_hz",
    "horizon_steps", "horizon_s", "success", "pilot_success", "pilot_return",
    "ppo_success", "ppo_return", "evaluated_episodes",
)  # fmt: skip


def scene_slug(env_id: str) -> str:
    """``fluidsim/PaperAirplane-v0`` -> ``paper_airplane`` (the scene's package name)."""
    name = env_id.split("/")[1].rsplit("-v", 1)[0]
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name).lower()


def _scores(env_id: str) -> dict[str, str]:
    """The pilot's and PPO's success rate and mean return from the evaluation CSV."""
    path = DOCS / f"eval_{scene_slug(env_id)}_ppo.csv"
    if not path.is_file():
        return {}
    _, rows = read_csv(path)
    by = {r["policy"]: r for r in rows}
    out = {}
    for key, policy in (("pilot", "scripted pilot"), ("ppo", "trained PPO")):
        row = _policy_row(by, policy)
        if row is not None:
            out[f"{key}_success"] = row["success_rate"]
            out[f"{key}_return"] = row["return_mean"]
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


def _pct(x: str) -> str:
    return f"{100.0 * float(x):.1f}%" if x else "n/a"


def _num(x: str) -> str:
    return f"{float(x):.1f}" if x else "n/a"


def markdown(table: list[dict[str, str]]) -> str:
    """The README's table: one row per env."""
    lines = [
        "| env | task | obs | actions | control | horizon | success means | scripted pilot | PPO |",
        "|---|---|---:|---|---:|---:|---|---:|---:|",
    ]
    for r in table:
        lines.append(
            f"| `{r['env_id']}` | {r['summary']} | {r['observations']} | {r['actions']}: "
            f"{r['action_names'].replace(' ', ', ')} | {r['control_hz']} Hz | "
            f"{r['horizon_s']} s | {r['success']} | {_pct(r['pilot_success'])} "
            f"({_num(r['pilot_return'])}) | {_pct(r['ppo_success'])} ({_num(r['ppo_return'])}) |"
        )
    return "\n".join(lines)


def results_markdown() -> str:
    """docs/training.md's table: each env's PPO run against the pilot and random."""
    from fluidsim_envs.scenes import SCENES

    head = " | ".join(f"{p} return | {p} success" for p in POLICIES)
    lines = [f"| env | episodes | {head} |", "|---|---:|" + "---:|---:|" * len(POLICIES)]
    for env_id in SCENES:
        path = DOCS / f"eval_{scene_slug(env_id)}_ppo.csv"
        if not path.is_file():
            continue
        by = {r["policy"]: r for r in read_csv(path)[1]}
        cells = []
        for p in POLICIES:
            r = _policy_row(by, p)
            cells += (
                [f"{float(r['return_mean']):.2f} +- {float(r['return_std']):.2f}",
                 _pct(r["success_rate"])]
                if r else ["n/a", "n/a"]
            )  # fmt: skip
        episodes = by[POLICIES[0]]["episodes"] if POLICIES[0] in by else "n/a"
        lines.append(f"| {env_id.split('/')[1]} | {episodes} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


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
        TRAINING: with_block(
            TRAINING.read_text(), RESULTS_BEGIN, RESULTS_END, results_markdown(), TRAINING
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
    print(f"written: {CSV.relative_to(ROOT)}, README.md, docs/training.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
