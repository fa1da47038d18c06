"""Record the interface topics to a rosbag2 with ``rosbags`` (sqlite3 or MCAP).

Messages are taken serialized (CDR, exactly as on the wire) and written as they are, with
the record time of the node's clock (sim time with ``use_sim_time``). A stamped message
identical to the one before it on its topic is a lockstep plant's resend of an unanswered
sample, and is recorded once. The bag is a standard rosbag2 directory: ``metadata.yaml``
version 9 with each topic's type, type-description hash (RIHS01, which must match what
ROS 2 Jazzy computes) and the publishers' offered QoS, so ``ros2 bag info/play`` on a ROS
install read it as they read their own. ``custom_data`` carries
``pneumatic_servo.circuit: servo``.
"""
from __future__ import annotations

import math
import time
from pathlib import Path

from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

from ..errors import ConfigError
from ..io.bag import BAG_VERSION, add_topic
from . import common, private

#: topics recorded by default (relative: a namespace moves them)
DEFAULT_TOPICS = (common.JOINT_STATES, common.PRESSURE_A, common.PRESSURE_B,
                  common.PRESSURE_SUPPLY, common.TEMPERATURE_A, common.TEMPERATURE_B,
                  common.COMMAND, common.SETPOINT, common.TRAJECTORY)
#: what ``record --monitor`` adds: the monitor's predictions and statistics, /diagnostics
#: (its verdicts over time) and valve/applied (the input it used)
MONITOR_TOPICS = tuple(common.MONITOR_TOPIC_TYPES) + (common.VALVE_APPLIED,)
STORAGES = ('sqlite3', 'mcap')
#: reliable topics (commands, targets, reports); the rest are sensor data (best effort)
RELIABLE = (common.COMMAND, common.SETPOINT, common.TRAJECTORY, common.MONITOR_RESIDUALS,
            common.MONITOR_EFFECTS, common.DIAGNOSTICS)


def check_topics(topics) -> None:
    """ConfigError unless every topic is one the recorder knows (checked before any file is
    made, so a bad name leaves no half-written bag)."""
    unknown = [t for t in topics if t not in common.TOPIC_TYPES]
    if unknown or not topics:
        raise ConfigError(f'cannot record {", ".join(map(repr, unknown)) or "no topics"}: known '
                          f'topics are {", ".join(common.TOPIC_TYPES)}')


def _typestore():
    from rosbags.typesys import Stores, get_typestore
    return get_typestore(Stores.ROS2_JAZZY)


class RecorderNode(Node):
    """Writes ``topics`` to the bag ``out`` until :meth:`close` (or ``duration_s`` of its clock).

    Parameters
    ----------
    out : path
        New bag directory (must not exist).
    storage : str
        'sqlite3' (default) or 'mcap'.
    duration_s : float [s]
        Stop after this long on the node's clock, from the first message (inf: until closed).
    """

    def __init__(self, out, storage: str = 'sqlite3', duration_s: float = math.inf,
                 topics=DEFAULT_TOPICS, node_name: str = 'pneumatic_servo_recorder', **kwargs):
        super().__init__(node_name, **kwargs)
        from rosbags.rosbag2 import StoragePlugin, Writer
        if storage not in STORAGES:
            raise ConfigError(f'storage {storage!r}: use one of {", ".join(STORAGES)}')
        self.out = Path(out)
        if self.out.exists():
            raise ConfigError(f'{self.out} exists; record into a new directory')
        if not self.out.parent.exists():
            raise ConfigError(f'parent directory {self.out.parent} does not exist')
        check_topics(topics)
        plugin = StoragePlugin.SQLITE3 if storage == 'sqlite3' else StoragePlugin.MCAP
        self.writer = Writer(self.out, version=BAG_VERSION, storage_plugin=plugin)
        self.writer.set_custom_data('pneumatic_servo.circuit', 'servo')
        self.writer.set_custom_data('pneumatic_servo.recorder', 'pneumatic-servo record')
        self.writer.open()
        store = _typestore()
        self.duration_s = duration_s
        self.counts = {}
        self._first = None
        self.done = False
        # with use_sim_time the clock is hot and first: a message is stamped with the sim
        # time of the sample it belongs to, not with a clock updated a few periods late
        clock_sub = private.clock_subscription(self)
        self.hot_subscriptions = [clock_sub] if clock_sub is not None else []
        for topic in topics:
            msgtype = common.TOPIC_TYPES[topic]
            full = self.resolve_topic_name(topic)
            reliable = topic in RELIABLE
            conn = add_topic(self.writer, full, msgtype, store, reliable)
            # deep queues: the recorder may lag a burst (lockstep runs faster than real time)
            qos = QoSProfile(depth=2000, history=HistoryPolicy.KEEP_LAST,
                             reliability=(ReliabilityPolicy.RELIABLE if reliable
                                          else ReliabilityPolicy.BEST_EFFORT),
                             durability=DurabilityPolicy.VOLATILE)
            cls = _msg_class(msgtype)
            stamped = 'header' in cls.get_fields_and_field_types()
            sub = self.create_subscription(cls, topic, self._writer_cb(conn, full, stamped),
                                           qos, raw=True)
            self.hot_subscriptions.append(sub)
            self.counts[full] = 0

    def _writer_cb(self, conn, topic, stamped: bool):
        last = [None]

        def cb(data: bytes):
            if self.done:
                return
            now = self.get_clock().now().nanoseconds
            if stamped and data == last[0]:
                return  # a lockstep plant resent an unanswered sample: the same message
            last[0] = data
            if self._first is None:
                self._first = now
            elif now - self._first > self.duration_s * 1e9:
                self.done = True
                return
            self.writer.write(conn, now, data)
            self.counts[topic] += 1
        return cb

    @property
    def receiving(self) -> bool:
        """Whether the first message has been written."""
        return self._first is not None

    def next_deadline(self) -> float:
        return math.inf

    def tick(self, now: float) -> None:
        pass

    def close(self) -> dict:
        """Finish the bag (writes metadata.yaml); returns message counts by topic."""
        self.done = True
        if self.writer is not None:
            self.writer.close()
            self.writer = None
        return dict(self.counts)

    def shutdown(self, reason: str) -> None:
        """Stop writing (the event loop's safe shutdown); the bag is finished on
        :meth:`destroy_node`."""
        self.done = True

    def destroy_node(self):
        self.close()
        return super().destroy_node()


def _msg_class(msgtype: str):
    pkg, _, name = msgtype.split('/')
    import importlib
    return getattr(importlib.import_module(f'{pkg}.msg'), name)


def record(out, duration_s: float, storage: str = 'sqlite3', topics=DEFAULT_TOPICS,
           use_sim_time: bool = False, args=None, wait_s: float = 30.0) -> dict:
    """Record ``duration_s`` seconds from the first message (wall seconds, or node-clock
    seconds with sim time); wait up to ``wait_s`` for that first message. Returns
    ``{'bag': path, 'counts': {...}, 'stopped': why}``. Initialises and shuts down rclpy."""
    from .loop import run_nodes
    made = []

    def make():
        made.append(RecorderNode(out, storage, duration_s if use_sim_time else math.inf,
                                 topics, parameter_overrides=common.sim_time(use_sim_time)))
        return made[0]

    clock = {}

    def stop_when() -> str:
        rec, now = made[0], time.monotonic()
        clock.setdefault('start', now)
        if rec.done:
            return 'duration'
        if 'first' not in clock:
            if rec.receiving:
                clock['first'] = now
            elif now - clock['start'] > wait_s:
                return f'no message on {", ".join(topics)} within {wait_s:g} s'
        elif not use_sim_time and now - clock['first'] >= duration_s:
            return 'duration'
        return ''

    reason = run_nodes([make], ros_args=args, stop_when=stop_when)
    return {'bag': str(out), 'counts': dict(made[0].counts) if made else {},
            'stopped': reason}
