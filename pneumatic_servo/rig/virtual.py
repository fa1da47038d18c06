"""The virtual DAQ: the simulated plant behind the same electrical signals as the real card.

The rig path (:class:`~.rigio.RigIO` scaling, counter unwrapping, output
limits, sensor-fault checks, and the plant node's handling of them) then runs
in CI with no hardware. What it produces, per sample:

* analog inputs [V]: each transmitter's output for the simulated pressure
  (gauge, 1-5 V for 0-0.6 MPa on the paper's rig), plus Gaussian noise,
  clipped to the input range and quantised like a 16-bit ADC over +/-10 V;
* the encoder counter: the simulated angle in counts (X4 decoding of the
  20,000-line encoder), offset by ``encoder.zero_count`` and wrapped at
  2**``counter_bits``, so a zero count just below the wrap exercises it;
* the analog output: clipped to the card's +/-10 V and quantised to 16 bits,
  then held for one period (the valve model itself clips to 0-10 V).

Faults can be injected on a schedule (``virtual.faults`` in the YAML) or with
:meth:`VirtualDaq.inject`: ``open_wire`` (an input reads 0 V), ``encoder_jump``
(the count jumps) and ``daq_error`` (reads fail).

Time advances one period per :meth:`read`, like a hardware-timed sample
clock: the rig loop reads once per period.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import ConfigError
from .config import RigConfig
from .driver import DaqDriver, DaqError, RawSample

FAULT_KINDS = ('open_wire', 'encoder_jump', 'daq_error')


def _quantise(volts: float, range_v: float, bits: int) -> float:
    """Clip to +/-``range_v`` and round to the ADC/DAC step (2 range / 2**bits)."""
    lsb = 2.0 * range_v / (1 << bits)
    v = min(max(volts, -range_v), range_v - lsb)
    return round(v / lsb) * lsb


class VirtualDaq(DaqDriver):
    """A DAQ whose signals come from a :class:`~pneumatic_servo.model.Stepper`.

    Parameters
    ----------
    config : RigConfig
    period_s : float [s]
        Sample period: each read advances the simulated plant by this.
    model : Model or ModelConfig, optional
        The simulated plant (default: ``config.virtual.model_config`` or the paper's).
    initial_angle_rad : float [rad], optional
        Start angle (default: ``config.virtual.initial_angle_rad``, else mid-stroke).
    method : str
        The stepper's integrator ('fixed' RK4: constant cost per period).
    """

    def __init__(self, config: RigConfig, period_s: float, model=None,
                 initial_angle_rad: float | None = None, method: str = 'fixed'):
        from ..model import Model, ModelConfig, Stepper, initial_state  # model layer, on use
        self.config = config
        self.period_s = float(period_s)
        if model is None:
            path = config.virtual.model_config
            model = ModelConfig.load(path) if path else ModelConfig.paper()
        if not isinstance(model, Model):
            model = Model(model)
        self.model = model
        angle = config.virtual.initial_angle_rad if initial_angle_rad is None \
            else initial_angle_rad
        x0 = initial_state(model, angle_rad=None if not math.isfinite(angle) else angle)
        self.stepper = Stepper(model, period_s=self.period_s, x0=x0, method=method)
        # compile the kernels now rather than in the first real-time period
        Stepper(model, period_s=self.period_s, x0=x0, method=method).step(5.0)
        self.state = self.stepper.x.copy()
        self.rng = np.random.default_rng(config.virtual.seed)
        self.ao_v = config.valve.safe_v
        self.t_s = 0.0
        self._started = False
        self._open: set[str] = set()
        self._count_offset = 0
        self._failing = ''
        self._schedule = sorted((self._check_fault(f) for f in config.virtual.faults),
                                key=lambda f: f['at_s'])
        self.description = f'virtual DAQ (simulated {config.device}, seed {config.virtual.seed})'

    def _check_fault(self, fault: dict) -> dict:
        kind = fault.get('kind')
        if kind not in FAULT_KINDS:
            raise ConfigError(f'virtual fault kind {kind!r}: use one of {", ".join(FAULT_KINDS)}')
        at = float(fault.get('at_s', 0.0))
        return {'at_s': at, 'kind': kind, 'channel': fault.get('channel', 'chamber_a'),
                'counts': int(fault.get('counts', 10000))}

    # ----------------------------------------------------------------- faults
    def inject(self, kind: str, channel: str = 'chamber_a', counts: int = 10000) -> None:
        """Inject a fault now: ``open_wire`` on ``channel``, ``encoder_jump`` by ``counts``,
        or ``daq_error``."""
        if kind == 'open_wire':
            if channel not in self.config.inputs():
                raise ConfigError(f'no analog input {channel!r}; known: '
                                  f'{", ".join(self.config.inputs())}')
            self._open.add(channel)
        elif kind == 'encoder_jump':
            self._count_offset += int(counts)
        elif kind == 'daq_error':
            self._failing = 'virtual DAQ: injected read error'
        else:
            raise ConfigError(f'fault kind {kind!r}: use one of {", ".join(FAULT_KINDS)}')

    # ----------------------------------------------------------------- driver
    def read(self) -> RawSample:
        if self._started:
            self.state = self.stepper.step(self.ao_v).copy()
            self.t_s += self.period_s
        self._started = True
        while self._schedule and self._schedule[0]['at_s'] <= self.t_s + 1e-12:
            f = self._schedule.pop(0)
            self.inject(f['kind'], f['channel'], f['counts'])
        if self._failing:
            raise DaqError(self._failing)
        cfg = self.config
        x = self.state
        pe = cfg.atmospheric_pressure_pa
        truth = {'chamber_a': x[2] - pe, 'chamber_b': x[3] - pe,
                 'supply': self.stepper.supply_pa - pe,
                 'temperature_a': x[4] - 273.15, 'temperature_b': x[5] - 273.15}
        volts = {}
        for name, ai in cfg.inputs().items():
            v = 0.0 if name in self._open else ai.to_volts(truth[name])
            v += self.rng.normal(0.0, ai.noise_v) if ai.noise_v > 0 else 0.0
            volts[name] = _quantise(v, cfg.ai_range_v, cfg.ai_resolution_bits)
        enc = cfg.encoder
        counts = int(round(x[0] / enc.rad_per_count)) * enc.direction
        raw = (enc.zero_count + counts + self._count_offset) % (1 << enc.counter_bits)
        return RawSample(volts, raw)

    def write(self, volts: float) -> None:
        if not math.isfinite(volts):
            raise DaqError(f'virtual DAQ: refusing to write {volts!r} V')
        v = self.config.valve
        self.ao_v = _quantise(float(volts), v.range_v, v.resolution_bits)

    def close(self) -> None:
        self._started = False
