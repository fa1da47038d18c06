"""Recorded experiments in and out: rosbag2 (sqlite3, MCAP) and static CSV <-> Experiment.

``read_experiment`` takes a bag directory or a CSV file and returns a
validated :class:`~pneumatic_servo.experiment.Experiment`: time series
resampled onto one uniform grid (CSV: ``static=True``, one row per
operating point). ``write_experiment_bag`` and ``write_static_csv`` write
them back in the docs/interfaces.md formats. Uses ``rosbags`` only, never rclpy.
"""
from __future__ import annotations

from pathlib import Path

from ..experiment import Experiment
from .bag import read_bag, read_series, write_experiment_bag
from .csv import read_static_csv, write_static_csv
from .topics import TOPICS
from .validate import check_physical

__all__ = ['read_experiment', 'read_bag', 'read_series', 'read_static_csv', 'write_experiment_bag',
           'write_static_csv', 'write_experiment', 'TOPICS']


def read_experiment(path, **options) -> Experiment:
    """Read a bag directory (sqlite3 or MCAP) or a static ``.csv`` file.

    ``options`` go to :func:`read_bag` (bags) or are ignored but ``name``
    (CSV). Any problem raises ``ExperimentError`` with a one-line reason.
    """
    path = Path(path)
    if path.suffix.lower() == '.csv':
        exp = read_static_csv(path, name=options.get('name'))
    else:
        exp = read_bag(path, **options)
    check_physical(str(path), exp.signals, exp.metadata)
    return exp


def write_experiment(exp: Experiment, path, storage: str = 'sqlite3',
                     metadata: dict | None = None, **options) -> Path:
    """Write a time series as a bag, a static table as a CSV (``path`` ending in .csv)."""
    if exp.static:
        return write_static_csv(exp, path, metadata)
    return write_experiment_bag(exp, path, storage, metadata, **options)
