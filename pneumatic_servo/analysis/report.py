"""The ``compare --report`` page: where the model fails and why, as HTML with PNG plots.

:func:`write_compare_report` shows measured against simulated signals, the
residuals, the regime heat map and the residual tests (:func:`where_sections`,
which the diagnosis page shares).

The PNGs are written next to ``index.html`` and also embedded in it, so the
page can be mailed on its own.
"""
from __future__ import annotations

import html
from pathlib import Path

from ..experiment import Experiment
from ..jsonable import dumps
from ..model.config import ModelConfig
from .html import fmt, img, page, table
from .plots import plot_correlations, plot_overlays, plot_regime_heatmap, plot_residuals
from .regimes import error_shares, hot_spots
from .residuals import residual_tests, summary


def where_sections(out_dir: Path, experiments, preds: list[dict], config) -> tuple[list, dict]:
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
        body.append(img(out_dir, plot_regime_heatmap(out_dir, shares), 'regime heat map'))
        if spots:
            body.append(table(['channel', 'regime', 'error share', 'time share'],
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
            body.append(img(out_dir, plot_correlations(out_dir, tests), 'correlations'))
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
        body.append(table(['channel', 'rmse [SI]', 'max |error| [SI]', 'fit [%]'],
                           [[ch, fmt(m.get('rmse')), fmt(m.get('max_abs')),
                             fmt(m.get('fit_percent'), 3)] for ch, m in metrics.items()]))
    body.append('<h2>Measured and simulated</h2>')
    body.append(img(out_dir, plot_overlays(out_dir, [exp], {k: [v] for k, v in views.items()}),
                     'overlays'))
    if not exp.static:
        body.append('<h2>Residuals' + (' (k-step view)' if 'k_step' in views else '')
                    + '</h2>')
        body.append(img(out_dir, plot_residuals(out_dir, [exp], [local]), 'residuals'))
    where_body, where = where_sections(out_dir, [exp], [local], config)
    body += where_body
    (out_dir / 'where.json').write_text(dumps(where, indent=1))
    path = out_dir / 'index.html'
    path.write_text(page('Model against measurement', body))
    return path


def _metrics_of(result) -> dict:
    if result is None:
        return {}
    if hasattr(result, 'to_json'):
        result = result.to_json()
    if isinstance(result, dict):
        return result.get('channels', {}) or {}
    return {}

