"""Twelve held-out effects: a rig's physics that the project's model does not contain, kept
apart to measure ONCE, without tuning, how well the discovery finds effects it was never
shown.

Independence: this module was written without reading the discovery's vocabulary or its
corrections (``effects.terms``, ``effects.corrections``, ``effects.term_words``,
``analysis``, ``docs/diagnosis.md``, ``bench_open_world.py``) and without running any
diagnosis. Its physics differs from the twelve effects of ``open_world_set.py``, the five
of ``synth.unlisted`` and the named effects of the catalogue. Every size was chosen, as a
realistic fault of an industrial rig of this scale, before any record with the effect was
generated, and none was changed after (each docstring says why its size is realistic).
The windows were placed, before any record with an effect was generated, inside the part
of the stroke that the benchmark's two records visit (about 36-140 deg), since a fault
where a rig never goes cannot be seen by anyone.

Each class says what a right answer is:

* ``equations``: the equations a correction may act in to be right;
* ``depends``: the acceptable sets of variables of the correction's leading term;
* ``closed_form = None``: not judged on this set; ``where_rad``: a window's (from, to).

Kinds:

* memory: :class:`SealLipPresliding` (elastic presliding of the vane seal lip, Dahl-type),
  :class:`TransmitterHysteresisA` (hysteresis of p_a's transmitter),
  :class:`HoseFlowLagB` (a long hose lags the valve's flow into chamber b);
* windows over the stroke: :class:`HardSpot` (friction over a dented stretch),
  :class:`ScoredCoverVentA` (chamber a vents to atmosphere over a scored stretch),
  :class:`TautHarness` (a cable harness pulls once the arm is past an angle);
* products of states: :class:`SpeedLiftedVaneSeal` (cross leak ~ speed x pressure
  difference), :class:`DamperLinkage` (damping ~ speed x a function of angle),
  :class:`CloggedSilencer` (exhaust back pressure ~ (opening x chamber pressure)^2);
* errors of measured signals: :class:`EncoderLatency` (angle, dynamic),
  :class:`SupplyGroundLoop` (supply, crosstalk from the valve's current),
  :class:`MultiplexerCrosstalkB` (p_b, crosstalk from p_a); with
  :class:`TransmitterHysteresisA` (p_a) every measured signal has an error in the set.
"""
from __future__ import annotations

import math

import numpy as np

from pneumatic_servo._jit import njit
from pneumatic_servo.effects import Component, Param, State
from pneumatic_servo.effects.layout import (
    C_FBRK_NEG,
    C_FBRK_POS,
    C_FKIN,
    C_KAPPA,
    C_MA,
    C_MB,
    C_MSUP,
    C_PE,
    C_PS,
    C_PS_REG,
    C_R,
    C_TE,
    C_TORQUE,
    C_TS,
    C_U,
    K_ALPHA,
    K_NULL,
    K_PE,
    OMEGA,
    P_A,
    P_B,
    T_A,
    T_B,
    THETA,
    add_flow,
)
from pneumatic_servo.physics.gas import ideal_critical_ratio, orifice_flow

DEG = math.pi / 180.0
_LAMINAR_BAND = 0.005  # width of the linear region next to pressure ratio 1 (orifices)


@njit(cache=True)
def _ramp_window(angle, lo, hi, edge):
    """1 inside [lo, hi], 0 outside [lo - edge, hi + edge], smoothstep ramps between."""
    if angle <= lo - edge or angle >= hi + edge:
        return 0.0
    if lo <= angle <= hi:
        return 1.0
    u = (angle - (lo - edge)) / edge if angle < lo else ((hi + edge) - angle) / edge
    return u * u * (3.0 - 2.0 * u)


# --- memory ----------------------------------------------------------------------------------
def _presliding_hook(t, x, s, p, P, c, dx):
    # Dahl: the lip's deflection z (-1..1) follows the shaft's angle with a presliding
    # angle p[1] and saturates in sliding; the lip pushes back with p[0] * z
    w, z = x[OMEGA], x[s]
    dx[s] = (w - abs(w) * z) / p[1]
    c[C_TORQUE] -= p[0] * z


class SealLipPresliding(Component):
    """The vane's seal lip deflects elastically before it slides (Dahl presliding friction):
    after each reversal the seal's torque turns over within about a degree, and the lip
    keeps pushing on a stopped shaft. Size: 0.1 N.m is a swollen, over-compressed lip seal
    (about twice the rig's nominal 0.04 N.m Coulomb friction), and 0.015 rad is the lip
    deflecting about 0.2 mm at a 15 mm radius before it slides."""

    name = 'held_out_seal_lip_presliding'
    params = (Param('torque_n_m', 'N.m', 0.1, 0.0, 2.0, 'sliding torque of the lip'),
              Param('presliding_rad', 'rad', 0.015, 1e-4, 0.2,
                    'angle over which the lip deflects before it slides'))
    states = (State('lip_deflection', '1', 1e-4, 'deflection of the lip, -1..1'),)
    mechanics = _presliding_hook
    equations = ('moment_balance',)
    depends = ({'motion_direction'}, {'velocity'}, {'angle', 'motion_direction'})
    closed_form = None
    where_rad = None


@njit(cache=True)
def _backlash_operator(v, width):
    """Output of a play (backlash) of total ``width`` driven by ``v``, starting on ``v[0]``."""
    out = np.empty(len(v))
    if len(v) == 0:
        return out
    half = 0.5 * width
    y = v[0]
    for i in range(len(v)):
        y = min(max(y, v[i] - half), v[i] + half)
        out[i] = y
    return out


def _hysteresis_a(values, signals, core):
    p = np.ascontiguousarray(signals['p_a_pa'], dtype=float)
    return {'p_a_pa': _backlash_operator(p, values['width_pa']) - p}


class TransmitterHysteresisA(Component):
    """Chamber a's pressure transmitter has hysteresis: its diaphragm reads low while the
    pressure rises and high while it falls, by half the band. Size: a band of 2.4 kPa is
    0.4 % of the 6 bar span, about four times a good transmitter's datasheet hysteresis, as
    an overloaded diaphragm shows."""

    name = 'held_out_transmitter_hysteresis_a'
    params = (Param('width_pa', 'Pa', 2.4e3, 0.0, 5e4, 'total width of the hysteresis band'),)
    sensor_error = staticmethod(_hysteresis_a)
    equations = ('measurement_p_a',)
    # the reading is behind the pressure in the direction it last moved: the sign of its
    # rate, or the pressure against a lagged copy of itself
    depends = ({'p_a_rate'}, {'p_a', 'p_a_lag_5ms'}, {'p_a', 'p_a_lag_20ms'})
    closed_form = None
    where_rad = None


def _hose_lag_hook(t, x, s, p, P, c, dx):
    # runs first among the effects' flows hooks, after the valve's: c[C_MB] is the valve's
    # flow into b at the chamber, which the hose delivers through a first-order lag
    valve = c[C_MB]
    dx[s] = (valve - x[s]) / p[0]
    add_flow(c, 1, x[s] - valve, c[C_TS], x[T_B])


class HoseFlowLagB(Component):
    """A long hose between the valve and chamber b: the gas column delivers the valve's flow
    into b through a first-order lag (the hose stores the difference). Size: 10 ms is the
    order of the transit and filling time of about 3 m of 4 mm hose (3 m / 343 m/s = 9 ms),
    a common retrofit of a valve moved off the actuator."""

    name = 'held_out_hose_flow_lag_b'
    params = (Param('lag_s', 's', 0.01, 1e-4, 0.5, 'time constant of the hose'),)
    states = (State('hose_outflow_kg_s', 'kg/s', 1e-7, 'flow the hose delivers into b'),)
    order = 1
    steady = False
    flows = _hose_lag_hook
    equations = ('mass_balance_b',)
    # -lag * d/dt (valve flow into b (command, p_b)): the rate of p_b, with the command, or
    # p_b against a lagged copy of itself
    depends = ({'p_b_rate'}, {'command', 'p_b_rate'}, {'command', 'p_b', 'p_b_rate'},
               {'p_b', 'p_b_lag_5ms'}, {'p_b', 'p_b_lag_20ms'},
               {'command', 'p_b', 'p_b_lag_5ms'}, {'command', 'p_b', 'p_b_lag_20ms'})
    closed_form = None
    where_rad = None


# --- windows over the stroke -------------------------------------------------------------------
def _hard_spot_hook(t, x, s, p, P, c, dx):
    f = p[0] * _ramp_window(x[THETA], p[1], p[2], 1.0 * DEG)
    c[C_FBRK_POS] += f
    c[C_FBRK_NEG] += f
    if abs(x[OMEGA]) > P[K_ALPHA]:
        c[C_FKIN] += math.copysign(f, x[OMEGA])


class HardSpot(Component):
    """A dent in the housing raises a burr the vane must scrape over between 118 and 128 deg:
    extra Coulomb (and breakaway) friction there only. Size: 0.15 N.m is about three times
    the rig's nominal Coulomb friction, or 0.3 bar of pressure difference, what a knock that
    raises a burr on the bore leaves."""

    name = 'held_out_hard_spot'
    params = (Param('torque_n_m', 'N.m', 0.15, 0.0, 2.0, 'extra friction on the burr'),
              Param('from_rad', 'rad', 118 * DEG, 0.0, 3.4, 'start of the dented stretch'),
              Param('to_rad', 'rad', 128 * DEG, 0.0, 3.4, 'end of the dented stretch'))
    mechanics = _hard_spot_hook
    where_rad = (118 * DEG, 128 * DEG)
    equations = ('moment_balance',)
    depends = ({'angle', 'velocity'}, {'angle', 'motion_direction'})
    closed_form = None


def _vent_hook(t, x, s, p, P, c, dx):
    w = _ramp_window(x[THETA], p[1], p[2], 2.0 * DEG)
    if w > 0.0:
        k = c[C_KAPPA]
        m = orifice_flow(p[0] * w, x[P_A], x[T_A], c[C_PE], c[C_TE], ideal_critical_ratio(k),
                         c[C_R], k, _LAMINAR_BAND)
        add_flow(c, 0, -m, c[C_TE], x[T_A])


class ScoredCoverVentA(Component):
    """A scored arc of the end cover's sealing face, 55-80 deg: while the vane's face seal
    rides on it, chamber a vents past the seal to the bearing's breather (atmosphere),
    through an orifice. Size: 4e-9 m^2 (a 70 um path) passes about 5e-6 kg/s at 6 bar, a
    leak one hears at the breather but a pressure test at another angle misses."""

    name = 'held_out_scored_cover_vent_a'
    params = (Param('area_m2', 'm^2', 4e-9, 0.0, 1e-6, 'leak area on the score'),
              Param('from_rad', 'rad', 55 * DEG, 0.0, 3.4, 'start of the score'),
              Param('to_rad', 'rad', 80 * DEG, 0.0, 3.4, 'end of the score'))
    flows = _vent_hook
    where_rad = (55 * DEG, 80 * DEG)
    equations = ('mass_balance_a',)
    depends = ({'angle', 'p_a'},)
    closed_form = None


def _harness_hook(t, x, s, p, P, c, dx):
    # a one-sided spring with a 1 deg rounded onset (softplus)
    e = 1.0 * DEG
    u = (x[THETA] - p[1]) / e
    stretch = x[THETA] - p[1] if u > 30.0 else e * math.log1p(math.exp(u))
    c[C_TORQUE] -= p[0] * stretch


class TautHarness(Component):
    """A cable and hose harness clipped to the arm is slack until the arm passes 125 deg,
    then pulls back like a spring. Size: 1.5 N.m/rad gives 0.4 N.m at 15 deg past the
    onset, a harness pulling about 4 N on a 0.1 m arm."""

    name = 'held_out_taut_harness'
    params = (Param('rate_n_m_per_rad', 'N.m/rad', 1.5, 0.0, 20.0, 'harness stiffness'),
              Param('onset_rad', 'rad', 125 * DEG, 0.0, 3.4, 'angle where it goes taut'))
    mechanics = _harness_hook
    where_rad = (125 * DEG, 3.31613)
    equations = ('moment_balance',)
    depends = ({'angle'},)
    closed_form = None


# --- products of states ---------------------------------------------------------------------
def _lifted_seal_hook(t, x, s, p, P, c, dx):
    q = p[0] * abs(x[OMEGA]) * (x[P_A] - x[P_B])  # from a to b
    add_flow(c, 0, -q, x[T_B], x[T_A])
    add_flow(c, 1, q, x[T_A], x[T_B])


class SpeedLiftedVaneSeal(Component):
    """The vane's tip seal lifts off the bore hydrodynamically while it slides, so the leak
    across the vane grows with speed times the pressure difference (none at rest). Size:
    2e-11 kg/(s.Pa.rad/s) leaks 4e-6 kg/s at 2 rad/s and 1 bar, a hardened lip that no
    longer follows the bore."""

    name = 'held_out_speed_lifted_vane_seal'
    params = (Param('flow_per_speed_pa', 'kg/(s.Pa.rad/s)', 2e-11, 0.0, 1e-8,
                    'leak per rad/s and Pa of pressure difference'),)
    flows = _lifted_seal_hook
    equations = ('mass_balance_a', 'mass_balance_b')
    depends = ({'velocity', 'p_a', 'p_b'},)
    closed_form = None
    where_rad = None


def _damper_hook(t, x, s, p, P, c, dx):
    lever = math.cos(x[THETA] - p[1])
    c[C_TORQUE] -= p[0] * lever * lever * x[OMEGA]


class DamperLinkage(Component):
    """A linear shock absorber on the arm through a linkage: its lever arm, and so the
    damping it gives the shaft, changes with angle as cos^2(angle - 1.2 rad). Size: a
    200 N.s/m industrial damper on a 12 mm lever gives 0.03 N.m.s/rad at most (0.3 N.m at
    10 rad/s), five times the rig's nominal viscous friction."""

    name = 'held_out_damper_linkage'
    params = (Param('damping_n_m_s', 'N.m.s/rad', 0.03, 0.0, 1.0, 'peak rotary damping'),
              Param('square_angle_rad', 'rad', 1.2, -3.2, 3.2,
                    'angle where the damper is at right angles to its lever'))
    mechanics = _damper_hook
    equations = ('moment_balance',)
    depends = ({'angle', 'velocity'},)
    closed_form = None
    where_rad = None


def _silencer_geometry(t, x, s, p, P, c, dx):
    # the valve exhausts into the silencer's pressure instead of the atmosphere
    c[C_PE] = x[s]


def _silencer_finish(t, x, s, p, P, c, dx):
    # the exhaust is what the valve drew from supply less what the chambers gained
    exhaust = c[C_MSUP] - c[C_MA] - c[C_MB]
    k, r, te = c[C_KAPPA], c[C_R], c[C_TE]
    out = orifice_flow(p[0], x[s], te, P[K_PE], te, ideal_critical_ratio(k), r, k,
                       _LAMINAR_BAND)
    dx[s] = r * te / p[1] * (exhaust - out)


class CloggedSilencer(Component):
    """The valve's exhaust silencer is clogged (oil mist in the sintered bronze): the exhaust
    backs up behind it, with a back pressure that grows as the square of the exhaust flow,
    i.e. of the spool's opening times the exhausting chamber's pressure. Size: 4e-6 m^2 is a
    G1/8 silencer of about 1e-5 m^2 clogged to 40 %, common after a year on unfiltered air;
    2e-6 m^3 is the exhaust passages and the silencer's body."""

    name = 'held_out_clogged_silencer'
    params = (Param('area_m2', 'm^2', 4e-6, 1e-8, 1e-4, 'effective area of the silencer'),
              Param('volume_m3', 'm^3', 2e-6, 1e-7, 1e-4, 'exhaust volume before it',
                    fit=False))
    states = (State('exhaust_pressure_pa', 'Pa', 5.0, 'pressure before the silencer'),)
    geometry = _silencer_geometry
    finish = _silencer_finish
    equations = ('mass_balance_a', 'mass_balance_b')
    depends = ({'command', 'p_a', 'p_b'}, {'command', 'p_a'}, {'command', 'p_b'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [core['atmospheric_pressure_pa']]


# --- errors of measured signals -------------------------------------------------------------
def _encoder_latency(values, signals, core):
    t = np.asarray(signals['t_s'], dtype=float)
    angle = np.asarray(signals['angle_rad'], dtype=float)
    if len(t) < 2:
        return {'angle_rad': np.zeros(len(angle))}
    return {'angle_rad': np.interp(t - values['latency_s'], t, angle) - angle}


class EncoderLatency(Component):
    """The absolute encoder is read over a serial link that latches its position one transfer
    before the pressures are sampled: the angle reads late, by the latency times the speed.
    Size: 2 ms is one SSI transfer and processing cycle of a common industrial encoder
    interface polled at 500 Hz."""

    name = 'held_out_encoder_latency'
    params = (Param('latency_s', 's', 0.002, 0.0, 0.05, 'how late the angle is read'),)
    sensor_error = staticmethod(_encoder_latency)
    steady = False
    equations = ('measurement_angle',)
    depends = ({'velocity'},)
    closed_form = None
    where_rad = None


def _ground_loop_hook(t, x, s, p, P, c, dx):
    # the supply transmitter reads high by p[0] per volt the command is off the null (the
    # solenoid's current through a shared return): the rig has less than its reading says
    e = p[0] * abs(c[C_U] - P[K_NULL])
    c[C_PS] -= e
    c[C_PS_REG] -= e


class SupplyGroundLoop(Component):
    """The supply transmitter shares its 0 V return with the valve's solenoid driver: the
    driver's current, which grows with how far the command is from 5 V, shifts the
    transmitter's signal, so the supply reads high while the valve is driven (the model is
    fed the reading). Size: 1.5 kPa/V reads 7.5 kPa (1.25 % of span) high at full drive, a
    common ground-loop fault of some 60 mOhm of shared return carrying 2 A."""

    name = 'held_out_supply_ground_loop'
    params = (Param('error_pa_per_v', 'Pa/V', 1.5e3, -2e4, 2e4,
                    'reading minus truth per volt of command off the null'),)
    supply = _ground_loop_hook
    order = 5
    equations = ('measurement_supply',)
    depends = ({'command'}, {'command', 'supply'})
    closed_form = None
    where_rad = None


def _mux_crosstalk(values, signals, core):
    pa = np.asarray(signals['p_a_pa'], dtype=float)
    pb = np.asarray(signals['p_b_pa'], dtype=float)
    return {'p_b_pa': values['fraction'] * (pa - pb)}


class MultiplexerCrosstalkB(Component):
    """The acquisition's multiplexed ADC samples p_b right after p_a and its sample-and-hold
    does not settle through the transmitters' filter: p_b reads a fraction of p_a's
    difference from it (ghosting). Size: 2 % is the settling error of a fast multiplexer
    behind a high-impedance anti-aliasing filter, a known fault of such set-ups."""

    name = 'held_out_mux_crosstalk_b'
    params = (Param('fraction', '1', 0.02, -0.5, 0.5, 'fraction of p_a - p_b read into p_b'),)
    sensor_error = staticmethod(_mux_crosstalk)
    equations = ('measurement_p_b',)
    depends = ({'p_a', 'p_b'}, {'p_a'})
    closed_form = None
    where_rad = None


SET = (SealLipPresliding, TransmitterHysteresisA, HoseFlowLagB, HardSpot, ScoredCoverVentA,
       TautHarness, SpeedLiftedVaneSeal, DamperLinkage, CloggedSilencer, EncoderLatency,
       SupplyGroundLoop, MultiplexerCrosstalkB)
