"""``pneumatic-servo compare BAG``: replay a recorded experiment through the model and
compare the measured angle and pressures with the prediction.

Two views: open loop over the whole record, and k-step ahead (re-initialised
from the measured state every --horizon seconds). ``--json`` writes
``{"channels": {"angle": {...}, "p_a": {...}, "p_b": {...}}, "k_step": {...}}``;
every channel has ``rmse``, ``max_abs`` and ``fit_percent`` in SI units (rad, Pa).
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

from ..jsonable import dumps
from ..prediction import COMPARE_HORIZON_S
from ..text import comma_list
from .options import output_dir, output_file, positive_seconds, seconds


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser('compare', help='compare a recorded experiment with the model '
                       '(open loop and k-step ahead)', description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('bag', metavar='BAG', help='rosbag2 directory (sqlite3 or MCAP) or static CSV')
    p.add_argument('--config', metavar='CFG', help='model config YAML (default: the paper\'s)')
    p.add_argument('--effects', metavar='E1,E2', type=comma_list,
                   help='catalogue effects to add (default values)')
    p.add_argument('--json', metavar='PATH', type=output_file, help='write the results as JSON')
    p.add_argument('--report', metavar='DIR', type=output_dir,
                   help='write plots (and an HTML report) into DIR')
    p.add_argument('--mode', choices=('open_loop', 'k_step'), default='open_loop',
                   help='view reported under "channels" (the other is under its own name)')
    p.add_argument('--horizon', type=positive_seconds, default=COMPARE_HORIZON_S, metavar='S',
                   help=f'k-step prediction horizon [s] (default {COMPARE_HORIZON_S:g})')
    p.add_argument('--skip', type=seconds, default=0.0, metavar='S',
                   help='leave the first S seconds out of the metrics')
    p.add_argument('--validate-on', nargs='+', metavar='OTHER', default=[],
                   help='also compare the same model with these experiments (any circuit); '
                        'JSON under "validation", by experiment')
    p.set_defaults(run=run)
    return p


def print_channels(result: dict, out=print) -> None:
    """Human-readable table of a compare result."""
    views = [(result['mode'], result['channels'])]
    for other in ('open_loop', 'k_step'):
        if other in result and other != result['mode']:
            views.append((other, result[other].get('channels', {})))
    out(f'{result["experiment"]} ({result["circuit"]}'
        f'{", synthetic" if result.get("synthetic") else ""})')
    out(f'{"view":<10} {"channel":<8} {"rmse":>14} {"max |error|":>14} {"fit %":>8}')
    for view, chans in views:
        for ch, m in chans.items():
            unit = result['units'][ch]
            k, u = (180.0 / math.pi, 'deg') if ch == 'angle' else (1.0, unit)
            fmt = (lambda v: '-' if v is None else f'{v * k:.4g} {u}')
            fit = '-' if m['fit_percent'] is None else f'{m["fit_percent"]:.1f}'
            out(f'{view:<10} {ch:<8} {fmt(m["rmse"]):>14} {fmt(m["max_abs"]):>14} {fit:>8}')


def write_report(directory, exp, preds, result, config=None) -> Path:
    """The HTML report (:func:`pneumatic_servo.analysis.report.write_compare_report`) in
    ``directory``; ``preds`` maps each view ('open_loop', 'k_step') to its predicted
    signals, and the report gets the view reported under ``channels``."""
    from ..analysis.report import write_compare_report
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    return write_compare_report(directory, exp, preds[result['mode']], result, config=config)


def run(args) -> int:
    from ..analysis.compare import compare, config_for, predict_views, resolve_config
    from ..io import read_experiment
    exp = read_experiment(args.bag)
    cfg = config_for(exp, resolve_config(args.config, args.effects))
    preds = predict_views(exp, cfg, horizon_s=args.horizon)
    result = compare(exp, cfg, mode=args.mode, horizon_s=args.horizon, skip_s=args.skip,
                     preds=preds)
    print_channels(result)
    if args.validate_on:
        result['validation'] = {}
        for path in args.validate_on:
            other = read_experiment(path)
            check = compare(other, config_for(other, cfg), mode=args.mode,
                            horizon_s=args.horizon)
            result['validation'][other.name] = check
            print_channels(check)
    if args.json:
        Path(args.json).write_text(dumps(result, indent=2))
        print(f'wrote {args.json}')
    if args.report:
        path = write_report(args.report, exp, preds, result, cfg)
        print(f'wrote {path}')
    return 0
