"""The batch CDR codecs (pneumatic_servo.io.codecs) against rosbags' own (de)serialiser: the
fast path decodes every message of every bag in bags/ and tests/data/ exactly as rosbags
does; messages off the common layout fall back and still decode as rosbags does, failing
where it fails; the encoders give rosbags' bytes."""
from pathlib import Path

import numpy as np
import pytest

from pneumatic_servo.errors import ExperimentError
from pneumatic_servo.io.bag.reader import _JointPicker
from pneumatic_servo.io.codecs import CODECS, DecodeError, codec_of, typestore
from pneumatic_servo.io.topics import FLOAT64, FLUID_PRESSURE, JOINT_STATE, TEMPERATURE

ROOT = Path(__file__).resolve().parents[1]
BAGS = sorted(p.parent for p in list((ROOT / 'bags').glob('**/metadata.yaml'))
              + list((ROOT / 'tests' / 'data').glob('**/metadata.yaml')))


def same(a, b) -> bool:
    """Equal to the bit (NaN, -0.0 and all)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return a.shape == b.shape and np.array_equal(a.view(np.int64), b.view(np.int64))


def rosbags_fields(raw, msgtype, joint='actuator_joint'):
    """What the reader takes from one message, by rosbags: (stamp or None, {field: value or
    None where absent})."""
    msg = typestore().deserialize_cdr(raw, msgtype)
    codec = CODECS[msgtype]
    stamp = None
    if codec.stamped:
        stamp = int(msg.header.stamp.sec) * 10**9 + int(msg.header.stamp.nanosec)
    if msgtype != JOINT_STATE:
        return stamp, {f: float(getattr(msg, f)) for f in codec.fields}
    names = list(msg.name)
    i = names.index(joint) if joint in names else 0
    return stamp, {f: float(getattr(msg, f)[i]) if len(getattr(msg, f)) > i else None
                   for f in codec.fields}


def check_batch(raws, msgtype, joint='actuator_joint'):
    """Decode ``raws`` as one batch and message by message with rosbags: the same."""
    got = CODECS[msgtype].decode(raws, _JointPicker('test', joint))
    for k, raw in enumerate(raws):
        stamp, fields = rosbags_fields(raw, msgtype, joint)
        if stamp is not None:
            assert got.stamp_ns[k] == stamp, k
        for f, value in fields.items():
            if value is None:
                assert not got.present[f][k], (k, f)
            else:
                assert got.present.get(f, np.ones(len(raws), bool))[k], (k, f)
                assert same(got.fields[f][k], value), (k, f, got.fields[f][k], value)
    return got


@pytest.mark.skipif(not BAGS, reason='bags/ not generated')
def test_fast_path_equals_rosbags_on_every_bag():
    from rosbags.rosbag2 import Reader, ReaderError
    seen, checked = set(), 0
    for bag in BAGS:
        by_conn = {}
        try:
            with Reader(bag) as reader:
                for conn, _, raw in reader.messages():
                    if conn.msgtype in CODECS:
                        by_conn.setdefault((conn.topic, conn.msgtype), []).append(raw)
        except ReaderError:
            continue  # a bag broken on purpose (the fleet demo's unclosed recording)
        checked += 1
        for (topic, msgtype), raws in by_conn.items():
            lay, mask, _ = CODECS[msgtype].fast(raws)
            assert lay is not None and mask.all(), f'{bag}: {topic} is not the fast case'
            check_batch(raws, msgtype)
            seen.add(msgtype)
    assert checked >= len(BAGS) - 2
    assert {FLOAT64, FLUID_PRESSURE, JOINT_STATE} <= seen


def _types():
    T = typestore().types
    return T['builtin_interfaces/msg/Time'], T['std_msgs/msg/Header']


def header(ns, frame=''):
    Time, Header = _types()
    return Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id=frame)


def ser(msg, msgtype, little=True):
    return bytes(typestore().serialize_cdr(msg, msgtype, little_endian=little))


def joint_state(ns, names, pos, vel=(), eff=(), frame=''):
    JS = typestore().types[JOINT_STATE]
    return ser(JS(header=header(ns, frame), name=list(names), position=np.array(pos, float),
                  velocity=np.array(vel, float), effort=np.array(eff, float)), JOINT_STATE)


def scalar(msgtype, ns, value, frame='', little=True):
    cls = typestore().types[msgtype]
    field = CODECS[msgtype].fields[0]
    return ser(cls(header=header(ns, frame), **{field: value}, variance=0.5), msgtype, little)


T0 = 1_700_000_000 * 10**9 + 123


@pytest.mark.parametrize('msgtype', [FLUID_PRESSURE, TEMPERATURE])
def test_scalars_of_mixed_layouts(msgtype):
    """Frame ids of other lengths, non-ASCII text, big-endian CDR, odd values and stamps in
    one batch: the common layout is read at its offsets, the rest by rosbags, in order."""
    rng = np.random.default_rng(1)
    frames = ['', '', 'a', 'base_link', 'ü', '', 'abcd', '']
    raws = []
    for k in range(400):
        v = float(rng.normal() * 1e5)
        v = [v, -0.0, np.inf, np.nan, 1e-310][k % 5] if k % 7 == 0 else v
        raws.append(scalar(msgtype, T0 + k * 999_999_937, v, frames[k % len(frames)],
                           little=k % 11 != 5))
    got = check_batch(raws, msgtype)
    assert got.stamp_ns[0] == T0
    # a stamp before 1970 (negative seconds) too
    check_batch([scalar(msgtype, -3 * 10**9 + 5, 1.0)] * 3, msgtype)


def test_float64_batches():
    F64 = typestore().types[FLOAT64]
    values = [0.0, -0.0, 5.25, np.nan, -np.inf, 1e300]
    raws = [ser(F64(data=v), FLOAT64) for v in values]
    raws.append(ser(F64(data=7.5), FLOAT64, little=False))
    raws.append(raws[2] + b'\x00\x00')  # trailing padding rosbags accepts
    check_batch(raws, FLOAT64)
    assert CODECS[FLOAT64].fast(raws)[1].sum() == len(values)


@pytest.mark.parametrize('first', ['one', 'many', 'unnamed'])
def test_joint_states_of_mixed_layouts(first):
    """One joint or several, named or not, velocity and effort present or empty, other
    frame ids: the actuator joint's values are what rosbags gives, message by message."""
    layouts = {
        'one': lambda k: joint_state(T0 + k, ['actuator_joint'], [k * 0.1], [0.5], []),
        'many': lambda k: joint_state(T0 + k, ['wrist', 'actuator_joint'], [9.0, k * 0.2],
                                      [1.0, 2.0], [3.0, 4.0], frame='arm'),
        'unnamed': lambda k: joint_state(T0 + k, [], [k * 0.3], [], [0.25]),
    }
    order = [first] * 50 + ['one', 'many', 'one', 'one', 'many'] + [first] * 20
    raws = [layouts[name](k) for k, name in enumerate(order)]
    check_batch(raws, JOINT_STATE)


def test_joint_picker_runs_in_message_order():
    """The picker sees the names in message order; a joint missing from a later layout is
    refused there, after the earlier messages decoded."""
    raws = [joint_state(T0 + k, ['actuator_joint'], [0.1]) for k in range(5)]
    raws += [joint_state(T0 + 9, ['wrist', 'elbow'], [0.1, 0.2])]
    with pytest.raises(ExperimentError, match="no joint 'actuator_joint'"):
        CODECS[JOINT_STATE].decode(raws, _JointPicker('test', 'actuator_joint'))


def test_a_joint_without_position_stops_the_batch():
    raws = [joint_state(T0 + k, ['actuator_joint'], [0.1]) for k in range(3)]
    raws += [joint_state(T0 + 3, ['actuator_joint'], [])]
    raws += [joint_state(T0 + 4, ['x', 'y'], [0.1, 0.2])]  # never reached: no picker error
    got = CODECS[JOINT_STATE].decode(raws, _JointPicker('test', 'actuator_joint'))
    assert got.present['position'].tolist() == [True, True, True, False, False]


@pytest.mark.parametrize('msgtype', [FLOAT64, FLUID_PRESSURE, JOINT_STATE])
def test_bad_messages_fail_where_rosbags_fails(msgtype):
    """A cut message, a wrong string length, a missing terminator: DecodeError at its
    index, as deserialising it alone would fail; the messages before it are not refused."""
    good = {FLOAT64: ser(typestore().types[FLOAT64](data=1.0), FLOAT64),
            FLUID_PRESSURE: scalar(FLUID_PRESSURE, T0, 2e5),
            JOINT_STATE: joint_state(T0, ['actuator_joint'], [0.5], [0.1])}[msgtype]
    spoilt = [good[:len(good) - 5], good + b'\x00' * 8, b'\x01\x01' + good[2:]]
    if msgtype != FLOAT64:
        spoilt.append(good[:12] + (200).to_bytes(4, 'little') + good[16:])
        spoilt.append(good[:16] + b'\x07' + good[17:])  # frame_id's NUL overwritten
    pick = _JointPicker('t', 'actuator_joint')
    for bad in spoilt:
        with pytest.raises(Exception):
            typestore().deserialize_cdr(bad, msgtype)
        with pytest.raises(DecodeError) as info:
            CODECS[msgtype].decode([good] * 3 + [bad] + [good], pick)
        assert info.value.index == 3
        with pytest.raises(DecodeError) as info:
            CODECS[msgtype].decode([bad, good], pick)
        assert info.value.index == 0


def test_encoders_give_rosbags_bytes():
    rng = np.random.default_rng(2)
    n = 50
    stamps = T0 + np.cumsum(rng.integers(1, 3 * 10**9, n))
    values = rng.normal(size=n) * 1e5
    values[:4] = [0.0, -0.0, np.nan, np.inf]
    F64, T = typestore().types[FLOAT64], typestore().types
    assert CODECS[FLOAT64].encode(None, {'data': values}) == [
        ser(F64(data=float(v)), FLOAT64) for v in values]
    for msgtype in (FLUID_PRESSURE, TEMPERATURE):
        field = CODECS[msgtype].fields[0]
        got = CODECS[msgtype].encode(stamps, {field: values})
        assert got == [ser(T[msgtype](header=header(int(s)), **{field: float(v)},
                                      variance=0.0), msgtype) for s, v in zip(stamps, values)]
    for vel, eff in ((values, None), (None, values), (None, None), (values, -values)):
        got = CODECS[JOINT_STATE].encode(
            stamps, {'position': values, 'velocity': vel, 'effort': eff}, joint='j1')
        assert got == [joint_state(int(s), ['j1'], [values[k]],
                                   [] if vel is None else [vel[k]],
                                   [] if eff is None else [eff[k]])
                       for k, s in enumerate(stamps)]


def test_every_topic_has_its_codec():
    from pneumatic_servo.io.topics import TOPICS
    for topic in TOPICS.values():
        assert codec_of(topic).msgtype == topic.msgtype
        assert set(topic.fields) <= set(codec_of(topic).fields)


@pytest.mark.parametrize('storage, compress', [('mcap', False), ('mcap', True),
                                               ('sqlite3', False)])
def test_bulk_writing_gives_the_files_of_message_by_message(tmp_path, monkeypatch, storage,
                                                            compress):
    """The bulk path of storage.write_samples (MCAP chunks cut where rosbags cuts them, its
    chunk index and statistics; sqlite3 rows at once) against rosbags' own write per
    message: the same files, byte for byte (MCAP) or row for row (sqlite3)."""
    import sqlite3

    from pneumatic_servo.experiment import Experiment
    from pneumatic_servo.io import write_experiment_bag
    from pneumatic_servo.io.bag import storage as disk
    n = 12_000  # 60,000 messages: four chunks of 1 MiB and a part
    t = np.arange(n) * 1e-3
    rng = np.random.default_rng(3)
    exp = Experiment(t, {'command_v': 5 + rng.normal(size=n), 'angle_rad': 1 + 0 * t,
                         'velocity_rad_s': rng.normal(size=n), 'p_a_pa': 3e5 + t,
                         'p_b_pa': 3e5 - t, 't_a_k': 293 + t, 'supply_pa': 7e5 + 0 * t},
                     'servo', 'bulk')
    kinds = []
    real = disk._bulk_kind
    monkeypatch.setattr(disk, '_bulk_kind', lambda *a: kinds.append(real(*a)) or kinds[-1])
    bulk = write_experiment_bag(exp, tmp_path / 'bulk' / 'bag', storage, compress=compress)
    assert kinds == [storage]
    monkeypatch.setattr(disk, '_bulk_kind', lambda writer, columns: None)
    single = write_experiment_bag(exp, tmp_path / 'single' / 'bag', storage,
                                  compress=compress)
    assert (bulk / 'metadata.yaml').read_text() == (single / 'metadata.yaml').read_text()
    if storage == 'mcap':
        a, b = (next(p.glob('*.mcap')).read_bytes() for p in (bulk, single))
        assert a == b
    else:
        def rows(path):
            with sqlite3.connect(next(path.glob('*.db3'))) as db:
                return db.execute('SELECT id, topic_id, timestamp, data FROM messages '
                                  'ORDER BY id').fetchall()
        assert rows(bulk) == rows(single)


def test_definitions_are_rosbags():
    """A bag is written with the codecs' definitions and hashes, not rosbags' typestore."""
    for msgtype, codec in CODECS.items():
        assert codec.definition == typestore().generate_msgdef(msgtype, ros_version=2)[0]
        assert codec.rihs01 == typestore().hash_rihs01(msgtype)
