"""Experiments prepared for diagnosis: decimated, split into fitted and held-out parts."""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ...errors import ExperimentError
from ...experiment import CHANNELS, Experiment
from ...fitting import Part, channel_scales, residual_rows
from ...prediction import quiet_starts
from .options import DiagnoseOptions


def decimate(exp: Experiment, q: int) -> Experiment:
    """Every ``q``-th sample; the valve command is averaged over each ``q`` samples.

    The average keeps the command's time integral (and so the volume of air
    metered) while cutting the number of zero-order-hold intervals to simulate.
    """
    if q <= 1 or exp.static:
        return exp
    n = len(exp.t) // q * q
    sig = {k: (v[:n].reshape(-1, q).mean(axis=1) if k == 'command_v' else v[:n:q])
           for k, v in exp.signals.items()}
    return Experiment(exp.t[:n:q], sig, exp.circuit, exp.name, exp.static, dict(exp.metadata))


def _rows(exp: Experiment, keep: np.ndarray, name: str) -> Experiment:
    return Experiment(np.arange(int(keep.sum()), dtype=float),
                      {k: v[keep] for k, v in exp.signals.items()}, exp.circuit, name, True,
                      dict(exp.metadata))


def smoothing_width(smooth_s: float, dt: float) -> int:
    """Odd number of samples of a moving average over ``smooth_s`` [s]."""
    return int(round(smooth_s / dt)) | 1


def fit_factor(exp: Experiment, options: DiagnoseOptions) -> int:
    """How much the fitted part of ``exp`` is decimated: to about ``options.fit_rate_hz``
    (1 for a static table, or when that rate is 0)."""
    if exp.static or not options.fit_rate_hz:
        return 1
    return max(1, int(1.0 / (exp.dt * options.fit_rate_hz) + 1e-9))


def split(exp: Experiment, scales: dict, options: DiagnoseOptions) -> tuple[Part, Part]:
    """(fit part, validation part) of one experiment.

    Tables alternate rows. Time series are cut into segments that start at
    quiet samples (:func:`~pneumatic_servo.prediction.quiet_starts`); whole
    blocks of segments alternate between fitting and validation, so the
    validation data are not interleaved with the fitted samples. The fitted part is
    decimated to about ``options.fit_rate_hz`` (:func:`fit_factor`): a fit simulates it
    many times, while the held-out part, which every statement is judged on, keeps the
    record's own rate.
    """
    if exp.static:
        idx = np.arange(len(exp.t))
        return (Part(_rows(exp, idx % 2 == 0, f'{exp.name}[fit]'), scales),
                Part(_rows(exp, idx % 2 == 1, f'{exp.name}[val]'), scales))
    plan = quiet_starts(exp, options.horizon_s, options.lead_s)
    block = len(exp.t) / options.blocks
    fit, val = [], []
    for a, b in plan.segments:
        (fit if int(a // block) % 2 == 0 else val).append((a, b))
    if not val or not fit:  # too short for blocks: alternate segments
        segs = list(plan.segments)
        fit, val = segs[0::2], segs[1::2] or segs[:1]
    return (coarse(Part(exp, scales, plan.subset(fit)), fit_factor(exp, options),
                   options.smooth_s),
            Part(exp, scales, plan.subset(val), smooth=smoothing_width(options.smooth_s,
                                                                       exp.dt)))


def coarse(part: Part, q: int, smooth_s: float) -> Part:
    """A time-series ``part`` decimated by ``q`` (:func:`decimate`), its segments mapped onto
    the coarse samples, its residual smoothed over ``smooth_s`` [s]."""
    exp = decimate(part.exp, q)
    n = len(exp.t)
    segments = [(a // q, min(-(-b // q), n)) for a, b in part.plan.segments]
    return Part(exp, part.scales, part.plan.subset([(a, b) for a, b in segments if b - a >= 2]),
                smooth=smoothing_width(smooth_s, exp.dt))


def noise_sigma(x: np.ndarray) -> float:
    """Robust white-noise level [units of x] from second differences:
    sigma = 1.4826 MAD(d2) / sqrt(6), blind to any smooth signal."""
    d2 = x[2:] - 2.0 * x[1:-1] + x[:-2]
    return 1.4826 * float(np.median(np.abs(d2 - np.median(d2)))) / np.sqrt(6.0)


@dataclass(frozen=True)
class Data:
    """Experiments prepared and split for diagnosis."""

    experiments: list[Experiment]
    fit: list[Part]
    val: list[Part]

    def noise(self, model=None, config=None) -> float:
        """Sensor noise in the validation residuals, pooled and normalised like
        :class:`~.scoring.Score`, divided by the square root of the smoothing width, as the
        residuals are smoothed.

        Time series: :func:`noise_sigma` of each measured channel, whose signal is smooth
        at the sample rate. Static tables: each row is another operating point, so the
        measurement itself is no measure of noise; :func:`noise_sigma` of the residual of
        ``config`` (the model as given, compiled as ``model``) is, where that model is
        smooth across rows (a table alone, without a model, counts no noise).
        """
        total, count = 0.0, 0
        for part in self.val:
            rows = None
            if part.plan is None:
                if model is None:
                    continue
                rows = residual_rows(model, [part], [config])[0]
            for ch, scale in part.scales.items():
                x = rows[ch] if rows is not None else part.measured(CHANNELS[ch].signal) / scale
                if len(x) < 5:
                    continue
                total += len(x) * noise_sigma(x) ** 2 / part.smooth
                count += len(x)
        return float(np.sqrt(total / count)) if count else 0.0

    @cached_property
    def screen_val(self) -> list[Part]:
        """The held-out parts at the fitted parts' rate: what discovery's linear screen
        ranks terms on (it simulates each of some 150 terms; the terms it keeps are then fitted
        and judged on :attr:`val`, at the record's rate)."""
        out = []
        for fit, val in zip(self.fit, self.val):
            if val.plan is None:
                out.append(val)
                continue
            q = max(1, int(round(fit.exp.dt / val.exp.dt)))
            out.append(coarse(val, q, val.smooth * val.exp.dt) if q > 1 else val)
        return out

    @property
    def whole(self) -> list[Part]:
        """Every part, fitted and held out: the whole of each experiment."""
        return self.fit + self.val

    @property
    def independent(self) -> int:
        """Validation segments (or table rows) times their channels."""
        return sum((len(p.plan.segments) if p.plan is not None else p.samples)
                   * len(p.scales) for p in self.val)

    @property
    def independent_units(self) -> int:
        """Validation segments and table rows: each starts afresh from measured states."""
        return sum(len(p.plan.segments) if p.plan is not None else p.samples for p in self.val)

    @classmethod
    def of(cls, experiments: list[Experiment], options: DiagnoseOptions) -> 'Data':
        """Prepare ``experiments``: decimation, fit/validation split.

        Channels are normalised by their spread over the whole experiment, so
        angle [rad] and pressures [Pa] weigh alike in every part.
        """
        if not experiments:
            raise ExperimentError('no experiments to diagnose; give at least one bag or CSV')
        prepared, fit, val = [], [], []
        for exp in experiments:
            scales = channel_scales(exp)
            if not scales:
                raise ExperimentError(f'{exp.name or "experiment"} measures none of '
                                      f'{", ".join(CHANNELS)}; nothing to compare with')
            if not exp.static and 'command_v' not in exp.signals:
                raise ExperimentError(f'{exp.name or "experiment"}: no valve command recorded; '
                                      'record valve/command')
            exp = decimate(exp, options.decimate)
            prepared.append(exp)
            f, v = split(exp, scales, options)
            fit.append(f)
            val.append(v)
        return cls(prepared, fit, val)
