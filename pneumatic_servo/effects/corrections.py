"""Generic correction terms: the vocabulary diagnosis uses when no named effect fits.

A correction adds, to one balance equation or one measurement, a linear
combination of physically meaningful regressors:

    correction = sum_k  coefficient_k * regressor_k(state, inputs)

Equations (each a component, named ``correction_<equation>``):

* ``moment_balance``: an extra torque on the shaft [N.m];
* ``mass_balance_a``, ``mass_balance_b``: an extra mass flow into a chamber [kg/s];
* ``valve_input``: an extra effective valve command [V];
* ``measurement_angle`` [rad], ``measurement_p_a``, ``measurement_p_b`` [Pa]: a sensor
  error, added to what the sensor reads; it does not feed back into the physics.

Regressors (:data:`REGRESSORS`) are evaluated on the physical state: angle,
its sine and cosine, velocity and its direction, the chamber pressures and
their difference, the valve command (minus its centre), its side and size, the
supply pressure, and the signed square roots of the pressure drops that an
orifice-like leak follows. Every coefficient is in SI units of the equation per
unit of the regressor, is zero by default (the correction then adds exactly
nothing) and is bounded by ten times the size a plausible correction has.

The classes are ``generic``: diagnosis never tries them as named effects; its
discovery step fits them (``analysis.diagnosis.discovery``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._jit import njit
from .base import Component, Param
from .layout import (
    C_PE,
    C_PS,
    C_TE,
    C_TORQUE,
    C_U,
    C_XV,
    K_GAIN,
    K_HALF_W,
    K_HOLE_R,
    K_NULL,
    OMEGA,
    P_A,
    P_B,
    T_A,
    T_B,
    THETA,
    add_flow,
)

#: [rad/s] and [V]: the widths over which the direction of motion and the side of the valve
#: centre change sign (tanh), so that a correction never makes the equations discontinuous
SIGN_VELOCITY_WIDTH = 0.01
SIGN_COMMAND_WIDTH = 0.02


@dataclass(frozen=True)
class Regressor:
    """A candidate term: its name, SI unit, a typical magnitude on a rig, and what it is."""

    name: str
    unit: str
    typical: float
    description: str


REGRESSORS = (
    Regressor('constant', '1', 1.0, 'one (a constant term)'),
    Regressor('angle', 'rad', 1.6, 'shaft angle'),
    Regressor('sin_angle', '1', 1.0, 'sine of the shaft angle'),
    Regressor('cos_angle', '1', 1.0, 'cosine of the shaft angle'),
    Regressor('velocity', 'rad/s', 2.0, 'shaft speed'),
    Regressor('sign_velocity', '1', 1.0, 'direction of motion'),
    Regressor('p_a', 'Pa', 4e5, 'chamber a pressure (absolute)'),
    Regressor('p_b', 'Pa', 4e5, 'chamber b pressure (absolute)'),
    Regressor('pressure_difference', 'Pa', 3e5, 'p_a - p_b'),
    Regressor('command', 'V', 1.0, 'valve command minus its centre (5 V)'),
    Regressor('sign_command', '1', 1.0, 'side of the valve centre the command is on'),
    Regressor('abs_command', 'V', 1.0, 'distance of the command from the valve centre'),
    Regressor('supply', 'Pa', 7e5, 'supply pressure (absolute)'),
    Regressor('sqrt_drop_a', 'Pa^0.5', 600.0,
              'signed square root of p_a - p_atm (an orifice from chamber a to atmosphere)'),
    Regressor('sqrt_drop_b', 'Pa^0.5', 600.0,
              'signed square root of p_b - p_atm (an orifice from chamber b to atmosphere)'),
    Regressor('sqrt_pressure_difference', 'Pa^0.5', 550.0,
              'signed square root of p_a - p_b (an orifice between the chambers)'),
)
REGRESSOR_NAMES = tuple(r.name for r in REGRESSORS)
N_REGRESSORS = len(REGRESSORS)


@njit(cache=True)
def _signed_sqrt(x):
    return math.copysign(math.sqrt(abs(x)), x)


@njit(cache=True)
def fill_regressors(angle, velocity, p_a, p_b, p_atm, command, supply, out):
    """Write the value of every regressor, in the order of :data:`REGRESSORS`, into ``out``.

    ``command`` is the valve command minus its centre [V]; the rest are SI.
    """
    out[0] = 1.0
    out[1] = angle
    out[2] = math.sin(angle)
    out[3] = math.cos(angle)
    out[4] = velocity
    out[5] = math.tanh(velocity / SIGN_VELOCITY_WIDTH)
    out[6] = p_a
    out[7] = p_b
    out[8] = p_a - p_b
    out[9] = command
    out[10] = math.tanh(command / SIGN_COMMAND_WIDTH)
    out[11] = abs(command)
    out[12] = supply
    out[13] = _signed_sqrt(p_a - p_atm)
    out[14] = _signed_sqrt(p_b - p_atm)
    out[15] = _signed_sqrt(p_a - p_b)


@njit(cache=True)
def _term(x, c, P, p):
    """sum_k p[k] * regressor_k at the state ``x`` and the inputs in the context ``c``."""
    reg = np.empty(N_REGRESSORS)
    fill_regressors(x[THETA], x[OMEGA], x[P_A], x[P_B], c[C_PE], c[C_U] - P[K_NULL], c[C_PS],
                    reg)
    total = 0.0
    for k in range(N_REGRESSORS):
        total += p[k] * reg[k]
    return total


@njit(cache=True)
def _fill_many(angle, velocity, p_a, p_b, p_atm, command, supply, out):
    for i in range(len(angle)):
        fill_regressors(angle[i], velocity[i], p_a[i], p_b[i], p_atm, command[i], supply[i],
                        out[i])


def regressor_values(signals: dict, p_atm: float, valve_null_v: float) -> np.ndarray:
    """(n, N_REGRESSORS) regressors over a record from its signals [SI]: ``angle_rad``,
    ``velocity_rad_s``, ``p_a_pa``, ``p_b_pa``, ``command_v`` and ``supply_pa`` (absent ones
    count as zero; a missing p_b as atmosphere)."""
    n = len(next(iter(signals.values())))

    def get(name, default=0.0):
        v = signals.get(name)
        return np.full(n, default) if v is None else np.ascontiguousarray(v, dtype=float)

    out = np.empty((n, N_REGRESSORS))
    _fill_many(get('angle_rad'), get('velocity_rad_s'), get('p_a_pa', p_atm),
               get('p_b_pa', p_atm), float(p_atm), get('command_v', valve_null_v) - valve_null_v,
               get('supply_pa', p_atm), out)
    return out


@dataclass(frozen=True)
class Equation:
    """Where a correction acts: its unit, the size [SI] of a plausible correction, what it
    adds, and the measured signal a sensor error shows in (None for a balance equation)."""

    name: str
    unit: str
    size: float
    description: str
    signal: str | None = None


EQUATIONS = (
    Equation('moment_balance', 'N.m', 1.0, 'an extra torque on the shaft'),
    Equation('mass_balance_a', 'kg/s', 5e-5, 'an extra mass flow into chamber a'),
    Equation('mass_balance_b', 'kg/s', 5e-5, 'an extra mass flow into chamber b'),
    Equation('valve_input', 'V', 0.5, 'an extra effective valve command'),
    Equation('measurement_angle', 'rad', 0.05, 'an error of the angle sensor', 'angle_rad'),
    Equation('measurement_p_a', 'Pa', 2e4, 'an error of the chamber a pressure sensor',
             'p_a_pa'),
    Equation('measurement_p_b', 'Pa', 2e4, 'an error of the chamber b pressure sensor',
             'p_b_pa'),
)


def coefficient_name(regressor: str) -> str:
    return f'{regressor}_coefficient'


def _params(eq: Equation) -> tuple[Param, ...]:
    out = []
    for r in REGRESSORS:
        size = eq.size / r.typical
        unit = eq.unit if r.unit == '1' else '1' if r.unit == eq.unit else f'{eq.unit}/{r.unit}'
        out.append(Param(coefficient_name(r.name), unit, 0.0, -10.0 * size, 10.0 * size,
                         f'{eq.description} per unit of {r.description}', fit=False,
                         plausible=(-size, size)))
    return tuple(out)


# --- hooks, one per equation ------------------------------------------------------------
@njit(cache=True)
def _moment_hook(t, x, s, p, P, c, dx):
    c[C_TORQUE] += _term(x, c, P, p)


@njit(cache=True)
def _mass_a_hook(t, x, s, p, P, c, dx):
    add_flow(c, 0, _term(x, c, P, p), c[C_TE], x[T_A])


@njit(cache=True)
def _mass_b_hook(t, x, s, p, P, c, dx):
    add_flow(c, 1, _term(x, c, P, p), c[C_TE], x[T_B])


@njit(cache=True)
def _valve_hook(t, x, s, p, P, c, dx):
    lim = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(c[C_XV] + P[K_GAIN] * _term(x, c, P, p), -lim), lim)


def _sensor(signal: str):
    def sensor_error(values: dict, signals: dict, core: dict) -> dict:
        reg = regressor_values(signals, core['atmospheric_pressure_pa'],
                               core['valve_null_voltage_v'])
        coef = np.array([values[coefficient_name(r)] for r in REGRESSOR_NAMES])
        return {signal: reg @ coef}
    return sensor_error


class Correction(Component):
    """Base of the generic corrections: never tried as a named effect."""

    generic = True
    summary = 'a generic correction term found by diagnosis'
    reference = 'analysis.diagnosis.discovery'

    @classmethod
    def refit_keys(cls, values: dict) -> list[str]:
        """Only the terms in use are refitted when the model is diagnosed again."""
        return [k for k, v in values.items() if v != 0.0]


def _correction_class(eq: Equation, **hooks) -> type[Component]:
    params = _params(eq)
    attrs = {'name': f'correction_{eq.name}', 'equation': eq, 'params': params,
             'neutral': {p.name: 0.0 for p in params},
             '__doc__': f'Generic correction: {eq.description} [{eq.unit}], a linear '
                        'combination of the regressors.', **hooks}
    return type(f'Correction_{eq.name}', (Correction,), attrs)


CORRECTIONS = (
    _correction_class(EQUATIONS[0], acts_on='angle', circuits=('servo',),
                      mechanics=_moment_hook),
    _correction_class(EQUATIONS[1], acts_on='pressure', flows=_mass_a_hook),
    _correction_class(EQUATIONS[2], acts_on='pressure', circuits=('servo', 'blocked'),
                      flows=_mass_b_hook),
    _correction_class(EQUATIONS[3], order=15, valve=_valve_hook),
    *(_correction_class(eq, sensor_error=staticmethod(_sensor(eq.signal)))
      for eq in EQUATIONS[4:]),
)
#: equation name -> its correction component
BY_EQUATION = {cls.equation.name: cls for cls in CORRECTIONS}
