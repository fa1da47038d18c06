"""Alerts: a tracked parameter of a rig that rises, falls or steps beyond its uncertainty.

For each rig and parameter, the estimates in time order are compared under three least-
squares models: constant, a step (one level before, another after), and a trend that
starts at some recording (constant, then a straight line: "since when?"). The step and
the trend are tried at every change point with at least ``MIN_AFTER`` recordings after
it. Each adds one parameter to the constant, so under a healthy rig (no change, Gaussian
scatter of unknown size) ``F = (RSS_const - RSS_change) / (RSS_change / (n - 2))``
follows an F(1, n - 2) distribution; the largest F over all ``m`` tries is compared with
the ``1 - FALSE_ALARM_RATE / m`` quantile (Bonferroni). So a healthy rig raises an alert
for a parameter in at most ``FALSE_ALARM_RATE`` (1 %) of runs: the documented false-alarm
rate, checked by simulation in ``tests/test_fleet.py``.

The scatter is measured from the series itself, not taken from the fits' standard errors:
a standard error from one recording is often optimistic (and meaningless where stick-slip
makes the cost rough), and a healthy rig must not alarm because of that. The standard
errors still guard the other side: a change smaller than ``MIN_CHANGE_STDERR`` times the
typical standard error is not reported, however regular the series.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass
from datetime import datetime

import numpy as np
from scipy.stats import f as f_dist

#: probability that a healthy rig's parameter raises an alert in one run
FALSE_ALARM_RATE = 0.01
#: recordings needed after a change point (a single odd recording is not a change)
MIN_AFTER = 2
#: recordings needed before one looks for a change at all
MIN_POINTS = 5
#: a change must exceed this many typical standard errors of one estimate
MIN_CHANGE_STDERR = 2.0


@dataclass
class Alert:
    """A parameter of a rig that changed beyond its uncertainty."""

    rig: str
    parameter: str
    kind: str          # 'trend' or 'step'
    since: str         # start time (ISO) or path of the first recording after the change
    from_value: float  # [SI] the fitted model's value before the change
    to_value: float    # [SI] its value at the last recording
    evidence: str
    text: str

    def to_json(self) -> dict:
        out = asdict(self)
        out['from'] = out.pop('from_value')
        out['to'] = out.pop('to_value')
        return out


def _rss(design: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, float]:
    """Least squares: (fitted values, residual sum of squares)."""
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    fitted = design @ coef
    return fitted, float(np.sum((y - fitted) ** 2))


def best_change(x: np.ndarray, values: np.ndarray):
    """The most significant change: (kind, index of the change, fitted values, F, threshold),
    ``x`` the times [days] (or recording numbers) of ``values``."""
    n = len(values)
    ones = np.ones(n)
    _, rss_const = _rss(ones[:, None], values)
    best, tries = None, 0
    for k in range(1, n - MIN_AFTER + 1):
        after = (np.arange(n) >= k).astype(float)
        ramp = np.maximum(x - x[k - 1], 0.0)  # flat up to recording k-1, then a line
        for kind, column in (('step', after), ('trend', ramp)):
            tries += 1
            fitted, rss = _rss(np.column_stack([ones, column]), values)
            stat = (rss_const - rss) / max(rss / (n - 2), 1e-300)  # a perfect fit: huge
            if best is None or stat > best[3]:
                best = (kind, k, fitted, stat)
    threshold = float(f_dist.isf(FALSE_ALARM_RATE / tries, 1, n - 2))
    return (*best, threshold)


def _when(times, paths, i) -> str:
    return times[i] if times[i] else paths[i]


def _days(a: str | None, b: str | None) -> str:
    if not (a and b):
        return ''
    days = (datetime.fromisoformat(b) - datetime.fromisoformat(a)).total_seconds() / 86400
    return f' over {days:.3g} days' if days >= 1 else f' over {days * 24:.3g} hours'


def describe(rig: str, label: str, unit: str, kind: str, start: float, end: float,
             since: str, span: str = '') -> str:
    """The alert as a maintenance note, e.g. 'cell-2: piston seal leakage area rose from
    about 0 to 4e-08 m^2 over 3 days, since 2026-11-02T08:00:00+00:00'."""
    verb = 'rose' if end > start else 'fell'
    what = f'{rig}: {label} {verb} from about {_round(start, end)} to {end:.2g} {unit}'.rstrip()
    if kind == 'step':
        return f'{what} in one step, at the recording of {since}'
    return f'{what}{span}, since {since}'


def _round(start: float, end: float) -> str:
    """``start`` as an engineer would say it next to ``end``: 'about 0' if tiny."""
    return '0' if abs(start) < 0.05 * abs(end) else f'{start:.2g}'


def detect_alerts(rows: list[dict], describe_param=None) -> list[Alert]:
    """Alerts over the tracked parameters of ``rows`` (fleet rows with ``status`` ok).

    ``describe_param(key) -> (label, unit)`` names a parameter for the alert text
    (default: its key, SI).
    """
    series: dict[tuple[str, str], list] = {}
    for row in rows:
        if row.get('status') != 'ok':
            continue
        for key, est in (row.get('params') or {}).items():
            if est.get('value') is None:
                continue
            series.setdefault((row['rig'], key), []).append(
                (row.get('start_time') or '', row['path'], est['value'],
                 np.nan if est.get('stderr') is None else est['stderr']))
    alerts = []
    for (rig, key), points in sorted(series.items()):
        if len(points) < MIN_POINTS:
            continue
        points.sort()
        times = [p[0] or None for p in points]
        paths = [p[1] for p in points]
        values = np.array([p[2] for p in points], dtype=float)
        x = (np.array([datetime.fromisoformat(t).timestamp() / 86400 for t in times])
             if all(times) else np.arange(len(points), dtype=float))
        stderr = np.array([p[3] for p in points], dtype=float)
        kind, k, fitted, stat, threshold = best_change(x, values)
        start, end = float(fitted[0]), float(fitted[-1])
        typical = float(np.nanmedian(stderr)) if np.isfinite(stderr).any() else 0.0
        if stat <= threshold or abs(end - start) <= MIN_CHANGE_STDERR * typical:
            continue
        label, unit = describe_param(key) if describe_param else (key, '')
        first = k if kind == 'step' else k - 1  # the first changed recording, or the hinge
        since = _when(times, paths, first)
        scatter = np.sqrt(np.sum((values - fitted) ** 2) / (len(values) - 2))
        evidence = (f'F = {stat:.3g} against {threshold:.3g} (false-alarm rate '
                    f'{FALSE_ALARM_RATE:.0%} per rig and parameter) over {len(points)} '
                    f'recordings; change {abs(end - start):.3g}, scatter {scatter:.2g}, '
                    f'typical standard error {typical:.2g}')
        text = describe(rig, label, unit, kind, start, end, since, _days(times[first], times[-1]))
        alerts.append(Alert(rig, key, kind, since, start, end, evidence, text))
    return alerts
