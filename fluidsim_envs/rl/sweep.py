"""Sweeps on Ray Tune: a config trained over seeds, or searched over a space, each trial a run
folder as ``fluidsim-train`` writes it.

    fluidsim-sweep CONFIG [--set KEY=VALUE ...] [--seeds N] [--search SPACE.yaml --trials K]
                   [--address ADDRESS] [--cpus-per-trial C [--torch-threads T]]
                   [--sweep-dir DIR]
                   [--target RETURN --wall-budget-s S] [--grace G]
    fluidsim-sweep --resume DIR

(also ``python -m fluidsim_envs.rl.sweep`` and ``python training/sweep.py``).

- ``--seeds N`` alone trains the config with seeds ``seed, seed+1, ... seed+N-1`` (every trial
  to its end: a multi-seed result is not cut short).
- ``--search SPACE.yaml --trials K`` (:mod:`.space`) samples K configs with Optuna's TPE
  (seeded: ``--sampler-seed``), the first of them the config itself (the one to beat, run
  in the same sweep on the same machine; ``--no-base-trial`` leaves it out), and stops the
  weak ones early with ASHA on the evaluation return, its rungs in timesteps from
  ``--grace`` up by threefold; with ``--seeds N``
  each sampled config runs N seeds and Optuna sees their mean (Tune's ``Repeater``; then no
  early stopping, which would cut the seeds unevenly).
- ``--target RETURN --wall-budget-s S`` makes it a race in wall-clock time: a trial stops on
  reaching the return (its best evaluation) or the budget, ASHA's rungs are in seconds, and
  the search maximizes :func:`target_score` (reached beats not reached; among those reached,
  sooner beats later). Wall-clock races are only fair between trials that get the same
  cores: on 2 cores run them one at a time (``--cpus-per-trial 2``).
- Ray: an embedded local Ray by default (nothing to start; every core of this machine),
  a running cluster with ``--address`` (``ray start --head`` on one machine, ``ray start
  --address=HEAD:6379`` on the others; each needs this package installed and the sweep folder
  at the same path, e.g. on NFS). Whether the head wants Ray's token (token authentication:
  ``RAY_AUTH_MODE=token``, or a head started where a token exists) is asked before Ray
  connects (:func:`check_token`): a sweep that would send none, or one the head refuses, is
  an error in one line that says what to set. Each trial takes ``--cpus-per-trial`` cores:
  numba's threads run on that many, torch's on ``--torch-threads`` (default 1: two torch
  threads in a Ray worker trained a 2-CPU trial at a third of the speed, docs/training.md).

The sweep folder holds ``sweep.yaml`` (everything needed to resume: the base config, the
space, the settings), ``runs/<trial>/`` (the run folders), ``tune/`` (Ray Tune's experiment
state), ``status.yaml`` (each trial's outcome as the driver saw it) and the results table,
``results.csv`` and ``results.md`` (:mod:`.sweep_results`), rewritten after each trial.
``--resume DIR`` continues a killed sweep: Tune restores its searcher and scheduler, the
unfinished trials continue from their run folders' newest checkpoint, errored ones stay
errors.
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import shlex
import socket
import sys
import warnings
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import yaml

from . import files
from .config import (
    ConfigError,
    add_overrides_argument,
    config_from_dict,
    config_to_dict,
    load_config,
    read_yaml,
)
from .files import RunError
from .runs import MODEL, checkpoints
from .space import (
    Dimension,
    apply_params,
    base_point,
    check_space,
    find_space,
    parse_space,
)

#: what the searcher and the early stopping maximize: each evaluation's mean return, or with
#: ``--target`` :func:`target_score` (how soon the target was reached in wall-clock time)
METRIC, TARGET_METRIC = "eval_return", "target_score"
#: Repeater's key in a trial's config: which of the N seeds of a sampled config it is
TRIAL_INDEX = "__trial_index__"


class SweepError(RunError):
    """A sweep that cannot start or go on: the message names the setting at fault."""


@dataclass(frozen=True)
class Sweep:
    """A sweep's settings, saved as ``sweep.yaml`` in its folder (what ``--resume`` reads).
    ``base`` is the config (overrides applied) as plain data; ``space`` the search space as
    its YAML mapping (empty: seeds only)."""

    folder: str
    base: dict[str, Any]
    space: dict[str, Any] = field(default_factory=dict)
    seeds: int = 1
    trials: int = 1
    cpus_per_trial: int = 1
    # torch's threads in a trial (numba's take its cpus): one, since two torch threads in a
    # Ray worker beside Ray's own processes trained a 2-CPU trial at a third of
    # fluidsim-train's rate (benchmarks/bench_sweep_trial.py); the policies are small MLPs
    torch_threads: int = 1
    target: float | None = None
    wall_budget_s: float | None = None  # with a target: a trial's wall-clock limit
    grace: float = 0  # ASHA's first rung, in timesteps (wall-clock seconds with a target)
    sampler_seed: int = 0
    base_first: bool = True  # a search's first trial is the config itself
    address: str | None = None
    command_line: str = ""
    started: str = ""

    @property
    def dir(self) -> Path:
        return Path(self.folder)

    @property
    def dimensions(self) -> dict[str, Dimension]:
        return parse_space(self.space, "sweep.yaml: space") if self.space else {}

    @property
    def total_timesteps(self) -> int:
        return int(self.base["total_timesteps"])

    @property
    def metric(self) -> str:
        return METRIC if self.target is None else TARGET_METRIC

    @property
    def time_attr(self) -> str:
        """ASHA's clock: the run's timesteps (reproducible), or its wall-clock seconds when
        the race is to a target in wall-clock time."""
        return "timesteps" if self.target is None else "wall_s"

    @property
    def max_t(self) -> float:
        return self.total_timesteps if self.target is None else self.wall_budget_s

    def save(self) -> None:
        files.write_text(self.dir / "sweep.yaml", yaml.safe_dump(asdict(self), sort_keys=False))

    @classmethod
    def load(cls, folder: Path) -> Sweep:
        path = folder / "sweep.yaml"
        if not path.is_file():
            raise SweepError(f"--resume {folder}: not a sweep folder (no sweep.yaml)")
        raw = read_yaml(path)
        try:
            return cls(**{**raw, "folder": str(folder.absolute())})
        except TypeError as e:  # not a mapping, or keys this version does not know
            raise SweepError(f"{path}: not a sweep this version can resume ({e})") from None


# --------------------------------------------------------------------------------------------
# a trial (runs in a Ray worker)


def trial_seed(sweep: Sweep, params: dict[str, Any]) -> int:
    """A trial's seed: the grid's (``--seeds`` alone), the base seed plus Repeater's index
    (``--search`` with ``--seeds``), or the base seed."""
    if "seed" in params:
        return int(params["seed"])
    return int(sweep.base["seed"]) + int(params.get(TRIAL_INDEX, 0))


def searched(params: dict[str, Any]) -> dict[str, Any]:
    """A trial's sampled config values (without the seed and Repeater's index)."""
    return {k: v for k, v in params.items() if k not in ("seed", TRIAL_INDEX)}


def target_score(best_return: float, wall_s: float, target: float, budget_s: float) -> float:
    """How well a trial races to ``target``: below it, the shortfall of its best return so far
    (negative, in return units); once reached, the share of the wall-clock budget left
    (in [0, 1]). So any trial that reached the target beats any that did not, and among
    those that did, the sooner the better.

    >>> target_score(10.0, 50.0, 12.0, 100.0), target_score(12.5, 50.0, 12.0, 100.0)
    (-2.0, 0.5)
    """
    if best_return < target:
        return best_return - target
    return max(1.0 - wall_s / budget_s, 0.0)


def run_trial(params: dict[str, Any], sweep: Sweep) -> None:
    """Tune's trainable: train the config with ``params`` into ``runs/<trial id>``, reporting
    each evaluation to Tune. A trial Tune restarts (a resumed sweep) continues its run folder
    from its newest checkpoint, or starts it again when it had none."""
    from ray import tune

    from ..threads import numba_pool_size
    from .train import train

    trial_id = tune.get_context().get_trial_id()
    raw = apply_params(sweep.base, searched(params))
    raw["seed"] = trial_seed(sweep, params)
    # the trial's threads (fluidsim_envs.threads, through train): its cpus, torch's share
    raw["torch_threads"] = sweep.torch_threads
    raw["numba_threads"] = min(sweep.cpus_per_trial, numba_pool_size())
    cfg = config_from_dict(raw)  # a combination the space's check could not see fails here
    run_dir = sweep.dir / "runs" / trial_id
    resume = _resumable(run_dir)
    if not resume and run_dir.exists():  # killed before its first checkpoint: start again
        import shutil

        shutil.rmtree(run_dir)
    log = sweep.dir / "runs" / f"{trial_id}.log"

    def say(line: str) -> None:
        with log.open("a") as f:
            f.write(line + "\n")

    last: list[dict[str, Any]] = []  # the run's final evaluation, held until it has finished

    def report(record: dict[str, Any]) -> bool:
        record = {**record, "run_dir": str(run_dir)}
        go_on = record["timesteps"] < cfg.total_timesteps
        if sweep.target is not None:
            best, wall_s = record["best_return"], record["wall_s"]
            record[TARGET_METRIC] = target_score(best, wall_s, sweep.target, sweep.wall_budget_s)
            # a trial that reached the target, or its wall-clock budget, ends here
            go_on = go_on and best < sweep.target and wall_s < sweep.wall_budget_s
        if go_on:
            tune.report(record)
        else:  # told to Tune once the run has finished: a STOP then cannot cut its end short
            last.append(record)
        return go_on

    command = [*shlex.split(sweep.command_line), f"(trial {trial_id})"]
    log.parent.mkdir(parents=True, exist_ok=True)
    train(cfg, run_dir, command, resume=resume, progress_bar=False, say=say, on_eval=report)
    if last:  # Tune may stop the trial here: its run folder is complete (final model, run.yaml)
        tune.report(last[-1])


def _resumable(run_dir: Path) -> bool:
    """A run folder with a saved state to continue from (a checkpoint or its final model)."""
    return (run_dir / "config.yaml").is_file() and (
        any(checkpoints(run_dir)) or (run_dir / MODEL).is_file()
    )


# --------------------------------------------------------------------------------------------
# the driver


def check_address(address: str, timeout_s: float = 5.0) -> None:
    """A clear error when nothing answers at ``address`` (``host:port`` or
    ``ray://host:port``; ``auto`` is left to Ray, which finds a cluster started here)."""
    if address == "auto":
        return
    hostport = address.removeprefix("ray://")
    host, sep, port = hostport.rpartition(":")
    if not sep or not host or not port.isdigit():
        raise SweepError(
            f"--address {address!r}: expected HOST:PORT (the head's GCS address that "
            "`ray start --head` prints, port 6379 by default), ray://HOST:PORT or auto"
        )
    try:
        socket.create_connection((host, int(port)), timeout=timeout_s).close()
    except OSError as e:
        raise SweepError(
            f"--address {address}: nothing answers at {host}:{port} ({e}); start the head "
            f"there with `ray start --head --port={port}`, or leave --address out to run on "
            "this machine alone"
        ) from None
    if not address.startswith("ray://"):  # Ray Client's server is not the GCS: Ray says
        check_token(address, timeout_s)


#: the environment variable that turns Ray's token authentication on (ray >= 2.52)
AUTH_MODE = "RAY_AUTH_MODE"
#: how to get the head's token onto this machine, said by each token error
_TOKEN_HOWTO = (
    "the head's token (`ray get-auth-token` there prints it) in ~/.ray/auth_token, in "
    "RAY_AUTH_TOKEN or in a file named by RAY_AUTH_TOKEN_PATH (docs/training.md, On a cluster)"
)


def ray_token() -> tuple[str | None, str]:
    """This machine's Ray token (None: none) and where it was looked for, in Ray's order:
    ``RAY_AUTH_TOKEN``, the file ``RAY_AUTH_TOKEN_PATH`` names, ``~/.ray/auth_token``
    (Ray trims whitespace, and so does this)."""
    if os.environ.get("RAY_AUTH_TOKEN", "").strip():
        return os.environ["RAY_AUTH_TOKEN"].strip(), "RAY_AUTH_TOKEN"
    named = os.environ.get("RAY_AUTH_TOKEN_PATH")
    path = Path(named) if named else Path.home() / ".ray" / "auth_token"
    try:
        token = path.read_text().strip()
    except OSError:
        return None, str(path)
    return token or None, str(path)


def check_token(address: str, timeout_s: float = 5.0) -> None:
    """A one-line error when the head at ``address`` wants Ray's token and this process
    would not send it (``RAY_AUTH_MODE`` is not ``token``; Ray turns it on by itself only for
    a cluster it finds with ``auto``, never for an address given), or sends one the head
    refuses. Asked once over the GCS's gRPC (its ``GetClusterId``, unauthenticated unless the
    mode is ``token``): Ray's own connect would retry for a while, print a screen of
    ``InvalidAuthToken`` lines, then fail without saying what to set. Anything else the
    head answers is left to Ray."""
    try:
        import grpc  # Ray's own dependency
    except ImportError:
        return
    mode = os.environ.get(AUTH_MODE, "").strip().lower()
    token, where = ray_token() if mode == "token" else (None, "")
    if mode == "token" and token is None:
        raise SweepError(
            f"--address {address}: {AUTH_MODE}=token is set here but no token was found "
            f"(in RAY_AUTH_TOKEN or {where}): put {_TOKEN_HOWTO}"
        )
    metadata = [("authorization", f"Bearer {token}")] if token else []
    with grpc.insecure_channel(address) as channel:
        ask = channel.unary_unary("/ray.rpc.NodeInfoGcsService/GetClusterId")
        try:
            ask(b"", timeout=timeout_s, metadata=metadata)  # an empty GetClusterIdRequest
            return
        except grpc.RpcError as e:
            if e.code() != grpc.StatusCode.UNAUTHENTICATED:
                return
    if token is None:
        raise SweepError(
            f"--address {address}: the Ray head there wants a token (Ray's token "
            f"authentication): set {AUTH_MODE}=token where fluidsim-sweep runs, with "
            f"{_TOKEN_HOWTO}"
        )
    raise SweepError(
        f"--address {address}: the Ray head there refused this machine's token (from "
        f"{where}): put {_TOKEN_HOWTO}"
    )


def start_ray(address: str | None) -> None:
    """Connect to the cluster at ``address``, or start Ray embedded in this process."""
    import ray

    os.environ.setdefault("RAY_AIR_NEW_OUTPUT", "0")  # our lines, not Tune's tables
    import optuna

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    # a resumed trial reports its evaluations from its checkpoint on again: Optuna keeps the
    # first value of each step and warns of the second
    warnings.filterwarnings("ignore", "The reported value is ignored", UserWarning)
    # a choice of mappings (SAC's net_arch) is fine in memory; Optuna warns for its databases
    warnings.filterwarnings("ignore", "Choices for a categorical distribution", UserWarning)
    quiet = {"include_dashboard": False, "log_to_driver": False, "logging_level": "WARNING"}
    if address is None:
        ray.init(num_cpus=os.cpu_count(), **quiet)
        return
    check_address(address)
    refused: tuple[type[Exception], ...] = (ConnectionError, RuntimeError, ValueError)
    try:
        from ray.exceptions import AuthenticationError  # ray >= 2.52: token authentication

        refused += (AuthenticationError,)
    except ImportError:
        pass
    try:
        ray.init(address=address, **quiet)
    except refused as e:
        raise SweepError(f"--address {address}: Ray could not connect ({e})") from None


def _trainable(sweep: Sweep):
    from ray import tune

    trainable = tune.with_parameters(run_trial, sweep=sweep)
    return tune.with_resources(trainable, {"cpu": sweep.cpus_per_trial})


def _tune_config(sweep: Sweep, concurrent: int):
    """Seeds alone: a grid, every trial to its end. A search: Optuna's TPE, with ASHA (one
    seed) or with each sampled config repeated over the seeds (Repeater, no early stop)."""
    from ray import tune
    from ray.tune.schedulers import ASHAScheduler, FIFOScheduler

    if not sweep.space:
        return tune.TuneConfig(
            metric=sweep.metric, mode="max", num_samples=1, max_concurrent_trials=concurrent
        )
    import optuna
    from ray.tune.search import Repeater
    from ray.tune.search.optuna import OptunaSearch

    first = [base_point(sweep.dimensions, sweep.base)[0]] if sweep.base_first else None
    searcher = OptunaSearch(
        sampler=optuna.samplers.TPESampler(seed=sweep.sampler_seed), points_to_evaluate=first
    )
    scheduler = ASHAScheduler(
        time_attr=sweep.time_attr,
        # one past the run's end: a trial that reaches it returns by itself (final model,
        # run.yaml) rather than being stopped there by Tune
        max_t=sweep.max_t + 1,
        grace_period=sweep.grace,
        reduction_factor=3,
    )
    if sweep.seeds > 1:
        searcher, scheduler = Repeater(searcher, repeat=sweep.seeds), FIFOScheduler()
    return tune.TuneConfig(
        metric=sweep.metric,
        mode="max",
        search_alg=searcher,
        scheduler=scheduler,
        num_samples=sweep.trials * sweep.seeds,
        max_concurrent_trials=concurrent,
    )


def _param_space(sweep: Sweep) -> dict[str, Any]:
    from ray import tune

    if not sweep.space:
        first = int(sweep.base["seed"])
        return {"seed": tune.grid_search(list(range(first, first + sweep.seeds)))}
    return {key: dim.tune_domain() for key, dim in sweep.dimensions.items()}


def run_sweep(sweep: Sweep, resume: bool, say: Callable[[str], None] = print) -> Path:
    """Run (or, with ``resume``, continue) the sweep; returns the results table's path."""
    import ray
    from ray import tune

    from .sweep_results import SweepProgress, closing_lines, read_status, write_results

    start_ray(sweep.address)
    try:
        cpus = int(ray.cluster_resources().get("CPU", 1))
        concurrent = max(cpus // sweep.cpus_per_trial, 1)
        if sweep.cpus_per_trial > cpus:
            raise SweepError(
                f"--cpus-per-trial {sweep.cpus_per_trial}: the cluster has {cpus} CPUs"
            )
        say(_plan(sweep, cpus, concurrent, resume))
        if sweep.space and sweep.base_first and not resume:
            point, notes = base_point(sweep.dimensions, sweep.base)
            say("the first trial is the config itself" + "".join(f"\n  {n}" for n in notes))
        progress = SweepProgress(sweep, say)
        tune_dir = sweep.dir / "tune"
        if resume and tune.Tuner.can_restore(str(tune_dir)):
            tuner = tune.Tuner.restore(
                str(tune_dir), _trainable(sweep), resume_unfinished=True, resume_errored=False
            )
        else:
            tuner = tune.Tuner(
                _trainable(sweep),
                param_space=_param_space(sweep),
                tune_config=_tune_config(sweep, concurrent),
                run_config=tune.RunConfig(
                    name="tune",
                    storage_path=str(sweep.dir),
                    callbacks=[progress],
                    verbose=0,
                    # a trial whose worker died (a lost machine) starts again, and continues
                    # its run folder from the newest checkpoint
                    failure_config=tune.FailureConfig(max_failures=2),
                ),
            )
        results = tuner.fit()
    finally:
        ray.shutdown()
    table = write_results(sweep)
    for line in closing_lines(sweep, table):
        say(line)
    # Ctrl-C: Tune saves its state and returns from fit() as if done; say it is not
    running = [t for t, st in read_status(sweep.dir).items() if st.get("status") == "running"]
    if running or len(results) < _expected_trials(sweep):
        raise KeyboardInterrupt
    return table


def _expected_trials(sweep: Sweep) -> int:
    return sweep.trials * sweep.seeds if sweep.space else sweep.seeds


def _plan(sweep: Sweep, cpus: int, concurrent: int, resume: bool) -> str:
    what = (
        f"{sweep.trials} configs from {len(sweep.space)} searched keys"
        + (f" x {sweep.seeds} seeds" if sweep.seeds > 1 else "")
        if sweep.space
        else f"{sweep.seeds} seeds"
    )
    unit = "steps" if sweep.target is None else "s"
    stop = (
        f"ASHA from {sweep.grace:,.0f} {unit}"
        if sweep.space and sweep.seeds == 1
        else "every trial to its end"
    )
    target = (
        f"; racing to return {sweep.target} within {sweep.wall_budget_s:,.0f} s a trial"
        if sweep.target is not None
        else ""
    )
    verb = "resuming" if resume else "sweeping"
    return (
        f"{verb} {sweep.base['env_id']} {sweep.base['algorithm']['name'].upper()}: {what}, "
        f"{sweep.total_timesteps:,} steps each ({stop}{target}); {concurrent} at a time on "
        f"{cpus} CPUs, {sweep.cpus_per_trial} per trial; into {sweep.dir}"
    )


# --------------------------------------------------------------------------------------------
# the command line


def parse_args(argv: list[str] | None, prog: str) -> argparse.Namespace:
    return build_parser(prog).parse_args(argv)


def build_parser(prog: str) -> argparse.ArgumentParser:
    """The command line's parser (this module imports Ray only where a sweep runs, so
    ``fluidsim-sweep --help`` works without the sweep extra)."""
    from .config import shipped_configs

    example = next(iter(shipped_configs()))
    parser = argparse.ArgumentParser(
        prog=prog,
        description="Train a config over seeds, or search its hyperparameters, on Ray Tune.",
        epilog=f"Examples: {prog} {example} --seeds 5; {prog} {example} --search ppo "
        "--trials 16. A cluster: `ray start --head` on one machine, `ray start "
        "--address=HEAD:6379` on the others, then --address HEAD:6379 (with Ray's token "
        "authentication: RAY_AUTH_MODE=token and the head's token on every machine).",
    )
    parser.add_argument("config", nargs="?", help="a config YAML file or a shipped config's name")
    add_overrides_argument(parser, "override config keys for every trial (as fluidsim-train --set)")
    parser.add_argument("--seeds", type=int, default=1, help="seeds per config (default 1)")
    parser.add_argument(
        "--search",
        type=Path,
        metavar="SPACE.yaml",
        help="a search space file, or a shipped one's name (ppo, sac)",
    )
    parser.add_argument("--trials", type=int, help="configs to sample from --search (default 8)")
    parser.add_argument(
        "--address",
        help="a running Ray cluster's HOST:PORT (default: local); a head with token "
        "authentication needs RAY_AUTH_MODE=token here and its token (docs/training.md)",
    )
    parser.add_argument("--cpus-per-trial", type=int, default=1, help="cores a trial takes")
    parser.add_argument(
        "--torch-threads",
        type=int,
        default=1,
        help="torch's threads in a trial (default 1: more trained a 2-CPU trial at a third "
        "of the speed, docs/training.md); numba's threads take --cpus-per-trial",
    )
    parser.add_argument("--sweep-dir", type=Path, help="default sweeps/<env>-<algo>-<time>")
    parser.add_argument(
        "--resume",
        type=Path,
        metavar="DIR",
        help="continue this sweep (Ray Tune restores its state from pickles: only a sweep "
        "folder your machine wrote)",
    )
    parser.add_argument(
        "--target",
        type=float,
        help="race to this evaluation return: a trial stops on reaching it, and the search "
        "looks for the config that reaches it soonest in wall-clock time",
    )
    parser.add_argument(
        "--wall-budget-s",
        type=float,
        help="with --target: a trial's wall-clock limit in seconds (required with --target)",
    )
    parser.add_argument(
        "--grace",
        type=float,
        help="ASHA's first rung: timesteps (default a ninth of the run, at least one "
        "evaluation period), or with --target seconds (default a ninth of the budget)",
    )
    parser.add_argument("--sampler-seed", type=int, default=0, help="Optuna's TPE seed")
    parser.add_argument(
        "--no-base-trial",
        action="store_true",
        help="do not start a search with the config itself (its first trial by default: "
        "the config the search must beat, run in the same sweep)",
    )
    return parser


def sweep_from_args(args: argparse.Namespace, command: list[str]) -> Sweep:
    """The sweep the arguments describe, checked (nothing is written or started)."""
    if args.seeds < 1:
        raise SweepError(f"--seeds {args.seeds}: a sweep needs at least one seed per config")
    if args.cpus_per_trial < 1:
        raise SweepError(f"--cpus-per-trial {args.cpus_per_trial}: at least 1")
    if not 1 <= args.torch_threads <= args.cpus_per_trial:
        raise SweepError(
            f"--torch-threads {args.torch_threads}: from 1 to --cpus-per-trial "
            f"({args.cpus_per_trial})"
        )
    if args.trials is not None and args.search is None:
        raise SweepError(f"--trials {args.trials}: only with --search SPACE.yaml")
    trials = 8 if args.trials is None else args.trials
    if trials < 1:
        raise SweepError(f"--trials {trials}: at least 1")
    if args.config is None:
        raise SweepError("a config is required (a file or a shipped config's name), or --resume")
    cfg = load_config(args.config, args.overrides)
    if cfg.eval.freq <= 0:
        raise SweepError("eval.freq is 0: a sweep ranks and stops trials by their evaluations")
    base = config_to_dict(cfg)
    space: dict[str, Any] = {}
    if args.search is not None:
        path = find_space(args.search)
        space = read_yaml(path)
        check_space(parse_space(space, str(path)), base, str(path))
    for flag, value in (("--target", args.target), ("--wall-budget-s", args.wall_budget_s)):
        if value is not None and not math.isfinite(value):
            raise SweepError(f"{flag} {value}: must be a finite number")
    budget = _wall_budget(args)
    longest = cfg.total_timesteps if budget is None else budget
    grace = args.grace if args.grace is not None else _default_grace(cfg, budget)
    if not 0 < grace <= longest:  # also NaN
        what = "total_timesteps" if budget is None else "--wall-budget-s"
        named = f"--grace {args.grace}" if args.grace is not None else f"eval.freq {grace:,}"
        raise SweepError(f"{named}: ASHA's first rung must be in (0, {what} = {longest:,}]")
    if args.address is not None:
        check_address(args.address)
    stamp = datetime.datetime.now().strftime("%Y%m%d-%H%M%S")
    folder = args.sweep_dir or Path("sweeps") / f"{cfg.env_name}-{cfg.algorithm.name}-{stamp}"
    files.check_writable_folder(folder, "--sweep-dir")
    if (folder / "sweep.yaml").exists():
        raise SweepError(f"{folder} already holds a sweep (continue it with --resume {folder})")
    return Sweep(
        folder=str(folder.absolute()),
        base=base,
        space=space,
        seeds=args.seeds,
        trials=trials if space else 1,
        cpus_per_trial=args.cpus_per_trial,
        torch_threads=args.torch_threads,
        target=args.target,
        wall_budget_s=budget,
        grace=grace,
        sampler_seed=args.sampler_seed,
        base_first=not args.no_base_trial,
        address=args.address,
        command_line=shlex.join(command),
        started=datetime.datetime.now().isoformat(timespec="seconds"),
    )


def _wall_budget(args: argparse.Namespace) -> float | None:
    """``--wall-budget-s``, which comes with ``--target`` and only with it."""
    if args.target is None:
        if args.wall_budget_s is not None:
            raise SweepError(f"--wall-budget-s {args.wall_budget_s}: only with --target")
        return None
    if args.wall_budget_s is None or not args.wall_budget_s > 0:
        raise SweepError(
            f"--target {args.target} needs --wall-budget-s S > 0 (a trial's wall-clock limit), "
            f"got {args.wall_budget_s}"
        )
    return float(args.wall_budget_s)


def _default_grace(cfg, budget: float | None) -> float:
    if budget is not None:
        return budget / 9
    return max(cfg.total_timesteps // 9, cfg.eval.freq)


def _warm(sweep: Sweep, say) -> None:
    """Build the env once here: a cold numba cache compiles now, once, and says so, not in
    every trial at the same time."""
    import gymnasium as gym

    import fluidsim_envs  # noqa: F401  (registers the ids)

    say(f"checking {sweep.base['env_id']} (its kernels compile here if the cache is cold)")
    env = gym.make_vec(sweep.base["env_id"], num_envs=1, **sweep.base["env_kwargs"])
    env.reset(seed=0)
    env.step(env.action_space.sample())
    env.close()


#: the options a resumed sweep takes from its sweep.yaml, with their defaults
_RESUME_FIXED = {
    "overrides": [],
    "seeds": 1,
    "search": None,
    "trials": None,
    "address": None,
    "cpus_per_trial": 1,
    "torch_threads": 1,
    "sweep_dir": None,
    "target": None,
    "wall_budget_s": None,
    "grace": None,
    "sampler_seed": 0,
    "no_base_trial": False,
}


def main(argv: list[str] | None = None, prog: str = "fluidsim-sweep") -> int:
    args = parse_args(argv, prog)
    command = [*prog.split(), *(sys.argv[1:] if argv is None else argv)]
    sweep = None
    try:
        if args.resume is not None:
            given = [f for f, default in _RESUME_FIXED.items() if getattr(args, f) != default]
            if args.config is not None or given:
                flags = ", ".join("--" + f.replace("_", "-") for f in given) or "a config"
                raise SweepError(
                    f"--resume DIR takes its settings from DIR/sweep.yaml, not from {flags}"
                )
            sweep = Sweep.load(args.resume)
        else:
            sweep = sweep_from_args(args, command)
            sweep.dir.mkdir(parents=True, exist_ok=True)
            sweep.save()
        _warm(sweep, print)
        run_sweep(sweep, resume=args.resume is not None)
    except (ConfigError, RunError) as e:
        print(f"{prog}: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        if sweep is not None and (sweep.dir / "sweep.yaml").is_file():
            print(f"\ninterrupted; continue with {prog} --resume {shlex.quote(str(sweep.dir))}")
        return 130
    return 0


__all__ = ["Sweep", "SweepError", "main", "run_sweep", "run_trial"]

if __name__ == "__main__":
    sys.exit(main(prog="python -m fluidsim_envs.rl.sweep"))
