"""Running the nodes without ``ros2 launch``: one process or two, safe on every exit path.

``main()`` style: ``rclpy.init()`` with try/finally ``rclpy.shutdown()`` (the
``with rclpy.init()`` form does not work on Jazzy). rclpy's own signal
handlers are not installed: SIGINT/SIGTERM stop the event loop instead, so
the plant can still write the safe valve voltage and publish its last
diagnostics before the context goes away.
"""
from __future__ import annotations

import math
import os
import signal
import subprocess
import sys

from ..errors import ConfigError, PneumaticServoError
from .common import sim_time
from .loop import run_nodes


def make_plant(overrides: dict, namespace: str = ''):
    from .plant_node import PlantNode
    return PlantNode(overrides=overrides, namespace=namespace)


def make_controller(overrides: dict, use_sim_time: bool = False, namespace: str = ''):
    from .controller_node import ControllerNode
    return ControllerNode(overrides=overrides, namespace=namespace,
                          parameter_overrides=sim_time(use_sim_time))


def make_monitor(overrides: dict, namespace: str = ''):
    from .monitor_node import MonitorNode
    return MonitorNode(overrides=overrides, namespace=namespace)


def _die_with_parent() -> None:
    """In the child, before exec: ask Linux to send SIGTERM when the parent dies, even by
    SIGKILL (prctl PR_SET_PDEATHSIG), so that no node outlives the process that started it."""
    import ctypes
    try:
        libc = ctypes.CDLL('libc.so.6', use_errno=True)
        libc.prctl(1, signal.SIGTERM, 0, 0, 0)  # 1 = PR_SET_PDEATHSIG
    except OSError:  # not Linux: the parent still stops the child on every catchable exit
        pass


def start_child(cmd: list) -> subprocess.Popen:
    """A child process that dies with its parent."""
    return subprocess.Popen(cmd, preexec_fn=_die_with_parent)


def controller_command(controller_overrides: dict, use_sim_time: bool, ros_args=None) -> list:
    """argv that runs the controller node alone in a new process."""
    cmd = [sys.executable, '-c',
           'import sys; from pneumatic_servo.cli import main; sys.exit(main(sys.argv[1:]))',
           'controller']
    for k, v in controller_overrides.items():
        cmd += ['--set', f'{k}={v}']
    if use_sim_time:
        cmd.append('--use-sim-time')
    if ros_args:
        cmd += ['--ros-args'] + [a for a in ros_args if a != '--ros-args']
    return cmd


def run_up(plant: dict, controller: dict, processes: int = 1, duration_s: float = math.inf,
           ros_args=None, record: str = '', storage: str = 'sqlite3') -> int:
    """Plant and controller (and optionally a recorder) without ``ros2 launch``.

    With ``processes=2`` the controller runs in a child process (its death is then
    seen by the plant's watchdog); SIGINT/SIGTERM are passed on to it.
    """
    if processes not in (1, 2):
        raise ConfigError('--processes must be 1 or 2')
    use_sim_time = plant.get('clock_mode') == 'lockstep'
    factories = [lambda: make_plant(plant)]
    if record:
        from .recorder import RecorderNode
        factories.append(lambda: RecorderNode(record, storage,
                                              parameter_overrides=sim_time(use_sim_time)))
    child = None
    if processes == 1:
        factories.append(lambda: make_controller(controller, use_sim_time))
    else:
        child = start_child(controller_command(controller, use_sim_time, ros_args))
    try:
        reason = run_nodes(factories, duration_s, ros_args)
    finally:
        if child is not None and child.poll() is None:
            child.send_signal(signal.SIGTERM)
            try:
                child.wait(timeout=5)
            except subprocess.TimeoutExpired:
                child.kill()
    return exit_code(reason)


def exit_code(reason: str) -> int:
    """0 for an orderly stop (time up, or a stop signal), 1 for a fault."""
    from .loop import STOP_SIGNALS
    return 0 if reason == 'time up' or reason in {s.name for s in STOP_SIGNALS} else 1


def guard(fn, *args, **kwargs) -> int:
    """Run ``fn``; a PneumaticServoError becomes one line and exit 2 (for console scripts)."""
    try:
        return int(fn(*args, **kwargs) or 0)
    except PneumaticServoError as exc:
        print(f'{os.path.basename(sys.argv[0])}: error: {exc}', file=sys.stderr)
        return 2
