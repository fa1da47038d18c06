"""Twelve effects on no list, for the open-world study (``bench_open_world.py``).

Written as a rig's physics would be, independently of the discovery's vocabulary: none
uses :mod:`pneumatic_servo.effects.terms`, several have shapes it cannot write exactly
(a smooth-edged window where the vocabulary has Gaussian bumps, |p_a - p_b| where it has
p_a - p_b, a code wheel's two cycles per stroke, a transducer's exact lag where it has the
first-order rate term). They are registered
only while their records are generated. Each class says what a right answer is:

* ``equations``: the equations a correction may act in to be right;
* ``depends``: the acceptable sets of variables of the leading term (after dropping the
  stroke and the atmosphere), e.g. ``({'angle'},)``: the correction is a function of angle;
* ``closed_form``: the terms that write it exactly ('' ends a prefix), or () where the
  vocabulary has none: then the right answer is the statement that no closed form fits.

Kinds: memory (solenoid hysteresis, coupling play, transducer lag), windows over the
stroke (a worn part of the vane housing, a detent), products of states (pressure- and
load-dependent friction), an error of every measured signal (angle, p_a, p_b, supply),
static and dynamic sensor errors.
"""
from __future__ import annotations

import math

import numpy as np

from pneumatic_servo._jit import njit
from pneumatic_servo.effects import Component, Param
from pneumatic_servo.effects.layout import (
    C_PE,
    C_PS,
    C_PS_REG,
    C_TE,
    C_TORQUE,
    OMEGA,
    P_A,
    P_B,
    T_A,
    THETA,
    add_flow,
)
from pneumatic_servo.synth.unlisted import SolenoidHysteresis as _UnlistedHysteresis

DEG = math.pi / 180.0


# --- memory ------------------------------------------------------------------------------
class SolenoidHysteresis(_UnlistedHysteresis):
    """Magnetic hysteresis of the proportional solenoid (the physics of the package's
    bundled memory demo, :mod:`pneumatic_servo.synth.unlisted`, under its own name)."""

    name = 'open_world_solenoid_hysteresis'
    equations, depends, closed_form = ('valve_input',), ({'command_direction'},), \
        ('command_direction',)


@njit(cache=True)
def _play(v, width):
    y, out = v[0], np.empty(len(v))
    for i in range(len(v)):
        vi = v[i]
        if vi - y > 0.5 * width:
            y = vi - 0.5 * width
        elif y - vi > 0.5 * width:
            y = vi + 0.5 * width
        out[i] = y
    return out


def _coupling_play(values, signals, core):
    angle = np.ascontiguousarray(signals['angle_rad'], dtype=float)
    return {'angle_rad': _play(angle, values['play_rad']) - angle}


class CouplingPlay(Component):
    """Play in the coupling between shaft and encoder: the encoder lags every reversal."""

    name = 'open_world_coupling_play'
    params = (Param('play_rad', 'rad', 1.2 * DEG, 0.0, 0.2, 'total play'),)
    sensor_error = staticmethod(_coupling_play)
    equations, depends, closed_form = ('measurement_angle',), ({'motion_direction'},), \
        ('motion_direction',)


def _transducer_lag(values, signals, core):
    from scipy.signal import lfilter
    p = np.asarray(signals['p_a_pa'], dtype=float)
    a = math.exp(-values['sample_interval_s'] / values['lag_s'])
    lagged = lfilter([1.0 - a], [1.0, -a], p, zi=[a * p[0]])[0] if len(p) else p
    return {'p_a_pa': lagged - p}


class TransducerLagA(Component):
    """Chamber a's transmitter reads through a first-order lag (a long thin line to it)."""

    name = 'open_world_transducer_lag_a'
    params = (Param('lag_s', 's', 0.008, 1e-4, 1.0, 'time constant'),
              Param('sample_interval_s', 's', 0.002, 1e-5, 1.0, 'record interval', fit=False))
    sensor_error = staticmethod(_transducer_lag)
    # to first order a lag reads -tau dp/dt: the rate of change is the dependence; a lag
    # operator on p_a (a memory of it) is the dependence and the closed form exactly
    equations = ('measurement_p_a',)
    depends = ({'p_a_rate'}, {'p_a', 'p_a_lag_5ms'}, {'p_a', 'p_a_lag_20ms'})
    closed_form = ('rate_p_a', 'lag_')


# --- windows over the stroke ---------------------------------------------------------------
@njit(cache=True)
def _smooth_box(angle, lo, hi, edge):
    return 1.0 / (1.0 + math.exp(-(angle - lo) / edge)) / (1.0 + math.exp((angle - hi) / edge))


def _vane_leak_hook(t, x, s, p, P, c, dx):
    # a worn stretch of the housing between p[1] and p[2]: the vane seal leaks there only
    w = _smooth_box(x[THETA], p[1], p[2], 2.0 * DEG)
    dp = x[P_A] - x[P_B]
    q = p[0] * w * math.copysign(math.sqrt(abs(dp)), dp)
    add_flow(c, 0, -q, c[C_TE], x[T_A])
    add_flow(c, 1, q, c[C_TE], x[T_A])


class PartStrokeVaneLeak(Component):
    """A leak across the vane that exists only over part of the stroke."""

    name = 'open_world_part_stroke_leak'
    params = (Param('flow_per_sqrt_pa', 'kg/(s.Pa^0.5)', 6e-8, 0.0, 1e-5, 'leak gain'),
              Param('from_rad', 'rad', 80 * DEG, 0.0, 3.4, 'start of the worn stretch'),
              Param('to_rad', 'rad', 110 * DEG, 0.0, 3.4, 'end of the worn stretch'))
    flows = _vane_leak_hook
    where_rad = (80 * DEG, 110 * DEG)
    equations = ('mass_balance_a', 'mass_balance_b')
    depends = ({'angle', 'p_a', 'p_b'},)
    closed_form = ('sqrt_pressure_difference_in_window_',)


def _detent_hook(t, x, s, p, P, c, dx):
    w = _smooth_box(x[THETA], p[1] - 15 * DEG, p[1] + 15 * DEG, 3.0 * DEG)
    c[C_TORQUE] += -p[0] * (x[THETA] - p[1]) * w


class TrackDetent(Component):
    """A spring detent that holds the shaft near one angle (only within 15 deg of it)."""

    name = 'open_world_detent'
    params = (Param('rate_n_m_per_rad', 'N.m/rad', 1.5, 0.0, 50.0, 'detent stiffness'),
              Param('at_rad', 'rad', 100 * DEG, 0.0, 3.4, 'detent angle'))
    mechanics = _detent_hook
    where_rad = (85 * DEG, 115 * DEG)
    equations, depends, closed_form = ('moment_balance',), ({'angle'},), ('window_',)


# --- products of states ---------------------------------------------------------------------
def _pressure_friction_hook(t, x, s, p, P, c, dx):
    gauge = 0.5 * (x[P_A] + x[P_B]) - c[C_PE]
    c[C_TORQUE] -= p[0] * gauge * math.tanh(x[OMEGA] / 0.005)


class PressureFriction(Component):
    """Seal friction that grows with the chambers' pressure."""

    name = 'open_world_pressure_friction'
    params = (Param('torque_per_pa', 'N.m/Pa', 4e-7, 0.0, 1e-4, 'friction per gauge Pa'),)
    mechanics = _pressure_friction_hook
    equations = ('moment_balance',)
    depends = ({'velocity', 'p_a', 'p_b'},)
    closed_form = ('sign_velocity_times_mean_pressure',)


def _load_friction_hook(t, x, s, p, P, c, dx):
    c[C_TORQUE] -= p[0] * abs(x[P_A] - x[P_B]) * math.tanh(x[OMEGA] / 0.005)


class LoadFriction(Component):
    """Gear friction that grows with the transmitted load |p_a - p_b|."""

    name = 'open_world_load_friction'
    params = (Param('torque_per_pa', 'N.m/Pa', 5e-7, 0.0, 1e-4, 'friction per Pa of load'),)
    mechanics = _load_friction_hook
    equations = ('moment_balance',)
    depends = ({'velocity', 'p_a', 'p_b'},)
    closed_form = ('sign_velocity_times_abs_pressure_difference',)


# --- errors of every measured signal ---------------------------------------------------------
def _supply_hook(t, x, s, p, P, c, dx):
    # the supply transmitter reads p[0] high: the rig has less than its reading says
    c[C_PS] -= p[0]
    c[C_PS_REG] -= p[0]


class SupplyTransmitterOffset(Component):
    """The supply transmitter reads high (the model is fed its reading)."""

    name = 'open_world_supply_offset'
    params = (Param('offset_pa', 'Pa', 3e4, -2e5, 2e5, 'reading minus truth'),)
    supply = _supply_hook
    order = 5
    equations, depends, closed_form = ('measurement_supply',), (set(), {'supply'}), \
        ('constant', 'supply')


def _gain_b(values, signals, core):
    return {'p_b_pa': values['gain_error'] * (signals['p_b_pa']
                                               - core['atmospheric_pressure_pa'])}


class TransmitterGainB(Component):
    """Chamber b's transmitter reads 4 % high over its span (a static gain error)."""

    name = 'open_world_gain_b'
    params = (Param('gain_error', '1', 0.04, -0.5, 0.5, 'relative gain error'),)
    sensor_error = staticmethod(_gain_b)
    equations, depends, closed_form = ('measurement_p_b',), ({'p_b'},), \
        ('gauge_p_b', 'p_b')


def _angle_scale(values, signals, core):
    return {'angle_rad': values['scale_error'] * signals['angle_rad']}


class AngleScale(Component):
    """The encoder's counts per revolution are set wrong: the angle reads 1.5 % high."""

    name = 'open_world_angle_scale'
    params = (Param('scale_error', '1', 0.015, -0.5, 0.5, 'relative scale error'),)
    sensor_error = staticmethod(_angle_scale)
    equations, depends, closed_form = ('measurement_angle',), ({'angle'},), ('angle',)


def _eccentric_wheel(values, signals, core):
    phase = 4.0 * math.pi * signals['angle_rad'] / core['stroke_rad']
    return {'angle_rad': values['amplitude_rad'] * np.sin(phase)}


class EccentricCodeWheel(Component):
    """An eccentric code wheel: the angle error cycles twice over the stroke."""

    name = 'open_world_eccentric_wheel'
    params = (Param('amplitude_rad', 'rad', 0.4 * DEG, 0.0, 0.1, 'error amplitude'),)
    sensor_error = staticmethod(_eccentric_wheel)
    equations, depends, closed_form = ('measurement_angle',), ({'angle'},), ()


def _gravity_hook(t, x, s, p, P, c, dx):
    c[C_TORQUE] -= p[0] * math.cos(x[THETA] - p[1])


class GravityArm(Component):
    """An arm with its mass off the axis, so gravity's torque turns with the shaft."""

    name = 'open_world_gravity_arm'
    params = (Param('torque_n_m', 'N.m', 0.25, 0.0, 10.0, 'm g r'),
              Param('phase_rad', 'rad', 0.4, -3.2, 3.2, 'angle of the arm at 0'))
    mechanics = _gravity_hook
    equations, depends, closed_form = ('moment_balance',), ({'angle'},), \
        ('cos_angle', 'sin_angle')


SET = (SolenoidHysteresis, CouplingPlay, TransducerLagA, PartStrokeVaneLeak, TrackDetent,
       PressureFriction, LoadFriction, SupplyTransmitterOffset, TransmitterGainB, AngleScale,
       EccentricCodeWheel, GravityArm)
