"""Realistic sensors on top of simulated signals: what the paper's rig would record.

Instruments (paper Tables 1 and 3):

* rotary encoder, 20,000 P/R: the angle is quantised to 2 pi / 20,000 rad;
  the velocity, where published, is the encoder difference over a short
  window (a causal estimate, as a DAQ computes it);
* pressure transmitters, 0-0.6 MPa gauge, 1-5 V into a 16-bit +/-10 V ADC:
  noise of 0.1 % of full scale (1 sigma) and the ADC's quantisation,
  saturating at the ends of the range;
* thermocouple (K type, 0.1 mm): a first-order lag, noise and quantisation;
* flow meters FESTO SFAH (M5, 0.1-5 L/min) and SFAB (M4, 2-200 L/min):
  noise from their accuracy (taken as 2 sigma per reading) averaged over
  the readings of one steady operating point;
* a 1 kHz DAQ that samples all of them on one clock.

Each function takes true signals in SI units (pressures absolute) and a
``numpy.random.Generator``; the sensor parameters are a :class:`SensorModel`.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

#: [kg/m^3] density of a standard litre (ANR: 293.15 K, 101325 Pa) of dry air
STANDARD_DENSITY = 101325.0 / (287.0 * 293.15)


@dataclass(frozen=True)
class SensorModel:
    """Parameters of the recording instruments (SI units unless the name says)."""

    rate_hz: float = 1000.0
    encoder_counts_per_rev: int = 20000
    #: encoder velocity: difference of the quantised angle over this window [s]
    velocity_window_s: float = 0.01
    pressure_full_scale_pa: float = 0.6e6
    #: 1-sigma noise as a fraction of full scale
    pressure_noise_fraction: float = 1e-3
    #: transmitter output span [V] and ADC range [V] and bits (sets the quantum)
    pressure_signal_span_v: float = 4.0
    adc_range_v: float = 20.0
    adc_bits: int = 16
    thermocouple_time_constant_s: float = 0.02
    temperature_noise_k: float = 0.05
    temperature_quantum_k: float = 0.01
    #: flow meters: (accuracy of reading, accuracy of full scale, full scale [L/min ANR])
    m4_meter: tuple[float, float, float] = (0.03, 0.003, 200.0)
    m5_meter: tuple[float, float, float] = (0.02, 0.01, 5.0)
    #: readings averaged per steady operating point of a static table
    readings_per_point: int = 500
    atmospheric_pa: float = 101325.0

    @property
    def encoder_step_rad(self) -> float:
        return 2.0 * math.pi / self.encoder_counts_per_rev

    @property
    def pressure_noise_pa(self) -> float:
        return self.pressure_noise_fraction * self.pressure_full_scale_pa

    @property
    def pressure_quantum_pa(self) -> float:
        """ADC step in pressure units [Pa]."""
        volts_per_pa = self.pressure_signal_span_v / self.pressure_full_scale_pa
        return self.adc_range_v / 2 ** self.adc_bits / volts_per_pa

    def with_full_scale(self, full_scale_pa: float) -> 'SensorModel':
        """The same instruments with a pressure transmitter of another range."""
        d = asdict(self)
        d['pressure_full_scale_pa'] = float(full_scale_pa)
        return SensorModel(**d)

    def describe(self) -> dict:
        """Plain dict for bag metadata and the README."""
        d = asdict(self)
        d.update(encoder_step_rad=self.encoder_step_rad,
                 pressure_noise_pa=self.pressure_noise_pa,
                 pressure_quantum_pa=self.pressure_quantum_pa)
        return d


def quantise(x: np.ndarray, step: float) -> np.ndarray:
    """Round ``x`` to multiples of ``step``."""
    return np.round(np.asarray(x, float) / step) * step


def encoder(angle_rad: np.ndarray, sensors: SensorModel) -> np.ndarray:
    """Encoder reading [rad] of the true angle."""
    return quantise(angle_rad, sensors.encoder_step_rad)


def encoder_velocity(angle_meas: np.ndarray, sensors: SensorModel) -> np.ndarray:
    """Velocity [rad/s] as the DAQ estimates it: encoder difference over a window (causal)."""
    n = max(1, int(round(sensors.velocity_window_s * sensors.rate_hz)))
    out = np.zeros_like(angle_meas)
    out[n:] = (angle_meas[n:] - angle_meas[:-n]) * sensors.rate_hz / n
    for k in range(1, min(n, len(angle_meas))):  # shorter window at the start
        out[k] = (angle_meas[k] - angle_meas[0]) * sensors.rate_hz / k
    return out


def pressure(p_abs: np.ndarray, rng: np.random.Generator, sensors: SensorModel) -> np.ndarray:
    """Transmitter reading [Pa, absolute] of the true absolute pressure."""
    pe = sensors.atmospheric_pa
    gauge = np.asarray(p_abs, float) - pe + rng.normal(0.0, sensors.pressure_noise_pa,
                                                       np.shape(p_abs))
    # the 1-5 V output saturates a little outside its range
    lo, hi = -0.02 * sensors.pressure_full_scale_pa, 1.05 * sensors.pressure_full_scale_pa
    return quantise(np.clip(gauge, lo, hi), sensors.pressure_quantum_pa) + pe


def first_order_lag(t: np.ndarray, x: np.ndarray, tau_s: float) -> np.ndarray:
    """``x`` seen through a first-order lag of time constant ``tau_s`` [s], exact for ZOH."""
    if tau_s <= 0:
        return np.asarray(x, float).copy()
    y = np.empty(len(x))
    y[0] = x[0]
    a = np.exp(-np.diff(t) / tau_s)
    for k in range(1, len(x)):
        y[k] = a[k - 1] * y[k - 1] + (1.0 - a[k - 1]) * x[k - 1]
    return y


def thermocouple(t: np.ndarray, temp_k: np.ndarray, rng: np.random.Generator,
                 sensors: SensorModel) -> np.ndarray:
    """Thermocouple reading [K] of the true gas temperature: lag, noise, quantisation."""
    lagged = first_order_lag(t, temp_k, sensors.thermocouple_time_constant_s)
    noisy = lagged + rng.normal(0.0, sensors.temperature_noise_k, len(lagged))
    return quantise(noisy, sensors.temperature_quantum_k)


def flow_meter(mdot_kg_s: np.ndarray, meter: tuple[float, float, float],
               rng: np.random.Generator, readings: int) -> np.ndarray:
    """Mean flow-meter reading [kg/s] over ``readings`` samples of a steady flow.

    The accuracy (``of reading``, ``of full scale``, full scale in standard
    L/min) is taken as 2 sigma of one reading; the mean of ``readings``
    independent readings has sigma / sqrt(readings).
    """
    rel, fs_frac, fs_lpm = meter
    fs = fs_frac * fs_lpm / 60000.0 * STANDARD_DENSITY
    m = np.asarray(mdot_kg_s, float)
    sigma = 0.5 * (rel * np.abs(m) + fs) / math.sqrt(readings)
    return m + rng.normal(0.0, 1.0, m.shape) * sigma


def measure(t: np.ndarray, true: dict[str, np.ndarray], rng: np.random.Generator,
            sensors: SensorModel | None = None, velocity: bool = True) -> dict[str, np.ndarray]:
    """Measured time series of the true signals ``true`` (Experiment signal names, SI).

    ``command_v`` passes unchanged (the DAQ knows what it outputs); the
    angle goes through the encoder (and gives the velocity when
    ``velocity``), pressures through the transmitters, gas temperatures
    through the thermocouples. Other signals pass unchanged.
    """
    s = sensors or SensorModel()
    out = {}
    for key, x in true.items():
        if key == 'angle_rad':
            out[key] = encoder(x, s)
            if velocity:
                out['velocity_rad_s'] = encoder_velocity(out[key], s)
        elif key == 'velocity_rad_s':
            continue  # from the encoder, above
        elif key in ('p_a_pa', 'p_b_pa', 'supply_pa'):
            out[key] = pressure(x, rng, s)
        elif key in ('t_a_k', 't_b_k'):
            out[key] = thermocouple(t, x, rng, s)
        else:
            out[key] = np.asarray(x, float).copy()
    return out


def measure_static(true: dict[str, np.ndarray], rng: np.random.Generator,
                   sensors: SensorModel | None = None) -> dict[str, np.ndarray]:
    """Measured rows of a steady-state table: each value the mean of many readings."""
    s = sensors or SensorModel()
    root = math.sqrt(s.readings_per_point)
    out = {}
    for key, x in true.items():
        x = np.asarray(x, float)
        if key in ('p_a_pa', 'p_b_pa', 'supply_pa'):
            noisy = x + rng.normal(0.0, s.pressure_noise_pa / root, x.shape)
            out[key] = quantise(noisy - s.atmospheric_pa, 1.0) + s.atmospheric_pa
        elif key == 'm4_kg_s':
            out[key] = flow_meter(x, s.m4_meter, rng, s.readings_per_point)
        elif key == 'm5_kg_s':
            out[key] = flow_meter(x, s.m5_meter, rng, s.readings_per_point)
        elif key == 't_s_k':
            out[key] = np.round(x + rng.normal(0.0, s.temperature_noise_k / root, x.shape), 3)
        else:
            out[key] = x.copy()
    return out
