"""``pneumatic-servo up``: plant and controller together, without ``ros2 launch``."""
from __future__ import annotations

import argparse

from .controller import add_controller_options, controller_overrides
from .plant import add_common, add_plant_options, plant_overrides, ros_argv


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        'up', help='run plant and controller (one process or two)',
        description='Run the plant node and the controller node, in one process or two, '
                    'without ros2 launch. Switching --backend changes nothing else in the '
                    'graph. Send setpoint (std_msgs/Float64, rad) or joint_trajectory to move.')
    add_plant_options(p, '--plant-set')
    add_controller_options(p, '--controller-set')
    p.add_argument('--processes', type=int, choices=(1, 2), default=1,
                   help='1: both nodes in this process; 2: the controller in a child process')
    p.add_argument('--record', metavar='OUT', default='',
                   help='also record the interface topics to the new bag OUT')
    p.add_argument('--storage', choices=('sqlite3', 'mcap'), default='sqlite3',
                   help='bag storage for --record (default: sqlite3)')
    add_common(p)
    p.set_defaults(run=run)
    return p


def run(args) -> int:
    from ..ros import require_rclpy
    require_rclpy()
    from ..ros.run import run_up
    plant = plant_overrides(args)
    controller = controller_overrides(args)
    if args.namespace:
        from ..errors import ConfigError
        raise ConfigError('up: use --ros-args -r __ns:=/NS to move both nodes into a namespace')
    return run_up(plant, controller, args.processes, args.duration, ros_argv(args),
                  args.record, args.storage)
