"""Closed loop over real DDS in lockstep sim time: plant and controller in separate processes,
a step then a sine sent as one JointTrajectory from the test process."""
import math

import numpy as np
import pytest
from rostest_helpers import PLANT_PATIENT

from pneumatic_servo.control.metrics import step_metrics, tracking_rms
from pneumatic_servo.control.reference import Reference, Trajectory
from pneumatic_servo.ros import common
from pneumatic_servo.ros.closed_loop_demo import (
    DEG,
    SINE_AT_S,
    SINE_HZ,
    STEP_AT_S,
    STEP_FROM_DEG,
    STEP_TO_DEG,
    profile_points,
)

END_S = SINE_AT_S + 2.0 / SINE_HZ  # two sine periods are enough here


@pytest.mark.parametrize('controller, limits', [
    # settling [s], overshoot [deg], steady-state [deg], sine RMS [deg]
    ('pid', (0.5, 1.0, 0.2, 0.6)),
    # a study (./run.sh study): the same loop over DDS with the other law, 2-3 min on a
    # loaded 2-core machine; tests/ros/test_control_laws.py holds the law itself
    pytest.param('smc', (0.2, 0.5, 0.2, 0.15), marks=pytest.mark.study),
])
def test_lockstep_step_and_sine(procs, probe, controller, limits):
    ctrl = procs.start('controller', '--controller', controller, '--use-sim-time',
                       name='controller')
    points = [p for p in profile_points() if p.t_s <= END_S]
    # the trajectory reaches the controller before sim time starts: a deterministic run
    probe.send(probe.trajectory_pub, common.joint_trajectory(points, 'actuator_joint'),
               wait_subscribers=30.0)
    probe.spin(0.3)
    plant = procs.start('plant', '--clock', 'lockstep', *PLANT_PATIENT, '--set',
                        f'initial_angle_rad={STEP_FROM_DEG * DEG}', '--set',
                        'wait_subscribers=2', name='plant')
    # a guard against a hang: a loaded CI machine ran lockstep at 0.05-0.3 x real time
    probe.spin_until(lambda: probe.joint and probe.joint[-1][0] >= END_S, 600.0,
                     f'sim time {END_S} s ({procs.log(plant)[-400:]})')
    assert plant.poll() is None and ctrl.poll() is None
    assert procs.stop(ctrl) == 0
    assert procs.stop(plant) == 0

    samples = {}
    for j in probe.joint:
        # a sample may come twice (lockstep resends an unanswered one): the same sample
        assert samples.setdefault(j[4], j[1]) == j[1]
    t = np.array(sorted(samples)) * 1e-9
    y = np.array([samples[k] for k in sorted(samples)])
    assert np.allclose(np.diff(t)[np.diff(t) < 0.0015], 0.001), 'a 1 ms sim-time grid'
    assert len(t) > 0.9 * END_S * 1000, 'lockstep runs at 1 kHz sim time'
    step = t < SINE_AT_S
    sm = step_metrics(t[step], y[step], STEP_AT_S, STEP_FROM_DEG * DEG, STEP_TO_DEG * DEG)
    settle, over, sse, rms = limits
    assert sm['settling_time_s'] < settle
    assert sm['overshoot_rad'] / DEG < over
    assert sm['steady_state_error_rad'] / DEG < sse
    assert abs(sm['final_error_rad']) / DEG < sse
    traj = Trajectory(points)
    ref = np.array([(traj.sample(tt) or Reference(STEP_FROM_DEG * DEG)).position for tt in t])
    tr = tracking_rms(t, y, ref, SINE_AT_S + 1.0, END_S)
    assert tr['rms_error_rad'] / DEG < rms
    assert math.isfinite(tr['max_error_rad'])
