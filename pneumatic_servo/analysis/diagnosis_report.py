"""The ``diagnose --report`` page: the status first, in words a user cannot misread, then what
was found and where the model fails.

Sections: the status and what to do next; the discovered corrections with their
interpretation and a plot of the equation's residual against the leading term (or the
one variable it is a function of: a window or a free shape against the angle), with the
learned correction and its 95 % band;
the ladder (the held-out error as effects are added, a channel that gets worse flagged);
the ranking of the named effects; measured against simulated signals; the residuals,
the regime heat map and the residual tests of the model as given.
"""
from __future__ import annotations

import html
from pathlib import Path

import numpy as np

from ..effects.corrections import BY_EQUATION
from ..effects.terms import BY_NAME as TERMS
from .diagnosis import predictions
from .diagnosis.coverage import next_record
from .diagnosis.dependence import words as dependence_words
from .diagnosis.result import Diagnosis
from .diagnosis.text import HEADLINES
from .equation_residual import equation_residual
from .html import fmt, img, page, table
from .plots import (
    plot_equation_residual,
    plot_ladder,
    plot_overlays,
    plot_ranking,
    plot_residuals,
)
from .report import where_sections

_STYLE = {'consistent': 'ok', 'explained': 'ok', 'partly_explained': 'warn',
          'unexplained': 'bad'}


def _status(result: Diagnosis) -> list[str]:
    res = result.to_json()
    size = ' (small)' if res['size'] == 'small' else ''
    out = [f'<div class="status {_STYLE[res["status"]]}"><b>Status: '
           f'{html.escape(res["status"].replace("_", " "))}</b> &mdash; '
           f'{html.escape(HEADLINES[res["status"]])}.<br>Verdict: '
           f'<b>{html.escape(res["verdict"])}{size}</b>. {html.escape(res["reason"])}.</div>']
    if res['ambiguous_with']:
        out.append(f'<p><b>About equally good:</b> {html.escape(", ".join(res["ambiguous_with"]))}'
                   f'. <b>To tell them apart:</b> {html.escape(res["suggested_experiment"])}</p>')
    if res['partial_fits']:
        out.append('<p><b>Partial fits only, not the answer:</b> '
                   f'{html.escape(", ".join(res["partial_fits"]))}.</p>')
    return out


def _tests(res: dict) -> list[str]:
    """The prediction floor per channel, and the model as given and what the verdict leaves
    against it, with p-values and the levels of the tests."""
    tests, floor = res['tests'], res['floor']
    models = [('model as given', tests['base'])]
    if 'remainder' in tests:
        models.append(('with the best named effect (against its own floor)', tests['remainder']))
    chans = [ch for ch, d in tests['base'].items() if isinstance(d, dict) and 'p_value' in d]
    rows = []
    for ch in chans:
        cells = [html.escape(ch), f'{floor["rms"][ch]:.4g}']
        for _, t in models:
            d = t[ch]
            mark = ' <b>departs</b>' if ch in t['deciding'] and d['p_value'] <= t['level'] \
                else ('' if ch in t['deciding'] else ' (pooled only)')
            cells.append(f'{d["ratio_to_floor"]:.2f} &times; (p = {d["p_value"]:.2g}){mark}')
        rows.append(cells)
    levels = tests['levels']
    return ['<h2>The tests: against this record\'s prediction floor</h2>',
            f'<p class="note">The floor is what the fitted model itself leaves on '
            f'{floor["replicas"]} simulated replicas of these records (same segments, '
            'the record\'s own sensor noise and quantisation, integrator and sampling-phase '
            f'jitter). At a false-alarm rate of {100 * res["options"]["false_alarm_rate"]:g} % '
            f'per record a channel departs at p &le; {levels["departure"]:.2g}; an effect '
            f'earns its place at p &le; {levels["candidate"]:.2g} when it explains at least '
            f'{res["options"]["practical_size"]:g} &times; the floor.</p>',
            *_refit_note(tests),
            table(['channel', 'floor (RMS / spread)'] + [m for m, _ in models], rows,
                  escape_header=False)]


def _refit_note(tests: dict) -> list[str]:
    """Where what the named effect leaves was judged with its fit's own scatter added."""
    floor = tests.get('remainder', {}).get('floor', {})
    if 'refits' not in floor:
        return []
    factors = ', '.join(f'{html.escape(ch)} {f:.2f}' for ch, f in floor['refit_inflation'].items())
    return [f'<p class="note">What the best named effect leaves departed from its own floor, '
            'or a generic correction fitted better than it, so its fit was repeated on '
            f'{floor["refits"]} whole replicas of these records: its fitted values scatter, '
            'and that scatter is part of what a correct answer leaves (and what a generic '
            f'correction must beat). The floor\'s mean squares were raised by {factors}.</p>']


def _next_steps(result: Diagnosis, applied_to: str | None, emitted_to: str | None,
                next_designs=()) -> str:
    steps = []
    added = result.added
    if added is not None and applied_to:
        steps.append(f'The model with <b>{html.escape(added.effect)}</b> added and fitted was '
                     f'written to <code>{html.escape(applied_to)}</code>. Diagnose again with '
                     f'<code>--config {html.escape(applied_to)}</code> to find the next effect.')
    elif added is not None:
        steps.append(f'Run <code>diagnose ... --apply OUT.yaml</code> to write the model with '
                     f'<b>{html.escape(added.effect)}</b> added and fitted, then diagnose again '
                     'on OUT.yaml.')
    if emitted_to:
        steps.append(f'The discovered correction was written as a user effect to '
                     f'<code>{html.escape(emitted_to)}</code>: rename its class to the physics '
                     'you recognise and use it as <code>FILE.py:Class</code>.')
    elif result.discovered:
        steps.append('Write the discovered correction as a user effect with '
                     '<code>--emit-effect FILE.py</code>.')
    tested = next_record(result.discovered[0]) if result.discovered else ''
    if tested:
        steps.append(html.escape(tested) + ''.join(f'<br>&rarr; {html.escape(d.words())}'
                                                   for d in next_designs))
    if result.status == 'consistent':
        steps.append('Nothing is missing that this record can show against its prediction '
                     'floor; a longer or richer record (steps, blocked-piston tests) would '
                     'tighten the test.')
    return '<h2>What to do next</h2><ul>' + ''.join(f'<li>{s}</li>' for s in steps) + '</ul>'


def _discovered(out_dir: Path, result: Diagnosis) -> list[str]:
    if not result.discovered:
        return []
    rows = []
    for d in result.discovered:
        se = d.to_json()['stderr']
        terms = '<br>'.join(f'{html.escape(r)}: {v:+.4g} &plusmn; {fmt(se.get(r), 2)} '
                            f'{html.escape(BY_EQUATION[d.equation].equation.unit)}'
                            + ('' if TERMS[r].unit == '1' else f'/{html.escape(TERMS[r].unit)}')
                            for r, v in d.terms.items())
        said = dependence_words(d)
        rows.append([html.escape(d.equation), terms, f'{100 * d.error_reduction:+.1f} %',
                     html.escape(d.interpretation)
                     + (f'<br><i>{html.escape(said)}</i>' if said else '')])
    out = ['<h2>Where the missing physics lives: generic correction terms</h2>',
           '<p class="note">Each term is fitted through the simulator on the same data and '
           'scored on the same held-out data as the named effects.</p>',
           table(['equation', 'terms (SI, &plusmn; 1 s.e.)', 'held-out error reduction',
                  'interpretation'], rows, 1, escape_header=False, prose=(3,))]
    name = _residual_plot(out_dir, result, result.discovered[0])
    if name:
        out.append(img(out_dir, name, 'equation residual'))
    return out


def _axis(reg: str, names: list[str]) -> str:
    """What to plot against: the variable term ``reg`` is a function of, where it is one
    and a term itself (a window or a knot of the shape: the angle), else ``reg``."""
    used = TERMS[reg].depends_on
    return used[0] if len(used) == 1 and used[0] in names else reg


def _term_covariance(term, names: list[str]) -> np.ndarray:
    """Covariance [SI] of the correction's coefficients over the equation's terms ``names``
    (zero for terms it does not hold; NaN where the fit could not determine one): the fit's
    correlation (its first rows are the correction's terms) scaled by the standard errors."""
    held = list(term.terms)
    se = np.array([np.nan if term.stderr.get(k) is None else term.stderr[k]
                   for k in term.params], dtype=float)
    corr = (term.correlation[:len(held), :len(held)] if term.correlation is not None
            else np.full((len(held), len(held)), np.nan))
    cov = np.zeros((len(names), len(names)))
    at = [names.index(r) for r in held]
    cov[np.ix_(at, at)] = corr * np.outer(se, se)
    return cov


def _band(regs: np.ndarray, cov: np.ndarray) -> np.ndarray:
    """Standard deviation of the correction at each sample (rows of ``regs``) from the
    coefficients' covariance; NaN where a term the fit could not determine is nonzero (a
    knot of the shape the record does not reach)."""
    unknown = np.isnan(np.diag(cov))
    known = np.nan_to_num(cov)
    sd = np.sqrt(np.maximum(np.einsum('ij,jk,ik->i', regs, known, regs), 0.0))
    sd[np.any(regs[:, unknown] != 0.0, axis=1)] = np.nan
    return sd


def _residual_plot(out_dir: Path, result: Diagnosis, term) -> str | None:
    """The discovered term's equation residual against its leading term's variable."""
    eq = BY_EQUATION[term.equation].equation
    names = [t.name for t in eq.terms]
    reg = _axis(term.leading, names)
    coef = np.array([term.terms.get(r, 0.0) for r in names])
    cov = _term_covariance(term, names)
    points = []
    for exp, pred in zip(result.data.experiments, result.base_predictions):
        found = equation_residual(result.baseline.config, exp, pred, term.equation)
        if found is None:
            continue
        res, ok, regs = found
        ok = ok & np.isfinite(res)
        if ok.sum() > 20:
            sd = _band(regs[ok], cov)
            points.append((regs[ok, names.index(reg)], res[ok], regs[ok] @ coef, sd))
    if not points:
        return None
    shown = eq.shown_as or term.equation
    return plot_equation_residual(out_dir, points, shown, reg, BY_EQUATION[shown].equation.unit,
                                  TERMS[reg].unit, eq.unit, reg_words=TERMS[reg].words)


def _ranking_table(ranking: list[dict]) -> str:
    rows = []
    for c in ranking:
        if c['fitted']:
            params = '<br>'.join(f'{html.escape(k.partition(".")[2])} = {v:.4g} &plusmn; '
                                 f'{fmt(c["stderr"].get(k), 2)}' for k, v in c['params'].items())
        else:
            params = '<i>screened out on the coarse grid (not fitted)</i>'
        chans = ', '.join(f'{ch} {100 * v:+.0f} %'
                          for ch, v in c['channel_error_reduction'].items())
        flag = 'yes' if c.get('earns_place') else ('implausible' if not c['plausible'] else 'no')
        rows.append([html.escape(c['effect']), params, f'{100 * c["error_reduction"]:+.1f} %',
                     chans, f'{c["gain_p_value"]:.2g}', f'{c["size_in_floor"]:.2f}',
                     f'{c["delta_bic"]:.1f}', flag, html.escape('; '.join(c['problems']))])
    return table(['effect', 'fitted parameters (SI, &plusmn; 1 s.e.)', 'error reduction',
                  'per channel', 'p (gain)', 'explained / floor', 'delta BIC', 'earns place',
                  'notes'], rows, 2, escape_header=False)


def _ladder_table(ladder: list[dict]) -> str:
    chans = list(ladder[0]['channels'])
    rows = []
    for i, r in enumerate(ladder):
        cells = []
        for ch in chans:
            v = r['channels'].get(ch, float('nan'))
            worse = i > 0 and v > ladder[i - 1]['channels'].get(ch, np.inf) * 1.02
            cells.append(f'<span class="worse">{v:.4g} (worse)</span>' if worse else f'{v:.4g}')
        rows.append([html.escape(r['model'])] + cells + [f'{r["overall"]:.4g}'])
    return table(['model'] + chans + ['overall'], rows, escape_header=False)


def write_diagnosis_report(out_dir, result: Diagnosis, applied_to: str | None = None,
                           emitted_to: str | None = None, next_designs=()) -> Path:
    """Write the page of ``result`` into ``out_dir`` (created); returns ``index.html``.

    ``applied_to`` and ``emitted_to`` name the files ``--apply`` and ``--emit-effect``
    wrote, so the page says where the fitted model is and what to do next;
    ``next_designs`` (:class:`~pneumatic_servo.synth.plan.NextDesign`, each with its
    ``words()``) the designs that would test the correction's dependence further.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    res = result.to_json()
    body = _status(result) + [_next_steps(result, applied_to, emitted_to, next_designs)]
    body += _tests(res)
    body += _discovered(out_dir, result)
    body.append(f'<p class="note">Experiments: {html.escape(", ".join(res["experiments"]))}. '
                f'Residuals are {res["options"]["horizon_s"]:g} s-ahead predictions from the '
                f'measured state, smoothed over {1e3 * res["options"]["smooth_s"]:g} ms; '
                f'fitted on alternate blocks, scored on the others.</p>')
    if res['ladder']:
        body.append('<h2>The ladder: held-out error as effects are added</h2>')
        body.append('<p class="note">Held-out RMS prediction error of each channel divided by '
                    'that channel\'s own spread (standard deviation over the record): 1 means '
                    'an error as large as the signal\'s variation, lower is better. A channel '
                    'that gets worse on a rung is marked.</p>')
        body.append(_ladder_table(res['ladder']))
        body.append(img(out_dir, plot_ladder(out_dir, res['ladder']), 'ladder'))
    if res['ranking']:
        body.append('<h2>Ranking of the named effects</h2>')
        body.append(img(out_dir, plot_ranking(out_dir, res['ranking']), 'ranking'))
        body.append(_ranking_table(res['ranking']))
    preds = {'model as given': result.base_predictions}
    if result.added is not None:
        preds[f'+ {result.added.effect}'] = predictions(result.added.config, result.data)
    exps = result.data.experiments
    body.append('<h2>Measured and simulated</h2>')
    body.append(img(out_dir, plot_overlays(out_dir, exps, preds), 'overlays'))
    if any(not e.static for e in exps):
        body.append('<h2>Residuals of the model as given</h2>')
        body.append(img(out_dir, plot_residuals(out_dir, exps, result.base_predictions),
                        'residuals'))
    body += where_sections(out_dir, exps, result.base_predictions, result.baseline.config)[0]
    path = out_dir / 'index.html'
    path.write_text(page('Model discrepancy diagnosis', body))
    return path
