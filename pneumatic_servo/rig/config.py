"""The rig's wiring and scaling: which DAQ channel carries what, and how volts and counts
become pascals and radians. Loaded from YAML (``config/rig_pci6229.yaml``). Pure.

Conventions: pressures absolute [Pa] after scaling (transmitters read gauge,
the atmospheric pressure is added); angles [rad]; voltages [V].
"""
from __future__ import annotations

import difflib
import math
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Optional

from ..errors import ConfigError
from ..files import load_yaml


@dataclass(frozen=True)
class AnalogInput:
    """A transmitter on an analog input: ``volts_lo``..``volts_hi`` map to
    ``value_lo``..``value_hi``.

    ``fault_below_v``/``fault_above_v`` bound a healthy signal: a live-zero
    1-5 V transmitter reads ~0 V when its wire is broken.
    """

    channel: str
    volts_lo: float = 1.0
    volts_hi: float = 5.0
    value_lo: float = 0.0
    value_hi: float = 6.0e5
    fault_below_v: float = 0.5
    fault_above_v: float = 5.5
    terminal: str = 'rse'
    noise_v: float = 0.0005

    def to_value(self, volts: float) -> float:
        """Engineering value (linear scaling) of a reading [V]."""
        return self.value_lo + (volts - self.volts_lo) * (self.value_hi - self.value_lo) \
            / (self.volts_hi - self.volts_lo)

    def to_volts(self, value: float) -> float:
        """Transmitter output [V] for an engineering value (inverse of :meth:`to_value`)."""
        return self.volts_lo + (value - self.value_lo) * (self.volts_hi - self.volts_lo) \
            / (self.value_hi - self.value_lo)

    def fault(self, volts: float) -> Optional[str]:
        """Why a reading [V] is not a healthy signal, or None."""
        if not math.isfinite(volts):
            return f'{self.channel} reads {volts!r}'
        if volts < self.fault_below_v:
            return (f'{self.channel} reads {volts:.3f} V < {self.fault_below_v:g} V: open wire '
                    'or no transmitter supply')
        if volts > self.fault_above_v:
            return f'{self.channel} reads {volts:.3f} V > {self.fault_above_v:g} V: over range'
        return None


@dataclass(frozen=True)
class Encoder:
    """A quadrature encoder on a counter.

    ``pulses_per_rev`` lines, ``decoding`` edges counted per line (4 for X4),
    ``zero_count``: the raw count at angle 0 (where chamber a is smallest),
    ``direction``: +1 or -1; ``counter_bits``: the counter wraps at 2**bits.
    ``max_speed_rad_s``: a larger apparent speed between two samples is a
    fault (a glitch or a lost count).
    """

    counter: str = 'ctr0'
    pulses_per_rev: int = 20000
    decoding: int = 4
    zero_count: int = 0
    direction: int = 1
    counter_bits: int = 32
    max_speed_rad_s: float = 100.0

    @property
    def counts_per_rev(self) -> int:
        return self.pulses_per_rev * self.decoding

    @property
    def rad_per_count(self) -> float:
        return 2.0 * math.pi / self.counts_per_rev


@dataclass(frozen=True)
class ValveOutput:
    """The valve's analog output: ``min_v``..``max_v`` electrical limits, ``safe_v`` centre."""

    channel: str = 'ao0'
    min_v: float = 0.0
    max_v: float = 10.0
    safe_v: float = 5.0
    resolution_bits: int = 16
    range_v: float = 10.0


@dataclass(frozen=True)
class Virtual:
    """Options of the virtual DAQ: noise seed, initial angle, and faults to inject.

    ``faults`` is a list of ``{at_s: T, kind: K, channel: C}`` with ``kind`` one of
    ``open_wire`` (an analog input reads 0 V), ``encoder_jump`` (the count jumps
    by ``counts``) and ``daq_error`` (the read fails).
    """

    seed: int = 0
    initial_angle_rad: float = float('nan')
    model_config: str = ''
    faults: tuple = ()


@dataclass(frozen=True)
class RigConfig:
    """The whole rig: device, inputs, encoder, valve output, virtual-DAQ options."""

    device: str = 'Dev1'
    atmospheric_pressure_pa: float = 101325.0
    ai_range_v: float = 10.0
    ai_resolution_bits: int = 16
    chamber_a: AnalogInput = AnalogInput('ai0')
    chamber_b: AnalogInput = AnalogInput('ai1')
    supply: AnalogInput = AnalogInput('ai2')
    temperature_a: Optional[AnalogInput] = None
    temperature_b: Optional[AnalogInput] = None
    encoder: Encoder = Encoder()
    valve: ValveOutput = ValveOutput()
    velocity_filter_s: float = 0.0005
    virtual: Virtual = field(default_factory=Virtual)

    #: analog inputs in read order: name -> AnalogInput (temperatures only when wired)
    def inputs(self) -> dict[str, AnalogInput]:
        out = {'chamber_a': self.chamber_a, 'chamber_b': self.chamber_b, 'supply': self.supply}
        if self.temperature_a is not None:
            out['temperature_a'] = self.temperature_a
        if self.temperature_b is not None:
            out['temperature_b'] = self.temperature_b
        return out

    # ------------------------------------------------------------------ loading
    @classmethod
    def from_dict(cls, data: dict, where: str = 'rig config') -> 'RigConfig':
        data = dict(data or {})
        kinds = {'chamber_a': AnalogInput, 'chamber_b': AnalogInput, 'supply': AnalogInput,
                 'temperature_a': AnalogInput, 'temperature_b': AnalogInput,
                 'encoder': Encoder, 'valve': ValveOutput, 'virtual': Virtual}
        out = {}
        for key, value in data.items():
            known = [f.name for f in fields(cls)]
            if key not in known:
                close = difflib.get_close_matches(key, known, n=1)
                hint = f"; did you mean '{close[0]}'?" if close else f'; known: {", ".join(known)}'
                raise ConfigError(f'{where}: unknown key {key!r}{hint}')
            if key in kinds:
                if value is None and key.startswith('temperature'):
                    out[key] = None
                    continue
                out[key] = _build(kinds[key], value, f'{where}: {key}')
            else:
                out[key] = value
        try:
            cfg = cls(**out)
        except TypeError as exc:
            raise ConfigError(f'{where}: {exc}') from None
        cfg.validate(where)
        return cfg

    @classmethod
    def load(cls, path) -> 'RigConfig':
        path = Path(path)
        data = load_yaml(path, 'rig config')
        if data is not None and not isinstance(data, dict):
            raise ConfigError(f'{path}: expected a mapping of rig settings')
        return cls.from_dict(data, str(path))

    def validate(self, where: str = 'rig config') -> None:
        for name, ai in self.inputs().items():
            if ai.volts_hi == ai.volts_lo or ai.value_hi == ai.value_lo:
                raise ConfigError(f'{where}: {name} has an empty scaling span')
            if not ai.fault_below_v < ai.volts_lo < ai.volts_hi < ai.fault_above_v:
                raise ConfigError(f'{where}: {name} needs fault_below_v < volts_lo < volts_hi '
                                  '< fault_above_v')
        e = self.encoder
        if e.pulses_per_rev < 1 or e.decoding not in (1, 2, 4) or e.direction not in (1, -1):
            raise ConfigError(f'{where}: encoder needs pulses_per_rev >= 1, decoding 1, 2 or 4 '
                              'and direction +1 or -1')
        if not 8 <= e.counter_bits <= 64:
            raise ConfigError(f'{where}: encoder.counter_bits must be within 8-64')
        v = self.valve
        if not 0.0 <= v.min_v <= v.safe_v <= v.max_v <= 10.0:
            raise ConfigError(f'{where}: valve needs 0 <= min_v <= safe_v <= max_v <= 10 V')
        if self.velocity_filter_s < 0:
            raise ConfigError(f'{where}: velocity_filter_s must be >= 0 s')


def _build(kind, value, where):
    if not isinstance(value, dict):
        raise ConfigError(f'{where}: expected a mapping, got {value!r}')
    known = {f.name for f in fields(kind)}
    unknown = set(value) - known
    if unknown:
        name = sorted(unknown)[0]
        close = difflib.get_close_matches(name, sorted(known), n=1)
        hint = f"; did you mean '{close[0]}'?" if close else f'; known: {", ".join(sorted(known))}'
        raise ConfigError(f'{where}: unknown key {name!r}{hint}')
    value = dict(value)
    if kind is Virtual and 'faults' in value:
        value['faults'] = tuple(dict(f) for f in (value['faults'] or ()))
    try:
        return kind(**value)
    except TypeError as exc:
        raise ConfigError(f'{where}: {exc}') from None
