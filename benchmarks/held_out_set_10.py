"""A tenth set of held-out effects (twelve): a rig's physics that the project's model does
not contain, kept apart to measure ONCE, without tuning, how well the discovery finds
effects it was never shown.

Independence: this module was written without reading the discovery's vocabulary or its
corrections (``effects.terms``, ``effects.variables``, ``effects.bases``,
``effects.term_words``, ``effects.corrections``, ``effects.operators``), anything under
``analysis`` or ``docs``, the README, ``bench_open_world.py``, ``bench_dependence.py``,
``open_world_set.py``, ``synth.unlisted`` or any test, without importing any of them itself
and without running any diagnosis, benchmark, test or git command. What was read:
``held_out_set_6.py`` to ``held_out_set_9.py`` whole; of ``held_out_set.py`` to
``held_out_set_5.py`` their module docstrings, their classes' names and the statements that
assign their ``equations``, ``depends`` and ``where_rad`` (a parse that printed those and
nothing else); ``effects.base``, ``layout``, ``paper`` and ``effects/__init__`` whole; of
``catalogue`` its classes' names and the first lines of their docstrings (a text search);
``model/core.py`` and ``model/simulate.py``; ``physics/__init__``, ``gas.py``,
``valve.py``, ``mechanics.py`` and ``friction.py``; ``synth.varied``, ``synth.hidden`` and
``synth.sensors``; ``_jit``; ``experiment.py``; of ``model/config.py`` a text search for
five method names and for the bounds' check, its lines 30-60 (``_check_values``) and
170-215 (``copy``, ``with_effect``, ``with_slot``, ``component_classes``, ``values_of``);
of ``control/pid.py`` a text search for its gains and its ``ControlLaw`` and
``PidController`` classes; of the paper, the lines a text search for its rig's parts found
(the parts' table, the circuit's description); ``ruff.toml`` (the line length). No web
search. Slips, none of a forbidden file's content: a first listing of the repository's top
level, ``benchmarks/`` and ``pneumatic_servo/*`` showed forbidden files' and folders' names
(the README, ``docs``, ``tests``, ``bench_open_world.py``, ``bench_dependence.py``,
``open_world_set.py``, and the names of the files under ``analysis``); a search for files
changed during this work (to see what the check runs wrote) printed the names of two test
files, a package module and git's own files that others changed meanwhile (none was
opened); ``effects/__init__`` names ``CORRECTIONS`` from ``.corrections``, and the
package's registry loads those modules whenever it is used (as every record's generation
here did). Nothing here was chosen or sized with any of that in mind. The check runs kept
their scratch files, compiled kernels and numba's caches in a folder of their own under
``/tmp``; the records without any effect, generated first, used the package's usual caches.

Its physics differs from the effects of ``held_out_set.py`` to ``held_out_set_9.py`` (their
docstrings and classes, as above, were read for this), from the earlier open-world and
unlisted effects those sets name (solenoid hysteresis, shaft-encoder coupling play, a
lagging transducer, a part-stroke vane leak, a track detent, friction growing with mean
pressure or with |p_a - p_b|, a supply offset, a p_b gain error, an encoder scale error, an
eccentric code wheel, a gravity arm, a spring-balanced arm, a pilot line into chamber a, a
larger bore of b, a valve dead band, a transmitter offset), from the examples the earlier
sets left aside and from the named effects of the catalogue and of the paper's parts. Some
candidates were dropped before any record was made with them: an i^2 t guard of the old
valve's solenoids in the output block (the records without any effect keep the command more
than 2.5 V from the centre for 12 ms at most: at a realistic boost time it would never
trip), a centrifugal speed governor on the shaft (its shoes' inertia outweighs their
braking in the steps: mostly a payload), a two-way hydraulic orifice damper (a damper on
the shaft, near set 4's), a hydraulic axis block's load-pressure compensation (at any
sizing either a gain error or nothing at the holds), a gravity feed-forward left in the
block (near the gravity arm), a crosstalk of the valve's current into a reading (set 1's
ground loop), an encoder driven through a flexible shaft (near the cable-driven encoder set
7 left aside), air dissolving in oil puddled in the chambers (under 1 kPa), a transmitter's
self-heating (a slow mean of the pressure, as set 9's charge amplifier) and a
direction-flipped piston lip (its realism unclear).

Every size was chosen, as what a real rig of this scale (the paper's SMC MSQA30A actuator,
FESTO MPYE-5-M5 valve, 0-0.6 MPa transmitters, 20,000 P/R encoder, 0.6 MPa gauge supply)
would have, before any record with the effect was generated (each docstring says why its
size is realistic); none was changed after. The angles, levels and times were placed,
before any record with an effect was generated, from the benchmark's two records made
without any effect (``closed_steps`` at 500 Hz, seed 7, and ``chirp`` at 500 Hz, seed 8,
both 10 s after a 1 s run-in, with both integrators, looked at for this): the closed loop
holds its run-in at 109 deg, then holds at about 140, 126, 64, 72, 137, 38, 131, 129, 91 and
72 deg within 36-140 deg (its shaft at rest for 68 % of the record), at up to 48 rad/s
(above 20 rad/s for 1.4 % of the time) and 5,100 rad/s^2, its chambers at 3.5-5.9 bar gauge
(4.8-5.0 at the holds), p_a - p_b within -213..+204 kPa (beyond +-100 kPa for 4.1 % of the
time), p_a and p_b changing at up to 273 and 228 bar/s (p_a's rate 40 bar/s RMS), its
command at 2.3-7.7 V (1st-99th percentile), more than 2.5 V from the centre for 2.6 % of the
time in stretches of 12 ms at most, the valve's draw at 0.1 g/s at the holds and up to 2.6
g/s in the steps, below 0.3 g/s for 88 % of the time in stretches of up to 1.7 s (nine over
0.5 s), its gases at 271-307 K; the open-loop chirp stays at 100-124 deg (its discarded
run-in swings over 95-130), below 2.9 rad/s and 240 rad/s^2, p_a at 4.70-5.02 and p_b at
4.78-5.04 bar gauge, p_a - p_b within +-19 kPa, changing at up to 4 (a) and 5 (b) bar/s,
its command at 4.7-5.3 V, the valve's draw at 0.10-0.15 g/s.

Scales of the rig used to size them (from the model's nominal values): 1 bar of pressure
difference gives 0.485 N.m on the shaft (A d_f = 4.85e-6 m^3/rad); the racks travel 7 mm per
radian of the shaft (d_f / 2); the shaft's inertia with the pistons is 1.9e-4 kg.m^2; the
nominal Coulomb friction is 0.042 N.m; the spool travels 0.2 mm per volt, its lands overlap
the sleeve's holes by 10 um, the valve's largest effective area is about 3.4e-6 m^2; the
pressure transmitters span 0-0.6 MPa gauge on 1-5 V (noise 0.6 kPa, 1 sigma); the encoder's
count is 0.018 deg; a chamber holds about 1.3e-5 m^3 at mid-stroke (5e-6 m^3 at its end);
the supply is 0.6 MPa gauge (701 kPa abs).

Each class says what a right answer is:

* ``equations``: the equations a correction may act in to be right;
* ``depends``: the acceptable sets of variables of the correction's leading term;
* ``closed_form = None``: not judged on this set; ``where_rad``: a window's (from, to).

Kinds:

* memory: :class:`OvertravelLimitSwitch` (a switch's differential travel),
  :class:`EjectorLeverAbove116` (a state of its own: a lever's angle and speed, behind a
  contact that only pushes), :class:`TimedBlowOffB` (a timer started by a downward pass),
  :class:`StandbyAirSavingSupply` (an idle timer and a regulator's output),
  :class:`UnsignedCounterAtHome` (the lowest angle reached below a limit),
  :class:`FrictionFeedforwardBlock` (a short lag of the speed),
  :class:`DifferentialGaugeDiaphragm` (a diaphragm that follows within 2 ms),
  :class:`LeadCompensatedInputA` (a lead-lag filter's state);
* windows over the stroke: :class:`OvertravelLimitSwitch` (from 132 deg, released below
  130), :class:`EjectorLeverAbove116` (from 116 deg up), :class:`TimedBlowOffB` (below 105
  deg after a downward pass), :class:`UnsignedCounterAtHome` (below 42 deg), and
  :class:`LoadedPotentiometerAngle` (a function of the angle over the whole stroke);
* products of states: :class:`OvertravelLimitSwitch` (the command's upward part x a latch
  set by the angle), :class:`HoldingRegulatorA` (an opening set by p_a x an orifice flow
  from the supply into a), :class:`TimedBlowOffB` (a timer x an orifice flow of p_b),
  :class:`DifferentialGaugeDiaphragm` (each pressure x the rate of a volume set by p_a - p_b),
  :class:`EjectorLeverAbove116` (a contact force set by the angle and the speed jointly),
  :class:`StandbyAirSavingSupply` (the valve's draw, of the command and the pressures, sets a
  timer), :class:`WetJunctionBoxB` (the command against a voltage set by p_b);
* errors of measured signals: angle: :class:`UnsignedCounterAtHome` (dynamic, a memory),
  :class:`LoadedPotentiometerAngle` (static); p_a: :class:`LeadCompensatedInputA` (dynamic);
  p_b: :class:`WetJunctionBoxB` (static, a function of the command and p_b); supply:
  :class:`StandbyAirSavingSupply` (dynamic, a memory: the valve is fed other than the
  reading).

Balance equations: valve input (:class:`OvertravelLimitSwitch`,
:class:`KneeCharacteristicCard`, :class:`FrictionFeedforwardBlock`), moment balance
(:class:`EjectorLeverAbove116`), mass balance of a (:class:`HoldingRegulatorA`,
:class:`DifferentialGaugeDiaphragm`), mass balance of b (:class:`DifferentialGaugeDiaphragm`,
:class:`TimedBlowOffB`); the others are sensor faults (the supply one a fault of what the
valve is fed).

Notes written after the check runs. Every class generated both of its records to the end
with finite signals, with ``rk4`` for the closed loop and ``predictor`` for the chirp for
the classes at even positions of :data:`SET`, the reverse for those at odd ones, each
parameter at its default (all within their bounds: checked for each, and by the records'
configurations); figures are RMS (max) differences of the recorded signals (after the
generator's noise and quantisation, the same seed) from the same record, same integrator,
made without the effect: angle in deg, pressures in kPa. As sets 7 to 9 noted, the closed
loop, whose holds are driven by the measurement noise, takes another path after any change
at all: a holding regulator of 1e-13 m^2 changed it by 0.19 deg and 3.9-4.0 kPa RMS with
``rk4`` (0.11 deg, 2.5-2.8 kPa with ``predictor``), a gauge's diaphragm switched off (its
state kept) by 0.23 deg and 5.3-5.6 kPa with ``predictor`` (nothing with ``rk4``): the
floor; the open-loop chirp is deterministic (within 0.005 deg of its own record, the
adaptive integrator's other steps). The sensor errors leave the physics, and so the noise,
as it was: their figures are the errors themselves (against the encoder's 0.018 deg and the
transmitters' 0.6 kPa).

Both records: :class:`DifferentialGaugeDiaphragm` (closed: angle 1.82 (17.5), p_a 20.1
(158), p_b 19.4 (149), the diaphragm moving +-3.0 cm^3, on its plates 0.3 % of the time;
chirp: angle 3.32 (6.6), p_a 3.8 (12), p_b 4.6 (15), +-0.5 cm^3, the arm at 102-127 deg;
its side volumes alone, the diaphragm held, give 0.82 deg closed and 0.30 deg chirp),
:class:`EjectorLeverAbove116` (closed: angle 0.83 (4.9), p_a 13.9 (64), p_b 13.7 (98), the
lever raised for 46 % of the record, lifting off the dog 19 times, by up to 12.6 deg, in the
decelerations and reversals, and bouncing on its rest stop when it comes back; chirp: angle
4.01 (5.3), p_a 1.4 (9.7), p_b 1.6 (12), picked up twice: the spring keeps the chirp's arm
lower, at 97-121 deg), :class:`HoldingRegulatorA` (closed: angle 0.86 (6.4), p_a 19.9 (141),
p_b 19.7 (113), the regulator open for 2.5 % of the record (fully for 0.6 %), in the
descents, p_a then no lower than 4.0 bar gauge (3.5 without); chirp: angle 39.4 (40.5), p_a
2.3 (15), p_b 2.5 (14): in the discarded run-in, whose chambers start at 3 bar gauge, it
fills a first and drives the arm up to 170 deg; in the record the chirp swings at 140-164
deg with p_a above the set, the regulator shut), :class:`KneeCharacteristicCard` (closed:
angle 1.21 (5.5), p_a 17.8 (142), p_b 17.6 (120); chirp: angle 14.3 (21.6), p_a 4.1 (9.8),
p_b 4.4 (11): the chirp's swings cut to 93-103 deg), :class:`StandbyAirSavingSupply`
(closed: the valve fed 552-701 kPa abs, mean 654, against the reading's 701, lowered in
eight of the record's pauses, for 41 % of the record, and raised again within some 30 ms of
each step's first draw: angle 0.61 (3.4), p_a 52.3 (145), p_b 52.7 (155); chirp: lowered
from 0.5 s into the run-in on, the valve fed 551-564 kPa abs throughout the record: angle
6.72 (8.4), p_a 133 (138), p_b 133 (139): there it acts as a lower supply, its memory shows
in the closed loop), :class:`TimedBlowOffB` (closed: it blows three times, for 0.3 s each,
at the record's 2.0, 5.0 and 8.1 s: angle 1.04 (4.8), p_a 47.0 (181), p_b 44.6 (165);
chirp: once, at 0.25 s, for the 30 ms the arm stays below 105 deg, after which the arm
rides higher, at 111-132 deg from 0.6 s on: angle 8.15 (10.2), p_a 5.1 (40), p_b 5.3 (52)),
:class:`FrictionFeedforwardBlock` (closed: angle 0.59 (3.4), p_a 11.6 (94), p_b 11.2 (75),
three to five times the floor; chirp: angle 9.44 (18.5), p_a 2.4 (5.4), p_b 2.5 (7.2): the
open loop is pushed up in its run-in, to 153 deg, and swings at 104-143 deg in the record),
:class:`LeadCompensatedInputA` (p_a reading 16.3 (108) closed, 0.65 (1.7) chirp),
:class:`WetJunctionBoxB` (p_b reading 2.0 (11.6) closed, -9.1..+11.6 kPa; 1.4 (2.0) chirp,
0.6-2.0 kPa), :class:`LoadedPotentiometerAngle` (angle reading 2.95 (3.64) closed, 1.1 deg
low at 36 deg, 3.6 at 140; 3.25 (3.46) chirp). The closed loop only:
:class:`OvertravelLimitSwitch` (closed: angle 8.43 (30.5), p_a 62.8 (192), p_b 80.3 (253):
made 101 times, 6.7 % of the record; while the setpoint lies above the switch (the holds at
140 and 137 deg, the overshoot of the one at 131) the loop hunts between 109 and 136 deg,
its command at 0 or 10 V for up to half of those seconds, and it hunts on into the next
hold until the arm has come back below 130 deg; chirp: unchanged, 0.005 deg),
:class:`UnsignedCounterAtHome` (angle reading 3.95 (5.69) closed: nothing until the arm
goes below 42 deg, at the record's 5.1 s, to 36.3 deg, then 5.7 deg high to the end; the
chirp never goes below the home: unchanged).

Changes after the first runs: one code change, no size changed, no bound narrowed.
:class:`DifferentialGaugeDiaphragm` at its largest compliance (1e-9 m^3/Pa, 100 cm^3 at
its range) emptied chamber b into the gauge and the stepper failed (its step size collapsed
at 1.05 s); the diaphragm now moves no more than 90 % of the chamber it takes from, a guard
that never binds at the defaults within the stroke (its records, taken again, gave the
figures above exactly).

Robustness: each class was also run with each parameter at its lower and at its upper bound
(the others at their defaults), both records, with its integrators: after the change above
none raised and every signal stayed finite. Some bounds make rigs that hardly work, finite
all the same: an overtravel switch made at 0 deg keeps the arm from moving up (closed
34-127 deg; the chirp drifts onto the lower stop); an ejector lever at rest at 0 deg pushes
the chirp down to 10 deg, a lever's spring of 1 N.m or 10 N.m/rad keeps the closed loop
below 125 deg; a holding regulator set at 1 MPa drives the chirp onto the upper stop (190
deg); a card with no fine slope (a +-1 V dead band) drives the chirp onto the upper stop,
one reaching full output at 1 V from the centre changes the closed loop's pressures by 130
kPa RMS; a gauge of 1e-9 m^3/Pa (with the guard) moves the closed loop by 10 deg RMS and
holds the chirp's arm still, as 1e-4 m^3 on each side does; a blow-off nozzle of 1e-5 m^2
moves the closed loop by 23 deg RMS and drives the chirp onto the upper stop; an air-saving
unit with a standby of 0 Pa gauge starves the valve in every pause (p 484 kPa RMS); a
friction feed-forward of 2 V sends the chirp across the whole stroke; a counter homed at 3.4
rad reads above the stroke (195-292 deg), a potentiometer loaded 10:1 reads 7-37 deg; a wet
film of 100 ohm moves the p_b reading by 95 kPa RMS. Start-up: the model's settling of the
effects' own states (a Newton step on each alone) leaves the ejector lever on its stop
(where its initial state puts it: the records start below it), the blow-off's latch at
'below' when the arm starts below the trigger (the chirp, at 95 deg) without starting its
timer, the air-saving unit at the working pressure with its idle time at zero (it first
lowers the pressure 0.5 s into the run-in) and the gauge's diaphragm centred (the chambers
start equal). Approximations in the code, not of size: the overtravel switch, the blow-off's
latch and valve are first-order lags behind their latches, the timers are cleared within
0.05 ms; the card's knee is a sharp corner; the friction block's speed is the shaft's
through a first-order lag, not a difference of counts; the lever's contact and its rest
stop are springs with damping that can only push, its spring linear, its pivot's friction
smoothed over 0.01 rad/s; the regulator opens in proportion to its droop, its check's
cracking pressure and its outlet's volume are neglected; the gauge's diaphragm is linear
within its range, with hard overload plates, and follows in a first-order lag; the
chambers' room for its travel (3 cm^3 a side at the centre, which a real gauge must have) is
not added: a fixed dead volume, of the catalogue's kind, left out to keep the class to the
volume it moves; the blow-off nozzle is an orifice from b to atmosphere; the air-saving
unit's regulator is a first-order lag towards its set (rising and falling at their own
rates) and its flow sensor is the valve's draw itself; the sensor errors (the counter, the
lead-lag, the wet box, the potentiometer) are computed on the true, sampled signals, before
the generator's noise and quantisation (so the lead does not amplify the noise as a real one
would, and the potentiometer's reading is still quantised to the encoder's count), the
counter from the sampled angle (a low between two samples is missed: the arm turns slowly
there), the lead-lag with p_a linear between samples, the wet box with the set value clipped
to the output's 0-10 V.
"""
from __future__ import annotations

import math

import numpy as np

from pneumatic_servo._jit import njit
from pneumatic_servo.effects import Component, Param, State
from pneumatic_servo.effects.layout import (
    BLOCKED,
    C_CIRCUIT,
    C_DVA,
    C_DVB,
    C_KAPPA,
    C_MSUP,
    C_PE,
    C_PS,
    C_PS_REG,
    C_R,
    C_TE,
    C_TORQUE,
    C_TS,
    C_U,
    C_VA,
    C_VB,
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
_BLOCKED = float(BLOCKED)
_STROKE_RAD = 3.31613  # the model's nominal stroke (190 deg)
_CLEAR_S = 5e-5  # [s] time constant with which a timer is cleared
_TURN_S = 1e-3  # [s] time in which a PLC's latch of the angle turns over
_GUARD = 0.9  # share of a chamber's volume the gauge's diaphragm may take at most


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
def _first_order(t, p, tau):
    """``p`` through a first-order lag of time constant ``tau``, starting from ``p[0]``, ``p``
    taken as linear between samples (exact for a ramp)."""
    n = len(p)
    out = np.empty(n)
    if n == 0:
        return out
    y = p[0]
    out[0] = y
    for i in range(1, n):
        h = t[i] - t[i - 1]
        a = math.exp(-h / tau)
        slope = (p[i] - p[i - 1]) / h if h > 0.0 else 0.0
        y = p[i] - tau * slope + a * (y - p[i - 1] + tau * slope)
        out[i] = y
    return out


# --- valve input -----------------------------------------------------------------------------
def _overtravel_valve(t, x, s, p, P, c, dx):
    # x[s]: the overtravel switch as the PLC sees it, 0 (free) to 1 (actuated), following within
    # p[2]: made once the arm is above p[0], broken once it is below p[0] - p[1] (the switch's
    # differential travel), kept in between. Actuated (past 0.45-0.55), the output block lets
    # through only set values at or below the centre: the valve cannot open towards a
    if c[C_CIRCUIT] != _SERVO:
        return
    z = x[s]
    th = x[THETA]
    if th > p[0]:
        target = 1.0
    elif th < p[0] - p[1]:
        target = 0.0
    else:
        target = 1.0 if z >= 0.5 else 0.0
    dx[s] = (target - z) / p[2]
    cut = _rise(z, 0.45, 0.55)
    if c[C_XV] > 0.0:  # opening towards a, which drives the arm up
        c[C_XV] = c[C_XV] * (1.0 - cut)


class OvertravelLimitSwitch(Component):
    """The frame still carries the old machine's upper overtravel switch, a roller-lever
    limit switch that a cam on the arm presses from 132 deg up (the old machine's top
    working position was 130 deg), and the PLC's output block still reads it: while the
    switch is actuated, the block passes only set values that drive the arm down (at or below
    the valve's centre) and holds the others at the centre; once the arm is back below the
    switch's release point, upward set values pass again. The record holds the PLC's command,
    before the block. A window over the stroke with a memory (the switch's differential
    travel: made at 132 deg, released at 130) times the command (it cuts the upward part), in
    the valve's input: not a clamp of the command over a window (it is one-way, and it
    remembers where it was made), a stop (the arm can coast past the switch) or a braking
    zone (it does not depend on the speed). Size: the cam's ramp lifts the roller 0.25 mm per
    degree of the arm and the switch's differential travel is 0.5 mm (its catalogue value):
    2 deg; the PLC's input filter (3 ms) and cycle (1 ms): 4 ms. The position was placed from
    the records without any effect: the closed loop holds at 126, 129 and 131 deg below it
    and at 137 and 140 deg above it; the chirp (run-in included) stays below 130 deg."""

    name = 'held_out10_overtravel_limit_switch'
    params = (Param('make_rad', 'rad', 132.0 * DEG, 0.0, 3.4,
                    'angle above which the switch is actuated'),
              Param('differential_rad', 'rad', 2.0 * DEG, 0.0, 0.2,
                    'how far below that it is released', fit=False),
              Param('response_s', 's', 4e-3, 1e-4, 0.05,
                    "time in which the PLC's block follows the switch", fit=False))
    states = (State('switch_seen', '1', 1e-3, 'the switch as the PLC sees it, 0 to 1'),)
    order = 90
    steady = False
    circuits = ('servo',)
    valve = _overtravel_valve
    equations = ('valve_input',)
    # the upward part of the command cut by a latch set by the angle (with a hysteresis)
    depends = ({'angle', 'command'}, {'angle', 'command', 'motion_direction'},
               {'angle', 'command', 'velocity'})
    closed_form = None
    where_rad = (130.0 * DEG, _STROKE_RAD)


def _knee_valve(t, x, s, p, P, c, dx):
    # the card's characteristic: the set value's distance from the centre, e, is passed with
    # the slope p[1] up to the knee p[0], then with the slope that reaches full output at the
    # half range p[2]; it sets the spool afresh (it runs first among the valve hooks)
    u = min(max(c[C_U], 0.0), 10.0)
    e = u - P[K_NULL]
    a = abs(e)
    if a <= p[0]:
        out = p[1] * a
    else:
        out = p[1] * p[0] + (a - p[0]) * (p[2] - p[1] * p[0]) / max(p[2] - p[0], 1e-6)
    if e < 0.0:
        out = -out
    lim = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(P[K_GAIN] * out, -lim), lim)


class KneeCharacteristicCard(Component):
    """Between the PLC's analog output and the valve sits the old machine's proportional
    amplifier card (its ramp and dither are off), whose characteristic switch is still on the
    'knee' curve it was set to for the old valve: to give fine control near the centre, the
    card passes the set value's distance from the centre with a low slope up to a knee and
    with a steeper one beyond it, so that full output is still reached at 0 and 10 V. The
    record holds the PLC's command, before the card. A static function of the command in the
    valve's input, two straight lines meeting at the knee, the same on both sides: not a dead
    band (it passes small commands, with a lower gain), a clip, an offset of the centre or a
    gain error (the gain differs inside and outside the knee). Size: the knee at 1 V from the
    centre (20 % of the half range) with the output there at 40 % of the straight line's
    (0.4 V): a fine-range setting such cards offer; the steep slope beyond is then 1.15.
    The records without any effect put the chirp's whole command (4.7-5.3 V) and the closed
    loop's holds inside the knee and its steps' kicks beyond it."""

    name = 'held_out10_knee_characteristic_card'
    params = (Param('knee_v', 'V', 1.0, 1e-3, 5.0,
                    "the knee's distance from the centre, at the card's input"),
              Param('knee_share', '1', 0.4, 0.0, 1.0,
                    "the output at the knee as a share of the input there (the fine slope)"),
              Param('half_range_v', 'V', 5.0, 1.0, 10.0,
                    'input at which the output is full, from the centre', fit=False))
    order = 20
    valve = _knee_valve
    equations = ('valve_input',)
    depends = ({'command'},)
    closed_form = None
    where_rad = None


def _friction_feedforward_valve(t, x, s, p, P, c, dx):
    # x[s]: the block's speed, the shaft's speed through a lag p[2]; the block adds p[0] volts
    # in its direction, switched over +-p[1] (tanh), to the set value (within 0-10 V)
    if c[C_CIRCUIT] != _SERVO:
        return
    w = x[s]
    dx[s] = (x[OMEGA] - w) / p[2]
    u = min(max(c[C_U], 0.0), 10.0)
    fed = min(max(u + p[0] * math.tanh(w / p[1]), 0.0), 10.0)
    lim = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(c[C_XV] + P[K_GAIN] * (fed - u), -lim), lim)


class FrictionFeedforwardBlock(Component):
    """The PLC's output block for the axis still has the old machine's friction compensation
    switched on: a Coulomb-friction feed-forward that adds a fixed voltage to the set value in
    the direction in which the arm turns (the block's speed, differenced from the encoder
    each cycle and filtered), switched smoothly across a small speed band. It was tuned for
    the old actuator's stiff seals; here it pushes the valve further open in the direction of
    motion, whatever the controller asks. The record holds the controller's command, before
    the block. A function of the speed (its sign, with a short lag) added in the valve's
    input: not a jump that follows the command's sign (it follows the motion, so it acts
    against the controller whenever the arm overshoots), not a damping (it does not grow
    with the speed beyond the band) and not a friction on the shaft. Size: 0.1 V, 2 % of the
    valve's 5 V half range (the 20 um of spool the old block's friction test had found);
    switched over +-0.5 rad/s (about one encoder count per 1 ms cycle at 20,000 counts per
    turn: 0.31 rad/s), the speed filtered over 5 ms. The records without any effect: the
    chirp turns at up to 2.9 rad/s; the closed loop's shaft is stuck at its holds (at rest
    for 68 % of the record) and its steps reach 48 rad/s."""

    name = 'held_out10_friction_feedforward_block'
    params = (Param('jump_v', 'V', 0.1, 0.0, 2.0,
                    'voltage added in the direction of motion'),
              Param('speed_band_rad_s', 'rad/s', 0.5, 1e-3, 10.0,
                    'speed over which it is switched (tanh)', fit=False),
              Param('speed_filter_s', 's', 5e-3, 1e-4, 0.1, "the block's speed filter",
                    fit=False))
    states = (State('block_speed_rad_s', 'rad/s', 1e-4, "the block's filtered speed"),)
    order = 60
    steady = False
    circuits = ('servo',)
    valve = _friction_feedforward_valve
    equations = ('valve_input',)
    # the command plus a term that follows the sign of the (lagged) speed
    depends = ({'velocity'}, {'velocity', 'motion_direction'}, {'command', 'velocity'},
               {'command', 'motion_direction'})
    closed_form = None
    where_rad = None


# --- moment balance --------------------------------------------------------------------------
def _lever_mechanics(t, x, s, p, P, c, dx):
    # x[s]: the lever's angle, reflected to the arm's [rad]; x[s+1]: its speed. p: rest angle
    # (its stop), inertia, spring preload at the rest angle, spring rate, pivot friction,
    # contact stiffness, contact damping (both reflected to the shaft). The dog on the arm can
    # push the lever up, never pull it; its spring pushes it back onto its stop
    if c[C_CIRCUIT] != _SERVO:
        return
    phi, wl = x[s], x[s + 1]
    push = 0.0
    if x[THETA] > phi:
        push = max(p[5] * (x[THETA] - phi) + p[6] * (x[OMEGA] - wl), 0.0)
    stop = 0.0
    if phi < p[0]:
        stop = max(p[5] * (p[0] - phi) - p[6] * wl, 0.0)
    spring = p[2] + p[3] * (phi - p[0])
    drag = p[4] * math.tanh(wl / 0.01)
    dx[s] = wl
    dx[s + 1] = (push + stop - spring - drag) / p[1]
    c[C_TORQUE] -= push


class EjectorLeverAbove116(Component):
    """The old machine's part ejector is still on the frame: a pivoted steel lever with a
    return spring, which a dog on the arm picks up at 116 deg on its way up and carries to
    the top; on the way down the spring pushes the lever after the dog until the lever is
    back on its rest stop at 116 deg. Above that angle the arm thus carries a second inertia
    on a spring, through a contact that can push and never pull: the dog strikes the lever
    (an impact that shares the arm's momentum with it) and, when the arm decelerates or turns
    faster than the spring can bring the lever along, the lever lifts off the dog and lands
    on it again later. A window over the stroke with a state of its own (the lever's angle
    and speed), in the moment balance: not a spring over a range alone (it has a mass and
    separates), a payload (only above 116 deg, one-way) or a stop. Size: a steel lever
    90 mm long, 35 g (9.5e-5 kg.m^2 about its pivot), met by the dog at 70 mm from the
    pivot while the dog is 60 mm from the arm's axis: 7e-5 kg.m^2 at the shaft (about a third
    of the shaft's own); its spring 0.07 N.m preloaded, 0.1 N.m/rad at the lever, 0.06 N.m
    and 0.075 N.m/rad at the shaft; a plain pivot's 4 mN.m; the dog's rubber tip, 300
    N.m/rad at the shaft, damped at about a fifth of critical. The angle was placed from the
    records without any effect: the chirp swings through 100-124 deg, the closed loop holds
    at 126-140 deg above it and at 39-91 deg below it."""

    name = 'held_out10_ejector_lever_above_116'
    params = (Param('rest_rad', 'rad', 116.0 * DEG, 0.0, 3.4,
                    "the arm's angle at which the dog meets the lever at rest"),
              Param('lever_inertia_kg_m2', 'kg.m^2', 7e-5, 1e-6, 1e-2,
                    "the lever's inertia, reflected to the shaft"),
              Param('spring_preload_n_m', 'N.m', 0.06, 0.0, 1.0,
                    "the return spring's torque at rest, at the shaft"),
              Param('spring_rate_n_m_per_rad', 'N.m/rad', 0.075, 0.0, 10.0,
                    "the return spring's rate, at the shaft", fit=False),
              Param('pivot_friction_n_m', 'N.m', 4e-3, 0.0, 0.1,
                    "the lever pivot's friction, at the shaft", fit=False),
              Param('contact_stiffness_n_m_per_rad', 'N.m/rad', 300.0, 1.0, 1e5,
                    "stiffness of the dog's tip (and of the rest stop), at the shaft",
                    fit=False),
              Param('contact_damping_n_m_s_per_rad', 'N.m.s/rad', 0.05, 0.0, 10.0,
                    'damping of that contact', fit=False))
    states = (State('lever_angle_rad', 'rad', 1e-7, "the lever's angle, reflected to the arm's"),
              State('lever_speed_rad_s', 'rad/s', 1e-4, "the lever's speed, reflected"))
    steady = False
    circuits = ('servo',)
    mechanics = _lever_mechanics
    equations = ('moment_balance',)
    # above the rest angle: the spring (angle), the lever's inertia (the drive's share, as for a
    # payload) and the impacts and lift-offs (speed)
    depends = ({'angle'}, {'angle', 'velocity'}, {'angle', 'velocity', 'motion_direction'},
               {'angle', 'p_a', 'p_b'}, {'angle', 'p_a', 'p_b', 'velocity'})
    closed_form = None
    where_rad = (116.0 * DEG, _STROKE_RAD)

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        # resting on its stop, pressed there by the spring's preload (the records start below)
        return [values['rest_rad']
                - values['spring_preload_n_m'] / values['contact_stiffness_n_m_per_rad'], 0.0]


# --- mass balances ---------------------------------------------------------------------------
def _holding_regulator_flows(t, x, s, p, P, c, dx):
    # the regulator opens in proportion to how far the gauge p_a is below its set p[0], fully
    # at p[1] below it (area p[2]); its check valve lets air only into a
    if c[C_CIRCUIT] > _BLOCKED:
        return
    share = (p[0] - (x[P_A] - c[C_PE])) / p[1]
    if share <= 0.0:
        return
    k = c[C_KAPPA]
    m = orifice_flow(p[2] * min(share, 1.0), c[C_PS], c[C_TS], x[P_A], x[T_A],
                     ideal_critical_ratio(k), c[C_R], k, _LAMINAR_BAND)
    if m <= 0.0:
        return
    add_flow(c, 0, m, c[C_TS], x[T_A])
    c[C_MSUP] += m


class HoldingRegulatorA(Component):
    """The old machine swung its arm on a horizontal axis and kept it from dropping when its
    valve centred with a holding circuit that is still teed into line a: a miniature
    (non-relieving) pressure regulator fed from the supply, with a check valve at its outlet,
    set to 4.8 bar gauge. Whenever p_a falls below that set, the regulator opens, the more the
    further below, and feeds a from the supply; above it, it is shut, and the check keeps a
    from blowing back into it. A product of states in the mass balance of a (an opening set
    by p_a below a level, times an orifice flow from the supply into a): not a pilot line or a
    leak from the supply (it is shut above its set), a relief (it only fills) or a pressure
    regulator in the valve's line (it works beside the valve, not on its flow). Size: the
    set at 4.8 bar gauge (80 % of the 6 bar supply, the old arm's holding pressure); a
    regulator with M5 ports, fully open 30 kPa below its set (its droop), 5e-7 m^2 then (a
    1 mm seat at a discharge coefficient of 0.64): some 0.7 g/s into a at 4.5 bar gauge; the
    check's cracking pressure neglected. The set was placed from the records without any
    effect: the closed loop's holds keep p_a at 4.8-5.0 bar gauge and its steps take it to
    3.5-5.9, the chirp keeps it at 4.7-5.0."""

    name = 'held_out10_holding_regulator_a'
    params = (Param('set_gauge_pa', 'Pa', 4.8e5, 0.0, 1e6,
                    "the regulator's set (gauge)"),
              Param('band_pa', 'Pa', 3e4, 1e2, 1e6,
                    'how far below its set it is fully open', fit=False),
              Param('open_area_m2', 'm^2', 5e-7, 0.0, 1e-5,
                    "the regulator's effective area fully open"))
    circuits = ('servo', 'blocked')
    flows = _holding_regulator_flows
    equations = ('mass_balance_a',)
    depends = ({'p_a'}, {'p_a', 'supply'})
    closed_form = None
    where_rad = None


def _gauge_geometry(t, x, s, p, P, c, dx):
    # x[s]: the volume the gauge's diaphragm has moved from b's side to a's [m^3]: it follows
    # p[0] (p_a - p_b) within p[3], the difference limited to +-p[1] by the overload plates;
    # each side adds its connection's and chamber's p[2]. Guard (it never binds at the defaults
    # within the stroke): the diaphragm moves no more than 90 % of the chamber it takes from
    if c[C_CIRCUIT] > _BLOCKED:
        return
    d = min(max(x[P_A] - x[P_B], -p[1]), p[1])
    target = min(max(p[0] * d, -_GUARD * c[C_VA]), _GUARD * c[C_VB])
    rate = (target - x[s]) / p[3]
    dx[s] = rate
    c[C_VA] += p[2] + x[s]
    c[C_VB] += p[2] - x[s]
    c[C_DVA] += rate
    c[C_DVB] -= rate


class DifferentialGaugeDiaphragm(Component):
    """The old machine showed its drive's load on a differential pressure gauge (a 100 mm
    diaphragm gauge, +-1 bar) across lines a and b; it is still teed into both. Its
    diaphragm, with a rigid centre plate and a range spring, moves with p_a - p_b and so
    moves a volume from one line to the other: as p_a rises over p_b, a's side of the gauge
    grows and b's shrinks by as much; beyond the gauge's range the diaphragm rests on its
    contoured overload plates. The chambers are thus coupled through a moving wall, with no
    air passing between them: a volume taken from b and given to a, set by p_a - p_b (a static
    function, clipped at the range), in the mass balances of a and b (through p dV/dt, a
    product of the pressures and the difference's rate): not a leak between the chambers,
    a fixed dead volume, a volume that follows one chamber alone or one that moves all at
    once (as a shuttle's line). Size: the diaphragm's effective area 20 cm^2 travelling
    +-1.5 mm over +-1 bar: 3 cm^3 at the range's ends (3e-11 m^3/Pa), about a quarter of a
    chamber at mid-stroke; each side adds its connection, 0.3 m of 2 mm bore tube, and what
    its chamber holds beyond the diaphragm's travel, 1 cm^3 (the chambers' room for the travel
    itself, a fixed 3 cm^3 a side, is not added: see the module's notes); the diaphragm
    follows within 2 ms (the tubes' filling).
    The records without any effect: p_a - p_b within +-213 kPa in the closed loop (beyond
    +-100 kPa for 4 % of the time), within +-19 kPa in the chirp."""

    name = 'held_out10_differential_gauge_diaphragm'
    params = (Param('compliance_m3_per_pa', 'm^3/Pa', 3e-11, 0.0, 1e-9,
                    "volume the diaphragm moves per pascal of p_a - p_b"),
              Param('range_pa', 'Pa', 1e5, 1e2, 1e6,
                    'difference at which it rests on its overload plates'),
              Param('side_volume_m3', 'm^3', 1e-6, 0.0, 1e-4,
                    "each side's tube and chamber", fit=False),
              Param('follow_s', 's', 2e-3, 1e-4, 0.1, 'time in which the diaphragm follows',
                    fit=False))
    states = (State('moved_volume_m3', 'm^3', 1e-11,
                    "volume the diaphragm has moved from b's side to a's"),)
    steady = False
    circuits = ('servo', 'blocked')
    geometry = _gauge_geometry
    equations = ('mass_balance_a', 'mass_balance_b')
    # a volume moved between the chambers, set by p_a - p_b (and its rate, through dV/dt)
    depends = ({'p_a', 'p_b'}, {'p_a', 'p_b', 'p_a_rate', 'p_b_rate'},
               {'p_a', 'p_b', 'p_a_lag_5ms', 'p_b_lag_5ms'})
    closed_form = None
    where_rad = None


def _blow_off_flows(t, x, s, p, P, c, dx):
    # x[s]: the side of p[0] the PLC last saw the arm on, 0 below to 1 above (turning within
    # _TURN_S, with a hysteresis of p[1] either side); x[s+1]: the time since the arm last
    # passed p[0] downwards (cleared while the side turns down, counting up to p[3] + 5 ms and
    # no further); x[s+2]: the blow-off valve, 0 shut to 1 open, following within p[4] its
    # command: open while the arm is below p[0] and the time is below p[3]. Open, b blows to
    # atmosphere through the nozzle p[2]
    if c[C_CIRCUIT] != _SERVO:
        return
    z = x[s]
    th = x[THETA]
    if th > p[0] + p[1]:
        target = 1.0
    elif th < p[0] - p[1]:
        target = 0.0
    else:
        target = 1.0 if z >= 0.5 else 0.0
    dx[s] = (target - z) / _TURN_S
    q = x[s + 1]
    if target < 0.5 and z > 0.05:
        dx[s + 1] = -q / _CLEAR_S
    else:
        dx[s + 1] = 1.0 - _rise(q, p[3] + 4e-3, p[3] + 5e-3)
    want = 1.0 if (q < p[3] and z < 0.5) else 0.0
    dx[s + 2] = (want - x[s + 2]) / p[4]
    v = min(max(x[s + 2], 0.0), 1.0)
    if v > 0.0:
        k = c[C_KAPPA]
        m = orifice_flow(p[2] * v, x[P_B], x[T_B], c[C_PE], c[C_TE], ideal_critical_ratio(k),
                         c[C_R], k, _LAMINAR_BAND)
        add_flow(c, 1, -m, c[C_TE], x[T_B])


class TimedBlowOffB(Component):
    """The PLC still runs the old machine's nest-cleaning step: each time the arm leaves the
    nest downwards, i.e. whenever the encoder's angle passes 105 deg going down, it opens a
    blow-off valve for 0.3 s, whose jet cleaned the nest for the next part. The blow-off's air
    was taken, by a tee, from line b (the chamber that drives the arm down, pressurised just
    then). The nozzle is still there and still blows, from b, for 0.3 s after each downward
    pass, while the arm stays below the nest. A memory (a timer started by a downward pass
    of a position) times an orifice flow of p_b to atmosphere, in the mass balance of b:
    not a leak (it blows only after a downward pass, for a fixed time), a leak over a window
    of the stroke (it goes on while the arm moves on, and the arm passing upwards does not
    start it) or a relief. Size: a 0.6 mm jet nozzle (2.3e-7 m^2 at a discharge coefficient
    of 0.8: some 0.33 g/s, 16 l/min ANR, at b's 5 bar gauge, three times the valve's draw at
    the holds); 0.3 s, the old step's time; a direct-acting 2/2 solenoid valve switching in
    10 ms; the PLC compares the angle with a hysteresis of +-0.5 deg. The angle was placed
    from the records without any effect: the closed loop passes it going down three times
    (126 to 64 deg, 138 to 38, 129 to 91), the chirp's swings reach down below it in its
    first seconds (to 100-106 deg) and not later."""

    name = 'held_out10_timed_blow_off_b'
    params = (Param('trigger_rad', 'rad', 105.0 * DEG, 0.0, 3.4,
                    'angle whose downward pass starts the blow-off'),
              Param('hysteresis_rad', 'rad', 0.5 * DEG, 0.0, 0.1,
                    "the PLC's hysteresis either side of it", fit=False),
              Param('nozzle_area_m2', 'm^2', 2.3e-7, 0.0, 1e-5,
                    "the nozzle's effective area"),
              Param('blow_time_s', 's', 0.3, 0.0, 5.0, 'how long it blows after a pass'),
              Param('valve_time_s', 's', 0.01, 1e-4, 0.1, "the blow-off valve's switching time",
                    fit=False))
    states = (State('side_seen', '1', 1e-3, 'the side of the trigger the PLC last saw, 0 to 1'),
              State('time_since_pass_s', 's', 1e-5, 'time since the last downward pass'),
              State('blow_valve', '1', 1e-3, 'the blow-off valve, 0 shut to 1 open'))
    steady = False
    circuits = ('servo',)
    flows = _blow_off_flows
    equations = ('mass_balance_b',)
    # b's orifice flow to atmosphere, for a while after a downward pass of an angle
    depends = ({'angle', 'p_b'}, {'angle', 'p_b', 'motion_direction'},
               {'angle', 'p_b', 'velocity'})
    closed_form = None
    where_rad = (0.0, 105.0 * DEG)

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        # seen above, long since passed, shut (the settling of the states turns the side to
        # below if the arm starts there, without starting the timer)
        return [1.0, values['blow_time_s'] + 5e-3, 0.0]


# --- supply ----------------------------------------------------------------------------------
def _standby_supply(t, x, s, p, P, c, dx):
    c[C_PS] = max(x[s + 1], 1e3)


def _standby_finish(t, x, s, p, P, c, dx):
    # x[s]: the time the draw has stayed below the module's threshold p[0] (cleared within
    # _CLEAR_S while above it, counting up to p[1] + 5 ms and no further); x[s+1]: the pressure
    # the module delivers to the valve: the regulated supply while that time is below p[1],
    # the standby pressure p[2] (gauge) beyond, reached within p[3] rising, p[4] falling
    q = x[s]
    if c[C_MSUP] > p[0]:
        dx[s] = -q / _CLEAR_S
    else:
        dx[s] = 1.0 - _rise(q, p[1] + 4e-3, p[1] + 5e-3)
    w = _rise(q, p[1], p[1] + 2e-3)
    target = (1.0 - w) * c[C_PS_REG] + w * min(c[C_PE] + p[2], c[C_PS_REG])
    pv = x[s + 1]
    tau = p[3] if target > pv else p[4]
    dx[s + 1] = (target - pv) / tau


class StandbyAirSavingSupply(Component):
    """The valve is fed through the old machine's air-saving unit, downstream of the service
    unit and its supply transmitter: a flow sensor and an electronic pressure regulator that
    lower the pressure to a standby level whenever the flow has stayed below a threshold for
    an idle time (the old machine's pauses), and bring the working pressure back as soon as
    the flow rises above the threshold again. The supply transmitter, before the unit, reads
    the working pressure throughout. The valve is thus fed other than the reading: at the
    working pressure while it draws, at a lower one in every pause long enough, and the
    pressure comes back only after the valve has started to draw (within the regulator's
    response). A memory (the time since the draw was last above the threshold, and the
    regulator's output) driven by the valve's draw (set by the command and the pressures):
    not a droop with the flow (it is lowest when the valve draws least), a supply offset (it
    changes with the pauses) or a tank's sawtooth. Size: the threshold 15 l/min ANR (0.3 g/s,
    three times the valve's draw at a hold), an idle time of 0.5 s (the unit's shortest,
    chosen for the old machine's short cycle), a standby pressure of 4.5 bar gauge (75 % of
    the working pressure, the unit's holding setting); its regulator raises the pressure
    within 30 ms and lowers it within 0.2 s (relieving through its small exhaust). The
    records without any effect: the closed loop draws 0.1 g/s at its holds (each 1-2 s long)
    and up to 2.6 g/s in its steps; the chirp draws 0.10-0.15 g/s throughout."""

    name = 'held_out10_standby_air_saving_supply'
    params = (Param('threshold_kg_s', 'kg/s', 3e-4, 0.0, 0.01,
                    'flow below which the unit counts the idle time'),
              Param('idle_s', 's', 0.5, 0.0, 60.0,
                    'time below the threshold after which it lowers the pressure'),
              Param('standby_gauge_pa', 'Pa', 4.5e5, 0.0, 1e6, 'the standby pressure (gauge)'),
              Param('rise_s', 's', 0.03, 1e-3, 1.0, "the regulator's time to raise the pressure",
                    fit=False),
              Param('fall_s', 's', 0.2, 1e-3, 10.0, "the regulator's time to lower it",
                    fit=False))
    states = (State('time_idle_s', 's', 1e-5, 'time the draw has stayed below the threshold'),
              State('valve_supply_pa', 'Pa', 5.0, "pressure the unit delivers to the valve"))
    order = 5
    steady = False
    supply = _standby_supply
    finish = _standby_finish
    equations = ('measurement_supply',)
    # the valve fed less than the reading after a pause in its draw (command, pressures)
    depends = ({'command', 'p_a', 'p_b'}, {'command', 'p_a', 'p_b', 'supply'}, {'supply'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [0.0, supply_pa]


# --- errors of measured signals --------------------------------------------------------------
@njit(cache=True)
def _floored(angle, floor):
    """The count of a counter that follows ``angle``'s changes but stops at ``floor`` (counts
    below it are discarded), starting at ``angle[0]`` (or ``floor``, if below)."""
    n = len(angle)
    out = np.empty(n)
    if n == 0:
        return out
    r = max(angle[0], floor)
    out[0] = r
    for i in range(1, n):
        r = max(r + angle[i] - angle[i - 1], floor)
        out[i] = r
    return out


def _count_floor_error(values, signals, core):
    angle = np.ascontiguousarray(signals['angle_rad'], dtype=float)
    return {'angle_rad': _floored(angle, values['home_rad']) - angle}


class UnsignedCounterAtHome(Component):
    """The encoder's counter is the PLC's high-speed counter, still configured as the old
    machine's: an unsigned count (its lower count limit 0, 'stop at the limit'), set to zero
    at the old machine's home switch, at 42 deg, where the rig is homed before each run; the
    PLC adds the home's 42 deg. Counting down past zero, the counter stays at zero and the
    counts are discarded; coming back up, it counts from zero again. So once the arm has been
    below the home, the reading is high by how far below it went (the deepest point so far),
    and stays so. A dynamic error of the angle with a memory (the lowest angle reached below a
    limit), static between new lows: not an offset from the start, a count loss at speed, a
    play of the reading or a resync at a switch (nothing happens on passing the home, only
    below it). Size: the home at 42 deg, the old machine's lower working position; the
    counter's limit at its zero. The home was placed from the records without any effect: the
    closed loop holds at 38 deg (coming down to 36 deg) once, at 64-140 deg otherwise; the
    chirp stays at 95-130 deg."""

    name = 'held_out10_unsigned_counter_at_home'
    params = (Param('home_rad', 'rad', 42.0 * DEG, 0.0, 3.4,
                    'angle at which the counter is zero (its lower limit)'),)
    sensor_error = staticmethod(_count_floor_error)
    steady = False
    equations = ('measurement_angle',)
    # the reading is the angle less the lowest it went below the home, so far
    depends = ({'angle'}, {'angle', 'motion_direction'})
    closed_form = None
    where_rad = None


def _lead_error(values, signals, core):
    p = np.ascontiguousarray(signals['p_a_pa'], dtype=float)
    t = np.ascontiguousarray(signals['t_s'], dtype=float)
    lag = values['lag_s']
    return {'p_a_pa': (values['lead_s'] / lag - 1.0) * (p - _first_order(t, p, lag))}


class LeadCompensatedInputA(Component):
    """The scaling block of chamber a's channel in the PLC was copied from the old machine's,
    whose transmitter sat at the end of a long sense line; to make up for that line's lag,
    the block passes the reading through a lead-lag, (1 + T1 s) / (1 + T2 s) with T1 > T2.
    The transmitter is now screwed into a's port, without the line, and the compensation is
    still in the block: the reading of p_a overshoots its changes, by T1 - T2 times p_a's
    rate (lagged by T2), and is right at rest. A dynamic error of p_a (a lead): not a lag (it
    leads), a resonance of a line, an offset or a filter bypassed by steps. Size: the lead of
    5 ms and lag of 1 ms that matched the old 2 m line's 4 ms; the closed loop's steps change
    p_a at up to 270 bar/s (the error up to some 100 kPa), its holds hardly, the chirp at up
    to 4 bar/s (1.6 kPa)."""

    name = 'held_out10_lead_compensated_input_a'
    params = (Param('lead_s', 's', 5e-3, 0.0, 0.1, "the block's lead time constant T1"),
              Param('lag_s', 's', 1e-3, 1e-4, 0.1, "the block's lag time constant T2",
                    fit=False))
    sensor_error = staticmethod(_lead_error)
    steady = False
    equations = ('measurement_p_a',)
    depends = ({'p_a', 'p_a_rate'}, {'p_a_rate'}, {'p_a', 'p_a_lag_5ms'},
               {'p_a', 'p_a_lag_20ms'})
    closed_form = None
    where_rad = None


def _wet_box_error(values, signals, core):
    p = np.asarray(signals['p_b_pa'], dtype=float)
    u = np.clip(np.asarray(signals['command_v'], dtype=float), 0.0, 10.0)
    span = values['span_pa']
    v = 1.0 + 4.0 * (p - core['atmospheric_pressure_pa']) / span  # the loop's volts
    k = values['burden_ohm'] / values['leak_ohm']
    return {'p_b_pa': k / (1.0 + k) * (u - v) * span / 4.0}


class WetJunctionBoxB(Component):
    """Chamber b's transmitter was replaced by a two-wire 4-20 mA one, read across a 250 ohm
    resistor fitted in the junction box at the actuator, so that the acquisition still gets
    1-5 V. The box also carries, on the next terminal, the valve's set-value line (0-10 V from
    the PLC's output), and condensate has collected in it: a film of water bridges the two
    terminals. The set-value line thus pushes a small current through the film into the
    burden resistor (the transmitter's current source does not resist it), and the reading of
    p_b moves with the difference between the set value and the loop's own voltage. A static
    error of p_b, a function of the command and p_b (linear in their difference): not a
    crosstalk from another pressure, a gain or an offset (it follows the command), and the
    valve itself is not affected (the output is a stiff source). Size: 20 kohm between the wet
    terminals (insulation of a condensate-filled box falls to tens of kohm); the 250 ohm
    burden: 1.9 kPa of reading per volt of difference, 1.4 kPa at the holds (5 V against the
    loop's 4.3 V), up to 10 kPa in the steps' kicks (0-10 V)."""

    name = 'held_out10_wet_junction_box_b'
    params = (Param('leak_ohm', 'ohm', 2e4, 1e2, 1e10,
                    'resistance of the wet film between the terminals'),
              Param('burden_ohm', 'ohm', 250.0, 1.0, 1e4, 'the burden resistor', fit=False),
              Param('span_pa', 'Pa', 6e5, 1e3, 1e7, "the transmitter's span", fit=False))
    sensor_error = staticmethod(_wet_box_error)
    equations = ('measurement_p_b',)
    depends = ({'command', 'p_b'}, {'command'})
    closed_form = None
    where_rad = None


def _pot_error(values, signals, core):
    angle = np.asarray(signals['angle_rad'], dtype=float)
    span = values['electrical_angle_rad']
    x0 = values['wiper_at_zero']
    r = values['load_ratio']
    x = np.clip(x0 + angle / span, 0.0, 1.0)
    loaded = x / (1.0 + r * x * (1.0 - x))
    loaded0 = x0 / (1.0 + r * x0 * (1.0 - x0))
    return {'angle_rad': ((loaded - x) - (loaded0 - x0)) * span}


class LoadedPotentiometerAngle(Component):
    """The angle channel is the old machine's feedback potentiometer, not the encoder (the
    encoder's counter card failed and the angle was rewired to the potentiometer that was
    still on the shaft's lower end): a 10 kohm conductive-plastic servo potentiometer of 340
    deg electrical angle, fed with the PLC's 10 V reference, its wiper read by the PLC's old
    voltage input, whose input resistance is 100 kohm. The input loads the wiper: the voltage
    read is x / (1 + r x (1 - x)) of the reference, x the wiper's position on the track and r
    the potentiometer's resistance over the input's, lower than x everywhere inside the
    track, most at two thirds of it; the PLC scales it as a straight line set to the arm's
    zero at 0 deg. A static error of the angle, a smooth bow (a cubic of x over the stroke):
    not a scale error, a periodic error or an offset (it is zero at 0 deg and grows, not in
    proportion, over the stroke). Size: r = 0.1 (10 kohm into 100 kohm); the stroke's 190 deg
    centred on the track (the wiper at 0.22 of it at 0 deg): the reading low by 1.1 deg at 36
    deg, by 3.6 deg at 140 deg."""

    name = 'held_out10_loaded_potentiometer_angle'
    params = (Param('load_ratio', '1', 0.1, 0.0, 10.0,
                    "the potentiometer's resistance over the input's"),
              Param('electrical_angle_rad', 'rad', 340.0 * DEG, 0.1, 6.3,
                    "the potentiometer's electrical angle", fit=False),
              Param('wiper_at_zero', '1', 0.22, 0.0, 1.0,
                    "the wiper's position on the track at the arm's zero", fit=False))
    sensor_error = staticmethod(_pot_error)
    equations = ('measurement_angle',)
    depends = ({'angle'},)
    closed_form = None
    where_rad = None


SET = (OvertravelLimitSwitch, DifferentialGaugeDiaphragm, EjectorLeverAbove116,
       UnsignedCounterAtHome, HoldingRegulatorA, LeadCompensatedInputA,
       KneeCharacteristicCard, StandbyAirSavingSupply, TimedBlowOffB, WetJunctionBoxB,
       FrictionFeedforwardBlock, LoadedPotentiometerAngle)
