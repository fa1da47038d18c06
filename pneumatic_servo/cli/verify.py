"""``pneumatic-servo verify BAG``: a regression test of the model against a recorded experiment.

Replays the bag through the model (open loop by default, like the paper's
Section 6.3) and checks the largest absolute error of each measured channel:
angle against --max-angle-error (degrees, default the paper's 1.25) and the
chamber pressures against --max-pressure-error (Pa by default, default the
paper's 4e-3 MPa = 4000 Pa; a unit may be given: '4 kPa', '0.004 MPa').
Exit status: 0 all channels pass, 1 a channel fails (the table names it),
2 bad input.
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

from ..analysis.compare import PAPER_MAX_ANGLE_ERROR_DEG, PAPER_MAX_PRESSURE_ERROR_PA
from ..jsonable import dumps
from ..prediction import COMPARE_HORIZON_S
from ..text import comma_list
from .options import output_file, positive_seconds, seconds


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser('verify', help='check a recorded experiment against the model; exit 0 '
                       'if within the error limits, 1 if not', description=__doc__,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('bag', metavar='BAG', help='rosbag2 directory (sqlite3 or MCAP) or static CSV')
    add_limit_arguments(p)
    p.add_argument('--max-flow-error', default=None, metavar='KG_S',
                   help='largest accepted flow error [kg/s] (static flow tables; default: '
                        'flows are reported, not checked)')
    p.add_argument('--config', metavar='CFG', help='model config YAML (default: the paper\'s)')
    p.add_argument('--effects', metavar='E1,E2', type=comma_list,
                   help='catalogue effects to add (default values)')
    p.add_argument('--mode', choices=('open_loop', 'k_step'), default='open_loop',
                   help='prediction view whose errors are checked (default open_loop)')
    p.add_argument('--horizon', type=positive_seconds, default=COMPARE_HORIZON_S, metavar='S',
                   help='k-step prediction horizon [s] (default %(default)g)')
    p.add_argument('--skip', type=seconds, default=0.0, metavar='S',
                   help='leave the first S seconds out of the check')
    p.add_argument('--json', metavar='PATH', type=output_file, help='write the check as JSON')
    p.set_defaults(run=run)
    return p


def add_limit_arguments(p) -> None:
    """--max-angle-error and --max-pressure-error, defaults the paper's (shared with fleet)."""
    p.add_argument('--max-angle-error', default=f'{PAPER_MAX_ANGLE_ERROR_DEG:g}', metavar='DEG',
                   help='largest accepted angle error [deg] (default %(default)s, the paper\'s)')
    p.add_argument('--max-pressure-error', default=f'{PAPER_MAX_PRESSURE_ERROR_PA:g}',
                   metavar='PA', help='largest accepted chamber pressure error [Pa, or with a '
                   'unit such as "4 kPa"] (default %(default)s Pa, the paper\'s)')


def _value(text: str, unit: str, what: str) -> float:
    """A positive limit: a bare number is in ``unit``; '4 kPa' and the like are converted."""
    from ..errors import ConfigError
    from ..model.units import to_si
    try:
        value = float(text)
    except ValueError:
        if unit != 'deg':
            value = to_si(text, unit, what)
        else:  # converted through rad, but the user thinks in degrees
            try:
                value = math.degrees(to_si(text, 'rad', what))
            except ConfigError:
                raise ConfigError(f"{what}: cannot read {text!r}; write a number in deg or a "
                                  "value with a unit such as '1.5 deg'") from None
    if not (value > 0 and math.isfinite(value)):
        raise ConfigError(f'{what} must be a positive number, got {text!r}')
    return value


def limits_from(args) -> dict:
    """The error limits [SI] of the --max-*-error options (shared with ``fleet``)."""
    from ..analysis.compare import limits_for
    flow = getattr(args, 'max_flow_error', None)
    return limits_for(_value(args.max_angle_error, 'deg', '--max-angle-error'),
                      _value(args.max_pressure_error, 'Pa', '--max-pressure-error'),
                      None if flow is None else _value(flow, 'kg/s', '--max-flow-error'))


def run(args) -> int:
    from ..analysis.compare import format_table, verify
    from ..io import read_experiment
    limits = limits_from(args)
    exp = read_experiment(args.bag)
    ok, rows, result = verify(exp, args.config, effects=args.effects, limits=limits,
                              mode=args.mode, horizon_s=args.horizon, skip_s=args.skip)
    print(f'{exp.name}: {args.mode.replace("_", "-")} prediction vs measurement')
    print(format_table(rows))
    failing = [r['channel'] for r in rows if r['passed'] is False]
    print('PASS' if ok else f'FAIL: {", ".join(failing)}')
    if args.json:
        Path(args.json).write_text(dumps({'passed': ok, 'failing': failing, 'rows': rows,
                                          'compare': result}, indent=2))
    return 0 if ok else 1

