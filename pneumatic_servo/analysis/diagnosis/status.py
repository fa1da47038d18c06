"""The open-world status: does the model fit, does a named effect explain the misfit, or is
the model wrong in a way no name on the list explains?

Every word is a test of :mod:`.criteria` against the record's prediction floor:

* ``consistent``: no channel departs from the floor and no candidate earns its place;
* ``explained``: a named effect earns its place and what it leaves does not depart;
* ``partly_explained``: what the named effect leaves departs, and a second named effect
  earns its place on top of it (two effects are missing; the next round finds the other);
* ``unexplained``: the model departs and no named effect accounts for all of it. A named
  effect that earns its place but leaves a departure (and no second one accounts for the
  rest), or that a generic correction beats clearly (unless a second named effect on top of
  it beats that correction clearly in turn), is listed as a partial fit, never as the
  answer.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

from .candidates import Candidate
from .criteria import (
    Departures,
    Status,
    certain,
    earns_place,
    explained_rms,
    gain_p_value,
    shortfalls,
)
from .trial import Trial
from .verdict import suggest_experiment


@dataclass(frozen=True)
class Pair:
    """A second named effect fitted on top of the first: the step (judged against the first)
    and the two together (judged against the model as given)."""

    first: Candidate
    step: Candidate
    both: Candidate


@dataclass(frozen=True)
class Finding:
    """What the diagnosis concludes.

    ``verdict`` is a named effect or 'none'; ``size`` 'small' for an effect that is certain
    but explains less than the practical size; ``partial`` the named effects that earn their
    place but fit only part of it; ``look_on_top`` asks for a discovery on top of the verdict
    (what it leaves still departs).
    """

    status: Status
    verdict: str = 'none'
    ties: tuple[str, ...] = ()
    suggestion: str = ''
    reason: str = ''
    size: str = ''
    partial: tuple[str, ...] = ()
    look_on_top: bool = False


def gain_over(trial: Trial, d: Candidate, c: Candidate, left: Departures | None = None,
              added: int | None = None) -> tuple[float, float]:
    """(one-sided p-value, size in prediction floors) of the held-out gain of ``d`` over
    ``c``, with ``added`` parameters more (default all of ``d``'s). ``left``: what ``c``
    leaves against its own floor; where that floor holds the scatter of ``c``'s fit
    (:mod:`.refit`), ``c``'s mean square is first taken down by that scatter's mean factor:
    fitting a little better than the named effect's own fit lands is no sign of a better
    correction (a generic constant torque beat a load torque fitted 4 % off)."""
    ref = c.score
    if left is not None and left.floor is not None:
        ref = replace(ref, overall=ref.overall / math.sqrt(left.floor.refit_factor()))
    gain = explained_rms(ref, d.score) / max(trial.floor.rms(), 1e-300)
    units = trial.data.independent
    return gain_p_value(ref, d.score, d.n_params if added is None else added, units), gain


def clearly_better(trial: Trial, d: Candidate, c: Candidate, left: Departures | None = None
                   ) -> bool:
    """Correction ``d`` explains the held-out data clearly better than ``c``: its gain over
    ``c`` (:func:`gain_over`) is significant at the candidate level and of practical
    size."""
    p_value, gain = gain_over(trial, d, c, left)
    return p_value <= trial.levels.candidate and gain >= trial.options.practical_size


def best_generic(trial: Trial, discovered: list[Candidate]) -> Candidate | None:
    """The best generic correction that earns its place, if any."""
    return next((d for d in discovered if earns_place(d, trial.options)), None)


def best_named(trial: Trial, ranking: list[Candidate]) -> Candidate | None:
    """The named effect of the verdict: the first that earns its place, else the first
    that is certain (small)."""
    return (next((c for c in ranking if earns_place(c, trial.options)), None)
            or next((c for c in ranking if certain(c, trial.options)), None))


def needs_pair(trial: Trial, ranking: list[Candidate], discovered: list[Candidate],
               left: Departures | None) -> tuple[Candidate, tuple[Candidate, ...]] | None:
    """(first, the other named effects) when the decision needs a second named effect fitted on
    top of the first: what the first leaves departs (``left``), or a generic correction
    beats it clearly."""
    first = best_named(trial, ranking)
    if first is None:
        return None
    found = best_generic(trial, discovered)
    if not left.departs and not (
            found is not None and clearly_better(trial, found, first, left)):
        return None
    # every other named effect: one the first has absorbed may not be certain alone
    others = tuple(c for c in ranking if c is not first)
    return (first, others) if others else None


def _ties(trial: Trial, best: Candidate, ranking, small: bool) -> tuple[str, ...]:
    test = certain if small else earns_place
    return tuple(c.effect for c in ranking if c is not best and test(c, trial.options)
                 and c.score.overall <= best.score.overall * (1.0 + trial.options.ambiguity))


def _why(best: Candidate, small: bool) -> str:
    gain = (f'cuts the held-out residual by {100 * best.error_reduction:.1f} % (p = '
            f'{best.gain_p_value:.2g}; it explains {best.size_in_floor:.1f} x the prediction '
            'floor)')
    if small:
        return f'{best.effect} is small but certain: it {gain}'
    return f'{best.effect} {gain} with plausible values'


def _named(trial: Trial, best: Candidate, ranking, left: Departures, pair: Pair | None,
           structured: bool = False) -> Finding:
    """The finding of named effect ``best``; ``structured``: a generic correction beats it
    clearly, so what it leaves is structured even where it does not depart."""
    small = not earns_place(best, trial.options)
    ties = _ties(trial, best, ranking, small)
    why = _why(best, small)
    suggestion = suggest_experiment(best.effect, ties[0]) if ties else ''
    if ties:
        why += '; ' + ', '.join(ties) + ' explain the data about as well'
    size = 'small' if small else ''
    if not left.departs and not structured:
        return Finding(Status.EXPLAINED, best.effect, ties, suggestion,
                       f'{why}; what remains is {left.words()}, as from a correct model', size)
    if pair is not None and certain(pair.step, trial.options):
        return Finding(Status.PARTLY_EXPLAINED, best.effect, ties, suggestion,
                       f'{why}; but what remains is still {left.words()}, and '
                       f'{pair.step.effect} earns its place on top of it (together they cut '
                       f'the error by {100 * pair.both.error_reduction:.0f} %): a second effect '
                       'is missing, which the next round will find', size, look_on_top=True)
    return Finding(Status.UNEXPLAINED, reason=(
        f'{best.effect} fits only part of it: {why}, but what remains is still '
        f'{left.words()}, and no second named effect accounts for the rest'),
        partial=(best.effect,))


def decide(trial: Trial, ranking: list[Candidate], discovered: list[Candidate],
           left: Departures | None = None, pair: Pair | None = None) -> Finding:
    """The status, verdict and reason from the ranked named candidates, the ranked generic
    corrections, what the best named effect (:func:`best_named`) leaves against its own
    floor (``left``) and, where :func:`needs_pair` asked for it, the second named effect
    fitted on top of the first."""
    named = best_named(trial, ranking)
    found = best_generic(trial, discovered)
    base = trial.departures(trial.base.score)
    if named is not None and found is not None and clearly_better(trial, found, named, left):
        both_fit = pair is not None and certain(pair.step, trial.options)
        # two names are the answer only where together they beat the generic term clearly:
        # two wrong effects can mimic one unlisted one about as well (a lagging transmitter
        # as a dead volume with a slow spool)
        if both_fit and clearly_better(trial, pair.both, found):
            return _named(trial, named, ranking, left, pair, structured=True)
        partial = tuple(c.effect for c in ranking if earns_place(c, trial.options))
        tie = (f'; {named.effect} with {pair.step.effect} on top explains it only about as '
               'well, so neither is named') if both_fit else ''
        return Finding(Status.UNEXPLAINED, reason=(
            f'no name on the list fits: {named.effect} fits only part of it '
            f'({100 * named.error_reduction:.0f} %), while a generic {found.equation} term '
            f'explains the held-out data clearly better ({100 * found.error_reduction:.0f} %): '
            f'{found.interpretation}{tie}'), partial=partial or (named.effect,))
    if named is not None:
        return _named(trial, named, ranking, left, pair)
    if found is not None:
        return Finding(Status.UNEXPLAINED, reason=(
            f'the model misses the data by {base.words()} and no named effect earns its '
            f'place; a generic {found.equation} term cuts the held-out residual by '
            f'{100 * found.error_reduction:.0f} %: {found.interpretation}'))
    if base.departs:
        return Finding(Status.UNEXPLAINED, reason=(
            f'the model misses the data by {base.words()}, and neither a named effect nor a '
            'generic correction earns its place: the missing physics is not in this '
            'vocabulary; see where it fails (regimes, residual tests)'))
    why = f'the model explains the data: its held-out residual is {base.words()}'
    top = ranking[0] if ranking else None
    if top is not None:
        why += (f', and no effect earns its place (the best, {top.effect}, cuts it by '
                f'{100 * top.error_reduction:.1f} %: ' + '; '.join(shortfalls(top, trial.options))
                + ')')
    return Finding(Status.CONSISTENT, reason=why)
