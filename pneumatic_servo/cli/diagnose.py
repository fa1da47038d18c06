"""``pneumatic-servo diagnose BAG [BAG ...]``: where the model fails and which physical effect
is missing.

Every candidate effect (the catalogue and any registered effect of your own)
is added to the model, fitted on alternate blocks of the data and scored on
the others. The verdict is the effect that cuts the held-out residual the
most with plausible values, or ``none``. ``--apply OUT.yaml`` writes the
model with the winner added and fitted; run diagnose again on OUT.yaml to
find the next effect.

JSON (``--json``): ``{"verdict": NAME or "none", "ranking": [{"effect", "params",
"error_reduction", ...}, ...], "ladder": [...], "where": {...}, ...}``.
"""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from ..errors import ConfigError


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser('diagnose', help='find which physical effect the model is missing',
                       description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('bags', nargs='+', metavar='BAG',
                   help='rosbag2 directories (sqlite3 or MCAP) and/or static CSV tables, '
                        'diagnosed jointly')
    p.add_argument('--config', metavar='CFG', help="model config YAML (default: the paper's)")
    p.add_argument('--json', metavar='PATH', help='write the diagnosis as JSON')
    p.add_argument('--report', metavar='DIR', help='write an HTML report with plots into DIR')
    p.add_argument('--apply', metavar='OUT.yaml',
                   help='write the model with the winning effect added and fitted')
    p.add_argument('--free', metavar='KEY,...', default='',
                   help="base parameters refitted with every candidate, e.g. "
                        "'stribeck_friction.coulomb_friction_n'")
    p.add_argument('--effects', metavar='E1,E2', default='',
                   help='candidate effects to try (default: all registered)')
    p.add_argument('--horizon', type=float, default=None, metavar='S',
                   help='prediction horizon [s] from each measured state (default 0.25)')
    p.add_argument('--min-reduction', type=float, default=None, metavar='F',
                   help='smallest held-out error reduction that can name an effect '
                        '(default 0.1)')
    p.add_argument('--quiet', action='store_true', help='print only the verdict')
    p.set_defaults(run=run)
    return p


def _names(text: str) -> list[str]:
    return [s.strip() for s in (text or '').split(',') if s.strip()]


def _json_default(o):
    if isinstance(o, (np.floating, np.integer, np.bool_)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    return str(o)


def _clean(o):
    """JSON-safe copy: NaN and inf become null (strict JSON readers reject them)."""
    if isinstance(o, dict):
        return {k: _clean(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_clean(v) for v in o]
    if isinstance(o, (float, np.floating)):
        return float(o) if math.isfinite(o) else None
    return o


def _print_where(result, out) -> None:
    where = result.where
    spots = where.get('hot_spots', [])
    if spots:
        out('where the model fails (error share vs time share):')
        for s in spots[:5]:
            out(f'  {s["channel"]:<6} {s["family"] + ": " + s["regime"]:<28} '
                f'{100 * s["error_share"]:5.1f} % of the error in {100 * s["time_share"]:5.1f} '
                '% of the time')
    text = where.get('residuals', {}).get('text')
    if text:
        out(f'residual tests: {text}')


def _print_ranking(result, out) -> None:
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


def read_all(paths) -> list:
    """Experiments of every bag directory and CSV table in ``paths``."""
    from ..io import read_experiment
    return [read_experiment(p) for p in paths]


def load_config(path):
    from ..model.config import ModelConfig
    return ModelConfig.load(path) if path else ModelConfig.paper()


def run(args) -> int:
    from ..analysis.diagnose import DiagnoseOptions, apply, diagnose
    experiments = read_all(args.bags)
    config = load_config(args.config)
    options = DiagnoseOptions()
    if args.horizon is not None:
        if not args.horizon > 0:
            raise ConfigError('--horizon must be a positive number of seconds')
        options.horizon_s = args.horizon
    if args.min_reduction is not None:
        options.min_reduction = args.min_reduction
    say = (lambda *a: None) if args.quiet else print

    def progress(c):
        say(f'  tried {c.effect:<24} held-out error {100 * c.error_reduction:+6.1f} % '
            f'({c.seconds:.1f} s)')

    result = diagnose(experiments, config, _names(args.effects), _names(args.free), options,
                      progress=progress)
    if not args.quiet:
        _print_where(result, say)
        _print_ranking(result, say)
        print_ladder(result.ladder, say)
    print(f'verdict: {result.verdict}  ({result.reason})')
    if result.ambiguous_with:
        print(f'about as good: {", ".join(result.ambiguous_with)}; to tell them apart, '
              f'{result.suggested_experiment}')
    if args.json:
        Path(args.json).write_text(json.dumps(_clean(result.to_json()), indent=1,
                                              default=_json_default))
        say(f'wrote {args.json}')
    if args.apply:
        if result.winner is None:
            print(f'nothing to apply: no effect earns its place; {args.apply} not written')
        else:
            cfg = apply(result)
            c = result.winner
            cfg.save(args.apply, header=f'diagnose: added {c.effect} '
                                        f'(held-out error -{100 * c.error_reduction:.1f} %)\n'
                     + '\n'.join(f'{k} = {v:.6g} +/- {c.stderr[k]:.2g}'
                                 for k, v in c.params.items()))
            print(f'wrote {args.apply} (model + {c.effect})')
    if args.report:
        path = write_report(args.report, result, config)
        say(f'wrote {path}')
    return 0


def write_report(directory, result, config):
    """HTML report of ``result``: the model as given and, if any, with the winner."""
    from ..analysis.diagnose import predictions
    from ..analysis.report import write_diagnose_report
    preds = {'model as given': result.base_predictions}
    if result.winner is not None:
        preds[f'+ {result.winner.effect}'] = predictions(result.winner.config, result.data)
    return write_diagnose_report(directory, result, result.data.experiments, preds,
                                 result.baseline.config)
