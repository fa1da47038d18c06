"""Which physical effect is missing: add each candidate, fit it, score it on held-out data.

For every candidate effect (the catalogue and any user-registered effect),
the model is extended with it, the effect's ``fit=True`` parameters (plus
any base parameters the user frees, plus the effects already in the model)
are fitted by output error on one part of the data, and the extended model
is scored on the other part. Candidates are ranked by the validated fall of
the residual, penalised by an information criterion (BIC) for the
parameters they add. An effect is the verdict only if it earns its place:
a real fall of the held-out residual, a clear BIC gain, an explained error
well above the sensor noise, and physically plausible fitted values.
Otherwise the verdict is ``'none'``, so that clean data raise no alarm.

How the residual is formed:

* **k-step segments** (:func:`pneumatic_servo.prediction.quiet_starts`): the
  actuator integrates, so open-loop errors grow without bound; every
  ``horizon_s`` the model restarts from the measured state, at the quietest
  sample nearby, with the unmeasured states from a short lead-in.
* **Split** (:mod:`.data`): alternate blocks of segments are fitted and held
  out; table rows alternate.
* **Scaling and smoothing**: channels are normalised by their measured
  spread; time-series residuals are smoothed over ``smooth_s``.
* **Fitting** (:mod:`.candidates`): a coarse grid screens every candidate; the
  best few are fitted in full (:mod:`pneumatic_servo.fitting`). Compositions
  are shared where an effect can be switched off by value (:mod:`.hosts`).
"""
from __future__ import annotations

import copy
import time

import numpy as np

from ... import effects as registry
from ...experiment import Experiment
from ...fitting import effective_samples
from ...model.assembly import Model
from ...model.config import ModelConfig
from ...prediction import predict
from ..regimes import error_shares, hot_spots
from ..residuals import residual_tests, summary
from .candidates import Baseline, baseline, candidate_effects, screen_effect, try_effect
from .data import Data
from .discovery import Discovered, discover
from .hosts import shared_host
from .ladder import ladder
from .options import DiagnoseOptions
from .result import Diagnosis
from .scoring import relative_fall
from .status import certain, consistent, decide
from .validation import score_on, validate
from .verdict import earns_place, rank


def predictions(config: ModelConfig, data: Data) -> list[dict[str, np.ndarray]]:
    """Predicted signals of every prepared experiment on its own time base, segment by
    segment (NaN outside the segments); static tables row by row."""
    host = shared_host(config)
    model = Model(host)
    out = []
    for exp, fit, val in zip(data.experiments, data.fit, data.val):
        plan = None
        if not exp.static:
            plan = fit.plan.subset(sorted(fit.plan.segments + val.plan.segments))
        out.append(predict(model, exp, [host], plan)[0])
    return out


def where_it_fails(experiments: list[Experiment], preds: list[dict],
                   config: ModelConfig) -> dict:
    """Regime error shares, hot spots and residual tests of a model's predictions (JSON)."""
    shares = error_shares(experiments, preds, config)
    series = [(e, p) for e, p in zip(experiments, preds) if not e.static]
    out = {'regimes': [s.to_json() for s in shares], 'hot_spots': hot_spots(shares)}
    if series:
        exps, prs = [e for e, _ in series], [p for _, p in series]
        tests = residual_tests(exps, prs)
        summ = summary(exps, prs, tests)
        out['residuals'] = {**summ, 'channels': {
            ch: {'rms': t.rms, 'acf_outside_band': t.whiteness,
                 'xcorr_command_peak': dict(zip(('lag_s', 'r'), t.xcorr_peak)),
                 'xcorr_band': t.xcorr_band,
                 'correlations': {k: {'r': r, 'band': t.bands[k]}
                                  for k, r in t.correlations.items()}}
            for ch, t in tests.items()}}
    return out


def present_keys(config: ModelConfig) -> list[str]:
    """The parameters of the effects already in ``config`` that are refitted with every
    candidate (each effect's class says which)."""
    return [f'{name}.{key}' for name, values in config.effects.items()
            for key in registry.get(name).refit_keys(values)]


def diagnose(experiments: list[Experiment], config: ModelConfig | None = None,
             effects=None, free=(), options: DiagnoseOptions | None = None,
             progress=None, validate_on: list[Experiment] | None = None) -> Diagnosis:
    """Find the physical effect missing from ``config`` that the ``experiments`` show.

    Parameters
    ----------
    experiments : list of Experiment
        Time series (any circuit) and static tables, diagnosed jointly.
    config : ModelConfig, optional
        The model as it stands (default the paper's).
    effects : iterable of str, optional
        Candidates to try (default: every registered additive effect not in
        ``config``, users' own included).
    free : iterable of str
        Base parameter keys (``'owner.name'``) refitted with every candidate
        and for the baseline.
    options : DiagnoseOptions, optional
        Fit and scoring settings.
    progress : callable, optional
        Called with each finished :class:`~.candidates.Candidate`.
    validate_on : list of Experiment, optional
        Other experiments (any circuit) on which every candidate and every rung of
        the ladder is also scored, whole (:mod:`.validation`).

    Returns
    -------
    Diagnosis
        Verdict (an effect name or 'none'), ranking best first, ties and a
        suggested experiment, and the held-out error ladder.
    """
    t0 = time.perf_counter()
    options = options or DiagnoseOptions()
    config = config or ModelConfig.paper()
    free = list(free)
    for key in free:
        config.get(key)  # a clear error for an unknown key
    if options.refit_present:
        free += [k for k in present_keys(config) if k not in free]
    names = candidate_effects(config, effects)
    data = Data.of(experiments, options)
    timings = {'prepare': time.perf_counter() - t0}
    base = baseline(config, data, free, options)
    base_preds = predictions(base.config, data)
    where = where_it_fails(data.experiments, base_preds, base.config)
    timings['baseline'] = time.perf_counter() - t0 - timings['prepare']
    screens = [screen_effect(name, base, data) for name in names]
    full = {s.name for s in sorted(screens, key=lambda s: s.cost)[:options.full_fits]}
    candidates = []
    for scr in screens:
        cand = try_effect(scr, base, data, free, options, full_fit=scr.name in full)
        timings[scr.name] = cand.seconds
        candidates.append(cand)
        if progress is not None:
            progress(cand)
    host = shared_host(base.config)
    noise = data.noise(Model(host), host)
    ranking = rank(candidates, base, options, data.independent, noise)
    found = []
    if options.discover and (any(certain(c, options) or earns_place(c, options)
                                 for c in ranking)
                             or not consistent(base.score.overall, noise)):
        t1 = time.perf_counter()
        found = look_for_terms(base, data, free, options, noise, progress)
        timings['discovery'] = time.perf_counter() - t1
        # one effective sample count for all, so that named and generic compare fairly
        joint = rank(candidates + found, base, options, data.independent, noise)
        ranking = [c for c in joint if not isinstance(c, Discovered)]
        found = [c for c in joint if isinstance(c, Discovered)]
    def pair(first, second):
        """``second`` fitted on top of ``first``: (the step, the pair against the base)."""
        t1 = time.perf_counter()
        with_first = Baseline(first.config, first.score, base.values)
        step = try_effect(screen_effect(second.effect, with_first, data), with_first, data,
                          free, options)
        step = rank([step], with_first, options, data.independent, noise)[0]
        both = copy.copy(step)
        both.n_params += first.n_params
        both = rank([both], base, options, data.independent, noise)[0]
        both.error_reduction = relative_fall(both.score.overall, base.score.overall)
        timings['named_pair'] = time.perf_counter() - t1
        return step, both

    finding = decide(ranking, found, base.score.overall, noise, options, pair)
    if finding.look_on_top:
        winner = next(c for c in ranking if c.effect == finding.verdict)
        t1 = time.perf_counter()
        on_top = Baseline(winner.config, winner.score, base.values)
        found = look_for_terms(on_top, data, free + present_keys(winner.config), options,
                               noise, progress)
        timings['discovery_on_top'] = time.perf_counter() - t1
    other = Data.of(validate_on, options) if validate_on else None
    if other is not None:
        t1 = time.perf_counter()
        base_other = score_on(base.config, shared_host, other)
        for c in ranking + found:
            c.validation = validate(c, base_other, other)
        timings['validation'] = time.perf_counter() - t1
        winner = next((c for c in ranking + found if c.effect == finding.verdict), None)
        if winner is not None and winner.validation.hurts:
            finding.reason += (f'; but it makes the other experiments worse (error '
                               f'{-100 * winner.validation.error_reduction:+.0f} %): it may '
                               'only overfit this one')
    result = Diagnosis(finding, ranking, base, options, free, [e.name for e in experiments],
                       0.0, discovered=found if finding.status in (
                           'partly_explained', 'unexplained') else [],
                       timings=timings, where=where, data=data, base_predictions=base_preds,
                       validated_on=[e.name for e in validate_on or ()])
    t1 = time.perf_counter()
    result.ladder = ladder(config, data, result.added, base, other)
    timings['ladder'] = time.perf_counter() - t1
    result.seconds = time.perf_counter() - t0
    return result


def look_for_terms(base: Baseline, data: Data, free: list[str], options: DiagnoseOptions,
                   noise: float, progress=None) -> list:
    """Generic corrections of ``base``, confirmed and ranked best first (:mod:`.discovery`)."""
    n_eff = max(effective_samples(base.score.residual), float(data.independent))
    found = discover(base, data, free, n_eff, options)
    for term in found:
        if progress is not None:
            progress(term)
    return rank(found, base, options, data.independent, noise)
