"""How a fitted generic correction is read: which of its terms its shape follows
(:func:`term_spread`), the one lag its lag terms of a reading amount to
(:func:`equivalent_lag_ms`), and which other readings the records cannot tell from it
(:func:`alike`, with the record that would: :func:`telling_apart`), which equation
leads where the records do not tell two apart (:func:`likeliest_first`), and saying so
(:func:`equations_alike`)."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from scipy.optimize import minimize_scalar

from ...effects.corrections import BY_EQUATION
from ...effects.terms import BY_NAME as TERMS
from ...effects.terms import BY_VARIABLE, lag, term_values
from ...prediction.inputs import smoothed_signals
from .candidates import Baseline
from .data import Data
from .scoring import BIC_TIE, information_criteria


def term_spread(terms: dict[str, float], data: Data, core: dict
                ) -> tuple[dict[str, float], dict[str, float]]:
    """How each term (coefficient times regressor) varies along the fitted time series:
    regressor -> its standard deviation [the equation's unit], and regressor -> the share of
    the whole correction's variation it follows alone (its squared correlation with the
    sum, 0 to 1). Two terms that are nearly the same function over the record (the angle
    and its cosine over a quarter turn) can both be large and cancel; the share says which
    of them the correction's shape is. The constant varies not at all."""
    names = list(terms)
    cols = [term_values([TERMS[r] for r in names], {**smoothed_signals(e), 't_s': e.t}, core)
            for e in data.experiments if not e.static]
    if not cols:
        return {r: 0.0 for r in names}, {r: 0.0 for r in names}
    values = np.concatenate(cols) * np.array([terms[r] for r in names])
    values = values[np.all(np.isfinite(values), axis=1)]
    centred = values - values.mean(axis=0)
    total = centred.sum(axis=1)
    sizes = np.sqrt(np.mean(centred ** 2, axis=0))
    shares = [float((centred[:, j] @ total) ** 2 / (centred[:, j] @ centred[:, j]
                                                      * (total @ total)))
              if sizes[j] > 0 and total @ total > 0 else 0.0 for j in range(len(names))]
    return dict(zip(names, map(float, sizes))), dict(zip(names, shares))


def angle_span_deg(data: Data) -> tuple[float, float] | None:
    """The angles [deg] the time series visit (1st to 99th percentile of the measured
    angle), for words that place a correction along the stroke; None without a series."""
    angles = [e.signals['angle_rad'] for e in data.experiments
              if not e.static and 'angle_rad' in e.signals]
    if not angles:
        return None
    lo, hi = np.nanpercentile(np.degrees(np.concatenate(angles)), [1.0, 99.0])
    return float(lo), float(hi)


def equivalent_lag_ms(equation: str, terms: dict[str, float], data: Data, core: dict
                      ) -> float | None:
    """The time constant [ms] of the one first-order lag of a pressure reading whose error
    is closest, over the fitted time series, to what the correction's lag and rate terms
    of it add (least squares, 0.1 ms to 1 s); None where it has none. Their first-order
    sum is far off where a coefficient is far from one: a 20 ms lag at 0.71 and a rate
    read 15.8 ms for a transmitter's 8 ms, this reads 9.4 ms."""
    reading = equation.removeprefix('measurement_')
    if reading not in BY_VARIABLE:
        return None
    dynamic = [r for r in terms if TERMS[r].dynamics_of(reading)]
    if not any(TERMS[r].lag_s for r in dynamic):
        return None
    signal = BY_VARIABLE[reading].signal
    cases = []  # (reading, its times, what the terms add to it) of each time series
    for e in data.experiments:
        if not e.static and signal in e.signals:
            signals = {**smoothed_signals(e), 't_s': e.t}
            added = term_values([TERMS[r] for r in dynamic], signals, core) @ np.array(
                [terms[r] for r in dynamic])
            cases.append((np.asarray(signals[signal], dtype=float), e.t, added))
    if not cases:
        return None

    def misfit(log_tau):
        return sum(float(np.nansum((added - (lag(p, t, math.exp(log_tau)) - p)) ** 2))
                   for p, t, added in cases)
    best = minimize_scalar(misfit, bounds=(math.log(1e-4), math.log(1.0)), method='bounded')
    return 1e3 * math.exp(best.x)


def _and(names) -> str:
    """'a', 'a and b', 'a, b and c'."""
    names = list(names)
    return ' and '.join([', '.join(names[:-1]), names[-1]] if len(names) > 1 else names)


def telling_apart(a, b) -> str:
    """The record that would tell a reading of variables ``a`` from one of ``b`` apart:
    one in which the variables only one of them depends on vary independently of those
    both do (or of each other)."""
    shared = [v for v in a if v in b]
    only = list(dict.fromkeys(v for v in (*a, *b) if v not in shared))
    if not only:
        return 'a record that excites one and not the other'
    if not shared and len(only) == 1:
        return f'a record over which {only[0]} varies more'
    if not shared:
        return f'a record in which {_and(only)} vary independently of each other'
    verb = 'varies' if len(only) == 1 else 'vary'
    return f'a record in which {_and(only)} {verb} independently of {_and(shared)}'


def _bic(d, k: int, base: Baseline, n_eff: float) -> float:
    """Held-out BIC of correction ``d`` counted as ``k`` parameters, against ``base``."""
    return information_criteria(base.score.overall ** 2, d.score.overall ** 2, k, n_eff)[1]


def simplest_best(found: list, base: Baseline, n_eff: float):
    """The best of one equation's corrections (:class:`.discovery.Discovered`) by held-out
    BIC, each term counted at its :attr:`Term.cost` (the simpler is preferred)."""
    return min(found, key=lambda d: _bic(d, d.n_params, base, n_eff))


def alike(found: list, base: Baseline, n_eff: float, best):
    """``best`` of one equation's corrections ``found``, with those it cannot be told from:
    where another, led by a term of other variables, fits the held-out data as well or
    better (BIC within :data:`BIC_TIE` or lower, counting one parameter per coefficient:
    the cost is a preference, not evidence), the records do not tell the two apart, and the
    interpretation says both, with the record that would (:func:`telling_apart`); the other
    is kept under ``fits_as_well``."""
    def bic(d, k):
        return _bic(d, k, base, n_eff)
    mine = TERMS[best.leading].depends_on
    tied = [d for d in found if bic(d, len(d.params)) - bic(best, len(best.params)) <= BIC_TIE
            and set(TERMS[d.leading].depends_on) != set(mine)]
    if not tied:
        return best
    words = '; or '.join(f'{d.interpretation} (held-out BIC within {BIC_TIE:g} or lower: '
                         f'{telling_apart(mine, TERMS[d.leading].depends_on)} would tell '
                         'them apart)' for d in tied)
    return replace(best, fits_as_well={d.leading: d.interpretation for d in tied},
                   interpretation=f'{best.interpretation}; or, as well or better on these '
                                  f'records, {words}')


def kind(d) -> int:
    """How likely a correction's kind is on a rig, most likely first: 0, a sensor's error
    in its own reading's terms (gain, offset, lag, a stuck bit: a transmitter's error
    follows what it measures); 1, a correction of a balance equation (physics); 2, a
    sensor's error with a term of another signal (a crosstalk, which needs a wiring
    fault)."""
    equation = BY_EQUATION[d.equation].equation
    if not (equation.reads or equation.signal):
        return 1
    return 0 if set(d.terms) <= {t.name for t in equation.own} else 2


def _not_told_apart(found: list, best, claims, beats_clearly) -> list:
    """The corrections of ``found`` in other equations than ``best``'s that earn their place
    (``claims``) and that ``best`` does not explain clearly better than (``beats_clearly``)."""
    return [d for d in found if d.equation != best.equation and claims(d)
            and not beats_clearly(best, d)]


def likeliest_first(found: list, claims, beats_clearly) -> list:
    """``found`` (generic corrections, best first) with the likeliest kind (:func:`kind`)
    first among the best and the corrections of other equations that also earn their place
    (``claims(d)``) and that the best does not explain the held-out data clearly better
    than (``beats_clearly(best, d)``, the candidate-level test): the records do not tell
    those equations apart, so the likelier physics leads, as within a sensor's equation
    its own reading does (:mod:`.discovery`). On held-out sets 9 and 10, five of the nine
    claims of a wrong equation had the truth's among those not beaten clearly, three of a
    likelier kind: a chamber's flow read as a crosstalk of the command into the supply
    reading, a rate-limited p_b reading as a valve error following the command."""
    if not found or not claims(found[0]):
        return found
    tied = [d for d in _not_told_apart(found, found[0], claims, beats_clearly)
            if kind(d) < kind(found[0])]
    if not tied:
        return found
    first = min(tied, key=kind)  # the best ranked of the likeliest kind
    return [first, *(d for d in found if d is not first)]


def equations_alike(found: list, claims, beats_clearly) -> list:
    """``found`` with its first correction, where it earns its place, saying the other
    equations these records cannot tell it from (:func:`_not_told_apart`), with the record
    that would (:func:`telling_apart`), in ``alike_equations`` and its interpretation. Call
    once, on the corrections as reported."""
    if not found or not claims(found[0]):
        return found
    best = found[0]
    others = _not_told_apart(found[1:], best, claims, beats_clearly)
    if not others:
        return found
    mine = TERMS[best.leading].depends_on
    words = '; or '.join(
        f'{d.summary} ({d.equation}): {d.interpretation} ('
        f'{telling_apart(mine, TERMS[d.leading].depends_on)} would tell them apart)'
        for d in others)
    said = replace(best, alike_equations=tuple(d.equation for d in others),
                   interpretation=f'{best.interpretation}; these records do not tell it from '
                                  f'{words}')
    return [said, *found[1:]]
