"""The output gate in the running plant: NaN, inf, out-of-range and stale commands, a killed
controller, lifecycle deactivation, SIGTERM, and bad parameters (start-up and run time).
Commands come over DDS from the test process; the valve voltage is read back from
/diagnostics (``output_v``)."""
import math
import signal
import subprocess
import sys
import time

import pytest
from lifecycle_msgs.msg import Transition
from rostest_helpers import CLI, PLANT_BUSY, REACTION_S, WATCHDOG_S, level, ros_env
from std_msgs.msg import Float64

PLANT = 'pneumatic_servo_plant'
CONTROLLER = 'pneumatic_servo_controller'


def out_v(probe, st) -> float:
    return float(probe.diag_values(st)['output_v'])


def command_for(probe, value: float, seconds: float) -> None:
    """Publish ``value`` at 100 Hz for ``seconds`` (fresh commands: no watchdog)."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        probe.command_pub.publish(Float64(data=value))
        probe.spin(0.01)


def recover(probe) -> None:
    """Operator acknowledgement: deactivate (valve held safe), then activate (faults clear)."""
    assert probe.change_state(PLANT, Transition.TRANSITION_DEACTIVATE)
    assert probe.change_state(PLANT, Transition.TRANSITION_ACTIVATE)


def test_bad_commands_stale_commands_lifecycle_and_sigterm(procs, probe):
    plant = procs.start('plant', '--set', 'diagnostics_period_s=0.05', *PLANT_BUSY,
                        name='plant')
    st = probe.wait_diag('plant', lambda s, v: v.get('state') == 'active', 60.0,
                         what='plant active')
    assert out_v(probe, st) == 5.0 and 'waiting for the first command' in st.message
    probe.spin_until(lambda: probe.command_pub.get_subscription_count() > 0, 10.0, 'plant sub')

    # in range: passes unchanged
    t = time.monotonic()
    command_for(probe, 6.5, 0.3)
    st = probe.wait_diag('plant', lambda s, v: float(v['output_v']) == 6.5, 5.0, t)
    assert level(st) == 0

    # out of range: clamped to 0-10 V, reported as a warning, not a fault
    t = time.monotonic()
    command_for(probe, 12.0, 0.3)
    st = probe.wait_diag('plant', lambda s, v: float(v['output_v']) == 10.0, 5.0, t)
    assert level(st) == 1 and 'clamped' in st.message
    t = time.monotonic()
    command_for(probe, -3.0, 0.3)
    last_command = time.monotonic()
    st = probe.wait_diag('plant', lambda s, v: float(v['output_v']) == 0.0, 5.0, t)
    assert level(st) == 1

    # stale: the watchdog trips, latches, and the valve goes to 5 V; not before its period
    # after the last command (timed from it: the wait above took 0.9 s on a loaded machine)
    t = time.monotonic()
    st = probe.wait_diag('plant', lambda s, v: level(s) == 2, REACTION_S, t, 'watchdog fault')
    assert 'watchdog' in st.message and out_v(probe, st) == 5.0
    assert time.monotonic() - last_command > WATCHDOG_S - 0.5
    # latched: fresh commands do not bring the valve back
    t = time.monotonic()
    command_for(probe, 7.0, 0.3)
    st = probe.wait_diag('plant', lambda s, v: int(v['ignored']) > 0, 5.0, t, 'ignored')
    assert level(st) == 2 and out_v(probe, st) == 5.0

    # non-finite commands: 5 V and a latched fault, each after an operator reset
    for bad in (math.nan, math.inf, -math.inf):
        recover(probe)
        t = time.monotonic()
        command_for(probe, 6.0, 0.2)
        probe.wait_diag('plant', lambda s, v: float(v['output_v']) == 6.0, 5.0, t)
        t = time.monotonic()
        probe.command_pub.publish(Float64(data=bad))
        st = probe.wait_diag('plant', lambda s, v: level(s) == 2, 5.0, t, f'{bad} fault')
        assert 'non-finite' in st.message and out_v(probe, st) == 5.0
        assert int(probe.diag_values(st)['non_finite']) >= 1

    # deactivate: the safe state, without a fault. Fresh commands flow until the request is
    # answered: finding the lifecycle service can take longer than the watchdog, which
    # would otherwise trip first (seen once in CI with 0.1 s)
    recover(probe)
    command_for(probe, 6.0, 0.2)
    t = time.monotonic()
    keep_fresh = probe.node.create_timer(
        0.01, lambda: probe.command_pub.publish(Float64(data=6.0)))
    try:
        assert probe.change_state(PLANT, Transition.TRANSITION_DEACTIVATE)
    finally:
        probe.node.destroy_timer(keep_fresh)
    st = probe.wait_diag('plant', lambda s, v: v['state'] == 'inactive', 5.0, t)
    assert out_v(probe, st) == 5.0 and level(st) == 0 and 'held' in st.message
    assert probe.change_state(PLANT, Transition.TRANSITION_ACTIVATE)

    # bad parameters at run time: rejected with a reason, good ones taken
    res = probe.set_parameters(PLANT, watchdog_s=-1.0)
    assert not res[0].successful and res[0].reason
    res = probe.set_parameters(PLANT, backend='rig')
    assert not res[0].successful and 'read-only' in res[0].reason
    res = probe.set_parameters(PLANT, watchdog_s=0.05)
    assert not res[0].successful and 'safety' in res[0].reason  # not while active
    res = probe.set_parameters(PLANT, replay_rate=2.0)
    assert res[0].successful

    # SIGTERM: the valve goes to 5 V and the last diagnostics say so
    command_for(probe, 6.0, 0.2)
    t = time.monotonic()
    plant.send_signal(signal.SIGTERM)
    st = probe.wait_diag('plant', lambda s, v: 'shut down' in s.message, 10.0, t, 'shutdown')
    assert 'SIGTERM' in st.message and out_v(probe, st) == 5.0
    assert plant.wait(10) == 0


def test_killed_controller_trips_the_watchdog(procs, probe):
    plant = procs.start('plant', *PLANT_BUSY, name='plant')
    ctrl = procs.start('controller', name='controller')
    st = probe.wait_diag('plant', lambda s, v: s.message == 'commanding', 60.0,
                         what='closed loop running')
    assert level(st) == 0
    # run-time parameter checks on the controller while it runs
    res = probe.set_parameters(CONTROLLER, kp=-1.0)
    assert not res[0].successful
    res = probe.set_parameters(CONTROLLER, output_min_v=9.0, output_max_v=4.0)
    assert not res[0].successful and 'output_min_v' in res[0].reason
    res = probe.set_parameters(CONTROLLER, controller='smc')
    assert not res[0].successful and 'restart' in res[0].reason
    res = probe.set_parameters(CONTROLLER, kp=5.0)
    assert res[0].successful
    # kill -9: no goodbye from the controller; the plant's watchdog must catch it
    t = time.monotonic()
    ctrl.send_signal(signal.SIGKILL)
    ctrl.wait(10)
    st = probe.wait_diag('plant', lambda s, v: level(s) == 2, REACTION_S, t, 'watchdog fault')
    assert 'watchdog' in st.message and out_v(probe, st) == 5.0
    assert plant.poll() is None  # (the reaction time is measured in benchmarks/bench_ros.py)


def run_cli(*argv, domain=99):
    return subprocess.run([sys.executable, '-c', CLI, *argv], env=ros_env(domain),
                          capture_output=True, text=True, timeout=60)


@pytest.mark.parametrize('argv, words', [
    (('plant', '--set', 'watchdog_s=-1'), 'watchdog_s'),
    (('plant', '--set', 'watchdog=0.1'), 'watchdog_s'),
    (('plant', '--ros-args', '-p', 'rate_hz:=0.0'), 'rate_hz'),
    (('plant', '--backend', 'replay'), 'bag'),
    (('plant', '--clock', 'lockstep', '--backend', 'rig'), 'lockstep'),
    (('plant', '--backend', 'rig', '--daq', 'nidaqmx'), 'nidaqmx'),
    (('controller', '--set', 'output_min_v=6', '--set', 'output_max_v=4'), 'output_min_v'),
    (('controller', '--set', 'kp=abc'), 'kp'),
])
def test_bad_parameters_rejected_at_start_up(argv, words):
    proc = run_cli(*argv)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    last = proc.stderr.strip().splitlines()[-1]
    assert last.startswith(f'pneumatic-servo {argv[0]}: error:') and words in last
    assert 'Traceback' not in proc.stderr
