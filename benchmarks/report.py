"""The README's table of envs, written from the registry and the committed evaluation CSVs.

    python -m benchmarks.report            # writes docs/envs.csv and the README's table
    python -m benchmarks.report --check    # exit 1 if either is out of date (the tests run it)

One row per registered env (:data:`fluidsim_envs.scenes.SCENES`): its observation and action
sizes, control rate and horizon (from the env's default parameters), what success means (the
scene's ``success``, with its numbers), and the scripted pilot's and trained PPO's success
rate and mean return from ``docs/eval_<scene>_ppo.csv`` (what ``fluidsim-evaluate RUN
--episodes 256`` wrote for the shipped PPO config's run; blank where no such file exists).
The README's table sits between the two ``envs-table`` markers and is never edited by hand.
"""

from __future__ import annotations

import argparse
import re
import sys

from .common import DOCS, ROOT, read_csv, write_csv

CSV = DOCS / "envs.csv"
README = ROOT / "README.md"
BEGIN = "<!-- envs-table: written by `python -m benchmarks.report` from docs/envs.csv -->"
END = "<!-- /envs-table -->"
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
        if policy in by:
            out[f"{key}_success"] = by[policy]["success_rate"]
            out[f"{key}_return"] = by[policy]["return_mean"]
            out["evaluated_episodes"] = by[policy]["episodes"]
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


def readme_with(table_md: str, text: str) -> str:
    """``text`` (the README) with the block between the markers replaced."""
    if BEGIN not in text or END not in text:
        raise SystemExit(f"{README}: the markers {BEGIN!r} ... {END!r} are missing")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    return f"{head}{BEGIN}\n{table_md}\n{END}{tail}"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m benchmarks.report",
        description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--check", action="store_true", help="only check, write nothing")
    args = parser.parse_args(argv)
    table = rows()
    readme = README.read_text()
    new_readme = readme_with(markdown(table), readme)
    if args.check:
        _, on_disk = read_csv(CSV) if CSV.is_file() else ([], [])
        checks = (("docs/envs.csv", on_disk == table), ("README.md", new_readme == readme))
        stale = [name for name, ok in checks if not ok]
        if stale:
            print(f"out of date: {', '.join(stale)}; run python -m benchmarks.report")
            return 1
        return 0
    write_csv(CSV, COLUMNS, ([r[c] for c in COLUMNS] for r in table))
    README.write_text(new_readme)
    print(markdown(table))
    print(f"written: {CSV.relative_to(ROOT)}, README.md")
    return 0


if __name__ == "__main__":
    sys.exit(main())
