"""Every statement of a diagnosis as a test with a stated error rate, declared once.

Two tests, both against the record's own prediction floor (:mod:`.floor`):

* **departure** (:func:`departures`): is a held-out mean square, per channel or pooled,
  larger than what the fitted model leaves on replicas of this record? Used for the model
  as given (``consistent`` or not) and for what a named effect leaves (``explained`` or
  not).
* **gain** (:func:`gain_p_value`): does a candidate cut the held-out error of a reference
  model? A likelihood-ratio test on the held-out residual with one independent sample per
  segment and channel (each held-out segment starts afresh from measured states, each
  table row is its own operating point).

The error budget: a record of a correct model is called anything but ``consistent`` with
probability at most ``false_alarm_rate`` (default 1 %). Half of it goes to the departure
tests (Bonferroni over the channels and the pooled residual), half to the candidates
(Bonferroni over every named effect and generic correction tried). An effect **earns its
place** when every criterion of :data:`EARNS_PLACE` holds: the model it corrects departs
from its floor (there is something to explain: a record at its floor gives no effect a
place, however a long record sharpens the gain test), and its gain is significant at its
level and of practical size (the error it explains, as a share of the floor). A significant
gain below the practical size is **certain but small**: reported, never hidden.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

from .floor import Departure, Floor
from .scoring import Score


class Status(StrEnum):
    """What a diagnosis concludes about the model."""

    CONSISTENT = 'consistent'
    EXPLAINED = 'explained'
    PARTLY_EXPLAINED = 'partly_explained'
    UNEXPLAINED = 'unexplained'


@dataclass(frozen=True)
class Levels:
    """Significance levels after the multiplicity correction: per departure test and per
    candidate."""

    departure: float
    candidate: float

    @classmethod
    def of(cls, false_alarm_rate: float, channels: int, tries: int) -> 'Levels':
        return cls(0.5 * false_alarm_rate / (channels + 1),
                   0.5 * false_alarm_rate / max(tries, 1))


@dataclass(frozen=True)
class Departures:
    """A held-out score against the floor, per channel and pooled (``'overall'``)."""

    tests: dict[str, Departure]
    level: float
    #: the tests that decide: the pooled one and the time-series channels (:class:`Floor`)
    deciding: tuple[str, ...] = ('overall',)
    #: the floor tested against
    floor: Floor | None = None

    @property
    def departs(self) -> bool:
        return any(self.tests[k].p_value <= self.level for k in self.deciding)

    @property
    def worst(self) -> str:
        """The deciding channel (or ``'overall'``) that departs the most."""
        return min(self.deciding, key=lambda k: self.tests[k].p_value)

    def words(self) -> str:
        """'what remains is 1.2 x the floor (p = 0.3)' with the worst channel named."""
        pooled = self.tests['overall']
        text = f'{pooled.ratio:.1f} x the prediction floor (p = {pooled.p_value:.2g})'
        worst = self.worst
        if worst != 'overall' and self.tests[worst].p_value <= self.level:
            w = self.tests[worst]
            text += f'; in {worst} alone {w.ratio:.1f} x (p = {w.p_value:.2g})'
        return text

    def to_json(self) -> dict:
        out = {'level': self.level, 'departs': self.departs, 'deciding': list(self.deciding),
               **{k: d.to_json() for k, d in self.tests.items()}}
        if self.floor is not None:
            out['floor'] = self.floor.to_json()
        return out


def departures(score: Score, floor: Floor, level: float) -> Departures:
    """``score`` against ``floor``, every channel and pooled."""
    tests = {ch: floor.test(score.mean_square(ch), ch) for ch in score.channels
             if ch in floor.channels}
    tests['overall'] = floor.test(score.mean_square())
    deciding = ('overall',) + tuple(ch for ch in floor.series_channels if ch in tests)
    return Departures(tests, level, deciding, floor)


def gain_p_value(reference: Score, candidate: Score, added: int, units: int) -> float:
    """One-sided p-value that ``candidate``, with ``added`` parameters more, cuts the
    held-out mean square of ``reference``: a likelihood-ratio test on the held-out residual,
    ``-units * ln(MS_candidate / MS_reference)`` against chi-square(``added``).

    ``units`` counts one independent sample per held-out segment and channel (and table
    row and channel): within a segment the prediction error is one smooth curve, so its
    samples are not independent, while each segment starts afresh from measured states.
    """
    from scipy.stats import chi2
    ratio = max(candidate.overall, 1e-300) ** 2 / max(reference.overall, 1e-300) ** 2
    return float(chi2.sf(max(-units * math.log(ratio), 0.0), max(added, 1)))


def explained_rms(reference: Score, candidate: Score) -> float:
    """RMS [normalised] of the error ``candidate`` explains of ``reference``'s."""
    return math.sqrt(max(reference.overall ** 2 - candidate.overall ** 2, 0.0))


#: (name, test of a ranked candidate ``c`` under ``options``, what a failure means). The
#: one declaration of earning a place: :func:`earns_place`, :func:`certain` and
#: :func:`shortfalls` read it.
EARNS_PLACE = (
    ('something to explain', lambda c, o: c.reference_departs,
     lambda c, o: 'the model it corrects does not depart from its prediction floor: there is '
                  'nothing to explain'),
    ('fitted', lambda c, o: c.fitted, lambda c, o: 'it was screened out before a full fit'),
    ('plausible', lambda c, o: c.plausible, lambda c, o: '; '.join(c.problems)),
    ('significant', lambda c, o: c.gain_p_value <= c.level,
     lambda c, o: f'its gain is not significant against the floor (p = {c.gain_p_value:.2g}'
                  f' > {c.level:.2g})'),
    ('practical', lambda c, o: c.size_in_floor >= o.practical_size,
     lambda c, o: f'the error it explains is {c.size_in_floor:.2f} x the prediction floor, '
                  f'under the practical size {o.practical_size:g} x'),
)


def _passes(c, options, skip=()) -> bool:
    return all(test(c, options) for name, test, _ in EARNS_PLACE if name not in skip)


def earns_place(c, options) -> bool:
    """Every criterion of :data:`EARNS_PLACE` holds for ranked candidate ``c``."""
    return _passes(c, options)


def certain(c, options) -> bool:
    """``c`` passes every criterion but perhaps the practical size: a real effect, if small."""
    return _passes(c, options, skip=('practical',))


def shortfalls(c, options) -> list[str]:
    """The criteria ``c`` fails, in words."""
    return [words(c, options) for _, test, words in EARNS_PLACE if not test(c, options)]
