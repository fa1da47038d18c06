"""Support for the ROS tests: isolated DDS domains, node processes, and a probe node.

Every test gets its own ``ROS_DOMAIN_ID`` (40-99) and
``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``, so tests (and other people's tests on the
same machine) never see each other's topics. Processes started here are ended here, by
their own handle.
"""
from __future__ import annotations

import itertools
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

#: [s] the plant's watchdog in the tests that are not about its period (the gate's own tests
#: run it on a clock they set). The default 0.1 s is for a rig's own machine: on a loaded
#: 2-core CI machine a process sleeping 10 ms woke 0.35 s late once in a hundred times, and
#: stalls of 0.4-1.07 s tripped it between two healthy commands
WATCHDOG_S = 3.0
#: [s] a fault shows on /diagnostics within this (the watchdog, DDS, a loaded machine)
REACTION_S = 5.0 + WATCHDOG_S


def busy_args(patience_s: float = WATCHDOG_S, flag: str = '--set') -> tuple:
    """Arguments of ``pneumatic-servo plant`` (``flag='--plant-set'``: of ``up``) for such
    tests: the watchdog above, and in lockstep the controller given up on after
    ``patience_s`` of wall time."""
    return flag, f'watchdog_s={WATCHDOG_S}', flag, f'lockstep_patience_s={patience_s:g}'


PLANT_BUSY, UP_BUSY = busy_args(), busy_args(flag='--plant-set')
#: lockstep runs whose subject is not a dead controller: a healthy one stalled for over 3 s
#: on a loaded CI machine (two test workers beside the loop), and the run was given up on
PLANT_PATIENT, UP_PATIENT = busy_args(60.0), busy_args(60.0, '--plant-set')

_counter = itertools.count()
#: domains 40-99, or half of them for each of two pytest-xdist workers (gw0, gw1)
_WORKER = os.environ.get('PYTEST_XDIST_WORKER', '')
_FIRST, _COUNT = ((40, 60) if not _WORKER.startswith('gw') else
                  (40 + 30 * (int(_WORKER[2:]) % 2), 30))
_BASE = (os.getpid() * 7) % _COUNT


def next_domain() -> int:
    """A domain id in 40-99, different for each call in this test session (and from the
    other worker's, when the suite runs on two)."""
    return _FIRST + (_BASE + next(_counter)) % _COUNT


def ros_env(domain: int) -> dict:
    env = dict(os.environ)
    env['ROS_DOMAIN_ID'] = str(domain)
    env['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    env.setdefault('PYTHONUNBUFFERED', '1')
    return env


CLI = 'import sys; from pneumatic_servo.cli import main; sys.exit(main(sys.argv[1:]))'


class Procs:
    """Processes of one test: ``start(verb, *args)`` runs ``pneumatic-servo verb args``."""

    def __init__(self, domain: int, logdir: Path):
        self.domain = domain
        self.logdir = Path(logdir)
        self.procs: list[tuple[subprocess.Popen, Path]] = []

    def start(self, *argv, name: str = '') -> subprocess.Popen:
        log = self.logdir / f'{name or argv[0]}-{len(self.procs)}.log'
        f = open(log, 'w')
        p = subprocess.Popen([sys.executable, '-c', CLI, *map(str, argv)],
                             env=ros_env(self.domain), stdout=f, stderr=subprocess.STDOUT)
        self.procs.append((p, log))
        return p

    def log(self, p) -> str:
        for q, log in self.procs:
            if q is p:
                return log.read_text()
        return ''

    def stop(self, p, sig=signal.SIGTERM, timeout: float = 10.0) -> int:
        if p.poll() is None:
            p.send_signal(sig)
        try:
            return p.wait(timeout)
        except subprocess.TimeoutExpired:
            p.kill()
            return p.wait(5)

    def cleanup(self) -> None:
        for p, _ in self.procs:
            if p.poll() is None:
                self.stop(p, signal.SIGTERM, 5.0)


def level(status) -> int:
    """DiagnosticStatus.level as an int (rclpy gives a one-byte bytes object)."""
    lv = status.level
    return lv[0] if isinstance(lv, (bytes, bytearray)) else int(lv)


def sensor_queue(depth: int = 20000) -> QoSProfile:
    """Best effort (matches the measurement publishers) with a deep queue: miss nothing."""
    return QoSProfile(depth=depth, history=HistoryPolicy.KEEP_LAST,
                      reliability=ReliabilityPolicy.BEST_EFFORT)


class Probe:
    """A node in the test process: records what the plant and controller say, sends targets
    and raw commands, calls services."""

    def __init__(self, domain: int, name: str = 'probe'):
        from diagnostic_msgs.msg import DiagnosticArray
        from sensor_msgs.msg import FluidPressure, JointState, Temperature
        from std_msgs.msg import Float64
        from trajectory_msgs.msg import JointTrajectory
        self.context = rclpy.Context()
        rclpy.init(context=self.context, domain_id=domain)
        self.node = Node(name, context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.joint = []        # (stamp s, position, velocity, receive monotonic, stamp ns)
        self.topics = {}       # topic -> list of (stamp s, value, receive monotonic, stamp ns)
        self.commands = []     # (receive monotonic, value)
        self.diagnostics = []  # (receive monotonic, DiagnosticStatus)
        n = self.node
        n.create_subscription(JointState, 'joint_states', self._on_joint, sensor_queue())
        for topic in ('chamber_a/pressure', 'chamber_b/pressure', 'supply/pressure'):
            n.create_subscription(FluidPressure, topic, self._scalar(topic, 'fluid_pressure'),
                                  sensor_queue())
        for topic in ('chamber_a/temperature', 'chamber_b/temperature'):
            n.create_subscription(Temperature, topic, self._scalar(topic, 'temperature'),
                                  sensor_queue())
        n.create_subscription(Float64, 'valve/command',
                              lambda m: self.commands.append((time.monotonic(), m.data)),
                              QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE))
        n.create_subscription(DiagnosticArray, '/diagnostics', self._on_diag,
                              QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE))
        rel = QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE)
        self.setpoint_pub = n.create_publisher(Float64, 'setpoint', rel)
        self.command_pub = n.create_publisher(Float64, 'valve/command', rel)
        self.trajectory_pub = n.create_publisher(JointTrajectory, 'joint_trajectory', rel)

    def _on_joint(self, m):
        if m.position:
            st = m.header.stamp
            self.joint.append((st.sec + st.nanosec * 1e-9, m.position[0],
                               m.velocity[0] if m.velocity else math.nan, time.monotonic(),
                               st.sec * 1_000_000_000 + st.nanosec))

    def _scalar(self, topic, field):
        def cb(m):
            st = m.header.stamp
            self.topics.setdefault(topic, []).append(
                (st.sec + st.nanosec * 1e-9, getattr(m, field), time.monotonic(),
                 st.sec * 1_000_000_000 + st.nanosec))
        return cb

    def _on_diag(self, m):
        t = time.monotonic()  # one receive time per array: its statuses are read together
        for st in m.status:
            self.diagnostics.append((t, st))

    # -------------------------------------------------------------------- spinning
    def spin(self, seconds: float) -> None:
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.executor.spin_once(timeout_sec=min(0.01, max(end - time.monotonic(), 0.0)))

    def spin_until(self, predicate, timeout: float, what: str = 'condition') -> None:
        end = time.monotonic() + timeout
        while not predicate():
            if time.monotonic() > end:
                raise AssertionError(f'timed out after {timeout:g} s waiting for {what}')
            self.executor.spin_once(timeout_sec=0.01)

    # -------------------------------------------------------------------- queries
    def diag(self, name_part: str, since: float = 0.0):
        """Latest DiagnosticStatus whose name contains ``name_part`` (received after since)."""
        for t, st in reversed(self.diagnostics):
            if t >= since and name_part in st.name:
                return st
        return None

    def diag_values(self, st) -> dict:
        return {kv.key: kv.value for kv in st.values}

    def wait_diag(self, name_part: str, predicate, timeout: float, since: float = 0.0,
                  what: str = 'diagnostics'):
        """Spin until a status of ``name_part`` satisfies ``predicate(status, values)``."""
        found = []

        def check():
            for t, st in reversed(self.diagnostics):
                if t >= since and name_part in st.name and predicate(st, self.diag_values(st)):
                    found.append(st)
                    return True
            return False
        self.spin_until(check, timeout, what)
        return found[0]

    def send(self, pub, msg, wait_subscribers: float = 10.0) -> None:
        self.spin_until(lambda: pub.get_subscription_count() > 0, wait_subscribers,
                        f'a subscriber on {pub.topic_name}')
        pub.publish(msg)

    def set_parameters(self, node_name: str, **values):
        """Call ``/node_name/set_parameters``; returns the SetParametersResult list."""
        from rcl_interfaces.srv import SetParameters
        from rclpy.parameter import Parameter
        cli = self.node.create_client(SetParameters, f'/{node_name}/set_parameters')
        self.spin_until(lambda: cli.service_is_ready(), 10.0, f'{node_name} parameters')
        req = SetParameters.Request()
        req.parameters = [Parameter(k, value=v).to_parameter_msg() for k, v in values.items()]
        results = self.call_idempotent(cli, req, 'set_parameters reply').results
        self.node.destroy_client(cli)
        return results

    def call_idempotent(self, cli, req, what: str, timeout: float = 30.0):
        """The reply to a request that may be sent again, sent again every 5 s until one
        comes. Why: a service reports ready once its request reader has matched ours; the
        reply writer may match our reader later, and a reply sent before is lost (seen on
        a loaded machine)."""
        end = time.monotonic() + timeout
        while True:
            fut = cli.call_async(req)
            try:
                self.spin_until(lambda: fut.done(), min(5.0, end - time.monotonic()), what)
                return fut.result()
            except AssertionError:
                cli.remove_pending_request(fut)
                if time.monotonic() >= end:
                    raise AssertionError(f'timed out after {timeout:g} s waiting for {what}')

    def change_state(self, node_name: str, transition_id: int) -> bool:
        from lifecycle_msgs.msg import Transition
        from lifecycle_msgs.srv import ChangeState
        cli = self.node.create_client(ChangeState, f'/{node_name}/change_state')
        self.spin_until(lambda: cli.service_is_ready(), 10.0, f'{node_name} change_state')
        fut = cli.call_async(ChangeState.Request(transition=Transition(id=transition_id)))
        self.spin_until(lambda: fut.done(), 10.0, 'change_state reply')
        self.node.destroy_client(cli)
        return fut.result().success

    def close(self) -> None:
        """Executor first: its suspended wait generator can hold the node's handles in use,
        which defers their destruction to an arbitrary later moment (a rare segfault in
        ``destroy_node`` was seen once in CI with the old order); then node, then context."""
        self.executor.shutdown(timeout_sec=5.0)
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.context)
