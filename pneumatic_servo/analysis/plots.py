"""Plots of where the model fails and why, as PNG files for the reports.

Every function draws one figure into ``out_dir`` and returns the file's name.
Channels are shown in the display units of :data:`pneumatic_servo.experiment.CHANNELS`.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..experiment import CHANNELS, STATE_CHANNELS, signal_of

#: display unit and factor per signal
UNITS = {**{c.signal: c.display for c in CHANNELS.values()}, 'command_v': ('V', 1.0)}
CHANNEL_LABELS = {ch: c.label for ch, c in CHANNELS.items()}


def _plt():
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    return plt


def _save(fig, out_dir: Path, name: str) -> str:
    path = out_dir / name
    fig.savefig(path, dpi=90, bbox_inches='tight')
    _plt().close(fig)
    return name


def plot_overlays(out_dir: Path, experiments, predictions: dict[str, list[dict]],
                  name: str = 'overlays.png', max_experiments: int = 4) -> str:
    """Measured against simulated signals, one row per experiment, one column per channel.

    ``predictions`` maps a model label to its predictions (one dict per experiment).
    """
    plt = _plt()
    exps = experiments[:max_experiments]
    sigs = [s for s in ('angle_rad', 'p_a_pa', 'p_b_pa', 'm4_kg_s', 'm5_kg_s')
            if any(s in e.signals for e in exps)]
    fig, axes = plt.subplots(len(exps), len(sigs), figsize=(4.2 * len(sigs), 2.6 * len(exps)),
                             squeeze=False)
    colours = ('tab:red', 'tab:blue', 'tab:green')
    for i, exp in enumerate(exps):
        for j, sig in enumerate(sigs):
            ax = axes[i, j]
            if sig not in exp.signals:
                ax.axis('off')
                continue
            unit, f = UNITS[sig]
            x = exp['command_v'] if exp.static else exp.t
            style = dict(ls='', marker='o', ms=3) if exp.static else dict(lw=0.6)
            ax.plot(x, exp[sig] * f, color='k', label='measured', **style)
            for (label, preds), col in zip(predictions.items(), colours):
                if sig in preds[i]:
                    ax.plot(x, np.asarray(preds[i][sig]) * f, color=col, label=label,
                            **(dict(ls='', marker='x', ms=3) if exp.static else dict(lw=0.8)))
            label = next((c.label for c in CHANNELS.values() if c.signal == sig), sig)
            ax.set_title(f'{exp.name}: {label} [{unit}]', fontsize=9)
            ax.set_xlabel('command [V]' if exp.static else 't [s]', fontsize=8)
            ax.set_ylabel(unit, fontsize=8)
            ax.tick_params(labelsize=7)
    axes[0, 0].legend(fontsize=7)
    fig.tight_layout()
    return _save(fig, out_dir, name)


def plot_residuals(out_dir: Path, experiments, predictions: list[dict],
                   name: str = 'residuals.png', max_experiments: int = 4) -> str:
    """Residual (simulated - measured) over time per channel."""
    plt = _plt()
    exps = experiments[:max_experiments]
    chans = [ch for ch in STATE_CHANNELS if any(signal_of(ch) in e.signals for e in exps)]
    fig, axes = plt.subplots(len(chans), 1, figsize=(12, 2.2 * len(chans)), squeeze=False)
    series = [(e, p) for e, p in zip(exps, predictions) if not e.static]
    # one time axis for all channels: experiments end to end, half a second apart
    offsets = np.cumsum([0.0] + [e.duration + 0.5 for e, _ in series[:-1]])
    colours = {e.name: f'C{i}' for i, (e, _) in enumerate(series)}
    for k, ch in enumerate(chans):
        ax = axes[k, 0]
        sig = signal_of(ch)
        unit, f = UNITS[sig]
        for (exp, pred), offset in zip(series, offsets):
            if sig in exp.signals and sig in pred:
                ax.plot(exp.t + offset, (np.asarray(pred[sig]) - exp[sig]) * f, lw=0.6,
                        label=exp.name, color=colours[exp.name])
        ax.axhline(0.0, color='k', lw=0.5)
        ax.set_ylabel(f'{ch} residual [{unit}]', fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=7, ncol=4, loc='upper right')
    axes[-1, 0].set_xlabel('t [s] (experiments end to end)', fontsize=8)
    fig.tight_layout()
    return _save(fig, out_dir, name)


def plot_regime_heatmap(out_dir: Path, shares, name: str = 'regimes.png') -> str:
    """Heat map of error share over time share, rows = regimes, columns = channels."""
    plt = _plt()
    chans = sorted({ch for s in shares for ch in s.error_share},
                   key=lambda c: list(CHANNELS).index(c) if c in CHANNELS else 9)
    rows = [s for s in shares if s.time_share > 0]
    data = np.array([[s.concentration(ch) for ch in chans] for s in rows])
    fig, ax = plt.subplots(figsize=(2.6 + 2.4 * len(chans), 0.42 * len(rows) + 1.6))
    im = ax.imshow(np.log2(np.clip(np.nan_to_num(data, nan=1.0), 1 / 8, 8)), cmap='RdBu_r',
                   vmin=-3, vmax=3, aspect='auto')
    for i, s in enumerate(rows):
        for j, ch in enumerate(chans):
            e = s.error_share.get(ch, float('nan'))
            ax.text(j, i, f'{100 * e:.0f}% / {100 * s.time_share:.0f}%', ha='center',
                    va='center', fontsize=10)
    ax.set_xticks(range(len(chans)), [CHANNEL_LABELS.get(c, c) for c in chans], fontsize=10)
    ax.set_yticks(range(len(rows)), [f'{s.family}: {s.regime}' for s in rows], fontsize=10)
    cbar = fig.colorbar(im, ax=ax)
    cbar.set_label('log2(error share / time share)', fontsize=8)
    ax.set_title('Share of squared error / share of time, per regime', fontsize=11)
    fig.tight_layout()
    return _save(fig, out_dir, name)


def plot_correlations(out_dir: Path, tests, name: str = 'correlations.png') -> str:
    """Per channel: residual autocorrelation, cross-correlation with the command and
    correlation with the candidate regressors, each with its 95 % band."""
    plt = _plt()
    chans = list(tests)
    fig, axes = plt.subplots(len(chans), 3, figsize=(14, 2.6 * len(chans)), squeeze=False)
    for i, ch in enumerate(chans):
        t = tests[ch]
        ax = axes[i, 0]
        ax.bar(t.lags_s * 1e3, t.acf, width=(t.lags_s[1] - t.lags_s[0]) * 1e3 if len(t.lags_s)
               > 1 else 1.0, color='tab:blue')
        ax.axhspan(-t.acf_band, t.acf_band, color='0.8')
        ax.set_title(f'{ch}: residual autocorrelation', fontsize=9)
        ax.set_xlabel('lag [ms]', fontsize=8)
        ax = axes[i, 1]
        ax.plot(t.xcorr_lags_s * 1e3, t.xcorr, color='tab:purple')
        ax.axhspan(-t.xcorr_band, t.xcorr_band, color='0.8')
        ax.axvline(0.0, color='k', lw=0.5)
        ax.set_title(f'{ch}: cross-correlation with the command', fontsize=9)
        ax.set_xlabel('lag of the command [ms]', fontsize=8)
        ax = axes[i, 2]
        names = list(t.correlations)
        vals = [t.correlations[k] for k in names]
        bands = [t.bands[k] for k in names]
        colours = ['tab:red' if abs(v) > b else 'tab:gray' for v, b in zip(vals, bands)]
        ax.barh(range(len(names)), vals, color=colours)
        ax.errorbar(np.zeros(len(names)), range(len(names)), xerr=bands, fmt='none',
                    ecolor='k', capsize=3, lw=0.8)
        ax.set_yticks(range(len(names)), names, fontsize=8)
        ax.set_xlim(-1, 1)
        ax.set_title(f'{ch}: correlation with regressors (bars: 95 % band)', fontsize=9)
        for a in axes[i]:
            a.tick_params(labelsize=7)
    fig.tight_layout()
    return _save(fig, out_dir, name)


def plot_ranking(out_dir: Path, ranking: list[dict], name: str = 'ranking.png') -> str:
    """Held-out error reduction of each candidate effect, best first."""
    plt = _plt()
    names = [c['effect'] for c in ranking]
    red = [100 * c['error_reduction'] for c in ranking]
    colours = ['tab:green' if c.get('earns_place') else
               ('tab:orange' if not c.get('plausible', True) else 'tab:gray') for c in ranking]
    fig, ax = plt.subplots(figsize=(8, 0.35 * len(names) + 1.2))
    ax.barh(range(len(names)), red, color=colours)
    ax.set_yticks(range(len(names)), names, fontsize=8)
    ax.invert_yaxis()
    ax.axvline(0, color='k', lw=0.5)
    ax.set_xlabel('held-out residual reduction [%]  (green: earns its place, orange: '
                  'implausible values)', fontsize=8)
    ax.set_title('Which effect is missing', fontsize=9)
    fig.tight_layout()
    return _save(fig, out_dir, name)


def plot_ladder(out_dir: Path, ladder: list[dict], name: str = 'ladder.png') -> str:
    """Held-out normalised RMS per channel as effects are added."""
    plt = _plt()
    labels = [r['model'] for r in ladder]
    chans = list(ladder[0]['channels'])
    fig, ax = plt.subplots(figsize=(2.0 + 1.6 * len(labels), 3.6))
    for ch in chans:
        ax.plot(range(len(labels)), [r['channels'].get(ch, np.nan) for r in ladder], 'o-',
                label=CHANNEL_LABELS.get(ch, ch))
    ax.plot(range(len(labels)), [r['overall'] for r in ladder], 'ks--', label='overall')
    ax.set_xticks(range(len(labels)), labels, fontsize=8, rotation=15)
    ax.set_ylabel('held-out RMS error / channel spread\n(lower is better)', fontsize=8)
    ax.set_yscale('log')
    ax.legend(fontsize=7)
    ax.set_title('The error falls as effects are added (held-out data)', fontsize=9)
    fig.tight_layout()
    return _save(fig, out_dir, name)


def plot_equation_residual(out_dir: Path, points: list[tuple], equation: str, regressor: str,
                           unit: str, reg_unit: str, term_unit: str | None = None,
                           name: str = 'equation_residual.png', reg_words: str = '') -> str:
    """The residual of ``equation`` [``unit``] against the leading term of a discovered
    correction (or the variable it is a function of), with binned medians: the shape the
    data show, and the learned correction at the same samples with its 95 % band (from the
    standard errors and correlation of its fitted coefficients).

    ``points`` holds (regressor values, residual, correction, its standard deviation) arrays
    per experiment. A correction in another unit than the residual (``term_unit``: the valve
    input's volts, seen through a chamber's mass balance) is drawn against its own axis.
    ``reg_words``: what the regressor is, on its axis (the command term is the command less
    the valve's centre, so it runs from -5 to 5 V).
    """
    plt = _plt()
    x, y, term, sd = (np.concatenate([p[i] for p in points]) for i in range(4))
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    keep = np.random.default_rng(0).permutation(len(x))[:4000]
    ax.plot(x[keep], y[keep], '.', ms=2, color='0.65', label='residual at each sample')
    edges = np.quantile(x, np.linspace(0.0, 1.0, 21))
    mids, med, fit, half = [], [], [], []
    for lo, hi in zip(edges[:-1], edges[1:]):
        m = (x >= lo) & (x <= hi)
        if m.sum() >= 10:
            mids.append(np.median(x[m]))
            med.append(np.median(y[m]))
            fit.append(np.median(term[m]))
            half.append(1.96 * np.median(sd[m]))  # NaN where a term is not determined
    fit, half = np.array(fit), np.array(half)
    ax.plot(mids, med, 'o-', color='tab:red', label='binned median: the shape in the data')
    own = term_unit not in (None, unit)
    tx = ax.twinx() if own else ax
    tx.plot(mids, fit, 's--', color='tab:blue',
            label='the learned correction' + (f' [{term_unit}], right axis' if own else ''))
    shown = np.isfinite(half)
    if shown.any():  # where the data do not determine the correction, no band is drawn
        gap = '' if shown.all() else '; none where the record does not determine it'
        tx.fill_between(mids, np.where(shown, fit - half, np.nan),
                        np.where(shown, fit + half, np.nan), color='tab:blue', alpha=0.25,
                        label=f'its 95 % band (fit uncertainty, at most '
                              f'\u00b1{np.nanmax(half):.2g}{gap})')
    lo, hi = np.percentile(y, [1, 99])
    pad = 0.2 * (hi - lo) or 1.0
    ax.set_ylim(lo - pad, hi + pad)
    ax.axhline(0.0, color='k', lw=0.5)
    words = f': {reg_words}' if reg_words and reg_words != regressor else ''
    ax.set_xlabel(f'{regressor}{words} [{reg_unit}]', fontsize=9)
    ax.set_ylabel(f'{equation} residual [{unit}]', fontsize=9)
    if own:
        tx.set_ylabel(f'correction [{term_unit}]', fontsize=9, color='tab:blue')
        # the same limits scaled: zero sits level with the residual's, so the shapes compare
        y0, y1 = ax.get_ylim()
        reach = np.nanmax(np.abs(np.concatenate([fit, fit - half, fit + half]))) * 1.2 or 1.0
        k = reach / max(abs(y0), abs(y1))
        tx.set_ylim(k * y0, k * y1)
    ax.set_title(f'What the {equation} lacks, against {regressor}', fontsize=10)
    handles = [h for a in {ax, tx} for h in a.get_legend_handles_labels()[0]]
    ax.legend(handles=handles, fontsize=8)
    fig.tight_layout()
    return _save(fig, out_dir, name)
