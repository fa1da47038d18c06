"""The floor file: what a baseline measured, saved so that the next run judges at once.

A YAML file::

    format: pneumatic_servo.monitor.floor/1
    period_s: 0.001              # sample period of the data it was measured on [s]
    horizon_s: 0.2               # k-step horizon of the windows [s]
    measured_on: {start_ns: ..., seconds: 20.0, samples: 20000}
    model: {components: [...], effects: [...]}
    sensors:                     # what the floor is made of, per channel [SI]
      noise: {angle: 0.0, p_a: 609.4, p_b: 609.4}       # 1 sigma, without quantisation
      quantum: {angle: 3.1416e-4, p_a: 45.78, p_b: 45.78}
    floor_rms: {angle: ..., p_a: ..., p_b: ...}           # median floor of a window [SI]

Only ``sensors`` (and the period) decide anything: every window's floor is measured on
the window from them (:mod:`.judge`); ``floor_rms`` says how large that floor typically
was on the baseline, for people.
"""
from __future__ import annotations

import math
import os
from pathlib import Path

import yaml

from ..errors import ConfigError
from ..files import load_yaml
from .judge import CHANNELS, Sensors

FORMAT = 'pneumatic_servo.monitor.floor/1'


def save_floor(path, data: dict) -> Path:
    """Write ``data`` (see module doc) to ``path`` atomically (a reader never sees half)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = ('# Prediction floor of `pneumatic-servo monitor` (docs/ros.md, The monitor):\n'
            '# the sensor noise and quantisation the baseline measured. Pass it with --floor\n'
            '# (parameter floor_file) to judge from the first window, without a baseline.\n')
    text += yaml.safe_dump({'format': FORMAT, **data}, sort_keys=False)
    tmp = path.with_name(path.name + '.tmp')
    tmp.write_text(text)
    os.replace(tmp, path)
    return path


def _number(where: str, value) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f'{where} = {value!r} is not a number') from None
    if not (math.isfinite(x) and x >= 0):
        raise ConfigError(f'{where} = {value!r}: give a finite number >= 0')
    return x


def load_floor(path) -> dict:
    """The floor file ``path``, checked: ``{'period_s', 'horizon_s', 'sensors': Sensors,
    ...}``; ConfigError naming the file and the fix."""
    data = load_yaml(path, 'monitor floor file', ConfigError)
    where = f'floor file {path}'
    if not isinstance(data, dict) or data.get('format') != FORMAT:
        raise ConfigError(f'{where} is not a floor written by pneumatic-servo monitor (no '
                          f'"format: {FORMAT}"); measure one: run the monitor without --floor')
    out = dict(data)
    for key in ('period_s', 'horizon_s'):
        out[key] = _number(f'{where}: {key}', data.get(key))
        if out[key] <= 0:
            raise ConfigError(f'{where}: {key} must be positive')
    sensors = data.get('sensors')
    if not isinstance(sensors, dict):
        raise ConfigError(f'{where} has no sensors: section; measure a new floor')
    try:
        noise = {ch: _number(f'{where}: sensors.noise.{ch}', sensors['noise'][ch])
                 for ch in CHANNELS}
        step = {ch: _number(f'{where}: sensors.quantum.{ch}', sensors['quantum'][ch])
                for ch in CHANNELS}
    except (KeyError, TypeError):
        raise ConfigError(f'{where}: sensors needs noise and quantum for '
                          f'{", ".join(CHANNELS)}; measure a new floor') from None
    out['sensors'] = Sensors(noise, step)
    return out


def default_floor_path(node_name: str = 'monitor') -> Path:
    """Where a node saves its floor when none is named: ``$ROS_HOME/pneumatic_servo/``
    (``~/.ros`` by default), one file per node name."""
    home = Path(os.environ.get('ROS_HOME') or Path.home() / '.ros')
    return home / 'pneumatic_servo' / f'{node_name}_floor.yaml'
