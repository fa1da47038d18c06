"""The bag on disk: its directory and storage files checked before rosbags opens them, the
messages streamed out of them, and rosbags' writer set up as ROS 2 Jazzy's recorder writes.
"""
from __future__ import annotations

from pathlib import Path

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
    description hash, the offered QoS."""
    name = topic if topic.startswith('/') else '/' + topic
    return writer.add_connection(name, msgtype, typestore=store,
                                 offered_qos_profiles=[offered_qos(reliable)])


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
