"""``pneumatic-servo identify INPUT... --out CFG.yaml``: the paper's identification procedures.

INPUT is any mix of bag directories, static CSV tables and directories of
them (e.g. ``bags/``). Each record is used by the procedure it suits:
flow tables -> flow coefficient C1 (Eq. 38) and its polynomial (Eq. 40);
blocked records with temperatures -> heat transfer coefficient h (Eqs 41-42);
servo runs at held voltages -> Stribeck friction (Eq. 43, Fig. 16, both the
geometric construction and least squares). ``--refine`` then fits chosen
parameters by output error over chosen records together and prints their
standard errors and correlation matrix. The config is written as YAML that
the nodes and every verb take as it is.
"""
from __future__ import annotations

import argparse
from pathlib import Path

from ..jsonable import dumps
from ..text import comma_list
from .options import number, output_dir, output_file, positive_seconds


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser('identify', help='identify C1, h and friction from recorded experiments; '
                       'write a config YAML', description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('inputs', nargs='+', metavar='INPUT',
                   help='bag directories, static CSV files, or directories holding them')
    p.add_argument('--out', required=True, metavar='CFG', type=output_file,
                   help='config YAML to write')
    p.add_argument('--config', metavar='BASE', help='base config YAML: geometry and everything '
                   'not identified (default: the paper\'s)')
    p.add_argument('--steps', type=comma_list, default='flow,heat,friction', metavar='S1,S2',
                   help='procedures to run: flow, heat, friction (default all that have data)')
    p.add_argument('--friction-method', choices=('least_squares', 'geometric'),
                   default='least_squares', help='Stribeck estimate written to the config')
    p.add_argument('--thermocouple-tau', type=positive_seconds, default=None, metavar='S',
                   help='thermocouple time constant [s] (default: from the records\' metadata)')
    p.add_argument('--refine', metavar='KEY1,KEY2', type=comma_list,
                   help="parameters ('owner.name') to refine by output error afterwards")
    p.add_argument('--refine-on', nargs='+', metavar='BAG',
                   help='records for the refinement (default: every time series given)')
    p.add_argument('--refine-bounds', metavar='KEY=LO:HI,...', type=comma_list,
                   help='bounds of refined parameters [SI] (default: their declared bounds)')
    p.add_argument('--refine-mode', choices=('open_loop', 'k_step'), default='open_loop')
    p.add_argument('--max-nfev', type=number(1, 10000, integer=True), default=30,
                   help='refinement evaluations (default %(default)s)')
    p.add_argument('--json', metavar='PATH', type=output_file, help='write the results as JSON')
    p.add_argument('--plots', metavar='DIR', type=output_dir,
                   help='write the identification plots into DIR')
    p.set_defaults(run=run)
    return p


def expand_inputs(inputs) -> list[Path]:
    """Bag directories and CSV files named or contained (one level) in ``inputs``."""
    from ..errors import ExperimentError
    out = []
    for item in inputs:
        path = Path(item)
        if not path.exists():
            raise ExperimentError(f'{path}: no such bag, CSV file or directory')
        if path.is_dir() and not (path / 'metadata.yaml').exists() and not any(
                p.suffix in ('.db3', '.mcap') for p in path.iterdir()):
            found = sorted(p for p in path.iterdir() if p.suffix == '.csv'
                           or (p.is_dir() and (p / 'metadata.yaml').exists()))
            if not found:
                raise ExperimentError(f'{path}: holds no bag directory or CSV file')
            out += found
        else:
            out.append(path)
    return out


def parse_bounds(items) -> dict | None:
    """``key=lo:hi`` items (of ``--refine-bounds key=lo:hi,key2=lo:hi``) -> {key: (lo, hi)}."""
    from ..errors import ConfigError
    if not items:
        return None
    out = {}
    for item in items:
        key, _, span = item.partition('=')
        lo, _, hi = span.partition(':')
        try:
            out[key.strip()] = (float(lo), float(hi))
        except ValueError:
            raise ConfigError(f"--refine-bounds: cannot read {item!r}; write key=lower:upper "
                              "in SI units, e.g. stribeck_friction.coulomb_friction_n=2:12"
                              ) from None
    return out


def run(args) -> int:
    from ..identification.identify import identify
    from ..io import read_experiment
    from ..model.config import ModelConfig
    base = ModelConfig.load(args.config) if args.config else ModelConfig.paper()
    experiments = [read_experiment(p) for p in expand_inputs(args.inputs)]
    steps = list(args.steps)
    refine = list(args.refine) if args.refine else None
    refine_on = ([read_experiment(p) for p in expand_inputs(args.refine_on)]
                 if args.refine_on else None)
    result = identify(experiments, base, steps=steps, friction_method=args.friction_method,
                      tc_time_constant_s=args.thermocouple_tau, refine=refine,
                      refine_experiments=refine_on, refine_mode=args.refine_mode,
                      refine_bounds=parse_bounds(args.refine_bounds), max_nfev=args.max_nfev)
    print(result.summary())
    result.config.save(args.out, header=result.header())
    print(f'wrote {args.out}')
    if args.json:
        Path(args.json).write_text(dumps(result.to_dict(), indent=2))
        print(f'wrote {args.json}')
    if args.plots:
        _plots(Path(args.plots), result, experiments)
    return 0


def _plots(directory: Path, result, experiments) -> None:
    from ..identification.flow_coefficient import plot_flow_coefficient
    from ..identification.friction import plot_friction
    from ..identification.heat_transfer import plot_heat_transfer
    directory.mkdir(parents=True, exist_ok=True)
    if result.flow is not None:
        plot_flow_coefficient(result.flow, directory / 'flow_coefficient.png')
    if result.friction is not None:
        plot_friction(result.friction, directory / 'friction.png')
    by_name = {e.name: e for e in experiments}
    for i, r in enumerate(result.heat):
        name = result.used['heat'][min(i, len(result.used['heat']) - 1)]
        exp = by_name.get(name)
        if exp is not None and len(exp.t) == len(r.t):
            plot_heat_transfer(exp, r, directory / f'heat_transfer_{i}_{r.chamber}.png')
    print(f'wrote plots into {directory}')
