"""The open-world status: does the model fit, does a named effect explain the misfit, or is
the model wrong in a way no name on the list explains?

Tests, decided from the data (``docs/diagnosis.md`` has the calibration):

* **size**: a held-out residual within :data:`CONSISTENT_RATIO` times the sensor
  noise (estimated from the data, as it is left in the smoothed residual) is
  what a correct model leaves. On clean synthetic records the paper's model
  leaves 1.05 x the noise; after the right effect is added, 1.0-1.8 x.
* **evidence** (:func:`certain`): a candidate's fall of the held-out residual and
  its BIC gain; a large gain is certain even when the error explained is small.
* **structure**: a generic correction (discovery) that earns its place on what
  a named effect leaves, or that explains the data clearly better than it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from .candidates import Candidate
from .options import MIN_NOISE_RATIO, DiagnoseOptions
from .verdict import earns_place, shortfalls, suggest_experiment

#: a held-out residual within this many times the sensor noise is consistent with a
#: correct model (clean data: 1.05-1.3 x; one or two right effects added: 1.0-2.6 x). The
#: same factor as an effect's practical size (``MIN_NOISE_RATIO``): an error below it is no
#: finding, and a residual below it is what noise leaves
CONSISTENT_RATIO = MIN_NOISE_RATIO
#: a named effect with at least this BIC gain (and the other tests of earning a place but
#: the practical size) is statistically certain: reported as small, never hidden
CERTAIN_DELTA_BIC = -100.0
#: a generic correction is clearly better than a named effect if its BIC is lower by this
#: much and it leaves at most this share of the named effect's held-out residual (a
#: second effect the named one misses leaves 0.9 of it; an unlisted effect, 0.1-0.4)
CLEARLY_BETTER_BIC = 10.0
CLEARLY_BETTER_SHARE = 2.0 / 3.0

STATUSES = ('consistent', 'explained', 'partly_explained', 'unexplained')


def certain(c: Candidate, options: DiagnoseOptions) -> bool:
    """``c`` passes every test of earning its place except, perhaps, the practical size, and
    its BIC gain is beyond doubt: a real effect, if a small one."""
    return (c.fitted and c.plausible and c.error_reduction >= options.min_reduction
            and c.delta_bic <= min(options.min_delta_bic, CERTAIN_DELTA_BIC))


def consistent(rms: float, noise: float) -> bool:
    """A held-out residual [normalised] that a correct model would leave."""
    return rms <= CONSISTENT_RATIO * noise


def clearly_better(d: Candidate, c: Candidate) -> bool:
    """Discovered correction ``d`` explains the held-out data clearly better than ``c``."""
    return (d.delta_bic < c.delta_bic - CLEARLY_BETTER_BIC
            and d.score.overall <= CLEARLY_BETTER_SHARE * c.score.overall)


@dataclass
class Finding:
    """What the diagnosis concludes.

    ``verdict`` is a named effect or 'none'; ``size`` 'small' for an effect that
    is certain but explains less than the practical threshold; ``partial`` the
    named effects that earn their place but fit only part of what a generic
    correction explains; ``look_on_top`` asks for a discovery on top of the
    verdict (what it leaves is still structured).
    """

    status: str
    verdict: str = 'none'
    ties: list[str] = field(default_factory=list)
    suggestion: str = ''
    reason: str = ''
    size: str = ''
    partial: list[str] = field(default_factory=list)
    look_on_top: bool = False


def _ties(best: Candidate, ranking: list[Candidate], test, options) -> list[str]:
    return [c.effect for c in ranking if c is not best and test(c)
            and c.score.overall <= best.score.overall * (1.0 + options.ambiguity)]


def _ratio(rms: float, noise: float) -> str:
    return f'{rms / max(noise, 1e-12):.1f} x the sensor noise'


def _named(best: Candidate, ranking, noise, options, small: bool) -> Finding:
    test = (lambda c: certain(c, options)) if small else (lambda c: earns_place(c, options))
    ties = _ties(best, ranking, test, options)
    snr = best.explained_rms / max(noise, 1e-12)
    if small:
        why = (f'{best.effect} is small but certain: it cuts the held-out residual by '
               f'{100 * best.error_reduction:.1f} % (delta BIC {best.delta_bic:.0f}), though '
               f'the error it explains is only {snr:.1f} x the sensor noise')
    else:
        why = (f'{best.effect} cuts the held-out residual by {100 * best.error_reduction:.1f} % '
               f'(delta BIC {best.delta_bic:.1f}, {snr:.0f} x the sensor noise) with plausible '
               'values')
    suggestion = ''
    if ties:
        why += '; ' + ', '.join(ties) + ' explain the data about as well'
        suggestion = suggest_experiment(best.effect, ties[0])
    left = best.score.overall
    if consistent(left, noise):
        return Finding('explained', best.effect, ties, suggestion,
                       why + f'; what remains is {_ratio(left, noise)}, as from a correct model',
                       'small' if small else '')
    return Finding('partly_explained', best.effect, ties, suggestion,
                   why + f'; but what remains is still {_ratio(left, noise)}: something else '
                   'is missing too', 'small' if small else '', look_on_top=True)


def decide(ranking: list[Candidate], discovered: list[Candidate], base_rms: float,
           noise: float, options: DiagnoseOptions, pair=None) -> Finding:
    """The status, verdict and reason from the ranked named candidates, the ranked generic
    corrections and the held-out residual [normalised] of the model as given.

    ``pair(first, second)``, if given, fits the named effect ``second`` on top of ``first``
    and returns (that step, the pair scored against the model as given). When a generic
    correction explains more than any single named effect, two named effects may still
    explain it together: a rig can miss two effects at once, and one generic term can
    mimic a mixture of both. If the second earns its place on top of the first and the
    generic term is not clearly better than the pair, the first is the verdict (partly
    explained: the second is looked for next round); otherwise nothing on the list fits.
    """
    named = next((c for c in ranking if earns_place(c, options)), None)
    found = next((d for d in discovered if earns_place(d, options)), None)
    if named is not None and found is not None and clearly_better(found, named):
        second = next((c for c in ranking if c is not named and earns_place(c, options)), None)
        step, both = pair(named, second) if pair and second else (None, None)
        if step is not None and earns_place(step, options) and not clearly_better(found, both):
            finding = _named(named, ranking, noise, options, small=False)
            finding.reason += (f'; a generic {found.equation} term explains more than it '
                               f'alone ({100 * found.error_reduction:.0f} %), but with '
                               f'{second.effect} on top the two named effects explain '
                               f'{100 * both.error_reduction:.0f} %: two effects are '
                               'missing, and the next round will find the other')
            finding.status, finding.look_on_top = 'partly_explained', True
            return finding
        partial = [c.effect for c in ranking if earns_place(c, options)]
        return Finding('unexplained', reason=(
            f'no name on the list fits: {named.effect} fits only part of it '
            f'({100 * named.error_reduction:.0f} %), while a generic {found.equation} term '
            f'explains the held-out data clearly better ({100 * found.error_reduction:.0f} %): '
            f'{found.interpretation}'), partial=partial)
    if named is not None:
        return _named(named, ranking, noise, options, small=False)
    if found is not None:
        return Finding('unexplained', reason=(
            f'the model misses the data by {_ratio(base_rms, noise)} and no named effect earns '
            f'its place; a generic {found.equation} term cuts the held-out residual by '
            f'{100 * found.error_reduction:.0f} %: {found.interpretation}'))
    small = next((c for c in ranking if certain(c, options)), None)
    if small is not None:
        return _named(small, ranking, noise, options, small=True)
    top = ranking[0] if ranking else None
    if consistent(base_rms, noise):
        why = f'the model explains the data: its held-out residual is {_ratio(base_rms, noise)}'
        if top is not None:
            why += (f', and no effect earns its place (the best, {top.effect}, cuts it by '
                    f'{100 * top.error_reduction:.1f} %: ' + '; '.join(shortfalls(top, options))
                    + ')')
        return Finding('consistent', reason=why)
    return Finding('unexplained', reason=(
        f'the model misses the data by {_ratio(base_rms, noise)}, and neither a named effect '
        'nor a generic correction earns its place: the missing physics is not in this '
        'vocabulary; see where it fails (regimes, residual tests)'))
