"""``pneumatic-servo plant``: run the plant node alone (sim, rig or replay backend)."""
from __future__ import annotations

import argparse
import math

from .options import number, positive_seconds_or_inf


def add_common(p: argparse.ArgumentParser) -> None:
    """Options every ROS verb shares."""
    p.add_argument('--duration', type=positive_seconds_or_inf, default=math.inf, metavar='S',
                   help='stop after S wall-clock seconds (default: until Ctrl-C / SIGTERM)')
    p.add_argument('--namespace', default='', metavar='NS',
                   help='ROS namespace for the nodes (topics are relative and move with it)')
    p.add_argument('--ros-args', dest='ros_args', nargs=argparse.REMAINDER, default=None,
                   help='everything after this goes to ROS (-p name:=value, --params-file F, '
                        '-r from:=to)')


def add_plant_options(p: argparse.ArgumentParser, set_flag: str = '--set') -> None:
    p.add_argument('--backend', choices=('sim', 'rig', 'replay'), default='sim',
                   help='what is behind the plant node (default: sim)')
    p.add_argument('--clock', choices=('free', 'lockstep'), default='free',
                   help='sim: free-running real time or lockstep with the controller '
                        '(default: free)')
    p.add_argument('--rate', type=number(1.0, 10000.0, unit='Hz'), metavar='HZ',
                   help='sample rate (default 1000 Hz)')
    p.add_argument('--config', metavar='CFG', help="model config YAML (default: the paper's)")
    p.add_argument('--rig-config', metavar='YAML',
                   help='rig wiring and scaling (default: config/rig_pci6229.yaml)')
    p.add_argument('--daq', choices=('nidaqmx', 'virtual'),
                   help='rig: DAQ driver (default nidaqmx; virtual simulates the card)')
    p.add_argument('--bag', metavar='BAG', help='replay: the rosbag2 directory to play')
    p.add_argument(set_flag, dest='plant_set', action='append', default=[],
                   metavar='NAME=VALUE', help='any plant parameter, e.g. watchdog_s=0.05')


def plant_overrides(args) -> dict:
    """Plant parameter values from the options (validated: ConfigError names a bad one)."""
    from ..ros.plant_specs import PLANT_SPECS
    values = PLANT_SPECS.parse_assignments(args.plant_set)
    values.setdefault('backend', args.backend)
    values.setdefault('clock_mode', args.clock)
    for opt, name in (('rate', 'rate_hz'), ('config', 'model_config'),
                      ('rig_config', 'rig_config'), ('daq', 'daq'), ('bag', 'bag')):
        value = getattr(args, opt, None)
        if value is not None:
            values[name] = PLANT_SPECS[name].coerce(value)
    reason = PLANT_SPECS.validate(values)
    if reason:
        from ..errors import ConfigError
        raise ConfigError(reason)
    return values


def ros_argv(args) -> list | None:
    return ['pneumatic-servo', '--ros-args', *args.ros_args] if args.ros_args else None


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        'plant', help='run the plant node (sim, rig or replay backend)',
        description='Run the plant node alone: it publishes joint_states, the chamber and '
                    'supply pressures (and temperatures when known), takes valve/command '
                    'through the safety gate, and reports on /diagnostics. Pair it with '
                    '`pneumatic-servo controller` or your own stack.')
    add_plant_options(p)
    add_common(p)
    p.set_defaults(run=run)
    return p


def run(args) -> int:
    from ..ros import require_rclpy
    require_rclpy()
    from ..ros.loop import run_nodes
    from ..ros.run import exit_code, make_plant
    overrides = plant_overrides(args)
    reason = run_nodes([lambda: make_plant(overrides, args.namespace)], args.duration,
                       ros_argv(args))
    return exit_code(reason)
