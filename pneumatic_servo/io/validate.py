"""Checks that a recorded signal is fit for analysis, each failing with one line that
names the topic, the place and the fix.

A series is the (stamps, values) of one signal as recorded, before resampling.
"""
from __future__ import annotations

import numpy as np

from ..errors import ExperimentError

#: a gap is a stamp interval longer than this many median intervals ...
GAP_FACTOR = 20.0
#: ... and longer than this [s] (so jitter on a fast topic is not a gap)
MIN_GAP_S = 0.02


def _at(stamps_ns: np.ndarray, i: int, t0_ns: int) -> str:
    return f't = {(int(stamps_ns[i]) - t0_ns) * 1e-9:.4f} s (message {i + 1})'


def check_finite(where: str, name: str, stamps_ns: np.ndarray, values: np.ndarray,
                 t0_ns: int) -> None:
    """Raise if ``values`` holds NaN or inf."""
    bad = ~np.isfinite(values)
    if bad.any():
        i = int(np.argmax(bad))
        raise ExperimentError(
            f'{where}: {name} is {values[i]} at {_at(stamps_ns, i, t0_ns)} and in '
            f'{int(bad.sum())} sample(s) in all; drop or repair those messages before analysis')


def check_stamps(where: str, topic: str, stamps_ns: np.ndarray, t0_ns: int,
                 source: str) -> None:
    """Raise if the stamps of ``topic`` go backwards or repeat."""
    if len(stamps_ns) < 2:
        return
    d = np.diff(stamps_ns)
    fix = ("pass time_source='record' to time every topic by its record time"
           if source == 'header' else 're-record with a monotonic clock')
    if (d < 0).any():
        i = int(np.argmax(d < 0)) + 1
        raise ExperimentError(
            f'{where}: {topic} {source} stamps go backwards at {_at(stamps_ns, i, t0_ns)}, '
            f'by {-int(d[i - 1]) * 1e-9:.6f} s; {fix}')
    if (d == 0).any():
        n = int((d == 0).sum())
        i = int(np.argmax(d == 0)) + 1
        hint = ' (header.stamp never set?)' if n == len(d) else ''
        raise ExperimentError(
            f'{where}: {topic} has {n} duplicated {source} stamp(s){hint}, first at '
            f'{_at(stamps_ns, i, t0_ns)}; {fix}')


def median_period_ns(stamps_ns: np.ndarray) -> float:
    """Median stamp interval [ns] (nan for fewer than two stamps)."""
    if len(stamps_ns) < 2:
        return float('nan')
    return float(np.median(np.diff(stamps_ns)))


def check_gaps(where: str, topic: str, stamps_ns: np.ndarray, t0_ns: int,
               max_gap_s: float | None) -> None:
    """Raise if ``topic`` has a stamp interval longer than ``max_gap_s`` [s].

    The default limit is the longer of ``GAP_FACTOR`` median intervals and
    ``MIN_GAP_S``.
    """
    if len(stamps_ns) < 3:
        return
    d = np.diff(stamps_ns)
    limit_ns = (max(GAP_FACTOR * float(np.median(d)), MIN_GAP_S * 1e9) if max_gap_s is None
                else max_gap_s * 1e9)
    if (d > limit_ns).any():
        i = int(np.argmax(d))
        raise ExperimentError(
            f'{where}: {topic} has a {d[i] * 1e-9:.3f} s gap after {_at(stamps_ns, i, t0_ns)} '
            f'(limit {limit_ns * 1e-9:.3f} s); pass max_gap_s={d[i] * 1e-9 * 1.5:.3g} to '
            'interpolate across it, or analyse the parts before and after separately')


def check_count(where: str, topic: str, expected: int, found: int) -> None:
    """Raise if the storage holds fewer (or more) messages than the bag's index lists."""
    if expected and found != expected:
        raise ExperimentError(
            f'{where}: metadata lists {expected} messages on {topic} but the storage holds '
            f'{found}: the bag is truncated or was not closed; re-record it, or rebuild its '
            'index with `ros2 bag reindex` if a partial record is acceptable')
