"""The figure of a recorded monitored run: measured vs model, and the verdicts over time.

Reads a bag recorded with ``pneumatic-servo record --monitor`` (measurements, the model's
k-step predictions under ``model/``, ``/diagnostics``, ``monitor/effects``) with the
package's reader and draws, with matplotlib: the angle and the chamber pressures against the model's
predictions in two short spans (before and after a change), the departure of each channel
in units of its floor with the monitor's level, and the tracked effects' estimates.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

LEVEL_COLOURS = {0: '#e8f5e9', 1: '#fff3cd', 2: '#f8d7da'}
CHANNELS = ('angle', 'p_a', 'p_b')
#: the drawn signals and the topics they are keyed by
SERIES = {'angle_rad': '/joint_states', 'p_a_pa': '/chamber_a/pressure',
          'p_b_pa': '/chamber_b/pressure'}


def read_run(bag) -> dict:
    """The monitored run in a bag: series by topic as (n, 2) arrays of (header stamp [s],
    value), the monitor's statuses and effect estimates by record time [s], and ``t0``, the
    first measurement [s]. Measurements and the model's predictions (the ``model``
    namespace) are read by :func:`pneumatic_servo.io.read_series`, the monitor's own topics
    by :func:`pneumatic_servo.io.bag.read_messages`."""
    from ..io import read_series
    from ..io.bag import read_messages
    series = {}
    for prefix, namespace in (('', None), ('/model', 'model')):
        got, _ = read_series(bag, namespace=namespace)
        for sig, topic in SERIES.items():
            if sig in got:
                stamps, values = got[sig]
                series[prefix + topic] = np.column_stack([stamps * 1e-9, values])
    status: dict = {}
    effects: list = []
    for topic, rec, msg in read_messages(bag, ('/diagnostics', '/monitor/effects')):
        if topic == '/monitor/effects':
            effects.append((rec * 1e-9, msg.layout.dim[0].label, np.array(msg.data)))
            continue
        for st in msg.status:
            if st.hardware_id == 'monitor' and ': monitor ' in st.name:
                values = {kv.key: kv.value for kv in st.values}
                status.setdefault(st.name.split(': monitor ')[1], []).append(
                    (rec * 1e-9, int(st.level), values))
    return {'series': series, 'status': status, 'effects': effects,
            't0': series['/joint_states'][0, 0]}


def _spans(ax, times, levels):
    """Background colour by level between consecutive reports."""
    for a, b, lv in zip(times[:-1], times[1:], levels[:-1]):
        ax.axvspan(a, b, color=LEVEL_COLOURS.get(lv, 'white'), lw=0, zorder=0)


def plot_run(bag, png, change_s: float | None = None, span_s: float = 1.5,
             title: str = '') -> Path:
    """Draw the monitored run in ``bag`` to ``png``. ``change_s`` [s from the first
    measurement]: when something changed (a line, and the second zoom after it)."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    run = read_run(bag)
    s, t0 = run['series'], run['t0']
    fig = plt.figure(figsize=(11, 10))
    grid = fig.add_gridspec(4, 2, height_ratios=[1, 1, 1.1, 0.8], hspace=0.45, wspace=0.18)
    end = s['/joint_states'][-1, 0] - t0
    change = change_s if change_s is not None else end / 2
    zooms = [(change - span_s - 0.5, change - 0.5), (change + 3.0, change + 3.0 + span_s)]
    labels = ('before', 'after')
    for col, (a, b) in enumerate(zooms):
        ax = fig.add_subplot(grid[0, col])
        for topic, style, name in (('/joint_states', 'k-', 'measured'),
                                   ('/model/joint_states', 'C1.', 'model, k-step')):
            d = s.get(topic)
            if d is None:
                continue
            m = (d[:, 0] - t0 >= a) & (d[:, 0] - t0 <= b)
            ax.plot(d[m, 0] - t0, np.degrees(d[m, 1]), style, ms=1.5, lw=1, label=name)
        ax.set_title(f'angle, {labels[col]} the change', fontsize=10)
        ax.set_ylabel('deg')
        ax.legend(fontsize=8, loc='best')
        ax = fig.add_subplot(grid[1, col])
        for topic, style, name in (('/chamber_a/pressure', 'k-', 'p_a measured'),
                                   ('/model/chamber_a/pressure', 'C1.', 'p_a model'),
                                   ('/chamber_b/pressure', 'C7-', 'p_b measured'),
                                   ('/model/chamber_b/pressure', 'C2.', 'p_b model')):
            d = s.get(topic)
            if d is None:
                continue
            m = (d[:, 0] - t0 >= a) & (d[:, 0] - t0 <= b)
            ax.plot(d[m, 0] - t0, d[m, 1] * 1e-3, style, ms=1.5, lw=1, label=name)
        ax.set_title(f'chamber pressures, {labels[col]} the change', fontsize=10)
        ax.set_ylabel('kPa (absolute)')
        ax.set_xlabel('time [s]')
        ax.legend(fontsize=7, loc='best', ncol=2)
    ax = fig.add_subplot(grid[2, :])
    worst_t, worst_lv = None, None
    for i, ch in enumerate(CHANNELS):
        rows = run['status'].get(ch, [])
        pts = [(float(v['data_time_s']) - t0, float(v['ratio']), lv) for _, lv, v in rows
               if v.get('data_time_s', 'nan') != 'nan' and v.get('ratio', 'nan') != 'nan']
        if not pts:
            continue
        t, r, lv = map(np.array, zip(*pts))
        ax.semilogy(t, r, '-', color=f'C{i}', lw=1.3, label=f'{ch}')
        if worst_lv is None:
            worst_t, worst_lv = t, lv
        else:
            n = min(len(worst_lv), len(lv))
            worst_t, worst_lv = worst_t[:n], np.maximum(worst_lv[:n], lv[:n])
    if worst_t is not None and len(worst_t) > 1:
        _spans(ax, worst_t, worst_lv)
    ax.axhline(1.0, color='grey', lw=0.8, ls=':')
    if change_s is not None:
        ax.axvline(change_s, color='k', lw=0.8, ls='--')
    ax.set_ylabel('departure [x floor]')
    ax.set_title('the monitor: each channel\'s residual in units of its floor (last 10 s); '
                 'background: OK / WARN / ERROR (worst channel)', fontsize=10)
    ax.legend(fontsize=8, loc='upper left')
    ax.set_xlim(0, end)
    ax = fig.add_subplot(grid[3, :], sharex=ax)
    if run['effects']:
        keys = run['effects'][-1][1].split(':', 1)[1].split(',')
        for j, key in enumerate(keys):
            pts = [(d[4 * j], d[4 * j + 1], d[4 * j + 2], d[4 * j + 3]) for _, _, d in
                   run['effects'] if np.isfinite(d[4 * j])]
            if not pts:
                continue
            t, v, e, alert = map(np.array, zip(*pts))
            t = t - t0
            ax.errorbar(t, v, yerr=np.where(np.isfinite(e), e, 0.0), fmt='o', ms=5,
                        color=f'C{j + 3}', label=f'{key} (+/- its standard error)')
            if alert.any():
                ax.plot(t[alert > 0], v[alert > 0], 'r*', ms=11, label='alert (a step)')
        ax.legend(fontsize=8, loc='upper left')
    if change_s is not None:
        ax.axvline(change_s, color='k', lw=0.8, ls='--')
    ax.set_ylabel('tracked estimate [m^2]')
    ax.set_xlabel('time [s]')
    ax.set_title('which effect: the tracked parameter, fitted at the baseline and while a '
                 'channel departs', fontsize=10)
    if title:
        fig.suptitle(title, fontsize=11)
    fig.savefig(png, dpi=100, bbox_inches='tight')
    plt.close(fig)
    return Path(png)
