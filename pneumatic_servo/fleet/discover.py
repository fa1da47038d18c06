"""Find the recordings of a fleet: a directory tree, a glob, or a manifest CSV.

A recording is a rosbag2 directory (it holds ``metadata.yaml``) or a static ``.csv``
table. Its rig is named in the manifest, else in the bag's custom data
(``pneumatic_servo.rig``, read by the task), else by its parent directory.
"""
from __future__ import annotations

import csv
import glob
from dataclasses import dataclass
from pathlib import Path

from ..errors import ConfigError


@dataclass(frozen=True)
class Recording:
    """One recording to check: its path and the rig it came from (None: ask the bag)."""

    path: str
    rig: str | None = None


def _is_bag(path: Path) -> bool:
    return path.is_dir() and (path / 'metadata.yaml').is_file()


def _in_tree(root: Path) -> list[Recording]:
    found = []
    for meta in sorted(root.rglob('metadata.yaml')):
        found.append(Recording(str(meta.parent)))
    for table in sorted(root.rglob('*.csv')):
        if not any(_is_bag(parent) for parent in table.parents):
            found.append(Recording(str(table)))
    return found


def _manifest(path: Path) -> list[Recording]:
    """Rows of a CSV with a ``path`` column (relative to the manifest) and an optional ``rig``."""
    with path.open(newline='', encoding='utf-8') as f:
        rows = list(csv.DictReader(f))
    if not rows or 'path' not in rows[0]:
        raise ConfigError(f'{path}: a fleet manifest needs a header with a path column (and '
                          'optionally rig), and one row per recording')
    out = []
    for i, row in enumerate(rows, start=2):
        if not (row.get('path') or '').strip():
            raise ConfigError(f'{path}:{i}: empty path; name a bag directory or a CSV table')
        rec = (path.parent / row['path'].strip()).resolve()
        out.append(Recording(str(rec), (row.get('rig') or '').strip() or None))
    return out


def find_recordings(sources) -> list[Recording]:
    """Every recording under ``sources``: directories (searched recursively), globs, or
    manifest CSVs (a ``.csv`` whose header has a ``path`` column). Each appears once."""
    out: dict[str, Recording] = {}
    for source in sources:
        path = Path(source)
        if path.is_dir() and not _is_bag(path):
            found = _in_tree(path)
        elif _is_bag(path):
            found = [Recording(str(path))]
        elif path.is_file() and path.suffix.lower() == '.csv' and _is_manifest(path):
            found = _manifest(path)
        elif path.is_file():
            found = [Recording(str(path))]
        else:
            found = [Recording(p) for p in sorted(glob.glob(str(source)))
                     if _is_bag(Path(p)) or Path(p).suffix.lower() == '.csv']
            if not found:
                raise ConfigError(f'{source}: no bag directory, CSV table or manifest there; '
                                  'name a directory tree, a glob or a manifest CSV')
        for rec in found:
            out.setdefault(str(Path(rec.path).resolve()), rec)
    if not out:
        raise ConfigError('no recordings found; a fleet needs bag directories (with '
                          'metadata.yaml) or static CSV tables')
    return list(out.values())


def _is_manifest(path: Path) -> bool:
    try:
        with path.open(encoding='utf-8') as f:
            header = f.readline()
    except (OSError, UnicodeError):
        return False
    return 'path' in [h.strip() for h in header.split(',')]


def rig_of(recording: Recording, metadata: dict) -> str:
    """The rig: the manifest's, else the bag's ``pneumatic_servo.rig``, else the parent
    directory's name."""
    if recording.rig:
        return recording.rig
    rig = metadata.get('rig')
    if rig not in (None, ''):
        return str(rig)
    return Path(recording.path).resolve().parent.name
