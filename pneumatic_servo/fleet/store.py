"""Stream fleet rows to disk as they finish, so a killed run loses nothing finished.

One JSON object per line, flushed and synced as each recording finishes. A rerun reads
the file and skips the recordings whose key (content, config and options) is already
there. A line cut short by a kill is ignored when read and dropped when writing resumes.
"""
from __future__ import annotations

import json
import os
from pathlib import Path


class RowStore:
    """Append-only JSON-lines file of fleet rows, keyed by ``row['key']``."""

    def __init__(self, path):
        self.path = Path(path)
        self.rows: dict[str, dict] = {}
        if self.path.exists():
            self._read()

    def _read(self) -> None:
        good = 0
        with self.path.open('rb') as f:
            for line in f:
                try:
                    row = json.loads(line)
                except ValueError:
                    break  # the line a killed run left half written, and anything after it
                if not isinstance(row, dict) or 'key' not in row:
                    break
                self.rows[row['key']] = row
                good += len(line)
        if good != self.path.stat().st_size:
            with self.path.open('r+b') as f:
                f.truncate(good)

    def __contains__(self, key: str) -> bool:
        return key in self.rows

    def add(self, row: dict) -> None:
        """Append ``row`` and make it durable before returning."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        with self.path.open('a', encoding='utf-8') as f:
            f.write(json.dumps(row, sort_keys=True, default=_plain) + '\n')
            f.flush()
            os.fsync(f.fileno())
        self.rows[row['key']] = row


def _plain(value):
    """numpy scalars and the like as plain JSON values."""
    if hasattr(value, 'item'):
        return value.item()
    return str(value)
