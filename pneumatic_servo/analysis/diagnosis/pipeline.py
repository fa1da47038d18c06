"""Which physical effect is missing: add each candidate, fit it, score it on held-out data.

For every candidate effect (the catalogue and any user-registered effect),
the model is extended with it, the effect's ``fit=True`` parameters (plus
any base parameters the user frees, plus the effects already in the model)
are fitted by output error on one part of the data, and the extended model
is scored on the other part. Every statement is a test against the record's own
prediction floor (:mod:`.floor`, :mod:`.criteria`): an effect is the verdict
only if its held-out gain is significant and of practical size with plausible
values, and the status says whether what it leaves still departs from the floor.
A record of a correct model gets any status but ``consistent`` with probability
at most ``options.false_alarm_rate``.

The pipeline, each stage a function of the frozen :class:`~.trial.Trial`:
prepare and split the data; fit the baseline; measure the floor; screen, fit and
rank the named candidates; discover generic corrections where the model departs;
fit a second named effect on top of the first where the decision needs it;
decide; where no name fits, fit a free shape beside the closed form found (shape before
formula); test, variable by variable, what the best correction depends on
(:mod:`.dependence`); validate on other experiments; the ladder.

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

import time
from dataclasses import replace

import numpy as np

from ... import effects as registry
from ...experiment import Experiment
from ...fitting import effective_samples
from ...model.assembly import Model, compile_in_background
from ...model.config import ModelConfig
from ...prediction import predict
from ..regimes import error_shares, hot_spots
from ..residuals import residual_tests, summary
from .candidates import Baseline, Candidate, baseline, candidate_effects, screen_effect, try_effect
from .criteria import Levels, certain, earns_place
from .data import Data
from .dependence import probe_dependence
from .discovery import Discovered, correction_host, discover
from .hosts import host_for, shareable, shared_host
from .ladder import ladder
from .options import DiagnoseOptions
from .readings import equations_alike, likeliest_first
from .refit import remainder, restarted
from .result import Diagnosis, added_by
from .scoring import relative_fall
from .shape import fit_shape
from .status import Pair, best_generic, best_named, clearly_better, decide, needs_pair
from .trial import Trial, floor_for
from .validation import score_on, validate
from .verdict import rank

#: second effects fitted in full on top of the first (the best of their screens)
PAIR_FITS = 2


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
        Fit, scoring and decision settings.
    progress : callable, optional
        Called with each finished :class:`~.candidates.Candidate`.
    validate_on : list of Experiment, optional
        Other experiments (any circuit) on which every candidate and every rung of
        the ladder is also scored, whole (:mod:`.validation`).

    Returns
    -------
    Diagnosis
        Status, verdict (an effect name or 'none'), ranking best first, the tests behind
        them, ties and a suggested experiment, and the held-out error ladder.
    """
    t0 = time.perf_counter()
    timings = {}

    def timed(name, fn, *args, **kwargs):
        t1 = time.perf_counter()
        out = fn(*args, **kwargs)
        timings[name] = time.perf_counter() - t1
        return out

    options = options or DiagnoseOptions()
    config = config or ModelConfig.paper()
    names = candidate_effects(config, effects)
    # on a fresh machine a helper process compiles the host of the generic corrections,
    # which carries every term and takes longest (about as long as everything this one
    # compiles before discovery needs it), while this one compiles the shared host, fits the
    # model as given and compiles the named effects; without discovery, the helper takes
    # every second named effect that needs a composition of its own
    compile_in_background([correction_host(config)] if options.discover else
                          [host_for(config, n) for n in names if not shareable(n)][1::2])
    data, base, free = timed('prepare', prepare, experiments, config, free, options)
    trial = timed('floor', make_trial, data, base, free, options, len(names))
    base_preds = timed('where', predictions, trial.base.config, trial.data)
    where = where_it_fails(trial.data.experiments, base_preds, trial.base.config)
    ranking = rank(timed('named', named_candidates, trial, names, progress), trial)
    found = []
    if options.discover and (any(certain(c, options) for c in ranking)
                             or trial.departures(trial.base.score).departs):
        found = timed('discovery', look_for_terms, trial, trial.base, progress)
        ranking, found = ranked_together(trial, ranking, found)
    ranking, found = timed('restart', settled, trial, ranking, found)
    first = best_named(trial, ranking)
    left = timed('floor_of_verdict', remainder, trial, first, found) if first else None
    asked = needs_pair(trial, ranking, found, left)
    pair = timed('named_pair', second_on_top, trial, *asked, left) if asked else None
    finding = decide(trial, ranking, found, left, pair)
    if finding.look_on_top:
        winner = next(c for c in ranking if c.effect == finding.verdict)
        on_top = Baseline(winner.config, winner.score, trial.base.values)
        found = timed('discovery_on_top', look_for_terms, replace(
            trial, free=trial.free + tuple(present_keys(winner.config))), on_top, progress,
            on_top, True)
        found = likelier_first(trial, found)
    if finding.status == 'unexplained' and found:
        finding, found = timed('shape', shape_before_formula, trial, finding, found)
    keep = finding.status in ('partly_explained', 'unexplained')  # validation keeps it
    if keep and found and options.test_dependence:
        found = [timed('dependence', probe_dependence, trial, found[0]), *found[1:]]
    other = Data.of(validate_on, options) if validate_on else None
    if other is not None:
        ranking, found, finding = timed('validation', validated, trial, ranking, found,
                                        finding, other)
    # said once, on the corrections as reported
    discovered = equations_alike(found, *_tie_tests(trial)) if keep else []
    added = added_by(finding, ranking, discovered, options)
    rungs = timed('ladder', ladder, config, trial.data, added, trial.base, other)
    return Diagnosis(finding, ranking, trial, [e.name for e in experiments],
                     time.perf_counter() - t0, remainder=left,
                     discovered=discovered, ladder=rungs,
                     timings=timings, where=where, base_predictions=base_preds,
                     validated_on=[e.name for e in validate_on or ()])


def prepare(experiments: list[Experiment], config: ModelConfig, free, options: DiagnoseOptions
            ) -> tuple[Data, Baseline, tuple[str, ...]]:
    """The data split, the model as given with its free keys fitted, and the keys refitted
    with every candidate."""
    free = list(free)
    for key in free:
        config.get(key)  # a clear error for an unknown key
    if options.refit_present:
        free += [k for k in present_keys(config) if k not in free]
    data = Data.of(experiments, options)
    return data, baseline(config, data, free, options), tuple(free)


def make_trial(data: Data, base: Baseline, free: tuple[str, ...], options: DiagnoseOptions,
               named: int) -> Trial:
    """The frozen context of the diagnosis: with the sensor noise, the prediction floor of
    the model as given and the test levels for ``named`` candidates and the discovery."""
    host = shared_host(base.config)
    floor = floor_for(host, data, options)
    tries = named + (options.discovery_fits if options.discover else 0)
    levels = Levels.of(options.false_alarm_rate, len(floor.series_channels), tries)
    return Trial(data, base, free, options, data.noise(Model(host), host), floor, levels)


def settled(trial: Trial, ranking: list[Candidate], found: list) -> tuple[list, list]:
    """(ranking, found), where a generic correction clearly beats the first named effect:
    that effect's fit restarted either side of its values (:func:`.refit.restarted`) and,
    where it landed lower, everything ranked again with it."""
    first = best_named(trial, ranking)
    generic = best_generic(trial, found)
    if first is None or generic is None or not clearly_better(trial, generic, first):
        return ranking, found
    again = restarted(trial, first)
    if again is first:
        return ranking, found
    return ranked_together(trial, [again if c is first else c for c in ranking], found)


def ranked_together(trial: Trial, ranking: list[Candidate], found: list) -> tuple[list, list]:
    """(named, generic) ranked in one list, with one effective sample count for all, so that
    named effects and generic corrections compare fairly; each part best first (of
    equations the records do not tell apart, the likeliest kind first)."""
    joint = rank(ranking + found, trial)
    return ([c for c in joint if not isinstance(c, Discovered)],
            likelier_first(trial, [c for c in joint if isinstance(c, Discovered)]))


def named_candidates(trial: Trial, names: list[str], progress=None) -> list[Candidate]:
    """Every named effect screened on a coarse grid of its parameters; the
    ``options.full_fits`` best screens fitted in full, the others scored at their grid
    point; all scored held out."""
    screens = [screen_effect(name, trial.base, trial.data) for name in names]
    full = {s.name for s in sorted(screens, key=lambda s: s.cost)[:trial.options.full_fits]}
    out = []
    for scr in screens:
        out.append(try_effect(scr, trial.base, trial.data, list(trial.free), trial.options,
                              full_fit=scr.name in full))
        if progress is not None:
            progress(out[-1])
    return out


def second_on_top(trial: Trial, first: Candidate, others: tuple[Candidate, ...], left
                  ) -> Pair:
    """The best of ``others`` fitted on top of ``first``: the step judged against ``first``
    (whose remainder against its own floor is ``left``), the two together against the model
    as given. Each is screened again on top of ``first``, not taken from the ranking: the
    first, fitted alone, has absorbed part of the second (a load torque 40 % high beside a
    hidden seal leak), so the effect ranked second alone is not the one that fits best on
    top."""
    with_first = Baseline(first.config, first.score, trial.base.values)
    screens = sorted((screen_effect(c.effect, with_first, trial.data) for c in others),
                     key=lambda s: s.cost)
    # a coarse grid ranks closely matched effects only roughly: the best few are fitted
    steps = [try_effect(s, with_first, trial.data, list(trial.free), trial.options)
             for s in screens[:PAIR_FITS]]
    step = min(steps, key=lambda c: c.score.overall)
    step = rank([step], trial, with_first, left.departs)[0]
    both = replace(step, n_params=step.n_params + first.n_params,
                   error_reduction=relative_fall(step.score.overall,
                                                 trial.base.score.overall))
    return Pair(first, step, rank([both], trial)[0])


def shape_before_formula(trial: Trial, finding, found: list) -> tuple:
    """The finding and corrections after the shape stage (:mod:`.shape`): where the best
    correction depends on the angle alone, a free shape over the stroke is fitted beside it;
    the reason says whether the closed form found stands, a formula fitted to the shape
    replaces it, or no closed form fits (the closest one follows the shape); what the stage
    answers leads."""
    check = fit_shape(trial, found[0])
    if check is None:
        return finding, found
    finding = replace(finding, reason=f'{finding.reason}; {check.words()}')
    return finding, check.corrections + found


def validated(trial: Trial, ranking, found, finding, other: Data):
    """Every candidate scored on the other experiments; the verdict's reason says so when
    it makes them worse."""
    base_other = score_on(trial.base.config, shared_host, other)
    ranking = [replace(c, validation=validate(c, base_other, other)) for c in ranking]
    found = [replace(c, validation=validate(c, base_other, other)) for c in found]
    winner = next((c for c in ranking + found if c.effect == finding.verdict), None)
    if winner is not None and winner.validation.hurts:
        finding = replace(finding, reason=finding.reason + (
            f'; but it makes the other experiments worse (error '
            f'{-100 * winner.validation.error_reduction:+.0f} %): it may only overfit this one'))
    return ranking, found, finding


def _tie_tests(trial: Trial) -> tuple:
    """(whether a correction earns its place, whether one explains clearly better than
    another): what says which equations the records do not tell apart (:mod:`.readings`)."""
    return (lambda d: earns_place(d, trial.options),
            lambda d, c: clearly_better(trial, d, c))


def likelier_first(trial: Trial, found: list) -> list:
    """``found`` with the likeliest kind of correction first among the equations the
    records do not tell apart (:func:`.readings.likeliest_first`)."""
    return likeliest_first(found, *_tie_tests(trial))


def look_for_terms(trial: Trial, base: Baseline, progress=None, reference=None,
                   departs=None) -> list:
    """Generic corrections of ``base``, confirmed and ranked best first (:mod:`.discovery`)."""
    n_eff = max(effective_samples(base.score.residual), float(trial.data.independent))
    found = discover(base, trial.data, list(trial.free), n_eff, trial.options,
                     lambda d, c: clearly_better(trial, d, c))
    for term in found:
        if progress is not None:
            progress(term)
    return rank(found, trial, reference, departs)
