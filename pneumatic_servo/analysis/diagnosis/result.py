"""The result of a diagnosis and its JSON form."""
from __future__ import annotations

from dataclasses import dataclass, field

from ...errors import ConfigError
from ...model.config import ModelConfig
from .candidates import Candidate
from .coverage import next_record
from .criteria import Departures, earns_place
from .status import Finding
from .trial import Trial


@dataclass(frozen=True)
class Diagnosis:
    """Result of :func:`~.run.diagnose`: the status and verdict, the ranking of named
    effects, the generic corrections discovered, the tests behind them, and what backs them."""

    finding: Finding
    ranking: list[Candidate]
    trial: Trial = field(repr=False)
    experiments: list[str]
    seconds: float
    #: what the best named effect leaves, against its own model's floor (None without one)
    remainder: Departures | None = None
    #: generic corrections, best first (when the status is partly_explained or unexplained)
    discovered: list = field(default_factory=list)
    ladder: list[dict] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)
    #: where the model as given fails: regime shares, hot spots, residual tests
    where: dict = field(default_factory=dict)
    #: names of the other experiments every candidate was also scored on (validation)
    validated_on: list[str] = field(default_factory=list)
    #: the model's predictions of the prepared experiments (for reports)
    base_predictions: list = field(default=None, repr=False)

    status = property(lambda self: self.finding.status)
    verdict = property(lambda self: self.finding.verdict)
    reason = property(lambda self: self.finding.reason)
    ambiguous_with = property(lambda self: list(self.finding.ties))
    suggested_experiment = property(lambda self: self.finding.suggestion)
    baseline = property(lambda self: self.trial.base)
    options = property(lambda self: self.trial.options)
    free = property(lambda self: list(self.trial.free))
    data = property(lambda self: self.trial.data)
    floor = property(lambda self: self.trial.floor)

    @property
    def winner(self) -> Candidate | None:
        """The named effect of the verdict, if any."""
        return next((c for c in self.ranking if c.effect == self.verdict), None)

    @property
    def added(self) -> Candidate | None:
        """What ``--apply`` adds (:func:`added_by`)."""
        return added_by(self.finding, self.ranking, self.discovered, self.options)

    def departures(self) -> dict:
        """The model as given against its floor, and what the named verdict leaves against
        its own."""
        out = {'base': self.trial.departures(self.baseline.score).to_json()}
        if self.remainder is not None:
            out['remainder'] = self.remainder.to_json()
        return out

    def to_json(self) -> dict:
        options = self.options
        return {'status': str(self.status), 'verdict': self.verdict,
                'size': self.finding.size,
                'ranking': [{'rank': i + 1, 'earns_place': earns_place(c, options),
                             **c.to_json()} for i, c in enumerate(self.ranking)],
                'discovered': [{'rank': i + 1, 'earns_place': earns_place(d, options),
                                **d.to_json(), 'next_record': next_record(d)}
                               for i, d in enumerate(self.discovered)],
                'partial_fits': list(self.finding.partial),
                'ambiguous_with': list(self.ambiguous_with),
                'suggested_experiment': self.suggested_experiment,
                'reason': self.reason,
                'baseline': {'heldout_rms': self.baseline.score.to_json(),
                             'base_params': dict(self.baseline.values),
                             'effects': list(self.baseline.config.effects)},
                'floor': self.floor.to_json(),
                'tests': {**self.departures(),
                          'levels': {'departure': self.trial.levels.departure,
                                     'candidate': self.trial.levels.candidate}},
                'ladder': self.ladder,
                'where': self.where,
                'experiments': list(self.experiments), 'free': list(self.free),
                'validated_on': list(self.validated_on),
                'options': options.to_json(),
                'noise_rms': self.trial.noise,
                'seconds': round(self.seconds, 2),
                'timings': {k: round(v, 2) for k, v in self.timings.items()}}


def added_by(finding: Finding, ranking: list[Candidate], discovered: list[Candidate],
             options) -> Candidate | None:
    """What ``--apply`` adds: the named verdict, else the best discovered correction if it
    earns its place."""
    winner = next((c for c in ranking if c.effect == finding.verdict), None)
    if winner is not None:
        return winner
    best = discovered[0] if discovered else None
    return best if best is not None and earns_place(best, options) else None


def apply(result: Diagnosis, effect: str | None = None) -> ModelConfig:
    """The model with what the diagnosis found added and fitted (the named winner, else the
    best discovered correction), or with ``effect`` from the ranking or the discovered."""
    if effect is None:
        if result.added is None:
            raise ConfigError(f'the diagnosis found nothing to add (status {result.status}); '
                              'name an effect from the ranking to add it anyway')
        return result.added.config
    for cand in result.ranking + result.discovered:
        if cand.effect == effect:
            return cand.config
    raise ConfigError(f'{effect!r} was not tried in this diagnosis; tried: '
                      f'{", ".join(c.effect for c in result.ranking + result.discovered)}')
