"""Static experiments (steady-state test tables) as CSV, docs/interfaces.md 'Static experiments'.

Columns: ``circuit`` (``closed_port``, ``flow``, or ``blocked``: the pistons held,
both chambers settled at a held voltage), ``voltage_v``, ``supply_pa``
(absolute), and whichever measurements exist: ``p_a_pa``, ``p_b_pa`` (absolute),
``m4_kg_s``, ``m5_kg_s``, ``t_s_k``. Each row is one steady operating point.
Metadata (how the table was made, whether it is synthetic) lives in an optional
sidecar ``<name>.meta.yaml``, so that the CSV itself stays a plain table any
tool reads.
"""
from __future__ import annotations

import csv
import difflib
import math
from pathlib import Path

import numpy as np
import yaml

from ..errors import ExperimentError
from ..experiment import Experiment
from ..files import load_yaml, read_text

REQUIRED_COLUMNS = ('circuit', 'voltage_v', 'supply_pa')
MEASURED_COLUMNS = ('p_a_pa', 'p_b_pa', 'm4_kg_s', 'm5_kg_s', 't_s_k')
STATIC_CIRCUITS = ('closed_port', 'flow', 'blocked')
#: CSV column -> Experiment signal
COLUMN_SIGNAL = {'voltage_v': 'command_v', 'supply_pa': 'supply_pa', 'p_a_pa': 'p_a_pa',
                 'p_b_pa': 'p_b_pa', 'm4_kg_s': 'm4_kg_s', 'm5_kg_s': 'm5_kg_s',
                 't_s_k': 't_s_k'}
#: a static table holds one row per steady operating point: tens to hundreds; thousands of
#: rows are a time series in the wrong format, and each row is a steady-state solve
MAX_ROWS = 5000
MAX_TABLE_BYTES = 4 * 1024 * 1024
#: [Pa] an absolute pressure below this is surely a gauge reading or in the wrong unit
_MIN_ABSOLUTE_PA = 2e4


def sidecar(path) -> Path:
    """The metadata file that accompanies a CSV table."""
    return Path(path).with_suffix('.meta.yaml')


def _number(where: str, line: int, column: str, text: str) -> float:
    if not text.strip():
        raise ExperimentError(f'{where} line {line}: {column} is empty; fill it in or remove '
                              'the row')
    try:
        value = float(text)
    except ValueError:
        raise ExperimentError(f"{where} line {line}: {column} = {text!r} is not a number; "
                              'write SI values (Pa, kg/s, K, V)') from None
    if not math.isfinite(value):
        raise ExperimentError(f'{where} line {line}: {column} is {text.strip() or "empty"}; '
                              'fill it in or remove the row')
    return value


def _header(where: str, fields: list[str]) -> list[str]:
    fields = [f.strip() for f in fields]
    known = REQUIRED_COLUMNS + MEASURED_COLUMNS
    for f in fields:
        if f not in known:
            close = difflib.get_close_matches(f, known, n=1)
            hint = (f"; did you mean '{close[0]}'?" if close
                    else f'; columns are {", ".join(known)}')
            raise ExperimentError(f"{where}: unknown column '{f}'{hint}")
    missing = [c for c in REQUIRED_COLUMNS if c not in fields]
    if missing:
        raise ExperimentError(f'{where}: missing column(s) {", ".join(missing)}; a static '
                              f'table needs {", ".join(REQUIRED_COLUMNS)}')
    if not any(c in fields for c in MEASURED_COLUMNS):
        raise ExperimentError(f'{where}: no measured column; add one of '
                              f'{", ".join(MEASURED_COLUMNS)}')
    dup = {f for f in fields if fields.count(f) > 1}
    if dup:
        raise ExperimentError(f'{where}: column(s) {", ".join(sorted(dup))} appear twice')
    return fields


def read_static_csv(path, name: str | None = None) -> Experiment:
    """Read a static CSV table into an Experiment with ``static=True`` (t = row index)."""
    path = Path(path)
    where = str(path)
    text = read_text(path, 'CSV table', ExperimentError, MAX_TABLE_BYTES)
    rows = list(csv.reader(line for line in text.splitlines() if line.strip()))
    if len(rows) > MAX_ROWS + 1:
        raise ExperimentError(f'{where}: {len(rows) - 1} rows; a static table holds one row '
                              f'per steady operating point (at most {MAX_ROWS}); record a time '
                              'series as a bag instead')
    if not rows:
        raise ExperimentError(f'{where}: empty file; a static table needs a header row and '
                              'one row per operating point')
    fields = _header(where, rows[0])
    if len(rows) < 2:
        raise ExperimentError(f'{where}: header only, no data rows')
    columns: dict[str, list[float]] = {f: [] for f in fields if f != 'circuit'}
    circuits = set()
    for line, row in enumerate(rows[1:], start=2):
        if len(row) != len(fields):
            raise ExperimentError(f'{where} line {line}: {len(row)} values for {len(fields)} '
                                  'columns; the file may be truncated')
        for f, cell in zip(fields, row):
            if f == 'circuit':
                circuits.add(cell.strip())
            else:
                columns[f].append(_number(where, line, f, cell))
    if len(circuits) != 1:
        raise ExperimentError(f'{where}: rows of several circuits ({", ".join(sorted(circuits))}'
                              '); write one file per circuit')
    circuit = circuits.pop()
    if circuit not in STATIC_CIRCUITS:
        raise ExperimentError(f"{where}: circuit '{circuit}' is not a static circuit; use "
                              f'{", ".join(STATIC_CIRCUITS)} (time series go in a bag)')
    for col in ('supply_pa', 'p_a_pa', 'p_b_pa'):
        if col in columns and min(columns[col]) < _MIN_ABSOLUTE_PA:
            raise ExperimentError(
                f'{where}: {col} has {min(columns[col]):g}, below {_MIN_ABSOLUTE_PA:g} Pa; '
                'pressures are absolute Pa (0.6 MPa gauge = 701325)')
    signals = {COLUMN_SIGNAL[c]: np.array(v) for c, v in columns.items()}
    meta = {'source': where}
    side = sidecar(path)
    if side.exists():
        extra = load_yaml(side, 'metadata file', ExperimentError) or {}
        if not isinstance(extra, dict):
            raise ExperimentError(f'{side}: expected a mapping of metadata; fix or delete it')
        meta.update({str(k): v for k, v in extra.items()})
    meta['synthetic'] = bool(meta.get('synthetic', False))
    n = len(rows) - 1
    return Experiment(np.arange(n, dtype=float), signals, circuit, name or path.stem, True, meta)


def write_static_csv(exp: Experiment, path, metadata: dict | None = None) -> Path:
    """Write a static experiment as an docs/interfaces.md CSV (and ``metadata`` as its sidecar)."""
    if not exp.static:
        raise ExperimentError(f'{exp.name}: a time series goes in a bag; use '
                              'write_experiment_bag')
    if exp.circuit not in STATIC_CIRCUITS:
        raise ExperimentError(f'{exp.name}: circuit {exp.circuit} is not a static circuit')
    path = Path(path)
    cols = [c for c in ('voltage_v', 'supply_pa') + MEASURED_COLUMNS
            if COLUMN_SIGNAL[c] in exp.signals]
    with path.open('w', newline='') as fh:
        out = csv.writer(fh)
        out.writerow(['circuit'] + cols)
        for k in range(len(exp.t)):
            out.writerow([exp.circuit] + [f'{exp.signals[COLUMN_SIGNAL[c]][k]:.10g}'
                                          for c in cols])
    if metadata:
        sidecar(path).write_text(yaml.safe_dump(_plain(metadata), sort_keys=False))
    return path


def _plain(value):
    """``value`` with numpy scalars and arrays made YAML-safe."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    return value
