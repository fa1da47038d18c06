"""What the monitor node says, as messages: its report per channel and the tracked estimates
as diagnostic statuses, and both as tables (``monitor/residuals``, ``monitor/effects``).
Messages are built here; the node publishes them."""
from __future__ import annotations

import math

from diagnostic_msgs.msg import DiagnosticStatus, KeyValue
from std_msgs.msg import Float64MultiArray, MultiArrayDimension

from . import common

#: columns of ``monitor/residuals``, one row per channel (angle, p_a, p_b); SI units
RESIDUAL_FIELDS = ('data_time_s', 'ratio', 'rms', 'floor_rms', 'cusum', 'threshold',
                   'p_value', 'window_p_value', 'z', 'level', 'windows')
#: columns of ``monitor/effects``, one row per tracked parameter; SI units; alert 0/1
EFFECT_FIELDS = ('data_time_s', 'value', 'stderr', 'alert')
LEVEL_NUMBER = {'ok': 0, 'warn': 1, 'error': 2}
#: a channel's report values shown as they are in its status
CHANNEL_VALUES = ('ratio', 'rms', 'floor_rms', 'unit', 'cusum', 'threshold', 'p_value',
                  'window_p_value', 'z', 'windows', 'alarms', 'regime')


def data_time(t_s: float) -> str:
    """A time [s] for a diagnostic value, to the microsecond (or 'nan'): a stamp is ~1.8e9 s,
    and six significant digits would say nothing."""
    return f'{t_s:.6f}' if math.isfinite(t_s) else 'nan'


def table(kind: str, rows: dict, fields: tuple) -> Float64MultiArray:
    """A table as a Float64MultiArray: one row per entry of ``rows`` (named in the first
    dimension's label, ``kind:a,b``), one column per field (NaN where a value is None)."""
    msg = Float64MultiArray()
    names = list(rows)
    msg.layout.dim = [
        MultiArrayDimension(label=f'{kind}:' + ','.join(names), size=len(names),
                            stride=len(names) * len(fields)),
        MultiArrayDimension(label='field:' + ','.join(fields), size=len(fields),
                            stride=len(fields))]
    msg.data = [float(r[f]) if r.get(f) is not None else math.nan
                for r in rows.values() for f in fields]
    return msg


def residual_table(report: dict) -> Float64MultiArray:
    """``monitor/residuals`` of a monitor report."""
    t = report['t_ns'] * 1e-9
    rows = {ch: {**c, 'data_time_s': t, 'level': LEVEL_NUMBER[c['level']]}
            for ch, c in report['channels'].items()}
    return table('channel', rows, RESIDUAL_FIELDS)


def effect_table(estimates: dict) -> Float64MultiArray:
    """``monitor/effects`` of the tracked estimates (key -> estimate)."""
    rows = {k: {'data_time_s': s['t_s'], 'value': s['value'], 'stderr': s['stderr'],
                'alert': 1.0 if s['alert'] else 0.0} for k, s in estimates.items()}
    return table('parameter', rows, EFFECT_FIELDS)


def status(node: str, name: str, level: str, message: str, values: dict) -> DiagnosticStatus:
    """A status ``<node>: <name>`` of the monitor."""
    st = DiagnosticStatus(level=common.LEVELS[level], name=f'{node}: {name}', message=message,
                          hardware_id='monitor')
    st.values = [KeyValue(key=str(k), value=common._fmt(v)) for k, v in values.items()]
    return st


def channel_statuses(node: str, report: dict) -> list[DiagnosticStatus]:
    """``<node>: monitor angle|p_a|p_b``: each channel's level, words and test."""
    out = []
    for ch, c in report['channels'].items():
        values = {k: c[k] for k in CHANNEL_VALUES}
        values['since_s'] = data_time(c['since_ns'] * 1e-9 if c['since_ns'] else math.nan)
        values['data_time_s'] = data_time(report['t_ns'] * 1e-9)
        out.append(status(node, f'monitor {ch}', c['level'], c['message'], values))
    return out


def estimate_statuses(node: str, estimates: dict) -> list[DiagnosticStatus]:
    """``<node>: monitor <effect.parameter>``: each tracked estimate, WARN when it moves."""
    out = []
    for key, s in estimates.items():
        alert = s.get('alert')
        if alert:
            message = alert['text']
        elif s['estimates']:
            message = (f'{s["value"]:.3g} +/- {s["stderr"]:.2g} {s["unit"]} '
                       f'({s["estimates"]} estimates, no change)')
        else:
            message = 'no estimate yet (fitted at the end of the baseline and while a ' \
                      'channel departs)'
        values = {'value': s['value'], 'stderr': s['stderr'], 'unit': s['unit'],
                  'estimates': s['estimates'], 'data_time_s': data_time(s['t_s']),
                  'alert': alert['text'] if alert else '',
                  'alert_p_value': alert['p_value'] if alert else math.nan}
        out.append(status(node, f'monitor {key}', 'warn' if alert else 'ok', message, values))
    return out


#: [s] wall time without a measurement after which the monitor says its verdicts are old
SILENT_S = 5.0


def health(state: str, report: dict, dropped: int, held: str | None, no_commands: bool,
           silent_s: float = 0.0) -> tuple[str, list[str]]:
    """(level, words) of a working monitor: its lifecycle ``state`` and the judge's
    ``report``; WARN when it decimates, drops or misses samples, cannot simulate a window,
    sees the plant hold its valve safe (``held``: the plant's words; None: it does not), gets no
    valve command (``no_commands``) or has heard no measurement for more than
    :data:`SILENT_S` (``silent_s`` [s] of wall time, after hearing some)."""
    level, words = 'ok', [f'{state}: {report.get("state", "starting")}']
    counts = report.get('counts', {})
    if report.get('state') == 'baseline':
        words.append(f'{report.get("baseline_left_s", 0.0):.0f} s of baseline to go')
    departing = [ch for ch, c in report.get('channels', {}).items() if c['level'] != 'ok']
    if departing:
        words.append('departs in ' + ', '.join(departing))
    lost, samples = counts.get('lost', 0), counts.get('samples', 0)
    warnings = [
        (report.get('decimating'),
         f'DECIMATING: judged {counts.get("judged", 0)} of the windows, skipped '
         f'{counts.get("skipped", 0)} (the monitor cannot keep up with the data; the '
         'false-alarm rate only falls)'),
        (dropped, f'dropped {dropped} samples (the judge is behind)'),
        (lost > 0.01 * (lost + samples),
         f'{lost} of {lost + samples} samples missing (lost on the way, or the plant stood '
         'still): windows over them are not judged'),
        (report.get('last_error'),
         f'a window could not be simulated: {report.get("last_error")}'),
        (held is not None, f'the plant holds its valve safe ({held}): the commands do not reach it, '
               'those samples are not judged'),
        (no_commands, 'no valve/command: the model cannot be run (a replay needs '
                      'replay_command:=true)'),
        # the verdicts stay those of the last data: say so, rather than an OK that looks live
        (silent_s > SILENT_S, f'no measurement for {silent_s:.0f} s (the plant stopped, or '
                              'this monitor stopped hearing it): the verdicts are of the data '
                              'before')]
    for when, text in warnings:
        if when:
            level = 'warn'
            words.append(text)
    return level, words
