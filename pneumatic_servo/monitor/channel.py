"""One monitored channel: its CUSUM, its recent judged windows, and what they say. Pure.

Units: stamps in integer nanoseconds, everything else SI.
"""
from __future__ import annotations

import collections
import math
from dataclasses import dataclass, field

import numpy as np

from ..analysis.regimes import FAMILIES, RegimeShare, hot_spots
from . import cusum
from .judge import CHANNELS, UNITS, Sensors
from .options import MonitorOptions


@dataclass
class ChannelState:
    """The verdict state of one channel (angle, p_a or p_b)."""

    cusum: cusum.Cusum
    #: stamp [ns] of the window where the current alarm began (None: no alarm)
    since_ns: int | None = None
    #: recent judged windows: (start index, stamp ns, mean square, floor mean square, p, z)
    recent: collections.deque = field(default_factory=collections.deque)

    def forget(self, first: int, horizon: int) -> None:
        """Drop the windows that start before index ``first`` (their samples are gone) or
        more than ``horizon`` samples before the latest."""
        while self.recent and (self.recent[0][0] < first
                               or self.recent[-1][0] - self.recent[0][0] > horizon):
            self.recent.popleft()

    def report(self, ch: str, sensors: Sensors | None, options: MonitorOptions,
               windows_per_hour: float, hot: dict | None, waiting: str) -> dict:
        """Channel ``ch``'s level, departure over the recent windows and the test behind it
        (plain data); ``hot``: the regime where its departure concentrates (or None);
        ``waiting``: what to say before any window is judged."""
        c, unit = self.cusum, UNITS[ch]
        if not self.recent:
            return {'level': 'ok', 'windows': 0, 'ratio': float('nan'), 'rms': float('nan'),
                    'floor_rms': float('nan'), 'cusum': c.s, 'threshold': c.h,
                    'p_value': 1.0, 'window_p_value': float('nan'), 'z': float('nan'),
                    'since_ns': None, 'regime': '', 'unit': unit, 'alarms': c.alarms,
                    'message': waiting}
        ms = np.array([r[2] for r in self.recent])
        fms = np.array([r[3] for r in self.recent])
        eps = sensors.reading_variance(ch)
        ratio = float(math.sqrt(ms.sum() / fms.sum())) if fms.sum() > 0 else float('inf')
        p = cusum.p_value(c.s, windows_per_hour)
        level = 'ok'
        if c.alarm:
            level = 'error' if ratio >= options.error_ratio else 'warn'
        regime = ''
        if hot is not None:
            regime = (f'{hot["family"]} {hot["regime"]} ({hot["error_share"]:.0%} of the '
                      f'departure in {hot["time_share"]:.0%} of the time)')
        rms = math.sqrt(max(float(ms.mean()) - eps, 0.0))
        floor_rms = math.sqrt(max(float(fms.mean()) - eps, 0.0))
        if level == 'ok':
            message = (f'{ratio:.2g} x the floor over the last {options.recent_s:g} s '
                       f'(CUSUM {c.s:.3g} < {c.h:.3g}, p = {p:.2g} per hour)')
        else:
            level_c = options.false_alarm_per_hour / len(CHANNELS)
            message = (f'departs: {ratio:.3g} x the floor (CUSUM {c.s:.3g} >= '
                       f'{c.h:.3g}, p = {p:.2g} per hour, level {level_c:.2g})')
            if level == 'error':
                message += (f'; at least {options.error_ratio:g} x: the model is not to be '
                            'trusted here')
            if regime:
                message += f'; concentrated in {regime}'
        return {'level': level, 'windows': len(self.recent), 'ratio': ratio, 'rms': rms,
                'floor_rms': floor_rms, 'cusum': c.s, 'threshold': c.h,
                'p_value': p, 'window_p_value': float(self.recent[-1][4]),
                'z': float(self.recent[-1][5]), 'since_ns': self.since_ns, 'regime': regime,
                'unit': unit, 'alarms': c.alarms, 'message': message}

    def hot_spot(self, ch: str, labels: dict, lo: int, hi: int, win: int) -> dict | None:
        """The regime where this channel's departure concentrates over the recent windows
        (squared residual in units of each window's floor), from the regime ``labels`` of
        samples ``lo`` to ``hi`` (windows of ``win`` samples); None if none stands out."""
        weight = np.zeros(hi - lo)
        mask = np.zeros(hi - lo, bool)
        for a, _, ms, fms, _, _ in self.recent:
            if a < lo:
                continue
            # the window's departure spread evenly over its samples, in units of its floor
            weight[a - lo + 1:a - lo + win] = ms / max(fms, 1e-300)
            mask[a - lo + 1:a - lo + win] = True
        if not mask.any() or weight[mask].sum() <= 0:
            return None
        shares = []
        for fam, lab in labels.items():
            for cls in FAMILIES[fam]:
                m = (lab == cls) & mask
                shares.append(RegimeShare(fam, cls, m.sum() / mask.sum(),
                                          {ch: weight[m].sum() / weight[mask].sum()}))
        spots = hot_spots(shares)
        return spots[0] if spots else None
