"""Where the model fails: operating regimes segmented from the signals, and the share of each
channel's squared error that falls in each regime against the share of time spent there.

Each regime *family* splits the samples of an experiment into named classes:

=============  ===============================================  =======================
family         classes                                          from
=============  ===============================================  =======================
valve          near_null, open                                  command, valve geometry
chamber_a/b    charging, discharging, holding                   measured pressure rate
flow           choked, subsonic                                 pressure ratio across
                                                                the supply edge
motion         stuck, sliding                                   velocity (estimated)
direction      increasing, decreasing, still                    velocity (estimated)
end_stop       near_stop, mid_stroke                            angle
acceleration   accelerating, steady                             acceleration (estimated)
=============  ===============================================  =======================

Measured signals are used where they exist (smoothed where a rate is
needed) and the simulated ones otherwise, so a regime is where the rig
*was*, not where the model thinks it was. An error share well above the
time share points at the regime where the model is wrong.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..experiment import STATE_CHANNELS, Experiment, signal_of
from ..model.config import ModelConfig
from ..physics.gas import ideal_critical_ratio
from ..smoothing import savgol_filter

#: regime family -> its classes, in display order
FAMILIES = {
    'valve': ('near_null', 'open'),
    'chamber_a': ('charging', 'discharging', 'holding'),
    'chamber_b': ('charging', 'discharging', 'holding'),
    'flow': ('choked', 'subsonic'),
    'motion': ('stuck', 'sliding'),
    'direction': ('increasing', 'decreasing', 'still'),
    'end_stop': ('near_stop', 'mid_stroke'),
    'acceleration': ('accelerating', 'steady'),
}


@dataclass
class Thresholds:
    """Where one class ends and the next begins (SI units).

    Attributes
    ----------
    null_band_v : float [V]
        Command within this of the valve's centre counts as near null
        (at least the spool overlap, converted to volts).
    pressure_rate_pa_s : float [Pa/s]
        A chamber whose pressure changes slower than this is holding.
    velocity_rad_s : float [rad/s]
        Below this speed the shaft counts as stuck (the encoder cannot resolve
        the model's stiction band of 1e-3 rad/s).
    stop_band_rad : float [rad]
        Within this of either end of the stroke counts as near a stop.
    acceleration_rad_s2 : float [rad/s^2]
        Above this angular acceleration the shaft is accelerating.
    smooth_s : float [s]
        Window of the Savitzky-Golay filter used for rates.
    """

    null_band_v: float = 0.1
    pressure_rate_pa_s: float = 2e4
    velocity_rad_s: float = 0.02
    stop_band_rad: float = 0.05
    acceleration_rad_s2: float = 5.0
    smooth_s: float = 0.025


def _rate(x: np.ndarray, dt: float, window_s: float, deriv: int = 1) -> np.ndarray:
    """Smoothed derivative of ``x`` [unit/s^deriv] by a Savitzky-Golay filter."""
    win = max(5, int(round(window_s / dt)) | 1)
    if len(x) <= win:
        return np.gradient(x, dt) if deriv == 1 else np.gradient(np.gradient(x, dt), dt)
    return savgol_filter(x, win, 2 + deriv - 1, deriv=deriv, delta=dt)


def _signal(exp: Experiment, pred: dict | None, name: str):
    """Measured signal ``name`` if recorded, else the simulated one, else None."""
    if name in exp.signals:
        return exp[name]
    if pred is not None and name in pred and np.all(np.isfinite(pred[name])):
        return np.asarray(pred[name])
    return None


def _labels(mask_by_class: dict[str, np.ndarray], n: int) -> np.ndarray:
    """Class name per sample from boolean masks (first match wins)."""
    out = np.full(n, '', dtype=object)
    for name, mask in mask_by_class.items():
        out[(out == '') & mask] = name
    return out


def _valve(exp, config, th):
    u = exp['command_v']
    core = config.core
    overlap_v = max(core['spool_shoulder_half_width_m'] - core['hole_radius_m'], 0.0) \
        / core['spool_gain_m_per_v']
    band = max(th.null_band_v, 2.0 * overlap_v)
    near = np.abs(u - core['valve_null_voltage_v']) < band
    return _labels({'near_null': near, 'open': ~near}, len(u))


def _chamber(p, dt, th):
    rate = _rate(p, dt, th.smooth_s)
    return _labels({'charging': rate > th.pressure_rate_pa_s,
                    'discharging': rate < -th.pressure_rate_pa_s,
                    'holding': np.ones(len(p), bool)}, len(p))


def _flow(exp, pred, config):
    """Choked if the metered supply edge (supply -> the filling chamber) runs below the
    critical pressure ratio.

    The exhaust edge is left out: it is choked whenever the emptying chamber
    is above about 1.9 bar, which is nearly always, so it separates nothing.
    """
    p_a, p_b = _signal(exp, pred, 'p_a_pa'), _signal(exp, pred, 'p_b_pa')
    if p_a is None or 'command_v' not in exp.signals:
        return None
    core = config.core
    ps = exp.signals.get('supply_pa', np.full(len(p_a), core['supply_pressure_pa']))
    # the valve's own critical ratio where its orifice part declares one, else the ideal
    crit = config.components.get('orifice_flow', {}).get(
        'critical_pressure_ratio', ideal_critical_ratio(core['heat_capacity_ratio']))
    positive = exp['command_v'] >= core['valve_null_voltage_v']
    filling = p_a if p_b is None or exp.circuit not in ('servo', 'blocked') else \
        np.where(positive, p_a, p_b)
    choked = filling / ps < crit
    return _labels({'choked': choked, 'subsonic': ~choked}, len(p_a))


def _motion_families(exp, pred, config, th) -> dict[str, np.ndarray]:
    angle = _signal(exp, pred, 'angle_rad')
    if angle is None or exp.circuit != 'servo':
        return {}
    dt = exp.dt
    vel = _rate(angle, dt, th.smooth_s)
    acc = _rate(angle, dt, 2.0 * th.smooth_s, deriv=2)
    n = len(angle)
    moving = np.abs(vel) >= th.velocity_rad_s
    stroke = config.core['stroke_rad']
    near = (angle < th.stop_band_rad) | (angle > stroke - th.stop_band_rad)
    fast = np.abs(acc) >= th.acceleration_rad_s2
    return {
        'motion': _labels({'stuck': ~moving, 'sliding': moving}, n),
        'direction': _labels({'increasing': moving & (vel > 0), 'decreasing': moving & (vel < 0),
                              'still': ~moving}, n),
        'end_stop': _labels({'near_stop': near, 'mid_stroke': ~near}, n),
        'acceleration': _labels({'accelerating': fast, 'steady': ~fast}, n),
    }


def segment(exp: Experiment, pred: dict | None = None, config: ModelConfig | None = None,
            thresholds: Thresholds | None = None) -> dict[str, np.ndarray]:
    """Regime class of every sample of ``exp``, per family that applies to it.

    Parameters
    ----------
    exp : Experiment
        Measured experiment (time series or static table).
    pred : dict, optional
        Simulated signals on ``exp.t`` (fills in what was not measured).
    config : ModelConfig, optional
        Supplies valve centre and geometry, stroke, critical ratio.
    thresholds : Thresholds, optional
        Class boundaries.

    Returns
    -------
    dict
        family -> array of class names (one per sample).
    """
    config = config or ModelConfig.paper()
    th = thresholds or Thresholds()
    out = {}
    if 'command_v' in exp.signals:
        out['valve'] = _valve(exp, config, th)
    if not exp.static:
        for fam, sig in (('chamber_a', 'p_a_pa'), ('chamber_b', 'p_b_pa')):
            if sig == 'p_b_pa' and exp.circuit not in ('servo', 'blocked'):
                continue  # the static circuits have no chamber b
            p = _signal(exp, pred, sig)
            if p is not None:
                out[fam] = _chamber(p, exp.dt, th)
        out.update(_motion_families(exp, pred, config, th))
    flow = _flow(exp, pred, config)
    if flow is not None:
        out['flow'] = flow
    return out


@dataclass
class RegimeShare:
    """One regime class: share of time and share of each channel's squared error there."""

    family: str
    regime: str
    time_share: float
    error_share: dict[str, float]

    def concentration(self, channel: str) -> float:
        """Error share over time share (> 1: the error concentrates here)."""
        if self.time_share <= 0:
            return float('nan')
        return self.error_share.get(channel, float('nan')) / self.time_share

    def to_json(self) -> dict:
        return {'family': self.family, 'regime': self.regime, 'time_share': self.time_share,
                'error_share': dict(self.error_share),
                'concentration': {ch: self.concentration(ch) for ch in self.error_share}}


def _squared_errors(exp: Experiment, pred: dict, channels) -> dict[str, np.ndarray]:
    """Squared residual per channel, normalised by the channel's measured spread, so that
    experiments pooled together weigh alike."""
    out = {}
    for ch in channels:
        sig = signal_of(ch)
        if sig in exp.signals and sig in pred:
            r = np.asarray(pred[sig]) - exp[sig]
            scale = max(float(np.nanstd(exp[sig])), 1e-12)
            out[ch] = np.where(np.isfinite(r), r / scale, 0.0) ** 2
    return out


def error_shares(experiments: list[Experiment], predictions: list[dict],
                 config: ModelConfig | None = None, channels=STATE_CHANNELS,
                 thresholds: Thresholds | None = None) -> list[RegimeShare]:
    """Share of time and of each channel's squared error per regime, pooled over experiments.

    Parameters
    ----------
    experiments : list of Experiment
        Measured experiments.
    predictions : list of dict
        Simulated signals of each experiment (signal -> array on its ``t``).
    config : ModelConfig, optional
        The model (valve centre, stroke, critical ratio).
    channels : iterable of str
        Compared channels ('angle', 'p_a', 'p_b').

    Returns
    -------
    list of RegimeShare
        In :data:`FAMILIES` order; the shares of one family sum to 1 over
        its classes for every channel that family covers.
    """
    time_n: dict[tuple, float] = {}
    err: dict[tuple, dict[str, float]] = {}
    fam_total: dict[str, float] = {}
    fam_err: dict[str, dict[str, float]] = {}
    for exp, pred in zip(experiments, predictions):
        labels = segment(exp, pred, config, thresholds)
        sq = _squared_errors(exp, pred, channels)
        for fam, lab in labels.items():
            fam_total[fam] = fam_total.get(fam, 0.0) + len(lab)
            for cls in FAMILIES[fam]:
                mask = lab == cls
                key = (fam, cls)
                time_n[key] = time_n.get(key, 0.0) + float(mask.sum())
                for ch, e in sq.items():
                    err.setdefault(key, {}).setdefault(ch, 0.0)
                    err[key][ch] += float(e[mask].sum())
                    fam_err.setdefault(fam, {}).setdefault(ch, 0.0)
                    fam_err[fam][ch] += float(e[mask].sum())
    out = []
    for fam, classes in FAMILIES.items():
        if fam not in fam_total:
            continue
        for cls in classes:
            key = (fam, cls)
            shares = {ch: (err.get(key, {}).get(ch, 0.0) / tot if tot > 0 else 0.0)
                      for ch, tot in fam_err.get(fam, {}).items()}
            out.append(RegimeShare(fam, cls, time_n.get(key, 0.0) / fam_total[fam], shares))
    return out


def hot_spots(shares: list[RegimeShare], min_error_share: float = 0.2,
              min_concentration: float = 1.5) -> list[dict]:
    """Regimes that hold a large share of a channel's error compared with their time share,
    strongest first: where to look for the missing effect."""
    spots = []
    for s in shares:
        for ch, e in s.error_share.items():
            c = s.concentration(ch)
            if e >= min_error_share and np.isfinite(c) and c >= min_concentration:
                spots.append({'channel': ch, 'family': s.family, 'regime': s.regime,
                              'error_share': e, 'time_share': s.time_share,
                              'concentration': c})
    return sorted(spots, key=lambda d: -d['concentration'] * d['error_share'])
