"""The prediction floor of one record: what the fitted model itself would leave on it.

A correct model does not predict a record exactly: sensor noise and quantisation, the
start state estimated from noisy samples, the unmeasured gas temperature, stick-slip
timing and the closed loop's sensitivity near the valve null all leave a residual, and how
much depends on the record (its sampling, sensors, controller and excitation), not on the
sensor noise alone. So the floor is measured on each record, by a parametric bootstrap:

* **replicas** of the held-out segments are simulated with the fitted model from the
  measured states (each with its own lead-in, so the unmeasured states differ from the
  predictor's as they do in reality), with model-form jitter of the size a different
  integrator and sampling phase give: an integrator tolerance drawn between a tenth of and
  three times the predictor's, and a measurement instant up to a fifth of a sample off;
* each replica is measured with the record's own sensor noise and quantisation, both
  estimated from the records (:func:`~.data.noise_sigma`, :func:`quanta`);
* each replica passes through the same prediction and scoring as the record.

Static tables are predicted row by row by a steady-state solve; their floor is the
measurement noise, estimated from the model's residual (rows are independent).

A held-out mean square is then compared with its replicas' (:meth:`Floor.test`): a one-sided
prediction-interval test on the log scale (Student t with R - 1 degrees of freedom), whose
spread has the chi-square sampling variance of the record's independent units added, so
that a record with nearly identical replicas is not judged against a spread of zero.

The replicas score the fitted values as they are. A named effect's values were themselves
fitted to this record, and where stick-slip makes the fit cost rough they scatter well
beyond their standard errors; so what a fitted effect leaves is judged against a floor
that has the fit's own scatter added (:meth:`Floor.with_refits`, :mod:`.refit`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ...experiment import CHANNELS, Experiment
from ...fitting import Part, residual_rows
from ...model.assembly import Model
from ...model.config import ModelConfig
from ...model.simulate import DEFAULT_RTOL
from ...prediction import Plan, predict
from .data import Data, noise_sigma

#: range of the replicas' integrator tolerance, as factors of the predictor's (log-uniform)
RTOL_FACTORS = (0.1, 3.0)
#: largest offset of a replica's measurement instant [samples]: a DAQ that samples a little
#: before or after the command is written
PHASE_SAMPLES = 0.2
#: replicas' segments are drawn in this many interleaved groups, so that a segment's lead-in
#: never overlaps the segment before it in the same replica
GROUPS = 3


def quantum(x: np.ndarray) -> float:
    """Quantisation step [units of x] of a signal whose values are whole multiples of one
    step (an encoder count, an ADC step), else 0."""
    values = np.unique(x[np.isfinite(x)])
    if len(values) < 3:
        return 0.0
    step = float(np.min(np.diff(values)))
    counts = (values - values[0]) / step
    return step if np.all(np.abs(counts - np.round(counts)) < 1e-3) else 0.0


@dataclass(frozen=True)
class Departure:
    """One held-out mean square against the floor: its RMS in units of the floor's RMS and
    the one-sided p-value of a departure upwards."""

    ratio: float
    p_value: float

    def to_json(self) -> dict:
        return {'ratio_to_floor': self.ratio, 'p_value': self.p_value}


@dataclass(frozen=True)
class Floor:
    """Held-out mean squares [normalised^2] of the replicas, per channel and pooled.

    Attributes
    ----------
    channels : dict of str to ndarray
        Channel -> the R replicas' held-out mean squares.
    pooled : ndarray
        The R replicas' pooled held-out mean squares.
    units : int
        Independent units of the held-out data (segments or table rows): the chi-square
        sampling variance of a mean square over them is added to the replicas' spread.
    series_channels : tuple of str
        Channels a time series measures. Only these are tested alone (besides the pooled
        residual): a static table measures its steady flows and pressures far more
        precisely than the time series determine the parameters they share, so a table
        channel alone would call every fit's last per cent a departure; tables count in
        the pooled test.
    """

    channels: dict
    pooled: np.ndarray
    units: int
    series_channels: tuple = ()
    #: channel (and ``'overall'``) -> log ratios of the held-out mean square of values refitted
    #: on whole replicas to that of the values they were simulated with (:meth:`with_refits`)
    refits: dict = field(default_factory=dict)

    @property
    def replicas(self) -> int:
        return len(self.pooled)

    def _refit(self, channel: str | None) -> tuple[float, float]:
        """(shift, variance) on the log scale that refitting adds to ``channel``'s mean
        square: the mean log ratio (never below 0: refitted values do not predict new data
        better than those the data came from) and the ratios' variance."""
        logs = self.refits.get(channel or 'overall')
        if logs is None or not len(logs):
            return 0.0, 0.0
        variance = float(np.var(logs, ddof=1)) if len(logs) > 1 else 0.0
        return max(float(np.mean(logs)), 0.0), variance

    def refit_factor(self, channel: str | None = None) -> float:
        """The factor by which refitting raises the mean square of ``channel`` (or pooled):
        1 without refits."""
        return float(np.exp(self._refit(channel)[0]))

    def rms(self, channel: str | None = None) -> float:
        """The floor's RMS [normalised] of ``channel``, or pooled."""
        ms = self.pooled if channel is None else self.channels[channel]
        return float(np.sqrt(np.mean(ms) * self.refit_factor(channel)))

    def test(self, mean_square: float, channel: str | None = None) -> Departure:
        """``mean_square`` [normalised^2] of ``channel`` (or pooled) against the replicas."""
        from scipy.stats import t as student
        ms = self.pooled if channel is None else self.channels[channel]
        shift, variance = self._refit(channel)
        logs = np.log(np.maximum(ms, 1e-300)) + shift
        r = len(logs)
        spread = np.sqrt(np.var(logs, ddof=1) + variance + 2.0 / max(self.units, 1))
        z = (np.log(max(mean_square, 1e-300)) - logs.mean()) / (spread * np.sqrt(1 + 1 / r))
        floor = self.rms(channel)
        # a floor of exactly zero (the arm held at an end stop in every replica): no residual
        # is no departure, any residual an infinite one
        ratio = (np.sqrt(mean_square) / floor if floor > 0.0
                 else 0.0 if mean_square == 0.0 else math.inf)
        return Departure(float(ratio), float(student.sf(z, r - 1)))

    def with_refits(self, refits: dict[str, np.ndarray]) -> 'Floor':
        """This floor with the fit's own scatter added: ``refits`` maps each channel (and
        ``'overall'``) to the log ratios of what values refitted on whole replicas leave
        held out to what the values the replicas came from leave."""
        return replace(self, refits={k: np.asarray(v, float) for k, v in refits.items()})

    def to_json(self) -> dict:
        out = {'replicas': self.replicas, 'units': self.units,
               'rms': {'overall': self.rms(), **{ch: self.rms(ch) for ch in self.channels}}}
        if self.refits:
            out['refits'] = len(self.refits['overall'])
            out['refit_inflation'] = {k: self.refit_factor(None if k == 'overall' else k)
                                      for k in self.refits}
        return out


def _jittered_truth(model: Model, config: ModelConfig, exp: Experiment, plan: Plan, regions,
                    rtol: float) -> dict[str, np.ndarray]:
    """The fitted model's signals over ``regions`` (each from the measured state at its
    start, after a lead-in of its own), at integrator tolerance ``rtol``."""
    truth_plan = Plan(tuple(regions), plan.open_loop, plan.smooth_start, plan.lead_s)
    return predict(model, exp, [config], truth_plan, rtol=rtol)[0]


def sensor_reading(truth: np.ndarray, phase: float, sigma: float, step: float,
                   rng: np.random.Generator) -> np.ndarray:
    """What sensors show of ``truth`` (samples along its last axis): read ``phase`` of a
    sample early, with white noise ``sigma`` and quantisation ``step`` [units of truth]
    (0: none). Also the monitor's copies (:mod:`pneumatic_servo.monitor.judge`)."""
    y = truth.copy()
    y[..., 1:] = (1.0 - phase) * y[..., 1:] + phase * y[..., :-1]
    y = y + rng.normal(0.0, sigma, y.shape)
    return np.round(y / step) * step if step > 0 else y


def _measured(truth: np.ndarray, regions, phase: float, sigma: float, step: float,
              rng: np.random.Generator) -> list[np.ndarray]:
    """What the record's sensors show of ``truth`` over each region (:func:`sensor_reading`)."""
    return [sensor_reading(truth[a:b], phase, sigma, step, rng) for a, b in regions]


def quanta(data: Data) -> dict[str, float]:
    """Signal -> its quantisation step [SI], the finest found in any of the time series: the
    records of one diagnosis share their sensors, and a record that sits still (at an end
    stop) shows no step of its own, yet reads its position to the nearest count."""
    out: dict[str, float] = {}
    for part in data.val:
        if part.plan is None:
            continue
        for ch in part.scales:
            sig = CHANNELS[ch].signal
            step = quantum(part.exp[sig])
            if step > 0:
                out[sig] = min(step, out.get(sig, np.inf))
    return out


def _series_replicas(model: Model, config: ModelConfig, part: Part, count: int,
                     steps: dict[str, float], rng: np.random.Generator, dt: float | None = None
                     ) -> list[tuple[int, Part]]:
    """(replica number, part) of ``count`` replicas of a time-series part, each replica cut
    into :data:`GROUPS` parts of interleaved segments; ``steps``: the quantisation steps
    (:func:`quanta`); ``dt`` [s]: the record's own sample interval, when the part is
    decimated (the sampling-phase jitter is a fraction of the record's interval, not of the
    part's: jitter of a fifth of a 250 Hz sample on a 500 Hz record's fitted part would double
    the time offset and quadruple what it leaves)."""
    exp, plan = part.exp, part.plan
    lead = int(round(plan.lead_s / exp.dt))
    signals = [CHANNELS[ch].signal for ch in part.scales]
    sensors = {}
    for sig in signals:
        step = steps.get(sig, 0.0)
        sensors[sig] = (np.sqrt(max(noise_sigma(exp[sig]) ** 2 - step ** 2 / 12.0, 0.0)), step)
    rtols = DEFAULT_RTOL * np.exp(rng.uniform(*np.log(RTOL_FACTORS), count))
    phases = rng.uniform(0.0, PHASE_SAMPLES, count) * min((dt or exp.dt) / exp.dt, 1.0)
    out = []
    for g in range(GROUPS):
        segments = plan.segments[g::GROUPS]
        if not segments:
            continue
        regions = [(max(a - lead, 0), b) for a, b in segments]
        for j in range(count):
            truth = _jittered_truth(model, config, exp, plan, regions, rtols[j])
            replica = dict(exp.signals)
            for sig in signals:
                x = exp[sig].copy()
                for (a, b), y in zip(regions, _measured(truth[sig], regions, phases[j],
                                                        *sensors[sig], rng)):
                    x[a:b] = y
                replica[sig] = x
            rep = Experiment(exp.t, replica, exp.circuit, f'{exp.name}[replica {j}]', False,
                             dict(exp.metadata))
            out.append((j, Part(rep, part.scales, plan.subset(segments), smooth=part.smooth)))
    return out


def _table_replica(model: Model, config: ModelConfig, part: Part, rng: np.random.Generator
                   ) -> Part:
    """A replica of a static table: the rows ``config`` predicts, with the noise its
    residual shows (rows are independent operating points)."""
    rows = residual_rows(model, [part], [config])[0]
    signals = dict(part.exp.signals)
    for ch, r in rows.items():
        sig, scale = CHANNELS[ch].signal, part.scales[ch]
        x = signals[sig].copy()
        x[part.index] = part.measured(sig) + scale * (r + rng.normal(0.0, noise_sigma(r), len(r)))
        signals[sig] = x
    exp = part.exp
    rep = Experiment(exp.t, signals, exp.circuit, f'{exp.name}[replica]', True, dict(exp.metadata))
    return Part(rep, part.scales, None, part.first, part.smooth)


def replica_data(model: Model, config: ModelConfig, data: Data, rng: np.random.Generator
                 ) -> Data:
    """One replica of the whole of ``data``, fitted and held-out parts, simulated with
    ``config`` (compiled as ``model``) and measured as the record's sensors measure: what a
    refit is tried on (:mod:`.refit`)."""
    steps = quanta(data)

    def copy(part: Part, exp: Experiment) -> list[Part]:
        if part.plan is None:
            return [_table_replica(model, config, part, rng)]
        return [p for _, p in _series_replicas(model, config, part, 1, steps, rng, exp.dt)]

    return Data(data.experiments,
                [p for part, exp in zip(data.fit, data.experiments) for p in copy(part, exp)],
                [p for part, exp in zip(data.val, data.experiments) for p in copy(part, exp)])


def measure_floor(model: Model, config: ModelConfig, data: Data, count: int, seed: int
                  ) -> Floor:
    """The floor of ``config`` (compiled as ``model``) on the held-out parts of ``data``,
    from ``count`` replicas."""
    rng = np.random.default_rng(seed)
    steps = quanta(data)
    sums: dict[str, np.ndarray] = {}
    counts: dict[str, np.ndarray] = {}

    def add(j, row):
        for ch, r in row.items():
            sums.setdefault(ch, np.zeros(count))[j] += float(r @ r)
            counts.setdefault(ch, np.zeros(count))[j] += len(r)

    for part in data.val:
        if part.plan is None:
            rows = residual_rows(model, [part], [config])[0]
            for j in range(count):
                add(j, {ch: rng.normal(0.0, noise_sigma(r), len(r)) for ch, r in rows.items()})
            continue
        for j, rep in _series_replicas(model, config, part, count, steps, rng):
            add(j, residual_rows(model, [rep], [config])[0])
    channels = {ch: sums[ch] / counts[ch] for ch in sums}
    pooled = sum(sums.values()) / sum(counts.values())
    series = tuple(dict.fromkeys(ch for p in data.val if p.plan is not None for ch in p.scales))
    return Floor(channels, pooled, data.independent_units, series)
