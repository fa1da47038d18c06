"""``pneumatic-servo monitor``: the model beside a running rig (the monitor node)."""
from __future__ import annotations

import argparse

from .options import positive_seconds
from .plant import add_common, ros_argv


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        'monitor', help='judge a running rig against its model, live (the monitor node)',
        description='Run the monitor node beside any plant (sim, rig or replay): it predicts '
                    'joint_states and the chamber pressures k-step from the measured state '
                    'with the identified model, publishes the predictions under model/, '
                    'judges every window against its own prediction floor and says on '
                    '/diagnostics, per channel, OK / WARN / ERROR with the departure in '
                    'units of the floor, the regime and the p-value, at a stated '
                    'false-alarm rate per hour. It never publishes valve/command.')
    p.add_argument('--config', metavar='CFG',
                   help="the identified model (default: the paper's)")
    p.add_argument('--floor', metavar='FILE',
                   help='floor file: loaded if it exists (judging starts at once), else '
                        'measured on the baseline and saved there')
    p.add_argument('--baseline', metavar='S', type=positive_seconds,
                   help='seconds of data the floor is measured on (default 20)')
    p.add_argument('--track', metavar='E1,E2',
                   help='effects fitted when a channel departs, e.g. piston_seal_leakage')
    p.add_argument('--set', dest='monitor_set', action='append', default=[],
                   metavar='NAME=VALUE', help='any monitor parameter, e.g. '
                                              'false_alarm_per_hour=0.1')
    add_common(p)
    p.set_defaults(run=run)
    return p


def monitor_overrides(args) -> dict:
    """Monitor parameter values from the options (validated: ConfigError names a bad one)."""
    from ..errors import ConfigError
    from ..ros.monitor_specs import MONITOR_SPECS
    values = MONITOR_SPECS.parse_assignments(args.monitor_set)
    for opt, name in (('config', 'model_config'), ('floor', 'floor_file'),
                      ('baseline', 'baseline_s'), ('track', 'track')):
        value = getattr(args, opt, None)
        if value is not None:
            values[name] = MONITOR_SPECS[name].coerce(value)
    reason = MONITOR_SPECS.validate(values)
    if reason:
        raise ConfigError(reason)
    return values


def run(args) -> int:
    from ..ros import require_rclpy
    require_rclpy()
    from ..ros.loop import run_nodes
    from ..ros.run import exit_code, make_monitor
    overrides = monitor_overrides(args)
    reason = run_nodes([lambda: make_monitor(overrides, args.namespace)], args.duration,
                       ros_argv(args))
    return exit_code(reason)
