"""Held-out scores of models and the information criterion that weighs added parameters."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ...fitting import residual_rows, stack
from ...model.assembly import Model
from ...model.config import ModelConfig
from .data import Data

#: BIC difference below which two models are not told apart ("not worth more than a bare
#: mention", Kass and Raftery 1995, J. Am. Stat. Assoc. 90:773)
BIC_TIE = 2.0


@dataclass(frozen=True)
class Score:
    """Held-out residual of one model: normalised RMS per channel and overall."""

    channels: dict[str, float]
    overall: float
    #: pooled normalised residual vector (for the information criterion)
    residual: np.ndarray = field(repr=False, default=None)
    @classmethod
    def of(cls, row: dict[str, np.ndarray]) -> 'Score':
        """The score of a :func:`~pneumatic_servo.fitting.residual_rows` row."""
        pooled = stack(row)
        return cls({ch: float(np.sqrt(np.mean(r ** 2))) for ch, r in row.items()},
                   float(np.sqrt(np.mean(pooled ** 2))), pooled)

    def mean_square(self, channel: str | None = None) -> float:
        """Held-out mean square [normalised^2] of ``channel``, or pooled."""
        return (self.overall if channel is None else self.channels[channel]) ** 2

    def to_json(self) -> dict:
        return {'overall': self.overall, 'channels': dict(self.channels)}


def score_many(model: Model, data: Data, configs: list[ModelConfig]) -> list[Score]:
    """Held-out scores of several configs of one composition, simulated together."""
    return [Score.of(row) for row in residual_rows(model, data.val, configs)]


def information_criteria(base_ms: float, cand_ms: float, k: int, n_eff: float
                         ) -> tuple[float, float]:
    """(delta AIC, delta BIC) of a candidate adding ``k`` parameters, from the held-out mean
    squares (or sums of squares) of the base and the candidate, on ``n_eff`` samples.

    Gaussian likelihood on the held-out residual: n ln(RSS_1/RSS_0) plus the
    penalty; ``n_eff`` discounts the residual's autocorrelation, without
    which any tiny improvement on thousands of samples looks significant.
    """
    fit_term = n_eff * math.log(max(cand_ms, 1e-300) / max(base_ms, 1e-300))
    return fit_term + 2.0 * k, fit_term + k * math.log(n_eff)


def relative_fall(new: float, old: float) -> float:
    """1 - new / old: the fraction by which an error fell (0 if there was none)."""
    return float(1.0 - new / old) if old > 0 else 0.0
