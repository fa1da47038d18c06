"""Each k-step window of live data against its own prediction floor.

The monitor predicts the rig in k-step windows, each from the measured state at its start,
as ``compare``'s k-step view does (:func:`pneumatic_servo.prediction.predict`). A correct
model does not predict a window exactly: how much it leaves depends on what the rig was
doing in that window (a fast move leaves more than a rest) and on the sensors. So every
window is judged against its own floor, measured as ``diagnose`` measures a record's
(:mod:`pneumatic_servo.analysis.diagnosis.floor`), by a parametric bootstrap:

* ``replicas`` copies of the window are simulated with the model from the measured state a
  lead-in earlier (so the unmeasured states differ from the predictor's as they do on the
  rig), each with model-form jitter: an integrator tolerance drawn between a tenth of and
  three times the predictor's, and a measurement instant up to a fifth of a sample off;
* where the valve command that acted in a sample is uncertain (a free-running loop whose
  command came just before the next measurement: ``command_alt_v``, :mod:`.assemble`),
  each copy's truth takes the other candidate with probability one half;
* each copy is measured with the rig's own sensor noise and quantisation
  (:class:`Sensors`, measured on the baseline or loaded from a floor file);
* each copy is predicted and scored exactly as the window.

The window's mean square residual per channel is then tested against its copies' with
:meth:`Floor.test <pneumatic_servo.analysis.diagnosis.floor.Floor.test>` (one independent
unit per window and channel): a one-sided p-value of a departure upwards, and the ratio of
the window's RMS residual to the floor's. All windows of a batch, and all their copies, go
through a handful of batched simulations (:func:`judge_windows`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..analysis.diagnosis.data import noise_sigma
from ..analysis.diagnosis.floor import (PHASE_SAMPLES, RTOL_FACTORS, Floor, quantum,
                                         sensor_reading)
from ..experiment import Experiment
from ..model.assembly import Model
from ..model.config import ModelConfig
from ..model.simulate import DEFAULT_RTOL
from ..prediction import Plan, predict

#: judged channel -> measured signal (the interface topics' angle and chamber pressures)
CHANNELS = {'angle': 'angle_rad', 'p_a': 'p_a_pa', 'p_b': 'p_b_pa'}
#: SI unit of each judged channel
UNITS = {'angle': 'rad', 'p_a': 'Pa', 'p_b': 'Pa'}
#: [SI] resolution below which no sensor reads: a noise-free simulated signal, held still
#: by stiction, leaves exactly zero residual in a window and its copies alike
RESOLUTION = {'angle': 1e-6, 'p_a': 1.0, 'p_b': 1.0}
#: signals a window needs (besides the judged channels): the valve command drives the model
REQUIRED = ('command_v', 'angle_rad', 'p_a_pa', 'p_b_pa')
#: signals used when every sample of a batch has them (start states, supply input)
OPTIONAL = ('supply_pa', 't_a_k', 't_b_k')


@dataclass(frozen=True)
class Sensors:
    """What the rig's sensors add to a prediction's residual, per judged channel [SI]:
    white noise (1 sigma, without the quantisation) and the quantisation step (0: none)."""

    noise: dict
    quantum: dict

    @classmethod
    def measure(cls, signals: dict[str, np.ndarray]) -> 'Sensors':
        """Estimated from measured signals (robust second differences; the smallest step of
        a signal with few distinct values), as ``diagnose`` estimates a record's."""
        noise, step = {}, {}
        for ch, sig in CHANNELS.items():
            x = np.asarray(signals[sig], float)
            x = x[np.isfinite(x)]
            q = quantum(x)
            # a step at the float resolution is a signal at rest, not a quantiser
            q = q if q > 1e-9 * max(1.0, float(np.max(np.abs(x)))) else 0.0
            step[ch] = q
            noise[ch] = float(np.sqrt(max(noise_sigma(x) ** 2 - q ** 2 / 12.0, 0.0)))
        return cls(noise, step)

    def reading_variance(self, channel: str) -> float:
        """[SI^2] Variance of one reading: noise, quantisation and :data:`RESOLUTION`. It is
        added to every mean square before a test: a residual within one reading's own error
        is no departure (without it, copies that a quantiser leaves exactly zero would make
        one flickering encoder count at rest a departure)."""
        return (self.noise[channel] ** 2 + self.quantum[channel] ** 2 / 12.0
                + RESOLUTION[channel] ** 2)

    def to_dict(self) -> dict:
        return {'noise': dict(self.noise), 'quantum': dict(self.quantum)}

    @classmethod
    def from_dict(cls, data: dict) -> 'Sensors':
        return cls({ch: float(data['noise'][ch]) for ch in CHANNELS},
                   {ch: float(data['quantum'][ch]) for ch in CHANNELS})


@dataclass(frozen=True)
class Window:
    """One judged window: its first sample (index), and per channel
    the mean square residual [SI^2], the floor's mean square (the copies' mean) [SI^2], both
    with one reading's variance added (:meth:`Sensors.reading_variance`), the one-sided
    p-value of a departure upwards and the RMS ratio to the floor."""

    start: int
    mean_square: dict
    floor_mean_square: dict
    p_value: dict
    ratio: dict


@dataclass(frozen=True)
class Judged:
    """A batch of judged windows, with what the model predicted in them."""

    windows: list
    #: per window: (sample indices [absolute], {channel: predicted values [SI]})
    predictions: list


def _blocks(signals: dict, starts, before: int, win: int) -> dict:
    """The samples ``[a - before, a + win)`` of each window start ``a``, one after another."""
    idx = np.concatenate([np.arange(a - before, a + win) for a in starts])
    return {k: v[idx] for k, v in signals.items()}


def _plan(count: int, block: int, first: int, lead: int, dt: float) -> Plan:
    """Segments ``[first, block)`` of ``count`` consecutive blocks, each after a lead-in of
    ``lead`` samples."""
    return Plan(tuple((j * block + first, (j + 1) * block) for j in range(count)),
                lead_s=lead * dt)


def _mean_squares(pred: dict, measured: dict, count: int, block: int, first: int) -> dict:
    """Per channel, the mean square residual [SI^2] of each block's segment (its first
    sample, the measured start, left out)."""
    out = {}
    for ch, sig in CHANNELS.items():
        r = (pred[sig] - measured[sig]).reshape(count, block)[:, first + 1:]
        ms = np.mean(r ** 2, axis=1)
        out[ch] = np.where(np.isfinite(ms), ms, np.inf)
    return out


def judge_windows(model: Model, config: ModelConfig, signals: dict, starts, win: int,
                  lead: int, dt: float, sensors: Sensors, replicas: int,
                  rng: np.random.Generator, rtol: float = DEFAULT_RTOL, first: int = 0
                  ) -> Judged:
    """Judge the windows starting at ``starts`` (indices into ``signals``) of ``win``
    samples each; :attr:`Window.start` counts from ``first``.

    Parameters
    ----------
    model, config : Model, ModelConfig
        The compiled model and its values.
    signals : dict of str to ndarray
        Measured signals on a uniform grid of period ``dt`` [s] (SI); every window needs
        ``2 * lead`` samples before its start and ``win`` from it, all finite; and
        optionally ``command_alt_v``, the other candidate command where the pairing is
        uncertain (NaN elsewhere).
    win : int
        Samples per window, its start included: the horizon is ``(win - 1) dt``.
    lead : int
        Samples of lead-in before a prediction (and again before a copy's truth).
    sensors : Sensors
        Noise and quantisation the copies are measured with.
    replicas : int
        Copies of each window (the floor's sample size).
    """
    starts = list(starts)
    count, block = len(starts), 2 * lead + win
    data = _blocks(signals, starts, 2 * lead, win)
    alt = data.pop('command_alt_v', None)
    uncertain = np.flatnonzero(np.isfinite(alt)) if alt is not None else np.zeros(0, int)
    n = count * block
    t = np.arange(n) * dt
    exp = Experiment(t, data, 'servo', 'monitor window')
    plan = _plan(count, block, 2 * lead, lead, dt)
    pred = predict(model, exp, [config], plan, rtol=rtol)[0]
    actual = _mean_squares(pred, data, count, block, 2 * lead)

    # the copies: truth from the measured state a lead-in before each window
    truth_plan = _plan(count, block, lead, lead, dt)
    rtols = rtol * np.exp(rng.uniform(*np.log(RTOL_FACTORS), replicas))
    phases = rng.uniform(0.0, PHASE_SAMPLES, replicas)
    copies = {k: np.tile(v, replicas) for k, v in data.items()}
    mask = np.zeros(block, bool)
    mask[lead:] = True
    mask = np.tile(mask, count)
    for j in range(replicas):
        truth_exp = exp
        if len(uncertain):
            u = data['command_v'].copy()
            late = uncertain[rng.random(len(uncertain)) < 0.5]
            u[late] = alt[late]
            truth_exp = Experiment(t, {**data, 'command_v': u}, 'servo', 'monitor copy')
        truth = predict(model, truth_exp, [config], truth_plan, rtol=float(rtols[j]))[0]
        part = slice(j * n, (j + 1) * n)
        for ch, sig in CHANNELS.items():
            y = sensor_reading(truth[sig].reshape(count, block)[:, lead:], phases[j],
                               sensors.noise[ch], sensors.quantum[ch], rng)
            x = copies[sig][part]
            x[mask] = y.ravel()
    rep_exp = Experiment(np.arange(n * replicas) * dt, copies, 'servo', 'monitor copies')
    rep_pred = predict(model, rep_exp, [config], _plan(count * replicas, block, 2 * lead, lead,
                                                       dt), rtol=rtol)[0]
    floor = _mean_squares(rep_pred, copies, count * replicas, block, 2 * lead)

    eps = {ch: sensors.reading_variance(ch) for ch in CHANNELS}
    windows, predictions = [], []
    for i, a in enumerate(starts):
        ms_rep = {ch: np.minimum(floor[ch][i::count], 1e300) + eps[ch] for ch in CHANNELS}
        fl = Floor(ms_rep, np.sum(list(ms_rep.values()), axis=0), 1)
        p, ratio, ms, fms = {}, {}, {}, {}
        for ch in CHANNELS:
            fms[ch] = float(np.mean(ms_rep[ch]))
            ms[ch] = float(actual[ch][i]) + eps[ch]
            if np.isfinite(ms[ch]) and fms[ch] > 0:
                d = fl.test(ms[ch], ch)
                p[ch], ratio[ch] = d.p_value, d.ratio
            else:  # the model could not be simulated over this window
                p[ch], ratio[ch] = 0.0, float('inf')
        windows.append(Window(first + a, ms, fms, p, ratio))
        seg = slice(i * block + 2 * lead, (i + 1) * block)
        predictions.append((np.arange(a, a + win),
                            {ch: pred[sig][seg] for ch, sig in CHANNELS.items()}))
    return Judged(windows, predictions)
