"""A wall-clock race per v1 env and algorithm: the shipped PPO config on its scene's v1 at
``standard`` (the boat: its v1 curriculum config), searched over the shipped PPO space
(``--search ppo``), and PaperAirplane-v1's SAC config over the SAC space (``--search
sac``), for the config that reaches the tuned pilot's return soonest on this machine's
cores.

    python -m benchmarks.sweep_envs                                  # all four (hours)
    python -m benchmarks.sweep_envs --configs boat_on_step_v1_ppo --trials 4
    python -m benchmarks.sweep_envs --configs paper_airplane_ppo --trials 12 --wall-budget-s 240
    python -m benchmarks.sweep_envs --csv-only                       # docs from the sweeps

The target is the tuned pilot's mean return at ``standard`` over 256 seeded episodes
(``docs/study_v1_ppo.csv``, the ``probes`` rows: the pilot flies v1 with the probes on, as
PPO does). Each sweep is the real CLI in a subprocess: ``fluidsim-sweep CONFIG --set
env_id=<v1> total_timesteps=<far> --search ppo --trials K --cpus-per-trial 2 --target T
--wall-budget-s B`` (PPO: one trial at a time, so every trial's clock runs on the same two
cores; ``total_timesteps`` far beyond what the budget allows, so only the target and the
budget end a trial). SAC's trials take one core each, two at a time: a SAC trial steps a
few envs and makes its gradient steps on one torch thread, so a second core would sit
idle, and each trial's clock still runs on a core of its own. A sweep folder that holds a
sweep is resumed, not started again.

The in-training evaluations that decide "reached" fly the config's ``eval.n_episodes``
episodes (32), not the pilot's 256: a trial's first evaluation at the target is a claim the
multi-seed results check on the full episodes. Writes ``docs/sweep_<config>.csv`` and
``.md``: the sweep's results table, with the command and the target in its header.
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import shutil
import subprocess
import sys
from dataclasses import dataclass

from benchmarks.common import DOCS, ROOT, read_csv
from benchmarks.study_v1_ppo import CONFIGS

SWEEPS = ROOT / "sweeps" / "v1"
PILOT_CSV = DOCS / "study_v1_ppo.csv"
FAR = 1_000_000_000  # total_timesteps: never reached within a budget


@dataclass(frozen=True)
class Race:
    """One config's race: the v1 env it flies, the shipped search space, a trial's wall-clock
    budget, the cores a trial takes and the settings every trial shares."""

    env_id: str
    search: str
    budget_s: float
    cpus_per_trial: int = 2
    sets: tuple[str, ...] = ()
    grace_s: float | None = None  # ASHA's first rung (default: a ninth of the budget)


#: PPO's budgets: a few times the shipped config's time to 3-5 M steps. The boat races its
#: curriculum config (2 M steps at easy first) for about what its five results seeds took to
#: their 5 M steps on a core each (1,273 to 1,958 s, docs/results_runs.csv), with ASHA's
#: first cut well after that stage. SAC's: what a trial
#: at a quarter of a gradient step per transition needs for ~300 k transitions on one core
#: (a probe of 64x64 nets, 8 envs, 2 gradient steps a step: ~420 transitions/s), with
#: evaluations every 10 k steps so that "reached" is seen soon after it happens, and ASHA's
#: first cut at a third of the budget (at a ninth, SAC's returns are still warm-up noise).
RACES = {
    "paper_airplane_ppo": Race(CONFIGS["paper_airplane_ppo"], "ppo", 240.0),
    "submarine_wake_ppo": Race(CONFIGS["submarine_wake_ppo"], "ppo", 480.0),
    "boat_on_step_v1_ppo": Race("fluidsim/BoatOnStep-v1", "ppo", 1500.0, grace_s=900.0),
    "paper_airplane_v1_sac": Race(
        "fluidsim/PaperAirplane-v1",
        "sac",
        720.0,
        cpus_per_trial=1,
        sets=("eval.freq=10000",),
        grace_s=240.0,
    ),
}


def pilot_return(env_id: str) -> float:
    """The tuned pilot's mean return on ``env_id`` at ``standard`` (docs/study_v1_ppo.csv)."""
    name = env_id.split("/")[1]
    _, rows = read_csv(PILOT_CSV)
    for row in rows:
        if row["env"] == name and row["variant"] == "probes" and row["policy"] == "tuned pilot":
            return round(float(row["return_mean"]), 2)
    raise SystemExit(f"{PILOT_CSV}: no tuned pilot row for {name}")


def sweep_command(config: str, trials: int, budget_s: float) -> list[str]:
    race = RACES[config]
    folder = SWEEPS / config
    if (folder / "sweep.yaml").is_file():
        return [sys.executable, "-m", "fluidsim_envs.rl.sweep", "--resume", str(folder)]
    return [
        sys.executable, "-m", "fluidsim_envs.rl.sweep", config,
        "--set", f"env_id={race.env_id}", f"total_timesteps={FAR}", *race.sets,
        "--search", race.search, "--trials", str(trials),
        "--cpus-per-trial", str(race.cpus_per_trial),
        "--target", str(pilot_return(race.env_id)), "--wall-budget-s", str(budget_s),
        "--sweep-dir", str(folder),
        *(["--grace", str(race.grace_s)] if race.grace_s else []),
    ]  # fmt: skip


def publish(config: str, command: str) -> None:
    """The sweep's table into docs/, its header naming this command and the target."""
    folder = SWEEPS / config
    if not (folder / "results.csv").is_file():
        print(f"{config}: no results yet in {folder}")
        return
    import yaml

    from fluidsim_envs.rl.space import base_point, parse_space

    target = pilot_return(RACES[config].env_id)
    sweep = yaml.safe_load((folder / "sweep.yaml").read_text())
    body = (folder / "results.csv").read_text()
    first = base_point(parse_space(sweep["space"], "sweep.yaml"), sweep["base"])[0]
    rows = list(csv.DictReader(io.StringIO(body)))
    first_trial = next((r["trial"] for r in rows if _same(r, first)), "none")
    head = [
        f"# command: {command}",
        f"# target: the tuned pilot's mean return at standard, {target} (docs/study_v1_ppo.csv)",
        f"# budget: a trial's wall-clock limit, {sweep['wall_budget_s']:g} s",
        f"# sweep: {folder.relative_to(ROOT)}",
        f"# first trial: {first_trial} (the config as it was when raced)",
    ]
    (DOCS / f"sweep_{config}.csv").write_text("\n".join(head) + "\n" + body)
    shutil.copyfile(folder / "results.md", DOCS / f"sweep_{config}.md")
    print(f"wrote docs/sweep_{config}.csv and .md")


def _base_values(config: str) -> dict[str, object]:
    """The shipped config's values of the searched keys (the sweep's first trial)."""
    import yaml

    from fluidsim_envs.rl.config import config_to_dict, load_config
    from fluidsim_envs.rl.space import base_point, find_space, parse_space

    race = RACES[config]
    path = find_space(race.search)
    space = parse_space(yaml.safe_load(path.read_text()), str(path))
    cfg = load_config(config, [f"env_id={race.env_id}"])
    return base_point(space, config_to_dict(cfg))[0]


def _same(row: dict, values: dict) -> bool:
    """The row's values are ``values`` (a trial that errored before drawing any: not)."""
    return all(_equal(row[k], v) for k, v in values.items())


def _equal(cell: str, value: object) -> bool:
    """A results-CSV cell holds ``value``: numbers to rounding, anything else (a net_arch
    mapping) as the sweep wrote it."""
    try:
        return math.isclose(float(cell), float(value), rel_tol=1e-9)
    except (TypeError, ValueError):
        return cell == str(value)


def markdown() -> str:
    """Each env's race: the trials, how many reached the tuned pilot's return within the
    budget, the time to it of the config raced from (the sweep's first trial: the config as
    it was when raced; a config that ships a race's winner was raced from another) and of
    the search's best trial (the soonest; where none reached it, the best return), each
    trial's env steps a second, and what the best changes (docs/sweep_<config>.csv)."""
    lines = [
        "| env | target (tuned pilot) | trials | reached | config raced from | the search's best "
        "| env steps/s (from, best) | what the best changes |",
        "|---|--:|--:|--:|--:|--:|--:|---|",
    ]
    found = False
    for config, race in RACES.items():
        path = DOCS / f"sweep_{config}.csv"
        if not path.is_file():
            continue
        found = True
        comments, rows = read_csv(path)
        target = next(c for c in comments if c.startswith("target:")).rsplit(", ", 1)[1]
        budget = float(next(c for c in comments if c.startswith("budget:")).split(", ")[1][:-2])
        reached = [
            r for r in rows if r["time_to_target_s"] and float(r["time_to_target_s"]) <= budget
        ]
        shipped, base = _first_trial(config, comments, rows)

        best = rows[0]  # the search's ranking: the soonest, then the best return
        change = ", ".join(
            f"{k.split('.')[-1]} {_fmt(best[k])}" for k, v in base.items() if not _equal(best[k], v)
        )
        lines.append(
            f"| {race.env_id.split('/')[1]} {race.search.upper()} | {target.split(' ')[0]} | "
            f"{len(rows)} | {len(reached)} | "
            f"{_when(shipped, budget)} | {_when(best, budget)} | "
            f"{_rate(shipped)}, {_rate(best)} | "
            f"{change or 'nothing: it is the config raced from'} |"
        )
    if not found:
        return "(no docs/sweep_*.csv yet: `python -m benchmarks.sweep_envs`)\n"
    return "\n".join(lines) + "\n"


def _first_trial(config: str, comments: list[str], rows: list[dict]) -> tuple[dict | None, dict]:
    """The race's first trial (the config as it was) and its searched values: named in the
    CSV's header, or (a CSV from before the header said it) the trial with the shipped
    config's values."""
    named = next((c.split()[2] for c in comments if c.startswith("first trial:")), None)
    base = _base_values(config)
    if named is None:
        return next((r for r in rows if _same(r, base)), None), base
    row = next((r for r in rows if r["trial"] == named), None)
    return row, ({k: row[k] for k in base} if row else base)


def _when(row: dict | None, budget: float) -> str:
    """A trial's time to the target, or that it did not reach it: within its budget, or
    before ASHA stopped it."""
    if row is None:
        return "not run"
    t = row["time_to_target_s"]
    if t and float(t) <= budget:
        return f"{float(t):.0f} s"
    best = f"best {float(row['best_return']):.3g}"
    if row["status"] == "stopped early":
        return f"stopped by ASHA at {float(row['wall_s']):.0f} s ({best})"
    return f"not in {budget:.0f} s ({best})"


def _rate(row: dict | None) -> str:
    """A trial's env steps a second over its whole run (evaluations and updates included)."""
    if row is None or not row["wall_s"] or not float(row["wall_s"]):
        return "-"
    return f"{float(row['timesteps']) / float(row['wall_s']):,.0f}"


def _fmt(text: str) -> str:
    """A searched value as the summary shows it: a number briefly, a net_arch as its layers
    (``{'pi': [64, 64], 'qf': [64, 64]}`` as ``64x64``)."""
    try:
        x = float(text)
    except ValueError:
        import ast

        arch = ast.literal_eval(text)
        layers = {tuple(v) for v in arch.values()} if isinstance(arch, dict) else {tuple(arch)}
        if len(layers) == 1:
            return "x".join(map(str, layers.pop()))
        return " / ".join(f"{k} " + "x".join(map(str, v)) for k, v in arch.items())
    return f"{x:.3g}" if x != int(x) else str(int(x))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--configs", nargs="+", choices=list(RACES), default=list(RACES))
    parser.add_argument("--trials", type=int, default=12)
    parser.add_argument("--wall-budget-s", type=float, help="default: the race's budget_s")
    parser.add_argument("--csv-only", action="store_true", help="publish the sweeps as they are")
    args = parser.parse_args(argv)
    command = "python -m benchmarks.sweep_envs " + " ".join(argv or sys.argv[1:])
    for config in args.configs:
        if not args.csv_only:
            budget = args.wall_budget_s or RACES[config].budget_s
            cmd = sweep_command(config, args.trials, budget)
            print("$", " ".join(cmd), flush=True)
            subprocess.run(cmd, check=True, cwd=ROOT)
        publish(config, command.strip())
    return 0


if __name__ == "__main__":
    sys.exit(main())
