"""A diagnosis as lines of text: where the model fails, the ranking, the ladder, the verdict.

Every function writes through ``out`` (default ``print``), so the CLI, the demo
and a user's script print the same thing.
"""
from __future__ import annotations

from .result import Diagnosis


def print_where(result: Diagnosis, out=print) -> None:
    """The regimes that hold the most error and the sentence of the residual tests."""
    spots = result.where.get('hot_spots', [])
    if spots:
        out('where the model fails (error share vs time share):')
        for s in spots[:5]:
            out(f'  {s["channel"]:<6} {s["family"] + ": " + s["regime"]:<28} '
                f'{100 * s["error_share"]:5.1f} % of the error in {100 * s["time_share"]:5.1f} '
                '% of the time')
    text = result.where.get('residuals', {}).get('text')
    if text:
        out(f'residual tests: {text}')


def print_ranking(result: Diagnosis, out=print) -> None:
    """One line per candidate: held-out error reduction, BIC change, fitted values."""
    out(f'{"effect":<24} {"error red.":>10} {"dBIC":>9}  fitted values (+/- 1 s.e.)')
    for c in result.ranking:
        vals = ', '.join(f'{k.partition(".")[2]}={v:.4g}+/-{c.stderr[k]:.2g}'
                         for k, v in c.params.items())
        note = '' if c.plausible else '  [implausible]'
        out(f'{c.effect:<24} {100 * c.error_reduction:9.1f}% {c.delta_bic:9.1f}  {vals}{note}')


def print_ladder(ladder: list[dict], out=print) -> None:
    """The ladder as a table: held-out normalised RMS per channel, per model."""
    if not ladder:
        return
    chans = list(ladder[0]['channels'])
    out('ladder (held-out RMS / channel spread):')
    out(f'  {"model":<28}' + ''.join(f'{ch:>10}' for ch in chans) + f'{"overall":>10}')
    for r in ladder:
        out(f'  {r["model"]:<28}' + ''.join(f'{r["channels"].get(ch, float("nan")):10.4f}'
                                            for ch in chans) + f'{r["overall"]:10.4f}')


#: the status in words a user cannot misread
HEADLINES = {
    'consistent': 'the model is consistent with the data: nothing is missing',
    'explained': 'a missing effect was found, and with it the model explains the data',
    'partly_explained': 'a missing effect was found, but something else is missing too',
    'unexplained': 'THE MODEL IS WRONG, and no effect on the list explains it',
}


def print_discovered(result: Diagnosis, out=print) -> None:
    """The generic corrections found, best first, with their interpretation."""
    if not result.discovered:
        return
    out('generic correction terms (where the missing physics lives):')
    for d in result.discovered:
        terms = ', '.join(f'{r} {v:+.4g} +/- {d.to_json()["stderr"][r]:.2g}'
                          for r, v in d.terms.items())
        out(f'  {d.equation:<20} {100 * d.error_reduction:6.1f} %  {terms}')
        out(f'  {"":<20} -> {d.interpretation}')


def print_verdict(result: Diagnosis, out=print) -> None:
    """The status first, then the verdict with its reason, and the experiment that
    separates tied effects."""
    out(f'status: {result.status}: {HEADLINES[result.status]}')
    size = ' (small)' if result.finding.size == 'small' else ''
    out(f'verdict: {result.verdict}{size}  ({result.reason})')
    if result.ambiguous_with:
        out(f'about as good: {", ".join(result.ambiguous_with)}; to tell them apart, '
            f'{result.suggested_experiment}')
    if result.finding.partial:
        out(f'partial fits only, not the answer: {", ".join(result.finding.partial)}')


def apply_header(result: Diagnosis) -> str:
    """Comment lines for a config written with what the diagnosis found applied."""
    c = result.added
    return (f'diagnose: added {c.effect} (held-out error -{100 * c.error_reduction:.1f} %)\n'
            + '\n'.join(f'{k} = {v:.6g} +/- {c.stderr[k]:.2g}' for k, v in c.params.items()))
