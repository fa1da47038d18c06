"""Every bad-bag case fails with a clear one-line reason, in both storage formats.

The bags are real rosbag2 directories written with rosbags; nothing is mocked.
"""
import shutil
from pathlib import Path

import numpy as np
import pytest
import yaml

from pneumatic_servo.errors import ExperimentError
from pneumatic_servo.io import read_experiment, read_series
from pneumatic_servo.io.bag import typestore, write_raw_bag

STORAGES = ('sqlite3', 'mcap')
T0 = 1_700_000_000 * 10**9
MS = 10**6


def _types():
    T = typestore().types
    return (T['builtin_interfaces/msg/Time'], T['std_msgs/msg/Header'],
            T['std_msgs/msg/Float64'], T['sensor_msgs/msg/FluidPressure'],
            T['sensor_msgs/msg/JointState'])


def _header(ns):
    Time, Header, *_ = _types()
    return Header(stamp=Time(sec=int(ns // 10**9), nanosec=int(ns % 10**9)), frame_id='')


def servo_messages(n=300, *, skip=(), stamp=None, value=None, rename=None, joint='actuator_joint',
                   pressure_type=None):
    """Messages of a clean 1 kHz servo record; the keyword arguments spoil it."""
    _, _, F64, FP, JS = _types()
    stamp = stamp or (lambda topic, k: T0 + k * MS)
    value = value or (lambda topic, k, v: v)
    rename = rename or {}
    out = []
    for k in range(n):
        t = k * 1e-3
        items = [('valve/command', 'std_msgs/msg/Float64', 5.0 + 0.2 * np.sin(t * 6)),
                 ('joint_states', 'sensor_msgs/msg/JointState', 1.0 + 0.1 * t),
                 ('chamber_a/pressure', 'sensor_msgs/msg/FluidPressure', 4e5 + 1e3 * t),
                 ('chamber_b/pressure', 'sensor_msgs/msg/FluidPressure', 3e5),
                 ('supply/pressure', 'sensor_msgs/msg/FluidPressure', 701325.0)]
        for topic, msgtype, v in items:
            if topic in skip:
                continue
            v = value(topic, k, v)
            ns = stamp(topic, k)
            if msgtype.endswith('Float64') or (topic == 'chamber_a/pressure' and pressure_type):
                msg, msgtype = F64(data=float(v)), 'std_msgs/msg/Float64'
            elif msgtype.endswith('JointState'):
                msg = JS(header=_header(ns), name=[joint], position=np.array([v]),
                         velocity=np.array([0.1]), effort=np.zeros(0))
            else:
                msg = FP(header=_header(ns), fluid_pressure=float(v), variance=0.0)
            out.append((rename.get(topic, topic), msgtype, T0 + k * MS + 1000, msg))
    return out


def _bag(tmp_path, storage, name='bag', **kw):
    finish = kw.pop('finish', True)
    custom = kw.pop('custom', None)
    return write_raw_bag(tmp_path / f'{name}_{storage}', servo_messages(**kw), storage, custom,
                         finish=finish)


def expect(path, match, **options):
    with pytest.raises(ExperimentError, match=match) as info:
        read_experiment(path, **options)
    text = str(info.value)
    assert '\n' not in text, 'an error is one line'
    assert str(Path(path)) in text or 'rate_hz' in text, 'an error names the bag'
    return text


@pytest.mark.parametrize('storage', STORAGES)
def test_clean_bag_reads(tmp_path, storage):
    exp = read_experiment(_bag(tmp_path, storage))
    assert exp.circuit == 'servo' and len(exp.t) == 300
    assert np.allclose(exp['p_a_pa'], 4e5 + 1e3 * exp.t)


@pytest.mark.parametrize('storage', STORAGES)
def test_missing_command_topic(tmp_path, storage):
    text = expect(_bag(tmp_path, storage, skip={'valve/command'}), 'no valve/command topic')
    assert 'record valve/command' in text


@pytest.mark.parametrize('storage', STORAGES)
def test_missing_angle_topic(tmp_path, storage):
    expect(_bag(tmp_path, storage, skip={'joint_states'}), 'no joint_states topic .*servo')


@pytest.mark.parametrize('storage', STORAGES)
def test_misspelt_topic(tmp_path, storage):
    path = _bag(tmp_path, storage, rename={'chamber_a/pressure': 'chamber_a/presure'})
    text = expect(path, "unknown topic 'chamber_a/presure': did you mean 'chamber_a/pressure'")
    assert 'topic_map=' in text
    # the fix the message names works
    exp = read_experiment(path, topic_map={'chamber_a/presure': 'chamber_a/pressure'})
    assert 'p_a_pa' in exp


@pytest.mark.parametrize('storage', STORAGES)
def test_unknown_topic_strict(tmp_path, storage):
    path = _bag(tmp_path, storage, rename={'supply/pressure': 'tank/level'})
    expect(path, "unknown topic 'tank/level' \\(strict mode", strict=True)
    assert 'tank/level' in read_experiment(path).metadata['ignored_topics']


@pytest.mark.parametrize('storage', STORAGES)
def test_wrong_type(tmp_path, storage):
    expect(_bag(tmp_path, storage, pressure_type=True),
           'chamber_a/pressure has type std_msgs/msg/Float64; expected '
           'sensor_msgs/msg/FluidPressure')


@pytest.mark.parametrize('storage', STORAGES)
def test_nan(tmp_path, storage):
    path = _bag(tmp_path, storage,
                value=lambda topic, k, v: float('nan') if topic == 'chamber_b/pressure'
                and k in (120, 121) else v)
    text = expect(path, r'chamber_b/pressure \(p_b_pa\) is nan at t = 0.1200 s \(message 121\)')
    assert '2 sample(s)' in text


@pytest.mark.parametrize('storage', STORAGES)
def test_stamps_backwards(tmp_path, storage):
    path = _bag(tmp_path, storage, stamp=lambda topic, k: T0 + (k - 5 if (
        topic == 'chamber_a/pressure' and k == 150) else k) * MS)
    text = expect(path, 'chamber_a/pressure header stamps go backwards at t = 0.1450 s')
    assert "time_source='record'" in text


@pytest.mark.parametrize('storage', STORAGES)
def test_duplicated_stamps(tmp_path, storage):
    path = _bag(tmp_path, storage, stamp=lambda topic, k: T0 + (k - 1 if (
        topic == 'joint_states' and k in (50, 90)) else k) * MS)
    expect(path, 'joint_states has 2 duplicated header stamp')


@pytest.mark.parametrize('storage', STORAGES)
def test_repeated_record_stamps_of_a_command(tmp_path, storage):
    """A recorder on sim time stamps two commands that arrive within one clock tick alike (a
    lockstep run). Resampled onto a grid they are ambiguous and refused, naming the fix; read
    as they are (``read_series``: the replay, the demo's figures) they are kept in order."""
    late = {T0 + k * MS + 1000 for k in (50, 90)}
    msgs = [(topic, ty, rec - MS if topic == 'valve/command' and rec in late else rec, msg)
            for topic, ty, rec, msg in servo_messages()]
    path = write_raw_bag(tmp_path / f'ties_{storage}', msgs, storage)
    expect(path, 'valve/command has 2 duplicated record stamp')
    series, _ = read_series(path)
    stamps, command = series['command_v']
    assert len(stamps) == 300 and (np.diff(stamps) == 0).sum() == 2
    assert command == pytest.approx([m.data for t, _, _, m in msgs if t == 'valve/command'])


@pytest.mark.parametrize('storage', STORAGES)
def test_header_never_set(tmp_path, storage):
    path = _bag(tmp_path, storage,
                stamp=lambda topic, k: 0 if topic == 'supply/pressure' else T0 + k * MS)
    expect(path, r'supply/pressure has 299 duplicated header stamp\(s\) \(header.stamp never '
           r'set\?\)')
    # time_source='record' is the fix the message names
    assert len(read_experiment(path, time_source='record').t) > 290


@pytest.mark.parametrize('storage', STORAGES)
def test_gap(tmp_path, storage):
    msgs = [m for m in servo_messages(400) if not (
        m[0] == 'chamber_a/pressure' and T0 + 200 * MS <= m[2] < T0 + 300 * MS)]
    path = write_raw_bag(tmp_path / f'gap_{storage}', msgs, storage)
    text = expect(path, r'chamber_a/pressure has a 0.101 s gap after t = 0.1990 s')
    assert 'max_gap_s=' in text
    assert len(read_experiment(path, max_gap_s=0.2).t) == 400


@pytest.mark.parametrize('storage', STORAGES)
def test_empty_topic(tmp_path, storage):
    _, _, F64, *_ = _types()
    msgs = [m for m in servo_messages(100) if m[0] != 'joint_states']
    path = tmp_path / f'empty_{storage}'
    from rosbags.rosbag2 import StoragePlugin, Writer
    store = typestore()
    w = Writer(path, version=8, storage_plugin=StoragePlugin.MCAP if storage == 'mcap'
               else StoragePlugin.SQLITE3)
    w.open()
    w.add_connection('joint_states', 'sensor_msgs/msg/JointState', typestore=store)
    conns = {}
    for topic, mt, rec, msg in msgs:
        if topic not in conns:
            conns[topic] = w.add_connection(topic, mt, typestore=store)
        w.write(conns[topic], rec, store.serialize_cdr(msg, mt))
    w.close()
    expect(path, 'joint_states has no messages')


@pytest.mark.parametrize('storage', STORAGES)
def test_unclosed_no_metadata(tmp_path, storage):
    path = _bag(tmp_path, storage, finish=False)
    assert not (path / 'metadata.yaml').exists()
    text = expect(path, 'no metadata.yaml next to .*: the recording was not closed')
    assert 'ros2 bag reindex' in text


def test_mcap_without_footer(tmp_path):
    # a closed MCAP whose footer (and summary) were cut off, metadata.yaml intact
    path = _bag(tmp_path, 'mcap')
    mcap = next(path.glob('*.mcap'))
    data = mcap.read_bytes()
    mcap.write_bytes(data[:len(data) - 37])
    expect(path, 'the MCAP file has no footer: the recording was not closed')


@pytest.mark.parametrize('storage', STORAGES)
@pytest.mark.parametrize('fraction', (0.3, 0.9))
def test_truncated_storage_file(tmp_path, storage, fraction):
    path = _bag(tmp_path, storage, n=2000)
    store = next(p for p in path.iterdir() if p.suffix in ('.db3', '.mcap'))
    data = store.read_bytes()
    store.write_bytes(data[:int(len(data) * fraction)])
    what = 'sqlite3 file is truncated or corrupt' if storage == 'sqlite3' else \
        'MCAP file has no footer'
    expect(path, what)


@pytest.mark.parametrize('storage', STORAGES)
def test_fewer_messages_than_metadata(tmp_path, storage):
    """A storage that holds fewer messages than the index lists is never read as whole."""
    path = _bag(tmp_path, storage)
    meta_path = path / 'metadata.yaml'
    meta = yaml.safe_load(meta_path.read_text())
    info = meta['rosbag2_bagfile_information']
    for entry in info['topics_with_message_count']:
        if entry['topic_metadata']['name'] == 'chamber_b/pressure':
            entry['message_count'] += 700
    info['message_count'] += 700
    meta_path.write_text(yaml.safe_dump(meta))
    text = expect(path, 'metadata lists 1000 messages on chamber_b/pressure but the storage '
                  'holds 300: the bag is truncated')
    assert 'ros2 bag reindex' in text


@pytest.mark.parametrize('storage', STORAGES)
def test_storage_file_missing(tmp_path, storage):
    path = _bag(tmp_path, storage)
    for p in list(path.iterdir()):
        if p.suffix in ('.db3', '.mcap'):
            p.unlink()
    expect(path, 'a storage file listed in metadata.yaml is missing')


def test_not_a_bag(tmp_path):
    (tmp_path / 'empty').mkdir()
    expect(tmp_path / 'empty', r'not a rosbag2 directory \(no metadata.yaml')
    expect(tmp_path / 'nothing_here', 'no such bag directory or CSV file')


@pytest.mark.parametrize('storage', STORAGES)
def test_different_clocks(tmp_path, storage):
    # sensors stamped with sim time from 0, command timed by wall-clock record time
    path = _bag(tmp_path, storage, stamp=lambda topic, k: k * MS + 10**9)
    text = expect(path, 'no time has every signal')
    assert "time_source='record'" in text


@pytest.mark.parametrize('storage', STORAGES)
def test_joint_not_found(tmp_path, storage):
    path = _bag(tmp_path, storage, joint='other_joint')
    # a single joint under another name is taken as the actuator ...
    assert 'angle_rad' in read_experiment(path)
    # ... unless a specific joint is asked for
    expect(path, "joint_states has no joint 'wrist'", joint='wrist')


@pytest.mark.parametrize('storage', STORAGES)
def test_unknown_circuit(tmp_path, storage):
    path = _bag(tmp_path, storage, custom={'pneumatic_servo.circuit': 'hydraulic'})
    expect(path, "unknown circuit 'hydraulic'")


@pytest.mark.parametrize('storage', STORAGES)
def test_several_namespaces(tmp_path, storage):
    msgs = servo_messages(100, rename={t: f'/rig1/{t}' for t in (
        'valve/command', 'joint_states', 'chamber_a/pressure', 'chamber_b/pressure',
        'supply/pressure')})
    msgs += servo_messages(100, rename={'joint_states': '/rig2/joint_states'},
                           skip={'valve/command', 'chamber_a/pressure', 'chamber_b/pressure',
                                 'supply/pressure'})
    path = write_raw_bag(tmp_path / f'ns_{storage}', msgs, storage)
    expect(path, 'joint_states is recorded twice')
    exp = read_experiment(path, namespace='/rig1')
    assert exp.metadata['namespace'] == 'rig1' and 'p_a_pa' in exp


def test_library_bag_cut_short(tmp_path):
    """A real generated bag, copied and cut: both storages of the library fail cleanly."""
    bags = Path(__file__).resolve().parents[1] / 'bags'
    for name in ('sine_2hz', 'friction_5.70V'):
        src = bags / name
        if not src.exists():
            pytest.skip('bags/ not generated')
        dst = tmp_path / name
        shutil.copytree(src, dst)
        store = next(p for p in dst.iterdir() if p.suffix in ('.db3', '.mcap'))
        store.write_bytes(store.read_bytes()[:store.stat().st_size // 2])
        with pytest.raises(ExperimentError, match='truncated or corrupt|no footer'):
            read_experiment(dst)


@pytest.mark.parametrize('storage', STORAGES)
def test_undecodable_message(tmp_path, storage):
    """A message whose bytes do not decode as its type (corrupt, or another definition)."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    store = typestore()
    path = tmp_path / f'garbage_{storage}'
    w = Writer(path, version=8, storage_plugin=StoragePlugin.MCAP if storage == 'mcap'
               else StoragePlugin.SQLITE3)
    w.open()
    conns = {}
    for i, (topic, mt, rec, msg) in enumerate(servo_messages(50)):
        if topic not in conns:
            conns[topic] = w.add_connection(topic, mt, typestore=store)
        raw = store.serialize_cdr(msg, mt)
        if topic == 'joint_states' and i > 100:
            raw = raw[:10]  # cut inside the name list
        w.write(conns[topic], rec, raw)
    w.close()
    expect(path, 'on joint_states cannot be decoded as sensor_msgs/msg/JointState')


def test_a_replay_reads_a_recording_with_a_gap_as_it_is(tmp_path):
    """A recorder that lost a quarter second of one topic (best-effort QoS on a busy
    machine) leaves a bag analysis refuses (it would interpolate across the gap), but a
    replay publishes what was recorded: ``read_series`` keeps every sample on its stamp."""
    from pneumatic_servo.io import read_series
    gap = (100 * MS, 350 * MS)
    msgs = [m for m in servo_messages(n=600)
            if not (m[0] == 'chamber_a/pressure' and gap[0] <= m[2] - T0 <= gap[1])]
    path = write_raw_bag(tmp_path / 'gap', msgs, 'sqlite3')
    with pytest.raises(ExperimentError, match='gap'):
        read_experiment(path)
    series, _ = read_series(path)
    stamps, values = series['p_a_pa']
    assert len(stamps) == 600 - 250 and np.all(np.diff(stamps) > 0)
    assert len(series['angle_rad'][0]) == 600


@pytest.mark.parametrize('storage', STORAGES)
def test_read_messages_of_any_topic_and_its_errors(tmp_path, storage):
    """read_messages (topics outside the interface, e.g. a monitor's) reads in record order
    and refuses a truncated bag with the same one-line reason as read_bag."""
    from pneumatic_servo.io.bag import read_messages
    path = _bag(tmp_path, storage, n=2000)
    got = read_messages(path, ['joint_states'])
    assert len(got) == 2000 and {t for t, _, _ in got} == {'joint_states'}
    assert [r for _, r, _ in got] == sorted(r for _, r, _ in got)
    assert got[0][2].position[0] == pytest.approx(1.0)
    store = next(p for p in path.iterdir() if p.suffix in ('.db3', '.mcap'))
    store.write_bytes(store.read_bytes()[:int(store.stat().st_size * 0.3)])
    with pytest.raises(ExperimentError, match='truncated or corrupt|has no footer') as info:
        read_messages(path, ['joint_states'])
    assert '\n' not in str(info.value) and str(path) in str(info.value)
