"""Output-error refinement: fit chosen parameters so that the simulated outputs match one or
more experiments, with bounds, standard errors and correlations.

A thin use of :mod:`pneumatic_servo.fitting`: each experiment is one part,
predicted open loop over the whole record or in k-step windows
(:mod:`pneumatic_servo.prediction`), its channels normalised by their
measured spread.
"""
from __future__ import annotations

import numpy as np

from ..errors import ConfigError, PneumaticServoError
from ..experiment import CHANNELS, Experiment
from ..fitting import Fit, Part, Problem, channel_scales, fit, residual_rows
from ..fitting.problem import with_values
from ..model.config import ModelConfig
from ..prediction import COMPARE_HORIZON_S, open_loop, windows

#: finite-difference step of the Jacobian relative to a parameter's scale, and at least this
#: share of its plausible magnitude (below that, stick-slip roughness swamps the slope)
FD_STEP = FD_MIN = 1e-3
#: the result of :func:`fit_output_error` (a :class:`~pneumatic_servo.fitting.Fit` with the
#: per-channel RMS residual in ``rms``)
FitResult = Fit
MODES = ('open_loop', 'k_step')


def parts_of(experiments: list[Experiment], channels=None, mode: str = 'open_loop',
             horizon_s: float = COMPARE_HORIZON_S, skip_s: float = 0.0) -> list[Part]:
    """One fitting part per experiment: its measured ``channels`` (default all), predicted
    open loop or in k-step windows of ``horizon_s`` [s], the first ``skip_s`` [s] left out."""
    if mode not in MODES:
        raise ConfigError(f"unknown prediction mode {mode!r}; use 'open_loop' or 'k_step'")
    parts = []
    for exp in experiments:
        scales = channel_scales(exp, channels)
        if exp.static:
            parts.append(Part(exp, scales))
            continue
        plan = open_loop(exp) if mode == 'open_loop' else windows(exp, horizon_s)
        first = int(np.searchsorted(exp.t, exp.t[0] + skip_s)) if skip_s > 0 else 0
        parts.append(Part(exp, scales, plan, first))
    if not any(p.scales for p in parts):
        raise PneumaticServoError('none of the experiments measures a fitted channel '
                                  f'({", ".join(channels or CHANNELS)})')
    return parts


def channel_rms(prob: Problem, values) -> dict[str, float]:
    """Normalised RMS residual per channel over all parts."""
    row = residual_rows(prob.model, prob.parts, [prob.config_at(values)])[0]
    return {ch: float(np.sqrt(np.mean(r ** 2))) for ch, r in row.items()}


def fit_output_error(config: ModelConfig, experiments: list[Experiment], free: list[str],
                     channels=None, mode: str = 'open_loop',
                     horizon_s: float = COMPARE_HORIZON_S, bounds: dict | None = None,
                     start: dict | None = None, max_nfev: int = 40,
                     skip_s: float = 0.0, starts: list[dict] | None = None,
                     bracket: bool = False) -> Fit:
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
    max_nfev : int
        Most evaluations of the solver.
    skip_s : float [s]
        Leave the first ``skip_s`` of every record out of the residual.
    starts : list of dict, optional
        Other start points (key -> value, the rest as ``start``): the cost is evaluated at
        each (one batch) and the fit starts from the best. A leak or a friction level can
        have a local minimum near the default that a start far away does not see.
    bracket : bool
        Search along each parameter before the solver (``fitting.solver.bracket_search``),
        for costs that stick-slip makes rough.

    Returns
    -------
    Fit
        Fitted config and values, standard errors, the correlation matrix and,
        in ``rms``, the normalised RMS residual per channel.
    """
    if not free:
        raise ConfigError('nothing to fit: name at least one free parameter')
    free = list(free)
    for key in free:
        config.get(key)  # a clear error for an unknown key
    start = start or {}
    config = with_values(config, list(start), list(start.values()))
    prob = Problem(config, free, parts_of(experiments, channels, mode, horizon_s, skip_s),
                   bounds=bounds, fd_step=FD_STEP, fd_min=FD_MIN)
    x0 = None
    if starts:
        x_start = np.array([config.get(k) for k in free])
        trials = [np.clip([s.get(k, v) for k, v in zip(free, x_start)], prob.lo, prob.hi)
                  for s in [{}] + list(starts)]
        x0 = trials[int(np.argmin(prob.costs(trials)))]
    result = fit(prob, x0, max_nfev=max_nfev, bracket=bracket)
    result.rms = channel_rms(prob, list(result.values.values()))
    return result
