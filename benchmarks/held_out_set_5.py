"""A fifth set of held-out effects (twelve): a rig's physics that the project's model does
not contain, kept apart to measure ONCE, without tuning, how well the discovery finds effects
it was never shown.

Independence: this module was written without reading the discovery's vocabulary or its
corrections (``effects.terms``, ``effects.term_words``, ``effects.corrections``,
``effects.operators``), ``analysis``, ``docs/diagnosis.md``, ``bench_open_world.py``,
``open_world_set.py``, ``synth.unlisted``, the open-world tests, ``tests/test_terms.py``,
``tests/test_judgement.py`` or the README, and without running any diagnosis, benchmark or
test. Slips, all of names or of words about the benchmark, none of a forbidden file's
content: directory listings of ``benchmarks/`` and ``pneumatic_servo/effects/`` showed the
forbidden files' names; ``git status`` showed that a file under ``analysis/diagnosis/`` is
modified (its name only); and ``git log`` of ``held_out_set_4.py`` printed that commit's
message, which says that ``bench_open_world --oracle`` asks of each confident wrong name
whether the truth fitted beside it explains the held-out data better, and that on set 3 it
did for 2 of 4 (keyway play, dwell stiction) and not for the teed cylinder and the
slider-crank. Nothing here was chosen or sized with that in mind.

Its physics differs from the effects of ``held_out_set.py`` to ``held_out_set_4.py``, from
the earlier open-world and unlisted effects (solenoid hysteresis, shaft-encoder coupling
play, a lagging transducer, a part-stroke vane leak, a track detent, friction growing with
mean pressure or with |p_a - p_b|, a supply offset, a p_b gain error, an encoder scale
error, an eccentric code wheel, a gravity arm, a spring-balanced arm, a pilot line into
chamber a, a larger bore of b, a valve dead band, a transmitter offset) and from the named
effects of the catalogue and of the paper's parts. Every size was chosen, as what a real
rig of this scale (the paper's SMC MSQA30A actuator, FESTO MPYE-5-M5 valve, 0-0.6 MPa
transmitters, 20,000 P/R encoder, 0.6 MPa gauge supply) would have, before any record with
the effect was generated, and none was changed after (each docstring says why its size is
realistic). The windows were placed, before any record with an effect was generated, inside
the part of the stroke that the benchmark's two records visit (as told: the closed loop's
steps hold at about 39, 64, 72, 91, 126-140 deg and move through 36-140 deg; the open-loop
chirp stays within 100-124 deg).

Scales of the rig used to size them (from the model's nominal values): 1 bar of pressure
difference gives 0.485 N.m on the shaft (A d_f = 4.85e-6 m^3/rad); the rack travels 7 mm per
radian of the shaft (d_f / 2); the shaft's inertia with the pistons is 1.9e-4 kg.m^2; the
nominal Coulomb friction is 0.042 N.m and the static 0.074 N.m; the spool travels 0.2 mm per
volt and the valve's largest effective area is about 3.4e-6 m^2 (1.5e-6 m^2 at 0.8 mm);
the valve draws up to about 5 g/s (250 l/min ANR) from the supply at full opening; a chamber
holds about 1.3e-5 m^3 at mid-stroke; the paper's wall heat transfer is 15.8 W/(m^2.K) over
1.5e-2 m^2 per chamber.

Each class says what a right answer is:

* ``equations``: the equations a correction may act in to be right;
* ``depends``: the acceptable sets of variables of the correction's leading term;
* ``closed_form = None``: not judged on this set; ``where_rad``: a window's (from, to).

Kinds:

* memory: :class:`ReferenceSwitchResync` (the angle reading remembers in which direction
  the arm last passed a reference switch), :class:`SendOnDeltaB` (p_b's reading is held
  until p_b has moved by a dead band: a memory of the last value sent),
  :class:`ValveRegulatorSupply` (a regulator's friction: a play between the valve's
  consumption and the supply's droop), :class:`BorePortCavityB` (a cavity that keeps the
  pressure of where it was last connected), :class:`AirDashpotStop` (a dashpot's pressure,
  built by the last approach, bleeding off), :class:`SplitChamberA` (half of chamber a
  behind a restriction: a lag);
* windows over the stroke: :class:`ReferenceSwitchResync` (below 81.7 deg, after a
  downward pass), :class:`SlowZoneClamp` (105-120 deg), :class:`BorePortCavityB` (below
  112 deg, crossing at 110-114 deg), :class:`AirDashpotStop` (from 128 deg);
* products of states: :class:`ValveRegulatorSupply` (droop ~ the valve's consumption, a
  function of command and pressures), :class:`SlowZoneClamp` (a function of angle x the
  command), :class:`InflowJetHeatA` (~ inflow^0.8 x (room - t_a)), :class:`LineRegulatorB`
  (b's inflow x a share set by p_b), :class:`BorePortCavityB` (a function of angle x
  orifice flows), :class:`AirDashpotStop` (compression ~ velocity over a volume set by the
  angle), :class:`SplitChamberA` (a volume ~ angle behind an orifice);
* errors of measured signals: angle: :class:`ReferenceSwitchResync` (a memory, static
  between passes), :class:`TenthDegreeAngle` (static); p_a: :class:`CalibrationTableA`
  (static); p_b: :class:`SendOnDeltaB` (dynamic); supply: :class:`ValveRegulatorSupply`
  (dynamic, a memory);
* shapes: closed-form friendly: :class:`CalibrationTableA` (a tent of p_a),
  :class:`IsolatorClipValve` (min(command, 9 V)), :class:`SlowZoneClamp`,
  :class:`LineRegulatorB`, :class:`TenthDegreeAngle` (a floor); awkward: the memories.

Balance equations: valve input (:class:`SlowZoneClamp`, :class:`IsolatorClipValve`), moment
balance (:class:`AirDashpotStop`, :class:`SplitChamberA`), mass balance of a
(:class:`SplitChamberA`, :class:`InflowJetHeatA` through a's pressure), mass balance of b
(:class:`LineRegulatorB`, :class:`BorePortCavityB`), energy balance of a
(:class:`InflowJetHeatA`, :class:`SplitChamberA`); the others are sensor faults (the supply
one a fault of what the valve is fed).

Notes written after the check runs (no code and no size changed; every class generated both
of its records to the end with finite signals; figures are RMS (max) differences from the
same record made without the effect, angle in deg, pressures in kPa):
:class:`CalibrationTableA` is nearly invisible: its tent peaks at 3.0 bar gauge, where the
loop's holds were assumed to sit, but the records keep p_a at 3.5-5.9 bar gauge (closed
loop) and 4.7-5.0 bar gauge (chirp), so only the closed loop's lowest p_a reaches the tent's
upper flank (p_a 0.30 (3.1)); the chirp is unchanged. Changing only the closed loop (the
chirp stays below the command or the angle that triggers them): :class:`ReferenceSwitchResync`
(angle 1.06 (1.71): 1.7 deg low after each downward pass of 80 deg),
:class:`SlowZoneClamp` (angle 0.99 (12.3), p_a 11.6, p_b 14.9), :class:`IsolatorClipValve`
(angle 0.34 (2.6), p_a 5.9, p_b 7.6), :class:`ValveRegulatorSupply` (angle 0.31 (2.1), p_a
8.4 (60), p_b 8.0 (34); in the chirp its state stays at zero, and the 0.005 deg left there
is the adaptive integrator's different steps). :class:`AirDashpotStop` (contact at
128 deg) changes the closed loop (angle 0.83 (6.1), p_a 12.4, p_b 16.2) and the chirp too
(angle 0.38), although the chirp's record stays at 99-124 deg: its discarded 1 s run-in
overshoots to 130 deg and touches the rod once. Both records: :class:`SendOnDeltaB` (p_b 1.4
(3.0) in each), :class:`TenthDegreeAngle` (angle 0.06 (0.11) in each),
:class:`InflowJetHeatA` (closed: angle 0.31, p_a 6.5, p_b 6.6; chirp: angle 0.14),
:class:`SplitChamberA` (closed: angle 0.87 (6.0), p_a 16.2 (133), p_b 16.5; chirp: angle
0.06, p_a 0.4). In the open-loop chirp, which integrates any imbalance into a drift,
:class:`BorePortCavityB` (the chirp crosses its drilling at 112 deg again and again) moves
the arm to 113-137 deg (mean 125, from 112; closed loop: angle 0.34, p_a 7.9, p_b 7.6),
and :class:`LineRegulatorB` drives it onto the end stop at 190 deg for most of the record
(mean 178 deg); in the closed loop it caps the filling of b (p_b at most 604 kPa abs
against 688) and changes p_a by 52 (219) and p_b by 45 (215), the arm holding a few
degrees off its lowest setpoint (reaching 39.9 deg, not 36.3). Two approximations in the
code, not of size: :class:`TenthDegreeAngle`'s truncation is applied before the generator's
encoder quantisation (0.018 deg), and :class:`AirDashpotStop`'s rod is taken to follow the
arm even where the contact force would be negative (then it gives no torque).
"""
from __future__ import annotations

import math

import numpy as np

from pneumatic_servo._jit import njit
from pneumatic_servo.effects import Component, Param, State
from pneumatic_servo.effects.layout import (
    C_CIRCUIT,
    C_CP,
    C_CV,
    C_DVA,
    C_HB,
    C_KAPPA,
    C_MA,
    C_MB,
    C_MSUP,
    C_PE,
    C_PS,
    C_QA,
    C_R,
    C_TE,
    C_TORQUE,
    C_U,
    C_VA,
    C_XV,
    K_AREA,
    K_DF,
    K_GAIN,
    K_HALF_W,
    K_HOLE_R,
    K_NULL,
    K_STROKE,
    OMEGA,
    P_A,
    P_B,
    SERVO,
    T_A,
    T_B,
    THETA,
    add_flow,
)
from pneumatic_servo.physics.gas import ideal_critical_ratio, orifice_flow

DEG = math.pi / 180.0
_LAMINAR_BAND = 0.005  # width of the linear region next to pressure ratio 1 (orifices)
_SERVO = float(SERVO)


@njit(cache=True)
def _window(angle, lo, hi, edge):
    """1 inside [lo, hi], 0 outside [lo - edge, hi + edge], smoothstep ramps between."""
    if angle <= lo - edge or angle >= hi + edge:
        return 0.0
    if lo <= angle <= hi:
        return 1.0
    u = (angle - (lo - edge)) / edge if angle < lo else ((hi + edge) - angle) / edge
    return u * u * (3.0 - 2.0 * u)


@njit(cache=True)
def _rise(value, lo, hi):
    """0 below ``lo``, 1 above ``hi``, a smoothstep between."""
    if value <= lo:
        return 0.0
    if value >= hi:
        return 1.0
    u = (value - lo) / (hi - lo)
    return u * u * (3.0 - 2.0 * u)


@njit(cache=True)
def _resync(angle, lo, hi):
    """Angle error [rad] of a counter set to ``lo`` at each rising edge of a switch that is
    on over [lo, hi]: entered from below, the edge is at ``lo`` (no error after it); from
    above, at ``hi`` (the reading is ``hi - lo`` low after it). No error before the first
    edge (the counter was synchronised when the record starts)."""
    n = len(angle)
    out = np.zeros(n)
    e = 0.0
    for i in range(1, n):
        a0, a1 = angle[i - 1], angle[i]
        if a0 < lo and a1 >= lo:
            e = 0.0
        elif a0 > hi and a1 <= hi:
            e = lo - hi
        out[i] = e
    return out


@njit(cache=True)
def _send_on_delta(p, delta):
    """The last value sent of ``p``: a new one whenever ``p`` is more than ``delta`` from the
    last value sent; the first sample is sent."""
    n = len(p)
    out = np.empty(n)
    if n == 0:
        return out
    held = p[0]
    for i in range(n):
        if abs(p[i] - held) > delta:
            held = p[i]
        out[i] = held
    return out


# --- errors of measured signals --------------------------------------------------------------
def _resync_error(values, signals, core):
    angle = np.ascontiguousarray(signals['angle_rad'], dtype=float)
    lo = values['edge_up_rad']
    return {'angle_rad': _resync(angle, lo, lo + values['switch_width_rad'])}


class ReferenceSwitchResync(Component):
    """The PLC's counter module re-synchronises the encoder count on every rising edge of a
    reference input ("periodic synchronisation", left on from commissioning), wired to a
    fork light barrier whose vane, on the arm's hub, blocks the beam from 80.0 to 81.7 deg.
    The value loaded was commissioned moving upwards, where the beam is first blocked at
    80.0 deg; moving downwards the beam is first blocked at 81.7 deg, and the counter is set
    to 80.0 deg there: after every downward pass the angle reads 1.7 deg low, until the next
    upward pass sets it right again. A memory of the direction of the last pass through the
    switch, which makes the error, after the first pass, a step of the angle (below the
    switch, after a downward pass). Size: a 1 mm vane at 50 mm from the axis and a 0.5 mm
    beam: the beam is blocked over 1.5 mm / 50 mm = 0.030 rad = 1.7 deg."""

    name = 'held_out5_reference_switch_resync'
    params = (Param('edge_up_rad', 'rad', 80.0 * DEG, 0.0, 3.4,
                    'angle where the beam is first blocked moving upwards'),
              Param('switch_width_rad', 'rad', 1.7 * DEG, 0.0, 0.2,
                    'angle over which the vane blocks the beam'))
    sensor_error = staticmethod(_resync_error)
    steady = False
    equations = ('measurement_angle',)
    # below the switch after a downward pass: the angle, with the direction of the motion
    depends = ({'angle'}, {'angle', 'motion_direction'})
    closed_form = None
    where_rad = (0.0, 81.7 * DEG)


def _table_error(values, signals, core):
    p = np.asarray(signals['p_a_pa'], dtype=float)
    gauge = p - core['atmospheric_pressure_pa']
    tent = np.clip(1.0 - np.abs(gauge - values['breakpoint_gauge_pa']) / values['spacing_pa'],
                   0.0, None)
    return {'p_a_pa': values['error_pa'] * tent}


class CalibrationTableA(Component):
    """Chamber a's transmitter is linearised in the PLC through a five-point table (0, 1.5,
    3.0, 4.5, 6.0 bar gauge). After its last calibration the 3.0 bar point was entered with
    the as-found reading instead of the as-left one: between 1.5 and 4.5 bar gauge the
    reading is high by a tent, nothing at the neighbouring points and the whole error at
    3.0 bar, where the chamber sits at the loop's holds. A static error of p_a, piecewise
    linear. Size: 4.8 kPa (0.8 % of span), the as-found drift of a transmitter a year after
    its calibration."""

    name = 'held_out5_calibration_table_a'
    params = (Param('error_pa', 'Pa', 4.8e3, -5e4, 5e4, 'reading minus truth at the breakpoint'),
              Param('breakpoint_gauge_pa', 'Pa', 3.0e5, 0.0, 1e6,
                    'gauge pressure of the wrong table point', fit=False),
              Param('spacing_pa', 'Pa', 1.5e5, 1e3, 1e6, "distance to the table's next points",
                    fit=False))
    sensor_error = staticmethod(_table_error)
    equations = ('measurement_p_a',)
    depends = ({'p_a'},)
    closed_form = None
    where_rad = None


def _send_on_delta_error(values, signals, core):
    p = np.ascontiguousarray(signals['p_b_pa'], dtype=float)
    return {'p_b_pa': _send_on_delta(p, values['dead_band_pa']) - p}


class SendOnDeltaB(Component):
    """Chamber b's transmitter was replaced by an IO-Link one whose value reaches the
    acquisition through a gateway set to send on change: a new value only when the pressure
    has moved more than a dead band from the value last sent, the last one held in between.
    The reading is a staircase that lags a moving pressure by up to the dead band and holds
    still while the pressure stays within it: a memory (of the last value sent), not a lag,
    a delay or a play (it jumps to the pressure, not to within half a band of it). Size:
    3 kPa, 0.5 % of span, a gateway's usual setting to spare the bus."""

    name = 'held_out5_send_on_delta_b'
    params = (Param('dead_band_pa', 'Pa', 3e3, 0.0, 5e4,
                    'change of p_b that sends a new value'),)
    sensor_error = staticmethod(_send_on_delta_error)
    steady = False
    equations = ('measurement_p_b',)
    # the reading is p_b as it was when last sent: p_b against its rate or a lagged copy
    depends = ({'p_b', 'p_b_rate'}, {'p_b', 'p_b_lag_5ms'}, {'p_b', 'p_b_lag_20ms'},
               {'p_b_rate'})
    closed_form = None
    where_rad = None


def _valve_regulator_supply(t, x, s, p, P, c, dx):
    # the valve is fed the reading less the regulator's shortfall
    c[C_PS] -= x[s]


def _valve_regulator_finish(t, x, s, p, P, c, dx):
    # the shortfall follows the droop p[0] x (the valve's draw from the supply) through a
    # play of total width p[1] (the poppet's and diaphragm's friction), with the response
    # time p[2]; the outlet never rises above the inlet (shortfall >= 0)
    target = p[0] * max(c[C_MSUP], 0.0)
    lo = max(target - 0.5 * p[1], 0.0)
    hi = target + 0.5 * p[1]
    z = x[s]
    if z < lo:
        dx[s] = (lo - z) / p[2]
    elif z > hi:
        dx[s] = (hi - z) / p[2]


class ValveRegulatorSupply(Component):
    """A second pressure regulator (G1/8, the relieving diaphragm kind) was fitted at the
    valve's inlet when the rig ran another product at a lower supply, and was later turned
    up until the valve side read the same as the supply transmitter (on the service unit,
    upstream) at rest. Its outlet droops as the valve draws air, and the friction of its
    poppet and diaphragm makes the droop lag by a band: while the draw rises the outlet
    stays up to half the band above the droop line, while it falls up to half the band
    below it (not below nothing: the outlet cannot exceed its inlet). The valve is fed less
    than the supply reading, by a play of its own consumption (a memory). Size: a droop of
    6e6 Pa per kg/s (30 kPa at the valve's 5 g/s, about what such a regulator's flow curve
    shows at 250 l/min with no margin of inlet pressure), a friction band of 10 kPa
    (regulators state 0.01-0.02 MPa of hysteresis), a response time of 5 ms."""

    name = 'held_out5_valve_regulator_supply'
    params = (Param('droop_pa_per_kg_s', 'Pa.s/kg', 6e6, 0.0, 1e9,
                    "outlet's fall per kg/s drawn by the valve"),
              Param('friction_band_pa', 'Pa', 1e4, 0.0, 2e5,
                    "total width of the outlet's hysteresis"),
              Param('response_s', 's', 5e-3, 1e-4, 0.5, "the regulator's response time",
                    fit=False))
    states = (State('regulator_shortfall_pa', 'Pa', 5.0,
                    'supply reading minus the pressure at the valve'),)
    order = 5
    steady = False
    supply = _valve_regulator_supply
    finish = _valve_regulator_finish
    equations = ('measurement_supply',)
    # the valve's draw from the supply (command and the pressure of the chamber it fills),
    # with a memory of whether it last rose or fell
    depends = ({'command', 'p_a', 'p_b'}, {'command', 'p_a', 'p_b', 'supply'},
               {'command', 'command_direction', 'p_a', 'p_b'})
    closed_form = None
    where_rad = None


def _tenth_degree(values, signals, core):
    angle = np.asarray(signals['angle_rad'], dtype=float)
    q = values['resolution_rad']
    return {'angle_rad': np.floor(angle / q) * q - angle}


class TenthDegreeAngle(Component):
    """The PLC hands the angle on as an integer in tenths of a degree (the HMI's format),
    converted from the counts by integer division, which truncates: the reading is the
    angle rounded down to 0.1 deg, low by 0 to 0.1 deg (0.05 deg on average), a sawtooth of
    the angle. A static error of the angle. Size: 0.1 deg, the resolution of such a word,
    coarser than the encoder's 0.018 deg."""

    name = 'held_out5_tenth_degree_angle'
    params = (Param('resolution_rad', 'rad', 0.1 * DEG, 1e-6, 0.1,
                    'step of the angle handed on'),)
    sensor_error = staticmethod(_tenth_degree)
    equations = ('measurement_angle',)
    depends = ({'angle'},)
    closed_form = None
    where_rad = None


# --- valve input -----------------------------------------------------------------------------
def _slow_zone_hook(t, x, s, p, P, c, dx):
    # in the zone, the set value is held within p[0] V of the valve's centre
    w = _window(x[THETA], p[1], p[2], p[3])
    if w <= 0.0:
        return
    u = min(max(c[C_U], 0.0), 10.0)
    null = P[K_NULL]
    held = min(max(u, null - p[0]), null + p[0])
    lim = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(c[C_XV] + P[K_GAIN] * w * (held - u), -lim), lim)


class SlowZoneClamp(Component):
    """Between 105 and 120 deg the arm passes the operator's loading station, and the
    machine's safety function (reduced speed while the light curtain there is muted) holds
    the valve's set value within 1 V of its centre: the controller's command, which the
    acquisition records, reaches the valve clipped to 4-6 V in that stretch and unchanged
    elsewhere. A window over the stroke times a clip of the command. Size: +-1 V is
    +-0.2 mm of spool, about 6 % of the valve's largest opening, a creep speed of the kind
    set for such a zone; the zone's flag follows the arm over about a degree at each end."""

    name = 'held_out5_slow_zone_clamp'
    params = (Param('limit_v', 'V', 1.0, 0.0, 5.0,
                    'largest distance of the set value from the centre in the zone'),
              Param('from_rad', 'rad', 105 * DEG, 0.0, 3.4, 'start of the zone'),
              Param('to_rad', 'rad', 120 * DEG, 0.0, 3.4, 'end of the zone'),
              Param('edge_rad', 'rad', 1.0 * DEG, 1e-4, 0.2, 'width of the edges',
                    fit=False))
    order = 5
    valve = _slow_zone_hook
    equations = ('valve_input',)
    depends = ({'angle', 'command'},)
    closed_form = None
    where_rad = (105 * DEG, 120 * DEG)


def _isolator_hook(t, x, s, p, P, c, dx):
    u = min(max(c[C_U], 0.0), 10.0)
    if u > p[0]:
        lim = P[K_HALF_W] + P[K_HOLE_R]
        c[C_XV] = min(max(c[C_XV] - P[K_GAIN] * (u - p[0]), -lim), lim)


class IsolatorClipValve(Component):
    """A signal isolator was put into the valve's set-value line to break a ground loop, and
    was powered from the 12 V sensor rail instead of 24 V: its output stage, which needs
    some 3 V of headroom, cannot rise above 9 V, so commands above 9 V reach the valve as
    9 V (below, it passes them unchanged). A static, one-sided clip of the valve's input.
    Size: 9.0 V, i.e. the spool reaches 0.8 mm instead of 1.0 mm towards opening supply to
    a, which leaves about 1.5e-6 of the 3.4e-6 m^2 of the full opening."""

    name = 'held_out5_isolator_clip_valve'
    params = (Param('ceiling_v', 'V', 9.0, 5.0, 10.0, 'highest voltage the isolator passes'),)
    order = 5
    valve = _isolator_hook
    equations = ('valve_input',)
    depends = ({'command'},)
    closed_form = None
    where_rad = None


# --- a heat transfer -------------------------------------------------------------------------
def _jet_heat_hook(t, x, s, p, P, c, dx):
    # the paper's exchange (h, room-temperature walls) is raised by p[0] (inflow / p[1])^p[2]
    # while air flows into a
    m = c[C_MA]
    if m <= 0.0:
        return
    h = p[0] * (m / p[1]) ** p[2]
    c[C_QA] += h * p[3] * (c[C_TE] - x[T_A])


class InflowJetHeatA(Component):
    """Air enters chamber a as a jet from the port, which sweeps the end cover and the bore:
    while a fills, its gas exchanges heat with the walls by forced convection, much more
    than the still gas the paper's constant coefficient describes, growing with the inflow
    as a turbulent jet's Nusselt number does (~ Re^0.8). A heat flow ~ inflow^0.8 x (room -
    t_a): a product of states in the energy balance of a, one-sided (only while a fills).
    Size: 40 W/(m^2.K) more at 2 g/s of inflow (about 80 at the valve's full 5 g/s), i.e.
    3-6 times the paper's 15.8, as measurements of charging chambers find."""

    name = 'held_out5_inflow_jet_heat_a'
    params = (Param('extra_coefficient_w_per_m2_k', 'W/(m^2.K)', 40.0, 0.0, 1000.0,
                    'heat transfer coefficient added at the reference inflow'),
              Param('reference_inflow_kg_s', 'kg/s', 2e-3, 1e-5, 1.0, 'reference inflow',
                    fit=False),
              Param('exponent', '1', 0.8, 0.1, 2.0, 'power of the inflow', fit=False),
              Param('wall_area_m2', 'm^2', 1.5106348e-2, 0.0, 10.0, "a's wall area",
                    fit=False))
    steady = False
    heat = _jet_heat_hook
    equations = ('energy_balance_a', 'mass_balance_a')
    # a heat flow ~ (inflow into a)^0.8 (room - t_a): the inflow from the valve (command,
    # p_a, supply) or from a's balance (p_a, its rate, the volume's rate)
    depends = ({'t_a', 'command', 'p_a'}, {'t_a', 'command', 'p_a', 'supply'},
               {'t_a', 'p_a', 'p_a_rate', 'velocity'}, {'t_a', 'angle', 'p_a', 'p_a_rate',
                                                        'velocity'})
    closed_form = None
    where_rad = None


# --- mass balances ---------------------------------------------------------------------------
def _line_regulator_hook(t, x, s, p, P, c, dx):
    # runs first among the effects' flows hooks, after the paper's parts: c[C_MB] is the
    # valve's net flow into b. Into b it must pass the regulator, whose opening closes over
    # the band p[1] below its setting p[0] (gauge); out of b its check passes freely
    m = c[C_MB]
    if m <= 0.0:
        return
    f = (c[C_PE] + p[0] - x[P_B]) / p[1]
    f = min(max(f, 0.0), 1.0)
    c[C_MB] = f * m
    c[C_HB] = f * c[C_HB]
    c[C_MSUP] -= (1.0 - f) * m


class LineRegulatorB(Component):
    """An in-line regulator with a built-in check valve (the kind fitted into a cylinder's
    line to lower its force on one stroke) sits in the line to port b, set to 4.5 bar gauge
    to soften the arm's return against a fragile part: air flowing to b passes the
    regulator, whose poppet closes as p_b comes up to its setting, so b fills normally
    below it and not above it; air leaving b goes round it through the check. A product of
    states (b's inflow x a share set by p_b), one-sided, closed-form friendly (a clip).
    Size: 4.5 bar gauge, a setting such force-limiting regulators are given, and a
    proportional band of 0.3 bar from fully open to shut, a small regulator's droop."""

    name = 'held_out5_line_regulator_b'
    params = (Param('setting_gauge_pa', 'Pa', 4.5e5, 0.0, 1e6,
                    'gauge pressure at which the regulator shuts'),
              Param('band_pa', 'Pa', 3e4, 1e2, 5e5, 'pressure band over which it closes',
                    fit=False))
    order = 1
    flows = _line_regulator_hook
    equations = ('mass_balance_b',)
    # the inflow into b lost: the valve's flow (command, p_b, supply) cut by a share of p_b,
    # or b's own balance (p_b, its rate, the volume's rate)
    depends = ({'command', 'p_b'}, {'command', 'p_b', 'supply'}, {'command', 'p_a', 'p_b'},
               {'p_b', 'p_b_rate', 'velocity'}, {'angle', 'p_b', 'p_b_rate', 'velocity'})
    closed_form = None
    where_rad = None


def _cavity_hook(t, x, s, p, P, c, dx):
    # the hole is in chamber b below the crossing and in the vented pinion housing above it;
    # while the piston's seal passes it (p[3] +- p[4]) it opens partly to both sides
    share = _rise(x[THETA], p[3] - p[4], p[3] + p[4])  # share of the hole on the housing side
    te, pe, r, k = c[C_TE], c[C_PE], c[C_R], c[C_KAPPA]
    crit = ideal_critical_ratio(k)
    pc = x[s]
    m_b = 0.0  # from b into the cavity
    if share < 1.0:
        m_b = orifice_flow(p[1] * (1.0 - share), x[P_B], x[T_B], pc, te, crit, r, k,
                           _LAMINAR_BAND)
        add_flow(c, 1, -m_b, te, x[T_B])
    m_v = 0.0  # from the cavity to the housing (atmosphere)
    if share > 0.0:
        m_v = orifice_flow(p[2] * share, pc, te, pe, te, crit, r, k, _LAMINAR_BAND)
    dx[s] = r * te / p[0] * (m_b - m_v)  # isothermal cavity at room temperature


class BorePortCavityB(Component):
    """A port was drilled through the wall of one bore, in b's half of the stroke, for a
    pressure switch that once signalled an intermediate position; the switch is still
    screwed in. Its tapping, the switch's port and a short stub form a cavity behind a 2 mm
    drilling, which the piston crosses at 112 deg: below that the cavity is part of
    chamber b, above it it opens into the vented pinion housing behind the piston, and
    while the seal passes the drilling it opens partly to both. So b gains a volume below
    112 deg, and each time the piston uncovers the drilling going down the emptied cavity
    fills from b (and going up it vents what it held): a memory (the cavity keeps the
    pressure of where it was last connected) over part of the stroke. Size: 0.6 cm^3 of
    cavity, 1.5e-6 m^2 of drilling and of the way past the piston's wear band into the
    housing, a crossing of +-2 deg (a 2 mm drilling against a 1.5 mm seal lip, at the
    rack's 7 mm per radian)."""

    name = 'held_out5_bore_port_cavity_b'
    params = (Param('cavity_volume_m3', 'm^3', 6e-7, 1e-9, 1e-4, 'volume of the cavity'),
              Param('hole_area_m2', 'm^2', 1.5e-6, 1e-10, 1e-4,
                    'effective area of the drilling', fit=False),
              Param('vent_area_m2', 'm^2', 1.5e-6, 1e-10, 1e-4,
                    'effective area from the drilling into the housing', fit=False),
              Param('crossing_rad', 'rad', 112 * DEG, 0.0, 3.4,
                    'angle at which the seal passes the drilling'),
              Param('half_band_rad', 'rad', 2.0 * DEG, 1e-4, 0.2,
                    'half the angle over which the seal passes it', fit=False))
    states = (State('cavity_pressure_pa', 'Pa', 5.0, 'pressure in the cavity'),)
    steady = False
    flows = _cavity_hook
    equations = ('mass_balance_b',)
    # below the crossing an extra capacitance of b (its rate), and after a downward crossing
    # a filling that depends on the angle, p_b and how long ago the arm crossed
    depends = ({'angle', 'p_b'}, {'angle', 'p_b', 'p_b_rate'}, {'angle', 'p_b_rate'},
               {'angle', 'velocity', 'p_b'}, {'angle', 'p_b', 'p_b_lag_5ms'})
    closed_form = None
    where_rad = (0.0, 114 * DEG)

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [0.5 * (supply_pa + core['atmospheric_pressure_pa'])]


# --- moment balance --------------------------------------------------------------------------
def _dashpot_hook(t, x, s, p, P, c, dx):
    # p: bore area, lever, contact angle, full volume, orifice, spring, stroke, polytropic
    # index, tip compliance. The rod is pushed in by lever x (angle - contact angle)
    area, arm = p[0], p[1]
    push = arm * (x[THETA] - p[2])
    travel, speed = 0.0, 0.0
    if push > 0.0:
        full = 0.95 * p[6]
        travel = min(push, full)
        if push < full:
            speed = arm * x[OMEGA]
    vol = p[3] - area * travel
    pd, pe, te, r, k = x[s], c[C_PE], c[C_TE], c[C_R], c[C_KAPPA]
    m_out = orifice_flow(p[4], pd, te, pe, te, ideal_critical_ratio(k), r, k, _LAMINAR_BAND)
    dx[s] = p[7] * (pd * area * speed - r * te * m_out) / vol
    if push > 0.0:
        force = p[5] * min(push / p[8], 1.0) + (pd - pe) * area
        if force > 0.0:  # the rod can push the arm, never pull it
            c[C_TORQUE] -= arm * force


class AirDashpotStop(Component):
    """A small air dashpot (a graphite piston in a glass cylinder, with a needle orifice)
    serves as a soft stop for the arm's approach to the placing station: from 128 deg on the
    arm pushes its rod in. Pushed fast, the air it compresses cannot leave through the
    orifice and pushes back; held, it bleeds off within a fraction of a second and only the
    light return spring remains. A torque over a window that depends on how fast and how far
    the arm has come in and on how long ago (the dashpot's pressure is a memory): not a
    viscous damper, a spring or a friction. Size: a 9.3 mm bore (6.8e-5 m^2) and 20 mm of
    stroke (1.66 cm^3 with its dead volume) at 50 mm from the axis, the needle nearly shut
    (3e-9 m^2), a 0.5 N return spring (0.025 N.m), a rubber tip taking 0.2 mm to bear, a
    polytropic index of 1.2: pushed 10 mm in fast it gives some 0.3 N.m (0.6 bar of drive);
    beyond 0.95 of its stroke it bottoms (not reached by these records)."""

    name = 'held_out5_air_dashpot_stop'
    params = (Param('bore_area_m2', 'm^2', 6.8e-5, 1e-7, 1e-2, "area of the dashpot's piston"),
              Param('lever_m', 'm', 0.05, 1e-3, 1.0, 'distance of the contact from the axis',
                    fit=False),
              Param('contact_rad', 'rad', 128 * DEG, 0.0, 3.4,
                    'angle where the arm meets the rod'),
              Param('full_volume_m3', 'm^3', 1.66e-6, 1e-8, 1e-3,
                    'volume with the rod out', fit=False),
              Param('orifice_area_m2', 'm^2', 3e-9, 1e-12, 1e-5, 'effective area of the needle'),
              Param('spring_n', 'N', 0.5, 0.0, 100.0, 'force of the return spring', fit=False),
              Param('stroke_m', 'm', 0.02, 1e-3, 0.2, "the rod's stroke", fit=False),
              Param('polytropic_index', '1', 1.2, 1.0, 1.4, 'index of the compression',
                    fit=False),
              Param('tip_m', 'm', 2e-4, 1e-6, 1e-2, 'travel over which the rubber tip bears',
                    fit=False))
    states = (State('dashpot_pressure_pa', 'Pa', 5.0, 'pressure in the dashpot'),)
    steady = False
    mechanics = _dashpot_hook
    equations = ('moment_balance',)
    # in the window: a function of the angle (volume, spring) and of the recent speed
    depends = ({'angle', 'velocity'}, {'angle', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = (128 * DEG, 128 * DEG + 0.02 / 0.05)

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [core['atmospheric_pressure_pa']]


@njit(cache=True)
def _far_end(theta, omega, P, dead):
    """Volume [m^3] and its rate [m^3/s] of chamber a's far end: its own dead volume and
    one piston's share of the swept volume."""
    th = min(max(theta, 0.0), P[K_STROKE])
    half = 0.5 * P[K_AREA] * P[K_DF]
    return dead + half * th, half * omega


def _split_geometry(t, x, s, p, P, c, dx):
    if c[C_CIRCUIT] != _SERVO:
        return
    v2, dv2 = _far_end(x[THETA], x[OMEGA], P, p[1])
    c[C_VA] -= v2
    c[C_DVA] -= dv2


def _split_flows(t, x, s, p, P, c, dx):
    # the far end (pressure x[s], temperature x[s+1]) fills from and empties into a's port
    # side through the passage p[0]; its gas obeys the same balances as the core's chambers,
    # with half of a's wall
    if c[C_CIRCUIT] != _SERVO:
        return
    p2, t2 = x[s], x[s + 1]
    r, k, cv, cp = c[C_R], c[C_KAPPA], c[C_CV], c[C_CP]
    m = orifice_flow(p[0], x[P_A], x[T_A], p2, t2, ideal_critical_ratio(k), r, k,
                     _LAMINAR_BAND)  # from a's port side into the far end
    add_flow(c, 0, -m, t2, x[T_A])
    v2, dv2 = _far_end(x[THETA], x[OMEGA], P, p[1])
    enthalpy = cp * (x[T_A] if m > 0.0 else t2) * m
    heat = 0.5 * p[2] * p[3] * (c[C_TE] - t2)
    mass = p2 * v2 / (r * t2)
    dt2 = (enthalpy - cv * t2 * m - p2 * dv2 + heat) / (mass * cv)
    dx[s + 1] = dt2
    dx[s] = (r * t2 * m + mass * r * dt2 - p2 * dv2) / v2


def _split_heat(t, x, s, p, P, c, dx):
    # the paper's wall exchange of a is over its whole wall: half of it belongs to the far end
    if c[C_CIRCUIT] != _SERVO:
        return
    c[C_QA] -= 0.5 * p[2] * p[3] * (c[C_TE] - x[T_A])


def _split_mechanics(t, x, s, p, P, c, dx):
    # one of a's two pistons is pushed by the far end's pressure, not by p_a
    if c[C_CIRCUIT] != _SERVO:
        return
    c[C_TORQUE] += 0.5 * P[K_AREA] * P[K_DF] * (x[s] - x[P_A])


class SplitChamberA(Component):
    """Chamber a is the outer ends of the actuator's two bores, joined by a passage drilled
    through the body; the valve's port is on one of them. That passage is partly blocked
    (shreds of sealing tape from port a's fitting, carried in and lodged at its narrow
    end), so the far end fills and empties through a restriction: during fast moves its
    pressure lags p_a, and its piston, which drives the pinion as much as the near one,
    pushes with the lagging pressure. Half of a (a volume ~ angle, with its own gas
    temperature) behind an orifice: a memory (lag) in the mass balance of a and in the
    moment balance; not a stored volume outside the actuator, nor a leak. Size: an
    effective 3e-7 m^2 left of the 2.5 mm passage (a 0.6 mm opening), against the valve's
    3.4e-6 m^2; the far end's own dead volume 1 cm^3 (of the 5 cm^3 of a); the paper's wall
    heat transfer split half and half."""

    name = 'held_out5_split_chamber_a'
    params = (Param('passage_area_m2', 'm^2', 3e-7, 1e-10, 1e-4,
                    'effective area of the blocked passage'),
              Param('far_dead_volume_m3', 'm^3', 1e-6, 1e-8, 1e-4,
                    "dead volume of a's far end", fit=False),
              Param('heat_transfer_coefficient_w_per_m2_k', 'W/(m^2.K)', 15.797, 0.0, 1000.0,
                    'heat transfer coefficient h', fit=False),
              Param('wall_area_m2', 'm^2', 1.5106348e-2, 0.0, 10.0, "a's wall area",
                    fit=False))
    states = (State('far_end_pressure_pa', 'Pa', 5.0, "pressure in a's far end"),
              State('far_end_temperature_k', 'K', 1e-3, "gas temperature in a's far end"))
    steady = False
    geometry = _split_geometry
    flows = _split_flows
    heat = _split_heat
    mechanics = _split_mechanics
    equations = ('mass_balance_a', 'moment_balance', 'energy_balance_a')
    # the far end's pressure is a lagged p_a: the flow into it and its piston's torque go
    # with p_a against a lagged copy or its rate (and the volume: angle, velocity)
    depends = ({'p_a', 'p_a_lag_5ms'}, {'p_a', 'p_a_lag_20ms'}, {'p_a', 'p_a_rate'},
               {'p_a_rate'}, {'p_a', 'p_a_rate', 'velocity'},
               {'angle', 'p_a', 'p_a_rate', 'velocity'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [0.5 * (supply_pa + core['atmospheric_pressure_pa']),
                core['room_temperature_k']]


SET = (ReferenceSwitchResync, CalibrationTableA, SendOnDeltaB, ValveRegulatorSupply,
       SlowZoneClamp, InflowJetHeatA, BorePortCavityB, LineRegulatorB, AirDashpotStop,
       SplitChamberA, TenthDegreeAngle, IsolatorClipValve)
