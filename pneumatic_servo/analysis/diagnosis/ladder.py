"""The ladder: held-out error as the model's effects are added one by one, then the winner."""
from __future__ import annotations

from ...fitting import residual_rows
from ...model.assembly import Model
from ...model.config import ModelConfig
from .candidates import Baseline, Candidate
from .data import Data
from .hosts import neutral, shared_host
from .scoring import Score, score_many


def ladder(config: ModelConfig, data: Data, winner: Candidate | None = None,
           base: Baseline | None = None, other: Data | None = None) -> list[dict]:
    """Held-out error of ``config`` without its added effects, then adding them one by one
    (with the values ``config`` holds), then adding ``winner``.

    Returns, per rung, ``{'model', 'effects', 'overall', 'channels'}``
    (normalised held-out RMS), and ``'validation'`` (the same on the whole of the
    ``other`` experiments) when there are any. The full model's rung reuses ``base``'s
    score.
    """
    names = list(config.effects)
    rungs = []
    for i in range(len(names) + 1):
        host = prefix_host(config, names, i)
        model = Model(host)
        if i == len(names) and base is not None:
            score = base.score
        else:
            score = score_many(model, data, [host])[0]
        rungs.append(rung('+' + names[i - 1] if i else 'base', names[:i], score))
        if other is not None:
            rungs[-1]['validation'] = Score.of(
                residual_rows(model, other.whole, [host])[0]).to_json()
    if winner is not None:
        rungs.append(rung('+' + winner.effect, names + [winner.effect], winner.score))
        if other is not None and winner.validation is not None:
            rungs[-1]['validation'] = winner.validation.score.to_json()
    return rungs


def prefix_host(config: ModelConfig, names: list[str], i: int) -> ModelConfig:
    """``config`` with only its first ``i`` effects active, on its shared host.

    Later effects with neutral values are switched off by value, so the
    same compiled model serves every rung; others are removed.
    """
    host = config.copy()
    for name in names[i:]:
        if neutral(name) is None:
            del host.effects[name]
        else:
            host = host.with_effect(name, neutral(name))
    return shared_host(host)


def rung(label: str, effects: list[str], score: Score) -> dict:
    return {'model': label, 'effects': list(effects), 'overall': score.overall,
            'channels': dict(score.channels)}
