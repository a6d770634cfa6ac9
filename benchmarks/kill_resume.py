"""Kill -9 a training run at random moments and resume it, again and again: is the run folder
always resumable, and does it lose no more than it must?

One tiny run (PaperAirplane-v0, PPO, 8 envs x 64 steps a rollout, an evaluation of 4 episodes
every 512 timesteps, a checkpoint every 1024) trains in a subprocess (``python -m
fluidsim_envs.rl.train``). Each trial starts it (the first one new, the others with
``--resume``), sends it SIGKILL at a moment of the trial's phase, then checks the folder:

- ``random``: at a uniform moment 0.5-10 s after the start (start-up, the resume's own
  trimming of the folder, training, evaluations, checkpoints alike);
- ``after-checkpoint``: as soon as a new checkpoint appears;
- ``mid-write``: inside an atomic write: the run is started with ``FLUIDSIM_WRITE_DELAY_S``
  (:mod:`fluidsim_envs.rl.files`), which sleeps 0.3 s between writing each temporary file and
  renaming it, and the kill lands when the k-th temporary file (k random, 1-16) appears: where a
  writer in place would have left a truncated checkpoint, best model, history or run.yaml;
- ``torn-checkpoint``: a ``random`` kill, after which the newest checkpoint's model is cut to half
  its size (what a writer in place leaves), so the resume must fall back to the one before.

The first trial's kill is timed from the first checkpoint (a run killed before it has nothing
to resume from). After the kill, the resume's own preparation of the folder
(``fluidsim_envs.rl.train._restart``: the newest saved state that loads, the best model's
interrupted commit completed, the logs past the restart point dropped) runs here, and:

- ``resumed``: a restart point was found (and the previous trial's resume, when it lived long
  enough to record one in run.yaml, continued from the point this script predicted);
- ``lost``: timesteps at the kill minus the restart point's is at most one checkpoint interval
  (two for ``torn-checkpoint``). The timesteps at the kill are the newest the folder shows: its
  last monitor.csv row (episodes end every few steps) or checkpoint or evaluation;
- ``best``: best/best.yaml's score is at least every evaluation any session printed, its model
  model is of the timesteps best.yaml names, and that model with its statistics scores
  the same again on the same seeded episodes (model, statistics and score belong together);
- ``history``: eval/evaluations.npz and history.csv hold the same evaluations, one at every
  multiple of the evaluation period up to the restart point, in order;
- ``monitor``: no monitor.csv row past the restart point; timesteps and times never decrease;
- ``clean``: no temporary file left.

A last session resumes the run and lets it finish (two checkpoint intervals more). Writes
``docs/kill_resume.csv`` (one row per trial); exits non-zero if any check failed.

    python -m benchmarks.kill_resume [--trials 20] [--seed 0]
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from fluidsim_envs.rl.config import read_yaml
from fluidsim_envs.rl.runs import checkpoint_paths, checkpoints, saved_timesteps

from .common import ROOT, arguments, describe, load_average, write_csv

EVAL_PERIOD = 512
CHECKPOINT_PERIOD = 1024
TINY = [
    "total_timesteps=100000000",  # never reached: every session ends with a kill
    "n_envs=8",
    "algorithm.n_steps=64",
    "algorithm.batch_size=256",
    "algorithm.n_epochs=4",
    f"eval.freq={EVAL_PERIOD}",
    "eval.n_episodes=4",
    f"checkpoint.freq={CHECKPOINT_PERIOD}",
]
PHASES = ("random", "after-checkpoint", "mid-write", "torn-checkpoint")
WRITE_DELAY_S = 0.3
MAX_WAIT_S = 90.0  # for the moment a phase waits for
EVAL_LINE = re.compile(r"eval @\s+([\d,]+) steps: return\s+(-?[\d.]+)")
COLUMNS = (
    "trial", "phase", "kill_s", "killed_in", "timesteps_at_kill", "resumed_from",
    "restart_timesteps", "lost_timesteps", "skipped", "checks_passed", "failed",
)  # fmt: skip


# --------------------------------------------------------------------------------------------
# the run in a subprocess


def launch(run_dir: Path, log: Path, resume: bool, delay_s: float = 0.0) -> subprocess.Popen:
    """``fluidsim-train`` on the tiny config (or ``--resume``), its output into ``log``."""
    cmd = [sys.executable, "-m", "fluidsim_envs.rl.train", "--no-progress-bar"]
    if resume:
        cmd += ["--resume", str(run_dir)]
    else:
        cmd += ["paper_airplane_ppo", "--set", *TINY, "--run-dir", str(run_dir)]
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    env.pop("FLUIDSIM_WRITE_DELAY_S", None)
    if delay_s:
        env["FLUIDSIM_WRITE_DELAY_S"] = str(delay_s)
    with log.open("w") as out:
        return subprocess.Popen(cmd, stdout=out, stderr=subprocess.STDOUT, env=env, cwd=ROOT)


def newest_checkpoint(run_dir: Path, whole: bool = False) -> int:
    """The timesteps of the newest checkpoint (0: none); ``whole``: of those whose model can
    be read (not one this script tore)."""
    steps = [n for n, p in checkpoints(run_dir) if not whole or saved_timesteps(p) is not None]
    return max(steps, default=0)


def partials(run_dir: Path) -> set[str]:
    """The temporary files being written now (their names)."""
    found = set()
    for folder in (run_dir, run_dir / "checkpoints", run_dir / "eval", run_dir / "best"):
        with contextlib.suppress(FileNotFoundError):
            found |= {e.name for e in os.scandir(folder) if ".partial" in e.name}
    return found


def wait_until(done, proc: subprocess.Popen, timeout_s: float = MAX_WAIT_S) -> bool:
    """Poll ``done()`` until true (True), the process ends or the time is up (False)."""
    end = time.perf_counter() + timeout_s
    while time.perf_counter() < end and proc.poll() is None:
        if done():
            return True
        time.sleep(0.002)
    return False


def kill_at(phase: str, proc: subprocess.Popen, run_dir: Path, rng) -> str:
    """Wait for the phase's moment and SIGKILL the run; what it was doing then ('' unknown,
    or the temporary file being written). Raises RuntimeError if it ended by itself."""
    killed_in = ""
    if phase == "after-checkpoint":
        before = newest_checkpoint(run_dir)
        wait_until(lambda: newest_checkpoint(run_dir) > before, proc)
        killed_in = f"{checkpoint_paths(run_dir, newest_checkpoint(run_dir)).model.name} written"
    elif phase == "mid-write":
        seen: set[str] = set()
        target = int(rng.integers(1, 17))

        def enough() -> bool:
            seen.update(partials(run_dir))
            return len(seen) >= target

        wait_until(enough, proc)
        now = partials(run_dir)
        killed_in = "writing " + ", ".join(sorted(_final_name(n) for n in now)) if now else ""
    else:
        deadline = time.perf_counter() + float(rng.uniform(0.5, 10.0))
        wait_until(lambda: time.perf_counter() >= deadline, proc)
    if proc.poll() is not None:
        raise RuntimeError(f"the run ended by itself (exit status {proc.returncode})")
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    return killed_in


def _final_name(partial: str) -> str:
    """``.model_1024_steps.safetensors.abc123.partial.safetensors`` ->
    ``model_1024_steps.safetensors``."""
    return partial[1:].split(".partial")[0].rsplit(".", 1)[0]


# --------------------------------------------------------------------------------------------
# the checks


def timesteps_shown(run_dir: Path) -> int:
    """The newest timesteps the folder shows: its last whole monitor.csv row, its newest
    whole checkpoint, its last evaluation."""
    steps = [newest_checkpoint(run_dir, whole=True)]
    monitor = run_dir / "monitor.csv"
    if monitor.is_file():
        lines = monitor.read_text().splitlines(keepends=True)
        rows = [ln for ln in lines[2:] if ln.endswith("\n")]
        if rows:
            steps.append(int(rows[-1].rstrip().rsplit(",", 1)[1]))
    history = run_dir / "eval" / "history.csv"
    if history.is_file():
        steps += [int(ln.split(",")[0]) for ln in history.read_text().splitlines()[1:] if ln]
    return max(steps)


def printed_evaluations(logs: list[Path]) -> list[float]:
    """The mean return of every evaluation any session printed."""
    return [float(m.group(2)) for log in logs for m in EVAL_LINE.finditer(log.read_text())]


def prepare_resume(run_dir: Path):
    """What ``--resume`` does before it trains (here, in this process): the restart point,
    and the lines it said (the states it skipped)."""
    from fluidsim_envs.rl import train as train_cli
    from fluidsim_envs.rl.config import load_config

    cfg = load_config(run_dir / "config.yaml")
    said = io.StringIO()
    with contextlib.redirect_stderr(said):
        try:
            restart, _ = train_cli._restart(run_dir, cfg)
        except train_cli.RunError:
            restart = None
    return cfg, restart, said.getvalue().splitlines()


def check_best(cfg, run_dir: Path, logs: list[Path]) -> bool:
    from stable_baselines3.common.evaluation import evaluate_policy

    from fluidsim_envs.rl import saved
    from fluidsim_envs.rl import train as train_cli
    from fluidsim_envs.rl.evaluate import load_run
    from fluidsim_envs.rl.runs import BestModel

    best = BestModel.open(run_dir / "best")
    printed = printed_evaluations(logs)
    if not printed:
        return True
    if best.score < max(printed) - 5e-4 or list((run_dir / "best").glob(".pending-*")):
        return False
    model_path, stats = BestModel(run_dir / "best").committed()
    if saved.model_header(model_path)["num_timesteps"] != best.record.get("timesteps"):
        return False
    _, model = load_run(run_dir, "best")  # its policy
    env = train_cli.make_env(
        cfg,
        cfg.eval.n_episodes,
        cfg.eval.seed,
        evaluation=True,
        stats=stats,
    )
    try:
        env.seed(cfg.eval.seed)
        returns, _ = evaluate_policy(
            model, env, cfg.eval.n_episodes, deterministic=True, return_episode_rewards=True
        )
    finally:
        env.close()
    return math.isclose(float(np.mean(returns)), best.score, rel_tol=1e-5, abs_tol=1e-4)


def check_history(run_dir: Path, restart_steps: int) -> bool:
    npz = run_dir / "eval" / "evaluations.npz"
    csv_path = run_dir / "eval" / "history.csv"
    expected = list(range(EVAL_PERIOD, restart_steps + 1, EVAL_PERIOD))
    if not npz.is_file():
        return not expected
    saved = np.load(npz)["timesteps"].tolist()
    rows = [int(ln.split(",")[0]) for ln in csv_path.read_text().splitlines()[1:] if ln]
    return saved == rows == expected


def check_monitor(run_dir: Path, restart_steps: int) -> bool:
    lines = (run_dir / "monitor.csv").read_text().splitlines()
    if lines[1] != "r,l,t,success,timesteps":
        return False
    rows = [ln.split(",") for ln in lines[2:]]
    steps = [int(r[4]) for r in rows]
    times = [float(r[2]) for r in rows]
    return (
        all(s <= restart_steps for s in steps) and steps == sorted(steps) and times == sorted(times)
    )


def run_checks(trial: dict, run_dir: Path, logs: list[Path], bound: int) -> dict[str, bool]:
    """The checks of the module's docstring, after the resume's preparation of the folder."""
    cfg, restart, said = prepare_resume(run_dir)
    trial["skipped"] = sum("skipped" in line for line in said)
    if restart is None:
        trial.update(resumed_from="none", restart_timesteps="", lost_timesteps="")
        return {"resumed": False}
    trial["resumed_from"] = str(restart.model.relative_to(run_dir))
    trial["restart_timesteps"] = restart.steps
    trial["lost_timesteps"] = trial["timesteps_at_kill"] - restart.steps
    trial["expected_from"] = trial["resumed_from"]
    return {
        "resumed": trial.get("previous_resume_ok", True),
        "lost": 0 <= trial["lost_timesteps"] <= bound,
        "best": check_best(cfg, run_dir, logs),
        "history": check_history(run_dir, restart.steps),
        "monitor": check_monitor(run_dir, restart.steps),
        "clean": not partials(run_dir),
    }


def resumed_as_predicted(run_dir: Path, resumes_before: int, predicted: str | None) -> bool:
    """The session just killed, if it lived long enough to record its resume in run.yaml,
    continued from the point the previous trial's checks found."""
    resumes = _meta(run_dir).get("resumes", [])
    if len(resumes) <= resumes_before or predicted is None:
        return True  # killed before it recorded where it resumed from
    return resumes[-1]["from"] == predicted


# --------------------------------------------------------------------------------------------
# the trials


def trial_once(i: int, phase: str, run_dir: Path, logs: list[Path], rng, state: dict) -> dict:
    """Start (or resume), kill, check; ``state`` carries what the next trial checks."""
    log = run_dir.parent / f"session_{i:02d}.log"
    logs.append(log)
    resume = (run_dir / "config.yaml").is_file()
    resumes_before = len((_meta(run_dir)).get("resumes", [])) if resume else 0
    proc = launch(run_dir, log, resume, WRITE_DELAY_S if phase == "mid-write" else 0.0)
    started = time.perf_counter()
    if not resume:  # a run killed before its first checkpoint has nothing to resume from
        wait_until(lambda: newest_checkpoint(run_dir) > 0, proc)
    trial = {"trial": i, "phase": phase}
    try:
        trial["killed_in"] = kill_at(phase, proc, run_dir, rng)
    except RuntimeError as e:
        trial.update(kill_s=round(time.perf_counter() - started, 2), checks_passed=False)
        return {**trial, "failed": f"ended: {e}; see {log}"}
    trial["kill_s"] = round(time.perf_counter() - started, 2)
    trial["timesteps_at_kill"] = timesteps_shown(run_dir)
    trial["previous_resume_ok"] = not resume or resumed_as_predicted(
        run_dir, resumes_before, state.get("predicted")
    )
    bound = CHECKPOINT_PERIOD
    if phase == "torn-checkpoint":
        tear_newest_checkpoint(run_dir)
        bound = 2 * CHECKPOINT_PERIOD
    checks = run_checks(trial, run_dir, logs, bound)
    state["predicted"] = trial.get("expected_from")
    failed = [name for name, ok in checks.items() if not ok]
    trial.update(checks_passed=not failed, failed=" ".join(failed))
    return trial


def _meta(run_dir: Path) -> dict:
    path = run_dir / "run.yaml"
    return (read_yaml(path) or {}) if path.is_file() else {}


def tear_newest_checkpoint(run_dir: Path) -> None:
    """Cut the newest checkpoint's model to half (what a kill during a write in place
    leaves)."""
    steps = newest_checkpoint(run_dir)
    if steps:
        path = checkpoint_paths(run_dir, steps).model
        path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def finish(run_dir: Path, logs: list[Path]) -> bool:
    """A last session: resume and run to the end (two checkpoint intervals more)."""
    cfg, restart, _ = prepare_resume(run_dir)
    if restart is None:
        return False
    total = restart.steps + 2 * CHECKPOINT_PERIOD
    log = run_dir.parent / "session_final.log"
    logs.append(log)
    cmd = [sys.executable, "-m", "fluidsim_envs.rl.train", "--resume", str(run_dir)]
    cmd += ["--set", f"total_timesteps={total}", "--no-progress-bar"]
    with log.open("w") as out:
        done = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT, cwd=ROOT, timeout=600)
    meta = _meta(run_dir)
    return (
        done.returncode == 0
        and meta.get("num_timesteps") == total
        and check_history(run_dir, total)
        and check_monitor(run_dir, total)
        and check_best(cfg, run_dir, logs)
    )


def main(argv: list[str] | None = None) -> int:
    parser = arguments(__doc__, "4 trials, into build/", "kill_resume.csv")
    parser.add_argument("--trials", type=int, default=20, help="kills (default: %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="of the kill moments and phases")
    parser.add_argument(
        "--work", type=Path, default=ROOT / "build" / "kill_resume", help="the run's folder"
    )
    args = parser.parse_args(argv)
    trials = 4 if args.quick else args.trials
    out = ROOT / "build" / "kill_resume.csv" if args.quick else args.out
    machine = describe()
    shutil.rmtree(args.work, ignore_errors=True)
    args.work.mkdir(parents=True)
    run_dir = args.work / "run"
    rng = np.random.default_rng(args.seed)
    phases = [PHASES[i % len(PHASES)] for i in range(trials)]
    rng.shuffle(phases)
    logs: list[Path] = []
    state: dict = {}
    rows = []
    for i, phase in enumerate(phases):
        row = trial_once(i, phase, run_dir, logs, rng, state)
        rows.append(row)
        print(
            f"trial {i:2d} {phase:<16} killed at {row.get('kill_s', '?'):>6} s "
            f"{row.get('killed_in', '')[:48]:<48} at {row.get('timesteps_at_kill', '?'):>6} "
            f"-> from {row.get('resumed_from', '?')} (lost {row.get('lost_timesteps', '?')}) "
            f"{'ok' if row['checks_passed'] else 'FAILED: ' + row['failed']}",
            flush=True,
        )
    finished = finish(run_dir, logs)
    passed = sum(bool(r["checks_passed"]) for r in rows)
    lost = [r["lost_timesteps"] for r in rows if isinstance(r.get("lost_timesteps"), int)]
    summary = (
        f"{passed}/{len(rows)} trials passed every check; "
        f"lost timesteps: max {max(lost, default=0)}, mean {np.mean(lost) if lost else 0:.0f} "
        f"(checkpoint interval {CHECKPOINT_PERIOD}); "
        f"fallbacks past a damaged state: {sum(r.get('skipped', 0) for r in rows)}; "
        f"final session ran to the end: {'yes' if finished else 'NO'}"
    )
    print(summary)
    write_csv(
        out,
        COLUMNS,
        [[r.get(c, "") for c in COLUMNS] for r in rows],
        [*machine, load_average(), f"summary: {summary}"],
    )
    print(f"written: {out}")
    return 0 if passed == len(rows) and finished else 1


if __name__ == "__main__":
    sys.exit(main())
