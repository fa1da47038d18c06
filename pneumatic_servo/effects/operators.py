"""Operators over a record's arrays that the vocabulary's expressions call
(:mod:`.terms`): a first-order lag, a rate of change and the direction of the last
change (a play). Each passes over a whole record, so a term that uses one is evaluated
over arrays (a sensor's error, the report), not in a compiled hook; emitted effect
files import them from :mod:`.terms`.
"""
from __future__ import annotations

import math

import numpy as np

from .._jit import njit

#: [s] span of the derivative a sensor's rate is taken over (the prediction's own
#: derivative window, ``analysis.equation_residual``, is 31 ms)
RATE_WINDOW_S = 0.021


@njit(cache=True)
def _play(v, half):
    out = np.empty(len(v))
    y = np.nan
    for i in range(len(v)):
        if np.isnan(v[i]):  # a missing sample: the play holds, and says nothing there
            out[i] = v[i]
            continue
        y = v[i] if np.isnan(y) else min(max(y, v[i] - half), v[i] + half)
        out[i] = y
    return out


@njit(cache=True)
def _first_order(v, a):
    out = np.empty(len(v))
    y = np.nan
    for i in range(len(v)):
        if np.isnan(v[i]):  # a missing sample: the lag holds, and says nothing there
            out[i] = v[i]
            continue
        y = v[i] if np.isnan(y) else a * y + (1.0 - a) * v[i]
        out[i] = y
    return out


def lag(v: np.ndarray, t, tau: float) -> np.ndarray:
    """``v`` read through a first-order lag of time constant ``tau`` [s], starting at rest
    at its first sample (unchanged without sample times); exact for a reading held over
    each sample interval."""
    v = np.ascontiguousarray(v, dtype=float)
    if t is None or len(v) < 2:
        return v.copy()
    return _first_order(v, math.exp(-_interval(t) / tau))


def _interval(t) -> float:
    """The sample interval of times ``t`` [s] (their median step)."""
    return float(np.median(np.diff(np.asarray(t, dtype=float))))


def rate(v: np.ndarray, t) -> np.ndarray:
    """d``v``/dt over a record [unit/s]: a Savitzky-Golay derivative over
    :data:`RATE_WINDOW_S`, so that a noisy reading's rate is not its noise (zero without
    sample times or with too few samples). A sensor's lag is, to first order, minus its
    time constant times this."""
    from ..smoothing import savgol_filter
    v = np.asarray(v, dtype=float)
    if t is None or len(v) < 5:
        return np.zeros(len(v))
    dt = _interval(t)
    window = min(max(5, int(round(RATE_WINDOW_S / dt)) | 1), len(v) - (1 - len(v) % 2))
    return savgol_filter(v, window, 2, deriv=1, delta=dt)


def direction(v: np.ndarray, width: float) -> np.ndarray:
    """The direction ``v`` last moved in, from -1 to 1 [1]: its distance from the output of
    a play (backlash) of ``width``, over half the width; 0 until it has moved, NaN where
    ``v`` is (a missing sample does not reset the memory)."""
    v = np.ascontiguousarray(v, dtype=float)
    return (v - _play(v, 0.5 * width)) / (0.5 * width)
