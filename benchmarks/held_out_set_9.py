"""A ninth set of held-out effects (twelve): a rig's physics that the project's model does
not contain, kept apart to measure ONCE, without tuning, how well the discovery finds
effects it was never shown.

Independence: this module was written without reading the discovery's vocabulary or its
corrections (``effects.terms``, ``effects.variables``, ``effects.bases``,
``effects.term_words``, ``effects.corrections``, ``effects.operators``), anything under
``analysis`` or ``docs``, the README, ``bench_open_world.py``, ``bench_dependence.py``,
``open_world_set.py``, ``synth.unlisted`` or any test, without importing any of them itself
and without running any diagnosis, benchmark, test or git command. What was read:
``held_out_set_6.py``, ``held_out_set_7.py`` and ``held_out_set_8.py`` whole; of
``held_out_set.py`` to ``held_out_set_5.py`` their module docstrings, their classes' names
and the statements that assign their ``equations``, ``depends`` and ``where_rad`` (a parse
that printed those and nothing else); ``effects.base``, ``layout``, ``paper`` and
``effects/__init__`` whole; of ``catalogue`` its classes' names, the first lines of their
docstrings, their summaries and its import lines (a text search); ``model/core.py`` and
``model/simulate.py``; ``physics/__init__``, ``gas.py``, ``valve.py``, ``mechanics.py`` and
``friction.py``; ``synth.varied``, ``synth.hidden`` and ``synth.sensors``; ``_jit``;
``experiment.py``; of the paper, the lines a text search for its rig's parts found (the
parts' table, the circuit's description). Besides these, of files neither listed nor
forbidden: of ``model/config.py`` a text search for four method names and its lines 170-215
(``copy``, ``with_effect``, ``with_slot``, ``component_classes``, ``values_of``: how a
record's effects are added and checked against their bounds), and of ``control/pid.py`` a
text search for its class and its gains; and a search of ``pyproject.toml`` and
``setup.cfg`` for a line length (none found). No web search. Slips, none of a forbidden
file's content: ``effects/__init__`` names ``CORRECTIONS`` from ``.corrections``, and the
package's registry loads those modules whenever it is used (as every record's generation
here did); listings of ``benchmarks/`` and of ``pneumatic_servo/`` were filtered (to the
held-out sets, and without ``analysis``), and a listing of ``/tmp`` showed other sessions'
scratch folders by name (none was opened). Nothing here was chosen or sized with any
forbidden content in mind.

Its physics differs from the effects of ``held_out_set.py`` to ``held_out_set_8.py`` (their
docstrings and classes, as above, were read for this), from the earlier open-world and
unlisted effects those sets name (solenoid hysteresis, shaft-encoder coupling play, a
lagging transducer, a part-stroke vane leak, a track detent, friction growing with mean
pressure or with |p_a - p_b|, a supply offset, a p_b gain error, an encoder scale error, an
eccentric code wheel, a gravity arm, a spring-balanced arm, a pilot line into chamber a, a
larger bore of b, a valve dead band, a transmitter offset), from the examples the earlier
sets left aside and from the named effects of the catalogue and of the paper's parts. Some
candidates were drafted and dropped before any record was made with them: a backlash of the
rack and pinion (a play between two inertias, as set 3's keyway play), a hose drawn over a
guide post (a capstan: a load torque and a friction growing with the angle, near set 1's
harness, set 2's bent shaft and the catalogue's load torque), a viscous inertia damper on
the shaft (a payload inertia at the loop's frequencies: stepper dampers couple within
milliseconds), a reserve tank charged from b through a check valve (the model's settling
of the effects' own states, a Newton step on each alone, would empty it at the start), a
regulated blow-off nozzle on line a (a leak of a's of another law, near the catalogue's
leak) and a crosstalk of the valve's coil current into a transmitter (too small to see).

Every size was chosen, as what a real rig of this scale (the paper's SMC MSQA30A actuator,
FESTO MPYE-5-M5 valve, 0-0.6 MPa transmitters, 20,000 P/R encoder, 0.6 MPa gauge supply)
would have, before any record with the effect was generated (each docstring says why its
size is realistic); none was changed after. The windows, thresholds and bands were placed,
before any record with an effect was generated, from the benchmark's two records made
without any effect (``closed_steps`` at 500 Hz, seed 7, and ``chirp`` at 500 Hz, seed 8,
both 10 s after a 1 s run-in, looked at for this): the closed loop holds at about 140, 126,
63, 72, 138, 39, 132, 129, 91 and 72 deg within 36-140 deg (30 % of the time at 60-80 deg,
48 % at 125-145 deg), at up to 48 rad/s (above 20 rad/s for 1.4 % of the time, above 25
for 0.8 %, in the largest steps) and 5,100 rad/s^2, its chambers at 454-690 kPa abs
(583-606 at the holds, i.e. 4.8-5.0 bar gauge), p_a - p_b within -213..+205 kPa, p_a and
p_b changing at up to 270 and 230 bar/s, its command at 2.3-7.7 V (1st-99th percentile),
crossing the valve's centre 1,376 times (mostly in the holds' noise-driven dither), the
valve's draw at 0.09-2.6 g/s (0.1 g/s at the holds); the open-loop chirp stays at 100-124
deg (its discarded run-in swings over 95-130), below 2.9 rad/s and 240 rad/s^2, its
chambers at 571-606 kPa abs, p_a - p_b within +-19 kPa, changing at up to 4 (a) and 5 (b)
bar/s, its command at 4.7-5.3 V, crossing the centre 48 times, the valve's draw at
0.10-0.15 g/s.

Scales of the rig used to size them (from the model's nominal values): 1 bar of pressure
difference gives 0.485 N.m on the shaft (A d_f = 4.85e-6 m^3/rad); the racks travel 7 mm per
radian of the shaft (d_f / 2); the shaft's inertia with the pistons is 1.9e-4 kg.m^2; the
nominal Coulomb friction is 0.042 N.m and the viscous 0.006 N.m.s/rad; the spool travels
0.2 mm per volt, the valve's largest effective area is about 3.4e-6 m^2; the pressure
transmitters span 0-0.6 MPa gauge (noise 0.6 kPa, 1 sigma); the encoder's count is
0.018 deg; a chamber holds about 1.3e-5 m^3 at mid-stroke; the supply is 0.6 MPa gauge
(701 kPa abs).

Each class says what a right answer is:

* ``equations``: the equations a correction may act in to be right;
* ``depends``: the acceptable sets of variables of the correction's leading term;
* ``closed_form = None``: not judged on this set; ``where_rad``: a window's (from, to).

Kinds:

* memory: :class:`SpeedMonitorRelay` (a monitor's hysteresis and a relay),
  :class:`ChangeoverDeadTime` (the side last driven and a timer),
  :class:`FreewheelIndexTurret` (a state of its own: a turret's speed, one-way),
  :class:`ShuttleValveGaugeLine` (a ball's hysteresis and a line's pressure),
  :class:`SpringClampTeedA` (a play of a piston), :class:`CamSwitchedEjectorSupply` (a
  short lag of a tee's pressure), :class:`ChargeAmplifierTransmitterA` (a slow mean: a
  high-pass), :class:`GradientLimitedInputB` (a rate limiter);
* windows over the stroke: :class:`CounterPressureCamB` (from 128 deg up),
  :class:`CamSwitchedEjectorSupply` (110-135 deg), and :class:`PistonMagnetReluctanceCellB`
  (a function of the angle, steep towards the top);
* products of states: :class:`SpeedMonitorRelay` (the command x a latch set by the speed),
  :class:`RotaryJointOnLineB` (p_b x the direction of motion, and p_b x the speed),
  :class:`ShuttleValveGaugeLine` (orifice flows of p_a and p_b x a side set by their
  difference), :class:`CounterPressureCamB` (a function of the angle x an orifice flow set
  by p_b), :class:`TornByteCounterRead` (a function of the angle and the speed jointly),
  :class:`CamSwitchedEjectorSupply` (a function of the angle, with the valve's draw);
* errors of measured signals: angle: :class:`TornByteCounterRead` (dynamic: the angle and
  the speed jointly); p_a: :class:`ChargeAmplifierTransmitterA` (dynamic, a memory); p_b:
  :class:`GradientLimitedInputB` (dynamic, a memory), :class:`PistonMagnetReluctanceCellB`
  (static, a function of the angle); supply: :class:`CamSwitchedEjectorSupply` (the valve is
  fed other than the reading).

Balance equations: valve input (:class:`SpeedMonitorRelay`, :class:`ChangeoverDeadTime`),
moment balance (:class:`FreewheelIndexTurret`, :class:`RotaryJointOnLineB`), mass balance
of a (:class:`ShuttleValveGaugeLine`, :class:`SpringClampTeedA`), mass balance of b
(:class:`ShuttleValveGaugeLine`, :class:`CounterPressureCamB`); the others are sensor faults
(the supply one a fault of what the valve is fed).



Notes written after the check runs. Every class generated both of its records to the end
with finite signals, with ``rk4`` for the closed loop and ``predictor`` for the chirp for
the classes at even positions of :data:`SET`, the reverse for those at odd ones, each
parameter at its default (all within their bounds, which the records' configurations check);
figures are RMS (max) differences of the recorded signals (after the generator's noise and
quantisation, the same seed) from the same record, same integrator, made without the effect:
angle in deg, pressures in kPa. As sets 7 and 8 noted, the closed loop, whose holds are
driven by the measurement noise, takes another path after any change at all: here a rotary
joint of 1e-13 N.m/Pa or a cam throttle of 1e-13 m^2 changed it by 0.15-0.21 deg and 3-5 kPa
RMS (the floor), while the open-loop chirp is deterministic (exactly unchanged by them); the
sensor errors leave the physics, and so the noise, as it was: their figures are the errors
themselves (against the encoder's 0.018 deg and the transmitters' 0.6 kPa).

Both records: :class:`ShuttleValveGaugeLine` (closed: angle 0.94 (5.8), p_a 18.9 (141), p_b
17.7 (119), the ball going over 93 times, the line at 564-672 kPa abs; chirp: angle 5.95
(7.7), p_a 2.4, p_b 2.7, 48 changeovers, the arm at 94-118 deg),
:class:`FreewheelIndexTurret` (closed: angle 1.02 (10.7), p_a 19.7 (163), p_b 19.7 (142),
the turret driven for 58 % of the record, overrunning for 5 %, at up to 40 rad/s; chirp:
angle 12.0 (21.0), p_a 4.4, p_b 4.3: the turret follows each upward swing and never
overruns, its brake a one-way friction that the open loop integrates into a drift),
:class:`SpringClampTeedA` (closed: angle 0.79 (4.8), p_a 16.8 (123), p_b 16.7 (108), the
piston moving for 6 % of the record over 1.7-4.7 mm; chirp: angle 6.71 (7.5), p_a 1.4, p_b
1.4: the chirp's swings stay within the play after the run-in has set the piston at 2.2-3.1
mm, a volume added to a), :class:`ChangeoverDeadTime` (closed: angle 5.48 (57.5), p_a 26.6
(271), p_b 25.9 (223), the valve held at the centre for 22 % of the record after 118 changes
of side: the steps start late and overshoot, to 142 and 32 deg; chirp: angle 7.82 (17.0),
p_a 1.8, p_b 2.3, held for 10 %), :class:`CamSwitchedEjectorSupply` (the valve fed 656-700
kPa abs, mean 691, closed, 674-700, mean 678, chirp, against the reading's 701; closed:
angle 0.60 (3.5), p_a 18.9 (96), p_b 18.1 (102); chirp: angle 1.90 (2.3), p_a 21.9 (25), p_b
21.8 (25)), :class:`RotaryJointOnLineB` (its Coulomb part 0.037-0.059 N.m closed,
0.047-0.051 chirp; closed: angle 1.03 (5.8), p_a 18.2 (119), p_b 18.3 (95); chirp: angle
1.21 (2.5), p_a 5.2, p_b 6.4), :class:`CounterPressureCamB` (closed: angle 1.06 (4.7), p_a
46.2 (97), p_b 42.2 (100): at the upper holds both chambers stand 45-80 kPa higher and the
arm up to 2 deg short (the top one at 138.3 deg); chirp: angle 6.16 (6.9), p_a 1.4, p_b 1.4:
only its discarded run-in, which swings to 126 deg, enters the cam's ramp, and the arm stays
lower, at 93-118 deg), :class:`TornByteCounterRead` (angle reading 0.32 (4.6) closed, 27
torn samples; 0.23 (4.6) chirp, 12), :class:`ChargeAmplifierTransmitterA` (p_a reading 10.9
(45) closed, 7.9 (39) chirp; the first second of each record carries the run-in's filling,
13-45 and 6-39 kPa: the slow mean starts at the amplifier's zero while the chambers start at
401 kPa abs; after it, -10..+18 kPa, RMS 6.9, closed, -4..+6, RMS 3.2, chirp),
:class:`GradientLimitedInputB` (p_b reading 18.8 (132) closed, lagging each step by up to
0.5 s; 1.2 (6) chirp, limited in the faster half of the chirp),
:class:`PistonMagnetReluctanceCellB` (p_b reading 4.7 (8.1) closed, 0.8-8.1 kPa from the
lowest to the top hold; 3.7 (5.0) chirp, 2.7-5.0). The closed loop only (the chirp, below 3
rad/s, never reaches the limit): :class:`SpeedMonitorRelay` (closed: angle 1.78 (21.8), p_a
30.5 (258), p_b 25.7 (204): it trips 9 times in the largest steps, the valve centred for
0.7 % of the record; chirp: unchanged).

Changes after the first runs (before the figures above): three code changes, no size
changed, no bound narrowed. :class:`ShuttleValveGaugeLine` first sent its ball towards the
higher line directly: once the ball had left its seat, both seats open let the chambers
equalise through the shuttle before the ball was half way, so that it fell back; it never
went over and acted as a leak between the chambers whenever b rose 3 kPa above a, which
drove the chirp onto the upper stop (closed: angle 0.93 (5.8), p_a 18.6 (141), p_b 17.6
(118); chirp: angle 70.3 (84.1), p_a 15.0, p_b 26.0). The push on the ball was given a state
of its own, which turns within 0.1 ms (once unseated, the flow carries a ball over); and
after the bound runs, in which a ball of 1e-5 s travel (faster than its push) brought the
same leak back (chirp angle 70.3), the ball now goes over only once the push has turned
(figures after the first change: closed angle 0.95 (5.7), p_a 18.9, p_b 18.0; chirp angle
5.95 (7.7)). :class:`ChangeoverDeadTime` cleared its timer only while its side was more than
0.2 from the new one, which cleared it to 1.5 ms, not to zero (a hold of 18.5 ms: closed
angle 6.30 (57.5), p_a 28.3, p_b 27.8; chirp angle 7.69 (16.7)); it now clears until the
side is within 0.05.

Robustness: each class was also run with each parameter at its lower and at its upper bound
(the others at their defaults), both records, with its integrators: none raised and every
signal stayed finite. Some bounds make rigs that hardly work, finite all the same: a speed
monitor tripping at 0 rad/s, or never resetting, centres the valve for good and the closed
loop's arm drifts onto the upper stop (190 deg; at 0 rad/s the chirp's too); a changeover
dead time of 0.5 s does that to the chirp; a turret brake of 1 N.m drives the chirp onto the
lower stop; a counter-pressure cam open from 0 deg, or a clamp of 1e-2 m^2 bore or of 1e-4
m^3 of tube, drives the chirp onto the lower stop; a gauge line of 1e-3 m^3 or shuttle seats
of 1e-4 m^2 hold the chirp's arm still (95 deg); a rotary joint of 1e-5 N.m/Pa holds both
records' arms near their start; an ejector line drooping 1e9 Pa.s/kg starves the valve (p
300-430 kPa RMS); a charge amplifier's zero at 0 or at 2 MPa puts the reading off the
transmitter's scale (p_a 500 and 140 kPa RMS). Without the ejector (a nozzle of 0 m^2) the
valve's own draw through the service unit's droop still changes the closed loop by angle
0.52, p_a 12.3, p_b 11.6 (the steps' largest draws; the catalogue's supply pressure drop),
the chirp by p 1.7. Start-up: the model's settling of the effects' own states (a Newton step
on each alone) leaves the shuttle's gauge line, like the chambers, at 401 kPa abs and the
clamp's piston against its stop; the records' 1 s run-in fills them (the clamp then stays
where the run-in left it while the chirp's swings are within its play). Approximations in
the code, not of size: the monitor, the relay, the changeover's side, the shuttle's push and
ball and the clamp's piston are first-order lags behind their latches or targets; the
turret's brake sticks within a speed band of 1e-3 rad/s and the freewheel's drag is smoothed
over 0.01 rad/s of slip; the gauge line is isothermal at room temperature; the clamp's air
is taken as part of a's gas (its pressure and temperature); the service unit's droop is
linear in the flow it passes (a regulator's characteristic), the tee isothermal at the
supply temperature, the ejector's nozzle an orifice to atmosphere; the cam valve's throttle
an orifice from the supply; the sensor errors (the torn read, the charge amplifier, the
limiter, the magnet) are computed on the true, sampled signals, before the generator's noise
and quantisation, the torn read from the sampled angle and speed (the count at the second
read extrapolated with the speed), the charge amplifier's slow mean with p_a linear between
samples.
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
    C_FBRK_NEG,
    C_FBRK_POS,
    C_FEDGE_NEG,
    C_FEDGE_POS,
    C_FKIN,
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
    C_XV,
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
def _band(angle, lo, hi, edge):
    """1 over [lo, hi], 0 beyond ``edge`` outside it, smoothstep ramps between (0 everywhere
    if ``hi`` < ``lo``)."""
    return _rise(angle, lo - edge, lo) * (1.0 - _rise(angle, hi, hi + edge))


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
def _speed_monitor_valve(t, x, s, p, P, c, dx):
    # x[s]: the speed monitor's output (0 off, 1 tripped; it switches within p[3]): tripped
    # once |speed| exceeds p[0], reset once it has fallen below p[1] x p[0], kept in between.
    # x[s+1]: its output relay's armature, following within p[2]; once pulled in (past
    # 0.45-0.55 of its travel) its contact opens the set-value line: the valve centres
    w = abs(x[OMEGA])
    z = x[s]
    if w > p[0]:
        target = 1.0
    elif w < p[1] * p[0]:
        target = 0.0
    else:
        target = 1.0 if z >= 0.5 else 0.0
    dx[s] = (target - z) / p[3]
    dx[s + 1] = (min(max(z, 0.0), 1.0) - x[s + 1]) / p[2]
    contact = _rise(x[s + 1], 0.45, 0.55)
    c[C_XV] = c[C_XV] * (1.0 - contact)


class SpeedMonitorRelay(Component):
    """The old machine's safety concept is still wired: a speed monitor (a safety relay that
    counts the encoder's pulses through a splitter box) watches the arm and, in automatic
    restart mode, whenever the arm turns faster than its limit, its output relay switches
    the valve's set-value input from the PLC's output to the 5 V centre reference (the
    'stop' wired for the old valve), so that the valve centres; once the speed has fallen
    below the reset level, the relay drops out and the set value passes again. The record
    holds the PLC's command, before the relay. A memory (the monitor's switching hysteresis
    and the relay's operate and release time) set by the speed, times the command (it cuts
    it): in the valve's input; not a ramp, a clip of the command, a latch set by a pressure
    or the command, or a friction (it does nothing at rest and below the limit, whatever
    the command). Size: the old machine's limit, 2 m/s of its gripper on an 80 mm arm, 25 rad/s
    (the closed loop's largest steps reach 48 rad/s; the chirp stays below 3); the reset at
    80 % of it (20 rad/s), the hysteresis such monitors are set to; the monitor's evaluation
    of the pulse frequency within 3 ms, its relay's 10 ms to operate or release."""

    name = 'held_out9_speed_monitor_relay'
    params = (Param('trip_speed_rad_s', 'rad/s', 25.0, 0.0, 200.0,
                    'speed above which the monitor trips'),
              Param('reset_share', '1', 0.8, 0.0, 1.0,
                    'speed, as a share of the trip speed, below which it resets'),
              Param('relay_time_s', 's', 0.01, 1e-4, 0.1,
                    "the output relay's operate and release time", fit=False),
              Param('monitor_time_s', 's', 3e-3, 1e-4, 0.05, "the monitor's response time",
                    fit=False))
    states = (State('monitor_output', '1', 1e-3, "the speed monitor's output, 0 to 1"),
              State('relay_armature', '1', 1e-3, "the output relay's armature, 0 to 1 (open)"))
    order = 90
    steady = False
    valve = _speed_monitor_valve
    equations = ('valve_input',)
    # the command cut (to the centre) by a latch set by |velocity| above a level
    depends = ({'command', 'velocity'}, {'command', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = None


_CLEAR_S = 5e-5  # [s] time constant with which the changeover timer is cleared


def _changeover_valve(t, x, s, p, P, c, dx):
    # x[s]: the side of the set value the block last saw, -1 or +1 (turning over within p[2]);
    # it changes once the set value is more than p[1] beyond the valve's centre on the other
    # side. x[s+1]: the time since the last change (cleared while the side turns over,
    # counting up to p[0] + 5 ms and no further). Until p[0] has passed the block holds its
    # output at the centre (released over 1 ms)
    u = min(max(c[C_U], 0.0), 10.0)
    e = u - P[K_NULL]
    z = x[s]
    if e > p[1]:
        target = 1.0
    elif e < -p[1]:
        target = -1.0
    else:
        target = 1.0 if z >= 0.0 else -1.0
    dx[s] = (target - z) / p[2]
    q = x[s + 1]
    if abs(target - z) > 0.05:
        dx[s + 1] = -q / _CLEAR_S
    else:
        dx[s + 1] = 1.0 - _rise(q, p[0] + 4e-3, p[0] + 5e-3)
    c[C_XV] = c[C_XV] * _rise(q, p[0], p[0] + 1e-3)


class ChangeoverDeadTime(Component):
    """The PLC's output block was written for the old machine's valve, a 4/3 proportional
    valve with a proportional solenoid for each direction and a two-channel amplifier. To keep
    the two solenoids from ever being driven together, the block holds its output at zero
    for a changeover dead time whenever the set value changes sign, and only then drives the
    other channel. When the MPYE (one input, 0-10 V about its 5 V centre) replaced that
    valve, the block was kept and its zero mapped to 5 V: each time the controller's
    command crosses the valve's centre (beyond a small detection band), the valve is held at
    the centre for the dead time, then follows the command. The record holds the command,
    before the block. A memory (the side last driven and a timer since it changed) of the
    command, in the valve's input: not a dead band (the valve follows small commands once
    the time has passed), a delay (only sign changes are held, and for a fixed time
    whatever comes after), a relay or a latch of large commands. Size: 20 ms, the release
    time of the old valve's solenoids that the dead time covered; a detection band of
    +-0.02 V, the block's noise threshold; the block's turnover within 0.2 ms."""

    name = 'held_out9_changeover_dead_time'
    params = (Param('dead_time_s', 's', 0.02, 0.0, 0.5,
                    'time the output is held at the centre after a change of side'),
              Param('band_v', 'V', 0.02, 0.0, 1.0,
                    'distance from the centre beyond which a change of side is detected',
                    fit=False),
              Param('turnover_s', 's', 2e-4, 1e-5, 0.01, "the block's turnover time",
                    fit=False))
    states = (State('side', '1', 1e-3, 'side of the set value last driven, -1 to 1'),
              State('time_since_change_s', 's', 1e-5, 'time since the side last changed'))
    order = 80
    steady = False
    valve = _changeover_valve
    equations = ('valve_input',)
    # the command held at the centre for a while after each change of its sign
    depends = ({'command'}, {'command', 'command_direction'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        side = 1.0 if command_v >= core['valve_null_voltage_v'] else -1.0
        return [side, values['dead_time_s'] + 5e-3]


# --- moment balance --------------------------------------------------------------------------
def _turret_mechanics(t, x, s, p, P, c, dx):
    # x[s]: wind-up of the chain and the freewheel's sprags (>= 0 while it drives) [rad of the
    # shaft]; x[s+1]: the turret's speed, reflected to the shaft. p: turret inertia, brake
    # torque, stiffness, damping, overrunning drag (all reflected to the shaft). The freewheel
    # drives the turret while the shaft turns up faster than it; otherwise it overruns with
    # its drag; the turret's brake holds it at rest
    if c[C_CIRCUIT] != _SERVO:
        return
    phi, wt = x[s], x[s + 1]
    rel = x[OMEGA] - wt
    if phi > 0.0 or rel > 0.0:
        drive = p[2] * max(phi, 0.0) + p[3] * rel
        if drive < 0.0:
            drive = 0.0
        dx[s] = rel
    else:  # overrunning: the sprags slip with their drag
        drive = p[4] * max(min(rel / 0.01, 1.0), -1.0)
        dx[s] = -phi / 1e-3
    if abs(wt) > 1e-3:
        brake = p[1] if wt > 0.0 else -p[1]
        dx[s + 1] = (drive - brake) / p[0]
    elif abs(drive) <= p[1]:  # held by its brake
        dx[s + 1] = -wt / 1e-3
    else:
        brake = p[1] if drive > 0.0 else -p[1]
        dx[s + 1] = (drive - brake) / p[0]
    c[C_TORQUE] -= drive


class FreewheelIndexTurret(Component):
    """The old machine used the arm's upward strokes to index a small turret beside it: a
    roller chain from a sprocket on the shaft's lower extension drives the turret through a
    roller freewheel, so that the turret turns on with the arm whenever it moves up and
    stays, held by a felt brake on its rim, while the arm returns. The turret is still
    chained on. Moving up, the arm thus carries the turret's inertia and its brake; moving
    down, only the freewheel's drag; and when the arm slows down faster than the brake slows
    the turret, the turret overruns and coasts on, disengaged, until the arm catches it up.
    A state of its own (the turret's speed and the chain's wind-up), one-way, in the moment
    balance: not a payload (it rides along one way only and can run ahead), not a friction
    that differs with the direction (it stores the turret's speed), not a play or a slipping
    coupling. Size: an aluminium turret plate of 120 mm and 0.4 kg (7.2e-4 kg.m^2) chained at
    2:1, 1.8e-4 kg.m^2 at the shaft (about the shaft's own); its felt brake 0.1 N.m at the
    turret, 0.05 N.m at the shaft (a light spring on the pad); the 6 mm-pitch chain's
    stretch and the sprags, 300 N.m/rad at the shaft, damped at a tenth of critical; the
    overrunning drag of an 8 mm roller freewheel, 3 mN.m."""

    name = 'held_out9_freewheel_index_turret'
    params = (Param('turret_inertia_kg_m2', 'kg.m^2', 1.8e-4, 1e-6, 1e-2,
                    "the turret's inertia, reflected to the shaft"),
              Param('brake_torque_n_m', 'N.m', 0.05, 0.0, 1.0,
                    "the turret brake's torque, reflected to the shaft"),
              Param('stiffness_n_m_per_rad', 'N.m/rad', 300.0, 1.0, 1e5,
                    "stiffness of the chain and the freewheel, at the shaft", fit=False),
              Param('damping_n_m_s_per_rad', 'N.m.s/rad', 0.03, 0.0, 10.0,
                    'damping across that stiffness', fit=False),
              Param('overrun_drag_n_m', 'N.m', 3e-3, 0.0, 0.1,
                    "the freewheel's drag while it overruns", fit=False))
    states = (State('windup_rad', 'rad', 1e-7, "wind-up of the chain and the freewheel"),
              State('turret_speed_rad_s', 'rad/s', 1e-4, "the turret's speed at the shaft"))
    steady = False
    circuits = ('servo',)
    mechanics = _turret_mechanics
    equations = ('moment_balance',)
    # moving up, the turret's share of the drive (p_a - p_b) and its brake; moving down, the
    # drag; overrunning, nothing: one way, with the turret's speed as its memory
    depends = ({'p_a', 'p_b', 'motion_direction'}, {'p_a', 'p_b', 'velocity', 'motion_direction'},
               {'velocity', 'motion_direction'}, {'p_a', 'p_b', 'velocity'})
    closed_form = None
    where_rad = None


def _rotary_joint_mechanics(t, x, s, p, P, c, dx):
    # the joint's lip seals, pressed by p_b's gauge pressure: a Coulomb part p[0] and a
    # viscous part p[1] per pascal
    if c[C_CIRCUIT] != _SERVO:
        return
    gauge = max(x[P_B] - c[C_PE], 0.0)
    _add_friction(c, p[0] * gauge, x[OMEGA])
    c[C_FKIN] += p[1] * gauge * x[OMEGA]


class RotaryJointOnLineB(Component):
    """The old machine fed its gripper's opening port through the table's centre bore: a
    one-circuit rotary joint on the hollow shaft, teed into line b (the gripper opened
    whenever the arm went down). The gripper is gone and the joint's outlet plugged, but
    the joint is still on the shaft and under b's pressure. Its two lip seals, on the 10 mm
    journal, are pressure-energised: their contact pressure, and so both their sliding
    friction and the viscous drag of the grease film under them, grow with the pressure they
    seal. A friction that scales with p_b, Coulomb and viscous (a product of states: p_b x
    the direction of motion, and p_b x the speed), in the moment balance: not the pistons'
    friction growing with the mean pressure or with |p_a - p_b|, and not a fixed friction
    (at the steps' 3.6-5.9 bar gauge of p_b it varies by a factor of 1.6). Size: 0.1 N.m at
    1 MPa, as small rubber-sealed rotary joints are rated, 0.05 N.m at the holds' 4.9 bar
    gauge (about the actuator's own Coulomb friction); the grease film's drag 3 mN.m.s/rad at
    5 bar (half the actuator's viscous friction). The joint's plugged passage adds some
    0.3 cm^3 to line b, neglected."""

    name = 'held_out9_rotary_joint_on_line_b'
    params = (Param('coulomb_n_m_per_pa', 'N.m/Pa', 1e-7, 0.0, 1e-5,
                    "sliding friction of the joint's seals per pascal of p_b (gauge)"),
              Param('viscous_n_m_s_per_rad_pa', 'N.m.s/(rad.Pa)', 6e-9, 0.0, 1e-6,
                    "viscous drag of the seals' film per pascal of p_b (gauge)"))
    circuits = ('servo',)
    mechanics = _rotary_joint_mechanics
    equations = ('moment_balance',)
    depends = ({'p_b', 'velocity'}, {'p_b', 'motion_direction'},
               {'p_b', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = None


# --- mass balances ---------------------------------------------------------------------------
def _shuttle_flows(t, x, s, p, P, c, dx):
    # x[s]: pressure in the gauge line (isothermal at room temperature, volume p[0]); x[s+1]:
    # which seat the ball is pushed to, 0 (b's) or 1 (a's), turning over within 0.1 ms once
    # the other line is p[2] higher and kept in between (once unseated, the flow carries the
    # ball over); x[s+2]: the ball, 0 (the line open to a) to 1 (open to b), going over within
    # p[3] once the push has turned (past 0.45-0.55). Mid-travel both seats are open (area
    # p[1] each when fully open)
    if c[C_CIRCUIT] > _BLOCKED:
        return
    side = x[s + 1]
    d = x[P_B] - x[P_A]
    if d > p[2]:
        target = 1.0
    elif d < -p[2]:
        target = 0.0
    else:
        target = 1.0 if side >= 0.5 else 0.0
    dx[s + 1] = (target - side) / _BALL_PUSH_S
    z = x[s + 2]
    dx[s + 2] = (_rise(side, 0.45, 0.55) - z) / p[3]
    zc = min(max(z, 0.0), 1.0)
    open_a = min(2.0 * (1.0 - zc), 1.0)
    open_b = min(2.0 * zc, 1.0)
    te, r, k = c[C_TE], c[C_R], c[C_KAPPA]
    crit = ideal_critical_ratio(k)
    pl = max(x[s], 1.0)
    m_a = 0.0
    m_b = 0.0
    if open_a > 0.0:
        m_a = orifice_flow(p[1] * open_a, x[P_A], x[T_A], pl, te, crit, r, k, _LAMINAR_BAND)
        add_flow(c, 0, -m_a, te, x[T_A])
    if open_b > 0.0:
        m_b = orifice_flow(p[1] * open_b, x[P_B], x[T_B], pl, te, crit, r, k, _LAMINAR_BAND)
        add_flow(c, 1, -m_b, te, x[T_B])
    dx[s] = r * te / p[0] * (m_a + m_b)


_BALL_PUSH_S = 1e-4  # [s] time in which the push on the ball turns over


class ShuttleValveGaugeLine(Component):
    """The old machine showed its working pressure on one gauge whichever way the arm moved:
    a shuttle valve (an OR element) takes lines a and b to a gauge line, its ball sealing the
    lower line and opening the gauge line to the higher. The shuttle, its gauge line and the
    gauge are still teed into both lines. The gauge line's air thus belongs to whichever
    chamber is higher: it adds to that chamber's capacity, and each time p_a - p_b changes
    sign by more than the ball's shifting pressure, the ball goes over and the line, still at
    the other chamber's pressure, is connected to this one (and, during the ball's travel,
    both seats are open for a moment). A memory (the ball's side, with a hysteresis, and the
    line's own pressure) in the mass balances of a and b, set jointly by p_a and p_b: not a
    leak between the chambers (nothing passes from one to the other but the line's charge
    at each changeover), not a fixed dead volume (it moves from one chamber to the other),
    not a lag of one chamber. Size: an M5 shuttle valve whose seats pass 1e-6 m^2 (1.4 mm at
    a discharge coefficient of 0.65); the line: 1 m of 2.5 mm tube and a 40 mm gauge, 5 cm^3
    (two fifths of a chamber at mid-stroke); the ball goes over at 3 kPa of difference (its
    weight and the seats' grip) within 1 ms."""

    name = 'held_out9_shuttle_valve_gauge_line'
    params = (Param('line_volume_m3', 'm^3', 5e-6, 1e-8, 1e-3,
                    'volume of the gauge line, the gauge and the outlet'),
              Param('seat_area_m2', 'm^2', 1e-6, 1e-9, 1e-4,
                    "effective area of each of the shuttle's open seats"),
              Param('shift_pa', 'Pa', 3e3, 0.0, 1e5,
                    'pressure difference at which the ball goes over', fit=False),
              Param('ball_time_s', 's', 1e-3, 1e-5, 0.05, "the ball's travel time", fit=False))
    states = (State('line_pressure_pa', 'Pa', 5.0, 'pressure in the gauge line'),
              State('ball_push', '1', 1e-3, 'seat the ball is pushed to, 0 (b) to 1 (a)'),
              State('ball', '1', 1e-3, "the ball's position, 0 (line on a) to 1 (line on b)"))
    steady = False
    circuits = ('servo', 'blocked')
    flows = _shuttle_flows
    equations = ('mass_balance_a', 'mass_balance_b')
    # a volume moved between the chambers by the sign of p_a - p_b (with a hysteresis)
    depends = ({'p_a', 'p_b'}, {'p_a', 'p_b', 'p_a_rate', 'p_b_rate'},
               {'p_a', 'p_b', 'p_a_lag_5ms', 'p_b_lag_5ms'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [0.5 * (supply_pa + core['atmospheric_pressure_pa']), 0.0, 0.0]


def _spring_clamp_geometry(t, x, s, p, P, c, dx):
    # x[s]: the clamp's piston travel [m], 0 (clamped) to p[1] (fully released). p: bore
    # area, stroke, gauge pressure at which the spring's preload is overcome, gauge pressure
    # at full release, seal friction (as a pressure), dead volume, follow time. The piston
    # stays put while the gauge p_a is within the friction of the spring's pressure at its
    # travel (a play), and follows beyond it within p[6]; its volume is part of chamber a
    if c[C_CIRCUIT] > _BLOCKED:
        return
    span = max(p[3] - p[2], 1.0)
    g = x[P_A] - c[C_PE]
    lo = p[1] * (g - p[4] - p[2]) / span
    hi = p[1] * (g + p[4] - p[2]) / span
    y = x[s]
    target = min(max(y, lo), hi)
    target = min(max(target, 0.0), p[1])
    rate = (target - y) / p[6]
    dx[s] = rate
    c[C_VA] += p[5] + p[0] * min(max(y, 0.0), p[1])
    c[C_DVA] += p[0] * rate


class SpringClampTeedA(Component):
    """The old machine's part clamp is a spring-clamping, air-releasing cylinder (it holds
    the part when the air fails), teed into line a so that the part was released whenever the
    arm lifted. Its piston starts to compress the clamping spring once the gauge p_a
    overcomes the spring's preload and is fully back at a higher pressure; its seals' friction
    makes it stick until p_a has moved the friction's worth beyond the pressure at which it
    last stopped. So over the clamp's pressure band chamber a gains a volume that follows
    p_a with a play: small changes of p_a (the holds, the chirp) leave the piston where it
    is, larger ones (the steps) move it, taking air into or giving air back to a. A memory
    (a play of the piston) in the mass balance of a, driven by p_a: not a lag behind a
    throttle (set 3's idle cylinder stores a fixed volume behind a restriction; this one has
    no restriction and a volume that depends on the pressure with a play), not a fixed dead
    volume, not a leak. Size: 20 mm bore (3.14e-4 m^2), 5 mm stroke (1.6 cm^3); a die spring
    of 110 N preload rising to 173 N, so that it releases between 3.5 and 5.5 bar gauge
    (the band the records' holds and steps are in); 9.4 N of seal friction, 30 kPa; 0.5 cm^3
    of tee and tube; the piston follows within 2 ms."""

    name = 'held_out9_spring_clamp_teed_a'
    params = (Param('bore_area_m2', 'm^2', 3.14e-4, 1e-6, 1e-2, "area of the clamp's bore"),
              Param('stroke_m', 'm', 5e-3, 1e-5, 0.05, "the clamp's stroke", fit=False),
              Param('start_gauge_pa', 'Pa', 3.5e5, 0.0, 1e6,
                    "gauge pressure that overcomes the spring's preload"),
              Param('full_gauge_pa', 'Pa', 5.5e5, 0.0, 1e6,
                    'gauge pressure at which the clamp is fully released'),
              Param('friction_pa', 'Pa', 3e4, 0.0, 3e5,
                    "the seals' friction as a pressure on the bore"),
              Param('dead_volume_m3', 'm^3', 5e-7, 0.0, 1e-4, 'volume of the tee and the tube',
                    fit=False),
              Param('follow_time_s', 's', 2e-3, 1e-4, 0.1,
                    'time in which the piston follows beyond its friction', fit=False))
    states = (State('clamp_travel_m', 'm', 1e-8, "the clamp piston's travel"),)
    steady = False
    circuits = ('servo', 'blocked')
    geometry = _spring_clamp_geometry
    equations = ('mass_balance_a',)
    # a volume that follows p_a with a play (over the clamp's band)
    depends = ({'p_a', 'p_a_rate'}, {'p_a', 'p_a_lag_5ms'}, {'p_a', 'p_a_lag_20ms'},
               {'p_a', 'p_a_rate', 'velocity'})
    closed_form = None
    where_rad = None

def _counter_pressure_flows(t, x, s, p, P, c, dx):
    # above p[1] (the cam's ramp p[2] below it) the cam valve feeds supply air into b through
    # the throttle p[0]
    if c[C_CIRCUIT] != _SERVO:
        return
    w = _rise(x[THETA], p[1] - p[2], p[1])
    if w <= 0.0:
        return
    k = c[C_KAPPA]
    m = orifice_flow(p[0] * w, c[C_PS], c[C_TS], x[P_B], x[T_B], ideal_critical_ratio(k),
                     c[C_R], k, _LAMINAR_BAND)
    add_flow(c, 1, m, c[C_TS], x[T_B])
    c[C_MSUP] += m


class CounterPressureCamB(Component):
    """The old machine braked its arm before the top of its swing by counter-pressure: a cam
    on the arm presses the roller of a 2/2 valve from 128 deg upwards, which then feeds
    supply air, through a needle throttle, into line b, the chamber the arm is moving
    against. The cam valve is still plumbed to the supply and to line b. So above 128 deg
    chamber b takes a steady inflow from the supply, which the loop has to exhaust again
    through the valve to hold the arm up there. A window over the stroke times an orifice
    flow from the supply into b (a product of states: a function of the angle x a flow set
    by p_b), in the mass balance of b: not a leak to atmosphere, a throttle of b's exhaust
    over a window or a pilot line everywhere. Size: the throttle's needle a quarter turn
    open, 1e-7 m^2, some 0.12 g/s into b at the holds' 6 bar abs (as much as the valve's own
    flow at the holds); the cam's ramp takes 3 deg of the arm (a 2.5 mm rise at its 50 mm
    radius). The window was placed from the records without any effect (the closed loop holds
    at 126, 129, 132, 138 and 140 deg; the chirp stays below 125 deg, its discarded run-in
    reaches 130)."""

    name = 'held_out9_counter_pressure_cam_b'
    params = (Param('throttle_area_m2', 'm^2', 1e-7, 0.0, 1e-5,
                    "effective area of the cam valve's throttle"),
              Param('from_rad', 'rad', 128.0 * DEG, 0.0, 3.4,
                    'angle above which the cam valve is fully open'),
              Param('ramp_rad', 'rad', 3.0 * DEG, 1e-4, 0.3, "width of the cam's ramp",
                    fit=False))
    circuits = ('servo',)
    flows = _counter_pressure_flows
    equations = ('mass_balance_b',)
    depends = ({'angle', 'p_b'}, {'angle', 'p_b', 'supply'})
    closed_form = None
    where_rad = (125.0 * DEG, _STROKE_RAD)


# --- supply ----------------------------------------------------------------------------------
def _ejector_supply(t, x, s, p, P, c, dx):
    c[C_PS] = max(x[s], 1e3)


def _ejector_finish(t, x, s, p, P, c, dx):
    # x[s]: pressure at the tee that feeds the valve and the ejector (volume p[5], at the
    # supply temperature); it is fed from the regulated supply through the service unit,
    # which droops by p[1] Pa per kg/s drawn. The ejector's nozzle (effective area p[0]) blows
    # to atmosphere while the cam valve is pressed, over [p[2], p[3]] (ramps p[4])
    ts, r, k = c[C_TS], c[C_R], c[C_KAPPA]
    pt = max(x[s], 1e3)
    w = 0.0
    if c[C_CIRCUIT] == _SERVO:
        w = _band(x[THETA], p[2], p[3], p[4])
    m_ej = 0.0
    if w > 0.0:
        m_ej = orifice_flow(p[0] * w, pt, ts, c[C_PE], c[C_TE], ideal_critical_ratio(k), r,
                            k, _LAMINAR_BAND)
    m_in = (c[C_PS_REG] - pt) / p[1]
    dx[s] = r * ts / p[5] * (m_in - c[C_MSUP] - m_ej)


class CamSwitchedEjectorSupply(Component):
    """The gripper's suction cup took its vacuum from an ejector (a vacuum generator) fed
    from the rig's own supply: a roller cam valve on the frame, pressed by a cam on the arm
    over the old machine's pick zone, switches the ejector on there. Ejector and cam valve
    are still in place and the ejector still blows, to atmosphere, whenever the arm is in
    that zone. It draws as much as the valve at its largest openings, from the same service
    unit: the pressure at the tee that feeds the valve sags while the ejector runs (by the
    regulator's and the line's droop), and the supply transmitter, at the service unit's
    regulated outlet, does not see it. The valve is fed other than the reading: a window
    over the stroke (the cam) sets a second draw on the supply, whose droop adds to that of
    the valve's own draw (a product of states: a function of the angle, with the valve's
    draw, set by the command and the pressures), through a line of small volume (a short
    lag). Not a droop with the valve's flow alone, a supply offset or a memory of a tank.
    Size: an ejector of 1.3 mm nozzle (1.06e-6 m^2 effective) drawing 1.8 g/s (90 l/min ANR)
    at 6 bar gauge, the size for a 40 mm suction cup; the service unit's regulator and its
    2 m of 6 mm line droop by 15 kPa per g/s (so 26 kPa while the ejector runs; 1.5 kPa
    with the valve's 0.1 g/s at the holds, up to 39 kPa in the steps' largest draws); 20
    cm^3 at the tee; the cam on from 110 to 135 deg, its ramps 2 deg of the arm. The window
    was placed from the records without any effect: the chirp swings through 100-124 deg,
    in and out of it; the closed loop holds in it at 126, 129 and 132 deg, above it at 138
    and 140, below it elsewhere."""

    name = 'held_out9_cam_switched_ejector_supply'
    params = (Param('nozzle_area_m2', 'm^2', 1.06e-6, 0.0, 1e-5,
                    "effective area of the ejector's nozzle"),
              Param('droop_pa_s_per_kg', 'Pa.s/kg', 1.5e7, 1e5, 1e9,
                    "the service unit's droop per kg/s drawn"),
              Param('from_rad', 'rad', 110.0 * DEG, 0.0, 3.4,
                    'angle from which the cam valve is fully pressed'),
              Param('to_rad', 'rad', 135.0 * DEG, 0.0, 3.4, 'angle up to which it is pressed'),
              Param('ramp_rad', 'rad', 2.0 * DEG, 1e-4, 0.2, "width of the cam's ramps",
                    fit=False),
              Param('tee_volume_m3', 'm^3', 2e-5, 1e-7, 1e-2,
                    'volume of the line at the tee', fit=False))
    states = (State('tee_pressure_pa', 'Pa', 5.0, 'pressure at the tee feeding the valve'),)
    order = 5
    supply = _ejector_supply
    finish = _ejector_finish
    equations = ('measurement_supply',)
    # the valve fed less than the reading over a window, more so when it draws
    depends = ({'angle'}, {'angle', 'supply'}, {'angle', 'command', 'p_a', 'p_b'},
               {'angle', 'command', 'p_a', 'p_b', 'supply'})
    closed_form = None
    where_rad = (108.0 * DEG, 137.0 * DEG)

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [supply_pa]


# --- errors of measured signals --------------------------------------------------------------
def _torn_read_error(values, signals, core):
    angle = np.asarray(signals['angle_rad'], dtype=float)
    speed = np.asarray(signals['velocity_rad_s'], dtype=float)
    step = 2.0 * math.pi / values['counts_per_rev']
    byte = values['byte_counts']
    first = np.floor(angle / step) + values['zero_count']
    later = np.floor((angle + speed * values['skew_s']) / step) + values['zero_count']
    # the reading is the high byte of the count at the first read and the low byte of the
    # count at the second: it is off from the count at the first read by the low bytes'
    # difference
    low_first = first - byte * np.floor(first / byte)
    low_later = later - byte * np.floor(later / byte)
    return {'angle_rad': (low_later - low_first) * step}


class TornByteCounterRead(Component):
    """The encoder's quadrature counter, a 16-bit counter chip on the acquisition's interface
    board, is read over an 8-bit bus, high byte first. Its inhibit latch should hold the
    count from the first byte's read to the second; the board's driver, rewritten when the
    board was moved to the new computer, releases it after the first read (it toggles the
    output enable between the two) and reads the low byte only after converting the three
    pressure channels. So the low byte is fresher than the high byte: if the count crosses a
    multiple of 256 between the two reads, the reading is torn, 256 counts off (4.6 deg),
    against the direction of motion, for that sample; otherwise it is ahead by what the low
    byte gained in between. A dynamic error of the angle, a function of the angle (where
    the count stands within its byte) and the speed jointly: not a latency (it is mostly
    zero, then a whole byte), a count loss that adds up, a periodic error of the angle or a
    scale error. Size: 0.3 ms between the reads (three conversions of 0.1 ms), so 15 % of the
    byte crossings at the records' 2 ms samples are caught; the counter zeroed at the
    stroke's lower end; 20,000 counts per turn."""

    name = 'held_out9_torn_byte_counter_read'
    params = (Param('skew_s', 's', 3e-4, 0.0, 0.01,
                    "time between the high byte's read and the low byte's"),
              Param('byte_counts', '1', 256.0, 1.0, 65536.0, 'counts of the low byte',
                    fit=False),
              Param('zero_count', '1', 0.0, -1e6, 1e6, 'count at angle 0', fit=False),
              Param('counts_per_rev', '1', 20000.0, 1.0, 1e7, 'counts per turn', fit=False))
    sensor_error = staticmethod(_torn_read_error)
    steady = False
    equations = ('measurement_angle',)
    depends = ({'angle', 'velocity'}, {'angle', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = None


@njit(cache=True)
def _slow_mean(t, p, first, tau):
    """``p`` through a first-order lag of time constant ``tau``, starting from ``first``,
    ``p`` taken as linear between samples."""
    n = len(p)
    out = np.empty(n)
    if n == 0:
        return out
    y = first
    out[0] = y
    for i in range(1, n):
        h = t[i] - t[i - 1]
        a = math.exp(-h / tau)
        slope = (p[i] - p[i - 1]) / h if h > 0.0 else 0.0
        # exact for a ramp between the samples
        y = p[i] - tau * slope + a * (y - p[i - 1] + tau * slope)
        out[i] = y
    return out


def _charge_amplifier_error(values, signals, core):
    p = np.ascontiguousarray(signals['p_a_pa'], dtype=float)
    t = np.ascontiguousarray(signals['t_s'], dtype=float)
    ref = values['reference_pa']
    mean = _slow_mean(t, p, ref, values['time_constant_s'])
    return {'p_a_pa': ref - mean}


class ChargeAmplifierTransmitterA(Component):
    """Chamber a's transmitter failed and was replaced, from the lab's shelf, by a
    piezoelectric (quartz) pressure sensor with its charge amplifier, the kind used for fast
    pressure measurements; its 0-10 V output is scaled to the channel's range and the PLC
    adds the pressure the technician set as the zero: the holds' 4.9 bar gauge. A charge
    amplifier cannot hold a static pressure: its output decays with its time constant, so
    the reading shows p_a's changes but returns to the set zero after each. The error is the
    zero less a slow mean of p_a (p_a through a lag of the amplifier's time constant): a
    dynamic error of p_a, a high-pass: not a lag of the reading (that would follow p_a's slow
    changes and miss its fast ones: here the reverse), an offset or a drift. Size: the
    amplifier's 'short' time constant, 0.5 s, which the technician chose to keep its drift
    down; its zero, 4.9 bar gauge (591 kPa abs), taken when the rig was holding (the slow
    mean starts there)."""

    name = 'held_out9_charge_amplifier_transmitter_a'
    params = (Param('time_constant_s', 's', 0.5, 1e-3, 1e3,
                    "the charge amplifier's time constant"),
              Param('reference_pa', 'Pa', 5.91325e5, 0.0, 2e6,
                    'pressure (absolute) the reading shows at the amplifier\'s zero'))
    sensor_error = staticmethod(_charge_amplifier_error)
    steady = False
    equations = ('measurement_p_a',)
    # the zero less p_a's slow mean: a lagged p_a (0.5 s, longer than the listed lags)
    depends = ({'p_a_lag_20ms'}, {'p_a', 'p_a_lag_20ms'}, {'p_a', 'p_a_rate'}, {'p_a_rate'})
    closed_form = None
    where_rad = None


@njit(cache=True)
def _rate_limited(t, p, rate):
    """``p`` passed through a rate-of-change limiter of ``rate`` [per s], from its first
    sample."""
    n = len(p)
    out = np.empty(n)
    if n == 0:
        return out
    y = p[0]
    out[0] = y
    for i in range(1, n):
        most = rate * (t[i] - t[i - 1])
        y += min(max(p[i] - y, -most), most)
        out[i] = y
    return out


def _gradient_limit_error(values, signals, core):
    p = np.ascontiguousarray(signals['p_b_pa'], dtype=float)
    t = np.ascontiguousarray(signals['t_s'], dtype=float)
    return {'p_b_pa': _rate_limited(t, p, values['max_rate_pa_s']) - p}


class GradientLimitedInputB(Component):
    """The PLC's analog input block for chamber b's channel is still the old machine's: there
    the channel read the pressure of the machine's air receiver, and its block limits the
    value's rate of change (a plausibility filter against spikes from a long unscreened
    cable), to what a receiver's pressure can do. The reading of p_b follows p_b while it
    changes slower than that and lags it, ramping at the limit, while it changes faster. A
    dynamic error of p_b with a memory (the last value passed): a rate limiter, not a lag
    (small and slow changes pass unchanged, however fast the sampling), a hold, a send-on-
    delta or a peak hold. Size: 2 bar/s, the limit set for the receiver (its pressure falls
    at most some 1 bar/s when the whole machine draws); the closed loop's steps change p_b
    at up to 230 bar/s, the chirp's swings at up to 5 bar/s."""

    name = 'held_out9_gradient_limited_input_b'
    params = (Param('max_rate_pa_s', 'Pa/s', 2e5, 1e3, 1e8,
                    "the block's largest rate of change"),)
    sensor_error = staticmethod(_gradient_limit_error)
    steady = False
    equations = ('measurement_p_b',)
    depends = ({'p_b', 'p_b_rate'}, {'p_b', 'p_b_lag_20ms'}, {'p_b', 'p_b_lag_5ms'},
               {'p_b_rate'})
    closed_form = None
    where_rad = None


def _magnet_error(values, signals, core):
    angle = np.asarray(signals['angle_rad'], dtype=float)
    travel = 0.5 * core['pinion_pitch_diameter_m'] * np.maximum(core['stroke_rad'] - angle, 0.0)
    d0 = values['gap_at_end_m']
    return {'p_b_pa': values['shift_at_end_pa'] * (d0 / (d0 + travel)) ** 3}


class PistonMagnetReluctanceCellB(Component):
    """Chamber b's pressure is read by a variable-reluctance cell (a magnetically permeable
    diaphragm between two coils, read with a carrier demodulator), from the lab's shelf,
    screwed straight into b's end cover in place of the cushion needle, to read the chamber
    itself. The actuator's pistons carry the ring magnets for its position switches, and as
    the arm turns up they come towards b's end cover: the magnet's field, along the cell's
    axis, biases its magnetic circuit and shifts its zero. A static error of p_b, a function
    of the angle alone that grows with the inverse cube of the magnet's distance (a dipole's
    field), steeply towards the top of the stroke: not an error that scales with p_b, a
    window with edges, a periodic error or a crosstalk of another pressure. Size: the cell
    shifts by 1 % of its 0.6 MPa span per mT, and the magnet gives some 15 mT at the 5 mm it
    would come to at the end of the stroke: 88 kPa there, falling to 8 kPa at the top hold
    (140 deg, 11 mm), 3-5 kPa over the chirp's 100-124 deg, 1 kPa at the lowest holds; the
    rack's travel, 7 mm per radian of the shaft."""

    name = 'held_out9_piston_magnet_reluctance_cell_b'
    params = (Param('shift_at_end_pa', 'Pa', 8.8e4, 0.0, 1e6,
                    "the cell's shift with the magnet at the end of the stroke"),
              Param('gap_at_end_m', 'm', 5e-3, 1e-4, 0.1,
                    "the magnet's distance from the cell at the end of the stroke"))
    sensor_error = staticmethod(_magnet_error)
    equations = ('measurement_p_b',)
    depends = ({'angle'},)
    closed_form = None
    where_rad = None


SET = (SpeedMonitorRelay, ShuttleValveGaugeLine, FreewheelIndexTurret, CounterPressureCamB,
       TornByteCounterRead, SpringClampTeedA, ChangeoverDeadTime, CamSwitchedEjectorSupply,
       ChargeAmplifierTransmitterA, RotaryJointOnLineB, GradientLimitedInputB,
       PistonMagnetReluctanceCellB)
