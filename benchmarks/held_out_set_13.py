"""A thirteenth set of held-out effects (twelve): a rig's physics that the project's model does
not contain, kept apart to measure ONCE, without tuning, how well the discovery finds effects
it was never shown.

Independence: this module was written without reading the discovery's vocabulary or its
corrections (``effects.terms``, ``effects.variables``, ``effects.bases``,
``effects.term_words``, ``effects.corrections``, ``effects.operators``), anything under
``analysis`` or ``docs``, the README, ``bench_open_world.py``, ``bench_dependence.py``,
``bench_next_record.py``, ``open_world_set.py``, ``synth.unlisted``, ``synth.plan`` or any
test, without importing any of them itself and without running any diagnosis, benchmark, test
or git command. What was read: ``held_out_set_12.py`` and ``held_out_set_11.py`` whole; the
module docstrings of ``held_out_set.py`` to ``held_out_set_10.py`` whole (those of sets 6 to 8
in one printing that a display cut in its middle, the cut part printed again) and, of those ten
files, their classes' names and the statements that assign their ``name``, ``equations``,
``depends`` and ``where_rad`` (a parse that printed those and nothing else; for sets 6 to 10
its printout was narrowed to the names, the ``equations``, the variable names their ``depends``
use and their windows); ``effects.base``, ``layout`` and ``effects/__init__`` whole; of
``catalogue`` and ``paper`` their classes' names, the statements assigning their ``name`` and
the first lines of their docstrings (a parse); ``model/core.py``; of ``model/simulate.py`` its
lines 1-200 (``initial_state``, ``sensor_errors``, ``measured_states``, the settling of the
effects' states) and 330-418 (``Stepper``); of ``model/config.py`` its lines 30-62
(``_check_values``) and 165-215 (``copy``, ``with_effect``, ``with_slot``); ``physics/gas.py``;
``synth.varied`` and ``synth.hidden`` whole; of ``experiment.py`` the ``Experiment`` class; of
``control/pid.py`` and ``model/circuits.py`` text searches (its gains and the valve's centre;
the paper's supply). Besides these, of files neither listed for this set nor forbidden: of
``synth/sensors.py`` its first five lines and a text search for its quantiser, its measurement
and its sensors' figures (seven lines), of ``model/units.py`` a text search for its conversion
and two unit names (two lines) and a call of its ``to_si`` on plain numbers with this module's
units (they pass unchanged). No web search. Slips, none of a forbidden file's content: a first,
unfiltered listing of ``benchmarks/`` showed the names of ``bench_open_world.py``,
``bench_dependence.py``, ``bench_next_record.py`` and ``open_world_set.py`` (the listings of
``pneumatic_servo/``, ``effects/`` and ``synth/`` were filtered; a listing of
``benchmarks/__pycache__`` showed the names of two cache files of sets 11 and 12; of two
searches for files changed since the first scratch file, made to see that the runs wrote
nothing into the repository, the first printed none, the second the names of files others
changed meanwhile: two test files, two pages under ``docs``, ``synth/plan.py``, a ruff cache
and numba's caches of set 11; none was opened); ``effects/__init__`` names ``CORRECTIONS`` from
``.corrections``, and the package's registry loads those modules whenever it is used (as every
record's generation here did). Nothing here was chosen or sized with any of that in mind. The
check runs kept their scratch files, compiled kernels and numba's caches in a folder of their
own, ``/tmp/ho13``, wrote no byte code into the repository, and generated the records with
``synth.varied``'s own steps (its ``make_record``, copied to keep the physical states as well;
checked identical for every record of the set at its defaults).

Its physics differs from the effects of ``held_out_set.py`` to ``held_out_set_12.py`` (their
docstrings and classes, as above, were read for this), from the earlier open-world and unlisted
effects those sets name (solenoid hysteresis, shaft-encoder coupling play, a lagging
transducer, a part-stroke vane leak, a track detent, friction growing with mean pressure or
with |p_a - p_b|, a supply offset, a p_b gain error, an encoder scale error, an eccentric code
wheel, a gravity arm, a spring-balanced arm, a pilot line into chamber a, a larger bore of b, a
valve dead band, a transmitter offset), from the candidates and examples the earlier sets left
aside and from the named effects of the catalogue and of the paper's parts. Some candidates
were dropped before any record was made with them: a stepper motor left coupled to the shaft
(its detent torque is the track detent), the old machine's tachogenerator with shorted windings
(a viscous friction and a payload), a fall-arrest lock on the tool's cable reel (once a fast
move locks it, it holds the arm for good), a volume booster left in line a (a relay with a dead
band, implausible on a chamber of 13 cm^3), a worn, eccentric pinion (its 1-2 % change of the
drive and of the swept volume would sit at the floor), the valve's exhausts piped into one
collector box (the chambers exhaust choked: its back pressure would not show), a one-way pawl
catch at the top (an asymmetric detent, a function of the angle), a seal friction falling as
its grease warms (under 1 K in these records), a piston-speed-driven wall heat transfer (near
set 5's inflow jet), a 2/2 valve in line a shut whenever the set value is near the centre (a
one-sided dead band, near the valve dead band; kept only at a station, as
:class:`StationHoldValveA`), the valve's set value written in the counter's interrupt (the
trigger of :class:`CountTriggeredReadB`), a worn slip-ring track in p_a's signal (set 3's
connector window on another signal), a combined analog module's reference sagging with its
output (under 0.1 kPa on p_a), p_b sent as a half-precision float (its steps below the noise)
and an intrinsic-safety barrier's Zener leakage on p_b (a soft clip, near set 3's loop
saturation).

Every size was chosen, as what a real rig of this scale (the paper's SMC MSQA30A actuator,
FESTO MPYE-5-M5 valve, 0-0.6 MPa transmitters, 20,000 P/R encoder, 0.6 MPa gauge supply) would
have, before any record with the effect was generated (each docstring says why its size is
realistic); none was changed after (the stopper's port throttling was re-expressed, from a
linear damping of 40 N.s/m to the square law below, before any record was made). The angles,
levels and times were placed, before any record with an effect was generated, from the
benchmark's two records made without any effect (``closed_steps`` at 500 Hz, seed 7, and
``chirp`` at 500 Hz, seed 8, both 10 s after a 1 s run-in, with both integrators, regenerated
and looked at for this) and set 12's account of them: the closed loop holds its run-in at 109
deg, then at about 140, 126, 64, 72, 137, 38, 131, 129, 92 and 73 deg within 36-140 deg (at
120-132 deg for 29 % of the time, in 14 stretches; at 84-108 deg for 11 %, entering 6 times),
at up to 48 rad/s and 5,100 rad/s^2 (its acceleration below -654 rad/s^2 for 6.5 % of the time
in 62-64 stretches, below -3,270 rad/s^2 for 0.8 % in 15-17 stretches of up to 8 ms), its shaft
below 0.05 rad/s for 71-73 % of the record (a 0.9 deg mark unpassed for up to 0.84 s), its
chambers at 454-690 kPa abs (p_b above p_a by 1.1 bar 26-27 times, 1.6 % of the time), p_a
changing by more than 10 kPa from one sample to the next at 9.7 % of the samples (at up to 282
bar/s), b's net inflow up to 2.4 g/s, its command at 2.3-7.7 V (1st-99th percentile), crossing
a +-0.5 V latch 128 times, within 0.3 V of the centre for 88 % of its time at 120-132 deg; the
open-loop chirp stays at 100-124 deg (its discarded run-in swings over 95-130), below 108 deg
for 19 % of the time (11 entries), above 120 deg for 5 %, below 2.9 rad/s and 240 rad/s^2,
never for more than 0.12 s without passing a 0.9 deg mark, its chambers at 571-606 kPa abs (p_a
- p_b within +-19 kPa), p_a changing at 4 bar/s at most, b's net inflow at 0.06 g/s at most,
its command at 4.7-5.3 V.

Scales of the rig used to size them (from the model's nominal values): 1 bar of pressure
difference gives 0.485 N.m on the shaft (A d_f = 4.85e-6 m^3/rad); the shaft's inertia with the
pistons is 1.9e-4 kg.m^2; the nominal Coulomb friction is 0.042 N.m; the spool travels 0.2 mm
per volt, its lands overlap the sleeve's holes by 10 um; the pressure transmitters span 0-0.6
MPa gauge (noise 0.6 kPa, 1 sigma); the encoder's count is 0.018 deg; a chamber holds about
1.3e-5 m^3 at mid-stroke (5e-6 m^3 at its end); the supply is 0.6 MPa gauge (701 kPa abs).

Each class says what a right answer is:

* ``equations``: the equations a correction may act in to be right;
* ``depends``: the acceptable sets of variables of the correction's leading term;
* ``closed_form = None``: not judged on this set; ``where_rad``: a window's (from, to).

Kinds:

* memory: :class:`QuadrantRampCard` (a ramp generator that acts only towards the centre: a
  driver with direction-dependent dynamics), :class:`SlackCableCounterweight` (the weight's
  flight: the cable's stretch and the weight's speed), :class:`StationHoldValveA` (a 2/2
  valve's stroke, shutting and opening at their own rates), :class:`StopperCylinderTeedAB` (a
  piston's position: a play of the volume it moves, set by its breakaway),
  :class:`GripperValveManifoldSupply` (a latch of the command with hysteresis, a spool, the
  lines' and the manifold's pressures), :class:`DrawWireAngle` (a drum's run-on),
  :class:`PlausibilityFilterA` (the last accepted value and a count),
  :class:`CountTriggeredReadB` (the value held since the last mark);
* windows over the stroke: :class:`BeltBrushWindow` (84-108 deg, with its lead-ins) and
  :class:`StationHoldValveA` (120-132 deg);
* products of states: :class:`BeltBrushWindow` (a function of the angle times a smooth sign of
  the brush's speed against the belt's), :class:`SlackCableCounterweight` (a tension that
  exists only while the cable is stretched), :class:`StationHoldValveA` (a's valve flow, of the
  command and p_a, times a shut share set by the angle and the command),
  :class:`StopperCylinderTeedAB` (each line's pressure times a volume rate set by p_a against
  p_b), :class:`HeatedHoseB` (b's net inflow times a warming that falls with it),
  :class:`GripperValveManifoldSupply` (fill flows set by a latch of the command, and the
  valve's draw), :class:`BiasRelaySupply` (the lesser of the line and p_b plus a bias),
  :class:`CountTriggeredReadB` (p_b sampled where the angle passes its marks);
* errors of measured signals: angle: :class:`DrawWireAngle` (dynamic, a memory); p_a:
  :class:`PlausibilityFilterA` (dynamic, a memory); p_b: :class:`CountTriggeredReadB` (dynamic,
  a memory); supply: :class:`GripperValveManifoldSupply` (dynamic, a memory) and
  :class:`BiasRelaySupply` (static, a function of p_b): the valve is fed other than the
  reading. The static errors in the balances are :class:`WeakChannelCard` (the valve's input),
  :class:`BeltBrushWindow` (the moment balance) and :class:`HeatedHoseB` (b's energy balance).
  The records carry no temperature, so none has an error here.

Balance equations: valve input (:class:`QuadrantRampCard`, :class:`WeakChannelCard`), moment
balance (:class:`SlackCableCounterweight`, :class:`BeltBrushWindow`), mass balance of a
(:class:`StationHoldValveA`, :class:`StopperCylinderTeedAB`), mass balance of b
(:class:`StopperCylinderTeedAB`, :class:`HeatedHoseB` through b's pressure), energy balance of
b (:class:`HeatedHoseB`); the others are sensor faults (the supply ones faults of what the
valve is fed).

Notes written after the check runs. Every class generated both of its records to the end with
finite signals (the physical states and the recorded signals), with ``rk4`` for the closed loop
and ``predictor`` for the chirp for the classes at even positions of :data:`SET`, the reverse
for those at odd ones, each parameter given explicitly at its default (every default within its
bounds: asserted, and checked by the records' configurations); figures are RMS (max)
differences of the recorded signals (after the generator's noise and quantisation, the same
seed) from the same record, same integrator, made without the effect: angle in deg, pressures
in kPa. As sets 7 to 12 noted, the closed loop, whose holds are driven by the measurement
noise, takes another path after any change at all: with ``rk4`` an own state that stays inert
leaves it exactly as it was (a stopper that never breaks away), but the least physical change
(a brush dragging 1e-6 N) moved it by 0.10 deg and 1.7 kPa RMS; with ``predictor`` that
stopper's inert states alone (its step control) moved it by 0.17 deg and 4.4-4.5 kPa, the brush
by 0.01 deg and 0.15 kPa: the floor; the open-loop chirp is deterministic (within 0.006 deg and
0.012 kPa of its own record). The ramp card at its least setting (1e5 V/s, which binds for
microseconds at each move of the command towards the centre) still moved the closed loop by 2.3
deg and 55 kPa RMS with either integrator: its holds from 3 to 8 s turned into hunting (the
command 2.6 V RMS about the centre there, against 0.1): this loop's holds hunt or rest by a
hair. The sensor errors leave the physics, and so the noise, as it was: their figures are the
errors themselves (against the encoder's 0.018 deg and the transmitters' 0.6 kPa).

Both records: :class:`WeakChannelCard` (closed: angle 1.30 (10.3), p_a 18.5 (159), p_b 18.4
(119); chirp: angle 50.8 (80.6), p_a 3.8 (19), p_b 6.9 (36): the chirp's downward half-waves
move the valve less, and the open loop drifts up, onto the upper stop 8.6 s into the record),
:class:`SlackCableCounterweight` (closed: angle 0.97 (6.7), p_a 20.2 (153), p_b 18.3 (132):
slack for 12 % of the record, 52 times, for up to 0.11 s, the weight flying up to 10 mm and
caught with up to 79 N, 1.2 N.m on the shaft; chirp: angle 28.2 (46.7), p_a 6.2 (13), p_b 6.2
(11): the cable taut throughout, a load torque and a payload, under which the open loop drifts
down, to 64-120 deg), :class:`StationHoldValveA` (closed: angle 0.50 (5.9), p_a 10.6 (91), p_b
10.7 (95): line a shut for 25 % of the record, three times, at the holds at 126-131 deg, for up
to 0.98 s; chirp: angle 9.27 (9.6), p_a 2.3 (18), p_b 2.3 (18): shut in the discarded run-in
only, from 0.54 to 0.91 s, which cuts its first upswing at 123 deg; the arm then swings lower,
at 90-115 deg, never reaching the station again), :class:`BeltBrushWindow` (closed: angle 0.62
(4.1), p_a 10.7 (68), p_b 12.6 (81): on the belt for 11 % of the record, entering 6 times;
chirp: angle 4.11 (6.0), p_a 2.0 (13), p_b 2.2 (12.5): the belt pushes the arm up out of its
arc, and the chirp swings at 104-127 deg, on the belt once, for 3 % of the record),
:class:`HeatedHoseB` (closed: angle 0.29 (1.6), p_a 6.5 (26), p_b 6.5 (38), b's gas at 273-309
K, 2.3 K warmer on average: near the floor, WEAK in the closed loop; chirp: angle 1.71 (2.7),
p_a 0.75 (2.2), p_b 0.72 (2.3), b's gas 1.7 K warmer on average), :class:`BiasRelaySupply`
(closed: the valve fed 416-701 kPa abs, mean 532, against the reading's 701: angle 1.21 (12.3),
p_a 159 (323), p_b 159 (314), p_b at 316-618 kPa abs; chirp: fed 529-628, mean 588: angle 10.0
(14.7), p_a 108 (153), p_b 108 (153), the arm at 109-139 deg: as the chambers' pressures follow
the valve's supply down and the supply follows p_b, both settle some 100 kPa lower; a gross
fault), :class:`CountTriggeredReadB` (p_b reading 13.3 (173) closed, off by more than 5 kPa for
half of the record; 4.8 (16.7) chirp, for 18 %). The closed loop only (the chirp's command,
accelerations, pressure differences and rates never reach them: its figures are the floor, or
nothing for a sensor error): :class:`QuadrantRampCard` (closed: angle 39.9 (103), p_a 92 (355),
p_b 105 (418): a gross fault with this loop: the ramped braking turns each step into a limit
cycle from stop to stop (0-190 deg, at a stop for 7 % of the record), the command beyond 2 V
from the centre for 84 % of the record, the card's output up to 9.4 V from the command; chirp:
angle 0.021 (0.07), the card's output within 0.02 V of the command),
:class:`StopperCylinderTeedAB` (closed: angle 0.82 (8.5), p_a 16.5 (117), p_b 16.1 (104): the
piston pushed in 5 times, by up to 9.4 mm, at up to 1.2 m/s, in for 0.8 % of the record; chirp:
never moves, 0.005 deg), :class:`GripperValveManifoldSupply` (closed: angle 0.56 (3.7), p_a
14.2 (121), p_b 13.0 (94), about twice the floor: the gripper valve switched 98 times, the
manifold, and the valve's supply, at 646-701 kPa abs, below 690 for 10 % of the record; without
its switching (set at 10 V) the feed's droop with the valve's draw alone gives 0.23 deg, 5.8
kPa: the floor's size; chirp: never switches: angle 0.03, p 0.33, the feed's droop at its 0.1
g/s), :class:`DrawWireAngle` (angle reading 0.135 (3.1) closed, running on 19 times, for 1.9 %
of the record; chirp: nothing), :class:`PlausibilityFilterA` (p_a reading 10.4 (98) closed,
held at 8.3 % of the samples; chirp: nothing).

Changes after the first runs: three code changes, no size changed, no bound narrowed; the
figures above are after them, and so are all the bound runs. :class:`DrawWireAngle` first took
the drum's run-on a semi-implicit Euler step at a time (speed first), which put the drum back
onto the wire's end within the step it left it: it never ran on, and both records were
unchanged; the run-on is now the exact motion at constant deceleration over each step.
:class:`StopperCylinderTeedAB`'s end stops first took up the piston's speed only while the net
force pushed it into the stop; where its ports' throttling had already turned that force round
at the impact, the piston ran 0.8 mm past its stop (its volumes held at the stop meanwhile:
closed angle 0.82 (8.6), p_a 16.8 (120), p_b 15.8 (104)); a stop now takes up any speed into it
(0.08 mm past at 1.2 m/s). :class:`QuadrantRampCard` first passed its ramp generator
everywhere, also where it only followed the set value (within 0.2 ms): closed angle 40.2 (121),
p_a 90 (251), p_b 103 (349), chirp 0.024 deg, and at 1e5 V/s 3.7 deg, 82 kPa closed; it now
passes the set value itself wherever that moves away from the centre. The docstrings (the
classes' and this one) were written after the first runs; the sizes, placements and bounds they
give are those the code had for the first runs.

Robustness: each class was also run with each parameter at its lower and at its upper bound
(the others at their defaults), both records, with its integrators (160 records): none raised
and every signal stayed finite. Some bounds make rigs that hardly work, finite all the same: a
ramp-down of 1 V/s keeps the closed loop at the stops (103 deg RMS) and moves the chirp by 65
deg; a channel B at zero gain moves the closed loop by 91 deg, at twice the gain the chirp by
104; a 5 kg counterweight or a 0.1 m drum sends the chirp onto the lower stop (103-110 deg RMS)
and moves the closed loop by 8-10 deg; a belt brush dragging 20 N moves the closed loop by 8
deg, one over the whole stroke (to 3.4 rad) or a belt running back at 1 m/s moves the chirp by
39 and 25 deg; a station hold from 0 deg moves the chirp by 66 deg, one that opens within 0.5 s
the closed loop by 2.4 deg; a stopper of 50 mm bore moves in the chirp too (19 deg) and the
closed loop by 5 deg; a manifold fed through 1e-7 m^2 starves the valve (p 283 kPa RMS closed,
70 chirp), a gripper valve of 1e-5 m^2 moves the closed loop's pressures by 43 kPa; a bias of 0
starves the valve (p 485 kPa RMS), one of 1 MPa never binds (unchanged); a wire retracting at 1
m/s^2 reads hundreds of degrees off (452 RMS), one on a 0.5 m pulley 41 deg RMS; a read every
20,000 counts (or a counter of 100 counts per turn) never refreshes after the start, 187-193
kPa RMS; a filter of 100 cycles or a 0.1 s cycle reads 21-23 kPa RMS off in the closed loop, 5
in the chirp (0.1 s), one of 0 kPa refreshes every third cycle; a hose of 20 W/K or at 450 K,
or cooling at 250 K, moves the chirp by 1.7-8.7 deg.

Start-up: the model's settling of the effects' own states (a Newton step on each alone) leaves
the ramp card's generator at the initial command (5 V: the centre), the counterweight hanging
at rest on its taut cable (its stretch 0.04 mm), the stopper out at its stop, the station valve
open (the records start below the station), and the gripper's output off with its port 2 line
charged, its port 4 line vented and the manifold at 700.9 kPa abs (its balance with the valve's
draw at the centre); the draw-wire starts taut; the filter starts at the first sample's value;
the count-triggered reading holds the first sample's p_b until the arm first passes a mark (the
closed loop's run-in rests at 109 deg: its reading holds the start's 401 kPa abs while the
chambers fill, until the record's first step).

Approximations in the code, not of size: the ramp card's generator follows the set value within
0.2 ms where it is not ramped (the card then passes the set value itself); the counterweight's
cable is a linear spring-damper that only pulls, the pulley's inertia and the weight's guide
neglected; the brush's drag turns round over 0.02 m/s of slip (widened where the slip would
settle faster than 50 us, which it never does at the defaults), the belt's own speed
unaffected; the station's 2/2 valve is a first-order lag behind its solenoid whose shut share
scales the valve's net flow into a and its enthalpy (the clearance flows with it), the line
between the two valves neglected; the stopper's chambers are at the lines' pressures, its
tubes' throttling a force on the piston per speed squared, its seals stick within 1e-4 m/s of
speed, its end stops take up its speed within 0.05 ms; the warm hose passes the net flow into b
with a steady flow's effectiveness, its resident warm air neglected; the gripper's PLC output
follows its latch within 0.1 ms, its spool is a first-order lag behind it that switches the
ports over 0.45-0.55 of its travel, its lines and the manifold are isothermal at room
temperature, the feed, the valve's paths and its vents are orifices; the bias relay is
instantaneous and of unlimited capacity; the sensor errors (the draw-wire, the filter, the
count-triggered read) are computed on the true, sampled signals, before the generator's noise
and quantisation: the arm's angle between samples is the cubic through the sampled angles and
speeds (16 steps a sample), the filter runs at its own cycle on p_a linear between samples (its
cycle the records' 2 ms), and a mark passed between samples is read at the next sample.
"""
from __future__ import annotations

import math

import numpy as np

from pneumatic_servo._jit import njit
from pneumatic_servo.effects import Component, Param, State
from pneumatic_servo.effects.layout import (
    C_CIRCUIT,
    C_CP,
    C_DVA,
    C_DVB,
    C_HA,
    C_HB,
    C_INERTIA,
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
    THETA,
)
from pneumatic_servo.physics.gas import ideal_critical_ratio, orifice_flow

DEG = math.pi / 180.0
_LAMINAR_BAND = 0.005  # width of the linear region next to pressure ratio 1 (orifices)
_SERVO = float(SERVO)
_STROKE_RAD = 3.31613  # the model's nominal stroke (190 deg)
_G = 9.80665  # [m/s^2]
_TRACK_S = 2e-4  # [s] time in which the ramp card's output follows where it is not ramped
_SETTLE_S = 5e-5  # [s] fastest a regularised slip may settle (the belt brush)
_BRISTLE_M_S = 0.02  # [m/s] slip over which the brush's drag reverses
_BRUSH_RAMP_RAD = 1.0 * DEG  # the brush's lead-in over the belt's edges
_PISTON_BAND_M_S = 1e-4  # [m/s] speed band within which the stopper's piston can stick
_PISTON_HOLD_S = 1e-3  # [s] time in which a stuck piston's residual speed decays
_PISTON_STOP_S = 5e-5  # [s] time in which the stopper's end stops take up its speed
_VOLUME_GUARD = 0.9  # the stopper takes no more than this share of chamber a's volume
_RELAY_S = 1e-4  # [s] time in which the PLC's output follows its latch


@njit(cache=True)
def _rise(value, lo, hi):
    """0 below ``lo``, 1 above ``hi``, a smoothstep between."""
    if value <= lo:
        return 0.0
    if value >= hi:
        return 1.0
    u = (value - lo) / (hi - lo)
    return u * u * (3.0 - 2.0 * u)


# --- valve input -----------------------------------------------------------------------------
def _quadrant_ramp_valve(t, x, s, p, P, c, dx):
    # x[s]: the card's ramp generator less the valve's centre [V]. Where the set value's distance
    # e from the centre is on its side and at least as far out, the card passes e (ramp-up set to
    # zero) and the generator follows it within _TRACK_S; where e lies nearer the centre, or
    # beyond it, the card passes the generator, which runs towards e at p[0] (the ramp-down)
    if c[C_CIRCUIT] != _SERVO:
        return
    e = min(max(c[C_U], 0.0), 10.0) - P[K_NULL]
    y = x[s]
    rate = (e - y) / _TRACK_S
    if rate * y < 0.0:  # towards the centre
        rate = min(max(rate, -p[0]), p[0])
    dx[s] = rate
    if e * y >= 0.0 and abs(e) >= abs(y):
        return  # passed unchanged
    half = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(c[C_XV] + P[K_GAIN] * (y - e), -half), half)


class QuadrantRampCard(Component):
    """The valve's set value still passes through the old machine's proportional amplifier
    card, now wired as a buffer between the PLC's analog output and the valve: its gain is one,
    but its ramp generator is on. Such cards ramp each quadrant on its own (the set value's
    moves away from the centre and back towards it, on either side); the old machine's
    setting-up left the ramp-up at zero and the ramp-down at 50 ms per full scale (5 V from the
    centre), its 'soft stop'. So every move of the set value away from the centre reaches the
    valve at once, and every move towards it (the loop's braking, its return to a hold, a
    crossing of the centre) reaches it no faster than 100 V/s. The record holds the PLC's
    command, before the card. A memory of the command (the ramp generator's output) with
    direction-dependent dynamics (it acts only where the set value moves towards the centre),
    in the valve's input: not a lag or a delay (moves away from the centre pass unchanged), a
    ramp limit both ways (set 3's), a one-sided lag of falling voltages (set 12's output stage:
    this one ramps, and on the lower side it holds back the rises), a hysteresis or a dead
    band. Size: 50 ms per 100 %, a short setting of such cards (their ramps run from some 10 ms
    to 5 s per 100 %): 100 V/s. The records without any effect: the closed loop's command is
    kicked by volts within a sample (2 ms) at each step and brought back towards the centre
    within a few samples, so the ramp binds at every braking; the chirp's command moves at 7.5
    V/s at most, within the ramp."""

    name = 'held_out13_quadrant_ramp_card'
    params = (Param('ramp_down_v_per_s', 'V/s', 100.0, 1.0, 1e5,
                    "the card's ramp-down: its output's largest rate towards the centre"),)
    states = (State('card_output_v', 'V', 1e-6, "the card's output less the valve's centre"),)
    order = 60
    steady = False
    circuits = ('servo',)
    valve = _quadrant_ramp_valve
    equations = ('valve_input',)
    # the command, lagging (ramped) wherever it moves towards the centre
    depends = ({'command'}, {'command', 'command_direction'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [min(max(command_v, 0.0), 10.0) - core['valve_null_voltage_v']]


def _weak_channel_valve(t, x, s, p, P, c, dx):
    # below the centre the card's channel B passes the set value's distance from the centre at
    # p[0] of its size; above it channel A passes it unchanged
    if c[C_CIRCUIT] != _SERVO:
        return
    e = min(max(c[C_U], 0.0), 10.0) - P[K_NULL]
    if e >= 0.0:
        return
    half = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(c[C_XV] + P[K_GAIN] * (p[0] - 1.0) * e, -half), half)


class WeakChannelCard(Component):
    """The old machine's valve was a double-solenoid proportional valve driven by a two-channel
    amplifier card, one channel per solenoid; the rig's valve gets its 0-10 V from that card's
    recombining output (centre 5 V), from channel A for set values above the centre, channel B
    below it. The old valve's solenoid B was the stronger one, so channel B's gain
    potentiometer was turned down to 70 %, and so it has stayed. The valve sees the set value's
    distance from the centre at full size above the centre and at 70 % below it. The record
    holds the PLC's command. A static function of the command in the valve's input, a kink of
    its gain at the centre: not a null offset (the centre is right), a dead band, a knee (set
    10's card: symmetric), a clip, a gain error (the upper side is right) or a staircase, and
    no memory. Size: 70 %, what balancing two solenoids of one valve leaves (they differ by
    some tens of %). The records without any effect: the closed loop's command swings both ways
    by volts in its steps and dithers about the centre at its holds; the chirp's swings +-0.3 V
    about it."""

    name = 'held_out13_weak_channel_card'
    params = (Param('channel_b_gain', '1', 0.7, 0.0, 2.0,
                    "the gain of the card's channel B (set values below the centre)"),)
    order = 60
    circuits = ('servo',)
    valve = _weak_channel_valve
    equations = ('valve_input',)
    depends = ({'command'}, {'command', 'command_direction'})
    closed_form = None
    where_rad = None


# --- moment balance --------------------------------------------------------------------------
def _counterweight_mechanics(t, x, s, p, P, c, dx):
    # x[s]: the cable's stretch [m] (the length the drum p[1] has wound since the start less the
    # weight's rise); x[s+1]: the weight's upward speed [m/s]. The cable (stiffness p[2],
    # damping p[3]) pulls only while stretched; the weight p[0] hangs on it
    if c[C_CIRCUIT] != _SERVO:
        return
    stretch = x[s]
    rate = p[1] * x[OMEGA] - x[s + 1]
    tension = 0.0
    if stretch > 0.0:
        tension = max(p[2] * stretch + p[3] * rate, 0.0)
    dx[s] = rate
    dx[s + 1] = tension / p[0] - _G
    c[C_TORQUE] -= tension * p[1]


class SlackCableCounterweight(Component):
    """The old machine's arm was balanced by a counterweight on a steel cable (1 mm, 7x7, 0.4 m
    free) wound on a drum on the shaft's lower end and led over a pulley, so that the arm lifts
    the weight as the angle rises; the weight still hangs there. While the cable is taut the
    arm carries the weight's pull (a torque against rising angles) and its inertia; but a cable
    only pulls: where the arm decelerates its rise, or starts a fall, faster than the weight
    can follow under gravity (an angular acceleration below -g/r, -654 rad/s^2), the cable goes
    slack, the weight flies on and the arm runs free of it, until the cable catches the weight
    again with a jolt. A memory (the weight's flight: the cable's stretch and the weight's
    speed) and a product (a tension that exists only while the cable is stretched), in the
    moment balance: not a load torque (the catalogue's constant one) or a payload (this one
    lets go in hard decelerations and jerks when it catches), a gravity arm or a spring (it
    does not depend on the angle), a play between two inertias (the weight is held by gravity,
    not by a second flank) or a lever behind a contact over a window (set 10's). Size: 0.4 kg
    on a 15 mm drum: 0.059 N.m (0.12 bar of drive) and 9e-5 kg.m^2 (half the shaft's own); the
    cable's stiffness 1e5 N/m (a 7x7 steel cable over 0.4 m), its damping 30 N.s/m (a damping
    ratio of some 0.08). The records without any effect: the closed loop's angular acceleration
    falls below -654 rad/s^2 for 6.5 % of the record, in 62 stretches (down to -4,800 rad/s^2);
    the chirp's stays within +-240 rad/s^2, where the cable stays taut."""

    name = 'held_out13_slack_cable_counterweight'
    params = (Param('weight_kg', 'kg', 0.4, 1e-3, 5.0, 'the counterweight'),
              Param('drum_radius_m', 'm', 0.015, 1e-3, 0.1, "the cable drum's radius"),
              Param('cable_stiffness_n_per_m', 'N/m', 1e5, 1e3, 1e7,
                    "the cable's stiffness over its free length", fit=False),
              Param('cable_damping_n_s_per_m', 'N.s/m', 30.0, 0.0, 1e3,
                    "the cable's internal damping", fit=False))
    states = (State('cable_stretch_m', 'm', 1e-8, "the cable's stretch"),
              State('weight_speed_m_s', 'm/s', 1e-6, "the weight's upward speed"))
    steady = False
    circuits = ('servo',)
    mechanics = _counterweight_mechanics
    equations = ('moment_balance',)
    # a constant torque and the weight's share of the acceleration (the pressures' drive less
    # the friction), lost in hard decelerations while the weight flies on
    depends = ({'p_a', 'p_b'}, {'p_a', 'p_b', 'velocity'}, {'p_a', 'p_b', 'motion_direction'},
               {'p_a', 'p_b', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        # hanging at rest on the taut cable
        return [values['weight_kg'] * _G / values['cable_stiffness_n_per_m'], 0.0]


def _belt_brush_mechanics(t, x, s, p, P, c, dx):
    # the brush on the arm (at radius p[4]) bears on the belt from p[0] to p[1] (lead-ins
    # _BRUSH_RAMP_RAD outside): a drag p[2] along the belt's motion relative to the brush (the belt
    # runs at p[3], in the direction of increasing angle), reversing over _BRISTLE_M_S of slip
    # (widened where the slip would settle faster than _SETTLE_S)
    if c[C_CIRCUIT] != _SERVO:
        return
    th = x[THETA]
    w = _rise(th, p[0] - _BRUSH_RAMP_RAD, p[0]) * (1.0 - _rise(th, p[1], p[1] + _BRUSH_RAMP_RAD))
    if w <= 0.0:
        return
    drag = p[2] * w
    band = max(_BRISTLE_M_S, drag * p[4] * p[4] * _SETTLE_S / c[C_INERTIA])
    c[C_TORQUE] += drag * p[4] * math.tanh((p[3] - p[4] * x[OMEGA]) / band)


class BeltBrushWindow(Component):
    """The arm's tip carries the old machine's strip brush (nylon bristles, at 60 mm radius),
    which swept parts off the slow belt of the feed conveyor running under the arm; the
    conveyor still runs, and the brush still bears on its 25 mm wide belt wherever the arm is
    over it: from 84 to 108 deg, with 1 deg lead-ins at the belt's edges. The belt drags the
    brush along its own motion (the way the angle rises) at 0.1 m/s: at rest over the belt the
    arm is pushed up by the brush's full drag; moving up faster than the belt (1.67 rad/s) it
    is held back; moving down, held back at full drag. A window over the stroke and a product
    (a function of the angle times a smooth sign of the brush's speed against the belt's: the
    angle and the speed jointly), in the moment balance: not a friction over a window (set 1's
    hard spot: no push at rest, reversing at zero speed), a jet pushing over a window (set 3's:
    no friction), an eddy-current brake (a damping) or a roller (set 12's: a memory). Size: the
    brush pressed on the belt with 3 N, nylon bristles on a PVC belt 0.5: a drag of 1.5 N, 0.09
    N.m at 60 mm (twice the actuator's Coulomb friction, 0.19 bar of drive); the belt at 6
    m/min, a slow feed. The window was placed from the records without any effect: the closed
    loop holds at 91-92 deg over it and crosses it 6 times; the chirp's lower swings reach down
    to 100 deg, below 108 deg for 19 % of the time (11 entries)."""

    name = 'held_out13_belt_brush_window'
    params = (Param('from_rad', 'rad', 84.0 * DEG, 0.0, 3.4,
                    'angle from which the brush bears fully on the belt'),
              Param('to_rad', 'rad', 108.0 * DEG, 0.0, 3.4, 'angle up to which it bears fully'),
              Param('drag_n', 'N', 1.5, 0.0, 20.0, "the brush's drag on the belt"),
              Param('belt_speed_m_s', 'm/s', 0.1, -1.0, 1.0,
                    "the belt's speed (positive: the way the brush moves as the angle rises)"),
              Param('radius_m', 'm', 0.06, 0.01, 0.2, "the brush's radius on the arm",
                    fit=False))
    circuits = ('servo',)
    mechanics = _belt_brush_mechanics
    equations = ('moment_balance',)
    # over the belt's arc: a drag set by the brush's speed against the belt's (the angle and the
    # speed jointly): a push along the belt at rest, reversing above the belt's speed
    depends = ({'angle', 'velocity'}, {'angle'}, {'angle', 'motion_direction'},
               {'angle', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = (83.0 * DEG, 109.0 * DEG)


# --- mass balances ---------------------------------------------------------------------------
def _station_hold_flows(t, x, s, p, P, c, dx):
    # runs after the valve's flows (order 90). x[s]: the 2/2 valve in line a, 0 open to 1 shut,
    # following its solenoid: shut while the station's switch is made (the angle within
    # [p[0], p[1]]) and the set value is within p[2] of the valve's centre; it shuts within p[3]
    # and opens within p[4]. It cuts the valve's flows into and out of a in proportion
    if c[C_CIRCUIT] != _SERVO:
        return
    th = x[THETA]
    u = min(max(c[C_U], 0.0), 10.0)
    want = 1.0 if (p[0] <= th <= p[1] and abs(u - P[K_NULL]) < p[2]) else 0.0
    z = x[s]
    dx[s] = (want - z) / (p[3] if want > z else p[4])
    q = min(max(z, 0.0), 1.0)
    if q > 0.0:
        c[C_MA] *= 1.0 - q
        c[C_HA] *= 1.0 - q


class StationHoldValveA(Component):
    """The old machine held its arm at the load station, where the part was pushed against it,
    by shutting line a: a 2/2 solenoid valve in line a, driven by the old program's 'station
    hold', which shuts it while the station's inductive switch is made (its target plate on the
    hub covers 120-132 deg) and the set value lies within +-0.3 V of the valve's centre ('axis
    at rest'), and opens it as soon as the set value leaves that band. Valve and rung are still
    there. So at the station, whenever the loop rests, a's air is sealed in and the valve can
    move b alone; a new move opens a's line again after the 2/2 valve's response. A window over
    the stroke, a memory (the 2/2 valve's stroke, which shuts within 15 ms and opens within 10
    ms: direction-dependent) and a product (the valve's flows into and out of a, of the command
    and p_a, times a shut share set by the angle and the command), in the mass balance of a:
    not a throttle or a pinched hose (set 2's: this one is all or nothing, and opened by the
    command), a check valve (it seals both ways), a dead band (the valve still acts on b, and
    only at the station) or a leak. Size: an 18 mm switch's 12 deg target at the old station
    (126 deg), the old program's band of 0.3 V (6 % of the half range), a direct-acting 2/2
    valve of ample bore (its throttling when open is neglected) with such a valve's response
    times. The window and the band were placed from the records without any effect: the closed
    loop holds at 126, 129 and 131 deg inside the window (29 % of the record), its set value
    within 0.3 V of the centre for 88 % of that time; the chirp's tops reach 120-124 deg (5 %
    of the time, its command always within the band), its discarded run-in swings to 130 deg."""

    name = 'held_out13_station_hold_valve_a'
    params = (Param('from_rad', 'rad', 120.0 * DEG, 0.0, 3.4,
                    "angle from which the station's switch is made"),
              Param('to_rad', 'rad', 132.0 * DEG, 0.0, 3.4, 'angle up to which it is made'),
              Param('band_v', 'V', 0.3, 0.0, 5.0,
                    "distance of the set value from the valve's centre that counts as 'hold'"),
              Param('shut_s', 's', 0.015, 1e-3, 0.5, 'time in which the 2/2 valve shuts',
                    fit=False),
              Param('open_s', 's', 0.01, 1e-3, 0.5, 'time in which it opens', fit=False))
    states = (State('hold_valve_shut', '1', 1e-3, 'the 2/2 valve, 0 open to 1 shut'),)
    order = 90
    steady = False
    circuits = ('servo',)
    flows = _station_hold_flows
    equations = ('mass_balance_a',)
    # a's valve flow (command and p_a) cut where the angle is at the station and the command near
    # the centre
    depends = ({'angle', 'command', 'p_a'}, {'angle', 'command', 'p_a', 'supply'},
               {'angle', 'command', 'p_a', 'p_b'}, {'angle', 'p_a', 'p_a_rate', 'velocity'})
    closed_form = None
    where_rad = (120.0 * DEG, 132.0 * DEG)


def _stopper_geometry(t, x, s, p, P, c, dx):
    # x[s]: the stopper's piston [m], 0 retracted to p[2] extended; x[s+1]: its speed [m/s]. Its
    # cap side (bore p[0]) is teed into a, its rod side (rod p[1]) into b; it sticks below a
    # breakaway p[3], slides against p[4] and the throttling of its ports and tubes (a force
    # p[6] v |v|), its moving parts p[5]. The lines gain what its chambers gain since the start
    # (extended), no more than _VOLUME_GUARD of a's volume taken
    if c[C_CIRCUIT] != _SERVO:
        return
    a_cap = 0.25 * math.pi * p[0] * p[0]
    a_rod = max(a_cap - 0.25 * math.pi * p[1] * p[1], 0.0)
    stroke = p[2]
    pos, vel = x[s], x[s + 1]
    force = x[P_A] * a_cap - x[P_B] * a_rod - c[C_PE] * (a_cap - a_rod)
    brk = max(p[3], p[4])
    if abs(vel) <= _PISTON_BAND_M_S:
        if abs(force) <= brk:
            acc = -vel / _PISTON_HOLD_S
        elif force > 0.0:
            acc = (force - p[4] - p[6] * vel * abs(vel)) / p[5]
        else:
            acc = (force + p[4] - p[6] * vel * abs(vel)) / p[5]
    elif vel > 0.0:
        acc = (force - p[4] - p[6] * vel * abs(vel)) / p[5]
    else:
        acc = (force + p[4] - p[6] * vel * abs(vel)) / p[5]
    # an end stop takes up the piston's speed into it, and holds it against a push into it
    if (pos <= 0.0 and vel <= 0.0 and (vel < 0.0 or acc < 0.0)) or \
            (pos >= stroke and vel >= 0.0 and (vel > 0.0 or acc > 0.0)):
        acc = -vel / _PISTON_STOP_S
    dx[s] = vel
    dx[s + 1] = acc
    inside = 0.0 < pos < stroke
    xc = min(max(pos, 0.0), stroke)
    take = a_cap * (stroke - xc)
    limit = _VOLUME_GUARD * c[C_VA]
    if take < limit:
        c[C_VA] -= take
        if inside:
            c[C_DVA] += a_cap * vel
    else:
        c[C_VA] -= limit
    c[C_VB] += a_rod * (stroke - xc)
    if inside:
        c[C_DVB] -= a_rod * vel


class StopperCylinderTeedAB(Component):
    """The old machine's part stopper, a small double-acting cylinder, was driven by the same
    valve: its cap side teed into line a, its rod side into line b, so that it came out as the
    arm went up and went in as it came down. Its stop plate was taken off; the cylinder and its
    two 0.3 m tubes are still plumbed in. Its piston, free but for its seals, stays out while
    p_a and p_b are near equal (the cap's larger area wins), is pushed in when p_b exceeds p_a
    by some 1.1 bar (the rod side's smaller area and the breakaway) and out again when the
    difference falls; each stroke takes volume from one line and gives it to the other. A
    memory (the piston's position and speed: a play of the volume it moves, set by its
    breakaway) and products (each line's pressure times the rate of the volume the piston
    moves), in the mass balances of a and b: not a dead volume (it moves), a compliant
    diaphragm between the lines (set 10's: this one sticks, then runs through its stroke), a
    spring-loaded clamp on one line (set 9's), a leak or a cross leak. Size: a 16 mm bore, 6 mm
    rod, 10 mm stroke cylinder (2.0 cm^3 on its cap side, 1.7 on its rod side), its piston and
    rod 30 g, its seals' breakaway 10 N (its minimum operating pressure, 0.05 MPa, over its
    bore), their sliding friction 6 N, the throttling of its M5 ports and 4 mm tubes 5 N per
    (m/s)^2 (some 13 kPa on either side at 1 m/s). Its fixed volumes (its tubes, its end
    covers, its cap side at the start) are not part of the class (a fixed dead volume, of the
    catalogue's kind): the class carries the volumes the piston moves. The records without any
    effect: the closed loop's downward steps take p_b above p_a by 1.1 bar 26-27 times (1.6 %
    of the record); the chirp's pressures stay within 19 kPa of each other."""

    name = 'held_out13_stopper_cylinder_teed_ab'
    params = (Param('bore_m', 'm', 0.016, 0.008, 0.05, "the stopper's bore"),
              Param('rod_m', 'm', 0.006, 0.0, 0.0075, "its rod's diameter", fit=False),
              Param('stroke_m', 'm', 0.01, 1e-4, 0.05, 'its stroke'),
              Param('breakaway_n', 'N', 10.0, 0.0, 200.0, "its seals' breakaway friction"),
              Param('sliding_n', 'N', 6.0, 0.0, 200.0, "its seals' sliding friction", fit=False),
              Param('mass_kg', 'kg', 0.03, 0.005, 1.0, 'its piston and rod', fit=False),
              Param('port_loss_n_s2_per_m2', 'N.s^2/m^2', 5.0, 0.0, 200.0,
                    "the throttling of its ports and tubes, as a force on the piston per its "
                    'speed squared', fit=False))
    states = (State('stopper_position_m', 'm', 1e-7, "the stopper's piston (0 retracted)"),
              State('stopper_speed_m_s', 'm/s', 1e-5, "its piston's speed"))
    order = 50
    steady = False
    circuits = ('servo',)
    geometry = _stopper_geometry
    equations = ('mass_balance_a', 'mass_balance_b')
    # each line's pressure times the rate of a volume that a piston, moved by p_a against p_b
    # past its breakaway, exchanges between them
    depends = ({'p_a', 'p_b'}, {'p_a', 'p_b', 'p_a_rate'}, {'p_a', 'p_b', 'p_b_rate'},
               {'p_a', 'p_b', 'p_a_rate', 'p_b_rate'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [values['stroke_m'], 0.0]  # extended: the records start with p_a = p_b


# --- energy balance --------------------------------------------------------------------------
def _heated_hose_heat(t, x, s, p, P, c, dx):
    # the net flow into b comes through the warm stretch of b's hose: it arrives warmed by
    # 1 - exp(-UA / (m c_p)) of the difference between the warm zone p[0] and the supply's
    # temperature (UA p[1])
    if c[C_CIRCUIT] != _SERVO:
        return
    m = c[C_MB]
    if m <= 0.0 or p[1] <= 0.0:
        return
    cp = c[C_CP]
    eff = 1.0 - math.exp(-p[1] / (m * cp))
    c[C_HB] += m * cp * eff * (p[0] - c[C_TS])


class HeatedHoseB(Component):
    """Line b's hose (6 x 4 mm PU) was routed along the hydraulic power unit's return pipe,
    which runs at 50 deg C: over 1.5 m it lies on the pipe, and the air flowing through it
    towards chamber b is warmed on its way; the air leaving b through it leaves at b's
    temperature. So b's inflow arrives warmer than the supply, by 1 - exp(-UA / (m c_p)) of the
    pipe's excess temperature: fully at the slow flows of the holds and the chirp, by some 15 %
    at the steps' 2.5 g/s. A product (b's net inflow, of the command and p_b, times a warming
    that falls with it), in the energy balance of b and through it in b's pressure: not a warm
    wall (set 4's cover: that one warms b's gas whatever flows), an inflow's convection to the
    wall (set 5's jet), a cold supply (all inflows alike: a core parameter) or a leak, and no
    memory. Size: the return pipe at 323 K (a hydraulic unit's usual 50 deg C); UA 0.4 W/K
    (laminar flow in the 4 mm bore, Nusselt number 3.66, over 1.5 m: 0.45 W/K, the PU wall's
    conduction some ten times larger). The records without any effect: b's net inflow reaches
    2.4 g/s in the closed loop's steps, 0.06 g/s in the chirp, whose b gas stays at 292-297 K."""

    name = 'held_out13_heated_hose_b'
    params = (Param('warm_temperature_k', 'K', 323.15, 250.0, 450.0,
                    'temperature of the warm zone the hose lies in'),
              Param('conductance_w_per_k', 'W/K', 0.4, 0.0, 20.0,
                    "the warm stretch's heat transfer to the air in the hose (UA)"))
    steady = False
    circuits = ('servo',)
    heat = _heated_hose_heat
    equations = ('energy_balance_b', 'mass_balance_b')
    # b's inflow (the valve's: command and p_b, or b's mass rate) times a warming that falls
    # with the flow
    depends = ({'command', 'p_b'}, {'command', 'p_b', 'supply'}, {'command', 'p_a', 'p_b'},
               {'p_b', 'p_b_rate', 'velocity'}, {'angle', 'p_b', 'p_b_rate', 'velocity'},
               {'command', 'p_b', 't_b'})
    closed_form = None
    where_rad = None


# --- supply ----------------------------------------------------------------------------------
def _gripper_supply(t, x, s, p, P, c, dx):
    if c[C_CIRCUIT] != _SERVO:
        return
    c[C_PS] = max(x[s + 4], 1e3)


def _gripper_finish(t, x, s, p, P, c, dx):
    # x[s]: the PLC's gripper output (on above p[0], off below p[1], kept between), followed within
    # _RELAY_S; x[s+1]: the 5/2 valve's spool, following the output within p[4]; x[s+2], x[s+3]:
    # the plugged lines on its ports 4 and 2 (volume p[3] each, isothermal at room temperature),
    # filled from the manifold and vented through the valve's area p[2]; x[s+4]: the manifold's
    # pressure (volume p[6]), fed from the service unit (the line, the supply reading) through
    # p[5], drawn by the proportional valve and the 5/2 valve
    if c[C_CIRCUIT] != _SERVO:
        return
    k, r, te = c[C_KAPPA], c[C_R], c[C_TE]
    crit = ideal_critical_ratio(k)
    u = c[C_U]
    o = x[s]
    if u > p[0]:
        target = 1.0
    elif u < p[1]:
        target = 0.0
    else:
        target = 1.0 if o >= 0.5 else 0.0
    dx[s] = (target - o) / _RELAY_S
    z = x[s + 1]
    dx[s + 1] = ((1.0 if o >= 0.5 else 0.0) - z) / p[4]
    q = _rise(z, 0.45, 0.55)
    pm = max(x[s + 4], 1e3)
    p4 = max(x[s + 2], 1e3)
    p2 = max(x[s + 3], 1e3)
    pe = c[C_PE]
    fill4 = vent4 = fill2 = vent2 = 0.0
    if q > 0.0:
        fill4 = orifice_flow(p[2] * q, pm, te, p4, te, crit, r, k, _LAMINAR_BAND)
        vent2 = orifice_flow(p[2] * q, p2, te, pe, te, crit, r, k, _LAMINAR_BAND)
    if q < 1.0:
        fill2 = orifice_flow(p[2] * (1.0 - q), pm, te, p2, te, crit, r, k, _LAMINAR_BAND)
        vent4 = orifice_flow(p[2] * (1.0 - q), p4, te, pe, te, crit, r, k, _LAMINAR_BAND)
    feed = orifice_flow(p[5], c[C_PS_REG], c[C_TS], pm, te, crit, r, k, _LAMINAR_BAND)
    dx[s + 2] = r * te / p[3] * (fill4 - vent4)
    dx[s + 3] = r * te / p[3] * (fill2 - vent2)
    dx[s + 4] = r * te / p[6] * (feed - c[C_MSUP] - fill4 - fill2)


class GripperValveManifoldSupply(Component):
    """The valve sits on a manifold with the old gripper's 5/2 solenoid valve, both fed through
    one fitting and hose from the service unit, downstream of the supply transmitter. The
    gripper is gone, its two 1 m lines (6 x 4 mm) plugged at their ends, but the old program
    still drives the gripper valve from the set value: it sets the output ('close: the arm is
    going up') when the set value goes above 5.5 V and resets it ('open') when it goes below
    4.5 V. Each switch fills one plugged line from the manifold and vents the other: a gulp of
    some 0.09 g, at up to 3 g/s for some 30 ms, which the feed must pass, so that the manifold,
    and the valve with it, dips by tens of kPa while the supply reading stays at the line's.
    The valve is fed other than the reading: a memory (a latch of the command with hysteresis,
    the 5/2 valve's spool, the lines' and the manifold's pressures) set by the command, and the
    feed's droop with the valve's own draw (small at this feed): not a supply offset, a
    regulator's droop or memory (sets 5, 11, 12), a tank's sawtooth (set 8's: set by the tank's
    pressure) or a window (set 9's ejector). Size: an M5 5/2 valve of 2 mm^2 effective area,
    switching within 15 ms; its lines 12.6 cm^3 each; the manifold's galleries and hose 10
    cm^3; its feed (a 6 mm fitting and 2 m of hose) 5 mm^2; the old program's levels 0.5 V
    either side of the centre. The levels were placed from the records without any effect: the
    closed loop's command crosses such a latch 128 times (the steps' kicks and counter-kicks),
    the chirp's (within 0.3 V of the centre) never."""

    name = 'held_out13_gripper_valve_manifold_supply'
    params = (Param('on_v', 'V', 5.5, 0.0, 10.0, 'set value above which the output is set'),
              Param('off_v', 'V', 4.5, 0.0, 10.0, 'set value below which it is reset'),
              Param('valve_area_m2', 'm^2', 2e-6, 0.0, 1e-5, "the 5/2 valve's effective area"),
              Param('line_volume_m3', 'm^3', 1.26e-5, 1e-6, 1e-3,
                    'volume of each plugged gripper line'),
              Param('switch_s', 's', 0.015, 1e-3, 0.1, 'time in which the 5/2 valve switches',
                    fit=False),
              Param('feed_area_m2', 'm^2', 5e-6, 1e-7, 1e-4,
                    "effective area of the manifold's feed from the service unit"),
              Param('manifold_volume_m3', 'm^3', 1e-5, 1e-6, 1e-3,
                    "the manifold's volume", fit=False))
    states = (State('gripper_output', '1', 1e-3, "the PLC's gripper output, 0 off to 1 on"),
              State('gripper_spool', '1', 1e-3, "the 5/2 valve's spool, 0 to 1"),
              State('gripper_line4_pa', 'Pa', 5.0, 'pressure of the line on port 4'),
              State('gripper_line2_pa', 'Pa', 5.0, 'pressure of the line on port 2'),
              State('manifold_pa', 'Pa', 5.0, "the valve manifold's pressure"))
    order = 5
    steady = False
    circuits = ('servo',)
    supply = _gripper_supply
    finish = _gripper_finish
    equations = ('measurement_supply',)
    # the valve fed the manifold's pressure: a dip at each change of the command's side (past
    # the latch's levels), and the feed's droop with the valve's draw
    depends = ({'command'}, {'command', 'command_direction'}, {'command', 'supply'},
               {'command', 'p_a', 'p_b'}, {'command', 'p_a', 'p_b', 'supply'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        # output off, port 2's line charged, port 4's vented; the model's settling then finds
        # the manifold's and the charged line's balance with the valve's draw
        return [0.0, 0.0, core['atmospheric_pressure_pa'], supply_pa, supply_pa]


def _bias_relay_supply(t, x, s, p, P, c, dx):
    # the relay's output: p_b plus its bias p[0], no higher than its supply (the line)
    if c[C_CIRCUIT] != _SERVO:
        return
    c[C_PS] = min(c[C_PS], max(x[P_B] + p[0], c[C_PE]))


class BiasRelaySupply(Component):
    """The valve is fed through the old machine's 'air-saving' bias relay (a 1:1 pneumatic
    booster relay with a bias spring), whose signal port is teed into line b: it delivers its
    signal, p_b, plus its bias of 1 bar, no more than its own supply (the line, read by the
    supply transmitter before it). The old machine used it to feed its valve no higher than its
    return side needed. So the valve is fed p_b + 1 bar wherever that is below the line's
    pressure; and as the chambers' pressures follow the valve's supply, they and the supply
    settle lower together. The valve is fed other than the reading, a static function of p_b
    (capped by the line): not an offset (it follows p_b), a droop with the flow, a regulator's
    or a tank's memory, or a window. Size: the bias spring at 1 bar (such relays' biases run
    from 0 to some 2 bar); the relay large and fast enough (its outlet following within
    milliseconds) to be taken as static. The records without any effect: p_b at 462-687 kPa abs
    in the closed loop (583-602 at its holds, where the valve would be fed 683-702), 580-606 in
    the chirp."""

    name = 'held_out13_bias_relay_supply'
    params = (Param('bias_pa', 'Pa', 1e5, 0.0, 1e6, "the relay's bias over its signal"),)
    order = 5
    circuits = ('servo',)
    supply = _bias_relay_supply
    equations = ('measurement_supply',)
    # the valve fed p_b plus a bias, capped by the line (the supply reading)
    depends = ({'p_b'}, {'p_b', 'supply'})
    closed_form = None
    where_rad = None


# --- errors of measured signals --------------------------------------------------------------
@njit(cache=True)
def _draw_wire(t, angle, speed, a_lim, n_sub):
    """The angle a spring-retracted wire's drum shows (rad), the wire paying out as the angle
    rises: taut, the drum follows the arm; where the arm's angle would have to fall faster than
    ``a_lim`` [rad/s^2] allows the drum, the wire goes slack and the drum runs on, decelerating at
    ``a_lim``, until it meets the wire's end again. Between samples the arm's angle is the cubic
    (Hermite) through the sampled angles and speeds, in ``n_sub`` steps."""
    n = len(t)
    out = np.empty(n)
    if n == 0:
        return out
    y = angle[0]
    v = speed[0]
    slack = False
    out[0] = y
    for i in range(n - 1):
        h = t[i + 1] - t[i]
        th0, th1 = angle[i], angle[i + 1]
        m0, m1 = h * speed[i], h * speed[i + 1]
        hs = h / n_sub
        for j in range(1, n_sub + 1):
            u = j / n_sub
            u2 = u * u
            u3 = u2 * u
            th = (2 * u3 - 3 * u2 + 1) * th0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * th1 \
                + (u3 - u2) * m1
            w = ((6 * u2 - 6 * u) * th0 + (3 * u2 - 4 * u + 1) * m0 + (-6 * u2 + 6 * u) * th1
                 + (3 * u2 - 2 * u) * m1) / h
            acc = ((12 * u - 6) * th0 + (6 * u - 4) * m0 + (-12 * u + 6) * th1
                   + (6 * u - 2) * m1) / (h * h)
            if not slack:
                if acc >= -a_lim:
                    y = th
                    v = w
                    continue
                slack = True
            y += v * hs - 0.5 * a_lim * hs * hs
            v -= a_lim * hs
            if y <= th:
                y = th
                v = w
                slack = False
        out[i + 1] = y
    return out


def _draw_wire_error(values, signals, core):
    angle = np.ascontiguousarray(signals['angle_rad'], dtype=float)
    t = np.ascontiguousarray(signals['t_s'], dtype=float)
    if len(t) < 2:
        return {'angle_rad': np.zeros(len(t))}
    speed = np.ascontiguousarray(signals['velocity_rad_s'], dtype=float)
    a_lim = values['retract_acceleration_m_s2'] / values['pulley_radius_m']
    return {'angle_rad': _draw_wire(t, angle, speed, a_lim, 16) - angle}


class DrawWireAngle(Component):
    """The angle is read, as on the old machine, by a draw-wire sensor: its wire is wound on a
    30 mm radius pulley on the shaft, paying out as the angle rises, and the sensor's drum,
    pulled back by its spring, turns an incremental encoder that the counter card counts
    (20,000 counts per turn of the pulley). The drum can take its wire back no faster than its
    spring accelerates it, 10 g at the wire. Where the arm's angle has to fall faster than that
    allows (a hard deceleration of a rise, a hard start of a fall: the pulley's rim
    accelerating below -98 m/s^2, -3,270 rad/s^2), the wire goes slack, the drum runs on and
    comes back on its spring until the wire is taut again: the reading overshoots, then catches
    up. A dynamic error of the angle with a memory (the drum's run-on), one-sided (the reading
    runs ahead of the arm, and only in hard decelerations): not a latency, a count loss above a
    speed, a hub that slips (set 7's: its slip stays), a play or a tracking converter's lag.
    Size: 10 g, the wire acceleration small draw-wire sensors allow; the pulley's 30 mm radius.
    The records without any effect: the closed loop's angular acceleration falls below -3,270
    rad/s^2 for 0.8 % of the record, in 15-17 stretches of up to 8 ms; the chirp's stays within
    +-240 rad/s^2."""

    name = 'held_out13_draw_wire_angle'
    params = (Param('retract_acceleration_m_s2', 'm/s^2', 98.0, 1.0, 1e4,
                    "the largest acceleration at which the sensor's spring retracts its wire"),
              Param('pulley_radius_m', 'm', 0.03, 1e-3, 0.5,
                    "radius of the pulley on the shaft the wire is wound on"))
    sensor_error = staticmethod(_draw_wire_error)
    steady = False
    equations = ('measurement_angle',)
    # the reading runs on after hard decelerations (of the pressures' drive less the friction)
    depends = ({'velocity'}, {'velocity', 'motion_direction'}, {'p_a', 'p_b', 'velocity'},
               {'p_a', 'p_b'}, {'p_a', 'p_b', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = None


@njit(cache=True)
def _plausibility(values, step, confirm):
    """A spike filter: a value more than ``step`` from the last accepted one is rejected (the
    last accepted one is kept) until ``confirm`` values in a row have been so."""
    n = len(values)
    out = np.empty(n)
    if n == 0:
        return out
    y = values[0]
    count = 0
    for i in range(n):
        xk = values[i]
        if abs(xk - y) <= step:
            y = xk
            count = 0
        else:
            count += 1
            if count >= confirm:
                y = xk
                count = 0
        out[i] = y
    return out


def _plausibility_error(values, signals, core):
    t = np.asarray(signals['t_s'], dtype=float)
    p = np.asarray(signals['p_a_pa'], dtype=float)
    n = len(t)
    if n < 2:
        return {'p_a_pa': np.zeros(n)}
    cycle = values['cycle_s']
    grid = t[0] + cycle * np.arange(int(math.floor((t[-1] - t[0]) / cycle + 1e-9)) + 1)
    held = _plausibility(np.interp(grid, t, p), values['step_pa'],
                         max(1, int(round(values['confirm_cycles']))))
    idx = np.clip(np.searchsorted(grid, t + 1e-9 * cycle, side='right') - 1, 0, len(grid) - 1)
    return {'p_a_pa': held[idx] - p}


class PlausibilityFilterA(Component):
    """p_a's channel passes the old program's plausibility block, written against the old
    transmitter's interference spikes: each PLC cycle (2 ms) it accepts a new value within 10
    kPa of the last accepted one and keeps the last accepted one otherwise, until three values
    in a row have been out of that band, when it takes the newest. The recording takes the
    channel after the block. So wherever p_a changes by more than 10 kPa a cycle (50 bar/s),
    its reading holds for two cycles and then jumps: a staircase behind p_a. A dynamic error of
    p_a with a memory (the last accepted value and the count): not a lag or a delay (slow
    changes pass unchanged), a rate limit (set 9's: that one ramps), a filter reset by large
    steps (set 7's: the reverse), a sample-and-hold at a fixed period (set 4's) or a
    send-on-delta (set 5's). Size: 10 kPa (1.7 % of the span) and three cycles, settings such
    blocks take; the PLC's 2 ms cycle. The records without any effect: p_a changes by more than
    10 kPa from one 2 ms sample to the next at 9.7 % of the closed loop's samples (at up to 282
    bar/s), at none of the chirp's (4 bar/s at most)."""

    name = 'held_out13_plausibility_filter_a'
    params = (Param('step_pa', 'Pa', 1e4, 0.0, 1e6,
                    'largest change from one cycle to the next the filter accepts at once'),
              Param('confirm_cycles', '1', 3.0, 1.0, 100.0,
                    'cycles in a row after which it accepts a larger change'),
              Param('cycle_s', 's', 2e-3, 1e-4, 0.1, "the filter's cycle", fit=False))
    sensor_error = staticmethod(_plausibility_error)
    steady = False
    equations = ('measurement_p_a',)
    # held behind p_a wherever p_a changes fast (its rate)
    depends = ({'p_a', 'p_a_rate'}, {'p_a_rate'}, {'p_a', 'p_a_lag_5ms'})
    closed_form = None
    where_rad = None


@njit(cache=True)
def _count_triggered(angle, p, step):
    """``p`` as read at each sample at which ``angle`` has passed into another interval of
    ``step`` since the last read, held between."""
    n = len(angle)
    out = np.empty(n)
    if n == 0:
        return out
    g = math.floor(angle[0] / step)
    held = p[0]
    for i in range(n):
        gi = math.floor(angle[i] / step)
        if gi != g:
            held = p[i]
            g = gi
        out[i] = held
    return out


def _count_triggered_error(values, signals, core):
    angle = np.ascontiguousarray(signals['angle_rad'], dtype=float)
    p = np.ascontiguousarray(signals['p_b_pa'], dtype=float)
    step = 2.0 * math.pi * values['counts_per_read'] / values['counts_per_rev']
    return {'p_b_pa': _count_triggered(angle, p, step) - p}


class CountTriggeredReadB(Component):
    """p_b's channel is read, as the old machine read it for its pressure-over-position
    profile, in the counter card's compare interrupt, which fires each time the count passes a
    multiple of 50 counts (0.9 deg): the process image, and the recording, hold p_b as it was
    at the last such passage. So while the arm stands, p_b's reading stays where it was when
    the arm last passed a mark, whatever p_b does; moving, it is refreshed every 0.9 deg. A
    dynamic error of p_b with a memory (the value held since the last mark), set by the motion:
    not a sample-and-hold at a fixed period (set 4's), a send-on-delta (set 5's: set by p_b's
    own change), a delay (set 12's) or a freeze over a window (set 4's sense line, set 11's
    capture register). Size: 50 counts, the old profile's 0.9 deg resolution; the encoder's
    20,000 counts per turn. The records without any effect: the closed loop's arm stands still
    (below 0.05 rad/s) for 71-73 % of the record, in stretches of up to 0.8 s, after each step
    while its pressures settle; the chirp's arm passes a 0.9 deg mark some 50 times a second
    and never for 0.12 s without."""

    name = 'held_out13_count_triggered_read_b'
    params = (Param('counts_per_read', '1', 50.0, 1.0, 20000.0,
                    "encoder counts between the compare interrupts that read p_b"),
              Param('counts_per_rev', '1', 20000.0, 100.0, 1e6, "the encoder's counts per turn",
                    fit=False))
    sensor_error = staticmethod(_count_triggered_error)
    steady = False
    equations = ('measurement_p_b',)
    # p_b as it was when the arm last passed a mark: held while the arm stands
    depends = ({'p_b', 'velocity'}, {'p_b', 'p_b_rate', 'velocity'}, {'p_b', 'p_b_rate'},
               {'angle', 'p_b'}, {'p_b', 'p_b_lag_20ms'}, {'p_b', 'p_b_lag_5ms'})
    closed_form = None
    where_rad = None


SET = (QuadrantRampCard, DrawWireAngle, SlackCableCounterweight, CountTriggeredReadB,
       StopperCylinderTeedAB, GripperValveManifoldSupply, WeakChannelCard, PlausibilityFilterA,
       StationHoldValveA, BeltBrushWindow, HeatedHoseB, BiasRelaySupply)
