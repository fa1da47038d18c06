"""What the data say about fitted values: standard errors, correlation, values at a bound.

The covariance is sigma^2 (J'J)^-1 of the normalised residuals, inflated by
n / n_eff: residuals sampled at 1 kHz are far from independent, and without
the inflation the standard errors would be over-confident by orders of
magnitude. :func:`effective_samples` is the package's one estimator of n_eff.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .identifiability import Identifiability, identifiability


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
    """Standard errors [SI] by key (None for a parameter the data do not determine), the
    correlation matrix (NaN in the rows of those), the keys stopped at a bound, the
    effective sample count of the residual, and what the data determine."""

    stderr: dict[str, float | None]
    correlation: np.ndarray
    at_bound: list[str]
    n_eff: float
    identifiability: Identifiability = field(default=None)


def uncertainty(keys: list[str], x: np.ndarray, r: np.ndarray, jac: np.ndarray,
                lo: np.ndarray, hi: np.ndarray, scale: np.ndarray | None = None
                ) -> Uncertainty:
    """Standard errors and correlation of the values ``x`` of ``keys`` fitted with residual
    ``r`` and Jacobian ``jac``; the keys within a relative 1e-6 of a bound ``lo``/``hi``.
    ``scale`` [SI] (default the values, or 1) weighs the columns of the identifiability test.

    The covariance is taken over the determined parameters only: a parameter the data
    do not see would otherwise have an arbitrary standard error (zero, from a
    pseudo-inverse), read as "known exactly"."""
    n, p = len(r), len(x)
    n_eff = effective_samples(r)
    scale = np.where(np.abs(x) > 0, np.abs(x), 1.0) if scale is None else scale
    ident = identifiability(keys, np.asarray(x, float), jac, scale)
    keep = [i for i, k in enumerate(keys) if k not in ident.undetermined]
    cov = np.full((p, p), np.nan)
    if keep:
        # columns scaled to their parameters' sizes first: a leak area (1e-8 m^2) and a
        # friction force (10 N) differ by 1e9 in column norm, and an unscaled pseudo-inverse
        # would drop the smaller as numerical noise and report its stderr as about zero
        s = np.asarray(scale, float)[keep]
        jk = jac[:, keep] * s
        cov[np.ix_(keep, keep)] = (float(r @ r) / max(n - len(keep), 1) * (n / n_eff)
                                   * np.outer(s, s) * np.linalg.pinv(jk.T @ jk))
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    with np.errstate(invalid='ignore', divide='ignore'):
        corr = cov / np.outer(sd, sd)
    at_bound = [k for k, v, a, b in zip(keys, x, lo, hi)
                if np.isclose(v, a, rtol=1e-6, atol=0) or np.isclose(v, b, rtol=1e-6, atol=0)]
    stderr = {k: (float(sd[i]) if i in keep else None) for i, k in enumerate(keys)}
    return Uncertainty(stderr, corr, at_bound, n_eff, ident)
