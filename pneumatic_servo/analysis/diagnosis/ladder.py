"""The ladder: held-out error as the model's effects are added one by one, then the winner."""
from __future__ import annotations

from ...model.assembly import Model
from ...model.config import ModelConfig
from .candidates import Baseline, Candidate
from .data import Data
from .hosts import neutral, shared_host
from .scoring import Score, score_many


def ladder(config: ModelConfig, data: Data, winner: Candidate | None = None,
           base: Baseline | None = None) -> list[dict]:
    """Held-out error of ``config`` without its added effects, then adding them one by one
    (with the values ``config`` holds), then adding ``winner``.

    Returns, per rung, ``{'model', 'effects', 'overall', 'channels'}``
    (normalised held-out RMS). The full model's rung reuses ``base``'s score.
    """
    names = list(config.effects)
    rungs = []
    for i in range(len(names) + 1):
        if i == len(names) and base is not None:
            score = base.score
        else:
            score = prefix_score(config, names, i, data)
        rungs.append(rung('+' + names[i - 1] if i else 'base', names[:i], score))
    if winner is not None:
        rungs.append(rung('+' + winner.effect, names + [winner.effect], winner.score))
    return rungs


def prefix_score(config: ModelConfig, names: list[str], i: int, data: Data) -> Score:
    """Held-out score of ``config`` with only its first ``i`` effects active.

    Later effects with neutral values are switched off by value, so the
    same compiled model serves every rung; others are removed.
    """
    host = config.copy()
    for name in names[i:]:
        if neutral(name) is None:
            del host.effects[name]
        else:
            host = host.with_effect(name, neutral(name))
    host = shared_host(host)
    return score_many(Model(host), data, [host])[0]


def rung(label: str, effects: list[str], score: Score) -> dict:
    return {'model': label, 'effects': list(effects), 'overall': score.overall,
            'channels': dict(score.channels)}
