"""A twelfth set of held-out effects (twelve): a rig's physics that the project's model does
not contain, kept apart to measure ONCE, without tuning, how well the discovery finds
effects it was never shown.

Independence: this module was written without reading the discovery's vocabulary or its
corrections (``effects.terms``, ``effects.variables``, ``effects.bases``,
``effects.term_words``, ``effects.corrections``, ``effects.operators``), anything under
``analysis`` or ``docs``, the README, ``bench_open_world.py``, ``bench_dependence.py``,
``open_world_set.py``, ``synth.unlisted`` or any test, without importing any of them itself
and without running any diagnosis, benchmark, test or git command. What was read:
``held_out_set_11.py`` and ``held_out_set_10.py`` whole; the module docstrings of
``held_out_set.py`` to ``held_out_set_9.py`` (those of sets 1-7 whole, of set 9 in two
printings that together cover it, of set 8 all but its last few lines, where a display cut
it) and, of those nine files, their classes' names and the statements that assign their
``name``, ``equations``, ``depends`` and ``where_rad`` (a parse that printed those and
nothing else); ``effects.base``, ``layout`` and ``effects/__init__`` whole; of ``catalogue``
and ``paper`` their classes' names, the statements assigning their ``name`` and the first
lines of their docstrings, and of ``paper`` also the statements that assign its classes'
slots and hooks (parses); ``model/core.py``; of ``model/simulate.py`` its lines 1-200
(``initial_state``, ``sensor_errors``, ``measured_states``, the settling of the effects'
states) and 330-418 (``Stepper``); of ``model/config.py`` its lines 30-62
(``_check_values``) and 165-215 (``copy``, ``with_effect``, ``with_slot``); ``physics/gas.py``;
``synth.varied`` and ``synth.hidden`` whole; of ``experiment.py`` the ``Experiment`` class's
fields and checks; of ``control/pid.py`` and ``model/circuits.py`` text searches (its gains;
the paper's supply). No web search. Slips, none of a forbidden file's content: unfiltered
listings of ``benchmarks/``, ``pneumatic_servo/`` and ``synth/`` showed the names of
``bench_open_world.py``, ``bench_dependence.py``, ``open_world_set.py``, ``analysis`` and
``unlisted.py``; ``effects/__init__`` names ``CORRECTIONS`` from ``.corrections``, and the
package's registry loads those modules whenever it is used (as every record's generation
here did). Nothing here was chosen or sized with any of that in mind. The check runs kept
their scratch files, compiled kernels and numba's caches in a folder of their own,
``/tmp/ho12``, and generated the records with ``synth.varied``'s own steps (its
``make_record``, copied to keep the physical states as well; checked identical).

Its physics differs from the effects of ``held_out_set.py`` to ``held_out_set_11.py``
(their docstrings and classes, as above, were read for this), from the earlier open-world
and unlisted effects those sets name (solenoid hysteresis, shaft-encoder coupling play, a
lagging transducer, a part-stroke vane leak, a track detent, friction growing with mean
pressure or with |p_a - p_b|, a supply offset, a p_b gain error, an encoder scale error, an
eccentric code wheel, a gravity arm, a spring-balanced arm, a pilot line into chamber a, a
larger bore of b, a valve dead band, a transmitter offset), from the examples the earlier
sets left aside and from the named effects of the catalogue and of the paper's parts. Some
candidates were dropped before any record was made with them: a spring-held radial slide on
the arm flung out by the centrifugal force (the records without any effect exceed its
27 rad/s for 10-24 ms in four steps: it would hardly move), an electromagnetic clutch to a
conveyor switched by the command (a torque limiter's second inertia under a command's latch,
near set 6 and set 11's brake), a feed-forward of the angle left in the output block (set 10
dropped its gravity feed-forward), a toggle of the output block's gain at each pass of a
switch (it comes down to a gain over a window, as set 3's connector), a back-pressure air
sensor bleeding from b except over a window (a leak over a window of another shape), a
regenerator insert in b (near the paper's isothermal chambers), a cold supply (a core
parameter) and, for the angle, a wrapping 8-bit counter and a count lost at each reversal
(near set 4's count loss; the reversals' losses cancel in pairs).

Every size was chosen, as what a real rig of this scale (the paper's SMC MSQA30A actuator,
FESTO MPYE-5-M5 valve, 0-0.6 MPa transmitters, 20,000 P/R encoder, 0.6 MPa gauge supply)
would have, before any record with the effect was generated (each docstring says why its
size is realistic); none was changed after. The angles, levels and times were placed, before
any record with an effect was generated, from the benchmark's two records made without any
effect (``closed_steps`` at 500 Hz, seed 7, and ``chirp`` at 500 Hz, seed 8, both 10 s after
a 1 s run-in, with both integrators, looked at for this): the closed loop holds its run-in at
109 deg, then at about 140, 126, 64, 72, 137, 38, 131, 129, 92 and 73 deg within 36-140 deg
(above 120 deg for 49 % of the time, crossing 105-115 deg 5-8 times), at up to 48 rad/s
(above 20 rad/s for 1.4 % of the time) and 5,100 rad/s^2, its shaft below 0.05 rad/s for
71-73 % of the record and with its set value within 0.1 V of the centre for 66-69 %, in 4-6
stretches over 0.3 s, its chambers at 454-690 kPa abs (p_a above 641 kPa abs 14-15 times,
below 541 kPa abs 48 times), p_a and p_b changing at up to 273 and 228 bar/s (p_b 39 bar/s
RMS), its command at 2.3-7.7 V (1st-99th percentile), the valve's draw at 0.08-2.6 g/s (0.1
at the holds, above 1 g/s for 4 % of the time), the flow out of a or b up to 2.4 g/s (above
1.5 g/s for 0.7 % of the time); the open-loop chirp stays at 100-124 deg (its discarded
run-in swings over 95-130, from chambers at 401 kPa abs), above 105 deg for 94 % of the
time, below 2.9 rad/s and 240 rad/s^2, never still for more than 0.09 s, its chambers at
571-606 kPa abs, p_b changing at up to 5 bar/s (2 RMS), its command at 4.7-5.3 V, its draw
at 0.10-0.15 g/s, the flows out of a and b at most 0.05 g/s.

Scales of the rig used to size them (from the model's nominal values): 1 bar of pressure
difference gives 0.485 N.m on the shaft (A d_f = 4.85e-6 m^3/rad); the shaft's inertia with
the pistons is 1.9e-4 kg.m^2; the nominal Coulomb friction is 0.042 N.m; the spool travels
0.2 mm per volt, its lands overlap the sleeve's holes by 10 um; the pressure transmitters
span 0-0.6 MPa gauge (noise 0.6 kPa, 1 sigma); the encoder's count is 0.018 deg; a chamber
holds about 1.3e-5 m^3 at mid-stroke; the supply is 0.6 MPa gauge (701 kPa abs).

Each class says what a right answer is:

* ``equations``: the equations a correction may act in to be right;
* ``depends``: the acceptable sets of variables of the correction's leading term;
* ``closed_form = None``: not judged on this set; ``where_rad``: a window's (from, to).

Kinds:

* memory: :class:`IntegratingAmplifierCard` (a leaky, clamped integral of the command),
  :class:`SinklessOutputStage` (a one-sided lag: the output capacitor's voltage),
  :class:`SupportRollerWindow` (the roller's speed), :class:`MagneticCouplingTurntable`
  (the coupling's twist and the turntable's speed), :class:`HoseBurstFuseA` (a latch: a
  hysteresis between its closing and reopening flows), :class:`PressureSequenceValveA` (a
  hysteresis of p_a, and the gripper line's pressure), :class:`CheckedReservoirB` (a
  follower of p_b's highs, bled), :class:`ProportionalRegulatorSupply` (an integral action),
  :class:`RestTareA` (a value held from the last rest), :class:`IoLinkDelayB` (a delay);
* windows over the stroke: :class:`SupportRollerWindow` (104-116 deg, with its ramps) and
  :class:`SoftLimitAngle` (from 120 deg up);
* products of states: :class:`SupportRollerWindow` (the contact's load, a function of the
  angle, times the skid's sign and the direction), :class:`MagneticCouplingTurntable` (the
  sine of the twist), :class:`HoseBurstFuseA` (a latch times a's outflow, both set by the
  command and p_a), :class:`PressureSequenceValveA` (a latch set by p_a times an orifice
  flow of p_a), :class:`CheckedReservoirB` (the check's opening, set by p_b against the
  reservoir, times an orifice flow of p_b), :class:`ProportionalRegulatorSupply` (the
  valve's draw, of the command and the pressures, through the regulator's loop),
  :class:`RestTareA` (p_a - p_b held at instants the speed and the command set);
* errors of measured signals: angle: :class:`SoftLimitAngle` (static, over a window); p_a:
  :class:`DisplayRetransmitA` (static), :class:`RestTareA` (dynamic, a memory); p_b:
  :class:`IoLinkDelayB` (dynamic); supply: :class:`ProportionalRegulatorSupply` (dynamic, a
  memory: the valve is fed other than the reading). The records carry no temperature (the
  generator records the command, the angle, p_a, p_b and the supply), so none has an error
  here.

Balance equations: valve input (:class:`IntegratingAmplifierCard`,
:class:`SinklessOutputStage`), moment balance (:class:`SupportRollerWindow`,
:class:`MagneticCouplingTurntable`), mass balance of a (:class:`HoseBurstFuseA`,
:class:`PressureSequenceValveA`), mass balance of b (:class:`CheckedReservoirB`); the others
are sensor faults (the supply one a fault of what the valve is fed).

Notes written after the check runs. Every class generated both of its records to the end
with finite signals (the physical states and the recorded signals), with ``rk4`` for the
closed loop and ``predictor`` for the chirp for the classes at even positions of
:data:`SET`, the reverse for those at odd ones, each parameter given explicitly at its
default (every default within its bounds: asserted, and checked by the records'
configurations); figures are RMS (max) differences of the recorded signals (after the
generator's noise and quantisation, the same seed) from the same record, same integrator,
made without the effect: angle in deg, pressures in kPa. As sets 7 to 11 noted, the closed
loop, whose holds are driven by the measurement noise, takes another path after any change
at all: with ``rk4`` an own state that stays inert leaves it exactly as it was, but the
least physical change (a card limited to 1e-6 V, a roller pressed with 1e-6 N) moved it by
0.09-0.13 deg and 1.9-3.7 kPa RMS; with ``predictor`` an inert own state alone (its step
control) moved it by 0.15-0.26 deg and 2.4-6.1 kPa: the floor; the open-loop chirp is
deterministic (within 0.005 deg and 0.01 kPa of its own record). The sensor errors leave the
physics, and so the noise, as it was: their figures are the errors themselves (against the
encoder's 0.018 deg and the transmitters' 0.6 kPa).

Both records: :class:`IntegratingAmplifierCard` (closed: angle 0.55 (3.8), p_a 10.9 (90),
p_b 10.2 (76), the integrator at -0.11..+0.09 V, beyond +-0.05 V for 22 % of the record,
never at its limit; chirp: angle 72.4 (82.6), p_a 17.7 (39), p_b 30.5 (79): the integral of
the chirp's sine, started at its zero, stays on one side (0.02-0.12 V), and the open loop
drifts onto the upper stop (190 deg) 2.3 s into the record, where it stays for half of it),
:class:`SupportRollerWindow` (closed: angle 0.69 (4.1), p_a 14.2 (95), p_b 15.2 (94): on
the rim for 1 % of the record, entering 6 times, skidding at up to 2.9 m/s, the roller spun
to up to 104 rad/s; chirp: angle 0.58 (1.7), p_a 2.6 (7.9), p_b 3.1 (10.5): on the rim for
83 % of the record, entering 11 times, rolling (skidding for 0.3 % of the contact), the
roller at up to 11 rad/s), :class:`CheckedReservoirB` (closed: angle 0.78 (4.7), p_a 30.1
(124), p_b 28.1 (142), the reservoir at 491-608 kPa abs, its check open for 61 % of the
record, p_b's peaks held to 627 kPa abs (687 without); chirp: angle 77.7 (87.6), p_a 23.8
(88), p_b 49.6 (94): in the run-in the reservoir fills from b (396 to 483 kPa abs) while the
chambers fill, a leads, and the arm drifts up (past 180 deg 0.74 s in); the record stays
at 181-190 deg, at the stop for 94 % of it, the reservoir at 483-575 kPa abs),
:class:`ProportionalRegulatorSupply` (closed: the valve fed 673-696 kPa abs, mean 691,
against the reading's 701: angle 0.51 (2.8), p_a 14.3 (86), p_b 13.9 (72); chirp: fed 691
kPa abs throughout: angle 0.70 (0.86), p_a 9.1 (9.4), p_b 9.1 (9.8): there it acts as a
supply offset, its memory shows in the closed loop only), :class:`SinklessOutputStage`
(closed: angle 41.2 (63.8), p_a 130 (322), p_b 171 (364): a gross fault with this loop: the
one-sided lag turns the PID's dither into a limit cycle, the command beyond +-2 V of the
centre for 80-89 % of each hold's second half, and the arm hunts 20-35 deg wide, 30-50 deg
above each setpoint (55-186 deg); chirp: angle 10.3 (21.1), p_a 0.7 (2.9), p_b 0.9 (3.9):
the capacitor holds the falling halves up by at most 0.045 V, and the open loop drifts up,
to 100-135 deg), :class:`MagneticCouplingTurntable` (closed: angle 0.59 (3.6), p_a 13.5
(103), p_b 11.9 (80), the twist within +-0.55 rad, beyond the pull-out for 1 % of the record
but never a pole slipped, the turntable at up to 40 rad/s: about twice the floor, WEAK in the
closed loop; chirp: angle 0.31 (0.97), p_a 1.3 (4.0), p_b 1.5 (5.1), the twist within
+-0.047 rad: a coupled inertia with its friction), :class:`SoftLimitAngle` (angle reading
9.55 (20.4) closed, clipped for 49 % of the record; 0.52 (4.2) chirp, clipped for 5 %),
:class:`DisplayRetransmitA` (p_a reading 2.88 (5.0) closed, 2.71 (5.0) chirp),
:class:`IoLinkDelayB` (p_b reading 27.4 (164) closed; 1.56 (4.0) chirp, some 2.6 times the
noise). The closed loop only (the chirp never reaches their flows, pressures or rests: its
figures are the floor, or nothing for a sensor error): :class:`HoseBurstFuseA` (closed: angle
7.57 (52.1), p_a 33.3 (265), p_b 34.2 (220): shut three times, in the downward steps at the
record's 2, 5 and 8 s, for 5.8 % of the record in all, once for 0.55 s, the arm creeping down
on the bleed meanwhile (from 100 deg, 0.5 s late at its hold); chirp: 0.005 deg),
:class:`PressureSequenceValveA` (closed: angle 0.77 (9.8), p_a 13.6 (167), p_b 15.9 (165):
three times the valve begins to switch and hunts back, since filling the empty line pulls
p_a below its reset before it is fully over (at most 0.86 of its travel), the line charged
to up to 303 kPa abs and vented again; chirp: 0.005 deg),
:class:`RestTareA` (p_a reading 10.5 (13.9) closed: seven tares, one in the run-in, the
reading off by -13.8..+13.2 kPa between them; chirp: never at rest, unchanged).

Changes after the first runs: one code change, no size changed, no bound narrowed.
:class:`CheckedReservoirB` started its reservoir just below the check's cracking pressure,
where the check is shut: the model's settling of the effects' own states (a Newton step on
each alone) stepped from there along the bleed's flow to an empty reservoir (0 Pa), which
then filled from b in the run-in (closed: angle 1.02 (7.6), p_a 58.3 (246), p_b 57.3 (261);
chirp: angle 78.1 (90.4), p_a 22.9 (85), p_b 167 (409), b drawn down to 175 kPa abs). It now
starts with its check half open (2.5 kPa further down), from where the settling finds the
balance of the check's inflow and the bleed just below the chambers' start (396 kPa abs);
the figures above are after the change, and so are all the bound runs. The docstrings
(the classes' and this one) were written after the first runs; the sizes, placements and
bounds they give are those the code had for the first runs.

Robustness: each class was also run with each parameter at its lower and at its upper bound
(the others at their defaults), both records, with its integrators (168 records): none
raised and every signal stayed finite. Some bounds make rigs that hardly work, finite all the
same: an output stage falling within 1 s moves the closed loop by 31 deg RMS and drives the
chirp onto the upper stop, as the card does at its default and with no leak; a card of
1 ms integral time moves the closed loop by 3.1 deg; a soft limit at 0 deg reads 0; a
roller pressed with 500 N or with a rolling resistance of half its load holds the chirp's
swings back (7-10 deg RMS), one on a 0.3 m rim moves the closed loop by 2.1 deg; a
reservoir of 10 l or bled through 1e-5 m^2 empties b (180-490 kPa RMS), and at every bound
but a shut check the chirp's arm goes onto the upper stop (for a third to all of the
record); a regulator set at 0 Pa gauge
starves the valve (490 kPa RMS, the closed loop's arm 39 deg off), one drooping 1e9 Pa.s/kg
moves the closed loop's pressures by 45 kPa; a fuse without a bleed hole holds the arm in
its descents (24.5 deg RMS); a turntable with 0.5 N.m of bearing friction moves the chirp by
12.5 deg; a sequence valve switched at 0 Pa gauge keeps its line on a throughout, a dead
volume that shifts the chirp by 54 deg; a delay of 0.5 s is 30 kPa RMS closed, 10 chirp; a
display of 1 MPa steps reads 440-480 kPa off; a tare with no dwell tares in the chirp too
(8 kPa RMS). Start-up: the model's settling of the effects' own states leaves the card's
integrator at zero and the output's capacitor at the initial command (5 V), the roller and
the turntable at rest and the coupling untwisted, the fuse open, the sequence valve reset
with its line at atmospheric pressure (the records start below its switching pressure),
the reservoir just below the chambers' start (above) and the regulator at its set less its
droop at the initial draw, its integral at zero; the tare's offset is zero until the first
rest (the closed loop's run-in rests at 109 deg and tares 0.3 s in: p_a reads 5.7 kPa high
until the first rest in the record); the delayed reading holds the first sample.
Approximations in the code, not of size: the card's limiter closes over its last fifth; the
output stage's rise is followed within 0.2 ms; the roller's tyre creeps over 0.05 m/s of
slip before it skids (widened where the slip would settle faster than 50 us, which it never
does at the defaults), its rolling resistance is a friction taken into the model's stiction
and its bearing's drag is smoothed over 1 rad/s; the turntable's bearing friction is
smoothed over 0.01 rad/s (widened likewise, never at the defaults); the fuse reads the
valve's net flow into a (the clearance flows with it) as the flow through it, the line
behind it shut is at atmospheric pressure, its reopening when the draw falls below the
bleed's flow stands for the line's refilling, and the poppet, the sequence valve and the
regulator's outlet are first-order lags behind their latches or targets; the sequence
valve, the check valve and the drain are orifices, the gripper line and the reservoir
isothermal at room temperature, the check opening over 5 kPa; the regulator's loop is a
droop behind an integral (no higher than its inlet, its integral held within +-1 MPa); the
sensor errors (the limit, the tare, the display, the delay) are computed on the true,
sampled signals, before the generator's noise and quantisation: the tare from the true speed
(the PLC's would be a difference of counts) and pressures, the delay interpolated linearly
between samples.
"""
from __future__ import annotations

import math

import numpy as np

from pneumatic_servo._jit import njit
from pneumatic_servo.effects import Component, Param, State
from pneumatic_servo.effects.layout import (
    C_CIRCUIT,
    C_CP,
    C_FBRK_NEG,
    C_FBRK_POS,
    C_FEDGE_NEG,
    C_FEDGE_POS,
    C_FKIN,
    C_HA,
    C_INERTIA,
    C_KAPPA,
    C_MA,
    C_MSUP,
    C_PE,
    C_PS,
    C_PS_REG,
    C_R,
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
_STROKE_RAD = 3.31613  # the model's nominal stroke (190 deg)
_TRACK_S = 2e-4  # [s] time in which the output stage's held voltage follows a rising output
_CREEP_M_S = 0.05  # [m/s] slip over which the roller's tyre creeps before it skids
_SETTLE_S = 5e-5  # [s] fastest a regularised slip may settle (see the roller and the turntable)
_STICK_RAD_S = 0.01  # [rad/s] speed band of the turntable bearing's friction
_CHECK_BAND_PA = 5e3  # [Pa] pressure difference over which a check valve opens fully
_INTEGRAL_MAX_PA = 1e6  # [Pa] anti-windup of the regulator's integral action


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
def _add_friction(c, torque, omega):
    """Add a friction ``torque`` [N.m] >= 0 to the breakaway, the sliding friction at the
    stiction band's edge and the sliding friction, against ``omega``."""
    c[C_FBRK_POS] += torque
    c[C_FBRK_NEG] += torque
    c[C_FEDGE_POS] += torque
    c[C_FEDGE_NEG] += torque
    if omega > 0.0:
        c[C_FKIN] += torque
    elif omega < 0.0:
        c[C_FKIN] -= torque


# --- valve input -----------------------------------------------------------------------------
def _integrating_card_valve(t, x, s, p, P, c, dx):
    # x[s]: the card's integrator [V]: it integrates the set value's distance e from the valve's
    # centre over p[0], leaks within p[2] and is held within +-p[1] by the card's limiter; the
    # card passes e plus its integrator on to the valve
    if c[C_CIRCUIT] != _SERVO:
        return
    e = min(max(c[C_U], 0.0), 10.0) - P[K_NULL]
    z = x[s]
    lim = p[1]
    rate = e / p[0] - z / p[2]
    if rate > 0.0:
        rate *= 1.0 - _rise(z, 0.8 * lim, lim)
    else:
        rate *= 1.0 - _rise(-z, 0.8 * lim, lim)
    dx[s] = rate
    out = min(max(e + min(max(z, -lim), lim), -P[K_NULL]), 10.0 - P[K_NULL])
    half = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(c[C_XV] + P[K_GAIN] * (out - e), -half), half)


class IntegratingAmplifierCard(Component):
    """Between the PLC's analog output and the valve still sits the old machine's valve
    amplifier card, a PI card: its proportional gain was set to one when the PLC took over,
    but its integral part, the old machine's 'load holding' trim, is still switched in. It
    integrates the set value's distance from the valve's centre (integral time 1 s), leaks
    through the resistor across its integrating capacitor (within 10 s) and is held within
    +-0.5 V by its zener limiter; the card passes the set value plus that integral on to the
    valve. The record holds the PLC's command, before the card. A memory of the command (a
    leaky, clamped integral), in the valve's input: not a lag or a delay (it adds to the
    command, growing while the command stays on one side of the centre), a null offset (it
    changes with every move and leaks away), a ramp limit or a dead band. Size: an integral
    time of 1 s and a limit of 10 % of the 5 V half range, the settings of such a trim; the
    leak of a 10 Mohm resistor across a 1 uF capacitor. The records without any effect: the
    closed loop's steps kick the command by up to 5 V from the centre for some 50-100 ms (an
    integral of some 0.1-0.3 V), its holds dither about the centre; the chirp's command
    swings +-0.3 V at 0.5-4 Hz (an integral of up to 0.19 V, on one side of zero: the
    integral of a sine started at its zero)."""

    name = 'held_out12_integrating_amplifier_card'
    params = (Param('integral_time_s', 's', 1.0, 1e-3, 100.0,
                    "the card's integral time (volts of set value per volt per second)"),
              Param('limit_v', 'V', 0.5, 0.0, 5.0, "its limiter: the integrator's largest output"),
              Param('leak_s', 's', 10.0, 1e-2, 1e4, 'time in which the integrator leaks away',
                    fit=False))
    states = (State('card_integral_v', 'V', 1e-6, "the card's integrator"),)
    order = 60
    steady = False
    circuits = ('servo',)
    valve = _integrating_card_valve
    equations = ('valve_input',)
    # the command plus a clipped, leaky integral of its distance from the centre
    depends = ({'command'}, {'command', 'command_direction'})
    closed_form = None
    where_rad = None


def _sinkless_valve(t, x, s, p, P, c, dx):
    # x[s]: the voltage held on the output's filter capacitor: the stage drives it up with the
    # set value at once (followed within _TRACK_S), and it falls only through the load, within
    # p[0]; the valve sees the higher of the set value and that voltage
    if c[C_CIRCUIT] != _SERVO:
        return
    u = min(max(c[C_U], 0.0), 10.0)
    y = x[s]
    if u >= y:
        dx[s] = (u - y) / _TRACK_S
        out = u
    else:
        dx[s] = (u - y) / p[0]
        out = y
    half = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(c[C_XV] + P[K_GAIN] * (out - u), -half), half)


class SinklessOutputStage(Component):
    """The PLC's analog output channel for the valve has lost the lower half of its push-pull
    output stage (its sink transistor failed open after a short on the valve's cable): it
    still drives its output up at once, but lowers it only as fast as the load discharges
    the output's filter capacitance, the EMC capacitor at the valve's connector and the cable
    (0.33 uF), through the valve's set-value input and the module's feedback divider (15 kohm
    together): within 5 ms. So the valve sees every rise of the set value at once and every
    fall late. The record holds the PLC's command, as the module's register holds it. A
    memory of the command, one-sided, in the valve's input: not a lag (rising commands pass
    unchanged), a slew limit, a delay or an offset (it vanishes at a steady command). Size:
    0.33 uF and 15 kohm, 5 ms. The records without any effect: the closed loop's command
    moves by volts within a sample (2 ms) in the steps and by tenths of a volt from sample to
    sample at its holds (its noise-driven dither); the chirp's falls at up to 7.5 V/s."""

    name = 'held_out12_sinkless_output_stage'
    params = (Param('fall_time_s', 's', 5e-3, 1e-5, 1.0,
                    "time in which the output falls (the filter capacitor through the load)"),)
    states = (State('output_capacitor_v', 'V', 1e-6, "the voltage on the output's capacitor"),)
    order = 60
    steady = False
    circuits = ('servo',)
    valve = _sinkless_valve
    equations = ('valve_input',)
    # the command where it rises, a lag of it where it falls
    depends = ({'command', 'command_direction'}, {'command'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [min(max(command_v, 0.0), 10.0)]


# --- moment balance --------------------------------------------------------------------------
def _roller_mechanics(t, x, s, p, P, c, dx):
    # x[s]: the roller's speed [rad/s]. The rim bears on it from p[0] to p[1] (ramps p[2]
    # outside), pressed by p[3]; at the contact, the tyre's friction (p[4] of the load) acts on
    # the slip between the rim's surface (radius p[5]) and the roller's (p[6]), the tyre creeping
    # over _CREEP_M_S (widened where the slip would settle faster than _SETTLE_S); the roller
    # (inertia p[7]) turns against its bearing's drag p[9]; rolling, the tyre's resistance p[8]
    # of the load opposes the arm
    if c[C_CIRCUIT] != _SERVO:
        return
    th = x[THETA]
    w = _rise(th, p[0] - p[2], p[0]) * (1.0 - _rise(th, p[1], p[1] + p[2]))
    wr = x[s]
    drag = p[9] * math.tanh(wr)
    if w <= 0.0:
        dx[s] = -drag / p[7]
        return
    load = p[3] * w
    grip = p[4] * load
    creep = max(_CREEP_M_S, grip * _SETTLE_S * (p[5] * p[5] / c[C_INERTIA]
                                               + p[6] * p[6] / p[7]))
    f = grip * math.tanh((x[OMEGA] * p[5] - wr * p[6]) / creep)
    dx[s] = (f * p[6] - drag) / p[7]
    c[C_TORQUE] -= f * p[5]
    _add_friction(c, p[8] * load * p[5], x[OMEGA])


class SupportRollerWindow(Component):
    """The old machine's arm, 600 mm long, was carried over its working zone by a support
    roller on the frame; the rig's short arm is bolted to the old hub, which still carries
    the old arm's running rim (a steel rim segment of 120 mm diameter), and the roller, a
    30 mm polyurethane-tyred roller on a spring arm, still bears on the rim wherever it passes
    over the roller: from 104 to 116 deg, with 1 deg lead-in ramps. Entering, the arm must
    spin the roller up: the tyre skids until the roller's surface speed matches the rim's,
    and the skid's friction brakes the arm; rolling, the arm carries the roller's inertia
    (reflected with the square of the radius ratio) and the tyre's rolling resistance;
    leaving, the roller coasts down on its bearing's drag, and a re-entry finds it still
    turning (the same way: less skid; the other way: more). A window over the stroke with a
    memory (the roller's speed) and products (the contact's load, a function of the angle,
    times the skid's sign; the rolling resistance times the direction), in the moment
    balance: not a friction over a window alone (the skid depends on the roller's speed and
    lasts until it is spun up), a payload, a stop or a spring. Size: the roller's spring load
    20 N (it carried part of the old arm's weight), the tyre's friction coefficient 0.5 on
    steel and rolling resistance 1.5 % of the load (a polyurethane tyre), its inertia
    5.6e-6 kg.m^2 (50 g at 15 mm radius: 9e-5 kg.m^2 at the shaft, half the shaft's own), its
    sealed bearing's drag 1 mN.m: a skid brakes the arm with up to 0.6 N.m, rolling costs
    0.018 N.m. The window was placed from the records without any effect: the chirp swings
    through 100-124 deg (above 105 deg for 94 % of the time, crossing 115 deg 41 times, 105
    deg 6 times); the closed loop crosses its edges 5-8 times in its steps and holds at 91
    and at 126-140 deg, either side of it."""

    name = 'held_out12_support_roller_window'
    params = (Param('from_rad', 'rad', 104.0 * DEG, 0.0, 3.4,
                    'angle from which the rim bears fully on the roller'),
              Param('to_rad', 'rad', 116.0 * DEG, 0.0, 3.4, 'angle up to which it bears fully'),
              Param('ramp_rad', 'rad', 1.0 * DEG, 1e-4, 0.2,
                    "the rim's lead-in ramps outside that arc", fit=False),
              Param('load_n', 'N', 20.0, 0.0, 500.0, "the roller's spring load on the rim"),
              Param('friction_coefficient', '1', 0.5, 0.0, 2.0,
                    "the tyre's friction coefficient on the rim", fit=False),
              Param('rim_radius_m', 'm', 0.06, 1e-3, 0.3, "the rim's radius", fit=False),
              Param('roller_radius_m', 'm', 0.015, 1e-3, 0.1, "the roller's radius", fit=False),
              Param('roller_inertia_kg_m2', 'kg.m^2', 5.6e-6, 1e-8, 1e-3,
                    "the roller's inertia about its axle"),
              Param('rolling_resistance', '1', 0.015, 0.0, 0.5,
                    "the tyre's rolling resistance, as a share of the load"),
              Param('bearing_drag_n_m', 'N.m', 1e-3, 0.0, 0.05,
                    "the roller bearing's drag", fit=False))
    states = (State('roller_speed_rad_s', 'rad/s', 1e-3, "the roller's speed"),)
    steady = False
    circuits = ('servo',)
    mechanics = _roller_mechanics
    equations = ('moment_balance',)
    # over the rim's arc: a skid until the roller has been spun up (the speed), its inertia
    # (the drive's share, as a payload's) and a rolling resistance (the direction)
    depends = ({'angle', 'velocity'}, {'angle', 'velocity', 'motion_direction'},
               {'angle', 'motion_direction'}, {'angle', 'p_a', 'p_b'},
               {'angle', 'p_a', 'p_b', 'velocity'})
    closed_form = None
    where_rad = (103.0 * DEG, 117.0 * DEG)


def _coupling_mechanics(t, x, s, p, P, c, dx):
    # x[s]: the coupling's twist, the shaft's angle less the turntable's [rad]; x[s+1]: the
    # turntable's speed. The magnets pull with p[0] sin(p[1] twist) (p[1] pole pairs), the
    # can's eddy currents damp the slip with p[3]; the turntable (inertia p[2]) turns against
    # its bearing's friction p[4] (smoothed over _STICK_RAD_S, widened where it would settle
    # faster than _SETTLE_S)
    if c[C_CIRCUIT] != _SERVO:
        return
    wt = x[s + 1]
    slip = x[OMEGA] - wt
    torque = p[0] * math.sin(p[1] * x[s]) + p[3] * slip
    band = max(_STICK_RAD_S, p[4] * _SETTLE_S / p[2])
    dx[s] = slip
    dx[s + 1] = (torque - p[4] * math.tanh(wt / band)) / p[2]
    c[C_TORQUE] -= torque


class MagneticCouplingTurntable(Component):
    """The old machine's small sealed turntable (its dust-tight indexing table) is still
    driven from the shaft's lower end through a magnetic coupling: a permanent-magnet coupling
    of four pole pairs through the housing's stainless can. The turntable is still there,
    empty. The coupling transmits the magnets' pull, a sinusoid of the twist between its
    halves, up to its pull-out torque; beyond that it slips poles, its torque pulsating, and
    it catches again once the slip has slowed enough; the can's eddy currents damp the slip
    a little. So the arm carries a second inertia on a magnetic spring with the turntable's
    friction, and drags it through pulsating torques when the coupling lets go. A memory
    (the coupling's twist and the turntable's speed) in the moment balance: not a payload (it
    is coupled through a spring and lets go beyond its pull-out torque), a friction torque
    limiter (it does not stick; it pulls back periodically with the twist), a resonance of
    the actuator's mounting or a play. Size: a 25 mm coupling of 0.15 N.m pull-out (the
    smallest such couplings, as on small pumps), 4 pole pairs (0.6 N.m/rad at small twist:
    10 Hz with the turntable), the turntable an aluminium disc of 100 mm, 6 mm thick
    (1.5e-4 kg.m^2), on a sealed bearing with a shaft seal (0.01 N.m), eddy damping of
    1e-3 N.m.s/rad. The records without any effect: the closed loop accelerates at up to
    5,100 rad/s^2 (0.75 N.m to carry the turntable: beyond the pull-out), the chirp at up to
    240 rad/s^2 (0.036 N.m: coupled)."""

    name = 'held_out12_magnetic_coupling_turntable'
    params = (Param('peak_torque_n_m', 'N.m', 0.15, 0.0, 5.0,
                    "the coupling's pull-out torque"),
              Param('pole_pairs', '1', 4.0, 1.0, 20.0, "the coupling's pole pairs", fit=False),
              Param('turntable_inertia_kg_m2', 'kg.m^2', 1.5e-4, 1e-5, 1e-2,
                    "the turntable's inertia"),
              Param('eddy_damping_n_m_s_per_rad', 'N.m.s/rad', 1e-3, 0.0, 0.01,
                    "damping of the coupling's slip by its can's eddy currents", fit=False),
              Param('bearing_friction_n_m', 'N.m', 0.01, 0.0, 0.5,
                    "the turntable's bearing and seal friction"))
    states = (State('coupling_twist_rad', 'rad', 1e-7,
                    "the shaft's angle less the turntable's"),
              State('turntable_speed_rad_s', 'rad/s', 1e-4, "the turntable's speed"))
    steady = False
    circuits = ('servo',)
    mechanics = _coupling_mechanics
    equations = ('moment_balance',)
    # a second inertia on a magnetic spring that slips poles: its share of the drive
    # (acceleration) and its friction while coupled, pulsating torques while slipping
    depends = ({'p_a', 'p_b'}, {'p_a', 'p_b', 'velocity'}, {'p_a', 'p_b', 'motion_direction'},
               {'p_a', 'p_b', 'velocity', 'motion_direction'}, {'velocity'},
               {'velocity', 'motion_direction'})
    closed_form = None
    where_rad = None


# --- mass balances ---------------------------------------------------------------------------
def _fuse_flows(t, x, s, p, P, c, dx):
    # runs after the valve's flows (order 90). x[s]: the fuse's poppet, 0 open to 1 shut,
    # following within p[2] its latch: shut once the flow out of a (the valve's net flow, as it
    # would be without the fuse) exceeds p[0], open again once it is below what the bleed hole
    # p[1] passes (the line behind refills and the spring lifts the poppet), kept between.
    # Shut, a's outflow is what the bleed hole passes to the exhausting line (at atmosphere)
    if c[C_CIRCUIT] != _SERVO:
        return
    k = c[C_KAPPA]
    bleed = orifice_flow(p[1], x[P_A], x[T_A], c[C_PE], c[C_TE], ideal_critical_ratio(k),
                         c[C_R], k, _LAMINAR_BAND)
    bleed = max(bleed, 0.0)
    demand = -c[C_MA]
    z = x[s]
    if demand > p[0]:
        target = 1.0
    elif demand < bleed:
        target = 0.0
    else:
        target = 1.0 if z >= 0.5 else 0.0
    dx[s] = (target - z) / p[2]
    q = min(max(z, 0.0), 1.0)
    if demand > 0.0 and q > 0.0:
        held = q * (demand - min(demand, bleed))  # outflow the shut poppet withholds
        c[C_MA] += held
        c[C_HA] += c[C_CP] * x[T_A] * held


class HoseBurstFuseA(Component):
    """The old machine's arm was vertical, and its port a carried a hose-break valve (an
    excess-flow 'air fuse') so that a burst hose would not let the arm drop; it is still
    screwed into a's port. Its poppet, held open by a spring, slams shut when the flow out of
    a through it exceeds its closing flow (the pressure drop across it overcomes the spring),
    and from then on a's air can leave only through its small bleed hole; it opens again once
    the valve no longer draws more than the bleed passes (the line behind it refills through
    the bleed, or the valve fills a, and the spring lifts the poppet). A memory (a latch set
    by a's outflow, reset when that falls to the bleed's) times a's outflow, in the mass
    balance of a: not a throttle (it passes up to its closing flow unhindered), a check valve
    (it closes on a flow's size, not its direction, and latches), a quick exhaust or a leak.
    Size: an M5 hose-break valve for the old 4 mm hose, closing at 75 l/min ANR (1.5 g/s), a
    0.3 mm bleed hole (5e-8 m^2: some 0.07 g/s at 5 bar gauge); the poppet moves within 2 ms.
    The records without any effect: the closed loop's downward steps draw up to 2.4 g/s out
    of a (above 1.5 g/s for 0.74 % of the time), the chirp at most 0.05 g/s."""

    name = 'held_out12_hose_burst_fuse_a'
    params = (Param('closing_flow_kg_s', 'kg/s', 1.5e-3, 0.0, 0.02,
                    'flow out of a at which the fuse slams shut'),
              Param('bleed_area_m2', 'm^2', 5e-8, 0.0, 1e-5,
                    "effective area of the poppet's bleed hole"),
              Param('poppet_s', 's', 2e-3, 1e-4, 0.1, "time in which the poppet moves",
                    fit=False))
    states = (State('fuse_shut', '1', 1e-3, "the fuse's poppet, 0 open to 1 shut"),)
    order = 90
    steady = False
    circuits = ('servo',)
    flows = _fuse_flows
    equations = ('mass_balance_a',)
    # a's outflow (the valve's: command and p_a) cut to a bleed by a latch set by that outflow
    depends = ({'command', 'p_a'}, {'command', 'p_a', 'supply'}, {'command', 'p_a', 'p_b'},
               {'p_a', 'p_a_rate', 'velocity'}, {'angle', 'p_a', 'p_a_rate', 'velocity'})
    closed_form = None
    where_rad = None


def _sequence_flows(t, x, s, p, P, c, dx):
    # x[s]: the sequence valve, 0 reset to 1 switched, following within p[4] its latch: switched
    # once a's gauge pressure is above p[0], reset once it is below p[0] - p[1] (its
    # hysteresis), kept between; x[s+1]: the gripper line's pressure (isothermal at room
    # temperature, volume p[3]). Switched (past 0.45-0.55), the valve connects a to the line
    # through p[2]; reset, it vents the line to atmosphere through p[2]
    if c[C_CIRCUIT] != _SERVO:
        return
    k, r, te = c[C_KAPPA], c[C_R], c[C_TE]
    crit = ideal_critical_ratio(k)
    z = x[s]
    gauge = x[P_A] - c[C_PE]
    if gauge > p[0]:
        target = 1.0
    elif gauge < p[0] - p[1]:
        target = 0.0
    else:
        target = 1.0 if z >= 0.5 else 0.0
    dx[s] = (target - z) / p[4]
    q = _rise(z, 0.45, 0.55)
    pg = max(x[s + 1], 1e3)
    m_in = 0.0
    if q > 0.0:
        m_in = orifice_flow(p[2] * q, x[P_A], x[T_A], pg, te, crit, r, k, _LAMINAR_BAND)
        add_flow(c, 0, -m_in, te, x[T_A])
    m_out = 0.0
    if q < 1.0:
        m_out = orifice_flow(p[2] * (1.0 - q), pg, te, c[C_PE], te, crit, r, k, _LAMINAR_BAND)
    dx[s + 1] = r * te / p[3] * (m_in - m_out)


class PressureSequenceValveA(Component):
    """The old gripper was closed by a pressure sequence valve teed into line a: once a's
    pressure rose above 5.4 bar gauge (the arm pressed home against its part), the valve
    switched and filled the gripper's line from a; below 4.4 bar gauge (its hysteresis, the
    valve's spring against its spool's seal friction) it switched back and vented the line to
    atmosphere. The gripper is gone; its line (1 m of 6 x 4 mm tube and its plugged fittings)
    and the sequence valve are still there. A memory (the valve's hysteresis, and the line's
    pressure) times an orifice flow of p_a into the line, in the mass balance of a: not a
    relief (it charges a fixed volume, then takes nothing, and vents the line, not a), a
    dead volume (the line is connected only after a high pressure and emptied after a low
    one), a lag volume or a leak. Size: an M5 sequence valve (2e-6 m^2), the line's 10 cm^3,
    set at 5.4 bar gauge with 1 bar of hysteresis; it switches within 5 ms. The levels were
    placed from the records without any effect: the closed loop's kicks take p_a above 5.4
    bar gauge (641 kPa abs) 14-15 times (0.7 % of the time), its downward steps below 4.4 bar
    gauge 48 times; the chirp's p_a stays at 4.7-5.0 bar gauge, its run-in starts at 3.0."""

    name = 'held_out12_pressure_sequence_valve_a'
    params = (Param('switch_gauge_pa', 'Pa', 5.4e5, 0.0, 1e6,
                    "a's gauge pressure above which the valve switches"),
              Param('hysteresis_pa', 'Pa', 1e5, 0.0, 1e6,
                    'how far below that it resets'),
              Param('valve_area_m2', 'm^2', 2e-6, 0.0, 1e-5, "the valve's effective area"),
              Param('line_volume_m3', 'm^3', 1e-5, 1e-6, 1e-3, "the gripper line's volume"),
              Param('switch_s', 's', 5e-3, 1e-4, 0.1, 'time in which the valve switches',
                    fit=False))
    states = (State('sequence_switched', '1', 1e-3, 'the valve, 0 reset to 1 switched'),
              State('gripper_line_pa', 'Pa', 5.0, "the gripper line's pressure"))
    steady = False
    circuits = ('servo',)
    flows = _sequence_flows
    equations = ('mass_balance_a',)
    # an orifice flow from a into a volume, connected by a hysteresis of p_a
    depends = ({'p_a'}, {'p_a', 'p_a_rate'}, {'p_a', 'p_a_lag_5ms'}, {'p_a', 'p_a_lag_20ms'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [0.0, core['atmospheric_pressure_pa']]


def _reservoir_flows(t, x, s, p, P, c, dx):
    # x[s]: the reservoir's pressure (isothermal at room temperature, volume p[0]); its check
    # valve (area p[1]) opens once p_b exceeds it by p[2] (fully _CHECK_BAND_PA above) and
    # lets air only into it; its drain cock (p[3]) bleeds it to atmosphere
    if c[C_CIRCUIT] != _SERVO:
        return
    k, r, te = c[C_KAPPA], c[C_R], c[C_TE]
    crit = ideal_critical_ratio(k)
    pt = max(x[s], 1e3)
    m_in = 0.0
    share = _rise(x[P_B] - pt, p[2], p[2] + _CHECK_BAND_PA)
    if share > 0.0:
        m_in = max(orifice_flow(p[1] * share, x[P_B], x[T_B], pt, te, crit, r, k,
                                _LAMINAR_BAND), 0.0)
        add_flow(c, 1, -m_in, te, x[T_B])
    m_out = orifice_flow(p[3], pt, te, c[C_PE], te, crit, r, k, _LAMINAR_BAND)
    dx[s] = r * te / p[0] * (m_in - m_out)


class CheckedReservoirB(Component):
    """The old machine kept its clamp's pressure through short drops of the line with a small
    reservoir behind a check valve, teed into line b; the clamp is gone, the reservoir and
    its check valve are still there, and the reservoir's drain cock has been left cracked
    open. So the reservoir takes air from b whenever p_b rises above the reservoir's pressure
    (by the check's cracking pressure), never gives it back, and loses it slowly through the
    drain: on every rise of p_b above its recent highs (less what has bled since), b's air is
    drawn into a volume four times b's own. A memory (the reservoir's pressure: the highest
    recent p_b, bled) times an orifice flow of p_b, in the mass balance of b: not a dead
    volume (it is one-way: it takes part in b's rises only), a lag volume, a leak (its own
    bleed, 0.01 g/s, is small beside what it takes on a rise) or a relief. Size: a 50 cm^3
    reservoir, an M5 check valve (2e-6 m^2, cracking at 5 kPa), a drain cock cracked to
    1e-8 m^2 (the reservoir bleeding down within some 25 s). The records without any effect:
    p_b at 462-687 kPa abs in the closed loop (about 590 at its holds), at 580-606 in the
    chirp, rising and falling every second or less in both."""

    name = 'held_out12_checked_reservoir_b'
    params = (Param('volume_m3', 'm^3', 5e-5, 1e-6, 1e-2, "the reservoir's volume"),
              Param('check_area_m2', 'm^2', 2e-6, 0.0, 1e-5, "the check valve's effective area"),
              Param('cracking_pa', 'Pa', 5e3, 0.0, 1e5, "the check valve's cracking pressure",
                    fit=False),
              Param('bleed_area_m2', 'm^2', 1e-8, 0.0, 1e-5,
                    'effective area of the cracked drain cock'))
    states = (State('reservoir_pa', 'Pa', 5.0, "the reservoir's pressure"),)
    steady = False
    circuits = ('servo',)
    flows = _reservoir_flows
    equations = ('mass_balance_b',)
    # an orifice flow of p_b into a volume that keeps its highest recent pressure (less a bleed)
    depends = ({'p_b'}, {'p_b', 'p_b_rate'}, {'p_b', 'p_b_lag_5ms'}, {'p_b', 'p_b_lag_20ms'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        # the chambers start at their mid pressure: the reservoir just below it, with its
        # check valve half open, from where the model's settling (a Newton step on this state
        # alone) finds the balance of the check's inflow and the bleed
        mid = 0.5 * (supply_pa + core['atmospheric_pressure_pa'])
        return [max(mid - values['cracking_pa'] - 0.5 * _CHECK_BAND_PA,
                    core['atmospheric_pressure_pa'])]


# --- supply ----------------------------------------------------------------------------------
def _regulator_supply(t, x, s, p, P, c, dx):
    c[C_PS] = max(x[s], 1e3)


def _regulator_finish(t, x, s, p, P, c, dx):
    # x[s]: the pressure the regulator delivers to the valve, following within p[3] (its outlet's
    # filling) its main stage: its set p[0] (gauge) plus its integral action x[s+1], less its
    # droop p[1] per kg/s drawn, no higher than its inlet; x[s+1] integrates the set less the
    # delivered pressure over p[2] (held within +-_INTEGRAL_MAX_PA)
    set_pa = c[C_PE] + p[0]
    integral = x[s + 1]
    target = max(min(set_pa + integral - p[1] * c[C_MSUP], c[C_PS_REG]), c[C_PE])
    dx[s] = (target - x[s]) / p[3]
    rate = (set_pa - x[s]) / p[2]
    if (integral > _INTEGRAL_MAX_PA and rate > 0.0) or (integral < -_INTEGRAL_MAX_PA
                                                       and rate < 0.0):
        rate = 0.0
    dx[s + 1] = rate


class ProportionalRegulatorSupply(Component):
    """The valve is fed through the old machine's electro-pneumatic pressure regulator (a
    proportional regulator of the ITV kind), downstream of the service unit and its supply
    transmitter; the PLC still sets it to 5.9 bar gauge, just below the line. Its small main
    valve droops as soon as the valve draws, and its internal pressure loop (a PI on its
    outlet's sensor) brings the outlet back to its set within some 0.1 s; when the draw stops,
    the outlet overshoots by as much (no higher than the line) until the loop has wound back.
    The supply transmitter, before it, reads the line's 6 bar throughout. The valve is thus
    fed other than the reading: a memory (the regulator's integral action) of the valve's
    draw (set by the command and the pressures): not a droop with the flow (it recovers, and
    rebounds after), a supply offset alone, a play, a tank's sawtooth or a timer. Size: set
    10 kPa below the line's 701 kPa abs; its main stage's droop 15 kPa per g/s (a small
    proportional regulator's: 130 l/min ANR at 40 kPa), recovered within 0.1 s (its response
    time); its outlet fills within 10 ms. The records without any effect: the closed loop
    draws 0.1 g/s at its holds and up to 2.6 g/s in its steps (above 1 g/s for 4 % of the
    time), the chirp 0.10-0.15 g/s throughout."""

    name = 'held_out12_proportional_regulator_supply'
    params = (Param('set_gauge_pa', 'Pa', 5.9e5, 0.0, 1e6, "the regulator's set (gauge)"),
              Param('droop_pa_s_per_kg', 'Pa.s/kg', 1.5e7, 0.0, 1e9,
                    "its main stage's droop per kg/s drawn, before its loop corrects it"),
              Param('recovery_s', 's', 0.1, 1e-3, 10.0,
                    'time in which its loop brings the outlet back to the set'),
              Param('outlet_s', 's', 0.01, 1e-4, 1.0, "time in which its outlet fills",
                    fit=False))
    states = (State('valve_supply_pa', 'Pa', 5.0, 'pressure the regulator delivers'),
              State('regulator_integral_pa', 'Pa', 5.0, "the regulator's integral action"))
    order = 5
    steady = False
    supply = _regulator_supply
    finish = _regulator_finish
    equations = ('measurement_supply',)
    # the valve fed a transient droop of its draw (command and pressures), recovering
    depends = ({'command', 'p_a', 'p_b'}, {'command', 'p_a', 'p_b', 'supply'}, {'supply'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [min(core['atmospheric_pressure_pa'] + values['set_gauge_pa'], supply_pa), 0.0]


# --- errors of measured signals --------------------------------------------------------------
def _soft_limit_error(values, signals, core):
    angle = np.asarray(signals['angle_rad'], dtype=float)
    return {'angle_rad': np.minimum(angle, values['upper_rad']) - angle}


class SoftLimitAngle(Component):
    """The PLC's position-scaling block, copied from the old machine's program, ends in a
    LIMIT function that keeps the angle it passes on within the old machine's working range,
    0-120 deg: the angle reading never goes above 120 deg, wherever the arm is (the
    controller here runs on the counter's own value). A static error of the angle over a
    window (from 120 deg up): not an offset, a scale error, a quantisation or a periodic
    error, and no memory (it reads right again as soon as the arm is below the limit). Size:
    the old machine's top working position, 120 deg. The limit was placed from the records
    without any effect: the closed loop holds above it at 126-140 deg (49 % of the time), the
    chirp swings up to 122-124 deg at the top of some of its swings (5 % of the time)."""

    name = 'held_out12_soft_limit_angle'
    params = (Param('upper_rad', 'rad', 120.0 * DEG, 0.0, 3.4,
                    "the scaling block's upper limit"),)
    sensor_error = staticmethod(_soft_limit_error)
    equations = ('measurement_angle',)
    depends = ({'angle'},)
    closed_form = None
    where_rad = (120.0 * DEG, _STROKE_RAD)


@njit(cache=True)
def _tare_offsets(t, speed, command, diff, still, band, null, dwell, n_avg):
    """The offset a rest-triggered tare subtracts at each sample: once the shaft has been
    slower than ``still`` with ``command`` within ``band`` of ``null`` for ``dwell``, the
    mean of ``diff`` over the last ``n_avg`` samples (once per such rest); zero before the
    first tare."""
    n = len(t)
    out = np.zeros(n)
    timer = 0.0
    done = False
    offset = 0.0
    for i in range(n):
        ok = abs(speed[i]) < still and abs(command[i] - null) < band
        if ok:
            if i > 0:
                timer += t[i] - t[i - 1]
        else:
            timer = 0.0
            done = False
        if ok and not done and timer >= dwell:
            j0 = max(0, i - n_avg + 1)
            acc = 0.0
            for j in range(j0, i + 1):
                acc += diff[j]
            offset = acc / (i + 1 - j0)
            done = True
        out[i] = offset
    return out


def _tare_error(values, signals, core):
    t = np.ascontiguousarray(signals['t_s'], dtype=float)
    if len(t) == 0:
        return {'p_a_pa': np.zeros(0)}
    dt = float(t[1] - t[0]) if len(t) > 1 else 1.0
    n_avg = max(1, int(round(values['average_s'] / dt))) if dt > 0 else 1
    speed = np.ascontiguousarray(signals['velocity_rad_s'], dtype=float)
    command = np.clip(np.ascontiguousarray(signals['command_v'], dtype=float), 0.0, 10.0)
    diff = np.ascontiguousarray(signals['p_a_pa'], dtype=float) - np.ascontiguousarray(
        signals['p_b_pa'], dtype=float)
    offsets = _tare_offsets(t, speed, command, diff, values['still_speed_rad_s'],
                            values['band_v'], core['valve_null_voltage_v'], values['dwell_s'],
                            n_avg)
    return {'p_a_pa': -offsets}


class RestTareA(Component):
    """The old machine measured its drive's load as p_a - p_b and so tared its pressure
    channels at rest: whenever the arm has stood still (below 0.05 rad/s) with the set value
    within 0.1 V of the valve's centre for 0.3 s, the old program, still running, takes the
    mean of p_a - p_b over the last 20 ms and subtracts it from p_a's channel from then on,
    until the next rest. At rest p_a and p_b differ by whatever the stiction holds, so each
    tare sets p_a's reading off by that difference, a new one at every rest. A dynamic error
    of p_a with a memory (the difference held from the last rest): not an offset (it changes
    at each rest), a lag, a crosstalk from p_b (it is the difference at one instant, held) or
    a drift. Size: the old program's settle time of 0.3 s and mean over 20 ms, its rest band
    of 0.1 V and 0.05 rad/s (one encoder count in 6 ms). The thresholds were placed from the
    records without any effect: the closed loop stands still with its set value within 0.1 V
    for 66-69 % of the time, in 4-6 stretches of over 0.3 s, with p_a - p_b at rest within
    some +-15 kPa (the stiction's range); the chirp never stands still for more than
    0.09 s."""

    name = 'held_out12_rest_tare_a'
    params = (Param('dwell_s', 's', 0.3, 0.0, 10.0, 'time at rest after which it tares'),
              Param('band_v', 'V', 0.1, 0.0, 5.0,
                    "distance of the set value from the valve's centre that counts as rest"),
              Param('still_speed_rad_s', 'rad/s', 0.05, 0.0, 10.0,
                    'speed below which the shaft counts as at rest', fit=False),
              Param('average_s', 's', 0.02, 0.0, 1.0, 'time over which the tare averages',
                    fit=False))
    sensor_error = staticmethod(_tare_error)
    steady = False
    equations = ('measurement_p_a',)
    # the reading less p_a - p_b as it was at the last rest
    depends = ({'p_a', 'p_b'}, {'p_a', 'p_b', 'velocity'}, {'command', 'p_a', 'p_b'},
               {'command', 'p_a', 'p_b', 'velocity'})
    closed_form = None
    where_rad = None


def _display_error(values, signals, core):
    p = np.asarray(signals['p_a_pa'], dtype=float)
    pe = core['atmospheric_pressure_pa']
    step = values['step_pa']
    return {'p_a_pa': pe + np.floor((p - pe) / step + 0.5) * step - p}


class DisplayRetransmitA(Component):
    """Chamber a's pressure is read from the old machine's digital pressure display (a panel
    instrument showing bar with one decimal), whose 0-10 V retransmission output is generated
    from the value it displays: the reading moves in steps of 10 kPa, each where the display
    rounds to its next digit. A static error of p_a, a staircase of equal steps over the whole
    range: not a gain error, an offset, a bow or a hysteresis (no memory), and not a stuck
    bit (the steps are the display's, equal and rounded to the nearest). Size: the display's
    last digit, 0.1 bar. The records without any effect: p_a at 454-690 kPa abs in the closed
    loop, 571-603 in the chirp (some four steps), against a noise of 0.6 kPa."""

    name = 'held_out12_display_retransmit_a'
    params = (Param('step_pa', 'Pa', 1e4, 1.0, 1e6, "the display's last digit"),)
    sensor_error = staticmethod(_display_error)
    equations = ('measurement_p_a',)
    depends = ({'p_a'},)
    closed_form = None
    where_rad = None


def _delay_error(values, signals, core):
    p = np.asarray(signals['p_b_pa'], dtype=float)
    t = np.asarray(signals['t_s'], dtype=float)
    if len(t) < 2:
        return {'p_b_pa': np.zeros(len(t))}
    return {'p_b_pa': np.interp(t - values['delay_s'], t, p) - p}


class IoLinkDelayB(Component):
    """Chamber b's transmitter was replaced by an IO-Link transmitter: its process data reach
    the PLC through the IO-Link master's cycle and the fieldbus, 8 ms after the analog
    channels of p_a and of the angle, which are read directly, and the recording takes each
    channel as the PLC has it. So p_b's reading is the chamber's pressure of 8 ms before. A
    dynamic error of p_b alone: not a delay of all the measurements (the angle and p_a are on
    time), a lag (it is a pure delay), a sample-and-hold or a rate limit. Size: the IO-Link
    cycle with the master's and the fieldbus's cycles and the PLC's task, 8 ms. The records
    without any effect: p_b changes at up to 228 bar/s in the closed loop's steps (39 bar/s
    RMS), at up to 5 bar/s in the chirp (2 bar/s RMS)."""

    name = 'held_out12_io_link_delay_b'
    params = (Param('delay_s', 's', 8e-3, 0.0, 0.5,
                    "the reading's delay behind the analog channels"),)
    sensor_error = staticmethod(_delay_error)
    steady = False
    equations = ('measurement_p_b',)
    depends = ({'p_b', 'p_b_rate'}, {'p_b_rate'}, {'p_b', 'p_b_lag_5ms'},
               {'p_b', 'p_b_lag_20ms'})
    closed_form = None
    where_rad = None


SET = (IntegratingAmplifierCard, SoftLimitAngle, SupportRollerWindow, RestTareA,
       CheckedReservoirB, ProportionalRegulatorSupply, SinklessOutputStage, IoLinkDelayB,
       HoseBurstFuseA, MagneticCouplingTurntable, PressureSequenceValveA, DisplayRetransmitA)
