"""Tracking figures of a closed-loop run: step settling and overshoot, steady-state and RMS
error. Pure; angles in rad, times in s.
"""
from __future__ import annotations

import math

import numpy as np


def step_metrics(t, angle, t_step: float, start: float, target: float,
                 band_rad: float = math.radians(1.0), final_window_s: float = 0.5) -> dict:
    """Figures of a step from ``start`` to ``target`` [rad] commanded at ``t_step`` [s].

    Returns
    -------
    dict
        ``settling_time_s``: from the step until the angle stays within
        ``band_rad`` of the target (NaN if it never does); ``overshoot_rad`` and
        ``overshoot_percent`` (of the step size, 0 if none); ``steady_state_error_rad``:
        mean absolute error over the last ``final_window_s``; ``final_error_rad``:
        error at the last sample (signed, target - angle); ``rise_time_s`` (10-90 %).
    """
    t = np.asarray(t, float)
    y = np.asarray(angle, float)
    after = t >= t_step
    ta, ya = t[after], y[after]
    if len(ta) < 2:
        raise ValueError('no samples after the step')
    size = target - start
    direction = 1.0 if size >= 0 else -1.0
    err = target - ya
    outside = np.nonzero(np.abs(err) > band_rad)[0]
    if len(outside) == 0:
        settle = 0.0
    elif outside[-1] == len(ya) - 1:
        settle = math.nan
    else:
        settle = float(ta[outside[-1] + 1] - t_step)
    over = max(0.0, float(np.max(direction * (ya - target))))
    final = ta >= ta[-1] - final_window_s
    lo, hi = start + 0.1 * size, start + 0.9 * size
    crossed_lo = np.nonzero(direction * (ya - lo) >= 0)[0]
    crossed_hi = np.nonzero(direction * (ya - hi) >= 0)[0]
    rise = (float(ta[crossed_hi[0]] - ta[crossed_lo[0]])
            if len(crossed_lo) and len(crossed_hi) else math.nan)
    return {'settling_time_s': settle, 'overshoot_rad': over,
            'overshoot_percent': 100.0 * over / abs(size) if size else 0.0,
            'steady_state_error_rad': float(np.mean(np.abs(err[final]))),
            'final_error_rad': float(err[-1]), 'rise_time_s': rise}


def tracking_rms(t, angle, reference, t_from: float = -math.inf, t_to: float = math.inf) -> dict:
    """RMS and largest absolute tracking error [rad] between ``t_from`` and ``t_to`` [s]."""
    t = np.asarray(t, float)
    e = np.asarray(reference, float) - np.asarray(angle, float)
    keep = (t >= t_from) & (t <= t_to) & np.isfinite(e)
    if not np.any(keep):
        raise ValueError('no samples in the window')
    return {'rms_error_rad': float(np.sqrt(np.mean(e[keep] ** 2))),
            'max_error_rad': float(np.max(np.abs(e[keep])))}
