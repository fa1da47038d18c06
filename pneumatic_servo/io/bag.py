"""rosbag2 (sqlite3 and MCAP) <-> :class:`~pneumatic_servo.experiment.Experiment`.

Reading streams the bag: messages are deserialised one at a time with the
rosbags typestore and only the scalar values of the signals asked for are
kept, so memory grows with the signals kept, not with the bag's size.
Every problem that would make an analysis wrong (a missing, misspelt or
mistyped topic, NaN, stamps that repeat, go backwards or leave gaps, a
truncated or unclosed bag) stops the read with one line that says what and
where and how to fix it; a partial read is never returned as a whole one.

Writing produces a standard rosbag2 directory with the INTERFACES.md topics,
so a generated or simulated experiment looks like a recorded one.
"""
from __future__ import annotations

import difflib
import json
import struct
from array import array
from pathlib import Path

import numpy as np

from ..errors import ExperimentError
from ..experiment import Experiment
from ..files import load_yaml, regular_file
from . import resample, validate
from .topics import (
    CELSIUS_K,
    CIRCUIT_KEY,
    DEFAULT_JOINT,
    FLOAT64,
    FLUID_PRESSURE,
    INFRASTRUCTURE,
    JOINT_STATE,
    KEY_PREFIX,
    REQUIRED,
    SIGNAL_TOPIC,
    SYNTHETIC_KEY,
    TEMPERATURE,
    TOPICS,
)

#: start of the time axis of a written bag when the experiment does not say [ns since epoch]
DEFAULT_START_NS = 1_700_000_000 * 1_000_000_000
#: [s] a sensor message is recorded this long after its measurement time
DEFAULT_LATENCY_S = 2e-4
STORAGES = ('sqlite3', 'mcap')

_TYPESTORE = None


def typestore():
    """The ROS 2 Jazzy message typestore (built once)."""
    global _TYPESTORE
    if _TYPESTORE is None:
        from rosbags.typesys import Stores, get_typestore
        _TYPESTORE = get_typestore(Stores.ROS2_JAZZY)
    return _TYPESTORE


# ------------------------------------------------------------------------------ errors
def _storage_error(where: str, exc: Exception) -> ExperimentError:
    """A one-line reason for an exception raised by the storage layer."""
    text = str(exc).strip().rstrip('.') or type(exc).__name__
    low = text.lower()
    if 'end magic' in low or 'mcap footer' in low or 'summary offset' in low:
        why = ('the MCAP file has no footer: the recording was not closed (recorder killed?); '
               're-record it, or recover the messages with `mcap recover` and `ros2 bag reindex`')
    elif 'truncated record' in low or 'chunk size mismatch' in low or 'checksum' in low:
        why = (f'the MCAP file is truncated or corrupt ({text}); re-record it, or recover '
               'with `mcap recover`')
    elif ('malformed' in low or 'not a database' in low or 'corrupt' in low
          or 'missing tables' in low or 'disk i/o' in low):
        why = (f'the sqlite3 file is truncated or corrupt ({text}); re-record it, or recover '
               'what was written with `sqlite3 .recover` and `ros2 bag reindex`')
    elif 'database files are missing' in low or 'does not exist' in low:
        why = f'a storage file listed in metadata.yaml is missing ({text}); copy the whole bag'
    else:
        why = f'cannot read the bag ({type(exc).__name__}: {text})'
    return ExperimentError(f'{where}: {why}')


def _storage_exceptions() -> tuple[type[Exception], ...]:
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


def _bag_dir(path: Path) -> Path:
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
    _unmerged_wal(path)
    return path


def _unmerged_wal(bag: Path) -> None:
    """Refuse a sqlite3 bag whose write-ahead log still holds data: the writer was not
    closed, and reading the .db3 alone would silently give part of the recording."""
    for wal in bag.glob('*.db3-wal'):
        if wal.stat().st_size > 0:
            raise ExperimentError(
                f'{wal}: the recording was not closed and part of it is still in the '
                f"write-ahead log; merge it with `sqlite3 {wal.with_suffix('')} "
                "'PRAGMA wal_checkpoint(TRUNCATE);'` (or `ros2 bag reindex`), then read again")


def _custom_data(bag: Path) -> dict[str, str]:
    meta = load_yaml(bag / 'metadata.yaml', 'bag metadata file', ExperimentError)
    info = meta.get('rosbag2_bagfile_information') if isinstance(meta, dict) else None
    if not isinstance(info, dict):
        raise ExperimentError(f'{bag}: metadata.yaml has no rosbag2_bagfile_information; '
                              f'rebuild it with `ros2 bag reindex {bag}`')
    custom = info.get('custom_data') or {}
    if not isinstance(custom, dict):
        raise ExperimentError(f'{bag}: custom_data in metadata.yaml is a '
                              f'{type(custom).__name__}, not a mapping of key: value; fix it')
    return {str(k): str(v) for k, v in custom.items()}


# ------------------------------------------------------------------------------ topics
def _relative(name: str) -> str:
    return name.strip('/')


def _match_topics(where: str, names: list[str], namespace: str | None,
                  topic_map: dict[str, str] | None, strict: bool) -> tuple[dict[str, str], str,
                                                                           list[str]]:
    """Map bag topic names to INTERFACES.md topics.

    Returns (bag name -> interface topic, namespace, ignored names).
    """
    remap = {_relative(k): _relative(v) for k, v in (topic_map or {}).items()}
    ns = None if namespace is None else _relative(namespace)
    found: dict[str, str] = {}
    prefixes: dict[str, str] = {}
    unknown = []
    for name in names:
        rel = remap.get(_relative(name), _relative(name))
        if ns:
            if not rel.startswith(ns + '/'):
                continue
            rel = rel[len(ns) + 1:]
        hit = next((t for t in TOPICS if rel == t or rel.endswith('/' + t)), None)
        if hit is None:
            unknown.append(rel)
            continue
        prefix = rel[:-len(hit)].strip('/')
        if hit in found:
            raise ExperimentError(
                f'{where}: {hit} is recorded twice ({found[hit]} and {name}); pass '
                f'namespace=... to choose one rig')
        found[hit] = name
        prefixes[hit] = prefix
    spaces = sorted(set(prefixes.values()))
    if len(spaces) > 1:
        raise ExperimentError(
            f'{where}: topics of several namespaces ({", ".join("/" + s for s in spaces)}); '
            "pass namespace='...' to choose one")
    ignored = []
    for rel in unknown:
        if any(rel == i or rel.endswith('/' + i) for i in INFRASTRUCTURE):
            continue
        base = rel[len(spaces[0]) + 1:] if spaces and spaces[0] and rel.startswith(
            spaces[0] + '/') else rel
        close = difflib.get_close_matches(base, list(TOPICS), n=1, cutoff=0.8)
        if close and close[0] not in found:
            raise ExperimentError(
                f"{where}: unknown topic '{rel}': did you mean '{close[0]}'? Rename it, or "
                f"pass topic_map={{'{rel}': '{close[0]}'}}")
        if strict:
            raise ExperimentError(
                f"{where}: unknown topic '{rel}' (strict mode; INTERFACES.md topics are "
                f"{', '.join(TOPICS)}); pass strict=False to ignore it")
        ignored.append(rel)
    space = spaces[0] if spaces else ''
    if ns:
        space = f'{ns}/{space}'.strip('/')
    return found, space, ignored


def _check_required(where: str, circuit: str, found: dict[str, str], counts: dict[str, int]):
    present = {t for t in found if counts.get(t, 0) > 0}
    for group in REQUIRED[circuit]:
        if not present.intersection(group):
            need = ' or '.join(group)
            have = ', '.join(sorted(present)) or 'none of the INTERFACES.md topics'
            empty = [t for t in group if t in found]
            what = (f'{empty[0]} has no messages' if empty
                    else f'no {need} topic')
            raise ExperimentError(
                f'{where}: {what} (a {circuit} record needs it; found {have}); record '
                f'{need}, or set the circuit if this is not a {circuit} experiment')


# ----------------------------------------------------------------------------- reading
class _Series:
    """Growing stamps [ns] and values of one signal: the only per-message memory kept."""

    __slots__ = ('stamps', 'values')

    def __init__(self):
        self.stamps = array('q')
        self.values = array('d')

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        return (np.frombuffer(self.stamps, dtype=np.int64) if len(self.stamps)
                else np.zeros(0, np.int64),
                np.frombuffer(self.values, dtype=float) if len(self.values)
                else np.zeros(0))


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


def _stamp_ns(msg) -> int:
    s = msg.header.stamp
    return int(s.sec) * 1_000_000_000 + int(s.nanosec)


def _make_handlers(where: str, topic_names: dict[str, str], wanted: set[str], joint: str,
                   time_source: str, series: dict[str, _Series], flags: dict):
    """One function per bag topic that appends a message's values to ``series``."""
    store = typestore()
    deser = store.deserialize_cdr
    header = time_source == 'header'
    picker = _JointPicker(where, joint)
    handlers = {}

    def add(sig):
        if sig in wanted and sig not in series:
            series[sig] = _Series()
        return series.get(sig)

    for topic, bag_name in topic_names.items():
        spec = TOPICS[topic]
        if spec.msgtype == FLOAT64:
            s = add(spec.signals[0])
            if s is None:
                continue

            def h(raw, rec, msgtype, s=s):
                s.stamps.append(rec)
                s.values.append(deser(raw, msgtype).data)
        elif spec.msgtype in (FLUID_PRESSURE, TEMPERATURE):
            s = add(spec.signals[0])
            if s is None:
                continue
            field = 'fluid_pressure' if spec.msgtype == FLUID_PRESSURE else 'temperature'
            offset = CELSIUS_K if spec.msgtype == TEMPERATURE else 0.0

            def h(raw, rec, msgtype, s=s, field=field, offset=offset):
                msg = deser(raw, msgtype)
                s.stamps.append(_stamp_ns(msg) if header else rec)
                s.values.append(getattr(msg, field) + offset)
        else:  # joint_states
            pos, vel, eff = (add(sig) for sig in spec.signals)
            if pos is None and vel is None and eff is None:
                continue

            def h(raw, rec, msgtype, pos=pos, vel=vel, eff=eff):
                msg = deser(raw, msgtype)
                i = picker(msg.name)
                stamp = _stamp_ns(msg) if header else rec
                if len(msg.position) <= i:
                    raise ExperimentError(
                        f'{where}: a joint_states message at {(stamp) * 1e-9:.3f} s has no '
                        'position; the angle is needed: publish position [rad]')
                for s, arr, key in ((pos, msg.position, 'pos'), (vel, msg.velocity, 'vel'),
                                    (eff, msg.effort, 'eff')):
                    if s is None:
                        continue
                    if len(arr) > i:
                        s.stamps.append(stamp)
                        s.values.append(arr[i])
                    else:
                        flags['missing_' + key] = True
        handlers[bag_name] = h
    return handlers, picker


def _read_series(path: Path, circuit: str | None, joint: str, namespace: str | None,
                 time_source: str, start_s: float | None, stop_s: float | None, strict: bool,
                 topic_map: dict | None, signals, required: bool = True
                 ) -> tuple[dict[str, _Series], str, dict]:
    """The bag's measurement series, each on its own stamps, checked message by message:
    (series by signal, circuit, metadata). ``required``: the circuit's topics must be there."""
    from rosbags.rosbag2 import Reader
    bag = _bag_dir(path)
    where = str(path)
    if time_source not in ('header', 'record'):
        raise ExperimentError(f"time_source must be 'header' or 'record', got {time_source!r}")
    custom = _custom_data(bag)
    circuit = circuit or custom.get(CIRCUIT_KEY, 'servo')
    if circuit not in REQUIRED:
        raise ExperimentError(f'{where}: unknown circuit {circuit!r} in custom_data; use one of '
                              f'{", ".join(REQUIRED)}')
    wanted = set(signals) if signals is not None else set(SIGNAL_TOPIC)
    unknown_sig = wanted - set(SIGNAL_TOPIC)
    if unknown_sig:
        raise ExperimentError(f'unknown signal(s) {sorted(unknown_sig)}; choose from '
                              f'{", ".join(SIGNAL_TOPIC)}')
    excs = _storage_exceptions()
    series: dict[str, _Series] = {}
    flags: dict = {}
    try:
        with Reader(bag) as reader:
            conns = reader.connections
            storage = 'mcap' if any(p.suffix == '.mcap' for p in bag.iterdir()) else 'sqlite3'
            names = sorted({c.topic for c in conns})
            found, ns, ignored = _match_topics(where, names, namespace, topic_map, strict)
            by_name = {c.topic: c for c in conns}
            for topic, bag_name in found.items():
                got = by_name[bag_name].msgtype
                if got != TOPICS[topic].msgtype:
                    raise ExperimentError(
                        f'{where}: topic {bag_name} has type {got}; expected '
                        f'{TOPICS[topic].msgtype} (INTERFACES.md)')
            listed = {t: sum(c.msgcount for c in conns if c.topic == found[t]) for t in found}
            if required:
                _check_required(where, circuit, found, listed)
            handlers, picker = _make_handlers(where, found, wanted, joint, time_source,
                                              series, flags)
            t_first = reader.start_time
            window = start_s is not None or stop_s is not None
            lo = None if start_s is None else t_first + int(start_s * 1e9)
            hi = None if stop_s is None else t_first + int(stop_s * 1e9)
            use = [c for c in conns if c.topic in handlers]
            # the index's counts, taken now: the reader clears its connections on close
            expected = {name: sum(c.msgcount for c in conns if c.topic == name)
                        for name in handlers}
            counts = dict.fromkeys(handlers, 0)
            for conn, rec, raw in reader.messages(connections=use, start=lo, stop=hi):
                counts[conn.topic] += 1
                try:
                    handlers[conn.topic](raw, rec, conn.msgtype)
                except ExperimentError:
                    raise
                except Exception as exc:  # a message the typestore cannot decode
                    raise ExperimentError(
                        f'{where}: message {counts[conn.topic]} on {conn.topic} cannot be '
                        f'decoded as {conn.msgtype} ({type(exc).__name__}: {exc}); the bag '
                        'is corrupt or was recorded with another message definition'
                    ) from None
    except ExperimentError:
        raise
    except excs as exc:
        raise _storage_error(where, exc) from None
    if not window:
        for bag_name, n in counts.items():
            validate.check_count(where, bag_name, expected[bag_name], n)
    if flags.get('missing_pos'):
        raise ExperimentError(f'{where}: some joint_states messages lack a position; publish '
                              'position [rad] in every message')
    for key, sig in (('missing_vel', 'velocity_rad_s'), ('missing_eff', 'effort_n_m')):
        if flags.get(key) or (sig in series and not len(series[sig].values)):
            series.pop(sig, None)  # optional and not in every message: drop it
    meta = {'source': str(path), 'storage': storage, 'custom_data': custom,
            'namespace': ns, 'time_source': time_source, 'ignored_topics': ignored,
            'message_counts': {found_t: counts.get(found[found_t], 0) for found_t in found}}
    if picker.name:
        meta['joint'] = picker.name
    if window:  # a part of the bag, by request: say so
        meta['window_s'] = [start_s, stop_s]
    _parse_custom(custom, meta)
    del handlers  # its closures hold the raw series; _assemble releases them one by one
    return series, circuit, meta


def _parse_custom(custom: dict[str, str], meta: dict) -> None:
    """Known custom_data entries as Python values in the experiment's metadata."""
    for key, text in custom.items():
        if not key.startswith(KEY_PREFIX):
            continue
        short = key[len(KEY_PREFIX):]
        if short == 'circuit':
            continue
        try:
            value = json.loads(text)
        except (ValueError, TypeError):
            value = text
        meta[short] = value
    meta['synthetic'] = str(custom.get(SYNTHETIC_KEY, 'false')).lower() == 'true'


def _assemble(where: str, series: dict[str, _Series], circuit: str, name: str,
              rate_hz: float | None, max_gap_s: float | None, meta: dict) -> Experiment:
    """Validate each series and resample all onto one grid.

    Each raw series is released as soon as it is resampled, so the peak
    memory is about the raw series plus one resampled signal.
    """
    for sig in [k for k, s in series.items() if not len(s.values)]:
        del series[sig]  # in place: the caller's dict must not keep the raw samples alive
    if not series:
        raise ExperimentError(f'{where}: none of the requested signals has any message')
    t_ref = min(int(s.stamps[0]) for s in series.values())
    by_topic: dict[str, np.ndarray] = {}
    for sig, s in series.items():
        stamps, values = s.arrays()
        topic = SIGNAL_TOPIC[sig]
        validate.check_finite(where, f'{topic} ({sig})', stamps, values, t_ref)
        if topic not in by_topic:
            validate.check_stamps(where, topic, stamps, t_ref, meta['time_source']
                                  if TOPICS[topic].stamped else 'record')
            validate.check_gaps(where, topic, stamps, t_ref, max_gap_s)
            by_topic[topic] = stamps
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
        Time sensor messages by ``header.stamp`` (INTERFACES.md) or by record time.
    max_gap_s : float, optional [s]
        Longest stamp interval accepted (default: 20 median intervals, >= 20 ms).
    start_s, stop_s : float, optional [s]
        Read only this window (record time after the bag's first message).
    strict : bool
        Treat any topic outside INTERFACES.md (and ROS infrastructure) as an error.
    topic_map : dict, optional
        Bag topic name -> INTERFACES.md topic, for bags recorded under other names.
    signals : iterable of str, optional
        Experiment signals to keep (default all recorded); fewer signals, less memory.
    name : str, optional
        Experiment name (default the bag directory's name).
    """
    path = Path(path)
    series, circuit, meta = _read_series(path, circuit, joint, namespace, time_source, start_s,
                                         stop_s, strict, topic_map, signals)
    return _assemble(str(path), series, circuit, name or _bag_dir(path).name, rate_hz,
                     max_gap_s, meta)


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
    series, _, meta = _read_series(path, None, joint, namespace, time_source, None, None,
                                   False, None, None, required=False)
    out = {}
    for sig, raw in series.items():
        stamps, values = raw.arrays()
        if not len(values):
            continue
        topic = SIGNAL_TOPIC[sig]
        validate.check_finite(where, f'{topic} ({sig})', stamps, values, int(stamps[0]))
        validate.check_stamps(where, topic, stamps, int(stamps[0]), time_source
                              if TOPICS[topic].stamped else 'record')
        out[sig] = (stamps, values)
    if not out:
        raise ExperimentError(f'{where}: no measurement topic has any message; record '
                              'joint_states and the pressures')
    return out, meta


# ----------------------------------------------------------------------------- writing
def _custom_value(value) -> str:
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return 'true' if value else 'false'
    return json.dumps(value, sort_keys=True, default=float)


def _messages(exp: Experiment, joint: str, start_ns: int, latency_ns: int):
    """Per topic: (msgtype, list of (record time, message)) built lazily per sample."""
    store = typestore()
    T = store.types
    Time, Header = T['builtin_interfaces/msg/Time'], T['std_msgs/msg/Header']
    F64, FP, TMP, JS = (T[FLOAT64], T[FLUID_PRESSURE], T[TEMPERATURE], T[JOINT_STATE])
    sig = exp.signals
    stamps = start_ns + np.round(exp.t * 1e9).astype(np.int64)

    def header(ns):
        return Header(stamp=Time(sec=int(ns // 1_000_000_000), nanosec=int(ns % 1_000_000_000)),
                      frame_id='')

    topics = []
    if 'command_v' in sig:
        v = sig['command_v']
        topics.append(('valve/command', FLOAT64, lambda k, v=v: (int(stamps[k]),
                                                                  F64(data=float(v[k])))))
    if 'setpoint_rad' in sig:
        v = sig['setpoint_rad']
        topics.append(('setpoint', FLOAT64, lambda k, v=v: (int(stamps[k]),
                                                             F64(data=float(v[k])))))
    if 'angle_rad' in sig:
        pos = sig['angle_rad']
        vel = sig.get('velocity_rad_s')
        eff = sig.get('effort_n_m')
        empty = np.zeros(0)

        def js(k):
            return (int(stamps[k]) + latency_ns, JS(
                header=header(int(stamps[k])), name=[joint], position=np.array([pos[k]]),
                velocity=np.array([vel[k]]) if vel is not None else empty,
                effort=np.array([eff[k]]) if eff is not None else empty))
        topics.append(('joint_states', JOINT_STATE, js))
    for topic, key in (('chamber_a/pressure', 'p_a_pa'), ('chamber_b/pressure', 'p_b_pa'),
                       ('supply/pressure', 'supply_pa')):
        if key in sig:
            v = sig[key]
            topics.append((topic, FLUID_PRESSURE, lambda k, v=v: (
                int(stamps[k]) + latency_ns,
                FP(header=header(int(stamps[k])), fluid_pressure=float(v[k]), variance=0.0))))
    for topic, key in (('chamber_a/temperature', 't_a_k'), ('chamber_b/temperature', 't_b_k')):
        if key in sig:
            v = sig[key]
            topics.append((topic, TEMPERATURE, lambda k, v=v: (
                int(stamps[k]) + latency_ns,
                TMP(header=header(int(stamps[k])), temperature=float(v[k]) - CELSIUS_K,
                    variance=0.0))))
    return topics


#: rosbag2 metadata version written: what ROS 2 Jazzy's recorder writes (type hashes, QoS)
BAG_VERSION = 9


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


#: [ns] the latest stamp a ROS 2 ``builtin_interfaces/Time`` (int32 seconds) can hold
MAX_STAMP_NS = (2**31 - 1) * 10**9


def write_experiment_bag(exp: Experiment, path, storage: str = 'sqlite3',
                         metadata: dict | None = None, *, joint: str = DEFAULT_JOINT,
                         start_time_ns: int | None = None,
                         latency_s: float = DEFAULT_LATENCY_S, compress: bool = False) -> Path:
    """Write ``exp`` as a rosbag2 directory with the INTERFACES.md topics.

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
        ``pneumatic_servo.circuit`` is always written from ``exp.circuit``.
    joint : str
        Joint name in ``joint_states``.
    start_time_ns : int, optional [ns since epoch]
        Stamp of t = 0 (default ``exp.metadata['start_time_ns']`` or a fixed epoch).
    latency_s : float [s]
        Record time of sensor messages after their header stamp.
    compress : bool
        zstd chunk compression (MCAP only).
    """
    from rosbags.rosbag2 import (
        CompressionFormat,
        CompressionMode,
        StoragePlugin,
        Writer,
        WriterError,
    )
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
    store = typestore()
    plugin = StoragePlugin.MCAP if storage == 'mcap' else StoragePlugin.SQLITE3
    writer = Writer(path, version=BAG_VERSION, storage_plugin=plugin)
    if compress and storage == 'mcap':
        writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    custom = {CIRCUIT_KEY: exp.circuit}
    for key, value in (metadata or {}).items():
        custom[key if '.' in key else KEY_PREFIX + key] = _custom_value(value)
    custom[CIRCUIT_KEY] = exp.circuit
    try:
        writer.open()
        for key, value in custom.items():
            writer.set_custom_data(key, value)
        conns = [(add_topic(writer, topic, msgtype, store, TOPICS[topic].hold), msgtype, make)
                 for topic, msgtype, make in topics]
        ser = store.serialize_cdr
        for k in range(len(exp.t)):
            for conn, msgtype, make in conns:
                rec, msg = make(k)
                writer.write(conn, rec, ser(msg, msgtype))
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
    from rosbags.rosbag2 import StoragePlugin, Writer
    path = Path(path)
    store = typestore()
    plugin = StoragePlugin.MCAP if storage == 'mcap' else StoragePlugin.SQLITE3
    writer = Writer(path, version=BAG_VERSION, storage_plugin=plugin)
    writer.open()
    for key, value in (custom_data or {}).items():
        writer.set_custom_data(key, _custom_value(value))
    conns = {}
    for topic, msgtype, rec, msg in messages:
        if (topic, msgtype) not in conns:
            conns[topic, msgtype] = writer.add_connection(topic, msgtype, typestore=store)
        writer.write(conns[topic, msgtype], int(rec), store.serialize_cdr(msg, msgtype))
    if finish:
        writer.close()
    elif storage == 'mcap':
        writer.abort()  # no summary, no footer
    else:
        # a killed recorder leaves its committed rows but no metadata.yaml
        writer.storage.close(BAG_VERSION, '')
        writer.storage = None
    return path
