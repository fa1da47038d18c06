"""Timing of the ROS nodes over real DDS (this is not a test: it prints what it measures).

* free-running sim plant at 1 kHz with the PID controller in another process, tracking a
  0.5 Hz sine: the rate the plant achieves and the p50/p99 jitter of its loop period (its
  own monotonic clock), the share of samples the controller answered, and the closed-loop
  latency plant publish -> command received (p50/p99, measured in the plant);
* lockstep simulation: simulated seconds per wall second, with plant and controller in two
  processes and in one process (``pneumatic-servo up --processes 1``).

Targets (issue 3): >= 99 % of 1 kHz with p99 jitter <= 1 ms; lockstep >= 5x real time.
The machine's load is printed too: these are wall-clock figures on shared cores.

Usage::

    python benchmarks/bench_ros.py [--seconds S] [--json PATH]
"""
from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

CLI = 'import sys; from pneumatic_servo.cli import main; sys.exit(main(sys.argv[1:]))'
TARGET_RATE, TARGET_JITTER_MS, TARGET_LOCKSTEP = 0.99, 1.0, 5.0


def env(domain: int) -> dict:
    e = dict(os.environ)
    e.update(ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST')
    return e


def start(domain: int, *argv) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, '-c', CLI, *map(str, argv)], env=env(domain),
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def stop(procs) -> None:
    for p in procs:
        if p.poll() is None:
            p.terminate()
    for p in procs:
        try:
            p.wait(10)
        except subprocess.TimeoutExpired:
            p.kill()


class Listener:
    """Reads the plant's /diagnostics and counts joint_states in this process."""

    def __init__(self, domain: int, joint: bool = True):
        import rclpy
        from diagnostic_msgs.msg import DiagnosticArray
        from rclpy.node import Node
        from rclpy.qos import QoSProfile, ReliabilityPolicy
        from sensor_msgs.msg import JointState
        self.rclpy = rclpy
        self.ctx = rclpy.Context()
        rclpy.init(context=self.ctx, domain_id=domain)
        self.node = Node('bench_listener', context=self.ctx)
        from rclpy.executors import SingleThreadedExecutor
        self.executor = SingleThreadedExecutor(context=self.ctx)
        self.executor.add_node(self.node)
        self.plant = {}
        self.joint = 0
        self.node.create_subscription(DiagnosticArray, '/diagnostics', self._diag,
                                      QoSProfile(depth=100,
                                                 reliability=ReliabilityPolicy.RELIABLE))
        if joint:  # not in lockstep: a third reader of every sample slows the loop down
            self.node.create_subscription(JointState, 'joint_states', self._js,
                                          QoSProfile(depth=1000,
                                                     reliability=ReliabilityPolicy.BEST_EFFORT))
        from std_msgs.msg import Float64
        from trajectory_msgs.msg import JointTrajectory
        self.traj = self.node.create_publisher(JointTrajectory, 'joint_trajectory', 10)
        self.Float64 = Float64

    def _diag(self, msg):
        for st in msg.status:
            if 'plant' in st.name:
                self.plant = {kv.key: kv.value for kv in st.values}
                self.plant['_message'] = st.message
                self.plant['_t'] = time.monotonic()

    def _js(self, msg):
        self.joint += 1

    def spin(self, seconds: float) -> None:
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            self.executor.spin_once(timeout_sec=0.01)

    def wait(self, pred, timeout: float) -> bool:
        end = time.monotonic() + timeout
        while not pred():
            if time.monotonic() > end:
                return False
            self.executor.spin_once(timeout_sec=0.01)
        return True

    def value(self, key: str) -> float:
        try:
            return float(self.plant.get(key, 'nan'))
        except ValueError:
            return math.nan

    def close(self) -> None:
        self.node.destroy_node()
        self.rclpy.try_shutdown(context=self.ctx)


def sine_trajectory(listener, start_s: float, seconds: float):
    from pneumatic_servo.control.reference import sine_points
    from pneumatic_servo.ros.common import joint_trajectory
    pts = sine_points(start_s, seconds, math.radians(105), math.radians(45), 0.5)
    return joint_trajectory(pts, 'actuator_joint')


def bench_free(domain: int, seconds: float, priority: int = 0) -> dict:
    lis = Listener(domain)
    procs = [start(domain, 'plant', '--set', f'realtime_priority={priority}'),
             start(domain, 'controller')]
    try:
        if not lis.wait(lambda: lis.plant.get('state') == 'active'
                        and lis.traj.get_subscription_count() > 0, 90):
            raise RuntimeError('plant or controller did not start')
        lis.spin(1.0)
        now_s = lis.node.get_clock().now().nanoseconds * 1e-9
        lis.traj.publish(sine_trajectory(lis, now_s + 0.2, seconds + 5.0))
        lis.spin(1.0)
        c0, j0, t0 = lis.value('commands'), lis.joint, time.monotonic()
        s0 = lis.value('samples')
        lis.spin(seconds)
        dt = time.monotonic() - t0
        samples = lis.value('samples') - s0
        # kill -9 the controller: how long until the plant's diagnostics report the watchdog
        t_kill = time.monotonic()
        procs[1].kill()
        lis.wait(lambda: 'watchdog' in lis.plant.get('_message', ''), 10.0)
        reaction_s = time.monotonic() - t_kill
        return {'watchdog_reaction_s': reaction_s,
                'achieved_rate_hz': lis.value('achieved_rate_hz'),
                'jitter_p50_ms': lis.value('jitter_p50_ms'),
                'jitter_p99_ms': lis.value('jitter_p99_ms'),
                'overruns': lis.value('overruns'),
                'latency_p50_ms': lis.value('latency_p50_ms'),
                'latency_p99_ms': lis.value('latency_p99_ms'),
                'answered_fraction': (lis.value('commands') - c0) / samples if samples else 0,
                'listener_rate_hz': (lis.joint - j0) / dt, 'plant_state': lis.plant['_message'],
                'scheduling': lis.plant.get('scheduling', '?')}
    finally:
        stop(procs)
        lis.close()


def bench_lockstep(domain: int, seconds: float, processes: int) -> dict:
    lis = Listener(domain, joint=False)
    if processes == 2:
        procs = [start(domain, 'controller', '--use-sim-time'),
                 start(domain, 'plant', '--clock', 'lockstep')]
    else:
        procs = [start(domain, 'up', '--clock', 'lockstep', '--processes', '1')]
    try:
        if not lis.wait(lambda: lis.value('sim_time_s') > 0.5, 90):
            raise RuntimeError('lockstep did not start')
        lis.spin(0.5)
        sim0, t0 = lis.value('sim_time_s'), lis.plant['_t']
        lis.spin(seconds)
        sim1, t1 = lis.value('sim_time_s'), lis.plant['_t']
        return {'speed_x_real_time': (sim1 - sim0) / (t1 - t0), 'sim_s': sim1 - sim0,
                'wall_s': t1 - t0, 'resends': lis.value('resends')}
    finally:
        stop(procs)
        lis.close()


ECHO = """
import sys, rclpy
from std_msgs.msg import Float64
from pneumatic_servo.ros import private
rclpy.init()
node = rclpy.create_node('echo')
pub = node.create_publisher(Float64, 'pong', 10)
kind = sys.argv[1]
if kind == 'waitset':
    sub = node.create_subscription(Float64, 'ping', lambda m: None, 10)
    ws = private.wait_set(node.context, 1)
    while rclpy.ok():
        if private.is_ready(sub, private.wait(ws, [sub], 100_000_000)):
            msg = private.take(sub)
            if msg is not None:
                pub.publish(msg)
else:
    node.create_subscription(Float64, 'ping', pub.publish, 10)
    if kind == 'events':
        from rclpy.experimental import EventsExecutor
        ex = EventsExecutor()
    else:
        from rclpy.executors import SingleThreadedExecutor
        ex = SingleThreadedExecutor()
    ex.add_node(node)
    ex.spin()
"""


def bench_executor(domain: int, kind: str, seconds: float) -> dict:
    """Round trips per second through an echo node spun by ``kind`` in another process (one
    message in flight: what a 1 kHz loop needs is a round trip well under 1 ms)."""
    import rclpy
    from std_msgs.msg import Float64

    from pneumatic_servo.ros import private
    echo = subprocess.Popen([sys.executable, '-c', ECHO, kind], env=env(domain),
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    ctx = rclpy.Context()
    rclpy.init(context=ctx, domain_id=domain)
    try:
        node = rclpy.create_node('pinger', context=ctx)
        pub = node.create_publisher(Float64, 'ping', 10)
        sub = node.create_subscription(Float64, 'pong', lambda m: None, 10)
        ws = private.wait_set(ctx, 1)
        end = time.monotonic() + 30
        while pub.get_subscription_count() == 0 or sub.get_publisher_count() == 0:
            if time.monotonic() > end:
                raise RuntimeError(f'echo node ({kind}) did not start')
            time.sleep(0.05)
        time.sleep(0.5)
        lat, t_end, seq = [], time.monotonic() + seconds, 0.0
        while time.monotonic() < t_end:
            seq += 1.0
            t0 = time.perf_counter()
            pub.publish(Float64(data=seq))
            while True:  # wait for this message's echo (late ones of a lost turn are skipped)
                if private.is_ready(sub, private.wait(ws, [sub], 100_000_000)):
                    msg = private.take(sub)
                    if msg is not None and msg.data == seq:
                        break
                if time.perf_counter() - t0 > 0.1:
                    break
            lat.append(time.perf_counter() - t0)
        lat = np.array(lat)
        return {'round_trips_per_s': len(lat) / seconds,
                'latency_p50_ms': 1e3 * float(np.percentile(lat, 50)),
                'latency_p99_ms': 1e3 * float(np.percentile(lat, 99))}
    finally:
        echo.terminate()
        try:
            echo.wait(5)
        except subprocess.TimeoutExpired:  # the EventsExecutor does not stop on SIGTERM
            echo.kill()
            echo.wait(5)
        rclpy.shutdown(context=ctx)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--seconds', type=float, default=8.0, help='measuring time per case [s]')
    ap.add_argument('--json', metavar='PATH', help='also write the figures as JSON')
    args = ap.parse_args()
    domain = int(os.environ.get('PNEUMATIC_SERVO_BENCH_DOMAIN', 90 + os.getpid() % 10))
    load = os.getloadavg()
    print(f'machine: {os.cpu_count()} cores, load average {load[0]:.2f} {load[1]:.2f} '
          f'{load[2]:.2f}; ROS_DOMAIN_ID {domain}')
    res = {'load_average': load}
    print('\nexecutors (item 21): round trip through an echo node in another process')
    for kind in ('single_threaded', 'events', 'waitset'):
        res[f'executor_{kind}'] = e = bench_executor(domain, kind, min(args.seconds, 4.0))
        print(f'  {kind:16s} {e["round_trips_per_s"]:7.0f} round trips/s, latency p50 '
              f'{e["latency_p50_ms"]:.3f} ms, p99 {e["latency_p99_ms"]:.3f} ms')
    for prio in (0, 50):
        res[f'free_priority_{prio}'] = f = bench_free(domain, args.seconds, prio)
        ok_rate = f['achieved_rate_hz'] >= TARGET_RATE * 1000.0
        ok_jit = f['jitter_p99_ms'] <= TARGET_JITTER_MS
        print(f'\nfree-running sim plant, 1 kHz, PID controller in another process, 0.5 Hz '
              f'sine; plant loop scheduling: {f["scheduling"]}')
        print(f'  achieved rate       {f["achieved_rate_hz"]:8.1f} Hz   (target >= '
              f'{TARGET_RATE * 1000:.0f}: {"met" if ok_rate else "NOT met"})')
        print(f'  period jitter       p50 {f["jitter_p50_ms"]:.3f} ms, p99 '
              f'{f["jitter_p99_ms"]:.3f} ms   (target p99 <= {TARGET_JITTER_MS:g} ms: '
              f'{"met" if ok_jit else "NOT met"})')
        print(f'  overruns            {f["overruns"]:.0f} (periods late by more than one '
              'period)')
        print(f'  closed-loop latency plant publish -> command received: p50 '
              f'{f["latency_p50_ms"]:.3f} ms, p99 {f["latency_p99_ms"]:.3f} ms')
        print(f'  answered samples    {100 * f["answered_fraction"]:.1f} %;  a third process '
              f'receives {f["listener_rate_hz"]:.0f} joint_states/s')
        print(f'  watchdog            {f["watchdog_reaction_s"]:.2f} s from kill -9 of the '
              'controller to the fault on /diagnostics (watchdog 0.1 s + diagnostics period)')
    for n in (2, 1):
        res[f'lockstep_{n}'] = r = bench_lockstep(domain, args.seconds, n)
        ok = r['speed_x_real_time'] >= TARGET_LOCKSTEP
        print(f'\nlockstep, plant and PID controller in {n} process{"es" if n == 2 else ""}:')
        print(f'  speed               {r["speed_x_real_time"]:.2f} x real time '
              f'({r["sim_s"]:.1f} sim s in {r["wall_s"]:.1f} wall s; target >= '
              f'{TARGET_LOCKSTEP:g}x: {"met" if ok else "NOT met"}); resends '
              f'{r["resends"]:.0f}')
    if args.json:
        Path(args.json).write_text(json.dumps(res, indent=2, default=str))
    return 0


if __name__ == '__main__':
    sys.exit(main())
