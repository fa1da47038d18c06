"""``pneumatic-servo generate OUTDIR``: regenerate the synthetic experiment library.

Runs every experiment design of the paper (flow tests, closed-port test,
heat-transfer discharge, charge/discharge, friction runs, the 2 Hz sine,
closed-loop steps and sine) on the synthetic rig through realistic sensors,
and writes rosbag2 directories (sqlite3 and MCAP), static CSV tables, the
ground truth (truth.yaml) and a README. Every record is labelled synthetic.
"""
from __future__ import annotations

import argparse

from ..text import comma_list
from .options import number


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser('generate', help='regenerate the synthetic experiment library (bags/)',
                       description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('outdir', metavar='OUTDIR', nargs='?', help='directory to write (e.g. bags/)')
    p.add_argument('--designs', metavar='D1,D2', type=comma_list,
                   help="only these designs, or designs beyond the library's (see --list)")
    p.add_argument('--seed', type=number(0, 2**32 - 1, integer=True), default=None,
                   help='base noise seed (default 2019)')
    p.add_argument('--config', metavar='CFG',
                   help='rig to generate from (default: the synthetic rig, synth.truth)')
    p.add_argument('--force', action='store_true', help='replace existing records')
    p.add_argument('--list', action='store_true', help='list the designs and exit')
    p.set_defaults(run=run)
    return p


def run(args) -> int:
    from ..errors import ConfigError
    from ..synth.designs import DESIGNS, LIBRARY
    if args.list:
        for name, design in DESIGNS.items():
            extra = '' if name in LIBRARY else ' (not in the library: give it in --designs)'
            print(f'{name:<20} {design.circuit:<12} {design.summary}{extra}')
        return 0
    if not args.outdir:
        raise ConfigError('give OUTDIR (e.g. bags/), or --list')
    from ..model.config import ModelConfig
    from ..synth.library import DEFAULT_SEED, generate_library
    designs = list(args.designs) if args.designs else None
    cfg = ModelConfig.load(args.config) if args.config else None
    written = generate_library(args.outdir, designs, DEFAULT_SEED if args.seed is None
                               else args.seed, cfg, overwrite=args.force)
    print(f'wrote {len(written)} records, truth.yaml and README.md in {args.outdir}')
    return 0
