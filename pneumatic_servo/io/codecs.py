"""Batch CDR codecs of the interface message types (docs/interfaces.md): the messages of a topic decoded (or
encoded) all at once with numpy, at fixed offsets. Keyed by message type; each
:func:`codec_of` finds a :class:`~pneumatic_servo.io.topics.Topic`'s.

The messages of one topic nearly always share one layout: the same frame_id, the same
joint names, the same sequence lengths; only the stamps and the numbers change. The first
message of a batch is parsed as rosbags' deserialiser does (the same alignment, the same
checks of lengths, terminators and UTF-8), which gives that layout: where the stamp and
the numbers are, and which bytes (string lengths and contents, sequence counts, the
encapsulation) decide it. Every message of the same length that repeats those bytes
decodes the same way, so its numbers are read at those offsets, all messages at once. Any
other message (another frame_id or joint list, a cut message, big-endian CDR) is
deserialised on its own by rosbags' typestore, in order, so a batch decodes exactly as
rosbags would and fails where it would. tests/test_codecs.py checks this on every bag in
bags/ and tests/data/.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass, field
from itertools import compress

import numpy as np

from . import cdr
from .topics import FLOAT64, FLUID_PRESSURE, JOINT_STATE, TEMPERATURE

_TYPESTORE = None
_SEP = '=' * 80 + '\n'
#: the std_msgs/Header and builtin_interfaces/Time a stamped message's definition ends with
_HEADER_DEFINITIONS = (_SEP + 'MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\n'
                       'string frame_id\n' + _SEP + 'MSG: builtin_interfaces/Time\nint32 sec\n'
                       'uint32 nanosec\n')


def typestore():
    """The ROS 2 Jazzy message typestore (built once, when first needed)."""
    global _TYPESTORE
    if _TYPESTORE is None:
        from rosbags.typesys import Stores, get_typestore
        _TYPESTORE = get_typestore(Stores.ROS2_JAZZY)
    return _TYPESTORE


class DecodeError(Exception):
    """Message ``index`` of a batch does not decode as its type; ``cause`` says why."""

    def __init__(self, index: int, cause: Exception):
        super().__init__(index, cause)
        self.index, self.cause = index, cause


@dataclass
class Decoded:
    """A batch's fields, one value per message in order: ``stamp_ns`` (``header.stamp``
    [ns], None for a type without header), ``fields`` (float, NaN where absent) and, for
    fields a message may lack, ``present``. A JointState batch stops at the first message
    without the picked joint's position (``present['position']`` False there)."""

    stamp_ns: np.ndarray | None
    fields: dict[str, np.ndarray]
    present: dict[str, np.ndarray] = field(default_factory=dict)


@dataclass
class Layout:
    """Where one message's numbers are: ``length`` [bytes], the ``fixed`` byte columns every
    message of this layout repeats, byte offsets of float64 ``fields`` (sequences: of their
    first element), and for JointState the joint ``names`` and the sequence ``counts``."""

    length: int
    fixed: np.ndarray
    fields: dict[str, int]
    names: tuple[str, ...] = ()
    counts: dict[str, int] = field(default_factory=dict)


class _Parser:
    """One little-endian CDR message read as rosbags' deserialiser reads it, noting the
    bytes that decide the layout. Raises (ValueError, struct.error, UnicodeDecodeError)
    wherever rosbags would refuse the message."""

    def __init__(self, raw):
        self.raw = bytes(raw)
        if len(self.raw) < 4 or self.raw[:2] != b'\x00\x01':
            raise ValueError('not little-endian CDR')
        self.size = len(self.raw) - 4  # payload
        self.pos = 0                   # payload offset
        self.fixed = [0, 1]
        self.offsets: dict[str, int] = {}

    def align(self, n: int) -> None:
        self.pos += -self.pos % n

    def u32(self) -> int:
        self.align(4)
        value = struct.unpack_from('<I', self.raw, 4 + self.pos)[0]
        self.fixed += range(4 + self.pos, 8 + self.pos)
        self.pos += 4
        return value

    def string(self) -> str:
        n = self.u32()
        end = self.pos + n
        if n < 1 or end > self.size or self.raw[4 + end - 1] != 0:
            raise ValueError(f'invalid string at offset {self.pos - 4}')
        text = self.raw[4 + self.pos:4 + end - 1].decode()
        self.fixed += range(4 + self.pos, 4 + end)
        self.pos = end
        return text

    def header(self) -> None:
        """std_msgs/Header: the stamp (not fixed) and the frame_id (fixed)."""
        if self.size < 8:
            raise ValueError('no header stamp')
        self.pos = 8
        self.string()

    def f64(self, name: str) -> None:
        self.align(8)
        if self.pos + 8 > self.size:
            raise ValueError(f'no {name}')
        self.offsets[name] = 4 + self.pos
        self.pos += 8

    def doubles(self, name: str) -> int:
        n = self.u32()
        if self.pos + 8 * n > self.size:
            raise ValueError(f'invalid sequence length {n}')
        if n:
            self.align(8)
            if self.pos + 8 * n > self.size:
                raise ValueError(f'invalid sequence length {n}')
        self.offsets[name] = 4 + self.pos
        self.pos += 8 * n
        return n

    def layout(self, **extra) -> Layout:
        if self.pos + 4 + 3 < len(self.raw):
            raise ValueError('message size mismatch')
        return Layout(len(self.raw), np.array(self.fixed, dtype=np.intp), self.offsets,
                      **extra)


def _column(rows: np.ndarray, offset: int, dtype: str) -> np.ndarray:
    """The values of ``dtype`` at byte ``offset`` of every row."""
    width = np.dtype(dtype).itemsize
    return rows[:, offset:offset + width].copy().view(dtype)[:, 0].astype(
        dtype.replace('<', '='), copy=False)


def _stamps(rows: np.ndarray) -> np.ndarray:
    sec = _column(rows, 4, '<i4').astype(np.int64)
    return sec * 1_000_000_000 + _column(rows, 8, '<u4').astype(np.int64)


def _split(rows: np.ndarray) -> list[bytes]:
    """Each row of ``rows`` as the bytes of one message."""
    blob, size = rows.tobytes(), rows.shape[1]
    return [blob[i:i + size] for i in range(0, len(blob), size)]


class Codec:
    """The batch codec of one message type (a subclass per layout). Besides decoding and
    encoding, it knows its type's definition as rosbag2 stores it with a connection (its
    own fields' ``lines`` after the header, and the ``rihs01`` type hash), so a bag is
    written without building rosbags' typestore (tests/test_codecs.py checks both)."""

    msgtype: str
    fields: tuple[str, ...]
    stamped = True
    lines: tuple[str, ...]
    rihs01: str

    @property
    def definition(self) -> str:
        """The message definition (ros2msg) rosbag2 stores with a connection."""
        own = ''.join(line + '\n' for line in self.lines)
        return 'std_msgs/Header header\n' + own + _HEADER_DEFINITIONS if self.stamped else own

    def layout(self, raw) -> Layout:
        raise NotImplementedError

    def fast(self, raws) -> tuple[Layout | None, np.ndarray, np.ndarray]:
        """(layout of the first message, mask of the messages that share it, their bytes as
        rows); no layout and an empty mask when the first message is not the fast case."""
        try:
            lay = self.layout(raws[0])
        except (ValueError, struct.error, UnicodeDecodeError):
            return None, np.zeros(len(raws), bool), np.zeros((0, 0), np.uint8)
        lengths = np.fromiter(map(len, raws), np.intp, len(raws))
        mask = lengths == lay.length
        chosen = raws if mask.all() else list(compress(raws, mask))
        rows = np.frombuffer(b''.join(chosen), np.uint8).reshape(len(chosen), lay.length)
        same = (rows[:, lay.fixed] == rows[0, lay.fixed]).all(axis=1)
        if not same.all():
            mask[np.flatnonzero(mask)[~same]] = False
            rows = rows[same]
        return lay, mask, rows

    def slow(self, raw, index: int):
        """One message deserialised by rosbags."""
        try:
            return typestore().deserialize_cdr(raw, self.msgtype)
        except Exception as exc:  # whatever the typestore raises, the message is bad
            raise DecodeError(index, exc) from None


class Float64Codec(Codec):
    """std_msgs/Float64: 8 bytes after the encapsulation, no header."""

    msgtype, fields, stamped = FLOAT64, ('data',), False
    lines = ('float64 data',)
    rihs01 = 'RIHS01_705ba9c3d1a09df43737eb67095534de36fd426c0587779bda2bc51fe790182a'

    def layout(self, raw) -> Layout:
        p = _Parser(raw)
        p.f64('data')
        return p.layout()

    def decode(self, raws, pick=None) -> Decoded:
        lay, mask, rows = self.fast(raws)
        values = np.empty(len(raws))
        if len(rows):
            values[mask] = _column(rows, lay.fields['data'], '<f8')
        for k in np.flatnonzero(~mask).tolist():
            values[k] = self.slow(raws[k], k).data
        return Decoded(None, {'data': values})

    def encode(self, stamps_ns, fields: dict, joint: str = '', frame_id: bytes = b''
               ) -> list[bytes]:
        """Messages carrying ``fields['data']`` (no header: ``stamps_ns`` is not used)."""
        values = np.ascontiguousarray(fields['data'], dtype='<f8')
        rows = np.empty((len(values), 12), np.uint8)
        rows[:, :4] = np.frombuffer(cdr.HEADER, np.uint8)
        rows[:, 4:] = values.reshape(-1, 1).view(np.uint8)
        return _split(rows)


class ScalarCodec(Codec):
    """sensor_msgs/FluidPressure or Temperature: a header, then the value and a variance."""

    def __init__(self, msgtype: str, name: str, rihs01: str):
        self.msgtype, self.fields, self.rihs01 = msgtype, (name, 'variance'), rihs01
        self.lines = tuple(f'float64 {f}' for f in self.fields)

    def layout(self, raw) -> Layout:
        p = _Parser(raw)
        p.header()
        for name in self.fields:
            p.f64(name)
        return p.layout()

    def decode(self, raws, pick=None) -> Decoded:
        lay, mask, rows = self.fast(raws)
        n = len(raws)
        stamps, out = np.empty(n, np.int64), {f: np.empty(n) for f in self.fields}
        if len(rows):
            stamps[mask] = _stamps(rows)
            for f in self.fields:
                out[f][mask] = _column(rows, lay.fields[f], '<f8')
        for k in np.flatnonzero(~mask).tolist():
            msg = self.slow(raws[k], k)
            try:
                stamps[k] = int(msg.header.stamp.sec) * 1_000_000_000 + int(
                    msg.header.stamp.nanosec)
                for f in self.fields:
                    out[f][k] = getattr(msg, f)
            except Exception as exc:
                raise DecodeError(k, exc) from None
        return Decoded(stamps, out)

    def encode(self, stamps_ns, fields: dict, joint: str = '', frame_id: bytes = b''
               ) -> list[bytes]:
        """Messages stamped ``stamps_ns`` [ns] carrying ``fields`` (variance 0 if absent)."""
        template = cdr.pack_scalar(0, 0, frame_id, 0.0)
        lay = self.layout(template)
        rows = _template_rows(template, stamps_ns)
        for f in self.fields:
            if f in fields:
                _fill(rows, lay.fields[f], fields[f])
        return _split(rows)


class JointStateCodec(Codec):
    """sensor_msgs/JointState: a header, the joint names, then position, velocity and effort
    (each a sequence of float64, one per joint, or empty). ``pick(names)`` gives the index
    of the actuator joint (or raises), called in message order as the names change."""

    msgtype, fields = JOINT_STATE, ('position', 'velocity', 'effort')
    lines = ('string[] name', 'float64[] position', 'float64[] velocity', 'float64[] effort')
    rihs01 = 'RIHS01_a13ee3a330e346c9d87b5aa18d24e11690752bd33a0350f11c5882bc9179260e'

    def layout(self, raw) -> Layout:
        p = _Parser(raw)
        p.header()
        count = p.u32()
        if p.pos + 5 * count > p.size:
            raise ValueError(f'invalid sequence length {count}')
        names = tuple(p.string() for _ in range(count))
        counts = {f: p.doubles(f) for f in self.fields}
        return p.layout(names=names, counts=counts)

    def decode(self, raws, pick) -> Decoded:
        lay, mask, rows = self.fast(raws)
        n = len(raws)
        stamps = np.zeros(n, np.int64)
        out = {f: np.full(n, np.nan) for f in self.fields}
        present = {f: np.zeros(n, bool) for f in self.fields}
        done = Decoded(stamps, out, present)
        if len(rows):
            stamps[mask] = _stamps(rows)
        picked: dict[int, dict] = {}  # joint index -> its values in every fast message
        slow = np.flatnonzero(~mask).tolist()
        start = 0
        for j, k in enumerate(slow + [n]):
            if k > start:  # the fast messages start..k-1, rows start-j..k-j-1
                i = pick(lay.names)
                if i not in picked:
                    picked[i] = {f: _column(rows, lay.fields[f] + 8 * i, '<f8')
                                 for f in self.fields if i < lay.counts[f]}
                if 'position' not in picked[i]:
                    return done  # present['position'][start] is False: the reader refuses
                for f, values in picked[i].items():
                    out[f][start:k] = values[start - j:k - j]
                    present[f][start:k] = True
            if k == n:
                break
            msg = self.slow(raws[k], k)
            try:
                stamps[k] = int(msg.header.stamp.sec) * 1_000_000_000 + int(
                    msg.header.stamp.nanosec)
                names = msg.name
                arrays = [getattr(msg, f) for f in self.fields]
            except Exception as exc:
                raise DecodeError(k, exc) from None
            i = pick(names)
            if len(arrays[0]) <= i:
                return done
            for f, arr in zip(self.fields, arrays):
                if len(arr) > i:
                    out[f][k], present[f][k] = arr[i], True
            start = k + 1
        return done

    def encode(self, stamps_ns, fields: dict, joint: str = '', frame_id: bytes = b''
               ) -> list[bytes]:
        """One-joint messages (the joint named ``joint``): ``fields['position']`` and,
        where given, velocity and effort (an absent one is an empty sequence)."""
        have = [f for f in self.fields if fields.get(f) is not None]
        template = cdr.pack_joint_state(0, 0, frame_id, joint.encode(), *(
            0.0 if f in have else np.nan for f in self.fields))
        lay = self.layout(template)
        rows = _template_rows(template, stamps_ns)
        for f in have:
            _fill(rows, lay.fields[f], fields[f])
        return _split(rows)


def _template_rows(template: bytes, stamps_ns) -> np.ndarray:
    """``template`` repeated once per stamp [ns], each row's header stamp set."""
    stamps = np.asarray(stamps_ns, dtype=np.int64)
    rows = np.tile(np.frombuffer(template, np.uint8), (len(stamps), 1))
    sec, nsec = np.divmod(stamps, 1_000_000_000)
    if len(sec) and (sec.min() < -2**31 or sec.max() >= 2**31):
        raise ValueError('a stamp outside what a ROS 2 time holds (int32 seconds)')
    _fill(rows, 4, sec.astype('<i4'))
    _fill(rows, 8, nsec.astype('<u4'))
    return rows


def _fill(rows: np.ndarray, offset: int, values) -> None:
    """Write ``values`` (one per row; float64 unless typed) at byte ``offset`` of each row."""
    values = np.asarray(values)
    if values.dtype.kind == 'f':
        values = values.astype('<f8')
    rows[:, offset:offset + values.dtype.itemsize] = np.ascontiguousarray(
        values).reshape(-1, 1).view(np.uint8)


#: message type -> its batch codec
CODECS: dict[str, Codec] = {c.msgtype: c for c in (
    Float64Codec(),
    ScalarCodec(FLUID_PRESSURE, 'fluid_pressure',
                'RIHS01_22dfb2b145a0bd5a31a1ac3882a1b32148b51d9b2f3bab250290d66f3595bc32'),
    ScalarCodec(TEMPERATURE, 'temperature',
                'RIHS01_72514a14126ab9f8a9abec974c78e5610a367b59db5da355ff1fb982d5bad4b8'),
    JointStateCodec())}


def codec_of(topic) -> 'object':
    """The batch codec of ``topic``'s message type (a :class:`~.topics.Topic`). Kept here,
    not on the topic, so that ``topics`` imports nothing of this module (no import cycle)."""
    return CODECS[topic.msgtype]
