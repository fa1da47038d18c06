"""The ``Experiment`` type: one recorded (or generated) experiment, time-aligned, in SI.

Readers in ``pneumatic_servo.io`` produce it from rosbag2 (sqlite3, MCAP)
and static CSV; identification and analysis consume it. Signal names and
units are fixed (``SIGNALS``); a signal that was not measured is absent.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .effects.layout import CIRCUITS
from .errors import ExperimentError

#: signal name -> (unit, meaning). Pressures absolute.
SIGNALS = {
    'command_v': ('V', 'valve command'),
    'supply_pa': ('Pa', 'supply pressure (absolute)'),
    'angle_rad': ('rad', 'actuator angle'),
    'velocity_rad_s': ('rad/s', 'actuator angular velocity'),
    'effort_n_m': ('N.m', 'shaft torque'),
    'p_a_pa': ('Pa', 'chamber a pressure (absolute)'),
    'p_b_pa': ('Pa', 'chamber b pressure (absolute)'),
    't_a_k': ('K', 'chamber a gas temperature'),
    't_b_k': ('K', 'chamber b gas temperature'),
    'm4_kg_s': ('kg/s', 'mass flow out of port 4 (flow test)'),
    'm5_kg_s': ('kg/s', 'mass flow out of exhaust port 5 (flow test)'),
    't_s_k': ('K', 'supply temperature (flow test)'),
    'setpoint_rad': ('rad', 'controller setpoint (closed-loop records)'),
}


@dataclass(frozen=True)
class Channel:
    """A measured output the model predicts: its signal, SI unit, what it is, the smallest
    spread [SI] a fit normalises it by (None: never fitted), its display unit and factor, and
    the equation whose error shows first in it."""

    signal: str
    unit: str
    label: str
    floor: float | None
    display: tuple[str, float]
    equation: str = ''


#: compared channels (the keys of the 'compare' JSON, docs/interfaces.md): the one table of them
CHANNELS = {
    'angle': Channel('angle_rad', 'rad', 'angle', 2e-3, ('deg', 180.0 / np.pi),
                     'moment balance (angle)'),
    'p_a': Channel('p_a_pa', 'Pa', 'chamber a pressure', 2e3, ('kPa', 1e-3),
                   'mass balance of chamber a'),
    'p_b': Channel('p_b_pa', 'Pa', 'chamber b pressure', 2e3, ('kPa', 1e-3),
                   'mass balance of chamber b'),
    't_a': Channel('t_a_k', 'K', 'chamber a temperature', 0.5, ('K', 1.0),
                   'energy balance of chamber a'),
    't_b': Channel('t_b_k', 'K', 'chamber b temperature', 0.5, ('K', 1.0),
                   'energy balance of chamber b'),
    'm4': Channel('m4_kg_s', 'kg/s', 'port 4 flow', 1e-6, ('g/s', 1e3), 'valve flow (port 4)'),
    'm5': Channel('m5_kg_s', 'kg/s', 'port 5 flow', 1e-7, ('g/s', 1e3),
                  'valve flow (exhaust port 5)'),
}
#: the channels of a time series that the residual tests and regime shares look at
STATE_CHANNELS = ('angle', 'p_a', 'p_b')
CIRCUIT_NAMES = tuple(CIRCUITS)


def signal_of(channel: str) -> str:
    """The signal of ``channel`` (a signal name is returned as it is)."""
    return CHANNELS[channel].signal if channel in CHANNELS else channel


@dataclass
class Experiment:
    """Time-aligned signals of one experiment.

    For a time series, ``t`` [s] starts at 0 and is uniformly sampled (the
    readers resample onto it). For a static table (``static=True``), each
    row is one steady operating point and ``t`` is the row index.
    """

    t: np.ndarray
    signals: dict[str, np.ndarray]
    circuit: str = 'servo'
    name: str = ''
    static: bool = False
    metadata: dict = field(default_factory=dict)

    def __post_init__(self):
        self.t = np.asarray(self.t, dtype=float)
        if self.circuit not in CIRCUIT_NAMES:
            raise ExperimentError(f'{self.name or "experiment"}: unknown circuit '
                                  f'{self.circuit!r}; use one of {", ".join(CIRCUIT_NAMES)}')
        for key, values in list(self.signals.items()):
            if key not in SIGNALS:
                raise ExperimentError(f'{self.name or "experiment"}: unknown signal {key!r}')
            values = np.asarray(values, dtype=float)
            if values.shape != self.t.shape:
                raise ExperimentError(f'{self.name or "experiment"}: signal {key} has '
                                      f'{values.size} samples, time has {self.t.size}')
            self.signals[key] = values

    def __getitem__(self, key: str) -> np.ndarray:
        try:
            return self.signals[key]
        except KeyError:
            raise ExperimentError(f'{self.name or "experiment"} has no {key} signal') from None

    def __contains__(self, key: str) -> bool:
        return key in self.signals

    @property
    def dt(self) -> float:
        """Sample period [s] of a time series."""
        return float(self.t[1] - self.t[0]) if len(self.t) > 1 else float('nan')

    @property
    def duration(self) -> float:
        return float(self.t[-1] - self.t[0]) if len(self.t) else 0.0

    def slice(self, start_s: float, stop_s: float) -> 'Experiment':
        """The part with start_s <= t < stop_s, time re-based to 0."""
        keep = (self.t >= start_s) & (self.t < stop_s)
        t = self.t[keep]
        return Experiment(t - t[0] if not self.static else t,
                          {k: v[keep] for k, v in self.signals.items()}, self.circuit,
                          f'{self.name}[{start_s:g}:{stop_s:g}]', self.static,
                          dict(self.metadata))

    def channels(self) -> list[str]:
        """Compared channels (angle, p_a, p_b) present in this experiment."""
        return [ch for ch in STATE_CHANNELS if CHANNELS[ch].signal in self.signals]
