"""A sweep's results: the lines the driver prints as trials go (:class:`SweepProgress`, a Ray
Tune callback that also keeps ``status.yaml``), and the table over all trials, ``results.csv``
and ``results.md`` (:func:`write_results`), built from the run folders' evaluation histories
and ``run.yaml`` files: it can be rebuilt from the sweep folder alone.

A trial's status: ``finished`` (ran its timesteps), ``reached target`` (``--target``, within
its budget; ``after its budget`` where the evaluation that got there ended past it), ``out
of time`` (``--wall-budget-s``), ``stopped early`` (ASHA cut it at a rung), ``error`` (the
message in the table), ``running`` (a sweep killed or still going: ``--resume`` continues it).
"""

from __future__ import annotations

import csv
import io
import math
import shlex
from pathlib import Path
from typing import Any

import yaml
from ray.tune import Callback

from . import files
from .config import read_yaml
from .runs import MODEL, read_history
from .space import plain

STATUS_FILE = "status.yaml"
COLUMNS_BEFORE = ("trial", "status")
COLUMNS_AFTER = (
    "seed",
    "timesteps",
    "final_return",
    "best_return",
    "best_at",
    "best_success",
    "wall_s",
    "time_to_target_s",
    "peak_rss_mb",
    "run_dir",
)


def read_status(sweep_dir: Path) -> dict[str, dict[str, Any]]:
    path = sweep_dir / STATUS_FILE
    return (read_yaml(path) or {}) if path.is_file() else {}


class SweepProgress(Callback):
    """Says what each trial does, one line per event, and records its outcome in
    ``status.yaml`` (then rewrites the results table)."""

    def __init__(self, sweep, say) -> None:
        self.sweep, self.say = sweep, say

    def _update(self, trial, **fields: Any) -> None:
        status = read_status(self.sweep.dir)
        status.setdefault(trial.trial_id, {}).update(fields)
        text = yaml.safe_dump(status, sort_keys=False)
        files.write_text(self.sweep.dir / STATUS_FILE, text)

    def on_trial_start(self, iteration, trials, trial, **info) -> None:
        from .sweep import searched, trial_seed

        params = {k: plain(v) for k, v in searched(trial.config).items()}
        seed = trial_seed(self.sweep, trial.config)
        self._update(trial, status="running", seed=seed, params=params)
        shown = ", ".join(f"{k}={_fmt(v)}" for k, v in params.items())
        self.say(f"trial {trial.trial_id} started: seed {seed}" + (f", {shown}" * bool(shown)))

    def on_trial_result(self, iteration, trials, trial, result, **info) -> None:
        self._update(trial, peak_rss_mb=result.get("peak_rss_mb"))
        rate = result.get("success_rate", math.nan)
        success = "" if math.isnan(rate) else f", success {rate:.0%}"
        self.say(
            f"trial {trial.trial_id} @ {result['timesteps']:>10,} steps, {result['wall_s']:6.0f} "
            f"s: return {result['eval_return']:9.3f} (best {result['best_return']:.3f}){success}"
        )

    def on_trial_complete(self, iteration, trials, trial, **info) -> None:
        last = trial.last_result or {}
        steps = int(last.get("timesteps", 0))
        sweep = self.sweep
        # a run that ended by itself has its final model; one ASHA cut short has none (its
        # last evaluation may fall short of total_timesteps either way: evaluations come
        # every eval.freq steps, the end after the last whole rollout)
        complete = (Path(last.get("run_dir", "")) / MODEL).is_file()
        if sweep.target is not None and last.get("best_return", -math.inf) >= sweep.target:
            status = "reached target"
        elif sweep.target is not None and last.get("wall_s", 0.0) >= sweep.wall_budget_s:
            status = "out of time"
        elif complete or steps >= sweep.total_timesteps:
            status = "finished"
        else:
            status = "stopped early"
        self._update(trial, status=status)
        self.say(f"trial {trial.trial_id} {status} at {steps:,} steps")
        write_results(self.sweep)

    def on_trial_error(self, iteration, trials, trial, **info) -> None:
        message = _error_line(trial.error_file)
        self._update(trial, status="error", error=message)
        self.say(f"trial {trial.trial_id} failed: {message}")
        write_results(self.sweep)


def _error_line(path: str | None) -> str:
    """The last line of a trial's error file (the exception and its message)."""
    if not path or not Path(path).is_file():
        return "unknown error (no error file)"
    lines = [ln for ln in Path(path).read_text().splitlines() if ln.strip()]
    return lines[-1].strip() if lines else "unknown error"


# --------------------------------------------------------------------------------------------
# the table


def trial_row(sweep, trial_id: str, state: dict[str, Any]) -> dict[str, Any]:
    """One trial's row: its status and sampled values, then what its run folder shows."""
    row: dict[str, Any] = {"trial": trial_id, "status": state.get("status", "running")}
    if row["status"] == "error":
        row["status"] = f"error: {state.get('error', '')}"
    params = state.get("params", {})
    for key in sweep.space:
        row[key] = params.get(key)
    row["seed"] = state.get("seed")
    run_dir = sweep.dir / "runs" / trial_id
    history = read_history(run_dir)
    if history:
        best = max(history, key=lambda h: h["mean_return"])
        reached = [
            h for h in history if sweep.target is not None and h["mean_return"] >= sweep.target
        ]
        row.update(
            timesteps=int(history[-1]["timesteps"]),
            final_return=history[-1]["mean_return"],
            best_return=best["mean_return"],
            best_at=int(best["timesteps"]),
            best_success=best["success_rate"],
            wall_s=history[-1]["wall_s"],
            time_to_target_s=reached[0]["wall_s"] if reached else None,
        )
        late = reached and reached[0]["wall_s"] > (sweep.wall_budget_s or math.inf)
        if late:  # the evaluation that got there came after the budget had run out
            row["status"] = "reached target after its budget"
    row["peak_rss_mb"] = state.get("peak_rss_mb")  # as of the trial's last evaluation
    row["run_dir"] = f"runs/{trial_id}" if run_dir.is_dir() else None
    return row


def results_rows(sweep) -> list[dict[str, Any]]:
    """Every trial the driver saw, as the search ranks them: by best evaluation, or with a
    target the soonest to reach it first, then the others by best evaluation (trials
    without an evaluation last)."""
    rows = [trial_row(sweep, tid, state) for tid, state in read_status(sweep.dir).items()]

    def key(row: dict[str, Any]) -> tuple:
        best, reached = row.get("best_return"), row.get("time_to_target_s")
        return (
            reached is None,
            reached or 0.0,
            best is None or math.isnan(best),
            -(best or 0.0),
            row["trial"],
        )

    return sorted(rows, key=key)


def columns(sweep) -> list[str]:
    return [*COLUMNS_BEFORE, *sweep.space, *COLUMNS_AFTER]


def write_results(sweep) -> Path:
    """``results.csv`` and ``results.md`` in the sweep folder; returns the CSV's path."""
    rows, cols = results_rows(sweep), columns(sweep)
    out = io.StringIO()
    writer = csv.DictWriter(out, cols, extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    writer.writerows({c: _csv_value(row.get(c)) for c in cols} for row in rows)
    files.write_text(sweep.dir / "results.csv", out.getvalue())
    files.write_text(sweep.dir / "results.md", markdown(sweep, rows, cols))
    return sweep.dir / "results.csv"


def markdown(sweep, rows: list[dict[str, Any]], cols: list[str]) -> str:
    base = sweep.base
    lines = [
        f"# Sweep: {base['env_id']}, {base['algorithm']['name'].upper()}",
        "",
        f"`{sweep.command_line}` (started {sweep.started}); {sweep.total_timesteps:,} timesteps "
        f"a trial, evaluations every {base['eval']['freq']:,} steps on "
        f"{base['eval']['n_episodes']} episodes (seed {base['eval']['seed']}).",
        "",
    ]
    if sweep.space:
        lines += ["Searched:", ""] + [f"- {dim}" for dim in sweep.dimensions.values()] + [""]
    lines += (_seed_summary(rows) if not sweep.space else []) + [
        "| " + " | ".join(cols) + " |",
        "|" + "---|" * len(cols),
    ]
    lines += ["| " + " | ".join(_fmt(row.get(c)) for c in cols) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def _seed_summary(rows: list[dict[str, Any]]) -> list[str]:
    finals = [r["final_return"] for r in rows if r.get("final_return") is not None]
    if len(finals) < 2:
        return []
    mean = sum(finals) / len(finals)
    return [
        f"Final evaluation return over {len(finals)} trials: mean {mean:.3f}, "
        f"min {min(finals):.3f}, max {max(finals):.3f}.",
        "",
    ]


def _csv_value(value: Any) -> Any:
    return "" if value is None or (isinstance(value, float) and math.isnan(value)) else value


def _fmt(value: Any) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)


def closing_lines(sweep, table: Path) -> list[str]:
    """What the sweep ends with: the table, the best trial and the commands that use it."""
    rows = results_rows(sweep)
    lines = [f"results: {table} and {table.with_suffix('.md')} ({len(rows)} trials)"]
    best = next((r for r in rows if r.get("best_return") is not None), None)
    if best is not None and best["run_dir"]:
        run = shlex.quote(str(sweep.dir / best["run_dir"]))
        soonest = best.get("time_to_target_s")
        how = f"reached {sweep.target} in {soonest:,.0f} s, " if soonest is not None else ""
        lines += [
            f"best: trial {best['trial']}, {how}best return {best['best_return']:.3f} at "
            f"{best['best_at']:,} steps; its config {run}/config.yaml",
            f"  evaluate:    fluidsim-evaluate {run} --model best",
        ]
    return lines


__all__ = ["SweepProgress", "closing_lines", "results_rows", "write_results"]
