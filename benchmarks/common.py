"""What the benchmark scripts share: timing, the machine they ran on, and their CSV files.

- Timing: :func:`timed` (one call), :func:`best_of` (the fastest of several calls),
  :func:`rate_over` (calls repeated for a while: work per second), :func:`sized` (how many steps
  make a call of a given length) and :func:`interleaved_best` (several subjects timed in turn
  each repeat, so that a change of load on the machine hits them alike).
- The machine: :func:`describe` (CPU, cores, numba threads and threading layer, versions, load
  average), printed first by every benchmark and written as ``#`` lines in its CSV.
- CSV files: :func:`write_csv` writes ``#`` lines (the command that wrote the file first, then
  the machine and any notes), a header and the rows; :func:`read_csv` reads one back.

Every script in this package runs from the repository root as ``python -m benchmarks.<name>``.
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import platform
import shlex
import subprocess
import sys
import time
from collections.abc import Callable, Hashable, Iterable, Mapping, Sequence
from pathlib import Path

import numba
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


# ---- timing ----------------------------------------------------------------------------------


def timed(fn: Callable[[], object], setup: Callable[[], object] | None = None) -> float:
    """Seconds taken by one call of ``fn``; ``setup`` (untimed) is called first."""
    if setup is not None:
        setup()
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def best_of(
    fn: Callable[[], object],
    repeats: int,
    setup: Callable[[], object] | None = None,
    warmup: bool = True,
) -> float:
    """Fewest seconds over ``repeats`` timed calls of ``fn`` (``setup`` untimed before each),
    after one untimed warm-up call (compile or load from the cache, start the threads)."""
    if warmup:
        timed(fn, setup)
    return min((timed(fn, setup) for _ in range(repeats)), default=math.inf)


def rate_over(run: Callable[[], float], seconds: float) -> float:
    """Calls ``run`` (which returns the work it did: steps, env-steps) until ``seconds`` have
    passed; the work per second of wall time."""
    work, t0 = 0, time.perf_counter()
    while (elapsed := time.perf_counter() - t0) < seconds:
        work += run()
    return work / elapsed


def sized(call: Callable[[int], object], seconds: float, probe: int) -> int:
    """The count ``n`` for which ``call(n)`` lasts about ``seconds``, from one timed
    ``call(probe)``."""
    t0 = time.perf_counter()
    call(probe)
    return max(1, int(seconds / max(time.perf_counter() - t0, 1e-6) * probe))


def interleaved_best(
    calls: Mapping[Hashable, Callable[[], float]],
    repeats: int,
    best: Callable[[float, float], float] = min,
    before: Callable[[Hashable], object] | None = None,
) -> dict:
    """The best value each call returned over ``repeats`` rounds, the calls taken in turn every
    round (a, b, c, a, b, c, ...): ``best=min`` for seconds, ``best=max`` for rates.
    ``before(key)``, if given, runs before each call (for example ``numba.set_num_threads``
    when the keys are thread counts)."""
    out: dict = dict.fromkeys(calls, math.inf if best is min else -math.inf)
    for _ in range(repeats):
        for key, call in calls.items():
            if before is not None:
                before(key)
            out[key] = best(out[key], call())
    return out


# ---- the machine -----------------------------------------------------------------------------


def describe(show: bool = True) -> list[str]:
    """CPU, core and thread counts, numba's threading layer, versions, load average (printed
    too, unless ``show`` is false)."""
    from fluidsim_envs.physics import Craft, Simulator

    # a parallel call first, so that numba has picked its threading layer
    Simulator(Craft(name="probe", mass_kg=1.0, inertia_kgm2=(1, 1, 1)), parallel=True).step()
    try:
        lscpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        model = next(
            (
                ln.split(":", 1)[1].strip()
                for ln in lscpu.splitlines()
                if ln.startswith("Model name")
            ),
            "",
        )
    except OSError:
        model = ""
    lines = [
        f"cpu: {model or platform.processor() or 'unknown'} ({platform.machine()})",
        f"os.cpu_count: {os.cpu_count()}, numba threads: {numba.config.NUMBA_NUM_THREADS}, "
        f"threading layer: {numba.threading_layer()}",
        f"python {platform.python_version()}, numba {numba.__version__}, "
        f"numpy {np.__version__}, {platform.system()} {platform.release()}",
        load_average("start"),
    ]
    if show:
        print("\n".join(lines), flush=True)
    return lines


def load_average(when: str = "end") -> str:
    """The load average now, as a line for the CSV's ``#`` lines."""
    return f"load average at {when}: " + ", ".join(f"{x:.2f}" for x in os.getloadavg())


def command() -> str:
    """The command line of this process as one types it again, ``python -m benchmarks.<name>
    ARGS`` when run as a module."""
    spec = getattr(sys.modules.get("__main__"), "__spec__", None)
    prog = f"python -m {spec.name}" if spec is not None and spec.name else f"python {sys.argv[0]}"
    return " ".join([prog, *map(shlex.quote, sys.argv[1:])])


# ---- CSV -------------------------------------------------------------------------------------


def arguments(doc: str, quick: str, csv_name: str | None = None) -> argparse.ArgumentParser:
    """A parser with the options every benchmark takes: ``--quick`` (``quick`` says what it
    cuts) and ``--out``: the CSV file (default ``docs/<csv_name>``) where a script writes one,
    else the folder of a study (default ``docs/``, or ``build/study_quick`` with ``--quick``:
    see :func:`out_dir`)."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=quick)
    if csv_name is None:
        parser.add_argument("--out", default=None, help="folder (default docs/, quick: build/)")
    else:
        parser.add_argument(
            "--out", type=Path, default=DOCS / csv_name, help="CSV file (default: %(default)s)"
        )
    return parser


def out_dir(out: str | None, quick: bool) -> Path:
    """The folder a study writes into: ``out`` if given, else ``docs/``, or ``build/study_quick``
    for a ``--quick`` run (so that a quick run never overwrites the published numbers)."""
    path = Path(out) if out else ROOT / ("build/study_quick" if quick else "docs")
    path.mkdir(parents=True, exist_ok=True)
    return path


def fmt(x) -> str:
    """A CSV cell: floats to 6 significant digits, anything else as ``str`` gives it."""
    return f"{x:.6g}" if isinstance(x, float) else str(x)


def write_csv(
    path: str | Path,
    header: Sequence[str],
    rows: Iterable[Sequence],
    comments: Sequence[str] = (),
) -> Path:
    """Write ``rows`` under ``header``, after ``#`` lines: ``command: ...`` (the command that
    wrote the file), then ``comments`` (the machine from :func:`describe`, notes). Readers skip
    the lines that start with ``#``."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as f:
        f.writelines(f"# {line}\n" for line in [f"command: {command()}", *comments])
        writer = csv.writer(f)
        writer.writerow(header)
        writer.writerows(rows)
    return path


class Table:
    """Rows kept for a CSV and printed as they come, aligned: ``widths`` holds one width per
    column (negative: right-aligned); the column named ``value`` is shown as a number."""

    def __init__(self, columns: Sequence[str], widths: Sequence[int], titles=None) -> None:
        self.columns, self.widths, self.rows = tuple(columns), tuple(widths), []
        self._value = self.columns.index("value")
        print(self._line(titles or self.columns))

    def _line(self, cells) -> str:
        return " ".join(
            f"{c:<{w}}" if w > 0 else f"{c:>{-w}}" for c, w in zip(cells, self.widths, strict=True)
        )

    def add(self, *row) -> None:
        self.rows.append(row)
        value = row[self._value]
        shown = list(row)
        shown[self._value] = f"{value:,.0f}" if value >= 1000 else f"{value:.3f}"
        print(self._line(shown), flush=True)


def prose(text: str, width: int = 96) -> str:
    """A generated paragraph wrapped as the docs' hand-written ones are (never inside a word,
    a link or at a hyphen)."""
    import textwrap

    return textwrap.fill(text, width, break_long_words=False, break_on_hyphens=False)


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """The 95% Wilson score interval of k successes in n."""
    if n == 0:
        return (math.nan, math.nan)
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0.0, c - h), min(1.0, c + h))


def read_csv(path: str | Path) -> tuple[list[str], list[dict]]:
    """The ``#`` lines (without the ``# ``) and the rows (dicts of strings) of a CSV file."""
    lines = Path(path).read_text().splitlines()
    comments = [ln[2:] for ln in lines if ln.startswith("# ")]
    return comments, list(csv.DictReader(ln for ln in lines if not ln.startswith("#")))


def keep_others(out: Path, header: tuple, cells: list, measured: list[str]) -> tuple[list, list]:
    """``cells`` (rows of the envs ``measured``, env first) with the other envs' rows kept
    from ``out`` where it exists, and the note that says where those came from."""
    if not out.is_file():
        return cells, []
    comments, kept = read_csv(out)
    cells = cells + [[r[k] for k in header] for r in kept if r["env"] not in measured]
    others = sorted({r[0] for r in cells} - set(measured))
    if not others:
        return cells, []
    before = next((c[len("command: ") :] for c in comments if c.startswith("command: ")), "?")
    older = [c for c in comments if c.startswith("rows of ")]  # where those came from
    note = f"rows of {', '.join(others)} kept from the previous file ({before})"
    return cells, [note + (f"; before it: {'; '.join(older)}" if older else "")]
