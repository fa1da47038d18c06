"""``pneumatic-servo simulate BAG --out OUT``: what the model predicts for a recorded experiment.

The recorded valve command and supply pressure drive the model from the
first measured state (open loop); the prediction is written with the same
topics as the input (a bag), or the same columns (a static CSV table), and
labelled synthetic in its metadata.
"""
from __future__ import annotations

import argparse
from pathlib import Path

from ..text import comma_list
from .options import new_path


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser('simulate', help='run the model on a recorded experiment; write its '
                       'prediction as a bag (or CSV) with the same topics',
                       description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('bag', metavar='BAG', help='rosbag2 directory (sqlite3 or MCAP) or static CSV')
    p.add_argument('--out', required=True, metavar='OUT_BAG', type=new_path,
                   help='new bag directory (or .csv file for a CSV input) to write')
    p.add_argument('--config', metavar='CFG', help='model config YAML (default: the paper\'s)')
    p.add_argument('--effects', metavar='E1,E2', type=comma_list,
                   help='catalogue effects to add (default values)')
    p.add_argument('--storage', choices=('sqlite3', 'mcap'), default=None,
                   help='storage of the output bag (default: that of the input)')
    p.set_defaults(run=run)
    return p


def run(args) -> int:
    from ..analysis.compare import resolve_config
    from ..errors import ExperimentError
    from ..experiment import Experiment
    from ..io import read_experiment, write_experiment
    from ..model.assembly import Model
    from ..prediction import config_for, predict_checked
    exp = read_experiment(args.bag)
    out = Path(args.out)
    if exp.static and out.suffix.lower() != '.csv':
        raise ExperimentError(f'{args.bag} is a static table: give --out a .csv file')
    if not exp.static and out.suffix.lower() == '.csv':
        raise ExperimentError(f'{args.bag} is a time series: give --out a bag directory')
    if out.exists():
        raise ExperimentError(f'{out} exists; choose a new output path')
    cfg = config_for(exp, resolve_config(args.config, args.effects))
    pred = predict_checked(Model(cfg), exp, cfg)
    signals = {k: v for k, v in exp.signals.items()
               if k in ('command_v', 'supply_pa', 't_s_k', 'setpoint_rad')}
    for key, values in exp.signals.items():
        if key in pred and key not in signals:
            signals[key] = pred[key]
    meta = {k: v for k, v in exp.metadata.items()
            if k in ('start_time_ns', 'blocked_angle_rad')}
    sim = Experiment(exp.t, signals, exp.circuit, f'{exp.name}-simulated', exp.static, meta)
    custom = {'synthetic': True,
              'generator': f'pneumatic-servo simulate {args.bag}'
                           + (f' --config {args.config}' if args.config else '')
                           + (f' --effects {",".join(args.effects)}' if args.effects else ''),
              'source': str(args.bag), 'truth': cfg.to_dict()}
    if 'blocked_angle_rad' in exp.metadata:
        custom['blocked_angle_rad'] = exp.metadata['blocked_angle_rad']
    storage = args.storage or exp.metadata.get('storage', 'sqlite3')
    write_experiment(sim, out, storage, custom)
    print(f'wrote {out} ({len(exp.t)} {"rows" if exp.static else "samples"}, '
          f'{", ".join(k for k in signals if k in pred)} predicted)')
    return 0
