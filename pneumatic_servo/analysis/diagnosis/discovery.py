"""When no named effect fits: find the equation, and the terms in it, where the missing
physics lives.

Every generic correction of :mod:`pneumatic_servo.effects.corrections` (one per
balance equation and measurement, each a linear combination of the
regressors) is tried through the real simulator, with the same split,
residuals and criteria as the named effects:

1. **Screen** (one batch): each (equation, regressor) coefficient is stepped
   once from zero; the change of the fitted and held-out residuals is its
   sensitivity. Per equation, a forward selection of at most ``max_terms``
   regressors fits the fit-part residual with these sensitivities (linear
   least squares) and keeps the subset with the best held-out information
   criterion. This is output-error sparse regression: it needs no derivative
   of noisy, quantised signals and no unmeasured gas temperature, which an
   equation-error regression would.
2. **Confirm**: the best few equations are fitted in full (nonlinear, through
   the simulator, with the bases and effects that the named candidates refit)
   and scored on the held-out data; the result is a :class:`Discovered`
   candidate that the ranking treats like a named one.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ...effects.corrections import BY_EQUATION, EQUATIONS, REGRESSORS, coefficient_name
from ...fitting import residual_rows, stack
from ...fitting.problem import with_values
from ...model.assembly import Model
from ...model.config import ModelConfig
from .candidates import Baseline, Candidate, fit_parameters
from .data import Data
from .hosts import shared_host
from .interpret import interpret
from .options import DiagnoseOptions
from .scoring import relative_fall, score_many

#: sensitivity step of a coefficient, as a share of its plausible size: large enough to step
#: over the roughness of stick-slip, small enough for the response to stay linear
SCREEN_STEP = 0.05


@dataclass
class Discovered(Candidate):
    """A generic correction fitted and scored like a named effect.

    ``effect`` is the correction component's name; ``equation`` where it acts;
    ``terms`` its regressors with their coefficients [SI].
    """

    equation: str = ''
    interpretation: str = ''
    #: held-out error reduction the linear screen predicted
    screened_reduction: float = 0.0

    @property
    def terms(self) -> dict[str, float]:
        return {k.partition('.')[2].removesuffix('_coefficient'): v
                for k, v in self.params.items()}

    def to_json(self) -> dict:
        stderr = {k.partition('.')[2].removesuffix('_coefficient'): v
                  for k, v in self.stderr.items()}
        return {'equation': self.equation, 'terms': self.terms, 'stderr': stderr,
                'error_reduction': self.error_reduction,
                'interpretation': self.interpretation, **super().to_json()}


def correction_host(config: ModelConfig) -> ModelConfig:
    """``config`` on its shared host plus every generic correction at zero (one compiled
    composition for the whole discovery)."""
    host = shared_host(config)
    for cls_ in BY_EQUATION.values():
        if cls_.name not in host.effects:
            host = host.with_effect(cls_.name, cls_.neutral)
    return host


def _key(equation: str, regressor: str) -> str:
    return f'{BY_EQUATION[equation].name}.{coefficient_name(regressor)}'


@dataclass
class Screened:
    """One equation after the linear screen: its best regressors and their coefficients [SI],
    and the held-out error reduction the linearisation predicts."""

    equation: str
    keys: list[str]
    start: dict[str, float]
    reduction: float
    bic: float = field(default=0.0)


def _sensitivities(model, host, keys, steps, parts) -> tuple[np.ndarray, np.ndarray]:
    """(residual at zero, sensitivity matrix) over ``parts``: one batch."""
    configs = [host] + [with_values(host, [k], [h]) for k, h in zip(keys, steps)]
    rows = [stack(r) for r in residual_rows(model, parts, configs)]
    r0 = rows[0]
    return r0, np.column_stack([(r - r0) / h for r, h in zip(rows[1:], steps)])


def _forward_selection(r_fit, S_fit, r_val, S_val, n_eff: float, max_terms: int):
    """(columns, coefficients, held-out RSS) of the subset with the best held-out BIC."""
    base = float(r_val @ r_val)
    best, chosen = ([], np.zeros(0), base, 0.0), []
    for _ in range(max_terms):
        trials = []
        for j in range(S_fit.shape[1]):
            if j in chosen or not np.any(S_fit[:, j]):
                continue
            cols = chosen + [j]
            coef = np.linalg.lstsq(S_fit[:, cols], -r_fit, rcond=None)[0]
            fit_rss = float(np.sum((r_fit + S_fit[:, cols] @ coef) ** 2))
            trials.append((fit_rss, cols, coef))
        if not trials:
            break
        _, cols, coef = min(trials, key=lambda t: t[0])
        rss = float(np.sum((r_val + S_val[:, cols] @ coef) ** 2))
        bic = n_eff * math.log(max(rss, 1e-300) / max(base, 1e-300)) + len(cols) * math.log(n_eff)
        chosen = cols
        if bic < best[3]:
            best = (cols, coef, rss, bic)
    return best


def screen_terms(base: Baseline, data: Data, n_eff: float, options: DiagnoseOptions
                 ) -> tuple[list[Screened], ModelConfig, Model]:
    """The linear screen of every equation, best first, with the host it ran on."""
    host = correction_host(base.config)
    model = Model(host)
    keys, steps = [], []
    for eq in EQUATIONS:
        for reg in REGRESSORS:
            keys.append(_key(eq.name, reg.name))
            steps.append(SCREEN_STEP * eq.size / reg.typical)
    r_fit, S_fit = _sensitivities(model, host, keys, steps, data.fit)
    r_val, S_val = _sensitivities(model, host, keys, steps, data.val)
    base_rms = math.sqrt(float(r_val @ r_val) / len(r_val))
    out, n_reg = [], len(REGRESSORS)
    for i, eq in enumerate(EQUATIONS):
        block = slice(i * n_reg, (i + 1) * n_reg)
        cols, coef, rss, bic = _forward_selection(r_fit, S_fit[:, block], r_val, S_val[:, block],
                                                  n_eff, options.max_terms)
        if not cols:
            continue
        chosen = [keys[block][j] for j in cols]
        reduction = relative_fall(math.sqrt(rss / len(r_val)), base_rms)
        out.append(Screened(eq.name, chosen, dict(zip(chosen, map(float, coef))), reduction,
                            bic))
    return sorted(out, key=lambda s: s.bic), host, model


def confirm(screened: Screened, host: ModelConfig, model: Model, base: Baseline, data: Data,
            free: list[str], options: DiagnoseOptions) -> Discovered:
    """Fit the screened terms in full through the simulator and score them held out."""
    t0 = time.perf_counter()
    name = BY_EQUATION[screened.equation].name
    keys = screened.keys
    start = {k: float(np.clip(v, host.param(k).lower, host.param(k).upper))
             for k, v in screened.start.items()}
    start_cfg = with_values(host, list(start), list(start.values()))
    result = fit_parameters(model, start_cfg, keys + [k for k in free if k not in keys], data,
                            options, bracket=False)
    score = score_many(model, data, [result.config])[0]
    values = {k: result.config.get(k) for k in keys}
    base_values = {k: result.config.get(k) for k in free}
    clean = with_values(base.config, list(base_values), list(base_values.values()))
    clean = clean.with_effect(name, {k.partition('.')[2]: v for k, v in values.items()})
    problems = [f'{k} stopped at a bound of its fit range' for k in result.at_bound
                if k in values]
    found = Discovered(
        effect=name, params=values, stderr={k: result.stderr[k] for k in keys}, fixed={},
        base_params=base_values, score=score,
        error_reduction=relative_fall(score.overall, base.score.overall),
        channel_reduction={ch: relative_fall(v, base.score.channels.get(ch, 0.0))
                           for ch, v in score.channels.items()},
        n_params=len(keys), problems=problems, config=clean, correlation=result.correlation,
        converged=result.converged, seconds=time.perf_counter() - t0,
        acts_on=BY_EQUATION[screened.equation].acts_on,
        summary=BY_EQUATION[screened.equation].equation.description,
        equation=screened.equation, screened_reduction=screened.reduction)
    found.interpretation = interpret(screened.equation, found.terms, base.config)
    return found


def discover(base: Baseline, data: Data, free: list[str], n_eff: float,
             options: DiagnoseOptions) -> list[Discovered]:
    """Generic corrections of the baseline, screened and the best ``discovery_fits``
    confirmed; unranked (the ranking fills in the information criteria)."""
    screened, host, model = screen_terms(base, data, n_eff, options)
    return [confirm(s, host, model, base, data, free, options)
            for s in screened[:options.discovery_fits]]
