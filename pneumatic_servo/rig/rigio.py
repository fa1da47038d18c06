"""From raw DAQ signals to a :class:`~pneumatic_servo.control.measurement.Measurement` and
back: scaling, counter unwrapping, velocity estimate, electrical output limits and the
sensor fault checks. Pure; every driver shares it.
"""
from __future__ import annotations

import math
from typing import Optional

from ..control.measurement import Measurement
from .config import RigConfig
from .driver import DaqDriver, DaqError

CELSIUS_K = 273.15


class SensorFault(DaqError):
    """A signal is implausible (open wire, over range, encoder glitch)."""


class RigIO:
    """Scaled, checked access to a rig through ``driver``.

    Parameters
    ----------
    config : RigConfig
    driver : DaqDriver
    period_s : float [s]
        Sampling period, for the velocity estimate and the time stamps of a
        driver that keeps no clock.
    """

    def __init__(self, config: RigConfig, driver: DaqDriver, period_s: float):
        self.config = config
        self.driver = driver
        self.period_s = float(period_s)
        self._last_count: Optional[int] = None
        self._counts = 0
        self._angle_prev = None
        self.velocity = 0.0
        self.last_output_v = config.valve.safe_v

    # ------------------------------------------------------------------ input
    def unwrap(self, raw: int) -> int:
        """Counts from ``encoder.zero_count`` (signed), continued across counter wrap-around.

        The first read takes the representation nearest the zero count; later
        reads add the signed difference to the previous raw count modulo
        2**bits, so the counter may wrap any number of times.
        """
        enc = self.config.encoder
        span = 1 << enc.counter_bits
        raw = int(raw) % span

        def signed(d):
            d %= span
            return d - span if d >= span // 2 else d

        if self._last_count is None:
            self._counts = signed(raw - enc.zero_count)
        else:
            self._counts += signed(raw - self._last_count)
        self._last_count = raw
        return self._counts

    def read(self, t_s: float) -> Measurement:
        """Sample, scale and check; raises :class:`SensorFault` on an implausible signal."""
        cfg = self.config
        raw = self.driver.read()
        values = {}
        for name, ai in cfg.inputs().items():
            volts = raw.volts.get(name, math.nan)
            reason = ai.fault(volts)
            if reason:
                raise SensorFault(f'{name} transmitter: {reason}')
            values[name] = ai.to_value(volts)
        enc = cfg.encoder
        counts = self.unwrap(raw.count)
        angle = enc.direction * counts * enc.rad_per_count
        if self._angle_prev is not None:
            jump = angle - self._angle_prev
            speed = jump / self.period_s
            if abs(speed) > enc.max_speed_rad_s:
                self._angle_prev = None
                raise SensorFault(f'encoder jumped {jump:+.4f} rad in one sample ({speed:.0f} '
                                  f'rad/s > {enc.max_speed_rad_s:g}): check the encoder wiring '
                                  'and shielding')
            tau = cfg.velocity_filter_s
            alpha = self.period_s / (tau + self.period_s)
            self.velocity += alpha * (speed - self.velocity)
        self._angle_prev = angle
        pe = cfg.atmospheric_pressure_pa
        p_a, p_b = values['chamber_a'] + pe, values['chamber_b'] + pe
        ta = values.get('temperature_a', math.nan) + CELSIUS_K
        tb = values.get('temperature_b', math.nan) + CELSIUS_K
        return Measurement(t_s, angle, self.velocity, p_a, p_b, values['supply'] + pe, ta, tb)

    # ----------------------------------------------------------------- output
    def write(self, volts: float) -> float:
        """Write the valve voltage [V], limited to the output's electrical range; returns it.

        A non-finite value never reaches the driver: the safe voltage is written instead
        (the gate upstream has already caught it; this is the last line).
        """
        v = self.config.valve
        out = float(volts)
        out = v.safe_v if not math.isfinite(out) else min(max(out, v.min_v), v.max_v)
        self.driver.write(out)
        self.last_output_v = out
        return out

    def safe(self) -> None:
        """Write the safe voltage; swallow a driver error (we are already failing safe)."""
        try:
            self.write(self.config.valve.safe_v)
        except DaqError:
            pass

    def close(self) -> None:
        self.safe()
        self.driver.close()
