"""``pneumatic-servo controller``: run the controller node alone."""
from __future__ import annotations

import argparse

from .plant import add_common, ros_argv


def add_controller_options(p: argparse.ArgumentParser, set_flag: str = '--set') -> None:
    p.add_argument('--controller', dest='controller', choices=('pid', 'smc'), default='pid',
                   help='control law: pid, or smc (model-based sliding mode) (default: pid)')
    p.add_argument(set_flag, dest='controller_set', action='append', default=[],
                   metavar='NAME=VALUE', help='any controller parameter, e.g. kp=8.0')


def controller_overrides(args) -> dict:
    from ..ros.controller_node import CONTROLLER_SPECS
    values = CONTROLLER_SPECS.parse_assignments(args.controller_set)
    values.setdefault('controller', args.controller)
    reason = CONTROLLER_SPECS.validate(values)
    if reason:
        from ..errors import ConfigError
        raise ConfigError(reason)
    return values


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        'controller', help='run the controller node (PID or model-based)',
        description='Run the position controller: it follows setpoint (rad) and '
                    'joint_trajectory, reads joint_states and the pressures, and publishes '
                    'valve/command (V).')
    add_controller_options(p)
    p.add_argument('--use-sim-time', action='store_true',
                   help='run on /clock (lockstep simulation, bag replay)')
    add_common(p)
    p.set_defaults(run=run)
    return p


def run(args) -> int:
    from ..ros import require_rclpy
    require_rclpy()
    from ..ros.loop import run_nodes
    from ..ros.run import exit_code, make_controller
    overrides = controller_overrides(args)
    reason = run_nodes([lambda: make_controller(overrides, args.use_sim_time, args.namespace)],
                       args.duration, ros_argv(args))
    return exit_code(reason)
