"""Alerts: a tracked parameter of a rig that rises, falls or steps beyond its uncertainty.

For each rig and parameter, the estimates in time order are compared under three least-
squares models: constant, a step (one level before, another after), and a trend that
starts at some recording (constant, then a straight line: "since when?"). The step and
the trend are tried at every change point with at least ``MIN_AFTER`` recordings after
it; each adds one parameter to the constant. An alert needs a change significant at
``FALSE_ALARM_RATE`` (1 %) per rig and parameter, Bonferroni over the ``m`` tries and over
the tests applied, and larger than ``MIN_CHANGE_STDERR`` typical standard errors:

- **scatter test** (every series of ``MIN_POINTS`` = 3 or more): the scatter is measured
  from the series, ``F = (RSS_const - RSS_change) / (RSS_change / (n - 2))`` follows
  F(1, n - 2) under a healthy rig whatever the size of its scatter and whatever the fits'
  standard errors say. From ``MIN_SCATTER_POINTS`` = 5 recordings it is the only test.
- **stderr test** (3 or 4 recordings, at least 3 of them with a standard error, finite and
  positive): 1 or 2 degrees of freedom measure no scatter, so the fits' standard errors
  stand for it, each widened ``STDERR_TRUST_FACTOR`` (10) times: the weighted
  ``RSS_const - RSS_change`` follows chi-square(1) while no standard error is optimistic by
  more than that. The two tests share the 1 % (0.5 % each). The widened standard errors
  are set aside where the scatter measured about the best change, on this series or pooled
  over the same parameter on the fleet's other rigs, is the larger sigma.

Rates measured by ``benchmarks/bench_alerts.py`` (and checked in ``tests/test_fleet.py``)
are in ``docs/fleet.md``, with where the rule's assumption fails.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass
from datetime import datetime

import numpy as np
from scipy.special import chdtrc, fdtrc
from scipy.stats import f as f_dist

from .row import Row

#: probability that a healthy rig's parameter raises an alert in one run
FALSE_ALARM_RATE = 0.01
#: recordings needed after a change point (a single odd recording is not a change)
MIN_AFTER = 2
#: recordings needed before one looks for a change at all (one before a change, two after)
MIN_POINTS = 3
#: from this many recordings on, a series measures its own scatter well enough (3 degrees
#: of freedom) and is judged by the scatter test alone, valid whatever its standard errors
MIN_SCATTER_POINTS = 5
#: a change must exceed this many typical standard errors of one estimate
MIN_CHANGE_STDERR = 2.0
#: a reported standard error is trusted as an uncertainty to within this factor (one
#: order of magnitude): the stderr test takes this many standard errors as the sigma of
#: each recording. Not fitted to any data; docs/fleet.md gives what it costs and buys.
STDERR_TRUST_FACTOR = 10.0


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
    p_value: float = float('nan')  # chance of a change this clear on a healthy rig (bound)
    sigma: float = float('nan')    # [SI] scatter of one recording the test assumed
    basis: str = ''                # 'stderr' or 'scatter': which test found it

    def to_json(self) -> dict:
        out = asdict(self)
        out['from'] = out.pop('from_value')
        out['to'] = out.pop('to_value')
        return out


@dataclass
class Change:
    """The clearest change in one series and the test that judged it."""

    kind: str            # 'step' or 'trend'
    index: int           # first recording after a step; the recording after a trend's hinge
    fitted: np.ndarray   # [SI] the change model's values at the recordings it was fitted to
    points: np.ndarray   # indices of those recordings in the series
    statistic: float     # F, or the chi-square of the widened standard errors
    p_value: float       # Bonferroni bound over the tries and the tests
    sigma: float         # [SI] typical scatter of one recording the test assumed
    basis: str           # 'scatter' or 'stderr'
    tries: int           # change models tried (steps and trends)

    @property
    def start(self) -> float:
        return float(self.fitted[0])

    @property
    def end(self) -> float:
        return float(self.fitted[-1])


def change_columns(x: np.ndarray) -> tuple[list[str], list[int], np.ndarray]:
    """The alternatives to a constant at times ``x`` [days]: (kinds, change indices, one
    column per try). A step's column is 0 before recording k and 1 from it on; a trend's is
    flat up to recording k-1 and then rises with time."""
    n = len(x)
    kinds, indices, columns = [], [], []
    for k in range(1, n - MIN_AFTER + 1):
        kinds += ['step', 'trend']
        indices += [k, k]
        columns += [(np.arange(n) >= k).astype(float), np.maximum(x - x[k - 1], 0.0)]
    return kinds, indices, np.column_stack(columns)


def fit_all(values: np.ndarray, weights: np.ndarray, columns: np.ndarray):
    """Weighted least squares of ``values`` on [1, column] for every column at once:
    (fitted values, one column per try; weighted residual sums; that of the constant)."""
    share = weights / weights.sum()
    mean_value = share @ values
    centred = columns - share @ columns
    spread = share @ centred ** 2
    covariance = (share * (values - mean_value)) @ centred
    # a column constant over the recordings (equal times) explains nothing
    slope = np.divide(covariance, spread, out=np.zeros_like(spread), where=spread > 0)
    fitted = mean_value + centred * slope
    rss = weights @ (values[:, None] - fitted) ** 2
    return fitted, rss, float(weights @ (values - mean_value) ** 2)


def _best(x: np.ndarray, values: np.ndarray, weights: np.ndarray, statistic
          ) -> tuple[Change, float]:
    """The try with the largest ``statistic(rss_const - rss, rss)`` (weighted least
    squares), its p-value, sigma and basis still to be set; and its weighted RSS."""
    kinds, indices, columns = change_columns(x)
    fitted, rss, rss_const = fit_all(values, weights, columns)
    stat = statistic(np.maximum(rss_const - rss, 0.0), rss)
    j = int(np.argmax(stat))
    return Change(kinds[j], indices[j], fitted[:, j], np.arange(len(values)), float(stat[j]),
                  float('nan'), float('nan'), '', len(kinds)), float(rss[j])


def scatter_test(x: np.ndarray, values: np.ndarray, tests: int = 1) -> Change:
    """The F test, the scatter measured from the series: valid whatever the standard
    errors. ``tests``: how many tests judge the series (for the Bonferroni bound)."""
    dof = len(values) - 2
    change, rss = _best(x, values, np.ones(len(values)),
                        lambda gain, rss: gain / np.maximum(rss / dof, 1e-300))  # perfect: huge
    change.p_value = min(1.0, float(fdtrc(1, dof, change.statistic)) * change.tries * tests)
    change.sigma, change.basis = float(np.sqrt(rss / dof)), 'scatter'
    return change


def best_change(x: np.ndarray, values: np.ndarray, alpha: float = FALSE_ALARM_RATE):
    """The scatter test's most significant change: (kind, index of the change, fitted values,
    F, threshold at false-alarm rate ``alpha``), ``x`` the times [days] of ``values``."""
    change = scatter_test(x, values)
    threshold = float(f_dist.isf(alpha / change.tries, 1, len(values) - 2))
    return change.kind, change.index, change.fitted, change.statistic, threshold


def stderr_fit(x: np.ndarray, values: np.ndarray, stderr: np.ndarray, tests: int = 1
               ) -> tuple[Change, tuple[float, int]]:
    """The chi-square test with ``STDERR_TRUST_FACTOR`` x ``stderr`` [SI] as each
    recording's known sigma, and the series' scatter about its best change in those units:
    (weighted residual sum, degrees of freedom), whose mean square is 1 or less on average
    where the widened standard errors hold."""
    sigma = STDERR_TRUST_FACTOR * stderr
    change, rss = _best(x, values, 1.0 / sigma ** 2, lambda gain, rss: gain)
    scatter = (rss, len(values) - 2)
    change.p_value = min(1.0, float(chdtrc(1, change.statistic)) * change.tries * tests)
    change.sigma, change.basis = float(np.median(sigma)), 'stderr'
    return change, scatter


def consistent(scatter: tuple[float, int] | None) -> bool:
    """Whether a measured scatter (``stderr_fit``: weighted residual sum, degrees of
    freedom) is no larger than the widened standard errors, i.e. their mean square is at
    most 1: ``STDERR_TRUST_FACTOR`` x stderr is still the larger of the two sigmas.
    None (nothing measured) or no degree of freedom: yes."""
    return scatter is None or scatter[1] < 1 or scatter[0] <= scatter[1]


def stderr_test(x: np.ndarray, values: np.ndarray, stderr: np.ndarray, tests: int,
                others: tuple[float, int] | None = None) -> Change | None:
    """``stderr_fit``'s change, or None when the widened standard errors are smaller than
    the scatter of this series or of the same parameter on the fleet's other rigs
    (``others``: their pooled scatter from ``stderr_fit``): then they are no uncertainty."""
    change, own = stderr_fit(x, values, stderr, tests)
    return change if consistent(own) and consistent(others) else None


def trusted_stderr(stderr: np.ndarray) -> np.ndarray:
    """Which standard errors [SI] can stand for an uncertainty: finite and positive (a fit
    reports none, or zero, where the recording does not determine the parameter)."""
    with np.errstate(invalid='ignore'):
        return np.isfinite(stderr) & (stderr > 0)


def typical_stderr(stderr: np.ndarray) -> float:
    """The median of the trusted standard errors [SI]; 0 if there is none."""
    trusted = trusted_stderr(stderr)
    return float(np.median(stderr[trusted])) if trusted.any() else 0.0


def judge_series(x, values, stderr=None, others: tuple[float, int] | None = None
                 ) -> Change | None:
    """The change in one rig's parameter that is significant at ``FALSE_ALARM_RATE``, or
    None: ``values`` [SI] in time order at times ``x`` [days], each with its fit's standard
    error ``stderr`` [SI] (NaN where none); ``others`` the pooled scatter (``stderr_fit``) of
    the same parameter on the fleet's other rigs (None: no other rig)."""
    x = np.asarray(x, dtype=float)
    values = np.asarray(values, dtype=float)
    stderr = (np.full(len(values), np.nan) if stderr is None
              else np.asarray(stderr, dtype=float))
    if len(values) < MIN_POINTS:
        return None
    trusted = trusted_stderr(stderr)
    # which tests apply depends on the length and on which standard errors exist, never
    # on the values: so the Bonferroni count is fixed before looking
    tests = 2 if len(values) < MIN_SCATTER_POINTS and trusted.sum() >= MIN_POINTS else 1
    found = [scatter_test(x, values, tests)]
    if tests == 2:
        subset = np.flatnonzero(trusted)
        by_stderr = stderr_test(x[subset], values[subset], stderr[subset], tests, others)
        if by_stderr is not None:
            by_stderr.points = subset
            by_stderr.index = int(subset[by_stderr.index])
            found.append(by_stderr)
    change = min(found, key=lambda c: c.p_value)
    if change.p_value > FALSE_ALARM_RATE or abs(change.end - change.start) <= (
            MIN_CHANGE_STDERR * typical_stderr(stderr)):
        return None
    return change


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


def _evidence(change: Change, n: int, typical: float) -> str:
    test = ('F' if change.basis == 'scatter'
            else f'chi-square with {STDERR_TRUST_FACTOR:g} x the standard errors as sigma')
    return (f'{test} = {change.statistic:.3g}, p = {change.p_value:.2g} against '
            f'{FALSE_ALARM_RATE:.0%} (false-alarm rate per rig and parameter) over {n} '
            f'recordings; change {abs(change.end - change.start):.3g}, sigma of one '
            f'recording {change.sigma:.2g} ({change.basis}), typical standard error '
            f'{typical:.2g}')


@dataclass
class Series:
    """One rig's estimates of one parameter in time order."""

    times: list          # ISO start times (None where unknown)
    paths: list
    values: np.ndarray   # [SI]
    stderr: np.ndarray   # [SI], NaN where the fit gave none

    @property
    def x(self) -> np.ndarray:
        """Times [days], or recording numbers where a time is missing."""
        if all(self.times):
            return np.array([datetime.fromisoformat(t).timestamp() / 86400
                             for t in self.times])
        return np.arange(len(self.values), dtype=float)

    def scatter(self) -> tuple[float, int] | None:
        """``stderr_fit``'s scatter over the recordings with a standard error; None if
        too few have one."""
        ok = trusted_stderr(self.stderr)
        if ok.sum() < MIN_POINTS:
            return None
        return stderr_fit(self.x[ok], self.values[ok], self.stderr[ok])[1]


def collect_series(rows: list[Row]) -> dict[tuple[str, str], Series]:
    """``(rig, key) -> Series`` of the tracked parameters of the ok rows."""
    points: dict[tuple[str, str], list] = {}
    for row in rows:
        if row.status != 'ok':
            continue
        for key, est in row.params.items():
            if est.get('value') is None:
                continue
            points.setdefault((row.rig, key), []).append(
                (row.start_time or '', row.path, est['value'],
                 np.nan if est.get('stderr') is None else est['stderr']))
    series = {}
    for name, pts in points.items():
        pts.sort()
        series[name] = Series([p[0] or None for p in pts], [p[1] for p in pts],
                              np.array([p[2] for p in pts], dtype=float),
                              np.array([p[3] for p in pts], dtype=float))
    return series


def pool_others(scatters: dict[tuple[str, str], tuple[float, int] | None],
                rig: str, key: str) -> tuple[float, int] | None:
    """The scatter (``stderr_fit``) of ``key`` summed over the fleet's rigs other than ``rig``
    (chi-square sums add, as do their degrees of freedom); None if none has one."""
    found = [s for (r, k), s in scatters.items() if k == key and r != rig and s is not None]
    if not found:
        return None
    return sum(s[0] for s in found), sum(s[1] for s in found)


def detect_alerts(rows: list[Row], describe_param=None) -> list[Alert]:
    """Alerts over the tracked parameters of ``rows`` (:class:`~.row.Row`, those with
    ``status`` ok).

    ``describe_param(key) -> (label, unit)`` names a parameter for the alert text
    (default: its key, SI).
    """
    series = collect_series(rows)
    # how the other rigs scatter against their standard errors tells whether this
    # parameter's standard errors can be trusted on a series too short to tell by itself
    scatters = {name: s.scatter() for name, s in series.items()}
    alerts = []
    for (rig, key), s in sorted(series.items()):
        change = judge_series(s.x, s.values, s.stderr, pool_others(scatters, rig, key))
        if change is None:
            continue
        label, unit = describe_param(key) if describe_param else (key, '')
        # the first changed recording, or the hinge (the last one on the flat part)
        first = change.index if change.kind == 'step' else int(
            change.points[np.searchsorted(change.points, change.index) - 1])
        since = _when(s.times, s.paths, first)
        text = describe(rig, label, unit, change.kind, change.start, change.end, since,
                        _days(s.times[first], s.times[-1]))
        alerts.append(Alert(rig, key, change.kind, since, change.start, change.end,
                            _evidence(change, len(s.values), typical_stderr(s.stderr)), text,
                            change.p_value, change.sigma, change.basis))
    return alerts
