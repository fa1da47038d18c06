"""Segment plans: which samples of a time series are predicted, and from where.

Every segment starts from the measured state at its first sample and is
predicted to its end. Three plans:

* :func:`open_loop`: one segment over the whole record; the model's
  measurement delay is applied to its outputs.
* :func:`windows`: fixed k-step windows every ``horizon_s`` (``compare``,
  ``verify``, output-error fits): the local view of an integrating actuator,
  whose open-loop angle error grows without bound from a small bias.
* :func:`quiet_starts`: windows about every ``horizon_s``, each started at the
  quietest sample nearby, with a lead-in for the unmeasured states
  (``diagnose``: the residual then shows the model, not the start state).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError
from ..experiment import Experiment
from ..smoothing import savgol_filter

#: [s] k-step horizon of ``compare``, ``verify`` and output-error fits
COMPARE_HORIZON_S = 0.2
#: [s] horizon of diagnosis segments: longer, because each starts at a quiet sample and a
#: slow effect (a leak) needs time to show within one segment
DIAGNOSIS_HORIZON_S = 0.25


@dataclass(frozen=True)
class Plan:
    """How a time series is predicted.

    Attributes
    ----------
    segments : tuple of (int, int)
        Sample ranges ``[first, stop)``, each predicted from the measured state
        at ``first``. Consecutive windows may share their boundary sample; the
        later segment's value is kept there.
    open_loop : bool
        The model's measurement delay delays the outputs (one run from the
        start); otherwise it is moved to the inputs (see
        :func:`~.inputs.valve_inputs`).
    smooth_start : bool
        Start states and the supply input from smoothed measurements
        (:func:`~.inputs.smoothed_signals`) instead of the raw samples.
    lead_s : float [s]
        Lead-in simulated before each segment to estimate the unmeasured states.
    """

    segments: tuple[tuple[int, int], ...]
    open_loop: bool = False
    smooth_start: bool = False
    lead_s: float = 0.0

    @property
    def index(self) -> np.ndarray:
        """Sample indices the plan predicts, each once, in order."""
        return np.unique(np.concatenate([np.arange(a, b) for a, b in self.segments]))

    def subset(self, segments) -> 'Plan':
        """The same plan over some of its segments."""
        return Plan(tuple(segments), self.open_loop, self.smooth_start, self.lead_s)


def open_loop(exp: Experiment) -> Plan:
    """The whole record from its first measured state."""
    return Plan(((0, len(exp.t)),), open_loop=True)


def check_horizon(horizon_s: float) -> float:
    """``horizon_s`` [s] if it is a finite positive number, else a ConfigError."""
    if not (isinstance(horizon_s, (int, float)) and np.isfinite(horizon_s) and horizon_s > 0):
        raise ConfigError(f'prediction horizon {horizon_s!r} s: give a positive number of '
                          'seconds, e.g. 0.2')
    return float(horizon_s)


def windows(exp: Experiment, horizon_s: float = COMPARE_HORIZON_S) -> Plan:
    """k-step windows of ``horizon_s`` [s], each starting on the last sample of the one before."""
    n = len(exp.t)
    win = max(2, int(round(check_horizon(horizon_s) / exp.dt)) + 1)
    if win >= n:
        return Plan(((0, n),))
    return Plan(tuple((k0, min(k0 + win, n)) for k0 in range(0, n - 1, win - 1)))


def _causal_mean(x: np.ndarray, m: int) -> np.ndarray:
    """Mean of the ``m`` samples before each sample (the first sample's value at the start)."""
    cs = np.concatenate([[0.0], np.cumsum(np.concatenate([np.full(m, x[0]), x]))])
    return (cs[m:m + len(x)] - cs[:len(x)]) / m


def _past_max(x: np.ndarray, m: int) -> np.ndarray:
    """Largest value of ``x`` over each sample and the ``m - 1`` before it."""
    padded = np.concatenate([np.full(m - 1, x[0]), x])
    return np.lib.stride_tricks.sliding_window_view(padded, m).max(axis=1)


def quietness(exp: Experiment, lookback_s: float = 0.02) -> np.ndarray:
    """How unsettled the rig is at each sample (0 = quiet), from measured signals only.

    Sums, each scaled by its own 90th percentile: the command's departure
    from its mean over the previous ``lookback_s`` (an effect-owned state such
    as the spool lags behind such a change, and the model cannot know it),
    the angular acceleration (the velocity estimate is worst there) and the
    chamber pressure rates over the last 5 ``lookback_s`` (the unmeasured gas
    temperature is off after a fast compression).
    """
    m = max(1, int(round(lookback_s / exp.dt)))
    features = []
    if 'command_v' in exp.signals:
        u = exp['command_v']
        features.append(_past_max(np.abs(u - _causal_mean(u, m)), m))
    if 'angle_rad' in exp.signals and len(exp.t) > 31:
        features.append(np.abs(savgol_filter(exp['angle_rad'], 31, 3, deriv=2, delta=exp.dt)))
    for sig in ('p_a_pa', 'p_b_pa'):
        if sig in exp.signals and len(exp.t) > 31:
            rate = np.abs(savgol_filter(exp[sig], 31, 2, deriv=1, delta=exp.dt))
            features.append(_past_max(rate, 5 * m))
    q = np.zeros(len(exp.t))
    for f in features:
        q += f / (np.percentile(f, 90) + 1e-12)
    return q


def quiet_starts(exp: Experiment, horizon_s: float = DIAGNOSIS_HORIZON_S,
                 lead_s: float = 0.0) -> Plan:
    """Segments about every ``horizon_s`` [s], each started at the quietest sample within a
    third of a horizon of its nominal place, and running to the next start.

    Starting where the rig is settled keeps the unmeasured parts of the start
    state (velocity, gas temperature, spool position) from dominating the
    residual. Start states come from smoothed measurements, after a lead-in of
    ``lead_s`` [s].
    """
    n = len(exp.t)
    h = max(2, int(round(check_horizon(horizon_s) / exp.dt)))
    starts = [0]
    if n > h:
        q = quietness(exp)
        reach = h // 3
        starts = []
        for nominal in range(0, n - reach, h):
            lo = max(nominal - reach, starts[-1] + reach if starts else 0)
            hi = min(nominal + reach + 1, n - reach)
            if hi > lo:
                starts.append(lo + int(np.argmin(q[lo:hi])))
    stops = starts[1:] + [n]
    return Plan(tuple(zip(starts, stops)), smooth_start=True, lead_s=lead_s)
