"""The fleet page: the alerts first, the pass/fail table, and each tracked parameter over
time per rig with its uncertainty band. One self-contained HTML file, PNGs embedded."""
from __future__ import annotations

import html
from datetime import datetime
from pathlib import Path

import numpy as np

from ..analysis.html import fmt, img, page, table
from ..analysis.plots import _plt, _save
from .row import Row
from .task import diagnosis_text


def _plot_parameter(out_dir: Path, key: str, label: str, unit: str, rows: list[Row],
                    alerted: set[str], name: str) -> str:
    plt = _plt()
    fig, ax = plt.subplots(figsize=(9, 3.6))
    rigs = sorted({r.rig for r in rows if key in r.params})
    for rig in rigs:
        pts = sorted((r.start_time or r.path, r.params[key]) for r in rows
                     if r.rig == rig and key in r.params)
        dated = all(p[0][:4].isdigit() for p in pts)
        x = [datetime.fromisoformat(p[0]) for p in pts] if dated else list(range(len(pts)))
        v = np.array([p[1]['value'] for p in pts], dtype=float)
        s = np.array([p[1]['stderr'] if p[1]['stderr'] is not None else np.nan for p in pts],
                     dtype=float)
        style = '-' if rig in alerted else ':'
        line, = ax.plot(x, v, style, marker='o', ms=3, label=rig + (' (alert)' if rig in alerted
                                                                     else ''))
        ax.fill_between(x, v - 2 * s, v + 2 * s, color=line.get_color(), alpha=0.15, lw=0)
    ax.set_title(f'{label} per rig ({key}; band: +/- 2 standard errors)', fontsize=10,
                 pad=14)
    ax.set_ylabel(f'[{unit}]' if unit else key)
    ax.legend(fontsize=8, ncol=min(4, len(rigs)))
    fig.autofmt_xdate()
    return _save(fig, out_dir, name)


def write_report(out_dir, rows: list[Row], alerts: list, describe_param) -> Path:
    """Write ``out_dir/fleet.html`` (and its PNGs); returns the page's path."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    n_err = sum(r.status == 'error' for r in rows)
    n_fail = sum(r.passed is False for r in rows)
    cls = 'bad' if alerts or n_err else 'warn' if n_fail else 'ok'
    body = [f'<div class="status {cls}">{len(rows)} recordings of '
            f'{len({r.rig for r in rows})} rigs: {len(alerts)} alerts, {n_fail} failed '
            f'verification, {n_err} could not be read.</div>', '<h2>Alerts</h2>']
    if alerts:
        body.append(table(['rig', 'parameter', 'kind', 'since', 'note', 'evidence'],
                          [[html.escape(a.rig), html.escape(a.parameter), a.kind,
                            html.escape(a.since), html.escape(a.text),
                            html.escape(a.evidence)] for a in alerts], left=6))
    else:
        body.append('<p>No tracked parameter changed beyond its uncertainty.</p>')
    keys = sorted({k for r in rows for k in r.params})
    for i, key in enumerate(keys):
        label, unit = describe_param(key)
        alerted = {a.rig for a in alerts if a.parameter == key}
        name = _plot_parameter(out_dir, key, label, unit, rows, alerted, f'param_{i}.png')
        body += [f'<h2>{html.escape(label)}</h2>', img(out_dir, name, label)]
    body.append('<h2>Recordings</h2>')
    channels = sorted({c for r in rows for c in r.channels})
    units = {c: u for r in rows for c, u in r.units.items()}
    diagnosed = any(r.diagnosis for r in rows)
    body.append(table(['rig', 'start', 'recording', 'result']
                      + (['diagnosis'] if diagnosed else [])
                      + [f'{c} RMS [{units.get(c, "SI")}]' for c in channels],
                      [_row_cells(r, channels, diagnosed) for r in sorted(
                          rows, key=lambda r: (r.rig, r.start_time or '', r.path))],
                      left=5 if diagnosed else 4))
    path = out_dir / 'fleet.html'
    path.write_text(page('Fleet check', body), encoding='utf-8')
    return path


def _diagnosis_cell(found: dict | None) -> str:
    """Status and verdict, the reason on hover; anything but 'consistent' stands out."""
    if not found:
        return '-'
    cls = '' if found['status'] == 'consistent' else ' class="worse"'
    return (f'<span{cls} title="{html.escape(found["reason"])}">'
            f'{html.escape(diagnosis_text(found))}</span>')


def _row_cells(row: Row, channels: list[str], diagnosed: bool = False) -> list[str]:
    if row.status == 'error':
        result = f'<span class="worse">error: {html.escape(row.error or "")}</span>'
    else:
        result = 'pass' if row.passed else '<span class="worse">FAIL</span>'
    cells = [html.escape(row.rig), html.escape(row.start_time or '-'),
             html.escape(Path(row.path).name), result]
    if diagnosed:
        cells.append(_diagnosis_cell(row.diagnosis))
    return cells + [fmt(row.channels.get(c, {}).get('rmse')) for c in channels]
