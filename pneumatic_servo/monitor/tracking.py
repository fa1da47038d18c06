"""Which effect: the tracked effects fitted on the latest data, and an alert when one moves.

The monitor's config may name effects to track (``track``, e.g. ``piston_seal_leakage``).
Each tracked fit adds them to the model and fits their parameters to the latest
``fit_window_s`` of data, in k-step windows, from several start points, as ``fleet
--track`` fits each recording (:func:`fit_tracked`). It is slow (seconds), so the monitor
runs it in a worker process of its own, never in the path of the windows' verdicts.

Each parameter's estimates form a series in data time, judged with the fleet's change
detection (:func:`pneumatic_servo.fleet.alerts.judge_series`: a step or a trend beyond the
estimates' scatter and standard errors, 1 % per parameter and series). Online the series is
judged again at every new estimate, so the level is spent over the looks: the ``j``-th
look is held to ``1 % x 6 / (pi^2 j^2)``, which sums to 1 % over any number of looks
(:func:`look_level`). An alert is a WARN on the parameter's status until a later look no
longer finds the change.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..experiment import Experiment
from ..fleet.alerts import FALSE_ALARM_RATE, judge_series
from ..fleet.task import SPREAD
from ..model.config import ModelConfig
from .judge import CHANNELS


def look_level(look: int, rate: float = FALSE_ALARM_RATE) -> float:
    """The level of the ``look``-th judgement of a growing series (1-based): ``rate x 6 /
    (pi^2 look^2)``, so that all looks together spend at most ``rate``."""
    return rate * 6.0 / (math.pi ** 2 * max(look, 1) ** 2)


def tracked_config(config: ModelConfig, track) -> tuple[ModelConfig, list[str]]:
    """``config`` with the tracked effects added (at their defaults where absent), and the
    keys of their fitted parameters."""
    from .. import effects as registry
    from ..analysis.compare import resolve_config
    cfg = resolve_config(config, list(track))
    keys = [f'{name}.{k}' for name in track
            for k in registry.get(name).refit_keys(cfg.effects[name])]
    return cfg, keys


def fit_tracked(config: ModelConfig, keys: list[str], exp: Experiment,
                horizon_s: float) -> dict[str, tuple[float, float]]:
    """Fit ``keys`` of ``config`` to ``exp`` in k-step windows of ``horizon_s``: key ->
    (value, standard error) [SI] (NaN where the data do not determine it)."""
    from ..identification.output_error import fit_output_error
    starts = [{key: config.get(key) * f} for key in keys for f in SPREAD if config.get(key)]
    result = fit_output_error(config, [exp], keys, channels=tuple(CHANNELS), mode='k_step',
                              horizon_s=horizon_s, starts=starts, bracket=True)
    out = {}
    for key in keys:
        se = result.stderr.get(key)
        out[key] = (float(result.values[key]), float('nan') if se is None else float(se))
    return out


@dataclass
class Series:
    """One tracked parameter's estimates in data time."""

    key: str
    label: str
    unit: str
    t_s: list = field(default_factory=list)
    values: list = field(default_factory=list)
    stderr: list = field(default_factory=list)
    looks: int = 0
    alert: dict | None = None

    def add(self, t_s: float, value: float, stderr: float) -> None:
        self.t_s.append(t_s)
        self.values.append(value)
        self.stderr.append(stderr)
        self.judge()

    def judge(self) -> None:
        """Judge the series after a new estimate (see module doc)."""
        x = np.asarray(self.t_s, float)
        change = judge_series(x - x[0], self.values, self.stderr)
        if len(self.values) >= 3:
            self.looks += 1
        level = look_level(self.looks)
        if change is None or change.p_value > level:
            self.alert = None
            return
        first = change.index if change.kind == 'step' else int(
            change.points[np.searchsorted(change.points, change.index) - 1])
        self.alert = {'kind': change.kind, 'since_s': self.t_s[first], 'from': change.start,
                      'to': change.end, 'p_value': change.p_value, 'level': level,
                      'text': self.describe(change.kind, change.start, change.end,
                                            self.t_s[first])}

    def describe(self, kind: str, start: float, end: float, since_s: float) -> str:
        """The alert as a maintenance note: 'effective orifice area of the seal leak rose
        from about 0 to 3e-08 m^2 in one step, at data time 15.9 s'."""
        verb = 'rose' if end > start else 'fell'
        before = '0' if abs(start) < 0.05 * abs(end) else f'{start:.2g}'
        what = f'{self.label} {verb} from about {before} to {end:.2g} {self.unit}'
        if kind == 'step':
            return f'{what} in one step, at data time {since_s:.1f} s'
        return f'{what}, since data time {since_s:.1f} s'

    def to_json(self) -> dict:
        last = len(self.values) - 1
        return {'key': self.key, 'label': self.label, 'unit': self.unit,
                'value': self.values[last] if last >= 0 else float('nan'),
                'stderr': self.stderr[last] if last >= 0 else float('nan'),
                't_s': self.t_s[last] if last >= 0 else float('nan'),
                'estimates': len(self.values), 'looks': self.looks, 'alert': self.alert}


class Tracker:
    """Fits the tracked effects on data windows and keeps each parameter's series."""

    def __init__(self, config: ModelConfig, track, horizon_s: float):
        self.config, self.keys = tracked_config(config, track)
        self.horizon_s = horizon_s
        self.series = {}
        for key in self.keys:
            p = self.config.param(key)
            self.series[key] = Series(key, p.description, p.unit)

    def fit(self, t_s: float, signals: dict, dt: float) -> dict:
        """Fit on ``signals`` (a complete stretch on a grid of ``dt`` [s]) ending at data time
        ``t_s``; returns every series (:meth:`Series.to_json`)."""
        exp = Experiment(np.arange(len(signals['angle_rad'])) * dt, dict(signals), 'servo',
                         'monitor fit window')
        for key, (value, se) in fit_tracked(self.config, self.keys, exp,
                                            self.horizon_s).items():
            self.series[key].add(t_s, value, se)
        return {key: s.to_json() for key, s in self.series.items()}
