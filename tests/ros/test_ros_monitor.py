"""The monitor over real DDS, in a process of its own beside the plant and controller.

In the first tier: it comes up, reports, publishes no command and ends on Ctrl-C. The
studies (minutes each): a healthy lockstep run raises no WARN (and the monitor, frozen, does
not hold the loop up, nor publishes a command); a seal leak switched on in the running sim
plant raises WARN on the pressures and its tracked estimate rises with an alert; a run
recorded with the monitor's topics still reads in compare and fleet; a replay of the bundled
hidden-effect bag raises WARN."""
import json
import math
import signal
import time

import numpy as np
import pytest
import yaml
from rostest_helpers import PLANT_BUSY, UP_PATIENT, level
from std_msgs.msg import Float64MultiArray

from pneumatic_servo.control.reference import TrajectoryPoint
from pneumatic_servo.ros import common

MONITOR = 'pneumatic_servo_monitor'
CHANNEL_NAMES = tuple(f'{MONITOR}: monitor {ch}' for ch in ('angle', 'p_a', 'p_b'))
SEAL = 'piston_seal_leakage.seal_leak_area_m2'
WARN = 1
#: the monitor judges every window, late if it must, where the data are bounded (a lockstep
#: loop, a 10 s replay): these tests are about what it says of the data, and a loaded CI
#: machine left it a fraction of the replay at the default ``max_backlog_s`` (2 s: beyond
#: it, data are skipped and the skipping reported). Not beside a free-running 1 kHz plant,
#: which it cannot keep up with there: it would fall ever further behind
ALL_DATA = ('--set', 'max_backlog_s=600')


def moves(duration_s: float, seed: int = 0) -> list:
    """A pick-and-place duty: a move to a random angle every second (absolute sim times)."""
    rng = np.random.default_rng(seed)
    return [TrajectoryPoint(0.5 + k, float(rng.uniform(0.6, 2.6)), 0.0, 0.0)
            for k in range(int(duration_s))]


def statuses(probe, name: str) -> list:
    """(receive time, level, values, message) of every status called ``name``."""
    return [(t, level(st), probe.diag_values(st), st.message)
            for t, st in probe.diagnostics if st.name == name]


def sim_time(probe) -> float:
    return probe.joint[-1][0] - probe.joint[0][0] if probe.joint else 0.0


def verdicts(probe) -> list:
    """Every channel and effect status of the monitor: (name, level, values, message)."""
    return [(st.name, level(st), probe.diag_values(st), st.message)
            for _, st in probe.diagnostics
            if st.name.startswith(f'{MONITOR}: monitor ') and st.hardware_id == 'monitor']


def assert_publishes_nothing_that_reaches_the_loop(probe) -> None:
    """Safety: the monitor has no publisher on the command or the measurement topic."""
    for topic in ('/valve/command', '/joint_states'):
        pubs = probe.node.get_publishers_info_by_topic(topic)
        assert all(p.node_name != MONITOR for p in pubs), (topic, [p.node_name for p in pubs])


def start_lockstep(procs, probe, duration_s: float, plant_config=None, processes: int = 1,
                   subscribers: int = 3):
    """Plant and controller (``up``, lockstep) with a trajectory of moves, once the monitor
    listens: the plant waits for the controller, the monitor and the probe (and whoever
    else is counted in ``subscribers``)."""
    args = ['up', '--clock', 'lockstep', '--processes', processes, *UP_PATIENT,
            '--plant-set', 'initial_angle_rad=1.0',
            '--plant-set', f'wait_subscribers={subscribers}']
    if plant_config is not None:
        args += ['--config', plant_config]
    up = procs.start(*args, name='up')
    probe.send(probe.trajectory_pub, common.joint_trajectory(moves(duration_s),
                                                             'actuator_joint'),
               wait_subscribers=60.0)
    return up


def test_the_monitor_comes_up_reports_publishes_no_command_and_ends_on_ctrl_c(procs, probe):
    mon = procs.start('monitor', '--baseline', '3', name='monitor')
    probe.spin_until(lambda: statuses(probe, f'{MONITOR}: monitor'), 120.0,
                     f'the monitor\'s status ({procs.log(mon)[-300:]})')
    # the graph is discovered apart from the data (later, on a loaded machine): until the
    # monitor's node is in it, "no publisher of the monitor's" would hold of nothing
    probe.spin_until(lambda: MONITOR in probe.node.get_node_names(), 60.0,
                     'the monitor in the ROS graph')
    assert_publishes_nothing_that_reaches_the_loop(probe)
    _, lv, values, message = statuses(probe, f'{MONITOR}: monitor')[-1]
    assert lv == 0 and message.startswith('active'), message
    assert int(values['windows_judged']) == 0  # nothing to judge yet: no plant
    assert procs.stop(mon, signal.SIGINT, 30.0) == 0, procs.log(mon)


@pytest.mark.study
def test_a_healthy_lockstep_run_raises_no_warn_and_the_monitor_never_holds_the_loop(
        procs, probe, tmp_path):
    # 100 s of sim time: a 20 s baseline, then 80 s judged (400 windows). A lockstep loop
    # ran at 4 x real time on a quiet machine and at 0.3 x on a loaded CI machine, where
    # 300 s took a quarter of an hour: the guards below are for a hang, not a speed
    end_s = 100.0
    # nice 0: a lockstep loop runs as fast as two cores let it, and a monitor at its default
    # nice 10 would see a fraction of it (decimating, and saying so); here it must see most
    mon = procs.start('monitor', '--floor', tmp_path / 'floor.yaml', '--set', 'nice=0',
                      name='monitor')
    probe.spin_until(lambda: statuses(probe, f'{MONITOR}: monitor'), 60.0, 'the monitor')
    up = start_lockstep(procs, probe, end_s)
    probe.spin_until(lambda: sim_time(probe) > 30.0, 300.0,
                     f'30 s of sim time ({procs.log(up)[-300:]})')
    assert probe.node.get_publishers_info_by_topic('/valve/command')  # the controller's
    assert_publishes_nothing_that_reaches_the_loop(probe)
    # frozen, the monitor holds nothing up: the lockstep loop goes on without it
    mon.send_signal(signal.SIGSTOP)
    try:
        frozen_at = sim_time(probe)
        probe.spin_until(lambda: sim_time(probe) > frozen_at + 10.0, 300.0,
                         'the loop to go on while the monitor is frozen')
    finally:
        mon.send_signal(signal.SIGCONT)
    probe.spin_until(lambda: sim_time(probe) >= end_s, 900.0, f'{end_s:g} s of sim time')
    probe.spin(3.0)  # the monitor's last reports
    assert up.poll() is None and mon.poll() is None
    seen = verdicts(probe)
    warned = [(n, m) for n, lv, _, m in seen if lv >= WARN]
    assert not warned, warned[:3]
    judged = max(int(v['windows']) for n, _, v, _ in seen if n in CHANNEL_NAMES)
    node = statuses(probe, f'{MONITOR}: monitor')[-1][2]
    data_end = max(float(v['data_time_s']) for n, _, v, _ in seen if n in CHANNEL_NAMES)
    print(f'judged {node["windows_judged"]} windows ({judged} in the last report), skipped '
          f'{node["windows_skipped"]}, incomplete {node["windows_incomplete"]}, samples '
          f'missing {node["samples_lost"]}; data up to {data_end - probe.joint[0][0]:.0f} s')
    assert int(node['windows_judged']) >= 100 and judged >= 10, (
        node, statuses(probe, f'{MONITOR}: monitor')[-1][3])
    # judged up to the end of the run (if not: what the monitor said, and its log)
    assert data_end - probe.joint[0][0] > end_s - 30.0, (
        statuses(probe, f'{MONITOR}: monitor')[-1][3], procs.log(mon)[-2000:])
    assert (tmp_path / 'floor.yaml').exists()  # the baseline's floor, saved


@pytest.mark.study
def test_a_seal_leak_switched_on_warns_on_the_pressures_and_its_estimate_rises(
        procs, probe, tmp_path):
    leak_at_s = 12.0
    cfg = tmp_path / 'plant.yaml'
    cfg.write_text('effects:\n  piston_seal_leakage: {seal_leak_area_m2: 0.0}\n')
    # nice 0, as in the healthy run: at its default nice 10 a lockstep loop this fast leaves
    # the monitor a fraction of the windows, and detection in data time waits for those
    procs.start('monitor', '--baseline', '5', '--track', 'piston_seal_leakage',
                '--set', 'fit_window_s=3', '--set', 'fit_period_s=2', '--set', 'nice=0',
                *ALL_DATA, name='monitor')
    probe.spin_until(lambda: statuses(probe, f'{MONITOR}: monitor {SEAL}'), 90.0,
                     'the monitor with its tracked effect')
    up = start_lockstep(procs, probe, 60.0, cfg, processes=2)
    probe.spin_until(lambda: sim_time(probe) >= leak_at_s, 600.0,
                     f'{leak_at_s:g} s of sim time ({procs.log(up)[-300:]})')
    result = probe.set_parameters('pneumatic_servo_plant', sim_values=f'{SEAL}=3e-8')
    assert result[0].successful, result[0].reason
    switched = probe.joint[-1][0]  # sim time when the leak was on, at the latest

    def warned(ch):
        return [(t, v) for t, lv, v, _ in statuses(probe, f'{MONITOR}: monitor {ch}')
                if lv >= WARN]
    probe.spin_until(lambda: warned('p_a') and warned('p_b'), 600.0, 'WARN on the pressures')
    node = {t: v for t, _, v, _ in statuses(probe, f'{MONITOR}: monitor')}
    for ch in ('p_a', 'p_b'):
        at, first = warned(ch)[0]
        since = float(first['since_s'])
        print(f'{ch}: WARN from data time {since - switched:+.2f} s after the leak; '
              f'{node[at]["windows_judged"]} windows judged, {node[at]["windows_skipped"]} '
              f'skipped, {node[at]["windows_incomplete"]} incomplete')
        # the stated time (docs/ros.md): within 10 s of data; measured 1.3-5.7 s
        assert switched - 1.0 < since < switched + 10.0, (since - switched, node[at])
    before = [(n, m) for n, lv, v, m in verdicts(probe)
              if n in CHANNEL_NAMES and lv >= WARN
              and float(v['since_s']) < switched - 1.0]
    assert not before, before  # nothing departed while the plant was its model
    probe.spin_until(lambda: any(lv >= WARN for _, lv, _, _ in
                                 statuses(probe, f'{MONITOR}: monitor {SEAL}')), 600.0,
                     'the alert on the seal leak')
    alert = [(v, m) for _, lv, v, m in statuses(probe, f'{MONITOR}: monitor {SEAL}')
             if lv >= WARN][0]
    print('alert:', alert[1])
    assert float(alert[0]['value']) > 2e-8 and 'rose' in alert[1]
    first = [v for _, _, v, _ in statuses(probe, f'{MONITOR}: monitor {SEAL}')
             if int(v['estimates']) == 1]
    assert first and abs(float(first[0]['value'])) < 3e-9  # the healthy reference: about 0


@pytest.mark.study
def test_a_run_recorded_with_the_monitor_reads_in_compare_and_fleet(procs, probe, tmp_path):
    """A free-running sim plant and its controller with the monitor beside them, recorded
    with the monitor's topics (wall-clock record times, as a rig is recorded): compare and
    fleet read the bag as the rig's record, the monitor's topics ignored. At 250 Hz, and on a
    machine that keeps the plant's real time: on a loaded 2-core machine the free-running
    plant stalled (the controller said 'no measurement for 0.8 s'), the monitor found most
    samples missing, no window was whole and none was judged, correctly."""
    from pneumatic_servo.analysis.compare import compare
    from pneumatic_servo.fleet.discover import Recording
    from pneumatic_servo.fleet.task import TaskOptions, check_recording
    from pneumatic_servo.io import read_experiment
    from pneumatic_servo.model import ModelConfig
    procs.start('monitor', '--baseline', '2', name='monitor')  # free-running: it decimates
    procs.start('controller', name='controller')
    plant = procs.start('plant', '--set', 'initial_angle_rad=1.0', '--set', 'rate_hz=250',
                        *PLANT_BUSY, name='plant')
    probe.spin_until(lambda: probe.joint, 60.0, f'the plant ({procs.log(plant)[-300:]})')
    t0 = probe.joint[-1][0]
    probe.send(probe.trajectory_pub, common.joint_trajectory(
        [TrajectoryPoint(t0 + p.t_s, p.position, 0.0, 0.0) for p in moves(30.0)],
        'actuator_joint'))
    probe.spin_until(lambda: any(int(v['windows']) > 0 for n, _, v, _ in verdicts(probe)
                                 if n in CHANNEL_NAMES), 600.0, 'the first verdicts')
    bag = tmp_path / 'recorded'
    # recorded until the monitor's worker has published residuals into it (every few
    # seconds, later on a loaded machine: a 4 s record once held none), then stopped as a
    # user stops a recording: with Ctrl-C
    residuals = []
    probe.node.create_subscription(Float64MultiArray, '/monitor/residuals',
                                   lambda m: residuals.append(time.monotonic()), 10)
    rec = procs.start('record', bag, '--duration', '120', '--monitor', name='record')
    probe.spin_until(lambda: probe.node.count_subscribers('/monitor/residuals') >= 2, 60.0,
                     'the recorder on /monitor/residuals')
    listening = time.monotonic()
    probe.spin_until(lambda: any(t > listening + 3.0 for t in residuals), 90.0,
                     'residuals published while recording')
    assert procs.stop(rec, signal.SIGINT, 30.0) == 0, procs.log(rec)
    counts = {t['topic_metadata']['name']: t['message_count'] for t in yaml.safe_load(
        (bag / 'metadata.yaml').read_text())['rosbag2_bagfile_information'][
        'topics_with_message_count']}
    for topic in ('/model/joint_states', '/model/chamber_a/pressure', '/monitor/residuals',
                  '/diagnostics', '/joint_states', '/valve/command'):
        assert counts.get(topic, 0) > 0, (topic, counts)
    # a recorder on a loaded machine can miss a few tens of ms of commands: interpolated
    # here (the pure test tests/test_monitor.py reads a bag with these topics, gap-free,
    # in compare and fleet exactly as the bag without them)
    exp = read_experiment(bag, max_gap_s=0.5)
    assert set(exp.signals) >= {'angle_rad', 'p_a_pa', 'p_b_pa', 'command_v'}
    result = compare(exp, ModelConfig.paper(), mode='k_step')
    assert all(math.isfinite(c['rmse']) for c in result['channels'].values())
    row = check_recording(Recording(str(bag), 'sim'), ModelConfig.paper().to_dict(),
                          TaskOptions(mode='k_step'), 'k')
    assert row.status == 'ok' or 'gap' in row.error, row.error  # read, or refused for a gap
    json.dumps(row.to_json())


@pytest.mark.study
def test_a_replay_of_the_hidden_effect_bag_warns(procs, probe):
    """The bundled demo (a load torque and two leaks the paper's model does not have),
    replayed with its recorded commands: the floor measured on its first 3 s, then WARN.
    At a quarter of its speed: at 1 kHz on a loaded 2-core machine the monitor found 3,415
    of the first 8,872 samples missing (the replay stalls and catches up in bursts), and
    its baseline never filled."""
    from pathlib import Path
    bag = Path(__file__).resolve().parents[2] / 'bags' / 'hidden_effect_demo'
    procs.start('monitor', '--baseline', '3', *ALL_DATA, name='monitor')
    probe.spin_until(lambda: statuses(probe, f'{MONITOR}: monitor'), 60.0, 'the monitor')
    plant = procs.start('plant', '--backend', 'replay', '--bag', bag, '--set',
                        'replay_command=true', '--set', 'wait_subscribers=2', '--set',
                        'replay_rate=0.25', *PLANT_BUSY, name='plant')
    probe.spin_until(lambda: any(lv >= WARN for n, lv, _, _ in verdicts(probe)
                                 if n in CHANNEL_NAMES), 600.0,
                     f'WARN on the replay ({procs.log(plant)[-300:]})')
    departed = [m for n, lv, _, m in verdicts(probe) if lv >= WARN]
    print(departed[:3])
    assert all('x the floor' in m for m in departed)
    # the bag (10 s) over, the monitor says its verdicts are of the data before, not live
    probe.spin_until(lambda: 'no measurement for' in statuses(probe, f'{MONITOR}: monitor')[-1][3],
                     600.0, 'the monitor to say it hears nothing')
    assert statuses(probe, f'{MONITOR}: monitor')[-1][1] == WARN
