"""The model-discrepancy workflow end to end, on a bundled bag with hidden effects:
compare -> see where it fails -> diagnose -> apply -> compare again, until nothing is missing.

``run_discrepancy_demo(out_dir)`` is what the README's main job ends with. It
prints each step and the ladder (held-out error per channel as effects are
added), and writes the reports, the fitted models and a JSON summary into
``out_dir``.
"""
from __future__ import annotations

from pathlib import Path

from .analysis.compare import compare, predict_views
from .analysis.diagnosis import apply, diagnose
from .analysis.diagnosis.text import plus_minus, print_ladder
from .analysis.diagnosis_report import write_diagnosis_report
from .analysis.report import write_compare_report
from .errors import ExperimentError
from .files import bundled
from .io import read_experiment
from .jsonable import dumps
from .model.config import ModelConfig

#: the bundled record: a closed-loop run of a rig with hidden effects (synthetic)
DEMO_BAG = 'hidden_effect_demo'


def demo_bag() -> Path:
    """Path of the bundled demo bag (``bags/hidden_effect_demo`` of the source tree)."""
    return bundled(DEMO_BAG, 'metadata.yaml',
                   'python -m pneumatic_servo.synth.hidden --demo bags/', ExperimentError)


def _compare(exp, config, out_dir: Path, label: str, say) -> dict:
    """Open-loop and k-step comparison, printed and reported (issue-4 compare if present)."""
    preds = predict_views(exp, config)
    result = compare(exp, config, preds=preds)
    write_compare_report(out_dir / f'compare_{label}', exp, preds, result, config)
    chans = result['channels']
    k_chans = result.get('k_step', {}).get('channels', {})
    say(f'compare ({label}): ' + ', '.join(
        f'{ch} fit {m["fit_percent"]:.1f} % open loop / '
        f'{k_chans.get(ch, {}).get("fit_percent", float("nan")):.1f} % k-step'
        for ch, m in chans.items()))
    return result


def _round(i: int, exp, config, out_dir: Path, say):
    """One diagnose/apply round; returns (diagnosis, new config or None)."""
    result = diagnose([exp], config)
    report = write_diagnosis_report(out_dir / f'diagnose_{i}', result)
    spots = result.where.get('hot_spots', [])
    if spots:
        s = spots[0]
        say(f'  where it fails: {s["channel"]} in {s["family"]}: {s["regime"]} '
            f'({100 * s["error_share"]:.0f} % of the error, {100 * s["time_share"]:.0f} % '
            'of the time)')
    text = result.where.get('residuals', {}).get('text')
    if text:
        say(f'  residual tests: {text}')
    say(f'  diagnose round {i}: status {result.status}, verdict {result.verdict} '
        f'({result.reason}); report {report}')
    if result.added is None:
        return result, None
    new = apply(result)
    path = out_dir / f'model_{i}.yaml'
    new.save(path, header=f'discrepancy demo round {i}: added {result.added.effect}')
    say('  applied: ' + ', '.join(f'{k} = {plus_minus(v, result.added.stderr[k])}'
                                   for k, v in result.added.params.items()) + f' -> {path}')
    print_ladder(result.ladder, say)
    return result, new


def run_discrepancy_demo(out_dir, bag=None, config: ModelConfig | None = None,
                         max_rounds: int = 3, say=print) -> dict:
    """Compare, diagnose, apply and compare again on a bag with hidden effects.

    Parameters
    ----------
    out_dir : path
        Where reports (``compare_before/``, ``diagnose_1/``, ...), fitted
        models (``model_1.yaml``, ...) and ``discrepancy_demo.json`` go.
    bag : path, optional
        The record (default the bundled ``bags/hidden_effect_demo``).
    config : ModelConfig, optional
        The model to start from (default the paper's).
    max_rounds : int
        Most diagnose/apply rounds.
    say : callable
        Where progress lines go.

    Returns
    -------
    dict
        ``bag``, ``found`` (effects in the order found, with the values fitted
        when found and ``final_params`` of the final model),
        ``ladder`` (of the last round), ``compare_before``/``compare_after``
        (channel metrics) and ``final_config`` (path).
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    bag = Path(bag) if bag is not None else demo_bag()
    exp = read_experiment(bag)
    config = config or ModelConfig.paper()
    say(f'== model-discrepancy workflow on {bag}')
    before = _compare(exp, config, out_dir, 'before', say)
    found, ladder, last = [], [], None
    for i in range(1, max_rounds + 1):
        result, new = _round(i, exp, config, out_dir, say)
        ladder = result.ladder or ladder
        if new is None:
            break
        found.append({'effect': result.added.effect, 'params': dict(result.added.params),
                      'stderr': dict(result.added.stderr),
                      'error_reduction': result.added.error_reduction,
                      'status': result.status})
        config, last = new, out_dir / f'model_{i}.yaml'
    after = _compare(exp, config, out_dir, 'after', say)
    for f in found:  # later rounds refit the effects found earlier
        f['final_params'] = {k: config.get(k) for k in f['params']}
    say('effects found: ' + (', '.join(
        f['effect'] + ' (' + ', '.join(f'{k.partition(".")[2]} = {v:.4g}'
                                       for k, v in f['final_params'].items()) + ')'
        for f in found) or 'none'))
    summary = {'bag': str(bag), 'found': found, 'ladder': ladder,
               'compare_before': before['channels'], 'compare_after': after['channels'],
               'final_config': str(last) if last else None}
    (out_dir / 'discrepancy_demo.json').write_text(dumps(summary, indent=1))
    return summary
