"""The catalogue of candidate missing effects (the contract's 'Effect names'; docs/model.md,
section 6).

Each is a component with named, bounded SI parameters. Defaults are typical
magnitudes for a small rotary actuator like the paper's SMC MSQA30A rig.
"""
import math

from .._jit import njit
from ..physics.gas import ideal_critical_ratio, orifice_flow
from .base import Component, Param, State
from .layout import (
    BLOCKED,
    C_CIRCUIT,
    C_FBRK_NEG,
    C_FEDGE_NEG,
    C_FKIN,
    C_INERTIA,
    C_KAPPA,
    C_MSUP,
    C_PE,
    C_PS,
    C_PS_REG,
    C_R,
    C_TE,
    C_TORQUE,
    C_TS,
    C_VA,
    C_VB,
    C_XV,
    K_DF,
    K_GAIN,
    K_HALF_W,
    K_HOLE_R,
    OMEGA,
    P_A,
    P_B,
    T_A,
    T_B,
    add_flow,
)

_BAND = 0.005  # laminar band next to pressure ratio 1 for the leak orifices


@njit(cache=True, allocates=False)
def _leak(area, p1, t1, p2, t2, c):
    k = c[C_KAPPA]
    return orifice_flow(area, p1, t1, p2, t2, ideal_critical_ratio(k), c[C_R], k, _BAND)


# --- valve ------------------------------------------------------------------
@njit(cache=True, allocates=False)
def _spool_hook(t, x, s, p, P, c, dx):
    dx[s] = (c[C_XV] - x[s]) / p[0]
    c[C_XV] = x[s]


class ValveSpoolDynamics(Component):
    """The spool follows the command with a first-order lag instead of instantly."""

    name = 'valve_spool_dynamics'
    example = {'spool_time_constant_s': 0.008}
    steady = False
    excitation = ('fast command steps or a chirp above 20 Hz (a lag smooths the pressure '
                  'rise, a pure delay only shifts it)')
    summary = 'spool lags the command (first-order, time constant)'
    reference = 'first-order proportional-valve dynamics, e.g. FESTO MPYE datasheet step response'
    params = (Param('spool_time_constant_s', 's', 0.004, 1e-4, 0.2, 'time constant of the spool',
                    plausible=(2e-4, 0.05)),)
    states = (State('spool_position_m', 'm', 1e-8, 'actual spool displacement'),)
    order = 20
    valve = _spool_hook

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        gain, null = core['spool_gain_m_per_v'], core['valve_null_voltage_v']
        return [gain * (min(max(command_v, 0.0), 10.0) - null)]


class TransportDelay(Component):
    """A pure delay between the command and the valve (lines, fieldbus, driver)."""

    name = 'transport_delay'
    example = {'command_delay_s': 0.015}
    steady = False
    shares_host = True
    excitation = ('sharp command steps with the pistons blocked (the response starts late but '
                  'rises as fast)')
    neutral = {'command_delay_s': 0.0}
    summary = 'pure delay between command and flow (lines, bus)'
    reference = 'dead time of signal and pneumatic lines'
    params = (Param('command_delay_s', 's', 0.01, 0.0, 0.2, 'command-to-valve delay',
                    plausible=(0.0, 0.05)),)

    @classmethod
    def input_delay_s(cls, values):
        return values['command_delay_s']


@njit(cache=True, allocates=False)
def _null_offset_hook(t, x, s, p, P, c, dx):
    lim = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(c[C_XV] - P[K_GAIN] * p[0], -lim), lim)


class ValveNullOffset(Component):
    """The valve's true centre is not at the nominal null voltage."""

    name = 'valve_null_offset'
    example = {'null_offset_v': 0.12}
    shares_host = True
    excitation = ('a slow command ramp through 5 V with the pistons blocked, or a closed-port '
                  'table near the centre (the pressure crossing moves)')
    neutral = {'null_offset_v': 0.0}
    summary = "the valve's true centre is not at 5 V"
    reference = 'spool/sleeve manufacturing and driver offset'
    params = (Param('null_offset_v', 'V', 0.05, -1.0, 1.0,
                    'true centre minus nominal centre voltage', plausible=(-0.5, 0.5)),)
    order = 10
    valve = _null_offset_hook


@njit(cache=True, allocates=False)
def _null_leak_hook(t, x, s, p, P, c, dx):
    area = p[0] * math.exp(-(c[C_XV] / p[1]) ** 2)
    ps, ts, pe, te = c[C_PS], c[C_TS], c[C_PE], c[C_TE]
    for ch in range(2):
        pc, tc = x[P_A + ch], x[T_A + ch]
        m_in = _leak(area, ps, ts, pc, tc, c)
        m_out = _leak(area, pc, tc, pe, te, c)
        add_flow(c, ch, m_in, ts, tc)
        add_flow(c, ch, -m_out, te, tc)
        c[C_MSUP] += m_in


class ValveNullLeakage(Component):
    """Near the centre, the lands leak like orifices (turbulent), not like a laminar gap."""

    name = 'valve_null_leakage'
    example = {'null_leak_area_m2': 4e-8}
    excitation = ('a closed-port or flow-rate table at voltages within 0.5 V of the centre '
                  '(the leak has the shape of an orifice, not a gap)')
    neutral = {'null_leak_area_m2': 0.0}
    shares_host = True  # its orifice flow is skipped while the area is zero
    skipped_at_neutral = True
    summary = 'leakage at and near the centre behaves like an orifice, not a laminar gap'
    reference = 'underlap/land leakage of proportional spool valves'
    acts_on = 'pressure'
    params = (
        Param('null_leak_area_m2', 'm^2', 2e-8, 0.0, 1e-6,
              'effective leak area of each land at the centre', plausible=(0.0, 2e-7)),
        Param('null_leak_width_m', 'm', 1e-4, 1e-6, 1e-3,
              'spool travel over which the leak fades (Gaussian width)', fit=False),
    )
    flows = _null_leak_hook


# --- supply -----------------------------------------------------------------
@njit(cache=True, allocates=False)
def _supply_drop_hook(t, x, s, p, P, c, dx):
    c[C_PS] = x[s]


@njit(cache=True, allocates=False)
def _supply_drop_finish(t, x, s, p, P, c, dx):
    ts = c[C_TS]
    m_in = _leak(p[0], c[C_PS_REG], ts, x[s], ts, c)
    dx[s] = c[C_R] * ts / p[1] * (m_in - c[C_MSUP])


class SupplyPressureDrop(Component):
    """The pressure at the valve sags with flow through the regulator and supply line.

    The line is a volume at supply temperature fed through an orifice from
    the regulator, whose pressure is the measured supply.
    """

    name = 'supply_pressure_drop'
    example = {'supply_line_area_m2': 7e-7}
    excitation = ('a flow-rate test at full opening (8-10 V), or large fast steps, with the '
                  'supply pressure measured at the regulator')
    summary = 'supply pressure at the valve sags with flow (line/regulator resistance)'
    reference = 'supply line as a restriction plus volume'
    params = (
        Param('supply_line_area_m2', 'm^2', 3e-6, 1e-8, 2e-5,
              'effective orifice area of regulator and line', plausible=(5e-7, 1e-5)),
        Param('supply_line_volume_m3', 'm^3', 2e-5, 1e-5, 1e-2, 'volume of the supply line',
              fit=False),
    )
    states = (State('valve_supply_pressure_pa', 'Pa', 5.0, 'supply pressure at the valve'),)
    supply = _supply_drop_hook
    finish = _supply_drop_finish

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [supply_pa]


# --- leakage ----------------------------------------------------------------
@njit(cache=True, allocates=False)
def _seal_leak_hook(t, x, s, p, P, c, dx):
    if c[C_CIRCUIT] > BLOCKED:
        return
    m = _leak(p[0], x[P_A], x[T_A], x[P_B], x[T_B], c)
    add_flow(c, 0, -m, x[T_B], x[T_A])
    add_flow(c, 1, m, x[T_A], x[T_B])


class PistonSealLeakage(Component):
    """Gas leaks from chamber a to chamber b across the piston seals."""

    name = 'piston_seal_leakage'
    example = {'seal_leak_area_m2': 3e-8}
    circuits = ('servo', 'blocked')
    excitation = ('pistons blocked with a pressure difference and the valve at its centre '
                  '(the chambers converge to each other)')
    neutral = {'seal_leak_area_m2': 0.0}
    shares_host = True  # its orifice flow is skipped while the area is zero
    skipped_at_neutral = True
    summary = 'gas leaks from chamber a to chamber b across the pistons'
    reference = 'worn or cold piston seals'
    acts_on = 'pressure'
    params = (Param('seal_leak_area_m2', 'm^2', 1e-8, 0.0, 1e-6,
                    'effective orifice area of the seal leak', plausible=(0.0, 1e-7)),)
    flows = _seal_leak_hook


@njit(cache=True, allocates=False)
def _external_leak_hook(t, x, s, p, P, c, dx):
    pe, te = c[C_PE], c[C_TE]
    for ch in range(2 if c[C_CIRCUIT] <= BLOCKED else 1):
        m = _leak(p[ch], x[P_A + ch], x[T_A + ch], pe, te, c)
        add_flow(c, ch, -m, te, x[T_A + ch])


class ExternalLeakage(Component):
    """Gas leaks from each chamber to atmosphere (fittings, rod seals)."""

    name = 'external_leakage'
    example = {'leak_area_a_m2': 2e-8, 'leak_area_b_m2': 1.2e-8}
    circuits = ('servo', 'blocked', 'closed_port')
    excitation = ('pistons blocked with the valve at its centre (both chambers decay towards '
                  'atmosphere)')
    neutral = {'leak_area_a_m2': 0.0, 'leak_area_b_m2': 0.0}
    shares_host = True  # its orifice flow is skipped while the area is zero
    skipped_at_neutral = True
    summary = 'gas leaks from a chamber to atmosphere'
    reference = 'leaky fittings and shaft seals'
    acts_on = 'pressure'
    params = (
        Param('leak_area_a_m2', 'm^2', 5e-9, 0.0, 1e-6, 'leak area, chamber a to atmosphere',
              plausible=(0.0, 1e-7), part='chamber a', mirror='leak_area_b_m2'),
        Param('leak_area_b_m2', 'm^2', 5e-9, 0.0, 1e-6, 'leak area, chamber b to atmosphere',
              plausible=(0.0, 1e-7), part='chamber b', circuits=('servo', 'blocked'),
              mirror='leak_area_a_m2'),
    )
    flows = _external_leak_hook


# --- mechanics --------------------------------------------------------------
@njit(cache=True, allocates=False)
def _load_torque_hook(t, x, s, p, P, c, dx):
    c[C_TORQUE] += p[0]


class ExternalLoadTorque(Component):
    """A constant torque on the shaft (gravity on an offset load, a spring preload)."""

    name = 'external_load_torque'
    example = {'load_torque_n_m': 0.25}
    circuits = ('servo',)
    shares_host = True
    excitation = ('closed-loop holds at several angles (a constant pressure difference at rest '
                  'in both directions of approach)')
    neutral = {'load_torque_n_m': 0.0}
    summary = 'a constant torque acts on the shaft'
    reference = 'Newton: extra term in the moment balance, Eq. 37'
    acts_on = 'angle'
    params = (Param('load_torque_n_m', 'N.m', 0.1, -3.0, 3.0,
                    'torque on the shaft, positive towards increasing angle',
                    plausible=(-1.0, 1.0)),)
    mechanics = _load_torque_hook


@njit(cache=True, allocates=False)
def _payload_hook(t, x, s, p, P, c, dx):
    c[C_INERTIA] += p[0]


class PayloadInertia(Component):
    """Extra inertia of a payload on the shaft."""

    name = 'payload_inertia'
    example = {'payload_inertia_kg_m2': 6e-4}
    circuits = ('servo',)
    steady = False
    shares_host = True
    excitation = 'fast closed-loop setpoint steps (the acceleration phase)'
    neutral = {'payload_inertia_kg_m2': 0.0}
    summary = 'extra inertia on the shaft'
    reference = 'Newton: inertia term of Eq. 37'
    acts_on = 'angle'
    params = (Param('payload_inertia_kg_m2', 'kg.m^2', 5e-4, 0.0, 1.0, 'payload inertia',
                    plausible=(0.0, 0.05)),)
    mechanics = _payload_hook


@njit(cache=True, allocates=False)
def _asym_friction_hook(t, x, s, p, P, c, dx):
    extra = 0.5 * P[K_DF] * p[0]
    c[C_FBRK_NEG] += extra
    c[C_FEDGE_NEG] += extra
    if x[OMEGA] < 0.0:
        c[C_FKIN] -= extra


class AsymmetricFriction(Component):
    """Friction is larger (or smaller) when the shaft turns towards decreasing angle."""

    name = 'asymmetric_friction'
    example = {'extra_negative_friction_n': 8.0}
    circuits = ('servo',)
    shares_host = True
    excitation = 'slow constant-speed moves in both directions'
    neutral = {'extra_negative_friction_n': 0.0}
    summary = 'friction differs with the direction of motion'
    reference = 'direction-dependent seal friction'
    acts_on = 'angle'
    order = 60  # after the friction law it modifies
    params = (Param('extra_negative_friction_n', 'N', 3.0, -5.0, 30.0,
                    'Coulomb and static friction added when turning towards angle 0',
                    plausible=(-5.0, 15.0)),)
    mechanics = _asym_friction_hook


# --- volumes and sensing -----------------------------------------------------
@njit(cache=True, allocates=False)
def _dead_volume_hook(t, x, s, p, P, c, dx):
    if c[C_CIRCUIT] <= BLOCKED:  # the static circuits close the valve ports: no tubing
        c[C_VA] += p[0]
        c[C_VB] += p[1]


class DeadVolume(Component):
    """Chamber dead volumes differ from the nominal (tubing, fittings)."""

    name = 'dead_volume'
    example = {'extra_dead_volume_a_m3': 1.5e-5, 'extra_dead_volume_b_m3': 8e-6}
    circuits = ('servo', 'blocked')
    shares_host = True
    excitation = ('charge/discharge steps with the pistons blocked (the pressure time constant '
                  'at a known volume)')
    neutral = {'extra_dead_volume_a_m3': 0.0, 'extra_dead_volume_b_m3': 0.0}
    summary = 'chamber dead volumes differ from the nominal (tubing)'
    reference = 'tubing between valve and actuator'
    acts_on = 'pressure'
    params = (
        Param('extra_dead_volume_a_m3', 'm^3', 3e-6, -4e-6, 1e-4, 'extra volume of chamber a',
              plausible=(-2e-6, 5e-5), part='chamber a', mirror='extra_dead_volume_b_m3'),
        Param('extra_dead_volume_b_m3', 'm^3', 3e-6, -4e-6, 1e-4, 'extra volume of chamber b',
              plausible=(-2e-6, 5e-5), part='chamber b', mirror='extra_dead_volume_a_m3'),
    )
    geometry = _dead_volume_hook


class SensorDelay(Component):
    """All measurements lag the physical state by a pure delay (filters, DAQ buffering)."""

    name = 'sensor_delay'
    example = {'measurement_delay_s': 0.008}
    steady = False
    shares_host = True
    excitation = ('a supply-pressure step with the valve held open and the pistons blocked '
                  '(only a measurement delay lags the response to supply)')
    separated_from = {'transport_delay': (
        'record a supply-pressure step with the valve held open and the pistons blocked: a '
        'measurement delay lags the pressure response to the supply step, a command delay '
        'does not (both lag command steps alike)')}
    neutral = {'measurement_delay_s': 0.0}
    summary = 'the measurements lag the physical state'
    reference = 'transmitter filtering and acquisition latency'
    params = (Param('measurement_delay_s', 's', 0.005, 0.0, 0.2, 'measurement delay',
                    plausible=(0.0, 0.05)),)

    @classmethod
    def output_delay_s(cls, values):
        return values['measurement_delay_s']


CATALOGUE = (ValveSpoolDynamics, TransportDelay, ValveNullOffset, ValveNullLeakage,
             SupplyPressureDrop, PistonSealLeakage, ExternalLeakage, ExternalLoadTorque,
             PayloadInertia, AsymmetricFriction, DeadVolume, SensorDelay)
