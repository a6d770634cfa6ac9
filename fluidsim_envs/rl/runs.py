"""What a run folder keeps across kills and resumes, and how ``--resume`` finds its way back.

- **Saved states** (:func:`save_state`): a checkpoint, the final model or the state saved on
  Ctrl-C is its replay buffer (when kept), its normalization statistics, then its model, each
  a file of numbers and plain metadata (:mod:`.saved`) written atomically (:mod:`.files`),
  the model last: a model under its final name means the files before it are whole.
  :func:`restart_point` takes the newest saved state whose model and statistics both read,
  and says on stderr which newer ones it skipped and why.
- **The evaluation history** (:class:`EvalLog`): ``eval/evaluations.npz`` (SB3's arrays) and
  ``eval/history.csv`` (a row per evaluation), both written whole from the same arrays after
  each evaluation; a resume drops the evaluations past its restart point and goes on.
- **The best model** (:class:`BestModel`): ``best/best_model.safetensors``, the normalization
  statistics it was evaluated with and ``best/best.yaml`` (its score), replaced only by a
  better evaluation, whatever the resumes in between.
- **Training episodes** (``monitor.csv``): each row carries the run's timesteps when its
  episode ended (:class:`~.callbacks.RunMonitor`), so :func:`trim_monitor` drops exactly the
  episodes after the restart point.
"""

from __future__ import annotations

import csv
import io
import math
import os
import re
import secrets
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from . import files, saved
from .config import ConfigError, read_yaml
from .files import RunError

CHECKPOINT_PREFIX = "model"
MODEL = f"model{saved.SUFFIX}"  # the final model and statistics (and replay buffer, kept)
STATS = f"vecnormalize{saved.SUFFIX}"
REPLAY = f"replay_buffer{saved.SUFFIX}"
#: SB3's pickled files of each of those, which an older version wrote: read only behind
#: --allow-pickle (:mod:`.saved`)
PICKLED = {MODEL: "model.zip", STATS: "vecnormalize.pkl", REPLAY: "replay_buffer.pkl"}
PICKLED_BEST = "best_model.zip"  # and best/'s statistics: PICKLED[STATS]
EVAL_HISTORY_COLUMNS = (
    "timesteps",
    "mean_return",
    "std_return",
    "mean_length",
    "success_rate",
    "wall_s",  # the run's wall-clock seconds at the evaluation's end, resumes included
)
MONITOR_STEPS = "timesteps"  # monitor.csv's column: the run's timesteps at the episode's end


def warn(text: str) -> None:
    print(text, file=sys.stderr, flush=True)


# --------------------------------------------------------------------------------------------
# saved states (checkpoints, the final model)


@dataclass(frozen=True)
class Restart:
    """Where ``--resume`` continues from: a saved model, its statistics and replay buffer
    (either may be absent), and the timesteps it had done."""

    steps: int
    model: Path
    stats: Path
    replay: Path


def checkpoint_stats(model_path: Path) -> Path:
    """The normalization statistics saved with a checkpoint (SB3's naming)."""
    steps = model_path.name[len(CHECKPOINT_PREFIX) + 1 :]
    return model_path.with_name(f"{CHECKPOINT_PREFIX}_vecnormalize_{steps}")


def checkpoint_paths(run_dir: Path, steps: int) -> Restart:
    """Where a checkpoint at ``steps`` goes (SB3's CheckpointCallback's naming)."""
    model = run_dir / "checkpoints" / f"{CHECKPOINT_PREFIX}_{steps}_steps{saved.SUFFIX}"
    replay = model.with_name(f"{CHECKPOINT_PREFIX}_replay_buffer_{steps}_steps{saved.SUFFIX}")
    return Restart(steps, model, checkpoint_stats(model), replay)


def final_paths(run_dir: Path, steps: int) -> Restart:
    """Where the final model of a run at ``steps`` goes."""
    return Restart(steps, run_dir / MODEL, run_dir / STATS, run_dir / REPLAY)


def checkpoints(run_dir: Path, suffix: str = saved.SUFFIX) -> list[tuple[int, Path]]:
    """(timesteps, model path) of every checkpoint in ``run_dir/checkpoints``, newest first
    (``suffix``: ``.zip``, those of SB3's format)."""
    found = []
    for path in (run_dir / "checkpoints").glob(f"{CHECKPOINT_PREFIX}_*_steps{suffix}"):
        m = re.fullmatch(rf"{CHECKPOINT_PREFIX}_(\d+)_steps{re.escape(suffix)}", path.name)
        if m:
            found.append((int(m.group(1)), path))
    return sorted(found, reverse=True)


def save_state(model, where: Restart, replay: bool) -> None:
    """The model, its normalization statistics and (``replay``, off-policy) its replay
    buffer at the paths ``where`` names, each written atomically and the model last: a model
    under its final name says the files before it are complete."""
    where.model.parent.mkdir(parents=True, exist_ok=True)
    if replay and getattr(model, "replay_buffer", None) is not None:
        files.write_with(where.replay, lambda tmp: saved.save_replay(model.replay_buffer, tmp))
    vec_normalize = model.get_vec_normalize_env()
    if vec_normalize is not None:
        files.write_with(where.stats, lambda tmp: saved.save_statistics(vec_normalize, tmp))
    files.write_with(where.model, lambda tmp: saved.save_model(model, tmp))


def saved_timesteps(path: Path) -> int | None:
    """The timesteps a saved model says it has done (its header alone), or None when it
    cannot be read."""
    try:
        return saved.model_header(path)["num_timesteps"]
    except RunError:
        return None


def saved_states(run_dir: Path) -> list[Restart]:
    """The run's saved states, newest first: its checkpoints and its final model (the
    timesteps in its header; a damaged one sorts first, to be reported)."""
    found = [checkpoint_paths(run_dir, steps) for steps, _ in checkpoints(run_dir)]
    final = run_dir / MODEL
    if final.is_file():
        steps = saved_timesteps(final)
        found.append(final_paths(run_dir, steps if steps is not None else -1))
    # a final model that cannot say its timesteps is examined (and reported) first
    return sorted(found, key=lambda r: math.inf if r.steps < 0 else r.steps, reverse=True)


def state_problem(restart: Restart, normalize: bool, replay: bool) -> str | None:
    """Why ``restart`` cannot be resumed from (its model, or with ``normalize`` its
    statistics, or a kept replay buffer, does not read), or None."""
    needed = [(restart.model, "model")]
    if normalize:
        needed.append((restart.stats, "statistics"))
    if replay and restart.replay.is_file():
        needed.append((restart.replay, "replay"))
    for path, kind in needed:
        if kind == "statistics" and not path.is_file():
            return f"its statistics {path.name} are missing"
        try:  # the header (safetensors checks then that the file holds all it declares)
            header = saved.read_header(path, kind)
        except RunError as e:
            return f"{path.name} does not load: {str(e).removeprefix(f'{path}: ')}"
        if header.get("policy_only"):
            return f"{path.name} {saved.POLICY_ONLY}"
    if restart.steps < 0:
        return "the model holds no timesteps"
    return None


def pickled_states(run_dir: Path) -> list[Path]:
    """The model files an older version saved in SB3's pickled format (the final model,
    the checkpoints), which ``--resume`` does not read."""
    found = [p for _, p in checkpoints(run_dir, ".zip")]
    return [run_dir / PICKLED[MODEL]] * (run_dir / PICKLED[MODEL]).is_file() + found


def restart_point(
    run_dir: Path, normalize: bool = True, replay: bool = False, say=warn
) -> Restart | None:
    """The newest saved state of a run that loads (its newest readable checkpoint, or its
    final model when that went further: a finished run continued with a larger
    ``total_timesteps``); each newer one that does not load (a kill during its write, with a
    version that wrote in place) is skipped, and ``say`` hears which and why."""
    for restart in saved_states(run_dir):
        problem = state_problem(restart, normalize, replay)
        if problem is None:
            return restart
        say(f"--resume: skipped {restart.model.relative_to(run_dir)}: {problem}")
    return None


# --------------------------------------------------------------------------------------------
# the evaluation history


@dataclass
class EvalLog:
    """The run's evaluations: per evaluation its timesteps, the run's wall-clock seconds at its
    end (NaN: not recorded, an older version's file), and each episode's return, length and
    success (NaN where an evaluation had fewer episodes or no success flag).
    :meth:`save` writes ``evaluations.npz`` (SB3's keys) and ``history.csv`` from them."""

    folder: Path
    timesteps: list[int] = field(default_factory=list)
    results: list[list[float]] = field(default_factory=list)
    lengths: list[list[float]] = field(default_factory=list)
    successes: list[list[float]] = field(default_factory=list)
    wall_s: list[float] = field(default_factory=list)

    @property
    def npz(self) -> Path:
        return self.folder / "evaluations.npz"

    @property
    def csv(self) -> Path:
        return self.folder / "history.csv"

    @classmethod
    def load(cls, folder: Path, say=warn) -> EvalLog:
        """The history saved in ``folder``, or an empty one (none saved, or unreadable: said)."""
        log = cls(folder)
        if not log.npz.is_file():
            return log
        try:
            with np.load(log.npz) as data:
                arrays = {k: data[k] for k in data.files}
            log.timesteps = [int(t) for t in arrays["timesteps"]]
            log.results = [list(map(float, r)) for r in arrays["results"]]
            log.lengths = [list(map(float, r)) for r in arrays["ep_lengths"]]
            ok = "successes" in arrays and len(arrays["successes"]) == len(log.timesteps)
            rows = arrays["successes"] if ok else [[] for _ in log.timesteps]
            log.successes = [list(map(float, r)) for r in rows]
            timed = "wall_s" in arrays and len(arrays["wall_s"]) == len(log.timesteps)
            log.wall_s = [float(t) for t in arrays["wall_s"]] if timed else [math.nan] * len(rows)
        except Exception as e:  # a damaged file (not one of ours: ours are written whole)
            say(f"--resume: {log.npz} does not load ({type(e).__name__}: {e}); history restarts")
            return cls(folder)
        return log

    def trim(self, steps: int) -> None:
        """Drop the evaluations made after ``steps`` (a restart point's timesteps)."""
        keep = [i for i, t in enumerate(self.timesteps) if t <= steps]
        for name in ("timesteps", "results", "lengths", "successes", "wall_s"):
            values = getattr(self, name)
            setattr(self, name, [values[i] for i in keep])

    def add(self, steps: int, returns, lengths, successes, wall_s: float = math.nan) -> None:
        self.timesteps.append(int(steps))
        self.wall_s.append(float(wall_s))
        self.results.append([float(r) for r in returns])
        self.lengths.append([float(n) for n in lengths])
        self.successes.append([float(s) for s in successes])

    def best_mean(self) -> float | None:
        """The best mean return of the evaluations (None: there are none)."""
        means = [_mean(r) for r in self.results]
        return max(means) if means else None

    def rows(self) -> list[list[float]]:
        """``history.csv``'s rows (:data:`EVAL_HISTORY_COLUMNS`)."""
        out = []
        for t, r, n, s, w in zip(
            self.timesteps, self.results, self.lengths, self.successes, self.wall_s, strict=True
        ):
            out.append([t, _mean(r), _std(r), _mean(n), _mean(s), round(w, 2)])
        return out

    def save(self) -> None:
        """``evaluations.npz`` then ``history.csv``, each written whole."""
        self.folder.mkdir(parents=True, exist_ok=True)
        arrays = {
            "timesteps": np.asarray(self.timesteps, dtype=np.int64),
            "results": _padded(self.results),
            "ep_lengths": _padded(self.lengths),
            "wall_s": np.asarray(self.wall_s, dtype=np.float64),
        }
        if any(self.successes):
            arrays["successes"] = _padded(self.successes)
        files.write_with(self.npz, lambda tmp: np.savez(tmp, **arrays))
        text = io.StringIO()
        writer = csv.writer(text)
        writer.writerow(EVAL_HISTORY_COLUMNS)
        writer.writerows(self.rows())
        files.write_text(self.csv, text.getvalue())


def read_history(run_dir: Path) -> list[dict[str, float]]:
    """A run's ``eval/history.csv`` as rows of numbers (NaN where a value is missing or not a
    number; no rows without the file): what sweeps and studies read of a run's evaluations."""
    path = run_dir / "eval" / "history.csv"
    if not path.is_file():
        return []
    with path.open() as f:
        return [{k: _float_or_nan(v) for k, v in r.items()} for r in csv.DictReader(f)]


def _float_or_nan(text: str | None) -> float:
    value = _float_or_none(text)
    return math.nan if value is None else value


def _padded(rows: list[list[float]]) -> np.ndarray:
    """Rows as one 2-D array; rows of unequal length (eval.n_episodes changed on a resume)
    are padded with NaN."""
    width = max((len(r) for r in rows), default=0)
    out = np.full((len(rows), width), np.nan)
    for i, r in enumerate(rows):
        out[i, : len(r)] = r
    return out


def _finite(values) -> np.ndarray:
    x = np.asarray(values, dtype=float)
    return x[~np.isnan(x)]


def _mean(values) -> float:
    x = _finite(values)
    return float(np.mean(x)) if x.size else math.nan


def _std(values) -> float:
    x = _finite(values)
    return float(np.std(x)) if x.size else math.nan


# --------------------------------------------------------------------------------------------
# the best model


class BestModel:
    """``best/``: the best evaluated model (``best_model.safetensors``), the normalization
    statistics it was evaluated with (``vecnormalize.safetensors``) and its score
    (``best.yaml``: mean return, timesteps, when).

    A new best is written in three steps so that a kill at any moment leaves the three files
    of one evaluation together: (1) the model and statistics go to pending files named with a
    fresh token; (2) ``best.yaml`` is written with the new score and that token (the commit);
    (3) the pending files take the final names. :meth:`recover` (on every start) completes
    step 3 for the committed token and deletes pending files of any other (a kill before the
    commit: the old best stands, whole).
    """

    MODEL = f"best_model{saved.SUFFIX}"
    STATS = STATS
    SCORE = "best.yaml"

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.record: dict[str, Any] = {}

    @property
    def score(self) -> float:
        """The best mean return so far (minus infinity before the first evaluation)."""
        return float(self.record.get("mean_return", -math.inf))

    @classmethod
    def open(cls, folder: Path, history: EvalLog | None = None, say=warn) -> BestModel:
        """The best model of a run being resumed: pending writes completed or dropped, its
        score read back. A run written before ``best.yaml`` existed takes the best mean of
        ``history`` (read before it is trimmed: the best may come from after the restart)."""
        best = cls(folder)
        best.recover()
        best.set_aside_if_damaged(say)
        path = folder / cls.SCORE
        if path.is_file():
            try:
                record = read_yaml(path)
            except ConfigError as e:
                raise RunError(f"{path}: unreadable best score ({e})") from None
            best.record = record if isinstance(record, dict) else {}
        elif (folder / cls.MODEL).is_file() and history is not None:
            score = history.best_mean()
            if score is not None:
                say(
                    f"--resume: {folder / cls.MODEL} has no {cls.SCORE}: its score is taken as "
                    f"the best of eval/evaluations.npz, {score:.6g}"
                )
                best.record = {"mean_return": score}
                files.write_text(path, yaml.safe_dump(best.record, sort_keys=False))
        return best

    def set_aside_if_damaged(self, say=warn) -> None:
        """A best model or statistics that does not read (a disk fault, a hand edit) is moved
        with its score into ``best/damaged-<token>/``, said, and the next evaluation makes a
        new best (the run goes on: the damaged files are kept for a look, never loaded)."""
        problem = None
        for name, kind in ((self.MODEL, "model"), (self.STATS, "statistics")):
            path = self.folder / name
            if path.is_file():
                try:
                    saved.read_header(path, kind)
                except RunError as e:
                    problem = problem or str(e)
        if problem is None:
            return
        aside = self.folder / f"damaged-{secrets.token_hex(4)}"
        aside.mkdir()
        for name in (self.MODEL, self.STATS, self.SCORE):
            if (self.folder / name).is_file():
                os.replace(self.folder / name, aside / name)
        say(f"--resume: {problem}; the best model is set aside in {aside} and the next "
            "evaluation makes a new one")  # fmt: skip

    def _pending(self) -> list[tuple[str, str, Path]]:
        """(token, final name, path) of each pending file."""
        out = []
        for path in self.folder.glob(".pending-*"):
            token, _, name = path.name.removeprefix(".pending-").partition("-")
            out.append((token, name, path))
        return out

    def committed(self) -> tuple[Path, Path]:
        """The model and statistics paths of the committed best, read without changing
        anything (what an evaluation beside a running trainer may do): the pending files of
        the committed token where a kill (or the trainer, now) is between steps 2 and 3,
        else the final names."""
        paths = {self.MODEL: self.folder / self.MODEL, self.STATS: self.folder / self.STATS}
        path = self.folder / self.SCORE
        try:
            committed = (read_yaml(path) or {}).get("commit") if path.is_file() else None
        except (ConfigError, AttributeError):
            committed = None
        for token, name, pending in self._pending():
            if token == committed and name in paths:
                paths[name] = pending
        return paths[self.MODEL], paths[self.STATS]

    def recover(self) -> None:
        """Finish the commit a kill interrupted (step 3 of a new best), drop uncommitted
        files."""
        if not self.folder.is_dir():
            return
        path = self.folder / self.SCORE
        committed = None
        if path.is_file():
            try:
                committed = (read_yaml(path) or {}).get("commit")
            except (ConfigError, AttributeError):
                committed = None
        for token, name, pending in self._pending():
            if token == committed and name in (self.MODEL, self.STATS):
                os.replace(pending, self.folder / name)
            else:
                pending.unlink(missing_ok=True)

    def save(self, model, record: dict[str, Any]) -> None:
        """``model`` (with the statistics its env normalizes with) as the new best, scored by
        ``record`` (``mean_return`` at least)."""
        self.folder.mkdir(parents=True, exist_ok=True)
        token = secrets.token_hex(6)
        pending = {self.MODEL: self.folder / f".pending-{token}-{self.MODEL}"}
        files.write_with(pending[self.MODEL], lambda tmp: saved.save_model(model, tmp))
        vec_normalize = model.get_vec_normalize_env()
        if vec_normalize is not None:
            pending[self.STATS] = self.folder / f".pending-{token}-{self.STATS}"
            files.write_with(
                pending[self.STATS], lambda tmp: saved.save_statistics(vec_normalize, tmp)
            )
        record = {**record, "commit": token}
        files.write_text(self.folder / self.SCORE, yaml.safe_dump(record, sort_keys=False))
        for name, path in pending.items():
            os.replace(path, self.folder / name)
        self.record = record


# --------------------------------------------------------------------------------------------
# training episodes (monitor.csv)


def trim_monitor(path: Path, steps: int, say=warn) -> float:
    """Drop the episodes of ``monitor.csv`` that ended after ``steps`` (a restart point's
    timesteps) and a last row a kill cut short; return the time column's last kept value,
    which the resumed run's times go on from.

    Each row's episode is placed by the run's timesteps at its end (its ``timesteps``
    column), not by wall time or by a row count kept with the checkpoint: timesteps are what
    a checkpoint is named by, they do not depend on clocks or file times, and a row written
    after its checkpoint (the same step) is placed right. A file of an older version, without
    the column, keeps its rows, with the column added empty."""
    if not path.is_file():
        return 0.0
    lines = path.read_text().splitlines(keepends=True)
    if lines and not lines[-1].endswith("\n"):
        lines.pop()  # a row a kill cut short
    if len(lines) < 2:  # no header row: the resumed run starts the file again, whole
        path.unlink()
        return 0.0
    header, rows = lines[:2], list(csv.DictReader(lines[1:]))
    columns = header[1].strip().split(",")
    if MONITOR_STEPS not in columns:
        say(
            f"--resume: {path} has no {MONITOR_STEPS} column (an older version wrote it): "
            "its rows are kept"
        )
        columns.append(MONITOR_STEPS)
        header[1] = ",".join(columns) + "\n"
        kept = rows
    else:
        kept = [r for r in rows if _int_or_none(r.get(MONITOR_STEPS)) is not None]
        kept = [r for r in kept if int(r[MONITOR_STEPS]) <= steps]
    out = io.StringIO()
    out.writelines(header)
    writer = csv.DictWriter(out, columns, extrasaction="ignore", lineterminator="\n")
    writer.writerows(kept)
    files.write_text(path, out.getvalue())
    times = [float(r["t"]) for r in kept if _float_or_none(r.get("t")) is not None]
    return max(times, default=0.0)


def _int_or_none(text: str | None) -> int | None:
    try:
        return int(text)
    except (TypeError, ValueError):
        return None


def _float_or_none(text: str | None) -> float | None:
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def trim_logs(run_dir: Path, restart: Restart, say=warn) -> float:
    """Drop what a run logged after its restart point, so a resumed run's history does not
    hold the lost stretch twice: evaluations past its timesteps (``eval/``) and training
    episodes that ended after it (``monitor.csv``). Returns the monitor's time offset."""
    log = EvalLog.load(run_dir / "eval", say)
    # an evaluations.npz that is gone or does not load leaves history.csv as it is (saving
    # the empty log would write an empty history over it)
    if log.timesteps or (log.npz.is_file() and not log.csv.is_file()):
        log.trim(restart.steps)
        log.save()
    return trim_monitor(run_dir / "monitor.csv", restart.steps, say)


def read_run_meta(run_dir: Path) -> dict[str, Any]:
    """``run.yaml`` (empty when absent)."""
    path = run_dir / "run.yaml"
    if not path.is_file():
        return {}
    meta = read_yaml(path)
    if not isinstance(meta, dict):
        raise RunError(f"{path}: expected a mapping, got {meta!r}")
    return meta


__all__ = [
    "CHECKPOINT_PREFIX",
    "EVAL_HISTORY_COLUMNS",
    "BestModel",
    "EvalLog",
    "Restart",
    "checkpoint_paths",
    "checkpoint_stats",
    "restart_point",
    "save_state",
    "trim_logs",
    "trim_monitor",
    "saved_timesteps",
]
