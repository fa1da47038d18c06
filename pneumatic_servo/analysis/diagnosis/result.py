"""The result of a diagnosis and its JSON form."""
from __future__ import annotations

from dataclasses import dataclass, field

from ...errors import ConfigError
from ...model.config import ModelConfig
from .candidates import Baseline, Candidate
from .data import Data
from .options import DiagnoseOptions
from .status import CONSISTENT_RATIO, Finding
from .verdict import earns_place


@dataclass
class Diagnosis:
    """Result of :func:`~.run.diagnose`: the status and verdict, the ranking of named
    effects, the generic corrections discovered, and what backs them."""

    finding: Finding
    ranking: list[Candidate]
    baseline: Baseline
    options: DiagnoseOptions
    free: list[str]
    experiments: list[str]
    seconds: float
    #: generic corrections, best first (when the status is partly_explained or unexplained)
    discovered: list = field(default_factory=list)
    ladder: list[dict] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)
    #: where the model as given fails: regime shares, hot spots, residual tests
    where: dict = field(default_factory=dict)
    #: names of the other experiments every candidate was also scored on (validation)
    validated_on: list[str] = field(default_factory=list)
    #: the prepared experiments and the model's predictions of them (for reports)
    data: Data = field(default=None, repr=False)
    base_predictions: list = field(default=None, repr=False)

    status = property(lambda self: self.finding.status)
    verdict = property(lambda self: self.finding.verdict)
    reason = property(lambda self: self.finding.reason)
    ambiguous_with = property(lambda self: self.finding.ties)
    suggested_experiment = property(lambda self: self.finding.suggestion)

    @property
    def winner(self) -> Candidate | None:
        """The named effect of the verdict, if any."""
        return next((c for c in self.ranking if c.effect == self.verdict), None)

    @property
    def added(self) -> Candidate | None:
        """What ``--apply`` adds: the named winner, else the best discovered correction if
        it earns its place."""
        if self.winner is not None:
            return self.winner
        best = self.discovered[0] if self.discovered else None
        return best if best is not None and earns_place(best, self.options) else None

    def to_json(self) -> dict:
        noise = self.ranking[0].noise_rms if self.ranking else None
        return {'status': self.status, 'verdict': self.verdict,
                'size': self.finding.size,
                'ranking': [{'rank': i + 1, 'earns_place': earns_place(c, self.options),
                             **c.to_json()} for i, c in enumerate(self.ranking)],
                'discovered': [{'rank': i + 1, 'earns_place': earns_place(d, self.options),
                                **d.to_json()} for i, d in enumerate(self.discovered)],
                'partial_fits': list(self.finding.partial),
                'ambiguous_with': list(self.ambiguous_with),
                'suggested_experiment': self.suggested_experiment,
                'reason': self.reason,
                'baseline': {'heldout_rms': self.baseline.score.to_json(),
                             'base_params': dict(self.baseline.values),
                             'effects': list(self.baseline.config.effects)},
                'ladder': self.ladder,
                'where': self.where,
                'experiments': list(self.experiments), 'free': list(self.free),
                'validated_on': list(self.validated_on),
                'options': self.options.to_json(),
                'noise_rms': noise, 'consistent_ratio': CONSISTENT_RATIO,
                'seconds': round(self.seconds, 2),
                'timings': {k: round(v, 2) for k, v in self.timings.items()}}


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
