"""``pneumatic-servo record OUT --duration S``: record the interface topics to a rosbag2."""
from __future__ import annotations

import argparse
import math

from ..errors import ConfigError
from ..jsonable import dumps
from ..text import comma_list
from .options import new_path, output_file, positive_seconds


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        'record', help='record the interface topics to a rosbag2 (sqlite3 or MCAP)',
        description='Record joint_states, the pressures and temperatures, valve/command and '
                    'setpoint to a new rosbag2 directory with rosbags; `ros2 bag info/play` '
                    'read it on a ROS install.')
    p.add_argument('out', metavar='OUT', type=new_path, help='new bag directory')
    p.add_argument('--duration', type=positive_seconds, required=True, metavar='S',
                   help='how long to record [s], from the first message (on /clock with '
                        '--use-sim-time)')
    p.add_argument('--wait', type=positive_seconds, default=30.0, metavar='S',
                   help='give up if no message arrives within S seconds (default 30)')
    p.add_argument('--storage', choices=('sqlite3', 'mcap'), default='sqlite3',
                   help='storage plugin (default: sqlite3)')
    p.add_argument('--topics', metavar='T1,T2', type=comma_list,
                   help='comma-separated subset of the interface topics (default: all)')
    p.add_argument('--monitor', action='store_true',
                   help="also the monitor's topics: model/joint_states and the model/ "
                        'pressures (its predictions), monitor/residuals, monitor/effects, '
                        "/diagnostics and the plant's valve/applied (compare, verify and fleet "
                        'read such a bag as if they were not there)')
    p.add_argument('--use-sim-time', action='store_true',
                   help='time stamps and duration from /clock (lockstep simulation)')
    p.add_argument('--json', metavar='PATH', type=output_file,
                   help='write the message counts as JSON')
    p.add_argument('--ros-args', dest='ros_args', nargs=argparse.REMAINDER, default=None,
                   help='everything after this goes to ROS (e.g. -r __ns:=/robot)')
    p.set_defaults(run=run)
    return p


def run(args) -> int:
    if not (args.duration > 0 and math.isfinite(args.duration)):
        raise ConfigError(f'--duration {args.duration:g}: give a positive number of seconds')
    from ..ros import require_rclpy
    require_rclpy()
    from ..ros.recorder import DEFAULT_TOPICS, MONITOR_TOPICS, check_topics, record
    topics = tuple(args.topics or DEFAULT_TOPICS)
    if args.monitor:
        topics = tuple(dict.fromkeys(topics + MONITOR_TOPICS))
    check_topics(topics)
    ros_args = ['pneumatic-servo', '--ros-args', *args.ros_args] if args.ros_args else None
    result = record(args.out, args.duration, args.storage, topics, args.use_sim_time, ros_args,
                    args.wait)
    total = sum(result['counts'].values())
    if total == 0:
        raise ConfigError(f'nothing recorded ({result["stopped"]}); is the plant running on '
                          'this ROS_DOMAIN_ID? the empty bag is at ' + result['bag'])
    print(f'recorded {total} messages to {result["bag"]} ({args.storage})')
    for topic, n in result['counts'].items():
        print(f'  {topic}: {n}')
    if args.json:
        with open(args.json, 'w') as f:
            f.write(dumps(result, indent=2))
    return 0
