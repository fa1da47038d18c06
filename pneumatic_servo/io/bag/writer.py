"""An Experiment (or any messages) written as a standard rosbag2 directory with the
docs/interfaces.md topics, so a generated or simulated experiment looks like a recorded one.

The messages of each topic are packed all at once by the topic's codec (numpy; the bytes
rosbags' serialiser gives, tests/test_codecs.py) and written sample by sample, every
topic's message of a sample in turn, as a recorder receives them (in bulk where the
storage allows: :func:`.storage.write_samples`).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ...errors import ExperimentError
from ...experiment import Experiment
from ..codecs import codec_of, typestore
from ..topics import CIRCUIT_KEY, DEFAULT_JOINT, KEY_PREFIX, TOPICS
from .metadata import custom_value
from .storage import STORAGES, abandon, add_topic, open_writer, write_samples

#: start of the time axis of a written bag when the experiment does not say [ns since epoch]
DEFAULT_START_NS = 1_700_000_000 * 1_000_000_000
#: [s] a sensor message is recorded this long after its measurement time
DEFAULT_LATENCY_S = 2e-4
#: [ns] the latest stamp a ROS 2 ``builtin_interfaces/Time`` (int32 seconds) can hold
MAX_STAMP_NS = (2**31 - 1) * 10**9
#: topics in the order of their connections, and of their messages within a sample
WRITE_ORDER = ('valve/command', 'setpoint', 'joint_states', 'chamber_a/pressure',
               'chamber_b/pressure', 'supply/pressure', 'chamber_a/temperature',
               'chamber_b/temperature')


def _messages(exp: Experiment, joint: str, start_ns: int, latency_ns: int
              ) -> list[tuple[str, list[int], list[bytes]]]:
    """Per topic the experiment has: (topic, record times [ns], serialised messages)."""
    sig = exp.signals
    stamps = start_ns + np.round(exp.t * 1e9).astype(np.int64)
    out = []
    for name in WRITE_ORDER:
        spec = TOPICS[name]
        if spec.signals[0] not in sig:
            continue
        fields = {}
        for signal, field in zip(spec.signals, spec.fields):
            if signal in sig:
                values = np.asarray(sig[signal], dtype=float)
                fields[field] = values - spec.offset if spec.offset else values
        raws = codec_of(spec).encode(stamps, fields, joint=joint)
        recs = stamps + latency_ns if spec.stamped else stamps
        out.append((name, recs.tolist(), raws))
    return out


def write_experiment_bag(exp: Experiment, path, storage: str = 'sqlite3',
                         metadata: dict | None = None, *, joint: str = DEFAULT_JOINT,
                         start_time_ns: int | None = None,
                         latency_s: float = DEFAULT_LATENCY_S, compress: bool = False) -> Path:
    """Write ``exp`` as a rosbag2 directory with the docs/interfaces.md topics.

    Parameters
    ----------
    exp : Experiment
        A time series (a static table is written with ``write_static_csv``).
    path : str or Path
        New bag directory (must not exist).
    storage : {'sqlite3', 'mcap'}
    metadata : dict, optional
        Extra ``custom_data`` entries; keys without a dot get the
        ``pneumatic_servo.`` prefix, non-string values are stored as JSON.
        ``pneumatic_servo.circuit`` is always written from ``exp.circuit``, and a blocked
        record's ``blocked_angle_rad`` from ``exp.metadata`` unless given here.
    joint : str
        Joint name in ``joint_states``.
    start_time_ns : int, optional [ns since epoch]
        Stamp of t = 0 (default ``exp.metadata['start_time_ns']`` or a fixed epoch).
    latency_s : float [s]
        Record time of sensor messages after their header stamp.
    compress : bool
        zstd chunk compression (MCAP only).
    """
    from rosbags.rosbag2 import WriterError
    if exp.static:
        raise ExperimentError(f'{exp.name}: a static table is a CSV file; use write_static_csv')
    if storage not in STORAGES:
        raise ExperimentError(f"unknown storage {storage!r}; use 'sqlite3' or 'mcap'")
    path = Path(path)
    if path.exists():
        raise ExperimentError(f'{path} exists already; choose a new bag directory or delete it')
    start = int(start_time_ns if start_time_ns is not None
                else exp.metadata.get('start_time_ns', DEFAULT_START_NS))
    t = np.asarray(exp.t, dtype=float)
    if not (np.all(np.isfinite(t)) and np.all(np.diff(t) > 0)):
        raise ExperimentError(f'{exp.name}: sample times must be finite and increasing to be '
                              'written as a bag')
    if not 0 <= start + t[-1] * 1e9 + latency_s * 1e9 < MAX_STAMP_NS:
        raise ExperimentError(f'{exp.name}: stamps from {start * 1e-9:.0f} s over {t[-1]:.3g} s '
                              'leave what a ROS 2 time holds (int32 seconds since 1970); '
                              'shift the start time or shorten the record')
    topics = _messages(exp, joint, start, int(round(latency_s * 1e9)))
    custom = {CIRCUIT_KEY: exp.circuit}
    # where the pistons were held is part of a blocked record: a reader needs it to know
    # the chamber volumes, so it is never lost on the way to the bag
    held = {'blocked_angle_rad': exp.metadata['blocked_angle_rad']} \
        if exp.circuit == 'blocked' and 'blocked_angle_rad' in exp.metadata else {}
    for key, value in {**held, **(metadata or {})}.items():
        custom[key if '.' in key else KEY_PREFIX + key] = custom_value(value)
    custom[CIRCUIT_KEY] = exp.circuit
    try:
        writer = open_writer(path, storage, compress)
        for key, value in custom.items():
            writer.set_custom_data(key, value)
        columns = [(add_topic(writer, topic, TOPICS[topic].msgtype, None, TOPICS[topic].hold),
                    recs, raws) for topic, recs, raws in topics]
        write_samples(writer, columns, len(exp.t))
        writer.close()
    except WriterError as exc:
        raise ExperimentError(f'{path}: cannot write the bag ({exc})') from None
    return path


def write_raw_bag(path, messages, storage: str = 'sqlite3', custom_data: dict | None = None,
                  finish: bool = True) -> Path:
    """Write arbitrary messages as a rosbag2 directory (a tool for converters and tests).

    ``messages`` is an iterable of ``(topic, msgtype, record_time_ns, message)``
    with messages built from :func:`typestore` types. ``finish=False``
    stops without closing the bag (no metadata.yaml, no MCAP footer), as a
    recorder that was killed leaves it.
    """
    path = Path(path)
    store = typestore()
    writer = open_writer(path, storage)
    for key, value in (custom_data or {}).items():
        writer.set_custom_data(key, custom_value(value))
    conns = {}
    for topic, msgtype, rec, msg in messages:
        if (topic, msgtype) not in conns:
            conns[topic, msgtype] = writer.add_connection(topic, msgtype, typestore=store)
        writer.write(conns[topic, msgtype], int(rec), store.serialize_cdr(msg, msgtype))
    if finish:
        writer.close()
    else:
        abandon(writer, storage)
    return path
