"""The fleet rows as one flat table for pandas users: Parquet (with pyarrow) or CSV.

One row per recording; nested results become columns: ``<channel>_rmse`` for each
channel's open-loop (or chosen mode's) RMS error [SI], ``passed``, ``diagnosis_status``
(with ``--diagnose``), and ``<key>`` and ``<key>_stderr`` for each tracked parameter [SI].
"""
from __future__ import annotations

import csv
from pathlib import Path

from ..errors import ConfigError
from .row import Row

FIXED = ('path', 'rig', 'start_time', 'status', 'error', 'passed', 'diagnosis_status',
         'verdict', 'seconds')


def flat(rows: list[Row]) -> tuple[list[str], list[dict]]:
    """(column names, one flat dict per row)."""
    out, extra = [], {}
    for row in rows:
        r = {'path': row.path, 'rig': row.rig, 'start_time': row.start_time,
             'status': row.status, 'error': row.error, 'passed': row.passed,
             'diagnosis_status': (row.diagnosis or {}).get('status'), 'verdict': row.verdict,
             'seconds': row.seconds}
        for ch, m in row.channels.items():
            r[f'{ch}_rmse'] = m.get('rmse')
        for key, est in row.params.items():
            r[key] = est.get('value')
            r[f'{key}_stderr'] = est.get('stderr')
        extra.update(dict.fromkeys(k for k in r if k not in FIXED))
        out.append(r)
    return list(FIXED) + sorted(extra), out


def write_table(rows: list[Row], path) -> Path:
    """Write the table as Parquet (``.parquet``) or CSV (``.csv``)."""
    path = Path(path)
    columns, records = flat(rows)
    if path.suffix.lower() == '.parquet':
        import pyarrow as pa
        import pyarrow.parquet as pq
        pq.write_table(pa.table({c: [r.get(c) for r in records] for c in columns}), path)
    elif path.suffix.lower() == '.csv':
        with path.open('w', newline='', encoding='utf-8') as f:
            writer = csv.DictWriter(f, columns)
            writer.writeheader()
            writer.writerows(records)
    else:
        raise ConfigError(f'{path}: the table is written as .parquet or .csv; name one')
    return path
