"""A fitting problem: normalised residuals of parameter vectors over parts of experiments.

Residuals are (prediction - measurement) / spread per experiment and channel,
so angle [rad], pressure [Pa] and flow [kg/s] channels weigh alike. Every
parameter vector of one call is simulated in one parallel batch.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..experiment import CHANNELS, Experiment
from ..model.assembly import Model
from ..model.config import ModelConfig
from ..prediction import Plan, predict

#: a failed simulation contributes this normalised residual (a very poor fit, not a crash)
FAILED_RESIDUAL = 1e3


def channel_scales(exp: Experiment, channels=None) -> dict[str, float]:
    """Normalising spread [SI] of each channel measured in ``exp`` (of ``channels``, if
    given): its standard deviation, but not below the channel's resolution floor."""
    out = {}
    for name, ch in CHANNELS.items():
        if ch.signal in exp.signals and (channels is None or name in channels):
            out[name] = max(float(np.nanstd(exp[ch.signal])), ch.floor)
    return out


def smooth(x: np.ndarray, width: int, breaks=()) -> np.ndarray:
    """Centred moving average over an odd ``width`` of samples (fewer at the ends); no delay.
    ``breaks``: indices where a new piece begins; each piece is averaged on its own."""
    if width <= 1 or len(x) < 2:
        return x
    n, half = len(x), width // 2
    starts = np.concatenate([[0], breaks]).astype(int)
    ends = np.append(starts[1:], n)
    piece = np.repeat(np.arange(len(starts)), ends - starts)
    i = np.arange(n)
    lo, hi = np.maximum(i - half, starts[piece]), np.minimum(i + half + 1, ends[piece])
    total = np.concatenate([[0.0], np.cumsum(x)])
    return (total[hi] - total[lo]) / (hi - lo)


@dataclass
class Part:
    """One experiment's share of a fit or a score.

    Attributes
    ----------
    exp : Experiment
        A time series or a static table.
    scales : dict
        Channel -> normalising spread [SI]; the channels compared.
    plan : Plan, optional
        How the time series is predicted (None for a static table: every row).
    first : int
        Samples before this index are left out (a start-up transient).
    smooth : int
        Width [samples] of the centred moving average applied to the residual
        within each segment (1: none).
    """

    exp: Experiment
    scales: dict[str, float]
    plan: Plan | None = None
    first: int = 0
    smooth: int = 1

    @cached_property
    def index(self) -> np.ndarray:
        """Samples (or rows) whose residuals count, in order."""
        idx = np.arange(len(self.exp.t)) if self.plan is None else self.plan.index
        return idx[idx >= self.first]

    @cached_property
    def breaks(self) -> np.ndarray:
        """Positions in :attr:`index` where a segment begins (the residual is smoothed
        within segments)."""
        if self.plan is None:
            return np.zeros(0, dtype=int)
        starts = np.array([a for a, _ in self.plan.segments])
        return np.searchsorted(self.index, starts[starts > self.index[0]])

    def measured(self, sig: str) -> np.ndarray:
        return self.exp[sig][self.index]

    @property
    def samples(self) -> int:
        return len(self.index)


def residual_rows(model: Model, parts: list[Part], configs: list[ModelConfig]
                  ) -> list[dict[str, np.ndarray]]:
    """Normalised residuals per config and channel over ``parts``, all configs (one
    composition) simulated together; non-finite residuals become :data:`FAILED_RESIDUAL`."""
    rows: list[dict[str, list]] = [dict() for _ in configs]
    for part in parts:
        preds = predict(model, part.exp, configs, part.plan)
        for j, pred in enumerate(preds):
            for ch, scale in part.scales.items():
                sig = CHANNELS[ch].signal
                r = (pred[sig][part.index] - part.measured(sig)) / scale
                r = np.where(np.isfinite(r), r, FAILED_RESIDUAL)
                r = smooth(r, part.smooth, part.breaks)
                rows[j].setdefault(ch, []).append(r)
    return [{ch: np.concatenate(v) for ch, v in row.items()} for row in rows]


def stack(row: dict[str, np.ndarray]) -> np.ndarray:
    """One residual vector of all channels of a :func:`residual_rows` row."""
    return np.concatenate(list(row.values()))


def with_values(config: ModelConfig, keys, values) -> ModelConfig:
    """A copy of ``config`` with ``keys`` (``'owner.name'``) set to ``values`` [SI]."""
    cfg = config.copy()
    for key, v in zip(keys, values):
        cfg.set(key, float(v))
    return cfg


def typical_size(p, value: float) -> float:
    """The size [SI] of parameter ``p`` (at ``value``): the largest magnitude of its declared
    plausible range, else of its default or value (hard bounds are often far wider than any
    rig), else 1."""
    if p.plausible is not None:
        return max(abs(a) for a in p.plausible) or 1.0
    return max(abs(p.default), abs(value)) or 1.0


class Problem:
    """Residuals over ``parts`` of ``config`` with the parameters ``keys`` set to a vector.

    Bounds are the parameters' declared bounds (or ``bounds``: key -> (lo, hi)
    [SI]); the scale of a parameter is its start value, but at least 1 % of
    its :func:`typical_size`, so a parameter that starts at zero still moves.
    The finite-difference step of the Jacobian is ``fd_step`` times that scale,
    but at least ``fd_min`` times the typical size: stick-slip and the
    integrator's tolerance make the residual rough on small scales, and a step
    below that roughness returns noise, not a slope.
    """

    def __init__(self, config: ModelConfig, keys: list[str], parts: list[Part],
                 model: Model | None = None, bounds: dict | None = None,
                 fd_step: float = 1e-3, fd_min: float = 0.0):
        self.config, self.keys, self.parts = config, list(keys), parts
        self.model = model or Model(config)
        params = [config.param(k) for k in self.keys]
        given = bounds or {}
        self.lo = np.array([given.get(k, (p.lower, p.upper))[0]
                            for k, p in zip(self.keys, params)], float)
        self.hi = np.array([given.get(k, (p.lower, p.upper))[1]
                            for k, p in zip(self.keys, params)], float)
        x0 = np.array([config.get(k) for k in self.keys])
        self.span = np.array([typical_size(p, v) for p, v in zip(params, x0)])
        self.scale = np.maximum(np.abs(x0), 0.01 * self.span)
        self.fd_step = np.maximum(fd_step * self.scale, fd_min * self.span)
        self.evaluations = 0

    def config_at(self, x) -> ModelConfig:
        return with_values(self.config, self.keys, x)

    def rows(self, xs) -> list[np.ndarray]:
        """Residual vectors of several parameter vectors (one batch)."""
        self.evaluations += len(xs)
        configs = [self.config_at(x) for x in xs]
        return [stack(r) for r in residual_rows(self.model, self.parts, configs)]

    def costs(self, xs) -> np.ndarray:
        """Sums of squared residuals of several parameter vectors."""
        return np.array([float(r @ r) for r in self.rows(xs)])

    def evaluate(self, x) -> tuple[np.ndarray, np.ndarray]:
        """(residual vector, Jacobian) at ``x``: one batch of 1 + p simulations, each probe
        stepping away from the nearer bound so that it stays feasible."""
        sets = [np.asarray(x, float)]
        for i in range(len(x)):
            xi = sets[0].copy()
            h = self.fd_step[i]
            xi[i] = x[i] + h if x[i] + h <= self.hi[i] else x[i] - h
            sets.append(xi)
        rows = self.rows(sets)
        jac = np.column_stack([(rows[i + 1] - rows[0]) / (sets[i + 1][i] - x[i])
                               for i in range(len(x))])
        return rows[0], jac
