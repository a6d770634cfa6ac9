"""Sensors: what a real instrument adds to the observation a scene computes exactly.

Each scene declares its instruments as a tuple of :class:`Sensor`: the observation columns an
instrument reads, its white noise, a slowly wandering bias, its resolution, and the class of
hardware the numbers come from. A v1 env reads through them (``sensor_scale``: 0 a perfect
instrument, 1 the hardware of the table, 2 a grade cheaper) with an optional latency of
whole steps; columns no instrument reads (what the task tells the pilot: a target speed;
an actuator's position feedback) pass through exactly and at once.

A reading is ``quantize(truth + bias + noise * n)``: ``n`` a standard normal fresh each step,
and the bias a first-order Gauss-Markov process (an Ornstein-Uhlenbeck process sampled at the
action period ``h``): drawn from its stationary law N(0, bias^2) at the episode start (the
turn-on bias), then ``b <- a b + bias sqrt(1 - a^2) n'`` with ``a = exp(-h / bias_time_s)``,
so that its standard deviation stays ``bias`` and its autocorrelation is
``exp(-lag / bias_time_s)`` (the model of IEEE Std 952's and 1293's bias instability term).
Quantization rounds to the nearest multiple of ``quantum``. With a latency of k steps the
pilot sees an instrument's reading taken k steps ago (at an episode start, the first).

The normals come from :mod:`.noise` (per sub-env key, the step in the episode, a lane per
column), so readings are bit for bit the same for any batch size and thread count.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from . import noise as NZ

# lanes of the noise stream (noise.normal_pair's): a column each
_WHITE = 0
PARALLEL_MIN_IDS = 1024  # from this many sub-envs a read runs on every thread
BLOCK_IDS = 64
MAX_COLUMNS = 1024  # observation columns a sensor model can read
MAX_LATENCY_STEPS = 16


@dataclass(frozen=True)
class Sensor:
    """One instrument and the observation columns it reads (all in the columns' SI unit).

    Attributes:
        name: what the instrument is, as the docs name it ("gyro", "rangefinder").
        columns: the observation columns it reads.
        noise: standard deviation of its white noise per reading, at the env's action rate.
        bias: standard deviation of its slowly wandering bias (0: none).
        bias_time_s: that bias's correlation time (> 0 where ``bias`` is).
        quantum: its resolution (0: continuous).
        hardware: the class of instrument the numbers are from, and the source.
    """

    name: str
    columns: tuple[str, ...]
    noise: float
    bias: float = 0.0
    bias_time_s: float = 0.0
    quantum: float = 0.0
    hardware: str = ""

    def __post_init__(self) -> None:
        own = f"Sensor {self.name!r}"
        for key in ("noise", "bias", "bias_time_s", "quantum"):
            v = getattr(self, key)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0.0):
                raise ValueError(f"{own}: {key} must be a finite number >= 0, got {v!r}")
        if self.bias > 0.0 and self.bias_time_s <= 0.0:
            raise ValueError(f"{own}: a bias needs bias_time_s > 0, got {self.bias_time_s!r}")
        if not self.columns or len(set(self.columns)) != len(self.columns):
            raise ValueError(f"{own}: columns must be distinct names, got {self.columns!r}")


class SensorModel:
    """The per-column arrays of a scene's sensors for one env: ``sensors`` over the
    observation ``names``, scaled by ``scale``, read every ``period_s``, ``latency`` steps
    late; and its kernel (:meth:`read`)."""

    def __init__(self, sensors, names, scale: float, period_s: float, latency: int, E: int):
        if len(names) > MAX_COLUMNS:
            raise ValueError(f"SensorModel: at most {MAX_COLUMNS} columns, got {len(names)}")
        column = {n: j for j, n in enumerate(names)}
        n = len(names)
        self.noise, self.bias = np.zeros(n), np.zeros(n)
        self.bias_a, self.bias_b = np.ones(n), np.zeros(n)
        self.quantum = np.zeros(n)
        self.reader = [""] * n  # which instrument reads each column ("" none)
        self.read_by = np.zeros(n, dtype=np.bool_)  # an instrument's: noisy and late
        for s in sensors:
            for c in s.columns:
                if c not in column:
                    raise ValueError(
                        f"Sensor {s.name!r} reads column {c!r}, not one of the observation's "
                        f"{list(names)}"
                    )
                j = column[c]
                if self.reader[j]:
                    raise ValueError(f"column {c!r} is read by {self.reader[j]!r} and {s.name!r}")
                self.reader[j] = s.name
                self.read_by[j] = True
                self.noise[j] = scale * s.noise
                self.bias[j] = scale * s.bias
                if s.bias > 0.0:
                    a = math.exp(-period_s / s.bias_time_s)
                    self.bias_a[j], self.bias_b[j] = a, scale * s.bias * math.sqrt(1.0 - a * a)
                self.quantum[j] = s.quantum if scale > 0.0 else 0.0
        self.latency = int(latency)
        # each sub-env's readings of the last ``latency + 1`` steps (a ring) and its biases
        self.history = np.zeros((E, self.latency + 1, n), dtype=np.float32)
        self.head = np.zeros(E, dtype=np.int64)
        self.state = np.zeros((E, n))  # the biases

    @property
    def exact(self) -> bool:
        """Whether the readings are the truth (no noise, bias, resolution or latency)."""
        return (
            self.latency == 0
            and not self.noise.any()
            and not self.bias.any()
            and not self.quantum.any()
        )

    def read(self, ids, start: bool, counter, keys, truth, out, skip) -> None:
        """Readings of sub-envs ``ids`` into ``out`` from the exact observation ``truth``
        (both [E, n] float32); ``start``: their episodes begin (turn-on bias, the latency's
        ring filled with the first reading); ``counter`` [E] each one's step in its episode;
        ``keys`` [E] uint64 their noise keys; where ``skip`` [E] is set (a diverged state)
        the reading stays the last one."""
        kernel = read_parallel if ids.size >= PARALLEL_MIN_IDS else read
        kernel(ids, start, counter, keys, truth, self.state, self.history, self.head, self.noise,
               self.bias, self.bias_a, self.bias_b, self.quantum, self.read_by, out,
               skip)  # fmt: skip


@njit(cache=True, inline="always")
def _read_range(lo, hi, ids, start, counter, keys, truth, bias, history, head, noise,
                bias_std, bias_a, bias_b, quantum, read_by, out, skip):  # fmt: skip
    """Sub-envs ``ids[lo:hi]``: each column's bias and white noise from one pair of normals
    (lane: the column; at the start, the pair's first draws the turn-on bias)."""
    slots = history.shape[1]
    for i in range(lo, hi):
        e = ids[i]
        if skip[e]:
            continue
        k, t = keys[e], counter[e]
        head[e] = 0 if start else (head[e] + 1) % slots
        h = head[e]
        late = (h + 1) % slots  # the slot read: ``latency`` steps ago (once per sub-env)
        for j in range(truth.shape[1]):
            if not read_by[j]:
                out[e, j] = truth[e, j]
                continue
            n_bias, n_white = NZ.normal_pair(k, t, _WHITE + j)
            if start:
                bias[e, j] = bias_std[j] * n_bias
            else:
                bias[e, j] = bias_a[j] * bias[e, j] + bias_b[j] * n_bias
            x = np.float64(truth[e, j]) + bias[e, j] + noise[j] * n_white
            if quantum[j] > 0.0:
                x = quantum[j] * math.floor(x / quantum[j] + 0.5)  # to the nearest step
            history[e, h, j] = x
            if start:
                for s in range(slots):
                    history[e, s, j] = x
            out[e, j] = history[e, late, j]


@njit(cache=True)
def read(ids, start, counter, keys, truth, bias, history, head, noise, bias_std, bias_a,
         bias_b, quantum, read_by, out, skip):  # fmt: skip
    """:meth:`SensorModel.read`, compiled: each sub-env's columns in turn; a column no
    instrument reads (``read_by``) is the truth, now."""
    _read_range(0, ids.size, ids, start, counter, keys, truth, bias, history, head, noise,
                bias_std, bias_a, bias_b, quantum, read_by, out, skip)  # fmt: skip


@njit(cache=True, parallel=True)
def read_parallel(ids, start, counter, keys, truth, bias, history, head, noise, bias_std,
                  bias_a, bias_b, quantum, read_by, out, skip):  # fmt: skip
    """:func:`read` on every thread, ``BLOCK_IDS`` sub-envs a task: each writes only its own
    rows, bit for bit as serial."""
    for b in prange((ids.size + BLOCK_IDS - 1) // BLOCK_IDS):
        lo = b * BLOCK_IDS
        _read_range(lo, min(ids.size, lo + BLOCK_IDS), ids, start, counter, keys, truth, bias,
                    history, head, noise, bias_std, bias_a, bias_b, quantum, read_by, out,
                    skip)  # fmt: skip


def table_rows(sensors) -> list[tuple[str, str, str, str, str, str]]:
    """(instrument, columns, noise, bias (time), resolution, hardware) per sensor: the docs'
    sensor tables."""
    rows = []
    for s in sensors:
        bias = f"{s.bias:g} ({s.bias_time_s:g} s)" if s.bias else "-"
        quantum = f"{s.quantum:g}" if s.quantum else "-"
        rows.append((s.name, ", ".join(s.columns), f"{s.noise:g}", bias, quantum, s.hardware))
    return rows
