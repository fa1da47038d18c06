"""Effects that are on no list: real physics a rig can have that the catalogue does not name.

They exist to generate test data and the bundled ``bags/unlisted_effect_demo`` and
``bags/hysteresis_demo`` (an effect with memory). They are
never registered, except while their data are generated (:func:`unlisted_data`), so that
diagnosis meets them as a user meets an unknown rig. Each acts in one equation class, with a
realistic magnitude, and is what a generic correction of that equation describes through one
leading regressor (:data:`EXPECTED`).

Regenerate the demo bags (the same seed gives a statistically equivalent record, see
:mod:`.hidden`)::

    python -m pneumatic_servo.synth.unlisted bags
"""
import math
from pathlib import Path

import numpy as np

from .. import effects as registry
from ..effects import Component, Param, State
from ..effects.layout import (
    C_TE,
    C_TORQUE,
    C_U,
    C_XV,
    K_GAIN,
    K_HALF_W,
    K_HOLE_R,
    K_NULL,
    OMEGA,
    T_A,
    T_B,
    THETA,
    add_flow,
)
from .hidden import closed_loop_experiment, hidden_config, make_hidden_set


def _arm_hook(t, x, s, p, P, c, dx):
    c[C_TORQUE] += p[0] * (x[THETA] - p[1])


class ArmSpring(Component):
    """A spring-balanced arm: a torque that falls with angle about a rest angle."""

    name = 'unlisted_arm_spring'
    summary = 'position-dependent torque'
    params = (Param('rate_n_m_per_rad', 'N.m/rad', -0.12, -2.0, 2.0, 'torque per angle'),
              Param('rest_angle_rad', 'rad', 0.9, 0.0, 3.4, 'rest angle'))
    mechanics = _arm_hook


def _bore_hook(t, x, s, p, P, c, dx):
    # chamber b's piston is larger than the model's: it sweeps more volume than modelled,
    # which at the model's volume reads as extra mass flow following the shaft speed
    add_flow(c, 1, p[0] * x[OMEGA], c[C_TE], x[T_B])


class LargerBoreB(Component):
    """Chamber b's bore is larger than chamber a's: extra flow that follows the speed."""

    name = 'unlisted_larger_bore_b'
    summary = 'unequal piston areas'
    params = (Param('flow_per_speed_kg_per_rad', 'kg/rad', 1.2e-5, 0.0, 1e-3,
                    'extra swept mass per radian'),)
    flows = _bore_hook


def _pilot_hook(t, x, s, p, P, c, dx):
    add_flow(c, 0, p[0], c[C_TE], x[T_A])


class PilotLineIntoA(Component):
    """A leaking pilot line feeds chamber a at a steady rate."""

    name = 'unlisted_pilot_line_a'
    summary = 'steady inflow into chamber a'
    params = (Param('inflow_kg_s', 'kg/s', 4e-6, 0.0, 1e-3, 'steady inflow'),)
    flows = _pilot_hook


def _deadband_hook(t, x, s, p, P, c, dx):
    u = c[C_U] - P[K_NULL]
    lim = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(c[C_XV] - P[K_GAIN] * p[0] * math.tanh(u / 0.02), -lim), lim)


class ValveDeadBand(Component):
    """Spool overlap: the valve ignores the first part of the command either side of 5 V."""

    name = 'unlisted_valve_dead_band'
    summary = 'nonlinearity of the valve around its null'
    order = 12
    params = (Param('dead_band_v', 'V', 0.12, 0.0, 1.0, 'half width of the dead band'),)
    valve = _deadband_hook


def _offset_a(values, signals, core):
    return {'p_a_pa': np.full(len(signals['p_a_pa']), values['offset_pa'])}


class TransmitterOffsetA(Component):
    """Chamber a's pressure transmitter reads high by a constant offset."""

    name = 'unlisted_transmitter_offset_a'
    summary = 'pressure sensor offset'
    params = (Param('offset_pa', 'Pa', 1.5e4, -1e5, 1e5, 'reading minus truth'),)
    sensor_error = staticmethod(_offset_a)


def _hysteresis_hook(t, x, s, p, P, c, dx):
    # the solenoid's flux remembers the direction of the last command change: the spool sits
    # as if the command were p[0] volts behind it; the memory follows outside a band of
    # p[1] volts within half a millisecond
    d = c[C_U] - x[s]
    half = 0.5 * p[1]
    dx[s] = (d - min(max(d, -half), half)) / 5e-4
    lim = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(c[C_XV] - P[K_GAIN] * p[0] * min(max(d / half, -1.0), 1.0), -lim), lim)


class SolenoidHysteresis(Component):
    """Magnetic hysteresis of the proportional solenoid: the spool lags the command by
    ``lag_v`` in the direction the command last moved (an effect with memory)."""

    name = 'unlisted_solenoid_hysteresis'
    summary = 'spool lags the command in the direction it last moved'
    params = (Param('lag_v', 'V', 0.06, 0.0, 1.0, 'command lag in the last direction'),
              Param('band_v', 'V', 0.1, 1e-3, 1.0, 'width of the hysteresis band', fit=False))
    states = (State('flux_memory_v', 'V', 1e-3, 'command as the flux remembers it'),)
    order = 12
    valve = _hysteresis_hook

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [command_v]


#: effect class -> (equation, leading regressor) the discovery must name
EXPECTED = {
    ArmSpring: ('moment_balance', 'angle'),
    PilotLineIntoA: ('mass_balance_a', 'constant'),
    LargerBoreB: ('mass_balance_b', 'velocity'),
    ValveDeadBand: ('valve_input', 'sign_command'),
    TransmitterOffsetA: ('measurement_p_a', 'constant'),
}


class _registered:
    """``with _registered(cls):`` the class is registered while its data are made."""

    def __init__(self, cls):
        self.cls = cls

    def __enter__(self):
        registry.register(self.cls)

    def __exit__(self, *exc):
        registry._REGISTRY.pop(self.cls.name, None)


def unlisted_data(cls, seed: int, designs=('closed_loop', 'sine'),
                  durations=None, rate_hz: float = 250.0):
    """Records of a rig with the unlisted effect ``cls`` (at its defaults), generated with
    it registered; it is unregistered again before they are returned."""
    with _registered(cls):
        return make_hidden_set({cls.name: cls.defaults()}, seed=seed, designs=designs,
                               durations=durations or {'closed_loop': 4.0, 'sine': 2.0},
                               rate_hz=rate_hz)


def write_demo_bag(bags_dir, seed: int = 9) -> Path:
    """Write ``bags/unlisted_effect_demo``: a 10 s, 1 kHz closed-loop record of a rig with a
    spring-balanced arm (:class:`ArmSpring`), which no catalogue effect describes. The bag's
    custom data say so, and that it is synthetic."""
    from ..io import write_experiment
    with _registered(ArmSpring):
        exp = closed_loop_experiment(hidden_config({ArmSpring.name: ArmSpring.defaults()}),
                                     np.random.default_rng(seed), 10.0)
    meta = {'synthetic': 'true', 'generator': 'pneumatic_servo.synth.unlisted', 'seed': seed,
            'hidden_effects': {'unlisted: a spring-balanced arm, torque k (angle - rest)':
                               ArmSpring.defaults()}, 'design': 'closed_loop'}
    return write_experiment(exp, Path(bags_dir) / 'unlisted_effect_demo', 'mcap', meta,
                            compress=True)


def write_memory_demo_bag(bags_dir, seed: int = 10) -> Path:
    """Write ``bags/hysteresis_demo``: a 10 s, 1 kHz open-loop chirp of a rig whose
    solenoid has magnetic hysteresis (:class:`SolenoidHysteresis`, an effect with memory
    that no catalogue effect describes), through industrial sensors. Synthetic, and says so."""
    from ..io import write_experiment
    from .varied import Record, make_record
    rec = Record('chirp', 1000.0, 10.0, seed=seed,
                 effects={SolenoidHysteresis.name: SolenoidHysteresis.defaults()})
    with _registered(SolenoidHysteresis):
        exp = make_record(rec)
    meta = {'synthetic': 'true', 'generator': 'pneumatic_servo.synth.unlisted', 'seed': seed,
            'hidden_effects': {'unlisted: solenoid hysteresis, the spool lags the command by '
                               'lag_v in the direction it last moved':
                               SolenoidHysteresis.defaults()}, 'design': 'chirp'}
    return write_experiment(exp, Path(bags_dir) / 'hysteresis_demo', 'mcap', meta,
                            compress=True)


if __name__ == '__main__':
    import sys
    print(write_demo_bag(sys.argv[1] if len(sys.argv) > 1 else 'bags'))
    print(write_memory_demo_bag(sys.argv[1] if len(sys.argv) > 1 else 'bags'))
