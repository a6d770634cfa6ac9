"""The planner's score against its planning budget, and where its time goes.

For each scene, the sampling planner (``fluidsim_envs/scenes/planner.py``, an oracle of the
present: it reads the true state and physics, but its rollouts draw noise and gusts of their
own) flies the same seeded episodes at several budgets around the scene's default
(``Scene.planner_config``): fewer candidate plans (samples K) and a shorter plan (horizon H
knots of ``hold`` actions each). Beside it, the scene's tuned scripted pilot on the
same episodes. The episodes come from a tuning seed (``evaluation.TUNING_SEEDS[0]``), not the
published evaluation's: this study is where the defaults were chosen.

Rows of ``docs/study_planner.csv``: env, policy, samples, horizon, hold, look-ahead (s),
budget (env-steps of rollouts per action flown per episode), episodes, the mean return and
success rate each with its 95% bootstrap interval, the milliseconds per decision (one call
for all episodes) and per episode-decision, and the shares of the planner's time in the
rollouts' env steps and in their physics (``Simulator.step``). ``docs/study_planner.png``
charts return and success against the budget.

    python -m benchmarks.study_planner                    # every scene, 64 episodes each
    python -m benchmarks.study_planner --env fluidsim/BoatOnStep-v0 --episodes 32
    python -m benchmarks.study_planner --quick            # 8 episodes, two budgets, build/
    (an env studied replaces its rows of the CSV; the other envs' are kept)
    python -m benchmarks.study_planner --replot           # the chart again from the CSV
"""

from __future__ import annotations

import dataclasses
import time

import numba
import numpy as np

from fluidsim_envs import threads
from fluidsim_envs.evaluation import TUNING_SEEDS, check_tuning_seeds, first_episodes
from fluidsim_envs.rl.evaluate import mean_interval
from fluidsim_envs.scenes import SCENES

from .common import DOCS, arguments, describe, load_average, out_dir, read_csv, write_csv

COLUMNS = (
    "env", "policy", "guided", "samples", "horizon", "hold", "lookahead_s", "budget", "episodes",
    "return_mean", "return_lo", "return_hi", "success_rate", "success_lo", "success_hi",
    "ms_per_decision", "ms_per_episode_decision", "rollout_share", "physics_share", "seconds",
    "numba_threads",
)  # fmt: skip


def budgets(config, quick: bool) -> list:
    """The scene's default, with a quarter and half of its samples, with half its horizon,
    and unguided (plans of actions, without the pilot under them: planner.py)."""
    K, H = config.samples, config.horizon
    points = [
        dict(samples=max(K // 4, config.elites)),
        dict(samples=max(K // 2, config.elites)),
        dict(),
        dict(horizon=max(H // 2, 1)),
        dict(guided=not config.guided),
    ]
    if quick:
        points = [points[0], points[-1]]
    return [dataclasses.replace(config, **p) for p in points]


def row(scene_id, policy, config, results, seconds, timing, action_s, seed) -> list:
    ret, success = results["return"], results["success"].astype(float)
    E = len(ret)
    decisions = max(timing.get("decisions", 0), 1)
    total = timing.get("total", 0.0)
    cells = [
        scene_id,
        policy,
        config.guided if config is not None else "",
        *(
            (
                config.samples,
                config.horizon,
                config.hold,
                config.lookahead * action_s,
                config.budget,
            )
            if config is not None
            else ("", "", "", "", 0)
        ),
        E,
        float(ret.mean()),
        *mean_interval(ret, seed),
        float(success.mean()),
        *mean_interval(success, seed),
        1e3 * total / decisions if config is not None else "",
        1e3 * total / decisions / E if config is not None else "",
        timing.get("rollout", 0.0) / total if total else "",
        timing.get("physics", 0.0) / total if total else "",
        seconds,
        numba.get_num_threads(),
    ]
    return cells


def study(scene_id: str, episodes: int, quick: bool, seed: int) -> list[list]:
    scene = SCENES[scene_id]
    venv = scene.vector_cls(num_envs=episodes)
    action_s = venv.params.dt * venv.params.substeps
    rows = []
    t0 = time.perf_counter()
    pilot = first_episodes(venv, scene.pilot(venv), seed=seed)
    rows.append(row(scene_id, "tuned pilot", None, pilot, time.perf_counter() - t0, {}, 0, seed))
    print(f"{scene_id}: tuned pilot return {pilot['return'].mean():.2f}", flush=True)
    for config in budgets(scene.planner_config, quick):
        planner = scene.planner(venv, **dataclasses.asdict(config))
        t0 = time.perf_counter()
        results = first_episodes(venv, planner, seed=seed)
        seconds = time.perf_counter() - t0
        rows.append(
            row(scene_id, "planner", config, results, seconds, planner.timing, action_s, seed)
        )
        r = dict(zip(COLUMNS, rows[-1], strict=True))
        print(
            f"{scene_id}: {'guided ' if config.guided else ''}K={config.samples} "
            f"H={config.horizon}x{config.hold} budget {config.budget}: return "
            f"{r['return_mean']:.2f} success {r['success_rate']:.1%}, "
            f"{r['ms_per_decision']:.0f} ms/decision, physics {r['physics_share']:.0%}, "
            f"{seconds:.0f} s",
            flush=True,
        )
    return rows


def chart(rows: list[list], path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    records = [dict(zip(COLUMNS, r, strict=True)) for r in rows]
    ids = list(dict.fromkeys(r["env"] for r in records))
    fig, axes = plt.subplots(2, len(ids), figsize=(4.4 * len(ids), 6.6), squeeze=False)
    for j, sid in enumerate(ids):
        mine = [r for r in records if r["env"] == sid]
        pilot = next(r for r in mine if r["policy"] == "tuned pilot")
        plans = [r for r in mine if r["policy"] == "planner"]
        for i, (mean, lo, hi, name) in enumerate(
            (
                ("return_mean", "return_lo", "return_hi", "return"),
                ("success_rate", "success_lo", "success_hi", "success rate"),
            )
        ):
            ax = axes[i, j]
            lines = sorted({(r["guided"], r["lookahead_s"]) for r in plans}, reverse=True)
            for guided, look in lines:
                pts = sorted(
                    (r for r in plans if (r["guided"], r["lookahead_s"]) == (guided, look)),
                    key=lambda r: r["budget"],
                )
                y = np.array([r[mean] for r in pts])
                err = np.array([y - [r[lo] for r in pts], [r[hi] for r in pts] - y])
                label = f"{'guided' if guided else 'unguided'}, {look:.1f} s look-ahead"
                ax.errorbar([r["budget"] for r in pts], y, yerr=err, marker="o", capsize=3,
                            label=label)  # fmt: skip
            ax.axhline(pilot[mean], color="gray", ls="--", label="tuned pilot")
            ax.axhspan(pilot[lo], pilot[hi], color="gray", alpha=0.15)
            ax.set_xscale("log")
            budgets_here = sorted({r["budget"] for r in plans})
            # a label per budget, except one within 10% of the last labelled (1408 and 1440)
            labels, last = [], -1.0
            for b in budgets_here:
                labels.append(str(b) if b > 1.1 * last else "")
                last = b if labels[-1] else last
            ax.set_xticks(budgets_here, labels)
            ax.minorticks_off()
            ax.set_xlabel("budget (rollout env-steps per action flown)")
            ax.set_ylabel(name)
            if i == 0:
                ax.set_title(f"{sid.split('/')[1]}, {pilot['episodes']} episodes", fontsize=10)
                ax.legend(fontsize=7)
    fig.suptitle(
        "Planner (an oracle of the present: the true state, noise of its own) against its "
        "budget, 95% bootstrap intervals"
    )
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def read_rows(path) -> list[list]:
    """The CSV's rows with the types :func:`row` gives them (what :func:`chart` reads)."""

    def cell(column: str, text: str):
        if column in ("env", "policy") or text == "":
            return text
        if column == "guided":
            return text == "True"
        number = float(text)
        return int(number) if number.is_integer() and column != "lookahead_s" else number

    # a row written before a column was kept has it blank
    return [[cell(c, r.get(c, "")) for c in COLUMNS] for r in read_csv(path)[1]]


def markdown(path=None) -> str:
    """docs/baselines.md's table of the study from ``docs/study_planner.csv``: per env the
    tuned pilot and each budget, with the time a decision costs per episode and the share of
    it in the rollouts' physics."""
    path = DOCS / "study_planner.csv" if path is None else path
    if not path.is_file():
        return "(no docs/study_planner.csv yet: run python -m benchmarks.study_planner)"
    lines = [
        "| env | policy | K | H x hold | look-ahead (s) | budget | episodes | return [95%] "
        "| success [95%] | ms per episode-decision | numba threads | physics share |",
        "|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|",
    ]
    pct = lambda x: f"{100 * float(x):.0f}%"  # noqa: E731
    for r in read_csv(path)[1]:
        planner = r["policy"] == "planner"
        name = ("guided " if r["guided"] == "True" else "unguided ") + "planner"
        budget = (
            f"{r['samples']} | {r['horizon']} x {r['hold']} | {float(r['lookahead_s']):.1f} | "
            f"{r['budget']}"
            if planner
            else " | | | "
        )
        lines.append(
            f"| {r['env'].split('/')[1]} | {name if planner else r['policy']} | {budget} | "
            f"{r['episodes']} | {float(r['return_mean']):.2f} [{float(r['return_lo']):.2f}, "
            f"{float(r['return_hi']):.2f}] | {pct(r['success_rate'])} [{pct(r['success_lo'])}, "
            f"{pct(r['success_hi'])}] | "
            + (
                f"{float(r['ms_per_episode_decision']):.2f} | {r.get('numba_threads', '')} | "
                f"{pct(r['physics_share'])} |"
                if planner
                else " | | |"
            )
        )
    lines += ["", "numba threads: blank in rows written before the column was kept."]
    return "\n".join(lines)


def main() -> None:
    parser = arguments(__doc__, "8 episodes, two budgets per scene, into build/study_quick")
    parser.add_argument("--env", action="append", choices=list(SCENES), help="scenes (all)")
    parser.add_argument("--episodes", type=int, default=64)
    parser.add_argument(
        "--replot", action="store_true", help="only draw the chart again from the CSV in --out"
    )
    args = parser.parse_args()
    threads.apply(threads.choose())  # the one owner's counts, as the CLIs run on
    if args.replot:
        folder = out_dir(args.out, args.quick)
        chart(read_rows(folder / "study_planner.csv"), folder / "study_planner.png")
        print(f"written: {folder / 'study_planner.png'}")
        return
    seed = check_tuning_seeds(TUNING_SEEDS[:1])[0]
    episodes = 8 if args.quick else args.episodes
    machine = describe()
    folder = out_dir(args.out, args.quick)
    csv = folder / "study_planner.csv"
    for sid in args.env or list(SCENES):  # written env by env: the boat's takes an hour
        mine = study(sid, episodes, args.quick, seed)
        # the envs not studied now keep their rows
        rows = [r for r in read_rows(csv) if r[0] != sid] if csv.is_file() else []
        notes = [*machine, f"episodes: reset(seed={seed}) (a tuning seed)", load_average()]
        print(f"written: {write_csv(csv, COLUMNS, rows + mine, notes)}")
    chart(read_rows(csv), folder / "study_planner.png")
    print(f"written: {folder / 'study_planner.png'}")


if __name__ == "__main__":
    main()
