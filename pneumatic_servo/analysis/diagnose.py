"""Which physical effect is missing: add each candidate, fit it, score it on held-out data.

For every candidate effect (the catalogue and any user-registered effect),
the model is extended with it, the effect's ``fit=True`` parameters (plus
any base parameters the user frees, plus the effects already in the model)
are fitted by output error on one part of the data, and the extended model
is scored on the other part. Candidates are ranked by the validated fall of
the residual, penalised by an information criterion (BIC) for the
parameters they add. An effect is the verdict only if it earns its place:
a real fall of the held-out residual, a clear BIC gain, an explained error
well above the sensor noise, and physically plausible fitted values.
Otherwise the verdict is ``'none'``, so that clean data raise no alarm.

How the residual is formed (each choice is explained where it is made):

* **k-step segments.** The actuator integrates, so open-loop errors grow
  without bound; every ``horizon_s`` the model restarts from the measured
  state, at the quietest sample nearby (:func:`segment_starts`), with the
  unmeasured states (gas temperature, spool position) from a short lead-in
  simulation (:func:`predict_segments`).
* **Split.** Alternate blocks of segments are fitted and held out; table
  rows alternate.
* **Scaling and smoothing.** Channels are normalised by their measured
  spread; time-series residuals are smoothed over ``smooth_s``.
* **Fitting.** A coarse grid screens every candidate; the best few get a
  bracket search and Levenberg-Marquardt (:func:`fit_parameters`), all
  simulations of a step in one parallel batch. Compositions are shared
  where an effect can be switched off by value (:func:`shared_host`), since
  each compiles in seconds.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.signal import savgol_filter

from .. import effects as registry
from ..effects.layout import OMEGA, P_A, P_B, THETA
from ..errors import ConfigError, ExperimentError
from ..experiment import Experiment
from ..identification.output_error import FIT_CHANNELS, channel_scales
from ..identification.predict import STATE_SIGNALS, predict_many
from ..model.assembly import Model
from ..model.config import ModelConfig
from ..model.simulate import initial_state, simulate_batch
from .regimes import error_shares, hot_spots
from .residuals import effective_samples, residual_tests, summary

#: a fall of the held-out residual below this fraction never names an effect
MIN_REDUCTION = 0.2
#: information-criterion gain (BIC, lower is better) an effect must reach
MIN_DELTA_BIC = -10.0
#: an effect must explain a held-out error this many times the sensor noise (as it is
#: left in the smoothed residual)
MIN_NOISE_RATIO = 3.0
#: two candidates whose held-out residuals differ by less than this fraction explain
#: the data about equally
AMBIGUITY = 0.05
#: fit tolerances: relative parameter step and relative cost fall that end the fit; far
#: below what the held-out comparison can resolve
XTOL, FTOL = 1e-3, 1e-4
#: finite-difference step of the Jacobian, relative to a parameter's size: large enough
#: to step over the small-scale roughness that stick-slip gives the fit cost
FD_STEP = 1e-2
#: a failed simulation contributes this normalised residual (a very poor fit, not a crash)
FAILED_RESIDUAL = 1e3


# --------------------------------------------------------------------------- options
@dataclass
class DiagnoseOptions:
    """How candidates are fitted and scored.

    Attributes
    ----------
    horizon_s : float [s]
        Length of the prediction segments, each started from the measured
        state (k-step-ahead prediction).
    lead_s : float [s]
        Lead-in simulated before each segment to estimate the states that
        are not measured (gas temperatures, effect states).
    smooth_s : float [s]
        Width of the centred moving average applied to time-series residuals.
    blocks : int
        Each time series is cut into this many blocks, alternately used for
        fitting and for validation.
    decimate : int
        Keep every n-th sample (command averaged over the n) when fitting and
        scoring: simulation cost is set by the number of input intervals.
    max_iter : int
        Levenberg-Marquardt iterations per candidate.
    refit_present : bool
        Refit the effects already in the model with every candidate (and for
        the baseline): an effect found in an earlier round absorbed what it
        could of the effects not yet found.
    full_fits : int
        Candidates fitted in full: those whose best point of the coarse
        parameter grid fits best. The others are scored at that grid point
        (a screen; raise this to fit every candidate).
    min_reduction : float
        Smallest held-out residual fall (fraction) that can name an effect.
    min_delta_bic : float
        BIC change an effect must reach (negative: lower is better).
    min_noise_ratio : float
        The held-out error an effect explains must be this many times the
        sensor noise (both as normalised RMS).
    ambiguity : float
        Relative difference of held-out residuals below which two effects tie.
    """

    horizon_s: float = 0.25
    lead_s: float = 0.1
    smooth_s: float = 0.01
    blocks: int = 4
    decimate: int = 1
    max_iter: int = 6
    full_fits: int = 4
    refit_present: bool = True
    min_reduction: float = MIN_REDUCTION
    min_delta_bic: float = MIN_DELTA_BIC
    min_noise_ratio: float = MIN_NOISE_RATIO
    ambiguity: float = AMBIGUITY


# ------------------------------------------------------------------------ data split
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


def _causal_mean(x: np.ndarray, m: int) -> np.ndarray:
    """Mean of the ``m`` samples before each sample (the first sample's value at the start)."""
    cs = np.concatenate([[0.0], np.cumsum(np.concatenate([np.full(m, x[0]), x]))])
    return (cs[m:m + len(x)] - cs[:len(x)]) / m


def _past_max(x: np.ndarray, m: int) -> np.ndarray:
    """Largest value of ``x`` over each sample and the ``m - 1`` before it."""
    padded = np.concatenate([np.full(m - 1, x[0]), x])
    return np.lib.stride_tricks.sliding_window_view(padded, m).max(axis=1)


def _width(smooth_s: float, dt: float) -> int:
    """Odd number of samples of a moving average over ``smooth_s`` [s]."""
    return int(round(smooth_s / dt)) | 1


def smooth(x: np.ndarray, width: int) -> np.ndarray:
    """Centred moving average over ``width`` samples (fewer at the ends); no delay."""
    if width <= 1 or len(x) < 2:
        return x
    kernel = np.ones(width)
    return (np.convolve(x, kernel, 'same') / np.convolve(np.ones(len(x)), kernel, 'same'))


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


def segment_starts(exp: Experiment, horizon_s: float) -> list[int]:
    """Start samples of the prediction segments: about every ``horizon_s``, each moved to
    the quietest sample within a third of a horizon of its nominal place.

    Every segment starts from the measured state; starting where the rig is
    settled keeps the unmeasured parts of that state (velocity, gas
    temperature, spool position) from dominating the residual.
    """
    n = len(exp.t)
    h = max(2, int(round(horizon_s / exp.dt)))
    if n <= h:
        return [0]
    q = quietness(exp)
    reach = h // 3
    starts = []
    for nominal in range(0, n - reach, h):
        lo = max(nominal - reach, starts[-1] + reach if starts else 0)
        hi = min(nominal + reach + 1, n - reach)
        if hi > lo:
            starts.append(lo + int(np.argmin(q[lo:hi])))
    return starts


@dataclass
class Part:
    """Segments of one experiment (or rows of a table) with the spread [SI] of each channel.

    ``segments`` are (first, stop) sample ranges predicted from the
    measured state at ``first``; None for a static table (``exp`` holds the rows).
    """

    exp: Experiment
    scales: dict[str, float]
    segments: list[tuple[int, int]] | None = None
    init: dict | None = None
    lead_s: float = 0.0

    def measured(self, sig: str) -> np.ndarray:
        if self.segments is None:
            return self.exp[sig]
        return np.concatenate([self.exp[sig][a:b] for a, b in self.segments])

    @property
    def lengths(self) -> list[int]:
        return [b - a for a, b in self.segments]


def split(exp: Experiment, scales: dict, options: 'DiagnoseOptions') -> tuple[Part, Part]:
    """(fit part, validation part) of one experiment.

    Tables alternate rows. Time series are cut into segments (see
    :func:`segment_starts`); whole blocks of segments alternate between
    fitting and validation, so the validation data are not interleaved with
    the fitted samples.
    """
    if exp.static:
        idx = np.arange(len(exp.t))
        return (Part(_rows(exp, idx % 2 == 0, f'{exp.name}[fit]'), scales),
                Part(_rows(exp, idx % 2 == 1, f'{exp.name}[val]'), scales))
    starts = segment_starts(exp, options.horizon_s)
    init = initial_signals(exp)
    stops = starts[1:] + [len(exp.t)]
    block = len(exp.t) / options.blocks
    fit, val = [], []
    for a, b in zip(starts, stops):
        (fit if int(a // block) % 2 == 0 else val).append((a, b))
    if not val or not fit:  # too short for blocks: alternate segments
        segs = list(zip(starts, stops))
        fit, val = segs[0::2], segs[1::2] or segs[:1]
    lead = options.lead_s
    return Part(exp, scales, fit, init, lead), Part(exp, scales, val, init, lead)


@dataclass
class Data:
    """Experiments prepared and split for diagnosis."""

    experiments: list[Experiment]
    fit: list[Part]
    val: list[Part]
    #: width [s] of the moving average applied to time-series residuals
    smooth_s: float = 0.0

    @property
    def noise(self) -> float:
        """Sensor noise in the validation residuals, pooled and normalised like
        :class:`Score`: a robust estimate from second differences (sigma = 1.4826 MAD /
        sqrt(6)), divided by the square root of the smoothing width, as the residuals
        are smoothed."""
        total, count = 0.0, 0
        for part in self.val:
            width = 1 if part.segments is None else _width(self.smooth_s, part.exp.dt)
            for ch in part.scales:
                x = part.measured(FIT_CHANNELS[ch][0])
                if len(x) < 5:
                    continue
                d2 = x[2:] - 2.0 * x[1:-1] + x[:-2]
                sigma = 1.4826 * float(np.median(np.abs(d2 - np.median(d2)))) / np.sqrt(6.0)
                total += len(x) * (sigma / part.scales[ch]) ** 2 / width
                count += len(x)
        return float(np.sqrt(total / count)) if count else 0.0

    @property
    def independent(self) -> int:
        """Validation segments (or table rows) times their channels."""
        return sum((len(p.segments) if p.segments is not None else len(p.exp.t))
                   * len(p.scales) for p in self.val)

    @classmethod
    def of(cls, experiments: list[Experiment], options: 'DiagnoseOptions') -> 'Data':
        """Prepare ``experiments``: decimation, smoothing, fit/validation split.

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
                                      f'{", ".join(FIT_CHANNELS)}; nothing to compare with')
            if not exp.static and 'command_v' not in exp.signals:
                raise ExperimentError(f'{exp.name or "experiment"}: no valve command recorded; '
                                      'record valve/command')
            exp = decimate(exp, options.decimate)
            prepared.append(exp)
            f, v = split(exp, scales, options)
            fit.append(f)
            val.append(v)
        return cls(prepared, fit, val, options.smooth_s)


# -------------------------------------------------------------------------- prediction
def _supply_input(ps: np.ndarray, win: int) -> np.ndarray:
    """The measured supply as the model's input: its median if it only shows sensor noise,
    else lightly smoothed.

    Sensor noise fed into the valve flows would perturb the stick-slip events
    of the prediction and so the residual, differently for every candidate.
    """
    noise = float(np.std(np.diff(ps))) / np.sqrt(2.0)
    slow = savgol_filter(ps, 5 * win | 1, 2) if len(ps) > 5 * win else ps
    if np.percentile(slow, 99) - np.percentile(slow, 1) < 5.0 * noise:
        return np.full(len(ps), float(np.median(ps)))
    return savgol_filter(ps, max(5, (win // 2) | 1), 2)


def initial_signals(exp: Experiment, window_s: float = 0.021) -> dict[str, np.ndarray]:
    """Measured signals smoothed (Savitzky-Golay, no delay) for starting predictions and
    for the measured supply input.

    A segment starts from one sample of the measurements, and sensor noise in
    that sample would persist through the whole segment; noise on the measured
    supply would be fed into the valve flows. The velocity is always the
    centred estimate from the angle: a recorded encoder velocity is usually a
    causal difference that lags.
    """
    out = dict(exp.signals)
    if exp.static:
        return out
    win = max(5, int(round(window_s / exp.dt)) | 1)
    if len(exp.t) <= win:
        return out
    for name in ('angle_rad', 'p_a_pa', 'p_b_pa'):
        if name in out:
            out[name] = savgol_filter(out[name], win, 2)
    if 'supply_pa' in out:
        out['supply_pa'] = _supply_input(out['supply_pa'], win)
    if 'angle_rad' in exp.signals:
        out['velocity_rad_s'] = savgol_filter(exp['angle_rad'], win, 2, deriv=1, delta=exp.dt)
    return out


def measured_state(model: Model, cfg: ModelConfig, exp: Experiment, k: int,
                   command_v: float, supply_pa: float, sig: dict | None = None) -> np.ndarray:
    """State vector from the measurements at sample ``k`` (``sig``, default the raw
    signals of ``exp``); the rest from defaults."""
    sig = exp.signals if sig is None else sig
    get = (lambda name: float(sig[name][k]) if name in sig else None)
    angle = get('angle_rad') if exp.circuit == 'servo' else cfg.core['blocked_angle_rad']
    return initial_state(model, angle_rad=angle, p_a_pa=get('p_a_pa'),
                         p_b_pa=get('p_b_pa'), t_a_k=get('t_a_k'), t_b_k=get('t_b_k'),
                         velocity_rad_s=get('velocity_rad_s') or 0.0, command_v=command_v,
                         supply_pa=supply_pa, config=cfg)


#: states reset to the measurements at a segment start, by circuit, with their signals
_MEASURED = {'servo': ((THETA, 'angle_rad'), (OMEGA, 'angle_rad'), (P_A, 'p_a_pa'),
                       (P_B, 'p_b_pa')),
             'blocked': ((P_A, 'p_a_pa'), (P_B, 'p_b_pa'))}


def _windows(win: int, segs, arrays_by_cfg) -> np.ndarray:
    """Stack per-config input arrays into (rows, win) windows starting at each ``segs`` index,
    padded with their last value."""
    out = []
    for arr in arrays_by_cfg:
        for a, b in segs:
            w = np.full(win, arr[b - 1])
            w[:b - a] = arr[a:b]
            out.append(w)
    return np.array(out)


def predict_segments(model: Model, exp: Experiment, configs: list[ModelConfig],
                     segments: list[tuple[int, int]], init: dict | None = None,
                     lead_s: float = 0.0) -> list[dict[str, np.ndarray]]:
    """Predicted signals over ``segments`` of ``exp`` for each config, in parallel batches.

    Each segment starts from the measured state at its first sample. What is
    not measured there (gas temperatures, states of effects such as the spool
    position) is taken from a lead-in simulation of the ``lead_s`` [s] before
    the segment, itself started from the measurements; the measured states
    are then reset to the measurements. A measurement delay d is applied as
    a delay of the inputs: the measured state at t is the physical state at
    t - d, which evolved under the inputs of time t - d (delaying the outputs
    instead would drop the first d of motion of every segment).

    Returns, per config, signal -> array over the concatenated segment
    samples; NaN where a simulation failed.
    """
    t = exp.t
    u = exp['command_v']
    ps = (init or exp.signals).get('supply_pa')
    if ps is None:
        ps = np.full(len(t), configs[0].core['supply_pressure_pa'])
    win = max(b - a for a, b in segments)
    # a blocked record says where the pistons were held (bag custom data)
    held = exp.metadata.get('blocked_angle_rad') if exp.circuit == 'blocked' else None
    cfgs, us, pss, params = [], [], [], []
    for cfg in configs:
        if held is not None:
            cfg = cfg.copy()
            cfg.core['blocked_angle_rad'] = float(held)
        d_in, d_out = model.delays(cfg)
        cfgs.append(cfg)
        us.append(np.interp(t - d_in - d_out, t, u) if d_in + d_out > 0 else u)
        pss.append(np.interp(t - d_out, t, ps) if d_out > 0 else ps)
        params.append(model.param_vector(cfg))
    starts = _lead_in(model, exp, cfgs, us, pss, params, segments, init, lead_s)
    P = np.repeat(np.array(params), len(segments), axis=0)
    XB, _, status = simulate_batch(model, t[:win] - t[0], _windows(win, segments, us),
                                   _windows(win, segments, pss), starts, P, exp.circuit)
    out, per = [], len(segments)
    for j in range(len(configs)):
        block = slice(j * per, (j + 1) * per)
        X = np.concatenate([XB[r, :b - a] for r, (a, b) in
                            zip(range(block.start, block.stop), segments)])
        if np.any(status[block] != 0):
            X = np.full_like(X, np.nan)
        out.append({name: X[:, idx] for name, idx in STATE_SIGNALS.items()})
    return out


def _lead_in(model, exp, cfgs, us, pss, params, segments, init, lead_s) -> np.ndarray:
    """Start states of every (config, segment): measured, with the unmeasured ones from a
    lead-in simulation where the record leaves room for one."""
    lead = int(round(lead_s / exp.dt))
    measured = [measured_state(model, cfg, exp, a, u[a], ps[a], init)
                for cfg, u, ps in zip(cfgs, us, pss) for a, _ in segments]
    X0 = np.array(measured)
    if lead < 2 or exp.circuit not in _MEASURED:
        return X0
    pre = [(max(a - lead, 0), a + 1) for a, _ in segments]
    if all(b - a < 3 for a, b in pre):
        return X0
    L0 = np.array([measured_state(model, cfg, exp, a, u[a], ps[a], init)
                   for cfg, u, ps in zip(cfgs, us, pss) for a, _ in pre])
    P = np.repeat(np.array(params), len(segments), axis=0)
    XB, _, status = simulate_batch(model, exp.t[:lead + 1] - exp.t[0],
                                   _windows(lead + 1, pre, us),
                                   _windows(lead + 1, pre, pss), L0, P, exp.circuit)
    keep = [i for i, sig in _MEASURED[exp.circuit] if sig in exp.signals]
    for r, (a, b) in enumerate(pre * len(cfgs)):
        if b - a >= 3 and status[r] == 0:
            x = XB[r, b - a - 1].copy()
            x[keep] = X0[r, keep]
            X0[r] = x
    return X0


def _predict_part(model: Model, part: Part, configs: list[ModelConfig]) -> list[dict]:
    if part.segments is None:
        return predict_many(model, part.exp, configs)
    return predict_segments(model, part.exp, configs, part.segments, part.init,
                            part.lead_s)


def predictions(config: ModelConfig, data: 'Data') -> list[dict[str, np.ndarray]]:
    """Predicted signals of every prepared experiment on its own time base, segment by
    segment (NaN before the first segment); static tables row by row."""
    host = shared_host(config)
    model = Model(host)
    out = []
    for exp, fit, val in zip(data.experiments, data.fit, data.val):
        if exp.static:
            out.append(predict_many(model, exp, [host])[0])
            continue
        segs = sorted(fit.segments + val.segments)
        pred = predict_segments(model, exp, [host], segs, fit.init, fit.lead_s)[0]
        idx = np.concatenate([np.arange(a, b) for a, b in segs])
        full = {}
        for name, values in pred.items():
            full[name] = np.full(len(exp.t), np.nan)
            full[name][idx] = values
        out.append(full)
    return out


# -------------------------------------------------------------------------- residuals
def residual_rows(model: Model, parts: list[Part], configs: list[ModelConfig],
                  options: DiagnoseOptions) -> list[dict[str, np.ndarray]]:
    """Normalised residuals (prediction - measurement) / spread, per config and channel.

    All configs (one composition) are simulated together, in parallel.
    """
    rows: list[dict[str, list]] = [dict() for _ in configs]
    for part in parts:
        preds = _predict_part(model, part, configs)
        width = 1 if part.segments is None else _width(options.smooth_s, part.exp.dt)
        for j, pred in enumerate(preds):
            for ch, scale in part.scales.items():
                sig = FIT_CHANNELS[ch][0]
                r = (pred[sig] - part.measured(sig)) / scale
                r = np.where(np.isfinite(r), r, FAILED_RESIDUAL)
                if width > 1:
                    r = np.concatenate([smooth(piece, width) for piece in
                                        np.split(r, np.cumsum(part.lengths)[:-1])])
                rows[j].setdefault(ch, []).append(r)
    return [{ch: np.concatenate(v) for ch, v in row.items()} for row in rows]


def _stack(row: dict[str, np.ndarray]) -> np.ndarray:
    return np.concatenate(list(row.values()))


@dataclass
class Score:
    """Held-out residual of one model: normalised RMS per channel and overall."""

    channels: dict[str, float]
    overall: float
    #: pooled normalised residual vector (for the information criterion)
    residual: np.ndarray = field(repr=False, default=None)

    @classmethod
    def of(cls, row: dict[str, np.ndarray]) -> 'Score':
        pooled = _stack(row)
        return cls({ch: float(np.sqrt(np.mean(r ** 2))) for ch, r in row.items()},
                   float(np.sqrt(np.mean(pooled ** 2))), pooled)

    def to_json(self) -> dict:
        return {'overall': self.overall, 'channels': dict(self.channels)}


def score_many(model: Model, data: Data, configs: list[ModelConfig],
               options: DiagnoseOptions) -> list[Score]:
    """Held-out scores of several configs of one composition."""
    return [Score.of(row) for row in residual_rows(model, data.val, configs, options)]


def information_criteria(base: Score, cand: Score, k: int, n_eff: float
                         ) -> tuple[float, float]:
    """(delta AIC, delta BIC) of a candidate adding ``k`` parameters, on ``n_eff`` samples.

    Gaussian likelihood on the held-out residual: n ln(RSS_1/RSS_0) plus the
    penalty; ``n_eff`` discounts the residual's autocorrelation, without
    which any tiny improvement on thousands of samples looks significant.
    """
    ratio = max(cand.overall, 1e-300) ** 2 / max(base.overall, 1e-300) ** 2
    fit_term = n_eff * math.log(ratio)
    return fit_term + 2.0 * k, fit_term + k * math.log(n_eff)


# -------------------------------------------------------------------------- fitting
@dataclass
class Fit:
    """Fitted values [SI] with standard errors, correlation and the fit-set cost."""

    config: ModelConfig
    values: dict[str, float]
    stderr: dict[str, float]
    correlation: np.ndarray
    cost: float
    at_bound: list[str]
    converged: bool
    evaluations: int


def _with_values(config: ModelConfig, keys: list[str], x) -> ModelConfig:
    cfg = config.copy()
    for key, v in zip(keys, x):
        cfg.set(key, float(v))
    return cfg


class _Problem:
    """Fit-set residuals of parameter vectors, many evaluated in one parallel batch."""

    def __init__(self, model, config, keys, data, options):
        self.model, self.config, self.keys = model, config, keys
        self.data, self.options = data, options
        params = [config.param(k) for k in keys]
        self.lo = np.array([p.lower for p in params])
        self.hi = np.array([p.upper for p in params])
        x0 = np.array([config.get(k) for k in keys])
        #: the size of a parameter: its plausible extent, or its value if larger
        self.span = np.array([max(abs(a) for a in p.plausible_range()) or 1.0 for p in params])
        self.scale = np.maximum(np.abs(x0), 0.01 * self.span)
        self.evaluations = 0

    def rows(self, xs) -> list[np.ndarray]:
        """Residual vectors of several parameter vectors (one batch)."""
        configs = [_with_values(self.config, self.keys, x) for x in xs]
        self.evaluations += len(xs)
        return [_stack(r) for r in residual_rows(self.model, self.data.fit, configs,
                                                  self.options)]

    def costs(self, xs) -> np.ndarray:
        return np.array([float(r @ r) for r in self.rows(xs)])

    def probes(self, x, rel: float):
        out = [x]
        for i in range(len(x)):
            xi = x.copy()
            h = rel * self.scale[i]
            # step away from the nearer bound so the probe stays feasible
            xi[i] = x[i] + h if x[i] + h <= self.hi[i] else x[i] - h
            out.append(xi)
        return out

    def evaluate(self, x, rel: float = FD_STEP):
        """(residual vector, Jacobian) at ``x``: one parallel batch of 1 + p simulations."""
        sets = self.probes(x, rel)
        rows = self.rows(sets)
        r0 = rows[0]
        jac = np.column_stack([(rows[i + 1] - r0) / (sets[i + 1][i] - x[i])
                               for i in range(len(x))])
        return r0, jac


def _bracket_search(prob: _Problem, x: np.ndarray, cost: float, rounds: int = 3,
                    points: int = 7) -> tuple[np.ndarray, float]:
    """Shrinking-bracket search along each parameter in turn, each round one batch.

    Stick-slip and end stops make the fit cost rough on small scales, so a
    local gradient can point the wrong way; trying a spread of values and
    narrowing around the best is robust to that and still cheap in batches.
    """
    x = x.copy()
    for i in range(len(x)):
        half = max(0.5 * abs(x[i]), 0.05 * prob.span[i])
        for _ in range(rounds):
            vals = np.unique(np.clip(x[i] + half * np.linspace(-1.0, 1.0, points),
                                     prob.lo[i], prob.hi[i]))
            trials = [np.where(np.arange(len(x)) == i, v, x) for v in vals]
            c = prob.costs(trials)
            j = int(np.argmin(c))
            if c[j] < cost:
                x, cost = trials[j], float(c[j])
            half *= 0.35
    return x, cost


def fit_parameters(model: Model, config: ModelConfig, keys: list[str], data: Data,
                   options: DiagnoseOptions) -> Fit:
    """Fit ``keys`` of ``config`` on the fit parts: bracket search, then Levenberg-Marquardt.

    The bracket search (:func:`_bracket_search`) finds the basin; bounded
    Levenberg-Marquardt polishes it, each iteration simulating the trial point
    with its finite-difference probes in one parallel batch. Standard errors
    are sigma^2 (J'J)^-1, inflated by n / n_eff for the residual's
    autocorrelation.
    """
    prob = _Problem(model, config, keys, data, options)
    x = np.clip([config.get(k) for k in keys], prob.lo, prob.hi).astype(float)
    x, _ = _bracket_search(prob, x, float(prob.costs([x])[0]))
    r, jac = prob.evaluate(x)
    cost, lam, converged = float(r @ r), 1e-2, False
    for _ in range(options.max_iter):
        js = jac * prob.scale
        a, g = js.T @ js, js.T @ r
        step = -np.linalg.solve(a + lam * np.diag(np.diag(a) + 1e-12), g) * prob.scale
        x_new = np.clip(x + step, prob.lo, prob.hi)
        if np.all(np.abs(x_new - x) <= XTOL * prob.scale):
            converged = True
            break
        r_new, jac_new = prob.evaluate(x_new)
        cost_new = float(r_new @ r_new)
        if cost_new < cost:
            done = cost - cost_new < FTOL * cost
            x, r, jac, cost, lam = x_new, r_new, jac_new, cost_new, lam / 5.0
            if done:
                converged = True
                break
        else:
            lam *= 8.0
    return _finish(prob, x, r, jac, cost, converged)


def _finish(prob: _Problem, x, r, jac, cost, converged) -> Fit:
    n, p = len(r), len(x)
    inflate = n / effective_samples(r)
    cov = cost / max(n - p, 1) * inflate * np.linalg.pinv(jac.T @ jac)
    sd = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    with np.errstate(invalid='ignore', divide='ignore'):
        corr = cov / np.outer(sd, sd)
    corr = np.where(np.isfinite(corr), corr, 0.0)
    at_bound = [k for k, v, a, b in zip(prob.keys, x, prob.lo, prob.hi)
                if np.isclose(v, a, rtol=1e-6, atol=0) or np.isclose(v, b, rtol=1e-6, atol=0)]
    return Fit(_with_values(prob.config, prob.keys, x), dict(zip(prob.keys, map(float, x))),
               dict(zip(prob.keys, map(float, sd))), corr, cost, at_bound, converged,
               prob.evaluations)


# ------------------------------------------------------------------------ candidates
def candidate_effects(config: ModelConfig, effects=None) -> list[str]:
    """Effects to try: the given names, else every registered additive effect not already
    in ``config`` (the catalogue first, then users' own effects)."""
    if effects:
        names = []
        for name in effects:
            cls_ = registry.get(name)
            if cls_.slot is not None:
                raise ConfigError(f'{name!r} fills the {cls_.slot} slot; diagnose tries '
                                  'additive effects only')
            names.append(cls_.name)
    else:
        catalogue = list(registry.CATALOGUE_NAMES)
        names = catalogue + [n for n in registry.names()
                             if n not in catalogue and registry.get(n).slot is None]
    return [n for n in dict.fromkeys(names) if n not in config.effects]


def fitted_keys(name: str) -> list[str]:
    """``'effect.param'`` keys of the parameters diagnosis fits for effect ``name``."""
    keys = [f'{name}.{p.name}' for p in registry.get(name).params if p.fit]
    if not keys:
        raise ConfigError(f'effect {name!r} declares no parameter with fit=True, so diagnosis '
                          'cannot fit it; mark its main parameter fit=True')
    return keys


def trial_grid(p) -> np.ndarray:
    """Trial values of parameter ``p`` over its plausible range, logarithmic on each side of 0."""
    lo, hi = p.plausible_range()
    lo, hi = max(lo, p.lower), min(hi, p.upper)
    fractions = np.array([0.003, 0.01, 0.03, 0.1, 0.3, 1.0])
    if lo > 0.0:
        return np.geomspace(lo, hi, 6) if hi / lo > 10.0 else np.linspace(lo, hi, 6)
    sides = [hi * fractions] if hi > 0.0 else []
    if lo < 0.0:
        sides.append(lo * fractions)
    return np.concatenate(sides)


def start_values(keys: list[str], host: ModelConfig, model: Model, data: Data,
                 options: DiagnoseOptions) -> tuple[dict[str, float], float]:
    """Best point of a coarse grid of the effect's parameters, and its fit-set cost.

    Multi-parameter effects are tried along the diagonal (all parameters at
    the same fraction of their ranges). All trials run in one batch; the
    grid keeps the local fit from starting in the wrong basin.
    """
    grids = [trial_grid(host.param(k)) for k in keys]
    n = min(len(g) for g in grids)
    trials = [{k: float(g[i]) for k, g in zip(keys, grids)} for i in range(n)]
    trials.append({k: host.get(k) for k in keys})
    configs = [_with_values(host, list(t), list(t.values())) for t in trials]
    costs = [float(_stack(r) @ _stack(r))
             for r in residual_rows(model, data.fit, configs, options)]
    best = int(np.argmin(costs))
    return trials[best], costs[best]


@dataclass
class Candidate:
    """One effect tried: fitted values, held-out score and whether they are plausible."""

    effect: str
    params: dict[str, float]
    stderr: dict[str, float]
    fixed: dict[str, float]
    base_params: dict[str, float]
    score: Score
    error_reduction: float
    channel_reduction: dict[str, float]
    n_params: int
    delta_aic: float
    delta_bic: float
    problems: list[str]
    config: ModelConfig = field(repr=False)
    correlation: np.ndarray = field(repr=False, default=None)
    converged: bool = True
    seconds: float = 0.0
    acts_on: str = 'both'
    summary: str = ''
    #: False if the candidate was screened out after the coarse grid (not fitted)
    fitted: bool = True
    #: held-out RMS [normalised] of the error the effect explains, sqrt(base^2 - cand^2),
    #: and the sensor noise it is compared with
    explained_rms: float = 0.0
    noise_rms: float = 0.0

    @property
    def plausible(self) -> bool:
        return not self.problems

    def to_json(self) -> dict:
        return {'effect': self.effect, 'params': dict(self.params),
                'stderr': dict(self.stderr), 'fixed_params': dict(self.fixed),
                'base_params': dict(self.base_params),
                'error_reduction': self.error_reduction,
                'channel_error_reduction': dict(self.channel_reduction),
                'heldout_rms': self.score.to_json(), 'n_params': self.n_params,
                'delta_aic': self.delta_aic, 'delta_bic': self.delta_bic,
                'plausible': self.plausible, 'problems': list(self.problems),
                'acts_on': self.acts_on, 'summary': self.summary,
                'correlation': np.round(self.correlation, 4).tolist()
                if self.correlation is not None else None,
                'explained_rms': self.explained_rms, 'noise_rms': self.noise_rms,
                'converged': self.converged, 'fitted': self.fitted,
                'fit_seconds': round(self.seconds, 2)}


def plausibility(config: ModelConfig, values: dict[str, float], at_bound: list[str]
                 ) -> list[str]:
    """Why fitted values are not physically plausible (empty list if they are)."""
    problems = []
    for key, v in values.items():
        p = config.param(key)
        lo, hi = p.plausible_range()
        if not lo <= v <= hi:
            problems.append(f'{key} = {v:.4g} {p.unit} is outside the plausible range '
                            f'[{lo:.4g}, {hi:.4g}] {p.unit}')
        elif key in at_bound:
            problems.append(f'{key} = {v:.4g} {p.unit} stopped at a bound of its fit range')
    return problems


def _relative(new: float, old: float) -> float:
    return float(1.0 - new / old) if old > 0 else 0.0


# ---------------------------------------------------------------- shared compositions
#: catalogue effects that add exactly nothing at these values (bit-identical results)
NEUTRAL = {n: registry.get(n).neutral for n in registry.CATALOGUE_NAMES
           if registry.get(n).neutral is not None}
#: neutral effects whose hooks cost almost nothing: they share one compiled host model
#: (a composition compiles in seconds, and one host replaces seven compilations)
SHARED = ('transport_delay', 'valve_null_offset', 'external_load_torque', 'payload_inertia',
          'asymmetric_friction', 'dead_volume', 'sensor_delay')


def shared_host(config: ModelConfig) -> ModelConfig:
    """``config`` plus every :data:`SHARED` effect it lacks, at neutral values.

    It predicts exactly what ``config`` predicts, and trying any shared
    effect on it needs no new compilation.
    """
    host = config
    for name in SHARED:
        if name not in host.effects:
            host = host.with_effect(name, NEUTRAL[name])
    return host


def host_for(base: ModelConfig, name: str) -> ModelConfig:
    """The model on which effect ``name`` is tried: the shared host, or base + effect."""
    return shared_host(base) if name in SHARED else base.with_effect(name)


@dataclass
class Baseline:
    """The model as given (free base keys fitted), scored on the held-out parts."""

    config: ModelConfig
    score: Score
    n_eff: float
    values: dict[str, float] = field(default_factory=dict)


def baseline(config: ModelConfig, data: Data, free: list[str], options: DiagnoseOptions
             ) -> Baseline:
    """Held-out score of ``config`` itself, with ``free`` base keys fitted first if any."""
    host = shared_host(config)
    model = Model(host)
    values = {}
    if free:
        fit = fit_parameters(model, host, list(free), data, options)
        values = fit.values
        config = _with_values(config, list(values), list(values.values()))
        host = fit.config
    score = score_many(model, data, [host], options)[0]
    return Baseline(config, score, effective_samples(score.residual), values)


@dataclass
class Screen:
    """A candidate after the coarse grid: its host model and best grid point."""

    name: str
    host: ModelConfig
    model: Model = field(repr=False)
    keys: list[str]
    start: dict[str, float]
    cost: float
    seconds: float


def screen_effect(name: str, base: Baseline, data: Data, options: DiagnoseOptions) -> Screen:
    """Add effect ``name`` to the baseline and try a coarse grid of its parameters."""
    t0 = time.perf_counter()
    host = host_for(base.config, name)
    if name in NEUTRAL:  # start from the model as it stands
        host = host.with_effect(name, NEUTRAL[name])
    model = Model(host)
    keys = fitted_keys(name)
    start, cost = start_values(keys, host, model, data, options)
    return Screen(name, host, model, keys, start, cost, time.perf_counter() - t0)


def try_effect(name: str, base: Baseline, data: Data, free: list[str],
               options: DiagnoseOptions, screen: Screen | None = None,
               fit: bool = True) -> Candidate:
    """Add effect ``name`` to the baseline, fit it (and ``free`` base keys), score it held out.

    With ``fit=False`` the best grid point of ``screen`` is scored as it is
    (a candidate screened out: no standard errors).
    """
    t0 = time.perf_counter()
    screen = screen or screen_effect(name, base, data, options)
    cls_ = registry.get(name)
    keys = screen.keys
    host = _with_values(screen.host, list(screen.start), list(screen.start.values()))
    if fit:
        result = fit_parameters(screen.model, host, keys + [k for k in free if k not in keys],
                                data, options)
        fitted, stderr = result.config, result.stderr
        at_bound, corr, converged = result.at_bound, result.correlation, result.converged
    else:
        fitted, stderr = host, {k: float('nan') for k in keys + list(free)}
        at_bound, corr, converged = [], None, False
    score = score_many(screen.model, data, [fitted], options)[0]
    values = {k: fitted.get(k) for k in keys}
    fixed = {f'{name}.{p.name}': fitted.get(f'{name}.{p.name}')
             for p in cls_.params if not p.fit}
    base_values = {k: fitted.get(k) for k in free}
    clean = _with_values(base.config, list(base_values), list(base_values.values()))
    clean = clean.with_effect(name, {k.partition('.')[2]: v
                                     for k, v in {**values, **fixed}.items()})
    return Candidate(
        effect=name, params=values, stderr={k: stderr[k] for k in keys}, fixed=fixed,
        base_params=base_values, score=score,
        error_reduction=_relative(score.overall, base.score.overall),
        channel_reduction={ch: _relative(v, base.score.channels.get(ch, 0.0))
                           for ch, v in score.channels.items()},
        n_params=len(keys), delta_aic=0.0, delta_bic=0.0,
        problems=plausibility(fitted, values, at_bound), config=clean, correlation=corr,
        converged=converged, seconds=screen.seconds + time.perf_counter() - t0,
        acts_on=cls_.acts_on, summary=cls_.summary, fitted=fit)


# ------------------------------------------------------------------ verdict and ties
#: what excites each catalogue effect more than the others: the basis of the experiment
#: suggested when two effects explain the data about equally
EXCITATION = {
    'valve_spool_dynamics': 'fast command steps or a chirp above 20 Hz (a lag smooths the '
                            'pressure rise, a pure delay only shifts it)',
    'transport_delay': 'sharp command steps with the pistons blocked (the response starts '
                       'late but rises as fast)',
    'valve_null_offset': 'a slow command ramp through 5 V with the pistons blocked, or a '
                         'closed-port table near the centre (the pressure crossing moves)',
    'valve_null_leakage': 'a closed-port or flow-rate table at voltages within 0.5 V of the '
                          'centre (the leak has the shape of an orifice, not a gap)',
    'supply_pressure_drop': 'a flow-rate test at full opening (8-10 V), or large fast steps, '
                            'with the supply pressure measured at the regulator',
    'piston_seal_leakage': 'pistons blocked with a pressure difference and the valve at its '
                           'centre (the chambers converge to each other)',
    'external_leakage': 'pistons blocked with the valve at its centre (both chambers decay '
                        'towards atmosphere)',
    'external_load_torque': 'closed-loop holds at several angles (a constant pressure '
                            'difference at rest in both directions of approach)',
    'payload_inertia': 'fast closed-loop setpoint steps (the acceleration phase)',
    'asymmetric_friction': 'slow constant-speed moves in both directions',
    'dead_volume': 'charge/discharge steps with the pistons blocked (the pressure time '
                   'constant at a known volume)',
    'sensor_delay': 'a supply-pressure step with the valve held open and the pistons blocked '
                    '(only a measurement delay lags the response to supply)',
}


def suggest_experiment(a: str, b: str) -> str:
    """An experiment that tells effect ``a`` from effect ``b``."""
    pair = {a, b}
    if pair == {'transport_delay', 'sensor_delay'}:
        return ('record a supply-pressure step with the valve held open and the pistons '
                'blocked: a measurement delay lags the pressure response to the supply step, '
                'a command delay does not (both lag command steps alike)')
    parts = [f'{n}: {EXCITATION[n]}' for n in (a, b) if n in EXCITATION]
    if not parts:
        return (f'record an experiment that excites {a} but not {b} (or the reverse) and '
                'diagnose it together with this one')
    return ('record what excites one and not the other, and diagnose it together with this '
            'data; ' + '; '.join(parts))


def rank(candidates: list[Candidate], base: Baseline, options: DiagnoseOptions,
         independent: int = 0, noise: float = 0.0) -> list[Candidate]:
    """Candidates with information criteria filled in, best first.

    The effective sample count is taken from the best candidate's residual
    (the nearest to the noise whose correlation discounts the samples), but
    not below ``independent``: every prediction segment starts afresh from
    the measured state, so each segment and channel is at least one
    independent sample. Candidates that earn their place come first, then
    the rest, each by BIC.
    """
    if not candidates:
        return []
    best = min(candidates, key=lambda c: c.score.overall)
    n_eff = max(effective_samples(best.score.residual), float(independent))
    for c in candidates:
        c.delta_aic, c.delta_bic = information_criteria(base.score, c.score, c.n_params, n_eff)
        c.explained_rms = float(np.sqrt(max(base.score.overall ** 2 - c.score.overall ** 2,
                                            0.0)))
        c.noise_rms = noise
    return sorted(candidates, key=lambda c: (not earns_place(c, options), c.delta_bic))


def earns_place(c: Candidate, options: DiagnoseOptions) -> bool:
    """True if ``c`` was fitted and cuts the held-out residual enough, with a clear BIC gain,
    an explained error well above the sensor noise, and plausible values.

    The noise test matters once the model is nearly right: the last few
    per cent of a small residual are partly the prediction's own floor
    (unmeasured gas temperature, stick-slip timing), which a sliver of almost
    any effect can mimic; a discrepancy below the sensor noise is no finding.
    """
    return (c.fitted and c.plausible and c.error_reduction >= options.min_reduction
            and c.delta_bic <= options.min_delta_bic
            and c.explained_rms >= options.min_noise_ratio * c.noise_rms)


@dataclass
class Diagnosis:
    """Result of :func:`diagnose`: the verdict, the ranking and what backs them."""

    verdict: str
    ranking: list[Candidate]
    baseline: Baseline
    ambiguous_with: list[str]
    suggested_experiment: str
    reason: str
    options: DiagnoseOptions
    free: list[str]
    experiments: list[str]
    seconds: float
    ladder: list[dict] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)
    #: where the model as given fails: regime shares, hot spots, residual tests
    where: dict = field(default_factory=dict)
    #: the prepared experiments and the model's predictions of them (for reports)
    data: 'Data' = field(default=None, repr=False)
    base_predictions: list = field(default=None, repr=False)

    @property
    def winner(self) -> Candidate | None:
        return self.ranking[0] if self.verdict != 'none' else None

    def to_json(self) -> dict:
        return {'verdict': self.verdict,
                'ranking': [{'rank': i + 1, 'earns_place': earns_place(c, self.options),
                             **c.to_json()} for i, c in enumerate(self.ranking)],
                'ambiguous_with': list(self.ambiguous_with),
                'suggested_experiment': self.suggested_experiment,
                'reason': self.reason,
                'baseline': {'heldout_rms': self.baseline.score.to_json(),
                             'base_params': dict(self.baseline.values),
                             'effects': list(self.baseline.config.effects)},
                'ladder': self.ladder,
                'where': self.where,
                'experiments': list(self.experiments), 'free': list(self.free),
                'options': {k: getattr(self.options, k) for k in
                            ('horizon_s', 'lead_s', 'smooth_s', 'blocks', 'decimate',
                             'min_reduction', 'min_delta_bic', 'min_noise_ratio',
                             'ambiguity')},
                'noise_rms': self.ranking[0].noise_rms if self.ranking else None,
                'seconds': round(self.seconds, 2),
                'timings': {k: round(v, 2) for k, v in self.timings.items()}}


def _shortfalls(c: Candidate, options: DiagnoseOptions) -> list[str]:
    """The tests of :func:`earns_place` that ``c`` fails, in words."""
    out = []
    if not c.fitted:
        out.append('it was screened out before a full fit')
    if c.error_reduction < options.min_reduction:
        out.append(f'needs {100 * options.min_reduction:.0f} %')
    if c.delta_bic > options.min_delta_bic:
        out.append(f'BIC gain {-c.delta_bic:.1f} < {-options.min_delta_bic:g}')
    if c.explained_rms < options.min_noise_ratio * c.noise_rms:
        out.append(f'the error it explains ({c.explained_rms:.3g}) is under '
                   f'{options.min_noise_ratio:g} x the sensor noise ({c.noise_rms:.3g})')
    out += c.problems
    return out


def _verdict(ranking: list[Candidate], options: DiagnoseOptions):
    """(verdict, tied effects, suggested experiment, reason)."""
    if not ranking or not earns_place(ranking[0], options):
        top = ranking[0] if ranking else None
        why = ('no candidate effects to try' if top is None else
               f'no effect earns its place: the best, {top.effect}, cuts the held-out '
               f'residual by {100 * top.error_reduction:.1f} % ('
               + '; '.join(_shortfalls(top, options)) + ')')
        return 'none', [], '', why
    best = ranking[0]
    ties = [c.effect for c in ranking[1:] if earns_place(c, options)
            and c.score.overall <= best.score.overall * (1.0 + options.ambiguity)]
    snr = best.explained_rms / max(best.noise_rms, 1e-12)
    why = (f'{best.effect} cuts the held-out residual by {100 * best.error_reduction:.1f} % '
           f'(delta BIC {best.delta_bic:.1f}, {snr:.0f} x the sensor noise) with plausible '
           'values')
    suggestion = ''
    if ties:
        why += '; ' + ', '.join(ties) + ' explain the data about as well'
        suggestion = suggest_experiment(best.effect, ties[0])
    return best.effect, ties, suggestion, why


def diagnose(experiments: list[Experiment], config: ModelConfig | None = None,
             effects=None, free=(), options: DiagnoseOptions | None = None,
             progress=None) -> Diagnosis:
    """Find the physical effect missing from ``config`` that the ``experiments`` show.

    Parameters
    ----------
    experiments : list of Experiment
        Time series (any circuit) and static tables, diagnosed jointly.
    config : ModelConfig, optional
        The model as it stands (default the paper's).
    effects : iterable of str, optional
        Candidates to try (default: every registered additive effect not in
        ``config``, users' own included).
    free : iterable of str
        Base parameter keys (``'owner.name'``) refitted with every candidate
        and for the baseline.
    options : DiagnoseOptions, optional
        Fit and scoring settings.
    progress : callable, optional
        Called with each finished :class:`Candidate`.

    Returns
    -------
    Diagnosis
        Verdict (an effect name or 'none'), ranking best first, ties and a
        suggested experiment, and the held-out error ladder.
    """
    t0 = time.perf_counter()
    options = options or DiagnoseOptions()
    config = config or ModelConfig.paper()
    free = list(free)
    for key in free:
        config.get(key)  # a clear error for an unknown key
    if options.refit_present:  # every fit=True parameter of the effects already present
        free += [f'{name}.{p.name}' for name in config.effects
                 for p in registry.get(name).params if p.fit and f'{name}.{p.name}' not in free]
    names = candidate_effects(config, effects)
    data = Data.of(experiments, options)
    timings = {'prepare': time.perf_counter() - t0}
    base = baseline(config, data, free, options)
    base_preds = predictions(base.config, data)
    where = where_it_fails(data.experiments, base_preds, base.config)
    timings['baseline'] = time.perf_counter() - t0 - timings['prepare']
    screens = [screen_effect(name, base, data, options) for name in names]
    full = {s.name for s in sorted(screens, key=lambda s: s.cost)[:options.full_fits]}
    candidates = []
    for scr in screens:
        cand = try_effect(scr.name, base, data, free, options, scr, fit=scr.name in full)
        timings[scr.name] = cand.seconds
        candidates.append(cand)
        if progress is not None:
            progress(cand)
    ranking = rank(candidates, base, options, data.independent, data.noise)
    verdict, ties, suggestion, why = _verdict(ranking, options)
    result = Diagnosis(verdict, ranking, base, ties, suggestion, why, options, free,
                       [e.name for e in experiments], 0.0, timings=timings, where=where,
                       data=data, base_predictions=base_preds)
    t1 = time.perf_counter()
    result.ladder = ladder(config, data, options, result.winner, base)
    timings['ladder'] = time.perf_counter() - t1
    result.seconds = time.perf_counter() - t0
    return result


def where_it_fails(experiments: list[Experiment], preds: list[dict],
                   config: ModelConfig) -> dict:
    """Regime error shares, hot spots and residual tests of a model's predictions (JSON)."""
    shares = error_shares(experiments, preds, config)
    series = [(e, p) for e, p in zip(experiments, preds) if not e.static]
    out = {'regimes': [s.to_json() for s in shares], 'hot_spots': hot_spots(shares)}
    if series:
        exps, prs = [e for e, _ in series], [p for _, p in series]
        tests = residual_tests(exps, prs)
        summ = summary(exps, prs, tests)
        out['residuals'] = {**summ, 'channels': {
            ch: {'rms': t.rms, 'acf_outside_band': t.whiteness,
                 'xcorr_command_peak': dict(zip(('lag_s', 'r'), t.xcorr_peak)),
                 'xcorr_band': t.xcorr_band,
                 'correlations': {k: {'r': r, 'band': t.bands[k]}
                                  for k, r in t.correlations.items()}}
            for ch, t in tests.items()}}
    return out


def apply(result: Diagnosis, effect: str | None = None) -> ModelConfig:
    """The model with the winning effect (or ``effect`` from the ranking) added and fitted."""
    if effect is None:
        if result.winner is None:
            raise ConfigError('the diagnosis found no effect to add (verdict none); name one '
                              'from the ranking to add it anyway')
        return result.winner.config
    for cand in result.ranking:
        if cand.effect == effect:
            return cand.config
    raise ConfigError(f'{effect!r} was not tried in this diagnosis; tried: '
                      f'{", ".join(c.effect for c in result.ranking)}')


# --------------------------------------------------------------------------- ladder
def _without(config: ModelConfig, names: list[str]) -> ModelConfig:
    out = config.copy()
    for name in names:
        del out.effects[name]
    return out


def ladder(config: ModelConfig, data: Data, options: DiagnoseOptions,
           winner: Candidate | None = None, base: Baseline | None = None) -> list[dict]:
    """Held-out error as the model's effects are added one by one, then the winner.

    Rung 0 is ``config`` without its added effects; rung i adds the i-th
    effect (with the values ``config`` holds); the last rung adds ``winner``.
    Returns, per rung, ``{'model', 'effects', 'overall', 'channels'}``
    (normalised held-out RMS).
    """
    names = list(config.effects)
    rungs = []
    for i in range(len(names) + 1):
        if i == len(names) and base is not None:
            score = base.score
        else:
            score = _prefix_score(config, names, i, data, options)
        rungs.append(_rung('+' + names[i - 1] if i else 'base', names[:i], score))
    if winner is not None:
        rungs.append(_rung('+' + winner.effect, names + [winner.effect], winner.score))
    return rungs


def _prefix_score(config, names, i, data, options) -> Score:
    """Held-out score of ``config`` with only its first ``i`` effects active.

    Later effects with neutral values are switched off by value, so the
    same compiled model serves every rung; others are removed.
    """
    later = names[i:]
    host = _without(config, [n for n in later if n not in NEUTRAL])
    for name in later:
        if name in NEUTRAL:
            host = host.with_effect(name, NEUTRAL[name])
    host = shared_host(host)
    return score_many(Model(host), data, [host], options)[0]


def _rung(label: str, effects: list[str], score: Score) -> dict:
    return {'model': label, 'effects': list(effects), 'overall': score.overall,
            'channels': dict(score.channels)}
