"""The hand-written CDR of the hot path against rclpy's own (de)serialisation."""
import math

import pytest
from rclpy.serialization import deserialize_message, serialize_message
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import FluidPressure, JointState, Temperature
from std_msgs.msg import Float64

from pneumatic_servo.ros import cdr

FRAMES = [b'', b'a', b'ab', b'abc', b'abcd', b'base_link']
NAMES = [b'j', b'actuator_joint', b'abc', b'abcd']
OPTIONAL = [(math.nan, math.nan), (2.0, math.nan), (math.nan, 3.0), (-2.0, 3.5)]


@pytest.mark.parametrize('frame', FRAMES)
@pytest.mark.parametrize('kind, field', [(FluidPressure, 'fluid_pressure'),
                                         (Temperature, 'temperature')])
def test_scalar_messages_both_ways(frame, kind, field):
    m = deserialize_message(cdr.pack_scalar(5, 7, frame, 1.5, 0.25), kind)
    assert (m.header.stamp.sec, m.header.stamp.nanosec, m.header.frame_id) == (5, 7,
                                                                                frame.decode())
    assert getattr(m, field) == 1.5 and m.variance == 0.25
    r = kind()
    r.header.stamp.sec, r.header.stamp.nanosec = 1_700_000_000, 999_999_999
    r.header.frame_id = frame.decode()
    setattr(r, field, -12.25)
    assert cdr.unpack_scalar(serialize_message(r)) == (1_700_000_000_999_999_999, -12.25)


@pytest.mark.parametrize('frame', FRAMES)
@pytest.mark.parametrize('name', NAMES)
@pytest.mark.parametrize('vel, eff', OPTIONAL)
def test_joint_state_both_ways(frame, name, vel, eff):
    m = deserialize_message(cdr.pack_joint_state(1, 2, frame, name, 0.5, vel, eff), JointState)
    assert list(m.name) == [name.decode()] and list(m.position) == [0.5]
    assert list(m.velocity) == ([] if math.isnan(vel) else [vel])
    assert list(m.effort) == ([] if math.isnan(eff) else [eff])
    r = JointState()
    r.header.frame_id = frame.decode()
    r.header.stamp.sec, r.header.stamp.nanosec = 1, 2
    r.name = ['other', name.decode()]
    r.position = [9.0, 0.5]
    r.velocity = [] if math.isnan(vel) else [8.0, vel]
    r.effort = [] if math.isnan(eff) else [7.0, eff]
    stamp, pos, v, e = cdr.unpack_joint_state(serialize_message(r), name.decode())
    assert (stamp, pos) == (1_000_000_002, 0.5)
    assert (math.isnan(v) if math.isnan(vel) else v == vel)
    assert (math.isnan(e) if math.isnan(eff) else e == eff)
    assert cdr.unpack_joint_state(serialize_message(r), 'missing') is None


def test_unnamed_single_joint_counts():
    r = JointState()
    r.position = [1.25]
    assert cdr.unpack_joint_state(serialize_message(r), 'actuator_joint')[1] == 1.25


def test_clock_and_float64():
    m = deserialize_message(cdr.pack_clock(3, 4), Clock)
    assert (m.clock.sec, m.clock.nanosec) == (3, 4)
    assert deserialize_message(cdr.pack_float64(2.5), Float64).data == 2.5
    for v in (-1.25, math.inf, 1e-300):
        assert cdr.unpack_float64(serialize_message(Float64(data=v))) == v
    assert math.isnan(cdr.unpack_float64(serialize_message(Float64(data=math.nan))))


def test_not_cdr_is_rejected():
    with pytest.raises(ValueError):
        cdr.unpack_float64(b'\x00\x00\x00\x00' + bytes(8))


def test_measurement_packer_matches_the_messages():
    from pneumatic_servo.control.measurement import Measurement
    from pneumatic_servo.ros.common import MeasurementPacker
    for frame in ('', 'f', 'frame_1'):
        p = MeasurementPacker('actuator_joint', frame)
        out = dict(p.pack(Measurement(1.0, 0.5, 0.1, 3e5, 2e5, 7e5, 300.0, 290.0, 1.5),
                          1_500_000_001))
        assert list(out)[-1] == 'joint_states'   # last: the controller answers it
        m = deserialize_message(out['chamber_b/pressure'], FluidPressure)
        assert m.fluid_pressure == 2e5 and m.header.frame_id == frame
        assert (m.header.stamp.sec, m.header.stamp.nanosec) == (1, 500_000_001)
        t = deserialize_message(out['chamber_a/temperature'], Temperature)
        assert t.temperature == pytest.approx(300.0 - 273.15)
        j = deserialize_message(out['joint_states'], JointState)
        assert list(j.position) == [0.5] and list(j.velocity) == [0.1]
        assert list(j.effort) == [1.5] and list(j.name) == ['actuator_joint']
    # unknown values are not published
    out = dict(MeasurementPacker('j').pack(Measurement(0.0, 1.0), 5))
    assert list(out) == ['joint_states']
    j = deserialize_message(out['joint_states'], JointState)
    assert list(j.velocity) == [] and list(j.effort) == []
