"""A diagnosis as lines of text: where the model fails, the ranking, the ladder, the verdict.

Every function writes through ``out`` (default ``print``), so the CLI, the demo
and a user's script print the same thing.
"""
from __future__ import annotations

from .coverage import next_record
from .dependence import words as dependence_words
from .result import Diagnosis


def plus_minus(value: float, stderr: float | None) -> str:
    """``value +/- stderr``, or ``value (not determined)`` when the data do not determine it."""
    if stderr is None or stderr != stderr:
        return f'{value:.4g} (not determined)'
    return f'{value:.4g} +/- {stderr:.2g}'


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
    """One line per candidate: held-out error reduction (and on the other experiments, when
    validated), BIC change, fitted values, and what the data could not determine."""
    other = bool(result.validated_on)
    out(f'{"effect":<24} {"error red.":>10}' + (f' {"on others":>10}' if other else '')
        + f' {"p":>8} {"x floor":>7} {"dBIC":>9}  fitted values (+/- 1 s.e.)')
    for c in result.ranking:
        vals = ', '.join(f'{k.partition(".")[2]}={plus_minus(v, c.stderr[k])}'
                         for k, v in c.params.items())
        note = '' if c.plausible else '  [implausible]'
        if c.undetermined:
            note += '  [not determined: ' + '; '.join(
                f'{k.partition(".")[2]}: {why}' for k, why in c.undetermined.items()) + ']'
        val = ''
        if other and c.validation is not None:
            val = f' {100 * c.validation.error_reduction:9.1f}%'
            note += '  [HURTS the other experiments]' if c.validation.hurts else ''
        out(f'{c.effect:<24} {100 * c.error_reduction:9.1f}%{val} {c.gain_p_value:8.2g} '
            f'{c.size_in_floor:7.2f} {c.delta_bic:9.1f}  {vals}{note}')
    for c in result.ranking:
        if c.validation is not None and c.validation.assumptions:
            out(f'  {c.effect} on the other experiments: ' + '; '.join(c.validation.assumptions))


def print_ladder(ladder: list[dict], out=print) -> None:
    """The ladder as a table: held-out normalised RMS per channel, per model."""
    if not ladder:
        return
    chans = list(ladder[0]['channels'])
    other = 'validation' in ladder[0]
    out('ladder (held-out RMS / channel spread):')
    out(f'  {"model":<28}' + ''.join(f'{ch:>10}' for ch in chans) + f'{"overall":>10}'
        + (f'{"on others":>11}' if other else ''))
    for r in ladder:
        val = f'{r["validation"]["overall"]:11.4f}' if other and 'validation' in r else ''
        out(f'  {r["model"]:<28}' + ''.join(f'{r["channels"].get(ch, float("nan")):10.4f}'
                                            for ch in chans) + f'{r["overall"]:10.4f}' + val)


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
        se = d.to_json()['stderr']
        terms = ', '.join(f'{r} {plus_minus(v, se[r])}' for r, v in d.terms.items())
        out(f'  {d.equation:<20} {100 * d.error_reduction:6.1f} %  {terms}')
        out(f'  {"":<20} -> {d.interpretation}')
        if d.dependence:
            out(f'  {"":<20} -> {dependence_words(d)}')
            tested = next_record(d)
            if tested:
                out(f'  {"":<20} -> {tested}')


def print_floor(result: Diagnosis, out=print) -> None:
    """The prediction floor per channel and how the model as given departs from it."""
    floor, base = result.floor, result.trial.departures(result.baseline.score)
    out(f'prediction floor ({floor.replicas} replicas of these records with the fitted '
        'model; held-out RMS / channel spread):')
    for ch, test in base.tests.items():
        rms = floor.rms(None if ch == 'overall' else ch)
        out(f'  {ch:<8} floor {rms:.4f}  model as given {test.ratio:5.2f} x the floor '
            f'(p = {test.p_value:.2g})')
    out(f'  tests at {100 * result.options.false_alarm_rate:g} % per record: a channel '
        f'departs at p <= {base.level:.2g}, an effect earns its place at p <= '
        f'{result.trial.levels.candidate:.2g} and explains >= '
        f'{result.options.practical_size:g} x the floor')
    left = result.remainder
    if left is not None and left.floor is not None and left.floor.refits:
        refit = left.floor.to_json()
        inflation = ', '.join(f'{ch} {f:.2f}' for ch, f in refit['refit_inflation'].items())
        out(f'  what the named effect leaves is judged against its own floor with the scatter '
            f'of its fit on {refit["refits"]} whole replicas added (mean-square factors: '
            f'{inflation}): {left.words()}')


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
    """Comment lines for a config written with what the diagnosis found applied; a value the
    data do not determine is said to be one, with the value written and why."""
    c = result.added
    lines = [f'diagnose: added {c.effect} (held-out error -{100 * c.error_reduction:.1f} %)']
    for k, v in c.params.items():
        if k in c.undetermined:
            lines.append(f'{k} = {v:.6g}: NOT FITTED, left at its neutral value; '
                         f'{c.undetermined[k]}')
        else:
            lines.append(f'{k} = {plus_minus(v, c.stderr[k])}')
    return '\n'.join(lines)
