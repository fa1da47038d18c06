"""What a bag says about itself: its custom data (metadata.yaml), and its topics matched to
the docs/interfaces.md vocabulary (namespaces, remaps, misspellings, the topics a circuit needs).
"""
from __future__ import annotations

import difflib
import json
from pathlib import Path

from ...errors import ExperimentError
from ...files import load_yaml
from ..topics import (
    DERIVED_NAMESPACES,
    INFRASTRUCTURE,
    KEY_PREFIX,
    REQUIRED,
    SYNTHETIC_KEY,
    TOPICS,
)


# -------------------------------------------------------------------------- custom data
def custom_data(bag: Path) -> dict[str, str]:
    """The ``custom_data`` of a bag's metadata.yaml, keys and values as text."""
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


def parse_custom(custom: dict[str, str], meta: dict) -> None:
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


def custom_value(value) -> str:
    """A custom_data value as written: text as it is, booleans as YAML's, the rest JSON."""
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return 'true' if value else 'false'
    return json.dumps(value, sort_keys=True, default=float)


# ------------------------------------------------------------------------------- topics
def relative(name: str) -> str:
    return name.strip('/')


def match_topics(where: str, names: list[str], namespace: str | None, topic_map, strict: bool
                 ) -> tuple[dict[str, str], str, list[str]]:
    """Map bag topic names to docs/interfaces.md topics (``topic_map``: bag name -> topic, a
    mapping or pairs).

    Returns (interface topic -> bag name, namespace, ignored names).
    """
    remap = {relative(k): relative(v) for k, v in dict(topic_map or ()).items()}
    ns = None if namespace is None else relative(namespace)
    found: dict[str, str] = {}
    prefixes: dict[str, str] = {}
    unknown = []
    for name in names:
        rel = remap.get(relative(name), relative(name))
        if ns:
            if not rel.startswith(ns + '/'):
                continue
            rel = rel[len(ns) + 1:]
        if DERIVED_NAMESPACES.intersection(rel.split('/')[:-1]):
            continue  # a monitor's predictions and statistics, not measurements
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
                f"{where}: unknown topic '{rel}' (strict mode; docs/interfaces.md topics are "
                f"{', '.join(TOPICS)}); pass strict=False to ignore it")
        ignored.append(rel)
    space = spaces[0] if spaces else ''
    if ns:
        space = f'{ns}/{space}'.strip('/')
    return found, space, ignored


def check_types(where: str, found: dict[str, str], connections) -> None:
    """Refuse a matched topic recorded with another message type than docs/interfaces.md's."""
    for topic, name in found.items():
        for conn in (c for c in connections if c.topic == name):
            if conn.msgtype != TOPICS[topic].msgtype:
                raise ExperimentError(
                    f'{where}: topic {name} has type {conn.msgtype}; expected '
                    f'{TOPICS[topic].msgtype} (docs/interfaces.md)')


def check_required(where: str, circuit: str, found: dict[str, str],
                   counts: dict[str, int]) -> None:
    """Refuse a record without a topic its circuit needs (or with it empty)."""
    present = {t for t in found if counts.get(t, 0) > 0}
    for group in REQUIRED[circuit]:
        if not present.intersection(group):
            need = ' or '.join(group)
            have = ', '.join(sorted(present)) or 'none of the docs/interfaces.md topics'
            empty = [t for t in group if t in found]
            what = (f'{empty[0]} has no messages' if empty
                    else f'no {need} topic')
            raise ExperimentError(
                f'{where}: {what} (a {circuit} record needs it; found {have}); record '
                f'{need}, or set the circuit if this is not a {circuit} experiment')
