"""Each environment's factors on its samples' sizes, one row for the samples scaled together.

``Simulator.set_sample_scale`` and ``set_thrust_scale`` give a group of samples a factor per
environment. Stored per sample and environment, a boat's 91 samples at E = 4096 would be
megabytes that every force evaluation streams through (the env step was 10-20% slower so).
Samples scaled together share their factors, so the kernels read them through one more
index: sample j's area in environment e is ``area_j * factor[row[F_AREA, j], e]``, where
``row`` (``Samples.factor_row``) is small and ``factor`` has a row per set of samples scaled
together (row 0, all ones, for everything left at the craft's values; two groups given equal
factors by separate calls keep a row each). A batch in which
nothing was scaled reads one row of ones: the craft's own numbers, bit for bit.

:class:`FactorTable` keeps the rows: a write to the samples that alone use a row changes that
row in place; a write to some of a row's users gives them a fresh copy; a row nobody uses is
free for the next copy; a row that becomes all ones hands its users back to row 0.
"""

from __future__ import annotations

import numpy as np


class FactorTable:
    """``factor [rows, E]`` and ``row [len(FACTORS), N]`` (``model.Samples``' fields) with
    their bookkeeping.

    Args:
        row: the samples' rows, ``[len(FACTORS), N]`` int64 (all 0: nothing scaled).
        factor: the table, ``[rows, E]`` in the simulation dtype, row 0 all ones.
    """

    def __init__(self, row: np.ndarray, factor: np.ndarray) -> None:
        self.row, self.factor = row, factor

    def set(self, which: int, samples: np.ndarray, env_ids: np.ndarray, values) -> None:
        """Factor ``which`` of ``samples`` becomes ``values`` (``[len(env_ids)]``) in
        environments ``env_ids``; other environments and samples keep theirs. May replace
        :attr:`factor` by a larger array."""
        values = np.asarray(values).astype(self.factor.dtype)
        # each sample once: a group that names one twice must not pass for a row's only users
        samples = np.asarray(samples, dtype=np.int64)
        if (samples[1:] <= samples[:-1]).any():
            samples = np.unique(samples)
        rows = self.row[which, samples]
        if samples.size and rows[0] != 0 and (rows == rows[0]).all():
            self._write(which, samples, rows[0], env_ids, values)  # a group that kept its row
            return
        for r in np.unique(rows):
            users = samples[self.row[which, samples] == r]
            self._write(which, users, r, env_ids, values)

    def _write(self, which: int, users: np.ndarray, r: int, env_ids, values) -> None:
        """``set`` for ``users``, the samples of ``samples`` on row ``r``."""
        if r != 0 and np.count_nonzero(self.row == r) == users.size:
            target = r  # the row is theirs alone
        else:
            target = self._free_row()
            self.factor[target] = self.factor[r]
            self.row[which, users] = target
        self.factor[target, env_ids] = values
        if (self.factor[target] == 1.0).all():
            self.row[which, users] = 0

    def values(self, env_ids: np.ndarray) -> np.ndarray:
        """Every sample's factors in environments ``env_ids``: ``[n, len(FACTORS), N]``."""
        return np.moveaxis(self.factor[self.row][..., env_ids], -1, 0).copy()

    def restore(self, values: np.ndarray, env_ids: np.ndarray) -> None:
        """Give environments ``env_ids`` the factors ``values`` (``[n, len(FACTORS), N]``, as
        :meth:`values` returns them); samples whose factors are unchanged are left alone."""
        now = self.values(env_ids)
        for which in range(values.shape[1]):
            new = values[:, which, :]  # [n, N]
            changed = np.flatnonzero(np.any(new != now[:, which, :], axis=0))
            if not changed.size:
                continue
            # the samples that share a column of values are set (and keep a row) together
            columns, group = np.unique(new[:, changed].T, axis=0, return_inverse=True)
            for g, column in enumerate(columns):
                self.set(which, changed[group.ravel() == g], env_ids, column)

    def _free_row(self) -> int:
        used = np.zeros(len(self.factor), dtype=bool)
        used[self.row.ravel()] = True
        used[0] = True
        free = np.flatnonzero(~used)
        if free.size:
            return int(free[0])
        grown = np.ones((2 * len(self.factor), self.factor.shape[1]), dtype=self.factor.dtype)
        grown[: len(self.factor)] = self.factor
        at, self.factor = len(self.factor), grown
        return at
