"""Reports: a self-contained HTML page with PNG plots of where the model fails and why.

:func:`write_diagnose_report` shows a diagnosis: measured against simulated
signals, residuals, the regime heat map, the residual correlations, the
ranking of candidate effects and the error ladder. :func:`write_compare_report`
is the same page for ``compare --report`` (no ranking, no ladder).

The PNGs are written next to ``index.html`` and also embedded in it, so the
page can be mailed on its own.
"""
from __future__ import annotations

import base64
import html
import json
from pathlib import Path

import numpy as np

from ..experiment import Experiment
from ..model.config import ModelConfig
from .diagnosis import predictions
from .plots import (
    plot_correlations,
    plot_ladder,
    plot_overlays,
    plot_ranking,
    plot_regime_heatmap,
    plot_residuals,
)
from .regimes import error_shares, hot_spots
from .residuals import residual_tests, summary

# ------------------------------------------------------------------------------- html
_CSS = ('body{font-family:sans-serif;max-width:1200px;margin:2em auto;color:#222}'
        'table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;'
        'padding:3px 8px;font-size:13px;text-align:right}th{background:#eee}'
        'td.l{text-align:left}img{max-width:100%;border:1px solid #ddd;margin:4px 0}'
        '.verdict{font-size:1.3em;padding:0.5em;background:#eef6ee;border:1px solid #8b8}'
        '.none{background:#f4f4f4;border-color:#aaa}.note{color:#555;font-size:13px}')


def _img(out_dir: Path, name: str, alt: str) -> str:
    data = base64.b64encode((out_dir / name).read_bytes()).decode()
    return f'<p><img src="data:image/png;base64,{data}" alt="{html.escape(alt)}" ' \
           f'title="{html.escape(name)}"></p>'


def _table(header: list[str], rows: list[list], left: int = 1) -> str:
    out = ['<table><tr>' + ''.join(f'<th>{html.escape(h)}</th>' for h in header) + '</tr>']
    for row in rows:
        cells = [f'<td class="l">{c}</td>' if i < left else f'<td>{c}</td>'
                 for i, c in enumerate(row)]
        out.append('<tr>' + ''.join(cells) + '</tr>')
    return '\n'.join(out) + '</table>'


def _fmt(v, digits=4) -> str:
    if v is None or (isinstance(v, float) and not np.isfinite(v)):
        return '-'
    return f'{v:.{digits}g}' if isinstance(v, (float, np.floating)) else html.escape(str(v))


def _page(title: str, body: list[str]) -> str:
    return ('<!DOCTYPE html><html><head><meta charset="utf-8"><title>' + html.escape(title)
            + f'</title><style>{_CSS}</style></head><body><h1>{html.escape(title)}</h1>\n'
            + '\n'.join(body) + '</body></html>\n')


def _where_sections(out_dir: Path, experiments, preds: list[dict], config) -> tuple[list, dict]:
    """HTML and JSON of the regime heat map and the residual tests."""
    body, where = [], {}
    series = [(e, p) for e, p in zip(experiments, preds) if not e.static]
    shares = error_shares(experiments, preds, config)
    if shares:
        spots = hot_spots(shares)
        body.append('<h2>Where the model fails: error by operating regime</h2>')
        body.append('<p class="note">Each cell: share of the channel\'s squared error in '
                    'the regime / share of time spent there. Red: the error concentrates '
                    'there.</p>')
        body.append(_img(out_dir, plot_regime_heatmap(out_dir, shares), 'regime heat map'))
        if spots:
            body.append(_table(['channel', 'regime', 'error share', 'time share'],
                               [[s['channel'], f'{s["family"]}: {s["regime"]}',
                                 f'{100 * s["error_share"]:.0f} %',
                                 f'{100 * s["time_share"]:.0f} %'] for s in spots[:8]], 2))
        where['regimes'] = [s.to_json() for s in shares]
        where['hot_spots'] = spots
    if series:
        tests = residual_tests([e for e, _ in series], [p for _, p in series])
        if tests:
            summ = summary([e for e, _ in series], [p for _, p in series], tests)
            body.append('<h2>Residual tests</h2>')
            body.append(f'<p><b>{html.escape(summ["text"])}</b></p>')
            body.append(_img(out_dir, plot_correlations(out_dir, tests), 'correlations'))
            where['residuals'] = {k: v for k, v in summ.items() if k != 'relative_rms'}
            where['residuals']['relative_rms'] = summ.get('relative_rms')
    return body, where


def write_compare_report(out_dir, exp: Experiment, pred: dict, result=None,
                         config: ModelConfig | None = None) -> Path:
    """The ``compare --report`` page: overlays, residuals, regime heat map, residual tests.

    Parameters
    ----------
    out_dir : path
        Directory for ``index.html`` and the PNGs (created).
    exp : Experiment
        Measured experiment.
    pred : dict
        Simulated signals on ``exp.t``, or view -> signals (``{'open_loop': {...},
        'k_step': {...}}``, as ``compare`` makes them). Regimes and residual
        tests use the k-step view when there is one: it shows where the model
        is locally wrong, where the open-loop error only accumulates.
    result : dict or object, optional
        The comparison metrics (``{'channels': {ch: {rmse, max_abs, fit_percent}}}``).
    config : ModelConfig, optional
        The model compared (regime thresholds: valve centre, stroke).

    Returns
    -------
    Path
        The written ``index.html``.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    views = pred if pred and all(isinstance(v, dict) for v in pred.values()) \
        else {'model': pred}
    local = views.get('k_step', next(iter(views.values())))
    body = [f'<p class="note">Experiment <b>{html.escape(exp.name or "experiment")}</b>, '
            f'circuit {exp.circuit}, {len(exp.t)} samples.</p>']
    metrics = _metrics_of(result)
    if metrics:
        body.append('<h2>Error per channel</h2>')
        body.append(_table(['channel', 'rmse [SI]', 'max |error| [SI]', 'fit [%]'],
                           [[ch, _fmt(m.get('rmse')), _fmt(m.get('max_abs')),
                             _fmt(m.get('fit_percent'), 3)] for ch, m in metrics.items()]))
    body.append('<h2>Measured and simulated</h2>')
    body.append(_img(out_dir, plot_overlays(out_dir, [exp], {k: [v] for k, v in views.items()}),
                     'overlays'))
    if not exp.static:
        body.append('<h2>Residuals' + (' (k-step view)' if 'k_step' in views else '')
                    + '</h2>')
        body.append(_img(out_dir, plot_residuals(out_dir, [exp], [local]), 'residuals'))
    where_body, where = _where_sections(out_dir, [exp], [local], config)
    body += where_body
    (out_dir / 'where.json').write_text(json.dumps(where, indent=1, default=_json_default))
    path = out_dir / 'index.html'
    path.write_text(_page('Model against measurement', body))
    return path


def _metrics_of(result) -> dict:
    if result is None:
        return {}
    if hasattr(result, 'to_json'):
        result = result.to_json()
    if isinstance(result, dict):
        return result.get('channels', {}) or {}
    return {}


def _json_default(o):
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    return str(o)


def _ranking_table(ranking: list[dict]) -> str:
    rows = []
    for c in ranking:
        params = '<br>'.join(f'{html.escape(k.partition(".")[2])} = {v:.4g} &plusmn; '
                             f'{c["stderr"].get(k, float("nan")):.2g}'
                             for k, v in c['params'].items())
        chans = ', '.join(f'{ch} {100 * v:+.0f} %'
                          for ch, v in c['channel_error_reduction'].items())
        flag = 'yes' if c.get('earns_place') else ('implausible' if not c['plausible'] else 'no')
        rows.append([html.escape(c['effect']), params, f'{100 * c["error_reduction"]:+.1f} %',
                     chans, f'{c["delta_bic"]:.1f}', flag,
                     html.escape('; '.join(c['problems']))])
    return _table(['effect', 'fitted parameters (SI, &plusmn; 1 s.e.)', 'error reduction',
                   'per channel', 'delta BIC', 'earns place', 'notes'], rows, 2)


def _ladder_table(ladder: list[dict]) -> str:
    chans = list(ladder[0]['channels'])
    rows = [[html.escape(r['model'])] + [f'{r["channels"].get(ch, float("nan")):.4g}'
                                         for ch in chans] + [f'{r["overall"]:.4g}']
            for r in ladder]
    return _table(['model'] + chans + ['overall'], rows)


def write_diagnose_report(out_dir, result, experiments, predictions: dict[str, list[dict]],
                          config: ModelConfig | None = None) -> Path:
    """The ``diagnose --report`` page.

    Parameters
    ----------
    out_dir : path
        Directory for ``index.html`` and the PNGs (created).
    result : Diagnosis or dict
        The diagnosis (or its JSON).
    experiments : list of Experiment
        The diagnosed experiments.
    predictions : dict
        Model label -> predictions (one dict per experiment); the first is the
        model as given, whose residuals the regime and residual analyses use.
    config : ModelConfig, optional
        The model as given.

    Returns
    -------
    Path
        The written ``index.html``.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    res = result.to_json() if hasattr(result, 'to_json') else result
    verdict = res['verdict']
    cls = 'verdict none' if verdict == 'none' else 'verdict'
    body = [f'<p class="{cls}">Verdict: <b>{html.escape(verdict)}</b> &mdash; '
            f'{html.escape(res.get("reason", ""))}</p>']
    if res.get('ambiguous_with'):
        ties = html.escape(', '.join(res['ambiguous_with']))
        body.append(f'<p><b>About equally good:</b> {ties}. <b>To tell them apart:</b> '
                    f'{html.escape(res["suggested_experiment"])}</p>')
    body.append(f'<p class="note">Experiments: {html.escape(", ".join(res["experiments"]))}. '
                f'Residuals are {res["options"]["horizon_s"]:g} s-ahead predictions from the '
                f'measured state, smoothed over {1e3 * res["options"]["smooth_s"]:g} ms; '
                f'fitted on alternate blocks, scored on the others.</p>')
    if res.get('ladder'):
        body.append('<h2>The ladder: held-out error as effects are added</h2>')
        body.append(_ladder_table(res['ladder']))
        body.append(_img(out_dir, plot_ladder(out_dir, res['ladder']), 'ladder'))
    if res['ranking']:
        body.append('<h2>Which effect is missing: ranking</h2>')
        body.append(_img(out_dir, plot_ranking(out_dir, res['ranking']), 'ranking'))
        body.append(_ranking_table(res['ranking']))
    body.append('<h2>Measured and simulated</h2>')
    body.append(_img(out_dir, plot_overlays(out_dir, experiments, predictions), 'overlays'))
    first = next(iter(predictions.values()))
    if any(not e.static for e in experiments):
        body.append('<h2>Residuals of the model as given</h2>')
        body.append(_img(out_dir, plot_residuals(out_dir, experiments, first), 'residuals'))
    where_body, _ = _where_sections(out_dir, experiments, first, config)
    body += where_body
    path = out_dir / 'index.html'
    path.write_text(_page('Model discrepancy diagnosis', body))
    return path


def write_diagnosis_report(out_dir, result) -> Path:
    """The ``diagnose --report`` page of a :class:`~.diagnosis.Diagnosis`: the model as
    given and, if the diagnosis found one, the model with the winning effect."""
    preds = {'model as given': result.base_predictions}
    if result.added is not None:
        preds[f'+ {result.added.effect}'] = predictions(result.added.config, result.data)
    return write_diagnose_report(out_dir, result, result.data.experiments, preds,
                                 result.baseline.config)
