"""Residual tests: is the residual white, does it follow the input, and what does it move with?

For each compared channel the residual e = simulated - measured is tested for

* autocorrelation (a white residual means nothing systematic is left),
* cross-correlation with the valve command (a missing input dynamic, e.g.
  a delay or lag, shows as a peak at a lag),
* correlation with candidate regressors: velocity, its sign, the pressure
  difference, the valve opening and the chamber pressures.

Confidence bands are +/- 1.96 / sqrt(n_eff), where n_eff discounts the
autocorrelation of the series (Bartlett), so a smooth residual is not
declared significant just because it has many samples. :func:`summary`
turns the figures into a sentence: which equation the residual lives in
(moment balance or a chamber's mass balance) and what it moves with.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..experiment import CHANNELS, STATE_CHANNELS, Experiment, signal_of
from ..fitting.uncertainty import autocorrelation, effective_samples
from ..smoothing import savgol_filter

#: 95 % two-sided normal quantile
Z95 = 1.96
#: channel -> the equation whose error shows first in it
EQUATIONS = {ch: c.equation for ch, c in CHANNELS.items()}




def _corr(x: np.ndarray, y: np.ndarray) -> float:
    x, y = x - x.mean(), y - y.mean()
    d = np.sqrt(np.dot(x, x) * np.dot(y, y))
    return float(np.dot(x, y) / d) if d > 0 else 0.0


def cross_correlation(e: np.ndarray, u: np.ndarray, max_lag: int) -> np.ndarray:
    """Correlation of e(t) with u(t - lag) for lag = -max_lag..max_lag."""
    e, u = e - e.mean(), u - u.mean()
    d = np.sqrt(np.dot(e, e) * np.dot(u, u))
    if d == 0:
        return np.zeros(2 * max_lag + 1)
    n = len(e)
    out = []
    for lag in range(-max_lag, max_lag + 1):
        if lag >= 0:
            out.append(np.dot(e[lag:], u[:n - lag]))
        else:
            out.append(np.dot(e[:n + lag], u[-lag:]))
    return np.array(out) / d


def regressors(exp: Experiment, pred: dict | None = None, smooth_s: float = 0.025
               ) -> dict[str, np.ndarray]:
    """Candidate regressors [SI] a missing effect may move with.

    Velocity is the smoothed derivative of the measured angle (or the
    simulated velocity without one); the valve opening is command minus 5 V.
    """
    out = {}
    sig = exp.signals
    if 'angle_rad' in sig and not exp.static and len(exp.t) > 7:
        win = max(5, int(round(smooth_s / exp.dt)) | 1)
        vel = (savgol_filter(sig['angle_rad'], win, 2, deriv=1, delta=exp.dt)
               if len(exp.t) > win else np.gradient(sig['angle_rad'], exp.dt))
        out['velocity'] = vel
        out['sign(velocity)'] = np.sign(vel) * (np.abs(vel) > 0.02)
    elif pred is not None and 'velocity_rad_s' in pred and exp.circuit == 'servo':
        out['velocity'] = np.asarray(pred['velocity_rad_s'])
        out['sign(velocity)'] = np.sign(out['velocity'])
    elif not exp.static:  # pistons held (or no shaft): the velocity is zero
        out['velocity'] = out['sign(velocity)'] = np.zeros(len(exp.t))
    p_a = sig.get('p_a_pa', None if pred is None else pred.get('p_a_pa'))
    p_b = sig.get('p_b_pa', None if pred is None else pred.get('p_b_pa'))
    if p_a is not None and p_b is not None and exp.circuit in ('servo', 'blocked'):
        out['p_a - p_b'] = np.asarray(p_a) - np.asarray(p_b)
    if 'command_v' in sig:
        out['valve opening'] = sig['command_v'] - 5.0
    if p_a is not None:
        out['p_a'] = np.asarray(p_a)
    if p_b is not None and exp.circuit in ('servo', 'blocked'):
        out['p_b'] = np.asarray(p_b)
    return {k: v for k, v in out.items() if np.all(np.isfinite(v))}


@dataclass
class ChannelTests:
    """Residual tests of one channel."""

    channel: str
    rms: float
    lags_s: np.ndarray
    acf: np.ndarray
    acf_band: float
    xcorr_lags_s: np.ndarray
    xcorr: np.ndarray
    xcorr_band: float
    correlations: dict[str, float]
    bands: dict[str, float]
    whiteness: float = 0.0
    residual: np.ndarray = field(repr=False, default=None)

    @property
    def significant(self) -> dict[str, float]:
        """Regressors whose correlation lies outside its band, strongest first."""
        out = {k: r for k, r in self.correlations.items() if abs(r) > self.bands[k]}
        return dict(sorted(out.items(), key=lambda kv: -abs(kv[1])))

    @property
    def xcorr_peak(self) -> tuple[float, float]:
        """(lag [s], correlation) of the largest cross-correlation with the command."""
        i = int(np.argmax(np.abs(self.xcorr)))
        return float(self.xcorr_lags_s[i]), float(self.xcorr[i])

    def to_json(self) -> dict:
        lag, peak = self.xcorr_peak
        return {'rms': self.rms, 'acf_band': self.acf_band,
                'acf_outside_band': self.whiteness,
                'acf': {'lag_s': self.lags_s.tolist(), 'value': self.acf.tolist()},
                'xcorr_command': {'lag_s': self.xcorr_lags_s.tolist(),
                                  'value': self.xcorr.tolist(), 'band': self.xcorr_band,
                                  'peak_lag_s': lag, 'peak': peak},
                'correlations': {k: {'r': r, 'band': self.bands[k],
                                     'significant': abs(r) > self.bands[k]}
                                 for k, r in self.correlations.items()}}


def _pooled(experiments, predictions, channel):
    """Concatenated residual, command and regressors of one channel over experiments."""
    sig = signal_of(channel)
    e, u, regs, dts = [], [], {}, []
    for exp, pred in zip(experiments, predictions):
        if exp.static or sig not in exp.signals or sig not in pred:
            continue
        r = np.asarray(pred[sig]) - exp[sig]
        ok = np.isfinite(r)
        if ok.sum() < 10:
            continue
        e.append(r[ok])
        u.append(exp['command_v'][ok] if 'command_v' in exp.signals else np.zeros(ok.sum()))
        dts.append(exp.dt)
        for k, v in regressors(exp, pred).items():
            regs.setdefault(k, []).append(v[ok])
    if not e:
        return None
    n_exp = len(e)
    regs = {k: np.concatenate(v) for k, v in regs.items() if len(v) == n_exp}
    regs = {k: v for k, v in regs.items() if np.std(v) > 0}
    return np.concatenate(e), np.concatenate(u), regs, float(np.median(dts))


def channel_tests(experiments: list[Experiment], predictions: list[dict], channel: str,
                  max_lag_s: float = 0.2) -> ChannelTests | None:
    """Residual tests of ``channel`` ('angle', 'p_a', 'p_b') pooled over experiments.

    Parameters
    ----------
    experiments, predictions : list
        Measured experiments and the simulated signals on their time bases.
    channel : str
        Compared channel.
    max_lag_s : float [s]
        Largest lag of the auto- and cross-correlations.

    Returns
    -------
    ChannelTests or None
        None when no time series measures the channel.
    """
    pooled = _pooled(experiments, predictions, channel)
    if pooled is None:
        return None
    e, u, regs, dt = pooled
    n = len(e)
    max_lag = max(1, min(int(round(max_lag_s / dt)), n // 4))
    acf = autocorrelation(e, max_lag)
    band = Z95 / np.sqrt(n)
    xc = cross_correlation(e, u, max_lag)
    corrs = {k: _corr(e, v) for k, v in regs.items()}
    bands = {k: Z95 / np.sqrt(effective_samples(e, v)) for k, v in regs.items()}
    lags = np.arange(max_lag + 1) * dt
    return ChannelTests(channel, float(np.sqrt(np.mean(e ** 2))), lags, acf, band,
                        np.arange(-max_lag, max_lag + 1) * dt, xc,
                        Z95 / np.sqrt(effective_samples(e, u)), corrs, bands,
                        float(np.mean(np.abs(acf[1:]) > band)), e)


def residual_tests(experiments: list[Experiment], predictions: list[dict],
                   channels=STATE_CHANNELS, max_lag_s: float = 0.2
                   ) -> dict[str, ChannelTests]:
    """:func:`channel_tests` for every channel some experiment measures."""
    out = {}
    for ch in channels:
        tests = channel_tests(experiments, predictions, ch, max_lag_s)
        if tests is not None:
            out[ch] = tests
    return out


def _normalised_rms(experiments, predictions, channel) -> float:
    sig = signal_of(channel)
    vals = []
    for exp, pred in zip(experiments, predictions):
        if sig in exp.signals and sig in pred:
            r = (np.asarray(pred[sig]) - exp[sig]) / max(float(np.nanstd(exp[sig])), 1e-12)
            vals.append(r[np.isfinite(r)])
    return float(np.sqrt(np.mean(np.concatenate(vals) ** 2))) if vals else float('nan')


def volume_explained(experiments, predictions, config=None) -> dict[str, float]:
    """Share of each chamber's pressure residual that the angle residual explains through
    the chamber volume (dp = -k p/V dV, dV = +/- A d_f d theta, k fitted).

    A moment-balance error moves the shaft, and the chambers' pressures
    follow the volume change; a mass-balance error changes a pressure
    directly. A high share therefore puts the residual in the moment balance.
    """
    from ..model.config import ModelConfig
    core = (config or ModelConfig.paper()).core
    swept = core['piston_area_m2'] * core['pinion_pitch_diameter_m']
    out = {}
    for ch, sign in (('p_a', -1.0), ('p_b', 1.0)):
        x_all, y_all = [], []
        for exp, pred in zip(experiments, predictions):
            sig = signal_of(ch)
            if exp.circuit != 'servo' or sig not in exp.signals or 'angle_rad' not in pred:
                continue
            theta = np.clip(exp['angle_rad'], 0.0, core['stroke_rad'])
            vol = (core['dead_volume_a_m3'] + swept * theta if ch == 'p_a' else
                   core['dead_volume_b_m3'] + swept * (core['stroke_rad'] - theta))
            e_p = np.asarray(pred[sig]) - exp[sig]
            e_th = np.asarray(pred['angle_rad']) - exp['angle_rad']
            ok = np.isfinite(e_p) & np.isfinite(e_th)
            x_all.append((sign * exp[sig] / vol * swept * e_th)[ok])
            y_all.append(e_p[ok])
        if not x_all:
            continue
        x, y = np.concatenate(x_all), np.concatenate(y_all)
        if not np.any(x) or not np.any(y):
            continue
        k = max(float(x @ y / (x @ x)), 0.0)
        out[ch] = float(max(0.0, 1.0 - np.sum((y - k * x) ** 2) / np.sum(y ** 2)))
    return out


def summary(experiments: list[Experiment], predictions: list[dict],
            tests: dict[str, ChannelTests] | None = None, config=None) -> dict:
    """Which equation the residual lives in and what it moves with.

    If the angle residual, through the chamber volumes, explains most of
    the pressure residuals (:func:`volume_explained`), the error is in the
    moment balance; otherwise it is in the mass balance of the chamber whose
    unexplained pressure residual is larger (both, if comparable). The
    regressors are those outside their bands in that channel, strongest first.

    Returns
    -------
    dict
        ``equation``, ``channel``, ``relative_rms`` (per channel),
        ``volume_explained``, ``white``, ``moves_with`` (regressor ->
        correlation), ``command_lag_s`` and a one-line ``text``.
    """
    tests = tests if tests is not None else residual_tests(experiments, predictions)
    rel = {ch: _normalised_rms(experiments, predictions, ch) for ch in tests}
    rel = {ch: v for ch, v in rel.items() if np.isfinite(v)}
    if not rel:
        return {'equation': 'unknown', 'text': 'no time series to test'}
    explained = volume_explained(experiments, predictions, config)
    pressures = [ch for ch in ('p_a', 'p_b') if ch in rel]
    if 'angle' in rel and explained and min(explained.values()) >= 0.5:
        worst, equation = 'angle', EQUATIONS['angle']
    elif pressures:
        left = {ch: rel[ch] * np.sqrt(1.0 - explained.get(ch, 0.0)) for ch in pressures}
        worst = max(left, key=left.get)
        other = [ch for ch in left if ch != worst]
        equation = EQUATIONS[worst]
        if other and left[other[0]] > 0.6 * left[worst]:
            equation = 'mass balance of both chambers'
    else:
        worst = max(rel, key=rel.get)
        equation = EQUATIONS.get(worst, worst)
    t = tests[worst]
    moves = t.significant
    lag, peak = t.xcorr_peak
    white = t.whiteness < 0.1
    text = f'the residual lives in the {equation}'
    if explained:
        text += (' (the angle error explains ' + ', '.join(
            f'{100 * v:.0f} % of the {ch} error' for ch, v in explained.items()) + ')')
    if moves:
        top = ', '.join(f'{k} (r = {r:+.2f})' for k, r in list(moves.items())[:3])
        text += f'; its {worst} residual moves with {top}'
    at_edge = abs(lag) >= t.xcorr_lags_s[-1] - 1e-9  # a peak at the window's end: no lag found
    if abs(peak) > t.xcorr_band and not at_edge:
        text += f'; it follows the command at a lag of {1000 * lag:.0f} ms (r = {peak:+.2f})'
    elif abs(peak) > t.xcorr_band:
        text += (f'; it correlates with the command (r = {peak:+.2f}) but at no lag within '
                 f'+/- {1000 * t.xcorr_lags_s[-1]:.0f} ms')
    if white:
        text += '; it is close to white (little left to explain)'
    return {'equation': equation, 'channel': worst, 'relative_rms': rel,
            'volume_explained': explained, 'white': white, 'moves_with': moves,
            'command_lag_s': lag, 'command_peak': peak, 'text': text}
