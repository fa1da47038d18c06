"""Error metrics of one channel: measured ``y`` against predicted ``yhat``, in SI units.

* ``rmse``: root mean square error [unit of the channel];
* ``max_abs``: largest absolute error [unit] (the paper's verification figure);
* ``fit_percent``: normalised RMS fit, 100 (1 - ||y - yhat|| / ||y - mean(y)||);
  100 is perfect, 0 is no better than the measured mean, negative is worse.

Samples where either signal is not finite are left out (and counted).
"""
from __future__ import annotations

import math

import numpy as np


def _pair(y, yhat) -> tuple[np.ndarray, np.ndarray]:
    y, yhat = np.asarray(y, float), np.asarray(yhat, float)
    if y.shape != yhat.shape:
        raise ValueError(f'measured and predicted differ in shape: {y.shape} vs {yhat.shape}')
    keep = np.isfinite(y) & np.isfinite(yhat)
    return y[keep], yhat[keep]


def rmse(y, yhat) -> float:
    """Root mean square error [unit of y]."""
    y, yhat = _pair(y, yhat)
    return float(np.sqrt(np.mean((y - yhat) ** 2))) if len(y) else float('nan')


def max_abs(y, yhat) -> float:
    """Largest absolute error [unit of y]."""
    y, yhat = _pair(y, yhat)
    return float(np.max(np.abs(y - yhat))) if len(y) else float('nan')


def fit_percent(y, yhat) -> float:
    """NRMSE fit [%]: 100 (1 - ||y - yhat|| / ||y - mean(y)||); NaN if y is constant."""
    y, yhat = _pair(y, yhat)
    if not len(y):
        return float('nan')
    spread = float(np.linalg.norm(y - np.mean(y)))
    if spread == 0.0:
        return float('nan')
    return float(100.0 * (1.0 - np.linalg.norm(y - yhat) / spread))


def channel_metrics(y, yhat) -> dict:
    """``rmse``, ``max_abs``, ``fit_percent`` (NaN -> None, for JSON) and the sample counts."""
    yy, _ = _pair(y, yhat)
    out = {'rmse': rmse(y, yhat), 'max_abs': max_abs(y, yhat), 'fit_percent': fit_percent(y, yhat),
           'n': int(len(yy)), 'n_missing': int(np.size(y) - len(yy))}
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v)
            for k, v in out.items()}
