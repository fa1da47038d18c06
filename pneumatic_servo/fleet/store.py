"""Stream fleet rows to disk as they finish, so a killed run loses nothing finished.

One JSON object per line, flushed and synced as each recording finishes. A rerun reads
the file and skips the recordings whose key (content, config and options) is already
there. A line cut short by a kill is ignored when read and dropped when writing resumes.
"""
from __future__ import annotations

import json
import os
from pathlib import Path

from ..jsonable import dumps
from .row import Row


class RowStore:
    """Append-only JSON-lines file of fleet rows (the JSON form of :class:`~.row.Row`),
    keyed by their ``key``."""

    def __init__(self, path):
        self.path = Path(path)
        self.rows: dict[str, Row] = {}
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
                if not isinstance(row, dict) or 'key' not in row or 'path' not in row:
                    break  # not a row: the store ends before it
                self.rows[row['key']] = Row.from_json(row)
                good += len(line)
        if good != self.path.stat().st_size:
            with self.path.open('r+b') as f:
                f.truncate(good)

    def __contains__(self, key: str) -> bool:
        return key in self.rows

    def add(self, row: Row) -> None:
        """Append ``row`` and make it durable before returning."""
        self.path.parent.mkdir(parents=True, exist_ok=True)
        with self.path.open('a', encoding='utf-8') as f:
            f.write(dumps(row.to_json(), sort_keys=True) + '\n')
            f.flush()
            os.fsync(f.fileno())
        self.rows[row.key] = row

