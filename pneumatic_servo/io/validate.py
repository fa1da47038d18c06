"""Checks that a recorded signal is fit for analysis, each failing with one line that
names the topic, the place and the fix.

A series is the (stamps, values) of one signal as recorded, before resampling.
"""
from __future__ import annotations

import numpy as np

from ..errors import ExperimentError

#: a gap is a stamp interval longer than this many median intervals ...
GAP_FACTOR = 20.0
#: ... and longer than this [s] (so jitter on a fast topic is not a gap)
MIN_GAP_S = 0.02


def _at(stamps_ns: np.ndarray, i: int, t0_ns: int) -> str:
    return f't = {(int(stamps_ns[i]) - t0_ns) * 1e-9:.4f} s (message {i + 1})'


def check_finite(where: str, name: str, stamps_ns: np.ndarray, values: np.ndarray,
                 t0_ns: int) -> None:
    """Raise if ``values`` holds NaN or inf."""
    bad = ~np.isfinite(values)
    if bad.any():
        i = int(np.argmax(bad))
        raise ExperimentError(
            f'{where}: {name} is {values[i]} at {_at(stamps_ns, i, t0_ns)} and in '
            f'{int(bad.sum())} sample(s) in all; drop or repair those messages before analysis')


def check_stamps(where: str, topic: str, stamps_ns: np.ndarray, t0_ns: int,
                 source: str, ties: bool = False) -> None:
    """Raise if the stamps of ``topic`` go backwards or repeat. ``ties``: record stamps may
    repeat (messages kept in record order, never resampled): a recorder on sim time stamps
    two messages that arrive within one clock tick alike."""
    if len(stamps_ns) < 2:
        return
    d = np.diff(stamps_ns)
    fix = ("pass time_source='record' to time every topic by its record time"
           if source == 'header' else 're-record with a monotonic clock')
    if (d < 0).any():
        i = int(np.argmax(d < 0)) + 1
        raise ExperimentError(
            f'{where}: {topic} {source} stamps go backwards at {_at(stamps_ns, i, t0_ns)}, '
            f'by {-int(d[i - 1]) * 1e-9:.6f} s; {fix}')
    if (d == 0).any() and not (ties and source == 'record'):
        n = int((d == 0).sum())
        i = int(np.argmax(d == 0)) + 1
        hint = ' (header.stamp never set?)' if n == len(d) else ''
        raise ExperimentError(
            f'{where}: {topic} has {n} duplicated {source} stamp(s){hint}, first at '
            f'{_at(stamps_ns, i, t0_ns)}; {fix}')


def median_period_ns(stamps_ns: np.ndarray) -> float:
    """Median stamp interval [ns] (nan for fewer than two stamps)."""
    if len(stamps_ns) < 2:
        return float('nan')
    return float(np.median(np.diff(stamps_ns)))


def check_gaps(where: str, topic: str, stamps_ns: np.ndarray, t0_ns: int,
               max_gap_s: float | None) -> None:
    """Raise if ``topic`` has a stamp interval longer than ``max_gap_s`` [s].

    The default limit is the longer of ``GAP_FACTOR`` median intervals and
    ``MIN_GAP_S``.
    """
    if len(stamps_ns) < 3:
        return
    d = np.diff(stamps_ns)
    limit_ns = (max(GAP_FACTOR * float(np.median(d)), MIN_GAP_S * 1e9) if max_gap_s is None
                else max_gap_s * 1e9)
    if (d > limit_ns).any():
        i = int(np.argmax(d))
        raise ExperimentError(
            f'{where}: {topic} has a {d[i] * 1e-9:.3f} s gap after {_at(stamps_ns, i, t0_ns)} '
            f'(limit {limit_ns * 1e-9:.3f} s); pass max_gap_s={d[i] * 1e-9 * 1.5:.3g} to '
            'interpolate across it, or analyse the parts before and after separately')


def check_count(where: str, topic: str, expected: int, found: int) -> None:
    """Raise if the storage holds fewer (or more) messages than the bag's index lists."""
    if expected and found != expected:
        raise ExperimentError(
            f'{where}: metadata lists {expected} messages on {topic} but the storage holds '
            f'{found}: the bag is truncated or was not closed; re-record it, or rebuild its '
            'index with `ros2 bag reindex` if a partial record is acceptable')


# --------------------------------------------------------------------- physical ranges
#: signal -> (lowest, highest) physically possible value [SI], and what it is
PHYSICAL = {
    'p_a_pa': (2e4, 3e6, 'chamber_a/pressure'),
    'p_b_pa': (2e4, 3e6, 'chamber_b/pressure'),
    'supply_pa': (1.1e5, 3e6, 'supply/pressure'),
    'angle_rad': (-0.5, 7.0, 'joint_states position'),
    'velocity_rad_s': (-200.0, 200.0, 'joint_states velocity'),
    't_a_k': (150.0, 500.0, 'chamber_a/temperature'),
    't_b_k': (150.0, 500.0, 'chamber_b/temperature'),
    't_s_k': (150.0, 500.0, 'supply temperature'),
    'command_v': (-1.0, 11.0, 'valve/command'),
    'm4_kg_s': (0.0, 0.1, 'port-4 mass flow'),
    'm5_kg_s': (0.0, 0.1, 'port-5 mass flow'),
    'setpoint_rad': (-0.5, 7.0, 'setpoint'),
}


def _likely_cause(sig: str, lo: float, hi: float) -> str:
    """What a reading outside the physical range most likely is, from its range of values."""
    if sig.endswith('_pa'):
        if lo < 0.0 and hi < 1.3e6:
            return ('an absolute pressure is never negative: gauge readings (or a transmitter '
                    'offset)? the contract is absolute Pa (add 101325 to gauge)')
        if hi < 2e4 and lo > 10.0:
            return 'looks like kPa; the contract is absolute Pa'
        if hi < 50.0:
            return 'looks like MPa or bar; the contract is absolute Pa'
        if lo < 2e4 and hi < 1.3e6:
            return 'looks like gauge pressure; the contract is absolute Pa (add 101325)'
        return 'no rig reaches that; check the transmitter scaling'
    if sig in ('angle_rad', 'setpoint_rad') and 7.0 < hi <= 400.0:
        return 'looks like degrees; the contract is rad'
    if sig.endswith('_k') and hi < 150.0:
        return 'looks like degrees Celsius; the signal is in K'
    if sig.startswith('m') and lo < 0.0:
        return 'a flow out of the port cannot be negative; check the meter\'s sign'
    if sig == 'command_v':
        return 'the valve takes 0-10 V; record the command after the output gate'
    return 'check the sensor scaling'


def check_physical(where: str, signals: dict, metadata: dict | None = None) -> None:
    """Raise if a signal (or the held angle of a blocked record) is outside what a rig can
    show, or if the signals together are impossible for the whole record (see
    :func:`check_consistent`), naming the likely cause (a unit, gauge instead of absolute
    pressure)."""
    _check_ranges(where, signals)
    held = (metadata or {}).get('blocked_angle_rad')
    if held is not None:
        try:
            ok = 0.0 <= float(held) <= 6.5
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ExperimentError(f'{where}: blocked_angle_rad = {held!r} in the custom data; '
                                  'give the angle the pistons are held at, 0 to 6.5 rad')
    check_consistent(where, {sig: (None, v) for sig, v in signals.items()})


def check_series(where: str, series: dict, metadata: dict | None = None) -> None:
    """:func:`check_physical` for measurements on their own stamps, ``{signal: (stamps [ns],
    values)}`` as :func:`~pneumatic_servo.io.read_series` gives them (a replay): the ranges
    on every value, the checks across signals with each compared at the other's stamps."""
    _check_ranges(where, {sig: values for sig, (_, values) in series.items()})
    check_consistent(where, series)


def _check_ranges(where: str, signals: dict) -> None:
    for sig, (low, high, what) in PHYSICAL.items():
        values = signals.get(sig)
        if values is None or not len(values):
            continue
        lo, hi = float(np.min(values)), float(np.max(values))
        if lo < low or hi > high:
            raise ExperimentError(
                f'{where}: {what} is {lo:.4g} to {hi:.4g} ({sig}), outside the possible '
                f'{low:g} to {high:g}: {_likely_cause(sig, lo, hi)}')


# ------------------------------------------------------------ consistency across signals
#: [Pa] the standard atmosphere: a chamber is vented to it or charged above it
ATMOSPHERE_PA = 101325.0
#: a chamber reads above the supply in every sample by more than this fraction of the supply
#: plus ``ABOVE_SUPPLY_PA`` [Pa] (transmitter noise and offsets are ~0.1-0.5 % of full scale)
ABOVE_SUPPLY_FRACTION, ABOVE_SUPPLY_PA = 0.005, 2000.0
_CHAMBERS = (('p_a_pa', 'chamber_a/pressure'), ('p_b_pa', 'chamber_b/pressure'))


def check_consistent(where: str, series: dict) -> None:
    """Raise if the signals together are impossible for the whole record, where each alone is
    within its range. ``series``: ``{signal: (stamps or None, values)}`` (None: all on one
    time base).

    Only whole-record conditions are refused; each can happen for a moment and is then
    legitimate:

    * every recorded chamber below the atmosphere in every sample: a chamber is vented to the
      atmosphere or charged above it; it pulls a vacuum only briefly, in a fast move. Readings
      gauge, recorded as absolute, look like this.
    * a chamber above the supply in every sample: gas reaches a chamber only from the supply
      (a chamber held while the supply drops, or compressed by a fast move, is above it for a
      while). A supply recorded as gauge beside absolute chambers, or swapped topics, look
      like this.
    """
    chambers = [(sig, what) for sig, what in _CHAMBERS
                if sig in series and len(series[sig][1])]
    if chambers and all(float(np.max(series[sig][1])) < ATMOSPHERE_PA for sig, _ in chambers):
        seen = ' and '.join(f'{what} {float(np.min(series[sig][1])) / 1e3:.4g} to '
                            f'{float(np.max(series[sig][1])) / 1e3:.4g} kPa'
                            for sig, what in chambers)
        raise ExperimentError(
            f'{where}: {seen}: below the atmosphere ({ATMOSPHERE_PA:g} Pa) in every sample, '
            'which no chamber is for a whole record (it is vented or charged): gauge readings? '
            'the contract is absolute Pa; add the atmospheric pressure to the readings')
    if 'supply_pa' not in series or not len(series['supply_pa'][1]):
        return
    s_stamps, supply = series['supply_pa']
    for sig, what in chambers:
        stamps, values = series[sig]
        if stamps is not None and s_stamps is not None:
            if len(s_stamps) < 2:
                continue
            supply_at = np.interp(stamps, s_stamps, supply)
        elif stamps is None and s_stamps is None and len(supply) == len(values):
            supply_at = supply
        else:
            continue
        excess = values - supply_at
        margin = ABOVE_SUPPLY_FRACTION * supply_at + ABOVE_SUPPLY_PA
        if len(excess) and np.all(excess > margin):
            raise ExperimentError(
                f'{where}: {what} is above supply/pressure in every sample (by '
                f'{float(np.min(excess)) / 1e3:.4g} to {float(np.max(excess)) / 1e3:.4g} kPa), '
                'which no chamber is for a whole record (it is fed from the supply): the '
                'supply recorded as gauge? the contract is absolute Pa for both; add the '
                'atmospheric pressure to the supply readings, or check that the topics (CSV '
                'columns) are not swapped')
