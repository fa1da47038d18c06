"""Hand-written CDR (little endian, XCDR1, as rmw_fastrtps puts ROS 2 messages on the wire)
of the docs/interfaces.md message types, one message at a time. Pure (struct only).

Two users: the ROS nodes' hot path (``pneumatic_servo.ros.cdr``, which re-exports this:
rclpy converts every message between Python objects and C structs, at 1 kHz with seven
messages per period the largest cost of the loop, so the plant publishes bytes packed here
and the controller reads the two or three numbers it needs straight from the bytes), and
the batch codecs of bags (:mod:`pneumatic_servo.io.codecs`), which pack one template
message here and fill its numbers for every sample at once. tests/ros/test_cdr.py checks
every function against rclpy's own (de)serialisation, tests/test_codecs.py against rosbags'.

Layout rules: a 4-byte encapsulation header (``00 01 00 00``: CDR little
endian), then the fields, each primitive aligned to its size counted from
the end of that header; strings are a uint32 length (with the NUL) then the
bytes and a NUL; sequences a uint32 count then the elements.
"""
from __future__ import annotations

import math
import struct

HEADER = b'\x00\x01\x00\x00'
_U32 = struct.Struct('<I')
_STAMP = struct.Struct('<iI')
_F64 = struct.Struct('<d')
F64x2 = struct.Struct('<dd')


def _pad(n: int, align: int) -> int:
    return (-n) % align


def _header(sec: int, nsec: int, frame_id: bytes) -> bytearray:
    """Encapsulation + std_msgs/Header; the payload length is then a multiple of 4."""
    b = bytearray(HEADER)
    b += _STAMP.pack(sec, nsec)
    b += _U32.pack(len(frame_id) + 1) + frame_id + b'\x00'
    b += b'\x00' * _pad(len(b) - 4, 4)
    return b


def pack_scalar(sec: int, nsec: int, frame_id: bytes, value: float,
                variance: float = 0.0) -> bytes:
    """sensor_msgs/FluidPressure or sensor_msgs/Temperature (same layout)."""
    b = _header(sec, nsec, frame_id)
    b += b'\x00' * _pad(len(b) - 4, 8)
    b += F64x2.pack(value, variance)
    return bytes(b)


def pack_clock(sec: int, nsec: int) -> bytes:
    """rosgraph_msgs/Clock."""
    return HEADER + _STAMP.pack(sec, nsec)


def pack_float64(value: float) -> bytes:
    """std_msgs/Float64."""
    return HEADER + _F64.pack(value)


def _doubles(b: bytearray, values) -> None:
    b += b'\x00' * _pad(len(b) - 4, 4)
    b += _U32.pack(len(values))
    if values:
        b += b'\x00' * _pad(len(b) - 4, 8)
        b += struct.pack(f'<{len(values)}d', *values)


def header_block(sec: int, nsec: int, frame_id: bytes) -> bytes:
    """Encapsulation and std_msgs/Header, padded to 4: the common start of stamped messages."""
    return bytes(_header(sec, nsec, frame_id))


def pack_joint_state(sec: int, nsec: int, frame_id: bytes, name: bytes, position: float,
                     velocity: float = math.nan, effort: float = math.nan) -> bytes:
    """sensor_msgs/JointState with one joint; NaN velocity/effort are left out (empty)."""
    return joint_state_after_header(header_block(sec, nsec, frame_id), name, position,
                                    velocity, effort)


def joint_state_after_header(head: bytes, name: bytes, position: float,
                             velocity: float = math.nan, effort: float = math.nan) -> bytes:
    """A one-joint JointState from a :func:`header_block`."""
    b = bytearray(head)
    b += _U32.pack(1) + _U32.pack(len(name) + 1) + name + b'\x00'
    _doubles(b, (position,))
    _doubles(b, (velocity,) if math.isfinite(velocity) else ())
    _doubles(b, (effort,) if math.isfinite(effort) else ())
    return bytes(b)


# ----------------------------------------------------------------------------- reading
def _check(data) -> None:
    if len(data) < 12 or data[1] != 1:
        raise ValueError('not little-endian CDR')


def _skip_string(data, off: int) -> int:
    """Offset after the string at ``off`` (payload offsets, relative to byte 4)."""
    n = _U32.unpack_from(data, 4 + off)[0]
    return off + 4 + n


def unpack_scalar(data) -> tuple[int, float]:
    """(stamp [ns], value) of a FluidPressure or Temperature."""
    _check(data)
    sec, nsec = _STAMP.unpack_from(data, 4)
    off = _skip_string(data, 8)
    off += _pad(off, 8)
    return sec * 1_000_000_000 + nsec, _F64.unpack_from(data, 4 + off)[0]


def unpack_float64(data) -> float:
    _check(data)
    return _F64.unpack_from(data, 4)[0]


def _read_doubles(data, off: int):
    off += _pad(off, 4)
    n = _U32.unpack_from(data, 4 + off)[0]
    off += 4
    if n:
        off += _pad(off, 8)
    values = struct.unpack_from(f'<{n}d', data, 4 + off) if n else ()
    return values, off + 8 * n


def unpack_joint_state(data, joint_name: str):
    """(stamp [ns], position, velocity, effort) of ``joint_name`` (NaN where absent), or
    None if the message does not carry that joint. A single unnamed joint counts."""
    _check(data)
    sec, nsec = _STAMP.unpack_from(data, 4)
    off = _skip_string(data, 8)
    off += _pad(off, 4)
    count = _U32.unpack_from(data, 4 + off)[0]
    off += 4
    names = []
    for _ in range(count):
        off += _pad(off, 4)
        n = _U32.unpack_from(data, 4 + off)[0]
        names.append(bytes(data[4 + off + 4:4 + off + 3 + n]).decode('utf-8', 'replace'))
        off += 4 + n
    pos, off = _read_doubles(data, off)
    vel, off = _read_doubles(data, off)
    eff, off = _read_doubles(data, off)
    if joint_name in names:
        i = names.index(joint_name)
    elif not names and len(pos) == 1:
        i = 0
    else:
        return None
    if i >= len(pos):
        return None
    return (sec * 1_000_000_000 + nsec, pos[i], vel[i] if i < len(vel) else math.nan,
            eff[i] if i < len(eff) else math.nan)
