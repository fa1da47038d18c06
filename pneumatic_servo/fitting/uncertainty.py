"""What the data say about fitted values: standard errors, correlation, values at a bound.

The covariance is sigma^2 (J'J)^-1 of the normalised residuals, inflated by
n / n_eff: residuals sampled at 1 kHz are far from independent, and without
the inflation the standard errors would be over-confident by orders of
magnitude. :func:`effective_samples` is the package's one estimator of n_eff.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def autocorrelation(x: np.ndarray, max_lag: int) -> np.ndarray:
    """Autocorrelation of ``x`` at lags 0..max_lag (biased estimator, FFT)."""
    x = x - x.mean()
    n = len(x)
    f = np.fft.rfft(x, 2 * n)
    acf = np.fft.irfft(f * np.conj(f))[:max_lag + 1]
    return acf / acf[0] if acf[0] > 0 else np.zeros(max_lag + 1)


def effective_samples(x: np.ndarray, y: np.ndarray | None = None) -> float:
    """Independent samples in a correlated series, n / (1 + 2 sum rho_x(k) rho_y(k)).

    With ``y`` given this is Bartlett's count for the correlation of x with
    y; alone, the integrated autocorrelation time of ``x`` (summed up to the
    first zero crossing).
    """
    n = len(x)
    if n < 4 or not np.any(x - x.mean()):
        return float(max(n, 1))
    rx = autocorrelation(x, n - 1)
    ry = rx if y is None else autocorrelation(y, n - 1)
    prod = rx * ry
    neg = np.nonzero(prod[1:] <= 0.0)[0]
    cut = neg[0] + 1 if len(neg) else n
    tau = max(1.0, 1.0 + 2.0 * float(np.sum(prod[1:cut])))
    return float(max(n / tau, 2.0))


@dataclass
class Uncertainty:
    """Standard errors [SI] by key, the correlation matrix, the keys stopped at a bound, and
    the effective sample count of the residual."""

    stderr: dict[str, float]
    correlation: np.ndarray
    at_bound: list[str]
    n_eff: float


def uncertainty(keys: list[str], x: np.ndarray, r: np.ndarray, jac: np.ndarray,
                lo: np.ndarray, hi: np.ndarray) -> Uncertainty:
    """Standard errors and correlation of the values ``x`` of ``keys`` fitted with residual
    ``r`` and Jacobian ``jac``; the keys within a relative 1e-6 of a bound ``lo``/``hi``."""
    n, p = len(r), len(x)
    n_eff = effective_samples(r)
    cov = float(r @ r) / max(n - p, 1) * (n / n_eff) * np.linalg.pinv(jac.T @ jac)
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    with np.errstate(invalid='ignore', divide='ignore'):
        corr = cov / np.outer(sd, sd)
    corr = np.where(np.isfinite(corr), corr, 0.0)
    at_bound = [k for k, v, a, b in zip(keys, x, lo, hi)
                if np.isclose(v, a, rtol=1e-6, atol=0) or np.isclose(v, b, rtol=1e-6, atol=0)]
    return Uncertainty(dict(zip(keys, map(float, sd))), corr, at_bound, n_eff)
