"""The monitor's sample buffer: live samples on a uniform grid, the latest ``keep`` of them.
Pure.

Indices are absolute (counted from the monitor's first sample), so that windows and fits
keep their place while old samples are dropped; a lost sample is a gap (NaN, stamp -1).

Units: stamps in integer nanoseconds, everything else SI.
"""
from __future__ import annotations

import numpy as np

from .judge import OPTIONAL, REQUIRED

#: every signal the buffer holds (``command_alt_v``: the command the plant may have applied
#: instead, where the pairing is uncertain; :mod:`.assemble`)
SIGNALS = REQUIRED + OPTIONAL + ('command_alt_v',)
#: a gap in the stamps longer than this [s] starts the buffer afresh (a new run)
MAX_GAP_S = 1.0
#: a gap in the stamps longer than this many periods is a gap in the data (see
#: :meth:`SampleGrid.index`)
GAP_PERIODS = 10


class SampleGrid:
    """Samples of one run on a grid of period ``dt_ns`` [ns], the latest ``keep`` kept.

    Attributes
    ----------
    base : int
        Absolute index of the first sample held.
    end : int
        Absolute index after the last sample held.
    epoch : int
        Absolute index where this run began.
    t_ns : ndarray of int64
        Stamps of the samples held (-1: lost).
    cols : dict of str to ndarray
        Signal -> values [SI] of the samples held (NaN: lost or not measured).
    last_ns : int or None
        Stamp of the latest sample.
    """

    def __init__(self, dt_ns: int = 0, keep: int = 0, start: int = 0):
        self.dt_ns, self.keep = dt_ns, keep
        self.base = self.end = self.epoch = start
        self.t_ns = np.zeros(0, np.int64)
        self.cols = {s: np.zeros(0) for s in SIGNALS}
        self.last_ns: int | None = None
        self._last_index: int | None = None
        self._last_t: int | None = None

    def restarted(self) -> 'SampleGrid':
        """An empty grid for a new run, its indices going on from this one's end."""
        return SampleGrid(self.dt_ns, self.keep, self.end)

    def on_grid(self, stamps: np.ndarray) -> np.ndarray:
        """Whether each of ``stamps`` lies a whole number of periods after the one before
        (the first: after the latest sample held)."""
        prev = stamps[0] - self.dt_ns if self._last_t is None else self._last_t
        return np.diff(np.concatenate([[prev], stamps])) % self.dt_ns == 0

    def index(self, t: int) -> int | None:
        """The grid index of a sample stamped ``t`` [ns], or None for a new run.

        Samples come in stamp order, one per plant step, and a free-running plant stamps a
        sample when its tick ran, which under load is late by a period or more now and
        then; the samples are consecutive steps all the same. So a sample is the next on
        the grid unless its stamp is more than :data:`GAP_PERIODS` periods after the last
        (the plant stood still, or the monitor lost everything for a while: a gap of that
        many periods). A sample lost alone shows as a sample without its joint state (its
        pressures arrived), from the assembler.
        """
        if self._last_t is None:
            self._last_index, self._last_t = self.end, t
            return self.end
        gap = t - self._last_t
        if gap <= 0 or gap > MAX_GAP_S * 1e9:
            return None
        k = self._last_index + (1 if gap <= GAP_PERIODS * self.dt_ns
                                else int(round(gap / self.dt_ns)))
        self._last_index, self._last_t = k, t
        return k

    def place(self, stamps: np.ndarray, cols: dict, index: np.ndarray) -> int:
        """Append samples at their grid ``index`` (:meth:`index`); returns how many grid
        places between them stay empty (samples lost)."""
        pos = index - self.end  # relative to the buffer's end
        size = int(pos[-1]) + 1
        t = np.full(size, -1, np.int64)
        t[pos] = stamps
        self.t_ns = np.concatenate([self.t_ns, t])
        for s in SIGNALS:
            block = np.full(size, np.nan)
            block[pos] = cols[s]
            self.cols[s] = np.concatenate([self.cols[s], block])
        self.end += size
        self.last_ns = int(stamps[-1])
        return size - len(stamps)

    def trim(self) -> None:
        """Drop all but the latest ``keep`` samples."""
        extra = len(self.t_ns) - self.keep
        if extra > 0:
            self.t_ns = self.t_ns[extra:]
            self.cols = {s: v[extra:] for s, v in self.cols.items()}
            self.base += extra

    def rows(self, a: int, b: int) -> slice:
        """The rows held of absolute indices ``a`` to ``b``."""
        return slice(a - self.base, b - self.base)

    def complete(self, a: int, b: int, signals=REQUIRED) -> bool:
        """Whether every sample from ``a`` to ``b`` has all of ``signals``."""
        rows = self.rows(a, b)
        return all(np.all(np.isfinite(self.cols[s][rows])) for s in signals)
