"""Output-error refinement: fit chosen parameters so that the simulated outputs match
one or more experiments, with bounds, standard errors and correlations.

Residuals are normalised per experiment and channel by the channel's
measured spread, so angle [rad], pressure [Pa] and flow [kg/s] channels
weigh alike. The Jacobian is computed by finite differences with all
perturbed parameter sets simulated in one parallel batch.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from ..errors import ConfigError, PneumaticServoError
from ..experiment import Experiment
from ..model.assembly import Model
from ..model.config import ModelConfig
from .predict import predict_many

#: channel -> (signal, smallest normalising spread in SI units)
FIT_CHANNELS = {'angle': ('angle_rad', 2e-3), 'p_a': ('p_a_pa', 2e3), 'p_b': ('p_b_pa', 2e3),
                'm4': ('m4_kg_s', 1e-6), 'm5': ('m5_kg_s', 1e-7)}


@dataclass
class FitResult:
    """Fitted values and what the data can say about them."""

    config: ModelConfig
    free: list[str]
    values: dict[str, float]
    stderr: dict[str, float]
    correlation: np.ndarray
    cost: float
    rms: dict[str, float]          # normalised RMS residual per channel
    n_data: int
    success: bool
    message: str = ''
    at_bound: list[str] = field(default_factory=list)

    def summary(self) -> str:
        lines = [f'{k} = {v:.6g} +/- {self.stderr[k]:.2g}' for k, v in self.values.items()]
        return '\n'.join(lines)


def channel_scales(exp: Experiment) -> dict[str, float]:
    """Normalising spread [SI] of each fit channel present in ``exp``."""
    out = {}
    for ch, (sig, floor) in FIT_CHANNELS.items():
        if sig in exp.signals:
            out[ch] = max(float(np.nanstd(exp[sig])), floor)
    return out


class Objective:
    """Normalised residuals of a set of experiments as a function of free parameter values."""

    def __init__(self, config: ModelConfig, experiments: list[Experiment], free: list[str],
                 channels=None, mode: str = 'open_loop', horizon_s: float = 0.2,
                 skip_s: float = 0.0):
        self.base = config
        self.model = Model(config)
        self.experiments = experiments
        self.free = list(free)
        for key in self.free:
            config.get(key)  # raises a clear error for an unknown key
        self.mode, self.horizon_s, self.skip_s = mode, horizon_s, skip_s
        self.scales = [channel_scales(e) for e in experiments]
        self.channels = [[ch for ch in s if channels is None or ch in channels]
                         for s in self.scales]
        if not any(self.channels):
            raise PneumaticServoError('none of the experiments measures a fitted channel '
                                      f'({", ".join(channels or FIT_CHANNELS)})')

    def config_at(self, values) -> ModelConfig:
        cfg = self.base.copy()
        for key, v in zip(self.free, values):
            cfg.set(key, float(v))
        return cfg

    def residuals_many(self, value_sets) -> np.ndarray:
        """Residual vectors (rows) for several parameter value sets, simulated together."""
        configs = [self.config_at(v) for v in value_sets]
        parts = []
        for exp, scales, chans in zip(self.experiments, self.scales, self.channels):
            preds = predict_many(self.model, exp, configs, self.mode, self.horizon_s)
            keep = exp.t >= exp.t[0] + self.skip_s if not exp.static else slice(None)
            rows = []
            for pred in preds:
                r = [(pred[FIT_CHANNELS[ch][0]][keep] - exp[FIT_CHANNELS[ch][0]][keep])
                     / scales[ch] for ch in chans]
                rows.append(np.concatenate(r) if r else np.zeros(0))
            parts.append(np.array(rows))
        res = np.concatenate(parts, axis=1)
        # a failed simulation is a very poor fit, not a crash of the optimiser
        return np.where(np.isfinite(res), res, 1e3)

    def residuals(self, values) -> np.ndarray:
        return self.residuals_many([values])[0]

    def channel_rms(self, values) -> dict[str, float]:
        """Normalised RMS residual per channel over all experiments."""
        cfg = self.config_at(values)
        sums: dict[str, list] = {}
        for exp, scales, chans in zip(self.experiments, self.scales, self.channels):
            pred = predict_many(self.model, exp, [cfg], self.mode, self.horizon_s)[0]
            for ch in chans:
                sig = FIT_CHANNELS[ch][0]
                r = (pred[sig] - exp[sig]) / scales[ch]
                sums.setdefault(ch, []).append(r[np.isfinite(r)])
        return {ch: float(np.sqrt(np.mean(np.concatenate(v) ** 2))) for ch, v in sums.items()}


def correlation_inflation(residual: np.ndarray) -> float:
    """n / n_eff of a residual with lag-1 autocorrelation rho: (1 + rho) / (1 - rho), >= 1."""
    r = residual - residual.mean()
    denom = float(np.dot(r, r))
    if r.size < 3 or denom == 0.0:
        return 1.0
    rho = min(max(float(np.dot(r[1:], r[:-1])) / denom, 0.0), 0.999)
    return (1.0 + rho) / (1.0 - rho)


def _bounds(config: ModelConfig, free, bounds):
    lo, hi = [], []
    for key in free:
        p = config.param(key)
        b = (bounds or {}).get(key, (p.lower, p.upper))
        lo.append(b[0])
        hi.append(b[1])
    return np.array(lo, float), np.array(hi, float)


def fit_output_error(config: ModelConfig, experiments: list[Experiment], free: list[str],
                     channels=None, mode: str = 'open_loop', horizon_s: float = 0.2,
                     bounds: dict | None = None, start: dict | None = None,
                     max_nfev: int = 40, skip_s: float = 0.0) -> FitResult:
    """Fit the parameters ``free`` (``'owner.name'`` keys of ``config``) to ``experiments``.

    Parameters
    ----------
    config : ModelConfig
        Model with every component the fitted keys belong to.
    experiments : list of Experiment
        Time series and/or static tables, fitted together.
    free : list of str
        Parameter keys to fit; others stay at ``config``'s values.
    channels : iterable of str, optional
        Subset of 'angle', 'p_a', 'p_b', 'm4', 'm5' (default: all measured).
    mode : {'open_loop', 'k_step'}
        Prediction mode; k_step re-initialises every ``horizon_s`` [s].
    bounds : dict, optional
        key -> (lower, upper) in SI; default the parameter's declared bounds.
    start : dict, optional
        key -> start value; default the config's value.

    Returns
    -------
    FitResult
        Fitted config and values, standard errors from the Jacobian
        (sigma^2 (J'J)^-1), the correlation matrix and per-channel RMS.
    """
    if not free:
        raise ConfigError('nothing to fit: name at least one free parameter')
    obj = Objective(config, experiments, free, channels, mode, horizon_s, skip_s)
    lo, hi = _bounds(config, obj.free, bounds)
    x0 = np.array([(start or {}).get(k, config.get(k)) for k in obj.free], float)
    x0 = np.clip(x0, lo, hi)
    scale = np.maximum(np.abs(x0), 1e-3 * (hi - lo))
    scale = np.where(scale > 0, scale, 1.0)

    def jac(x):
        steps = 1e-3 * scale
        sets = [x]
        for i in range(len(x)):
            xi = x.copy()
            # step away from the nearer bound so the probe stays feasible
            xi[i] = x[i] + steps[i] if x[i] + steps[i] <= hi[i] else x[i] - steps[i]
            sets.append(xi)
        rows = obj.residuals_many(sets)
        d = np.array([s[i] - x[i] for i, s in enumerate(sets[1:])])
        return ((rows[1:] - rows[0]) / d[:, None]).T

    sol = least_squares(obj.residuals, x0, jac=jac, bounds=(lo, hi), x_scale=scale,
                        max_nfev=max_nfev, xtol=1e-6, ftol=1e-8)
    n, p = sol.fun.size, len(x0)
    J = sol.jac
    dof = max(n - p, 1)
    sigma2 = 2.0 * sol.cost / dof
    # residuals sampled at 1 kHz are far from independent: inflate the covariance by
    # n / n_eff for an AR(1) residual, so the standard errors are not over-confident
    cov = sigma2 * correlation_inflation(sol.fun) * np.linalg.pinv(J.T @ J)
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    with np.errstate(invalid='ignore', divide='ignore'):
        corr = cov / np.outer(sd, sd)
    corr = np.where(np.isfinite(corr), corr, 0.0)
    at_bound = [k for k, v, a, b in zip(obj.free, sol.x, lo, hi)
                if np.isclose(v, a, rtol=1e-6, atol=0) or np.isclose(v, b, rtol=1e-6, atol=0)]
    return FitResult(obj.config_at(sol.x), obj.free, dict(zip(obj.free, map(float, sol.x))),
                     dict(zip(obj.free, map(float, sd))), corr, float(sol.cost),
                     obj.channel_rms(sol.x), n, bool(sol.success), sol.message, at_bound)
