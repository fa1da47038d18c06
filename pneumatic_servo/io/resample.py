"""Align signals recorded at different rates and times onto one uniform time grid.

Measurements are interpolated linearly between their stamps; commands are
held (zero-order hold), as the valve driver holds them. Times are integer
nanoseconds until the grid is built, so long records keep sub-microsecond
resolution.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import ExperimentError


def grid_period_ns(periods_ns: list[float], rate_hz: float | None = None) -> int:
    """Sample period [ns] of the grid: 1/``rate_hz``, else the shortest median period.

    The median is rounded to whole microseconds, so a 1 kHz DAQ with jitter
    gives exactly 1 ms.
    """
    if rate_hz is not None:
        if not (rate_hz > 0 and math.isfinite(rate_hz)):
            raise ExperimentError(f'rate_hz must be a positive number, got {rate_hz!r}')
        return max(1, int(round(1e9 / rate_hz)))
    finite = [p for p in periods_ns if math.isfinite(p) and p > 0]
    if not finite:
        raise ExperimentError('cannot tell the sample rate (fewer than two samples per '
                              'topic); pass rate_hz')
    return max(1000, int(round(min(finite) / 1000.0)) * 1000)


def common_span(spans: dict[str, tuple[int, int]], where: str) -> tuple[int, int]:
    """The time span [ns] covered by every series: latest start to earliest end."""
    start = max(s for s, _ in spans.values())
    stop = min(e for _, e in spans.values())
    if stop <= start:
        late = max(spans, key=lambda k: spans[k][0])
        early = min(spans, key=lambda k: spans[k][1])
        raise ExperimentError(
            f'{where}: {late} starts {(start - stop) * 1e-9:.3f} s after {early} ends, so '
            'no time has every signal; if the topics use different clocks (sim time vs '
            "wall time), pass time_source='record'")
    return start, stop


def make_grid(start_ns: int, stop_ns: int, period_ns: int) -> np.ndarray:
    """Grid stamps [ns] from ``start_ns`` while <= ``stop_ns``."""
    n = (stop_ns - start_ns) // period_ns + 1
    return start_ns + period_ns * np.arange(n, dtype=np.int64)


def interpolate(stamps_ns: np.ndarray, values: np.ndarray, grid_ns: np.ndarray) -> np.ndarray:
    """Linear interpolation of a measurement onto ``grid_ns`` (inside its span)."""
    t0 = grid_ns[0]
    return np.interp((grid_ns - t0).astype(float), (stamps_ns - t0).astype(float), values)


def hold(stamps_ns: np.ndarray, values: np.ndarray, grid_ns: np.ndarray,
         tolerance_ns: int) -> np.ndarray:
    """Zero-order hold of a command onto ``grid_ns``.

    A command stamped up to ``tolerance_ns`` after a grid point counts as
    applied at it: a controller publishes in the same tick as the DAQ
    samples, and its record time trails the tick by the publishing latency.
    """
    idx = np.searchsorted(stamps_ns, grid_ns + tolerance_ns, side='right') - 1
    return values[np.clip(idx, 0, len(values) - 1)]
