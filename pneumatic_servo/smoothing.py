"""Savitzky-Golay smoothing and differentiation of evenly sampled signals.

The same filter as ``scipy.signal.savgol_filter`` with its default ``mode='interp'``
(a least-squares polynomial over a sliding window; the first and last half windows take
the polynomial fitted to the first and last full window). It is written here because
importing ``scipy.signal`` costs about 0.9 s per process, half of what a whole
``simulate`` of a 10 s bag is allowed to take; ``tests/test_physics.py`` checks it
against scipy's.
"""
from __future__ import annotations

from functools import lru_cache
from math import factorial

import numpy as np


@lru_cache(maxsize=64)
def _fit_matrix(window: int, order: int, deriv: int, delta: float) -> np.ndarray:
    """Rows: the ``deriv``-th derivative at each position of the window, as weights on the
    window's samples, of the least-squares polynomial of degree ``order`` (read-only: it is
    cached, as every prediction smooths its record with the same few windows)."""
    pos = np.arange(window) - window // 2
    vander = np.vander(pos, order + 1, increasing=True)          # sample i, power k
    coef_of_samples = np.linalg.pinv(vander)                      # power k, sample i
    powers = np.arange(order + 1)
    scale = np.array([factorial(k) / factorial(k - deriv) if k >= deriv else 0.0
                      for k in powers])
    eval_at = np.array([[scale[k] * float(p) ** (k - deriv) if k >= deriv else 0.0
                         for k in powers] for p in pos])          # position, power k
    out = eval_at @ coef_of_samples / delta ** deriv
    out.flags.writeable = False
    return out


def savgol_filter(x, window: int, order: int, deriv: int = 0, delta: float = 1.0
                  ) -> np.ndarray:
    """Smoothed ``x`` (``deriv`` = 0) or its derivative [unit of x / s**deriv with ``delta``
    the sample spacing in s]; ``window`` odd, greater than ``order``, at most ``len(x)``."""
    x = np.asarray(x, dtype=float)
    if window % 2 == 0 or window <= order or window > len(x):
        raise ValueError(f'Savitzky-Golay window {window} must be odd, above the order '
                         f'{order} and at most the {len(x)} samples')
    weights = _fit_matrix(window, order, deriv, delta)
    half = window // 2
    out = np.empty_like(x)
    # interior: the centre row as a correlation (np.convolve flips its kernel)
    out[half:len(x) - half] = np.convolve(x, weights[half][::-1], mode='valid')
    out[:half] = weights[:half] @ x[:window]
    out[len(x) - half:] = weights[half + 1:] @ x[-window:]
    return out
