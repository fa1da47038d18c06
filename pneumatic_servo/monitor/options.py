"""What the monitor is asked to do: every choice in one frozen record, checked once."""
from __future__ import annotations

import math
from dataclasses import dataclass, fields

from ..errors import ConfigError
from ..prediction import COMPARE_HORIZON_S


@dataclass(frozen=True)
class MonitorOptions:
    """How the monitor judges the data (SI units).

    Attributes
    ----------
    horizon_s : float [s]
        k-step horizon of a window (``compare``'s, 0.2 s).
    lead_s : float [s]
        Lead-in simulated before a prediction for the unmeasured states (gas temperatures
        when not measured, effect-owned states); a copy's truth starts this much earlier
        again.
    replicas : int
        Copies of each window that measure its floor.
    baseline_s : float [s]
        Data measured before judging starts, without a floor file: the rig's sensor noise
        and quantisation are estimated on it.
    false_alarm_per_hour : float [1/h]
        Stated rate of false WARNs per hour of data, all channels together, when the
        model describes the rig (:mod:`.cusum`).
    error_ratio : float
        A departing channel whose recent residual is at least this many times its floor
        is an ERROR (the model is not to be trusted there), not a WARN.
    recent_s : float [s]
        Span of data over which the departure ratio and the regimes are reported.
    report_period_s : float [s]
        Data time between reports.
    max_backlog_s : float [s]
        Data waiting to be judged beyond which the oldest windows are skipped
        (decimation, counted and reported): the monitor never falls behind silently.
    batch_windows : int
        Windows judged per batch (one batched simulation per copy).
    track : tuple of str
        Catalogue effects fitted on the latest data, to follow their parameters.
    fit_window_s, fit_period_s : float [s]
        Data per tracked fit, and data time between fits while a channel departs (fits
        are made at the end of the baseline, as the reference, once a whole window lies
        after the start of a departure, and then every ``fit_period_s`` while one
        departs).
    seed : int
        Seed of the copies' jitter and noise.
    """

    horizon_s: float = COMPARE_HORIZON_S
    lead_s: float = 0.05
    replicas: int = 8
    baseline_s: float = 20.0
    false_alarm_per_hour: float = 0.01
    error_ratio: float = 10.0
    recent_s: float = 10.0
    report_period_s: float = 1.0
    max_backlog_s: float = 2.0
    batch_windows: int = 5
    track: tuple = ()
    fit_window_s: float = 10.0
    fit_period_s: float = 10.0
    seed: int = 0

    def __post_init__(self):
        positive = ('horizon_s', 'baseline_s', 'false_alarm_per_hour', 'recent_s',
                    'report_period_s', 'max_backlog_s', 'fit_window_s', 'fit_period_s')
        for name in positive:
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ConfigError(f'monitor option {name} = {value!r}: give a positive number')
        if not (math.isfinite(self.lead_s) and self.lead_s >= 0):
            raise ConfigError(f'monitor option lead_s = {self.lead_s!r}: give 0 or more seconds')
        if not (isinstance(self.replicas, int) and self.replicas >= 3):
            raise ConfigError(f'monitor option replicas = {self.replicas!r}: give at least 3 '
                              '(the floor test needs a spread)')
        if not (isinstance(self.batch_windows, int) and self.batch_windows >= 1):
            raise ConfigError(f'monitor option batch_windows = {self.batch_windows!r}: give 1 '
                              'or more')
        if not self.error_ratio >= 1:
            raise ConfigError(f'monitor option error_ratio = {self.error_ratio!r}: give 1 or '
                              'more (times the floor)')
        object.__setattr__(self, 'track', tuple(self.track))

    @classmethod
    def from_dict(cls, values: dict) -> 'MonitorOptions':
        """Options from a mapping; unknown keys are ignored."""
        names = {f.name for f in fields(cls)}
        return cls(**{k: v for k, v in values.items() if k in names})
