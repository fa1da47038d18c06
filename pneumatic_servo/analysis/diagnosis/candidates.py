"""Candidate effects: which to try, a coarse screen of each, and the full fit and held-out
score of the best."""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ... import effects as registry
from ...errors import ConfigError, SimulationError
from ...fitting import FAILED_RESIDUAL, Fit, Problem, fit, residual_rows, stack
from ...fitting.problem import with_values
from ...model.assembly import Model
from ...model.config import ModelConfig
from ...prediction import predict_checked
from .data import Data
from .hosts import host_for, shared_host
from .options import DiagnoseOptions
from .scoring import Score, relative_fall, score_many

#: fit tolerances: relative parameter step and relative cost fall that end the fit; far
#: below what the held-out comparison can resolve
XTOL, FTOL = 1e-3, 1e-4
#: finite-difference step of the Jacobian, relative to a parameter's size: large enough
#: to step over the small-scale roughness that stick-slip gives the fit cost
FD_STEP = 1e-2


def candidate_effects(config: ModelConfig, effects=None) -> list[str]:
    """Effects to try: the given names, else every registered additive effect not already
    in ``config`` (the catalogue first, then users' own effects; never a generic correction,
    which the discovery step fits)."""
    if effects:
        names = []
        for name in effects:
            cls_ = registry.get(name)
            if cls_.slot is not None:
                raise ConfigError(f'{name!r} fills the {cls_.slot} slot; diagnose tries '
                                  'additive effects only')
            names.append(cls_.name)
    else:
        catalogue = list(registry.CATALOGUE_NAMES)
        names = catalogue + [n for n in registry.names()
                             if n not in catalogue and registry.get(n).slot is None
                             and not registry.get(n).generic]
    return [n for n in dict.fromkeys(names) if n not in config.effects]


def fitted_keys(name: str) -> list[str]:
    """``'effect.param'`` keys of the parameters diagnosis fits for effect ``name``."""
    keys = [f'{name}.{p.name}' for p in registry.get(name).params if p.fit]
    if not keys:
        raise ConfigError(f'effect {name!r} declares no parameter with fit=True, so diagnosis '
                          'cannot fit it; mark its main parameter fit=True')
    return keys


def fit_parameters(model: Model, config: ModelConfig, keys: list[str], data: Data,
                   options: DiagnoseOptions, bracket: bool = True) -> Fit:
    """Fit ``keys`` of ``config`` on the fit parts: a bracket search finds the basin (the
    stick-slip cost is rough; skipped when a good start is known), the bounded trust-region
    solver polishes it."""
    prob = Problem(config, keys, data.fit, model=model, fd_step=FD_STEP)
    return fit(prob, max_nfev=options.max_iter, xtol=XTOL, ftol=FTOL, bracket=bracket)


def why_undetermined(config: ModelConfig, key: str, reason: str, data: Data) -> str:
    """Why the data do not determine ``key``, and which record would: the part it belongs
    to may not be in the circuits of these records (its ``Param`` or component says where
    it acts), else ``reason`` from the identifiability test."""
    owner, _, name = key.partition('.')
    p = config.param(key)
    acts = p.circuits or (registry.get(owner).circuits if owner != 'core' else ())
    seen = sorted({e.circuit for e in data.experiments})
    if acts and not set(acts) & set(seen):
        part = p.part or owner
        return (f'{part} is not part of the {" or ".join(seen)} circuit: a '
                f'{" or ".join(acts)} record would determine it')
    return f'{reason} in these records'


def undetermined_values(config: ModelConfig, keys: list[str], undetermined: dict
                        ) -> dict[str, float]:
    """The values ``apply`` writes: each determined key as fitted, each undetermined one at
    its effect's neutral value where there is one (never silently at a default)."""
    out = {}
    for key in keys:
        owner, _, name = key.partition('.')
        neutral = registry.get(owner).neutral or {}
        out[key] = neutral[name] if key in undetermined and name in neutral else config.get(key)
    return out


def trial_grid(p) -> np.ndarray:
    """Trial values of parameter ``p`` over its plausible range, logarithmic on each side of 0."""
    lo, hi = p.plausible_range()
    lo, hi = max(lo, p.lower), min(hi, p.upper)
    fractions = np.array([0.003, 0.01, 0.03, 0.1, 0.3, 1.0])
    if lo > 0.0:
        return np.geomspace(lo, hi, 6) if hi / lo > 10.0 else np.linspace(lo, hi, 6)
    sides = [hi * fractions] if hi > 0.0 else []
    if lo < 0.0:
        sides.append(lo * fractions)
    return np.concatenate(sides)


def start_values(keys: list[str], host: ModelConfig, model: Model, data: Data
                 ) -> tuple[dict[str, float], float]:
    """Best point of a coarse grid of the effect's parameters, and its fit-set cost.

    Multi-parameter effects are tried along the diagonal (all parameters at
    the same fraction of their ranges). All trials run in one batch; the
    grid keeps the local fit from starting in the wrong basin.
    """
    grids = [trial_grid(host.param(k)) for k in keys]
    n = min(len(g) for g in grids)
    trials = [{k: float(g[i]) for k, g in zip(keys, grids)} for i in range(n)]
    trials.append({k: host.get(k) for k in keys})
    configs = [with_values(host, list(t), list(t.values())) for t in trials]
    costs = [float(stack(r) @ stack(r)) for r in residual_rows(model, data.fit, configs)]
    best = int(np.argmin(costs))
    return trials[best], costs[best]


def plausibility(config: ModelConfig, values: dict[str, float], at_bound: list[str]
                 ) -> list[str]:
    """Why fitted values are not physically plausible (empty list if they are)."""
    problems = []
    for key, v in values.items():
        p = config.param(key)
        lo, hi = p.plausible_range()
        if not lo <= v <= hi:
            problems.append(f'{key} = {v:.4g} {p.unit} is outside the plausible range '
                            f'[{lo:.4g}, {hi:.4g}] {p.unit}')
        elif key in at_bound:
            problems.append(f'{key} = {v:.4g} {p.unit} stopped at a bound of its fit range')
    return problems


@dataclass(frozen=True)
class Baseline:
    """The model as given (free base keys fitted), scored on the held-out parts."""

    config: ModelConfig
    score: Score
    values: dict[str, float] = field(default_factory=dict)


def baseline(config: ModelConfig, data: Data, free: list[str], options: DiagnoseOptions
             ) -> Baseline:
    """Held-out score of ``config`` itself, with ``free`` base keys fitted first if any."""
    host = shared_host(config)
    model = Model(host)
    values = {}
    if free:
        result = fit_parameters(model, host, list(free), data, options)
        values = result.values
        config = with_values(config, list(values), list(values.values()))
        host = result.config
    return Baseline(config, score_many(model, data, [host])[0], values)


@dataclass(frozen=True)
class Screen:
    """A candidate after the coarse grid: its host model and best grid point."""

    name: str
    host: ModelConfig
    model: Model = field(repr=False)
    keys: list[str]
    start: dict[str, float]
    cost: float
    seconds: float


def placed(name: str, base: Baseline, start: dict[str, float]) -> Screen:
    """Effect ``name`` added to the baseline, to be fitted from ``start`` (no grid tried)."""
    host = host_for(base.config, name)
    return Screen(name, host, Model(host), fitted_keys(name), start, math.nan, 0.0)


def screen_effect(name: str, base: Baseline, data: Data) -> Screen:
    """Add effect ``name`` to the baseline and try a coarse grid of its parameters."""
    t0 = time.perf_counter()
    bare = placed(name, base, {})
    start, cost = start_values(bare.keys, bare.host, bare.model, data)
    return replace(bare, start=start, cost=cost, seconds=time.perf_counter() - t0)


@dataclass(frozen=True)
class Candidate:
    """One effect tried: fitted values, held-out score and whether they are plausible; the
    ranking (:func:`~.verdict.rank`) returns copies with its judgement filled in."""

    effect: str
    params: dict[str, float]
    stderr: dict[str, float]
    fixed: dict[str, float]
    base_params: dict[str, float]
    score: Score
    error_reduction: float
    channel_reduction: dict[str, float]
    n_params: int
    problems: list[str]
    config: ModelConfig = field(repr=False)
    correlation: np.ndarray = field(repr=False, default=None)
    converged: bool = True
    seconds: float = 0.0
    acts_on: str = 'both'
    summary: str = ''
    #: False if the candidate was screened out after the coarse grid (not fitted)
    fitted: bool = True
    #: fitted keys the data do not determine -> why (left out of the criterion; ``apply``
    #: writes them at their neutral value where the effect has one)
    undetermined: dict[str, str] = field(default_factory=dict)
    #: scores on other experiments (``--validate-on``), if any were given
    validation: object = None
    #: filled by the ranking, against the reference it was tried on: information criteria,
    #: the one-sided p-value of its held-out gain and the level it is tested at
    #: (:mod:`.criteria`), the RMS [normalised] of the error it explains, that RMS in units
    #: of the prediction floor, and the sensor noise (for reference)
    delta_aic: float = 0.0
    delta_bic: float = 0.0
    gain_p_value: float = 1.0
    level: float = 0.0
    explained_rms: float = 0.0
    size_in_floor: float = 0.0
    noise_rms: float = 0.0
    #: the reference it was judged against departs from its floor (:mod:`.criteria`)
    reference_departs: bool = False

    @property
    def plausible(self) -> bool:
        return not self.problems

    def to_json(self) -> dict:
        return {'effect': self.effect, 'params': dict(self.params),
                'stderr': dict(self.stderr), 'fixed_params': dict(self.fixed),
                'base_params': dict(self.base_params),
                'error_reduction': self.error_reduction,
                'channel_error_reduction': dict(self.channel_reduction),
                'heldout_rms': self.score.to_json(), 'n_params': self.n_params,
                'delta_aic': self.delta_aic, 'delta_bic': self.delta_bic,
                'plausible': self.plausible, 'problems': list(self.problems),
                'acts_on': self.acts_on, 'summary': self.summary,
                'correlation': np.round(self.correlation, 4).tolist()
                if self.correlation is not None else None,
                'explained_rms': self.explained_rms, 'noise_rms': self.noise_rms,
                'gain_p_value': self.gain_p_value, 'level': self.level,
                'size_in_floor': self.size_in_floor,
                'reference_departs': self.reference_departs,
                'converged': self.converged, 'fitted': self.fitted,
                'undetermined': dict(self.undetermined),
                'validation': self.validation.to_json() if self.validation else None,
                'fit_seconds': round(self.seconds, 2)}


def _cannot_simulate(name: str, model: Model, config: ModelConfig, data: Data) -> None:
    """Raise why candidate ``name`` failed on every held-out window: ranked, it would only
    read as a huge negative gain (a user's hook that yields NaN), never as the fault it is."""
    why = ''
    for part in data.val:
        try:
            predict_checked(model, part.exp, config, part.plan)
        except SimulationError as exc:
            why = str(exc)
            break
    raise SimulationError(f'candidate {name!r} could not be simulated over any held-out '
                          f'window ({why or "every window failed"}); fix the effect, or '
                          'leave it out of the candidates (--effects)')


def try_effect(screen: Screen, base: Baseline, data: Data, free: list[str],
               options: DiagnoseOptions, full_fit: bool = True, bracket: bool = True
               ) -> Candidate:
    """Fit the screened effect (and ``free`` base keys) on the fit parts, score it held out.

    With ``full_fit=False`` the best grid point of the screen is scored as it
    is (a candidate screened out: no standard errors). Without ``bracket`` the fit polishes
    from the screen's start (a start known to lie in the right basin).
    """
    t0 = time.perf_counter()
    name, keys = screen.name, screen.keys
    cls_ = registry.get(name)
    host = with_values(screen.host, list(screen.start), list(screen.start.values()))
    undetermined = {}
    if full_fit:
        result = fit_parameters(screen.model, host, keys + [k for k in free if k not in keys],
                                data, options, bracket)
        fitted, stderr = result.config, result.stderr
        at_bound, corr, converged = result.at_bound, result.correlation, result.converged
        undetermined = {k: why_undetermined(fitted, k, result.identifiability.reason(k), data)
                        for k in keys if stderr[k] is None}
    else:
        fitted, stderr = host, {k: float('nan') for k in keys + list(free)}
        at_bound, corr, converged = [], None, False
    score = score_many(screen.model, data, [fitted])[0]
    if score.overall >= FAILED_RESIDUAL:
        _cannot_simulate(name, screen.model, fitted, data)
    values = undetermined_values(fitted, keys, undetermined)
    fixed = {f'{name}.{p.name}': fitted.get(f'{name}.{p.name}')
             for p in cls_.params if not p.fit}
    base_values = {k: fitted.get(k) for k in free}
    clean = with_values(base.config, list(base_values), list(base_values.values()))
    clean = clean.with_effect(name, {k.partition('.')[2]: v
                                     for k, v in {**values, **fixed}.items()})
    return Candidate(
        effect=name, params=values, stderr={k: stderr[k] for k in keys}, fixed=fixed,
        base_params=base_values, score=score,
        error_reduction=relative_fall(score.overall, base.score.overall),
        channel_reduction={ch: relative_fall(v, base.score.channels.get(ch, 0.0))
                           for ch, v in score.channels.items()},
        n_params=len(keys) - len(undetermined),
        problems=plausibility(fitted, {k: v for k, v in values.items() if k not in undetermined},
                              at_bound),
        config=clean, correlation=corr, converged=converged, undetermined=undetermined,
        seconds=screen.seconds + time.perf_counter() - t0, acts_on=cls_.acts_on,
        summary=cls_.summary, fitted=full_fit)
