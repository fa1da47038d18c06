"""Reading and writing experiments: rosbag2 (sqlite3, MCAP) and static CSV, resampling."""
from pathlib import Path

import numpy as np
import pytest
import yaml

from pneumatic_servo.errors import ExperimentError
from pneumatic_servo.experiment import Experiment
from pneumatic_servo.io import (
    read_experiment,
    write_experiment,
    write_experiment_bag,
)
from pneumatic_servo.io.bag import typestore, write_raw_bag

BAGS = Path(__file__).resolve().parents[1] / 'bags'
STORAGES = ('sqlite3', 'mcap')
T0 = 1_650_000_000 * 10**9


def servo_experiment(n=1500, dt=1e-3):
    t = np.arange(n) * dt
    sig = {'command_v': 5.0 + 0.3 * np.sin(2 * np.pi * 2 * t),
           'supply_pa': np.full(n, 701325.0),
           'angle_rad': 1.5 + 0.2 * np.sin(2 * np.pi * 2 * t - 1.0),
           'velocity_rad_s': 0.4 * np.pi * np.cos(2 * np.pi * 2 * t - 1.0),
           'p_a_pa': 4e5 + 2e4 * np.sin(2 * np.pi * 2 * t),
           'p_b_pa': 4e5 - 2e4 * np.sin(2 * np.pi * 2 * t),
           't_a_k': 293.15 + np.sin(t), 't_b_k': 293.15 - np.sin(t),
           'setpoint_rad': 1.5 + 0.0 * t}
    return Experiment(t, sig, 'servo', 'roundtrip')


@pytest.mark.parametrize('storage', STORAGES)
def test_roundtrip(tmp_path, storage):
    exp = servo_experiment()
    path = write_experiment_bag(exp, tmp_path / 'b', storage,
                                {'synthetic': True, 'truth': {'h': 21.5}, 'design': 'x'},
                                compress=storage == 'mcap')
    meta = yaml.safe_load((path / 'metadata.yaml').read_text())['rosbag2_bagfile_information']
    assert meta['storage_identifier'] == storage
    assert meta['custom_data']['pneumatic_servo.synthetic'] == 'true'
    assert meta['custom_data']['pneumatic_servo.circuit'] == 'servo'
    # the recorder's convention, which is rosbag2's: version 9, absolute names, type hashes,
    # the QoS each publisher offers (commands reliable, measurements best effort)
    assert meta['version'] == 9
    topics = {t['topic_metadata']['name']: t['topic_metadata']
              for t in meta['topics_with_message_count']}
    assert topics['/joint_states']['type'] == 'sensor_msgs/msg/JointState'
    assert topics['/chamber_a/temperature']['type'] == 'sensor_msgs/msg/Temperature'
    for t in topics.values():
        assert t['type_description_hash'].startswith('RIHS01_')
    qos = {name: t['offered_qos_profiles'][0]['reliability'] for name, t in topics.items()}
    assert qos['/valve/command'] == 'reliable' and qos['/joint_states'] == 'best_effort'
    back = read_experiment(path)
    assert back.metadata['synthetic'] is True and back.metadata['truth'] == {'h': 21.5}
    assert back.metadata['storage'] == storage and back.metadata['rate_hz'] == 1000.0
    assert len(back.t) == len(exp.t) and back.t[0] == 0.0
    for key, values in exp.signals.items():
        np.testing.assert_allclose(back[key], values, rtol=0, atol=1e-9, err_msg=key)
    np.testing.assert_allclose(back['setpoint_rad'], 1.5)


def test_a_blocked_record_keeps_where_the_pistons_were_held(tmp_path):
    """The held angle of a blocked record sets its chamber volumes: written without being
    asked for, it reads back, and a reader never takes the pistons to be at 0."""
    exp = servo_experiment(n=200)
    sig = {k: v for k, v in exp.signals.items() if not k.startswith(('angle', 'velocity'))}
    blocked = Experiment(exp.t, sig, 'blocked', 'held', False, {'blocked_angle_rad': 1.6})
    back = read_experiment(write_experiment(blocked, tmp_path / 'b'))
    assert back.circuit == 'blocked' and back.metadata['blocked_angle_rad'] == 1.6


def test_write_refuses_existing_and_static(tmp_path):
    exp = servo_experiment(10)
    write_experiment_bag(exp, tmp_path / 'b')
    with pytest.raises(ExperimentError, match='exists already'):
        write_experiment_bag(exp, tmp_path / 'b')
    static = Experiment(np.arange(2.0), {'command_v': np.array([5.0, 6.0]),
                                         'p_a_pa': np.array([2e5, 3e5])}, 'closed_port',
                        static=True)
    with pytest.raises(ExperimentError, match='write_static_csv'):
        write_experiment_bag(static, tmp_path / 'c')


@pytest.mark.parametrize('storage', STORAGES)
def test_resample_different_rates_and_offsets(tmp_path, storage):
    """1 kHz encoder, 500 Hz pressures stamped 0.3 ms late, command on change + each 5 ms."""
    T = typestore().types
    Time, Header = T['builtin_interfaces/msg/Time'], T['std_msgs/msg/Header']
    F64, FP, JS = (T['std_msgs/msg/Float64'], T['sensor_msgs/msg/FluidPressure'],
                   T['sensor_msgs/msg/JointState'])

    def hdr(ns):
        return Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id='')

    def angle(t):
        return 0.5 + 0.3 * t

    def pressure(t):
        return 3e5 + 5e4 * t

    msgs = []
    for k in range(0, 1000):                       # 1 kHz angle
        ns = T0 + k * 10**6
        msgs.append(('joint_states', 'sensor_msgs/msg/JointState', ns + 50_000, JS(
            header=hdr(ns), name=['actuator_joint'], position=np.array([angle(k * 1e-3)]),
            velocity=np.zeros(0), effort=np.zeros(0))))
    for k in range(0, 500):                        # 500 Hz pressures, 0.3 ms offset
        ns = T0 + k * 2 * 10**6 + 300_000
        t = (ns - T0) * 1e-9
        for topic in ('chamber_a/pressure', 'chamber_b/pressure'):
            msgs.append((topic, 'sensor_msgs/msg/FluidPressure', ns + 10_000,
                         FP(header=hdr(ns), fluid_pressure=pressure(t), variance=0.0)))
    for k in range(0, 200):                        # command every 5 ms, a step at 0.5 s
        ns = T0 + k * 5 * 10**6
        msgs.append(('valve/command', 'std_msgs/msg/Float64', ns,
                     F64(data=5.0 if k < 100 else 6.0)))
    msgs.sort(key=lambda m: m[2])
    exp = read_experiment(write_raw_bag(tmp_path / 'rates', msgs, storage))
    assert exp.metadata['rate_hz'] == 1000.0
    # the grid starts where every signal exists (the first pressure at 0.3 ms)
    assert exp.metadata['trimmed_start_s'] == pytest.approx(0.001, abs=1e-9)
    t_abs = exp.t + exp.metadata['trimmed_start_s']
    np.testing.assert_allclose(exp['angle_rad'], angle(t_abs), atol=1e-12)
    np.testing.assert_allclose(exp['p_a_pa'], pressure(t_abs), rtol=1e-12)
    # the command is held, and switches at its own time
    assert np.all(exp['command_v'][t_abs < 0.5 - 1e-9] == 5.0)
    assert np.all(exp['command_v'][t_abs >= 0.5 - 1e-9] == 6.0)
    # a coarser grid on request
    coarse = read_experiment(tmp_path / 'rates', rate_hz=200.0)
    assert coarse.dt == pytest.approx(0.005)


@pytest.mark.parametrize('storage', STORAGES)
def test_namespace_infrastructure_and_record_time(tmp_path, storage):
    exp = servo_experiment(200)
    path = write_experiment_bag(exp, tmp_path / 'plain', storage)
    from rosbags.rosbag2 import Reader
    store = typestore()
    msgs = []
    with Reader(path) as reader:
        for conn, rec, raw in reader.messages():
            msgs.append((f'/rig/{conn.topic}', conn.msgtype, rec,
                         store.deserialize_cdr(raw, conn.msgtype)))
    msgs.append(('/rosout', 'std_msgs/msg/Float64', msgs[0][2],
                 store.types['std_msgs/msg/Float64'](data=0.0)))
    back = read_experiment(write_raw_bag(tmp_path / 'ns', msgs, storage))
    assert back.metadata['namespace'] == 'rig'
    np.testing.assert_allclose(back['p_a_pa'], exp['p_a_pa'], atol=1e-9)
    # timing every topic by record time shifts nothing here beyond the 0.2 ms latency
    rec = read_experiment(tmp_path / 'ns', time_source='record')
    assert len(rec.t) >= len(exp.t) - 1


def test_signals_subset_and_window(tmp_path):
    exp = servo_experiment(3000)
    path = write_experiment_bag(exp, tmp_path / 'b', 'mcap')
    only = read_experiment(path, signals=['command_v', 'angle_rad'])
    assert sorted(only.signals) == ['angle_rad', 'command_v']
    part = read_experiment(path, start_s=1.0, stop_s=2.0)
    assert part.duration == pytest.approx(1.0, abs=2e-3)
    np.testing.assert_allclose(part['p_a_pa'][0], exp['p_a_pa'][1000], atol=1e-6)
    with pytest.raises(ExperimentError, match='unknown signal'):
        read_experiment(path, signals=['pressure'])


# ------------------------------------------------------------------------------ CSV
def flow_table():
    n = 4
    return Experiment(np.arange(n, dtype=float), {
        'command_v': np.array([5.0, 6.0, 7.0, 8.0]), 'supply_pa': np.full(n, 701325.0),
        'p_a_pa': np.array([1.2e5, 1.5e5, 2.5e5, 4e5]),
        'm4_kg_s': np.array([1e-4, 5e-4, 1e-3, 1.5e-3]),
        'm5_kg_s': np.array([2e-5, 3e-5, 4e-5, 5e-5]), 't_s_k': np.full(n, 293.2)},
        'flow', 'flow', static=True)


def test_csv_roundtrip(tmp_path):
    path = write_experiment(flow_table(), tmp_path / 'flow.csv',
                            metadata={'synthetic': True, 'design': 'flow'})
    assert path.read_text().splitlines()[0] == \
        'circuit,voltage_v,supply_pa,p_a_pa,m4_kg_s,m5_kg_s,t_s_k'
    back = read_experiment(path)
    assert back.static and back.circuit == 'flow' and back.metadata['synthetic'] is True
    for key, values in flow_table().signals.items():
        np.testing.assert_allclose(back[key], values, rtol=1e-9)


@pytest.mark.parametrize('text, match', [
    ('circuit,voltage_v,supply_pa,p_a_pa\nclosed_port,5,701325,abc\n',
     "line 2: p_a_pa = 'abc' is not a number"),
    ('circuit,voltage_v,supply_pa,p_a_pa\nclosed_port,5,701325,\n', 'line 2: p_a_pa is empty'),
    ('circuit,voltage_v,supply_pa,p_a_pa\nclosed_port,5,701325,nan\n',
     'line 2: p_a_pa is nan'),
    ('circuit,voltage,supply_pa,p_a_pa\nclosed_port,5,701325,2e5\n',
     "unknown column 'voltage'; did you mean 'voltage_v'"),
    ('circuit,voltage_v,p_a_pa\nclosed_port,5,2e5\n', 'missing column.*supply_pa'),
    ('circuit,voltage_v,supply_pa\nclosed_port,5,701325\n', 'no measured column'),
    ('circuit,voltage_v,supply_pa,p_a_pa\nclosed_port,5,0.6,2e5\n',
     'supply_pa has 0.6, below .* pressures are absolute Pa'),
    ('circuit,voltage_v,supply_pa,p_a_pa\nclosed_port,5,701325,2e5\nflow,6,701325,3e5\n',
     'rows of several circuits'),
    ('circuit,voltage_v,supply_pa,p_a_pa\nservo,5,701325,2e5\n', "'servo' is not a static"),
    ('circuit,voltage_v,supply_pa,p_a_pa\nclosed_port,5,701325\n', 'the file may be truncated'),
    ('', 'empty file'),
])
def test_bad_csv(tmp_path, text, match):
    path = tmp_path / 'bad.csv'
    path.write_text(text)
    with pytest.raises(ExperimentError, match=match) as info:
        read_experiment(path)
    assert '\n' not in str(info.value)


# ------------------------------------------------------------------- the library
def library():
    """Every bag and table in bags/, those of the demo data sets (directories of tables)
    included."""
    if not BAGS.exists() or not (BAGS / 'README.md').exists():
        pytest.skip('bags/ not generated (pneumatic-servo generate bags/)')
    out = []
    for p in sorted(BAGS.iterdir()):
        if p.is_dir() and not (p / 'metadata.yaml').exists():
            out += sorted(p.glob('*.csv'))
        elif p.is_dir() or p.suffix == '.csv':
            out.append(p)
    return out


def test_library_reads_and_is_labelled_synthetic():
    storages = set()
    readme = (BAGS / 'README.md').read_text()
    for path in library():
        exp = read_experiment(path)
        assert exp.metadata['synthetic'] is True, path
        custom = (yaml.safe_load((path / 'metadata.yaml').read_text())[
            'rosbag2_bagfile_information']['custom_data'] if path.is_dir() else {})
        if path.is_dir():
            assert custom['pneumatic_servo.synthetic'] == 'true'
            assert exp.metadata['rate_hz'] == 1000.0
        demo = custom.get('pneumatic_servo.generator', exp.metadata.get('generator', ''))
        if demo in ('pneumatic_servo.synth.hidden', 'pneumatic_servo.synth.unlisted'):
            # the demo records, listed in the README with what they hide
            assert (path.name if path.is_dir() else path.parent.name) in readme, path
            continue
        assert exp.metadata['design'] == (path.name if path.is_dir() else path.stem)
        if path.is_dir():
            storages.add(exp.metadata['storage'])
            assert 'pneumatic-servo generate' in custom['pneumatic_servo.generator']
        else:
            assert exp.static
    assert storages == {'sqlite3', 'mcap'}
    assert 'SYNTHETIC' in readme and 'pneumatic-servo generate' in readme
    total = sum(f.stat().st_size for f in BAGS.rglob('*') if f.is_file())
    # 7 MB of single records, 2.6 MB of the fleet demo (24 bags, bags/fleet_demo) and 1.3 MB
    # of the memory walkthrough's chirp (bags/hysteresis_demo, 10 s at 1 kHz)
    assert total < 12e6, f'the library should stay small, is {total / 1e6:.1f} MB'
