"""Fleet alerts: false-alarm and detection rates of the change test, by simulation.

1. False-alarm rate per series length (3..12 recordings) of healthy rigs (no change,
   Gaussian scatter), with honest standard errors, optimistic ones (true scatter 1.5x and
   2x the reported standard error) and none reported; target <= 1 % per rig and parameter.
2. Where the rule's assumption (no standard error optimistic by more than 10x) fails: the
   rate at 5x .. 1000x, for a rig alone and beside 2 or 9 healthy rigs like it.
3. Detection rate of a trend of 50 and 100 standard errors (first to last recording) from
   3, 4 and 5 recordings; target: 100 standard errors alert (>= 99 %).
4. The issue-15 example: 4 daily fits of a growing seal leak.

Standard errors vary by a factor exp(N(0, 0.3)) from recording to recording. Pure numpy,
about half a minute; the machine's load is printed (shared cores).

Usage: ``python benchmarks/bench_alerts.py [--trials 4000]``
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from pneumatic_servo.fleet.alerts import (FALSE_ALARM_RATE, STDERR_TRUST_FACTOR,  # noqa: E402
                                          judge_series, stderr_fit)

DETECT_TARGET = 0.99
STDERR_M2 = 1e-10       # a seal leak area's standard error of one recording [m^2]
LEVEL_M2 = 2e-9         # a healthy rig's leak area [m^2]


def series(rng, n: int, optimism: float, missing: float = 0.0, change_stderr: float = 0.0):
    """One rig's fitted values [m^2] and standard errors [m^2] over ``n`` days: true scatter
    ``optimism`` x the standard error, a linear rise of ``change_stderr`` standard errors from
    the first to the last day, a share ``missing`` of standard errors not reported."""
    stderr = STDERR_M2 * np.exp(rng.normal(0.0, 0.3, n))
    rise = change_stderr * STDERR_M2 * np.arange(n) / (n - 1)
    values = LEVEL_M2 + rise + optimism * stderr * rng.normal(size=n)
    stderr[rng.random(n) < missing] = np.nan
    return values, stderr


def fleet_scatter(rng, n: int, optimism: float, rigs: int):
    """The pooled scatter (``stderr_fit``) of ``rigs`` healthy rigs like the one judged."""
    if rigs == 0:
        return None
    found = [stderr_fit(np.arange(n, dtype=float), *series(rng, n, optimism))[1]
             for _ in range(rigs)]
    return sum(f[0] for f in found), sum(f[1] for f in found)


def alert_rate(rng, trials: int, n: int, optimism: float, missing: float = 0.0,
               change_stderr: float = 0.0, other_rigs: int = 0) -> float:
    """Share of ``trials`` simulated rigs that raise an alert."""
    x = np.arange(n, dtype=float)
    alerts = 0
    for _ in range(trials):
        values, stderr = series(rng, n, optimism, missing, change_stderr)
        others = fleet_scatter(rng, n, optimism, other_rigs)
        alerts += judge_series(x, values, stderr, others) is not None
    return alerts / trials


def verdict(ok: bool) -> str:
    return 'met' if ok else 'MISSED'


def false_alarms(rng, trials: int) -> None:
    cases = (('honest', 1.0, 0.0), ('1.5x optimistic', 1.5, 0.0),
             ('2x optimistic', 2.0, 0.0), ('none reported', 1.0, 1.0))
    sd = np.sqrt(FALSE_ALARM_RATE * (1 - FALSE_ALARM_RATE) / trials)
    print(f'\n1. false-alarm rate of healthy rigs, {trials} series per cell (sampling sd '
          f'{sd:.2%} at 1 %); target <= {FALSE_ALARM_RATE:.0%}')
    print(f'  {"recordings":>10} ' + ' '.join(f'{name:>16}' for name, *_ in cases))
    worst = 0.0
    for n in range(3, 13):
        rates = [alert_rate(rng, trials, n, optimism, missing) for _, optimism, missing in cases]
        worst = max(worst, *rates)
        print(f'  {n:>10} ' + ' '.join(f'{r:>16.2%}' for r in rates))
    print(f'  worst cell {worst:.2%} (target <= {FALSE_ALARM_RATE:.0%} + 3 sd = '
          f'{FALSE_ALARM_RATE + 3 * sd:.2%}: {verdict(worst <= FALSE_ALARM_RATE + 3 * sd)})')


def beyond_assumption(rng, trials: int) -> None:
    print(f'\n2. beyond the assumption: true scatter > {STDERR_TRUST_FACTOR:g}x the standard '
          f'error (no target; {trials // 2} series per cell)')
    print(f'  {"scatter / stderr":>16} {"n":>2} {"rig alone":>10} {"+2 rigs":>8} '
          f'{"+9 rigs":>8}')
    for optimism in (5.0, 10.0, 15.0, 20.0, 30.0, 50.0, 1000.0):
        for n in (3, 4, 5):
            rates = [alert_rate(rng, trials // 2, n, optimism, other_rigs=rigs)
                     for rigs in (0, 2, 9)]
            print(f'  {optimism:>16g} {n:>2} ' + ' '.join(f'{r:>{w}.2%}' for r, w in
                                                       zip(rates, (10, 8, 8))))


def detection(rng, trials: int) -> None:
    print(f'\n3. detection of a linear rise (first to last recording), {trials} series per '
          f'cell; target: 100 standard errors alert in >= {DETECT_TARGET:.0%}')
    print(f'  {"rise":>12} {"scatter / stderr":>16} ' + ' '.join(f'{f"n = {n}":>8}'
                                                              for n in (3, 4, 5)))
    for change in (50.0, 100.0):
        for optimism in (1.0, 2.0):
            rates = [alert_rate(rng, trials, n, optimism, change_stderr=change)
                     for n in (3, 4, 5)]
            mark = (f'  ({verdict(min(rates) >= DETECT_TARGET)})' if change == 100.0 else '')
            print(f'  {change:>8g} s.e. {optimism:>16g} ' + ' '.join(f'{r:>8.1%}'
                                                                   for r in rates) + mark)


def issue_example() -> None:
    values = np.array([0.0, 3.8e-9, 8.1e-9, 1.4e-8])
    change = judge_series(np.arange(4.0), values, np.full(4, 1e-10))
    found = (f'{change.kind} from {change.start:.2g} to {change.end:.2g} m^2, p = '
             f'{change.p_value:.1e} ({change.basis} test)' if change else 'no alert')
    print(f'\n4. issue 15: seal leak 0, 3.8e-9, 8.1e-9, 1.4e-8 m^2, standard errors 1e-10 '
          f'm^2: {found} (target: an alert: {verdict(change is not None)})')


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--trials', type=int, default=4000, help='series per cell')
    args = parser.parse_args(argv)
    load = os.getloadavg()
    print(f'machine: {os.cpu_count()} cores, load average {load[0]:.2f} {load[1]:.2f} '
          f'{load[2]:.2f} (1, 5, 15 min)')
    rng = np.random.default_rng(2026)
    t0 = time.perf_counter()
    false_alarms(rng, args.trials)
    beyond_assumption(rng, args.trials)
    detection(rng, args.trials // 4)
    issue_example()
    print(f'\n{time.perf_counter() - t0:.1f} s')
    return 0


if __name__ == '__main__':
    sys.exit(main())
