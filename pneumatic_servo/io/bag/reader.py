"""A rosbag2 directory (sqlite3 or MCAP) read into a validated, resampled Experiment
(:func:`read_bag`), or into its measurements on their own stamps (:func:`read_series`).

Reading streams the bag: the messages of each topic are gathered in batches of
:data:`BATCH` and decoded a batch at a time by the topic's codec (numpy, at fixed
offsets; rosbags' deserialiser for any message off the common layout), and only the values
of the signals asked for are kept, so memory grows with the signals kept, not with the
bag's size. Every problem that would make an analysis wrong (a missing, misspelt or
mistyped topic, NaN, stamps that repeat, go backwards or leave gaps, a truncated or
unclosed bag) stops the read with one line that says what and where and how to fix it; a
partial read is never returned as a whole one.
"""
from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import ExperimentError
from ...experiment import Experiment
from .. import resample, validate
from ..codecs import DecodeError, codec_of, typestore
from ..topics import CIRCUIT_KEY, DEFAULT_JOINT, REQUIRED, SIGNAL_TOPIC, TOPICS, Topic
from . import errors, metadata, storage

#: messages of one topic decoded together (bounds the undecoded bytes held at once)
BATCH = 4096


@dataclass(frozen=True)
class ReadOptions:
    """What to read of a bag; the keywords of :func:`read_bag` that choose messages.
    ``required``: the circuit's topics must be there (a replay's raw series needs none).
    Immutable and hashable: ``topic_map`` is kept as (bag name, topic) pairs, ``signals``
    as a tuple."""

    circuit: str | None = None
    joint: str = DEFAULT_JOINT
    namespace: str | None = None
    time_source: str = 'header'
    start_s: float | None = None
    stop_s: float | None = None
    strict: bool = False
    topic_map: tuple[tuple[str, str], ...] | None = None
    signals: tuple[str, ...] | None = None
    required: bool = True

    def __post_init__(self):
        if self.topic_map is not None and not isinstance(self.topic_map, tuple):
            object.__setattr__(self, 'topic_map', tuple(dict(self.topic_map).items()))
        if self.signals is not None and not isinstance(self.signals, tuple):
            object.__setattr__(self, 'signals', tuple(self.signals))

    @property
    def window(self) -> bool:
        """Only a part of the bag is asked for."""
        return self.start_s is not None or self.stop_s is not None

    def check(self) -> None:
        if self.time_source not in ('header', 'record'):
            raise ExperimentError("time_source must be 'header' or 'record', got "
                                  f'{self.time_source!r}')

    def wanted(self) -> set[str]:
        """The signals to keep."""
        wanted = set(self.signals) if self.signals is not None else set(SIGNAL_TOPIC)
        unknown = wanted - set(SIGNAL_TOPIC)
        if unknown:
            raise ExperimentError(f'unknown signal(s) {sorted(unknown)}; choose from '
                                  f'{", ".join(SIGNAL_TOPIC)}')
        return wanted


class Series:
    """Stamps [ns] and values of one signal, a batch at a time: the only per-message memory
    kept."""

    __slots__ = ('chunks', 'size')

    def __init__(self):
        self.chunks: list[tuple[np.ndarray, np.ndarray]] = []
        self.size = 0

    def __len__(self) -> int:
        return self.size

    def extend(self, stamps: np.ndarray, values: np.ndarray) -> None:
        if len(values):
            self.chunks.append((stamps, values))
            self.size += len(values)

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """(stamps [ns], values), joined into one chunk."""
        if not self.chunks:
            return np.zeros(0, np.int64), np.zeros(0)
        if len(self.chunks) > 1:
            self.chunks = [(np.concatenate([c[0] for c in self.chunks]),
                            np.concatenate([c[1] for c in self.chunks]))]
        return self.chunks[0]


class _JointPicker:
    """Finds the actuator joint in each JointState message."""

    def __init__(self, where: str, joint: str):
        self.where, self.joint, self.index, self.name = where, joint, None, None

    def __call__(self, names) -> int:
        idx = self.index
        if idx is not None and idx < len(names) and names[idx] == self.name:
            return idx
        if self.joint in names:
            idx = list(names).index(self.joint)
        elif len(names) == 1 and self.joint == DEFAULT_JOINT:
            idx = 0
        elif not names:
            idx = 0
        else:
            raise ExperimentError(
                f"{self.where}: joint_states has no joint '{self.joint}' (joints: "
                f"{', '.join(names)}); pass joint='<name>'")
        self.index, self.name = idx, (names[idx] if names else '')
        return idx


class _Topic:
    """One bag topic being read: its docs/interfaces.md spec, the series its fields feed, and the
    messages not decoded yet."""

    def __init__(self, name: str, spec: Topic, outputs: list[tuple[str, Series | None]]):
        self.name, self.spec, self.outputs = name, spec, outputs
        self.recs: list[int] = []
        self.raws: list = []
        self.count = 0  # messages decoded


@dataclass
class _Read:
    """What :func:`_read` gives: the raw series by signal, and about the bag."""

    series: dict[str, Series]
    circuit: str
    meta: dict
    bag: Path


@contextmanager
def _reading(where: str, bag: Path):
    """rosbags' reader of the checked ``bag``; a failure of the storage layer, inside or
    while opening, becomes its one-line :class:`ExperimentError`."""
    try:
        with storage.open_reader(bag) as reader:
            yield reader
    except ExperimentError:
        raise
    except errors.storage_exceptions() as exc:
        raise errors.storage_error(where, exc) from None


def _read(path: Path, opts: ReadOptions) -> _Read:
    """The bag's measurement series, each on its own stamps, checked batch by batch."""
    bag = storage.bag_dir(path)
    where = str(path)
    opts.check()
    custom = metadata.custom_data(bag)
    circuit = opts.circuit or custom.get(CIRCUIT_KEY, 'servo')
    if circuit not in REQUIRED:
        raise ExperimentError(f'{where}: unknown circuit {circuit!r} in custom_data; use one of '
                              f'{", ".join(REQUIRED)}')
    wanted = opts.wanted()
    series: dict[str, Series] = {}
    picker = _JointPicker(where, opts.joint)
    missing: set[str] = set()
    with _reading(where, bag) as reader:
        conns = reader.connections
        found, ns, ignored = metadata.match_topics(
            where, sorted({c.topic for c in conns}), opts.namespace, opts.topic_map,
            opts.strict)
        metadata.check_types(where, found, conns)
        if opts.required:
            listed = {t: sum(c.msgcount for c in conns if c.topic == found[t])
                      for t in found}
            metadata.check_required(where, circuit, found, listed)
        topics = {}
        for topic, name in found.items():
            spec = TOPICS[topic]
            outputs = []
            for sig, field in zip(spec.signals, spec.fields):
                if sig in wanted and sig not in series:
                    series[sig] = Series()
                outputs.append((field, series.get(sig)))
            if any(s is not None for _, s in outputs):
                topics[name] = _Topic(name, spec, outputs)
        # the index's counts, taken now: the reader clears its connections on close
        expected = {name: sum(c.msgcount for c in conns if c.topic == name)
                    for name in topics}
        _collect(where, reader, topics, opts, picker, missing)
    if not opts.window:
        for name, t in topics.items():
            validate.check_count(where, name, expected[name], t.count)
    for field, sig in (('velocity', 'velocity_rad_s'), ('effort', 'effort_n_m')):
        if field in missing or (sig in series and not len(series[sig])):
            series.pop(sig, None)  # optional and not in every message: drop it
    counts = {name: t.count for name, t in topics.items()}
    meta = {'source': str(path), 'storage': storage.storage_of(bag), 'custom_data': custom,
            'namespace': ns, 'time_source': opts.time_source, 'ignored_topics': ignored,
            'message_counts': {t: counts.get(found[t], 0) for t in found}}
    if picker.name:
        meta['joint'] = picker.name
    if opts.window:  # a part of the bag, by request: say so
        meta['window_s'] = [opts.start_s, opts.stop_s]
    metadata.parse_custom(custom, meta)
    return _Read(series, circuit, meta, bag)


def _collect(where: str, reader, topics: dict[str, _Topic], opts: ReadOptions, picker,
             missing: set[str]) -> None:
    """Stream the messages of ``topics`` (in the window asked for) into their series."""
    t_first = reader.start_time
    lo = None if opts.start_s is None else t_first + int(opts.start_s * 1e9)
    hi = None if opts.stop_s is None else t_first + int(opts.stop_s * 1e9)
    header = opts.time_source == 'header'
    use = [c for c in reader.connections if c.topic in topics]
    for conn, rec, raw in reader.messages(connections=use, start=lo, stop=hi):
        t = topics[conn.topic]
        t.recs.append(rec)
        t.raws.append(raw)
        if len(t.raws) >= BATCH:
            _decode(where, t, header, picker, missing)
    for t in topics.values():
        _decode(where, t, header, picker, missing)


def _decode(where: str, t: _Topic, header: bool, picker, missing: set[str]) -> None:
    """Decode the pending messages of ``t`` and add their values to its series."""
    if not t.raws:
        return
    try:
        got = codec_of(t.spec).decode(t.raws, picker)
    except DecodeError as exc:
        raise errors.decode_error(where, t.count + exc.index + 1, t.name, t.spec.msgtype,
                                  exc.cause) from None
    stamps = (got.stamp_ns if header and got.stamp_ns is not None
              else np.array(t.recs, dtype=np.int64))
    has_position = got.present.get('position')
    if has_position is not None and not has_position.all():
        k = int(np.argmin(has_position))
        raise ExperimentError(
            f'{where}: a joint_states message at {stamps[k] * 1e-9:.3f} s has no '
            'position; the angle is needed: publish position [rad]')
    for field, s in t.outputs:
        if s is None:
            continue
        values, ok = got.fields[field], got.present.get(field)
        if t.spec.offset:
            values = values + t.spec.offset
        if ok is not None and not ok.all():
            missing.add(field)
            s.extend(stamps[ok], values[ok])
        else:
            s.extend(stamps, values)
    t.count += len(t.raws)
    t.recs, t.raws = [], []


def _check(where: str, series: dict[str, Series], time_source: str, t_ref: int | None,
           max_gap_s: float | None = None, gaps: bool = True) -> dict[str, np.ndarray]:
    """Every series fit for use: finite values, stamps that only go forward and, where
    samples will be resampled (``gaps``), no gap and no repeated stamp (without resampling,
    record stamps may repeat: :func:`~pneumatic_servo.io.validate.check_stamps`); times in the
    messages from ``t_ref`` [ns] (None: each series' first stamp). Returns the stamps of each
    topic."""
    by_topic: dict[str, np.ndarray] = {}
    for sig, s in series.items():
        stamps, values = s.arrays()
        topic = SIGNAL_TOPIC[sig]
        t0 = int(stamps[0]) if t_ref is None else t_ref
        validate.check_finite(where, f'{topic} ({sig})', stamps, values, t0)
        if topic not in by_topic:
            validate.check_stamps(where, topic, stamps, t0, time_source
                                  if TOPICS[topic].stamped else 'record', ties=not gaps)
            if gaps:
                validate.check_gaps(where, topic, stamps, t0, max_gap_s)
            by_topic[topic] = stamps
    return by_topic


def _assemble(where: str, series: dict[str, Series], circuit: str, name: str,
              rate_hz: float | None, max_gap_s: float | None, meta: dict) -> Experiment:
    """Validate each series and resample all onto one grid.

    Each raw series is released as soon as it is resampled, so the peak
    memory is about the raw series plus one resampled signal.
    """
    for sig in [k for k, s in series.items() if not len(s)]:
        del series[sig]  # in place: the caller's dict must not keep the raw samples alive
    if not series:
        raise ExperimentError(f'{where}: none of the requested signals has any message')
    t_ref = min(int(s.arrays()[0][0]) for s in series.values())
    by_topic = _check(where, series, meta['time_source'], t_ref, max_gap_s)
    measured = [t for t in by_topic if not TOPICS[t].hold] or list(by_topic)
    periods = {t: validate.median_period_ns(by_topic[t]) for t in measured}
    period = resample.grid_period_ns(list(periods.values()), rate_hz)
    # the grid falls on the samples of the fastest measurement, which is then not interpolated
    ref = min(periods, key=lambda t: periods[t] if np.isfinite(periods[t]) else np.inf)
    spans = {t: (int(s[0]), int(s[-1])) for t, s in by_topic.items()}
    # a command held from its first sample is valid up to half a period before it
    spans = {t: ((a - period // 2, b + period) if TOPICS[t].hold else (a, b))
             for t, (a, b) in spans.items()}
    start, stop = resample.common_span(spans, where)
    start += (int(by_topic[ref][0]) - start) % period
    del by_topic
    grid = resample.make_grid(start, stop, period)
    if len(grid) < 2:
        raise ExperimentError(f'{where}: the signals overlap for less than two samples')
    signals = {}
    for sig in list(series):
        stamps, values = series[sig].arrays()
        if TOPICS[SIGNAL_TOPIC[sig]].hold:
            out = resample.hold(stamps, values, grid, period // 2)
        else:
            out = resample.interpolate(stamps, values, grid)
        signals[sig] = out
        del stamps, values
        del series[sig]  # release the raw samples before the next signal
    meta.update({'start_time_ns': int(grid[0]), 'rate_hz': 1e9 / period,
                 'trimmed_start_s': (int(grid[0]) - t_ref) * 1e-9})
    return Experiment((grid - grid[0]) * 1e-9, signals, circuit, name, False, meta)


def read_bag(path, *, circuit: str | None = None, joint: str = DEFAULT_JOINT,
             namespace: str | None = None, rate_hz: float | None = None,
             time_source: str = 'header', max_gap_s: float | None = None,
             start_s: float | None = None, stop_s: float | None = None,
             strict: bool = False, topic_map: dict | None = None, signals=None,
             name: str | None = None) -> Experiment:
    """Read a rosbag2 directory (sqlite3 or MCAP) into a validated, resampled Experiment.

    Parameters
    ----------
    path : str or Path
        The bag directory (or a storage file inside it).
    circuit : str, optional
        Overrides ``pneumatic_servo.circuit`` of the bag's custom_data
        (default there: 'servo').
    joint : str
        Name of the actuator joint in ``joint_states``.
    namespace : str, optional
        Read the rig under this namespace (needed when several are recorded).
    rate_hz : float, optional [Hz]
        Grid rate; default the fastest measurement topic's median rate.
    time_source : {'header', 'record'}
        Time sensor messages by ``header.stamp`` (docs/interfaces.md) or by record time.
    max_gap_s : float, optional [s]
        Longest stamp interval accepted (default: 20 median intervals, >= 20 ms).
    start_s, stop_s : float, optional [s]
        Read only this window (record time after the bag's first message).
    strict : bool
        Treat any topic outside docs/interfaces.md (and ROS infrastructure) as an error.
    topic_map : dict, optional
        Bag topic name -> docs/interfaces.md topic, for bags recorded under other names.
    signals : iterable of str, optional
        Experiment signals to keep (default all recorded); fewer signals, less memory.
    name : str, optional
        Experiment name (default the bag directory's name).
    """
    path = Path(path)
    opts = ReadOptions(circuit, joint, namespace, time_source, start_s, stop_s, strict,
                       topic_map, signals)
    got = _read(path, opts)
    return _assemble(str(path), got.series, got.circuit, name or got.bag.name, rate_hz,
                     max_gap_s, got.meta)


def read_series(path, *, joint: str = DEFAULT_JOINT, namespace: str | None = None,
                time_source: str = 'header'
                ) -> tuple[dict[str, tuple[np.ndarray, np.ndarray]], dict]:
    """Every measurement of a bag on its own stamps, not resampled: ({signal: (stamps [ns
    since epoch], values [SI])}, metadata). The same checks as :func:`read_bag` (storage,
    types, counts, finite values, stamps), but no topic is required and gaps are kept (a
    gap matters where samples are interpolated onto a grid, and nothing is here): what a
    replay of measurements needs, whatever the circuit."""
    path = Path(path)
    where = str(path)
    got = _read(path, ReadOptions(joint=joint, namespace=namespace, time_source=time_source,
                                  required=False))
    series = {sig: s for sig, s in got.series.items() if len(s)}
    _check(where, series, time_source, None, gaps=False)
    out = {sig: s.arrays() for sig, s in series.items()}
    if not out:
        raise ExperimentError(f'{where}: no measurement topic has any message; record '
                              'joint_states and the pressures')
    return out, got.meta


def read_messages(path, topics) -> list[tuple[str, int, object]]:
    """Every message on ``topics`` (full names) in record order, as (topic, record stamp
    [ns], message), deserialised with the package's typestore: for topics outside the
    interface (a monitor's ``/diagnostics`` and ``/monitor/effects``), with the same
    storage checks and one-line errors as :func:`read_bag`."""
    path = Path(path)
    where = str(path)
    bag = storage.bag_dir(path)
    store = typestore()
    out, wanted = [], set(topics)
    with _reading(where, bag) as reader:
        use = [c for c in reader.connections if c.topic in wanted]
        for conn, rec, raw in reader.messages(connections=use):
            try:
                msg = store.deserialize_cdr(raw, conn.msgtype)
            except Exception as exc:  # noqa: BLE001 - any decoder failure: corrupt data
                raise errors.decode_error(where, len(out) + 1, conn.topic, conn.msgtype,
                                          exc) from None
            out.append((conn.topic, rec, msg))
    return out
