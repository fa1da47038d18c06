"""The bag on disk: its directory and storage files checked before rosbags opens them, the
messages streamed out of them, and rosbags' writer set up as ROS 2 Jazzy's recorder writes.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import ExperimentError
from ...files import regular_file

STORAGES = ('sqlite3', 'mcap')
#: rosbag2 metadata version written: what ROS 2 Jazzy's recorder writes (type hashes, QoS)
BAG_VERSION = 9


# ----------------------------------------------------------------------------- reading
def bag_dir(path: Path) -> Path:
    """The rosbag2 directory of ``path`` (a directory or a storage file in one), its
    metadata and storage files checked to be regular files (a FIFO would block)."""
    if not path.exists():
        raise ExperimentError(f'{path}: no such bag directory or CSV file')
    if not path.is_dir():
        regular_file(path, 'bag storage file', ExperimentError)
    if path.is_file():
        if path.suffix not in ('.db3', '.mcap'):
            raise ExperimentError(f'{path}: not a rosbag2 directory, .db3/.mcap file or CSV '
                                  'file; give the bag directory')
        path = path.parent
    if not (path / 'metadata.yaml').exists():
        files = sorted(p.name for p in path.iterdir() if p.suffix in ('.db3', '.mcap'))
        if not files:
            raise ExperimentError(f'{path}: not a rosbag2 directory (no metadata.yaml and no '
                                  '.db3 or .mcap file)')
        raise ExperimentError(
            f'{path}: no metadata.yaml next to {files[0]}: the recording was not closed '
            f'(recorder killed?); rebuild it with `ros2 bag reindex {path}` after checking '
            'the storage file, then read again')
    regular_file(path / 'metadata.yaml', 'bag metadata file', ExperimentError)
    for storage in path.iterdir():
        if storage.suffix in ('.db3', '.mcap'):
            regular_file(storage, 'bag storage file', ExperimentError)
    unmerged_wal(path)
    return path


def unmerged_wal(bag: Path) -> None:
    """Refuse a sqlite3 bag whose write-ahead log still holds data: the writer was not
    closed, and reading the .db3 alone would silently give part of the recording."""
    for wal in bag.glob('*.db3-wal'):
        if wal.stat().st_size > 0:
            raise ExperimentError(
                f'{wal}: the recording was not closed and part of it is still in the '
                f"write-ahead log; merge it with `sqlite3 {wal.with_suffix('')} "
                "'PRAGMA wal_checkpoint(TRUNCATE);'` (or `ros2 bag reindex`), then read again")


def storage_of(bag: Path) -> str:
    """'mcap' or 'sqlite3': the storage of a checked bag directory."""
    return 'mcap' if any(p.suffix == '.mcap' for p in bag.iterdir()) else 'sqlite3'


def open_reader(bag: Path):
    """rosbags' reader of ``bag`` (a context manager; raises the storage layer's errors)."""
    from rosbags.rosbag2 import Reader
    return Reader(bag)


# ----------------------------------------------------------------------------- writing
def offered_qos(reliable: bool):
    """The QoS a topic's publisher offers, as rosbag2 writes it into the metadata: commands
    and targets reliable (keep last 10), measurements best effort (keep last 5), as the
    nodes publish them."""
    from rosbags.interfaces import (
        Qos,
        QosDurability,
        QosHistory,
        QosLiveliness,
        QosReliability,
        QosTime,
    )
    return Qos(QosHistory.KEEP_LAST, 10 if reliable else 5,
               QosReliability.RELIABLE if reliable else QosReliability.BEST_EFFORT,
               QosDurability.VOLATILE, QosTime(0, 0), QosTime(0, 0), QosLiveliness.AUTOMATIC,
               QosTime(0, 0), False)


def add_topic(writer, topic: str, msgtype: str, store, reliable: bool):
    """A connection as rosbag2 records it: the absolute topic name, the type with its
    description hash, the offered QoS. ``store``: rosbags' typestore that knows the type;
    None for an docs/interfaces.md type (its codec knows the definition and hash)."""
    name = topic if topic.startswith('/') else '/' + topic
    qos = [offered_qos(reliable)]
    if store is None:
        from ..codecs import CODECS
        codec = CODECS[msgtype]
        return writer.add_connection(name, msgtype, msgdef=codec.definition,
                                     rihs01=codec.rihs01, offered_qos_profiles=qos)
    return writer.add_connection(name, msgtype, typestore=store, offered_qos_profiles=qos)


def open_writer(path: Path, storage: str, compress: bool = False):
    """rosbags' writer of a new bag directory, opened (zstd chunks: MCAP only)."""
    from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer
    plugin = StoragePlugin.MCAP if storage == 'mcap' else StoragePlugin.SQLITE3
    writer = Writer(path, version=BAG_VERSION, storage_plugin=plugin)
    if compress and storage == 'mcap':
        writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    writer.open()
    return writer


def abandon(writer, storage: str) -> None:
    """Stop writing as a killed recorder does: MCAP without summary and footer, sqlite3
    with its committed rows but no metadata.yaml."""
    if storage == 'mcap':
        writer.abort()
    else:
        writer.storage.close(BAG_VERSION, '')
        writer.storage = None


def write_samples(writer, columns, n: int) -> None:
    """Write ``n`` samples as a recorder receives them: for each sample the message of every
    column ``(connection, record times [ns], messages)`` in turn.

    rosbags' writer takes one message per call (3-4 us each, most of a bag's writing).
    Where the writer is one of the two this was checked against (rosbags' MCAP and sqlite3
    storage, no per-message compression) and each column's messages have one length, the
    same records are written in bulk: MCAP chunks built with numpy and cut where rosbags
    cuts them, with its chunk index and statistics; sqlite3 rows in one ``executemany``.
    tests/test_codecs.py checks that the files are the same as message by message.
    """
    kind = _bulk_kind(writer, columns)
    if kind is None:
        write = writer.write
        for k in range(n):
            for conn, recs, raws in columns:
                write(conn, recs[k], raws[k])
        return
    if n == 0:
        return
    if kind == 'mcap':
        _write_mcap(writer.storage, columns, n)
    else:
        writer.storage.cursor.executemany(
            'INSERT INTO messages (topic_id, timestamp, data) VALUES(?, ?, ?)',
            ((conn.id, recs[k], raws[k]) for k in range(n) for conn, recs, raws in columns))
    for conn, recs, _ in columns:
        writer.counts[conn.id] += n
        writer.min_timestamp = min(writer.min_timestamp, min(recs))
        writer.max_timestamp = max(writer.max_timestamp, max(recs))


def _bulk_kind(writer, columns) -> str | None:
    """'mcap' or 'sqlite3' where :func:`write_samples` may write in bulk, else None."""
    from rosbags.rosbag2 import CompressionMode
    storage = getattr(writer, 'storage', None)
    kind = {'rosbags.rosbag2.storage_mcap.McapWriter': 'mcap',
            'rosbags.rosbag2.storage_sqlite3.Sqlite3Writer': 'sqlite3'}.get(
        f'{type(storage).__module__}.{type(storage).__qualname__}')
    if (kind is None or getattr(writer, 'compression_mode', None) == CompressionMode.MESSAGE
            or not all(hasattr(writer, a) for a in ('counts', 'min_timestamp',
                                                     'max_timestamp', 'connections'))
            or any(conn not in writer.connections for conn, _, _ in columns)):
        return None
    if kind == 'mcap' and not all(hasattr(storage, a) for a in (
            'chunk', 'close_chunk', 'channel_stats', 'message_start_time',
            'message_end_time')):
        return None
    if kind == 'sqlite3' and not hasattr(storage, 'cursor'):
        return None
    if kind == 'mcap' and any(len({len(m) for m in raws}) > 1 for _, _, raws in columns):
        return None
    return kind


#: rosbags' MCAP writer closes a chunk after the message that takes it past this [bytes]
_CHUNK_BYTES = 2**20


def _write_mcap(st, columns, n: int) -> None:
    """The MCAP message records of ``n`` samples in rosbags' chunks, as its ``write`` makes
    them one at a time: opcode 0x05, length, channel id, sequence 0, log and publish time,
    the message."""
    parts, sizes = [], []
    for conn, recs, raws in columns:
        size = len(raws[0])
        rows = np.empty((n, 31 + size), np.uint8)
        rows[:, 0] = 0x05
        head = np.zeros(n, dtype=[('len', '<u8'), ('cid', '<u2'), ('seq', '<u4'),
                                  ('log', '<u8'), ('pub', '<u8')])
        head['len'], head['cid'] = 22 + size, conn.id
        head['log'] = head['pub'] = recs
        rows[:, 1:31] = head.view(np.uint8).reshape(n, 30)
        rows[:, 31:] = np.frombuffer(b''.join(raws), np.uint8).reshape(n, size)
        parts.append(rows)
        sizes.append(31 + size)
    blob = np.concatenate(parts, axis=1).tobytes()
    count = len(columns)
    start = (np.arange(n, dtype=np.int64)[:, None] * sum(sizes)
             + np.cumsum([0] + sizes[:-1])[None, :]).ravel()  # of message j = k * count + c
    end = start + np.tile(sizes, n)
    times = np.array([recs for _, recs, _ in columns], dtype=np.int64).T.ravel()
    j0 = 0
    while j0 < n * count:
        base = st.chunk.bio.tell() - int(start[j0])  # chunk offset of a record: base + start
        j1 = min(int(np.searchsorted(end, _CHUNK_BYTES - base, side='right')), n * count - 1)
        st.chunk.bio.write(blob[start[j0]:end[j1]])
        span = times[j0:j1 + 1]
        lo, hi = int(span.min()), int(span.max())
        st.chunk.message_start_time = min(st.chunk.message_start_time, lo)
        st.chunk.message_end_time = max(st.chunk.message_end_time, hi)
        st.message_start_time = min(st.message_start_time, lo)
        st.message_end_time = max(st.message_end_time, hi)
        for c in [(j0 + i) % count for i in range(min(count, j1 + 1 - j0))]:
            first = j0 + (c - j0) % count
            conn = columns[c][0]
            js = np.arange(first, j1 + 1, count)
            st.channel_stats[conn.id] += len(js)
            st.chunk.msgs[conn.id].extend(zip(times[js].tolist(), (base + start[js]).tolist()))
        if st.chunk.bio.tell() > _CHUNK_BYTES:
            st.close_chunk()
        j0 = j1 + 1
