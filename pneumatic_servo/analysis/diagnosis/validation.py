"""Validation on other experiments: does what was found on one experiment improve another?

The paper's own method: parameters identified on some tests (its section 5) are
validated on others (section 6). Every candidate fitted on the diagnosed data,
and every rung of the ladder, is scored on whole other records, any circuit
(a static table against a time series or the reverse), per channel, against
the model as given. A parameter the diagnosed data cannot determine needs an
assumption there: its mirror where it has one (chamber b's leak as chamber
a's, by symmetry), else its neutral value; the assumption is reported.
"""
from __future__ import annotations

from dataclasses import dataclass

from ... import effects as registry
from ...fitting import residual_rows
from ...model.assembly import Model
from ...model.config import ModelConfig
from .candidates import Candidate
from .data import Data
from .discovery import Discovered, correction_host
from .hosts import shared_host
from .scoring import Score, relative_fall

#: an effect that raises the error on the other experiments by more than this share hurts
HURTS = 0.05


@dataclass
class Validation:
    """Scores on the other experiments: the candidate's, the model as given's, the fall of
    the error (negative: it got worse), and the assumptions made."""

    score: Score
    base: Score
    error_reduction: float
    channel_reduction: dict[str, float]
    assumptions: list[str]

    @property
    def hurts(self) -> bool:
        return self.error_reduction < -HURTS

    def to_json(self) -> dict:
        return {'heldout_rms': self.score.to_json(), 'base_rms': self.base.to_json(),
                'error_reduction': self.error_reduction,
                'channel_error_reduction': dict(self.channel_reduction),
                'assumptions': list(self.assumptions), 'hurts': self.hurts}


def score_on(config: ModelConfig, host_of, other: Data) -> Score:
    """Score of ``config`` on the whole other experiments, on the compiled host ``host_of``
    gives it (so that no new composition is compiled)."""
    host = host_of(config)
    return Score.of(residual_rows(Model(host), other.whole, [host])[0])


def assumed(c: Candidate) -> tuple[ModelConfig, list[str]]:
    """``c``'s model for other experiments, with every parameter it could not determine set
    by an assumption, and the assumptions in words."""
    cfg, words = c.config, []
    for key in c.undetermined:
        owner, _, name = key.partition('.')
        p = cfg.param(key)
        twin = f'{owner}.{p.mirror}' if p.mirror else ''
        if twin and twin not in c.undetermined:
            cfg = cfg.with_effect(owner, {name: cfg.get(twin)})
            words.append(f'assuming {name} = {p.mirror} ({cfg.get(twin):.4g} {p.unit}, by '
                         'symmetry): the diagnosed data cannot determine it')
        else:
            value = (registry.get(owner).neutral or {}).get(name, cfg.get(key))
            cfg = cfg.with_effect(owner, {name: value})
            words.append(f'assuming {name} = {value:.4g} {p.unit} (its neutral value): the '
                         'diagnosed data cannot determine it')
    return cfg, words


def validate(c: Candidate, base: Score, other: Data) -> Validation:
    """``c`` scored on the other experiments against the model as given (``base``)."""
    cfg, words = assumed(c)
    host_of = correction_host if isinstance(c, Discovered) else shared_host
    score = score_on(cfg, host_of, other)
    return Validation(score, base, relative_fall(score.overall, base.overall),
                      {ch: relative_fall(v, base.channels.get(ch, 0.0))
                       for ch, v in score.channels.items()}, words)
