"""What a storage or decoding failure means for the user: one line, the cause and the fix.

The storage layers (rosbags' MCAP reader, apsw/sqlite3, the file system) say what broke
only in their messages' words, so a storage failure is recognised by those words: the
table :data:`STORAGE_FAILURES` maps them to the reason given.
"""
from __future__ import annotations

import struct

from ...errors import ExperimentError

#: (words any of which the storage layer's message holds, the reason given; ``{text}`` is
#: that message) in the order tried
STORAGE_FAILURES = (
    (('end magic', 'mcap footer', 'summary offset'),
     'the MCAP file has no footer: the recording was not closed (recorder killed?); '
     're-record it, or recover the messages with `mcap recover` and `ros2 bag reindex`'),
    (('truncated record', 'chunk size mismatch', 'checksum'),
     'the MCAP file is truncated or corrupt ({text}); re-record it, or recover with '
     '`mcap recover`'),
    (('malformed', 'not a database', 'corrupt', 'missing tables', 'disk i/o'),
     'the sqlite3 file is truncated or corrupt ({text}); re-record it, or recover what was '
     'written with `sqlite3 .recover` and `ros2 bag reindex`'),
    (('database files are missing', 'does not exist'),
     'a storage file listed in metadata.yaml is missing ({text}); copy the whole bag'),
)


def storage_error(where: str, exc: Exception) -> ExperimentError:
    """A one-line reason for an exception raised by the storage layer."""
    text = str(exc).strip().rstrip('.') or type(exc).__name__
    low = text.lower()
    why = next((reason.format(text=text) for words, reason in STORAGE_FAILURES
                if any(w in low for w in words)),
               f'cannot read the bag ({type(exc).__name__}: {text})')
    return ExperimentError(f'{where}: {why}')


def storage_exceptions() -> tuple[type[Exception], ...]:
    """The exception types the storage layer raises for a damaged bag."""
    from rosbags.rosbag2 import ReaderError
    excs: list[type[Exception]] = [ReaderError, OSError, struct.error, EOFError]
    try:
        import apsw
        excs.append(apsw.Error)
    except ImportError:  # pragma: no cover - rosbags depends on apsw
        pass
    import sqlite3
    excs.append(sqlite3.Error)
    return tuple(excs)


def decode_error(where: str, number: int, topic: str, msgtype: str,
                 exc: Exception) -> ExperimentError:
    """Message ``number`` (from 1) on ``topic`` does not decode as ``msgtype``."""
    return ExperimentError(
        f'{where}: message {number} on {topic} cannot be decoded as {msgtype} '
        f'({type(exc).__name__}: {exc}); the bag is corrupt or was recorded with another '
        'message definition')
