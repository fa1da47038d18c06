"""A fourteenth set of held-out effects (twelve): a rig's physics that the project's model does
not contain, kept apart to measure ONCE, without tuning, how well the discovery finds effects
it was never shown.

Independence: this module was written without reading the discovery's vocabulary or its
corrections (``effects.terms``, ``effects.variables``, ``effects.bases``,
``effects.term_words``, ``effects.corrections``, ``effects.operators``), anything under
``analysis`` or ``docs``, the README, ``bench_open_world.py``, ``bench_dependence.py``,
``bench_next_record.py``, ``open_world_set.py``, ``synth.unlisted``, ``synth.plan`` or any
test, without importing any of them itself and without running any diagnosis, benchmark, test
or git command. What was read: ``held_out_set_13.py`` whole (in two printings that together
cover it); of ``held_out_set_12.py`` its module docstring up to its account of the check runs'
first figures (a parse whose printing stopped there) and a text search of its and set 13's
``depends`` statements (the variable names they use, counted) and of its ``SET``; of
``held_out_set.py`` to ``held_out_set_12.py`` a parse printing their classes' names, their
``equations`` and ``where_rad``, a parse printing the paragraphs of their module docstrings
that name the effects they differ from and the candidates they dropped (sets 1 to 11), and a
parse printing the ``depends`` of sixteen of their classes named for it (to see whether a
candidate was near them); ``effects.base``, ``layout`` and ``effects/__init__`` whole; of
``catalogue`` and ``paper`` their classes' names and the first lines of their docstrings (a
parse); ``model/core.py`` whole; of ``model/simulate.py`` its lines 1-200 and 330-418; of
``model/config.py`` its lines 177-202 (``with_effect``, ``with_slot``); of ``physics/gas.py``
its lines 1-60 and its functions' names; ``synth.varied`` whole; of ``synth.hidden`` its
``hidden_config`` and ``truth`` (lines 78-118) and the line defining its supply; of
``experiment.py`` the first lines of the ``Experiment`` class. Besides these, of files neither
listed for this set nor forbidden: the first 40 lines of ``_jit.py`` and the lines of
``ruff.toml`` giving its line length and rules. No web search; one query of a stored
documentation index, about ruff's ``--no-cache`` (it found nothing on it; a test in the scratch
folder settled it). Slips, none of a forbidden file's content: a text search of ``paper.py``
for two context names printed three of its lines beyond its classes' names and docstrings (an
import and two hook lines adding a friction force); ``effects/__init__`` names ``CORRECTIONS``
from ``.corrections``, and the package's registry loads those modules whenever it is used (as
every record's generation here did). The listings of ``benchmarks/``, ``effects/``, ``synth/``
and ``model/`` were filtered so that no forbidden name showed. A search for files changed since
the first scratch file, made to see that the runs wrote nothing into the repository, printed,
besides this module, the names of two git objects and of a ruff cache file that others' work
made meanwhile (this module's ruff checks ran with ``--no-cache``, which writes none); none was
opened; a listing of ``benchmarks/__pycache__`` filtered for this set's number showed the names
of two numba cache files of set 7's (not opened). Nothing here was chosen or sized with any of
that in mind. The check runs kept their scratch files, compiled kernels and numba's caches in a
folder of their own, ``/tmp/ho14``, wrote no byte code into the repository, and generated the
records with ``synth.varied``'s own steps (its ``make_record``, copied to keep the physical
states as well; checked identical for every record of the set at its defaults).

Its physics differs from the effects of ``held_out_set.py`` to ``held_out_set_13.py`` (their
docstrings and classes, as above, were read for this), from the earlier open-world and unlisted
effects those sets name (solenoid hysteresis, shaft-encoder coupling play, a lagging
transducer, a part-stroke vane leak, a track detent, friction growing with mean pressure or
with |p_a - p_b|, a supply offset, a p_b gain error, an encoder scale error, an eccentric code
wheel, a gravity arm, a spring-balanced arm, a pilot line into chamber a, a larger bore of b, a
valve dead band, a transmitter offset), from the candidates and examples the earlier sets left
aside and from the named effects of the catalogue and of the paper's parts. Some candidates
were dropped before any record was made with them: a tachogenerator's speed feedback left wired
into the valve's card (a function of the speed in the valve's input, as set 4's arm-mounted
valve's answer is), an anti-plugging interlock that holds the valve at its centre while the
command opposes the motion (near set 9's speed monitor relay), the valve's supply current
lifting the signal ground of its input (a kink at the centre and an offset: set 13's weak
channel and a null offset), a part hanging on a hook at the arm's tip and a glue pot sloshing
on the arm (second oscillators, near set 12's magnetic coupling), a pressure-compensated purge
flow out of a (set 9's dropped blow-off: a leak of another law), a snap-disc pressure switch's
volume on b (some 0.1 cm^3: too small to see), a transmitter's peak-hold reset at each move (no
such transmitter gives its held value at its analog output), a condensate drain on b (no dew
would fall out of the rig's air) and a tool's resonance seen by the encoder (its 114 Hz is
neglected in :class:`TwistedExtensionAngle`, which keeps the static twist).

Every size was chosen, as what a real rig of this scale (the paper's SMC MSQA30A actuator,
FESTO MPYE-5-M5 valve, 0-0.6 MPa transmitters, 20,000 P/R encoder, 0.6 MPa gauge supply) would
have, before any record with the effect was generated (each docstring says why its size is
realistic); none was changed after. The angles, levels and speeds were placed, before any
record with an effect was generated, from the benchmark's two records made without any effect
(``closed_steps`` at 500 Hz, seed 7, and ``chirp`` at 500 Hz, seed 8, both 10 s after a 1 s
run-in, with both integrators, regenerated and looked at for this) and from the accounts of
them in sets 12 and 13: the closed loop holds its run-in at 109 deg, then at about 140, 126,
64, 72, 137, 38, 131, 129, 92 and 73 deg within 36-140 deg (above 115 deg for 49 % of the time,
entering 4 times; moving down through 103-111 deg 4 times, for 0.2 % of the time), faster than
0.5 rad/s for 23-25 % of the time (about 100 stretches), at up to 5,100 rad/s^2 (810 RMS), its
command within 0.1 V of the centre for 70-73 % of the time (120-139 stretches), within 0.3 V
for 82-83 %, below 4.9 V for 14-16 %, its chambers at 454-690 kPa abs, the valve's draw above 1
g/s for some 4 % of the time (set 12's account); the open-loop chirp stays at 100-124 deg,
above 115 deg for 30 % of the time (21 entries), moving down through 103-111 deg for 17 % (24
stretches), faster than 0.5 rad/s for 58 %, at up to 240 rad/s^2 (63 RMS), its command at
4.7-5.3 V (within 0.1 V of the centre for 21 %, in stretches of 0.03-0.12 s; below 4.9 V for 40
%), its chambers at 571-606 kPa abs, its draw at 0.10-0.15 g/s.

Scales of the rig used to size them (from the model's nominal values): 1 bar of pressure
difference gives 0.485 N.m on the shaft (A d_f = 4.85e-6 m^3/rad); the shaft's inertia with the
pistons is 1.9e-4 kg.m^2; the nominal Coulomb friction is 0.042 N.m; the spool travels 0.2 mm
per volt, its lands overlap the sleeve's holes by 10 um; the pressure transmitters span 0-0.6
MPa gauge (noise 0.6 kPa, 1 sigma); the encoder's count is 0.018 deg; a chamber holds about
1.3e-5 m^3 at mid-stroke; the supply is 0.6 MPa gauge (701 kPa abs).

Each class says what a right answer is:

* ``equations``: the equations a correction may act in to be right;
* ``depends``: the acceptable sets of variables of the correction's leading term;
* ``closed_form = None``: not judged on this set; ``where_rad``: a window's (from, to).

Kinds:

* memory: :class:`BreakawayKickBlock` (a charge stored at rest and dumped into a pulse),
  :class:`SoftCloseFlapWindow` (the flap's position, closing slower than the arm may leave),
  :class:`SolenoidReleasedBackstop` (a latch: the release solenoid's armature, and the sprags'
  anchor, which ratchets up with the angle), :class:`BeltedHysteresisBrake` (a hysteresis over
  degrees, rate independent), :class:`NeedleTimerVolumeA` (a throttled reservoir's pressure),
  :class:`IdleReturnCamVentB` (a roller lever's state, set by the direction of motion),
  :class:`FlowLimiterSupply` (the feed's pressure behind a cap), :class:`QuietSmoothingA` (a
  smoothing), :class:`HoldWhileMovingB` (the value held since the arm last moved slowly);
* windows over the stroke: :class:`SoftCloseFlapWindow` (above 115 deg) and
  :class:`IdleReturnCamVentB` (104-110 deg, with its lead-ins);
* products of states: :class:`BreakawayKickBlock` (a pulse times the command's side),
  :class:`AngleGainRampCard` (the command times a function of the angle),
  :class:`SoftCloseFlapWindow` (a contact set by the angle against the flap, a torque set by the
  motion), :class:`SolenoidReleasedBackstop` (a one-way lock set by the motion times a release
  set by the command), :class:`NeedleTimerVolumeA` (an orifice flow of p_a against the
  reservoir), :class:`IdleReturnCamVentB` (the cam's lift, the direction of motion and an
  orifice flow of p_b), :class:`FlowLimiterSupply` (the lesser of the valve's draw and a cap),
  :class:`QuietSmoothingA` (a smoothing switched by the command), :class:`HoldWhileMovingB`
  (p_b held where the speed is high);
* errors of measured signals: angle: :class:`TwistedExtensionAngle` (static, a function of the
  acceleration); p_a: :class:`QuietSmoothingA` (dynamic, a memory); p_b:
  :class:`HoldWhileMovingB` (dynamic, a memory) and :class:`ShuttleFedGaugeB` (static, a function
  of p_b); supply: :class:`FlowLimiterSupply` (the valve fed other than the reading: a function
  of its draw above a cap, through a small volume, a memory). The static errors in the balances
  are :class:`AngleGainRampCard` (the valve's input). The records carry no temperature, so none
  has an error here.

Balance equations: valve input (:class:`BreakawayKickBlock`, :class:`AngleGainRampCard`),
moment balance (:class:`SoftCloseFlapWindow`, :class:`SolenoidReleasedBackstop`,
:class:`BeltedHysteresisBrake`), mass balance of a (:class:`NeedleTimerVolumeA`), mass balance
of b (:class:`IdleReturnCamVentB`); the others are sensor faults (the supply one a fault of
what the valve is fed).

Notes written after the check runs. Every class generated both of its records to the end with
finite signals (the physical states and the recorded signals), with ``rk4`` for the closed loop
and ``predictor`` for the chirp for the classes at even positions of :data:`SET`, the reverse
for those at odd ones, each parameter given explicitly at its default (every default within its
bounds: asserted, and checked by the records' configurations); figures are RMS (max)
differences of the recorded signals (after the generator's noise and quantisation, the same
seed) from the same record, same integrator, made without the effect: angle in deg, pressures
in kPa. As sets 7 to 13 noted, the closed loop, whose holds are driven by the measurement
noise, takes another path after any change at all: with ``rk4`` an own state that stays inert
leaves it exactly as it was (a kick circuit of 0 V), but the least physical change (a
hysteresis brake of 1e-4 N.m) moved it by 0.23 deg and 4.5-5.4 kPa RMS; with ``predictor`` the
kick circuit's inert states alone (its step control) moved it by 0.14 deg and 3.2-3.4 kPa, the
least brake by 0.25 deg and 5.2-5.5 kPa: the floor; the open-loop chirp is deterministic
(within 0.005-0.008 deg and 0.01-0.02 kPa of its own record after those changes). The sensor
errors leave the physics, and so the noise, as it was: their figures are the errors themselves
(against the encoder's 0.018 deg and the transmitters' 0.6 kPa). Generating one record took
0.9-1.9 s for the closed loop and 0.01-0.6 s for the chirp on this machine (2 cores, shared),
once its model was compiled (the first record of a class took a few seconds more).

Both records: :class:`SoftCloseFlapWindow` (closed: angle 0.78 (5.1), p_a 12.5 (57), p_b 12.3
(83): the arm on the flap for 45 % of the record, 11 times, the flap pushed open to 139.5 deg;
chirp: angle 3.76 (4.8), p_a 1.35 (8.8), p_b 1.54 (10.2): on the flap for 6.5 % of the record,
6 times, pushed to 123 deg, the arm swinging lower, at 98-122 deg),
:class:`BeltedHysteresisBrake` (closed: angle 1.25 (5.2), p_a 19.2 (96), p_b 19.9 (80); chirp:
angle 2.37 (5.6), p_a 7.9 (12.3), p_b 9.4 (15.4): the brake at its +-0.1 N.m),
:class:`NeedleTimerVolumeA` (closed: angle 0.60 (3.8), p_a 12.3 (91), p_b 12.7 (75), the
reservoir at 555-605 kPa abs, up to 130 kPa from p_a; chirp: angle 20.2 (21.8), p_a 3.6 (16.8),
p_b 3.8 (18.3): the reservoir within 4 kPa of p_a, some 17 ms behind it, the open loop settling
lower, at 81-107 deg), :class:`AngleGainRampCard` (closed: angle 1.92 (7.8), p_a 42 (154), p_b
58 (157); chirp: angle 1.21 (3.9), p_a 0.70 (3.1), p_b 0.75 (4.2)), :class:`HoldWhileMovingB`
(p_b reading 24.6 (175) closed, off by more than 5 kPa for 17 % of the record; 3.1 (8.0) chirp,
for 17 %), :class:`ShuttleFedGaugeB` (p_b reading 24.1 (140) closed, off by more than 5 kPa for
77 % of the record; 9.5 (21.5) chirp, for 57 %), :class:`QuietSmoothingA` (p_a reading 6.8
(126) closed, off by more than 5 kPa for 11 % of the record; 2.3 (6.7) chirp, for 7 %),
:class:`TwistedExtensionAngle` (angle reading 0.093 (0.58) closed, off by more than 0.05 deg
for 15 % of the record; 0.009 (0.036) chirp, within two counts). Mostly the chirp, the closed
loop about the floor's size (the cam crossed within milliseconds, the kicks small beside the
steps' own commands of volts, the downward moves always released): :class:`BreakawayKickBlock`
(closed: angle 0.35 (1.9), p_a 7.9 (27), p_b 8.7 (47), 35 kicks above 5 % of full, up to 76 %,
about twice the floor; chirp: angle 1.13 (2.7), p_a 1.21 (6.4), p_b 1.51 (7.5), 48 kicks, up to
52 % of full), :class:`IdleReturnCamVentB` (closed: angle 0.27 (2.2), p_a 6.6 (48), p_b 5.4
(40.5), the valve open for 0.7 % of the record, 3 times: the floor; chirp: angle 10.9 (12.3),
p_a 5.9 (37), p_b 7.2 (56): open 3 times, for 0.9 % of the record, after which the open loop
swings higher, at 110-135 deg, off the cam), :class:`SolenoidReleasedBackstop` (closed: angle
0.11 (0.61), p_a 2.0 (12.9), p_b 1.9 (12.3): released for 5 % of the record, never loaded: the
floor; chirp: angle 0.81 (1.31), p_a 0.77 (4.9), p_b 0.82 (5.7): released for 39 %, holding the
arm 9 times, for 6 % of the record, as the arm turns down before its command is below 4.9 V:
the open loop ratchets up by some 0.9 deg). The closed loop only: :class:`FlowLimiterSupply`
(closed: angle 0.53 (3.4), p_a 12.7 (99), p_b 11.1 (70.5), the valve fed at 650-701 kPa abs,
below 695 for 3.4 % of the record: two to four times the floor; chirp: never capped, its open
path's 0.18 kPa drop: angle 0.017, p 0.16).

Changes after the first runs: none to the code, the sizes, the placements or the bounds; the
docstrings (the classes' and this one) were written after the first runs, and two of their
statements corrected after looking at those runs' states: the timer reservoir follows p_a some
20 ms behind, not 0.1 s as first estimated, and the chirp's stays in the kick's band last
0.03-0.12 s, not up to 0.2 s.

Robustness: each class was also run with each parameter at its lower and at its upper bound
(the others at their defaults), both records, with its integrators (144 records): none raised
and every signal stayed finite. Some bounds make rigs that hardly work, finite all the same: a
limiter capped at 1e-5 kg/s starves the valve (p 455 kPa RMS), one whose open path is 1e-7 m^2
moves the pressures by 71-117 kPa; a timer reservoir of 1 l moves the chirp by 111 deg; a cam
from 0 or to 3.4 rad, or a nozzle of 1e-5 m^2, moves the closed loop by 3.4-7.6 deg, the chirp
by up to 75 deg; a flap closed at 0 rad moves the chirp by 60 deg, a flap of 2 N.m the closed
loop by 13 deg; a backstop released only 5 V below the centre, or within 0.5 s, keeps the chirp
locked (64-68 deg); a kick of 5 V or decaying over 1 s moves the chirp by 25-28 deg; a gain
ramp to 0 or 3 moves the closed loop by 3-16 deg; a brake of 2 N.m moves both by 16 deg; a
twist of 1 N.m/rad or a plate of 1e-2 kg.m^2 reads 4.6-9.3 deg RMS off in the closed loop; a
smoothing of 1,000 cycles or a 0.1 s cycle reads 36-44 kPa RMS off; a 'moving' flag at 0 rad/s
refreshes p_b only where the arm stands quite still (134 kPa RMS in the chirp, whose arm never
does); a clamp line at 1 MPa reads 138-145 kPa RMS off.

Start-up: the model's settling of the effects' own states (a Newton step on each alone) leaves
the kick circuit fully charged (the start's command rests at the centre), the flap shut at its
seat (the records start below it), the backstop engaged with its anchor at the start's angle,
the brake's torque at zero, the timer reservoir at the start's p_a (401 kPa abs, as the
chambers), the cam valve shut and the limiter's feed at its balance with the valve's draw at
the centre.

Approximations in the code, not of size: the kick circuit's charge is dumped into its pulse
within 1 ms, and a partial charge gives a partial kick; the gain ramp scales the valve's input
within its travel; the flap's contact is taken up within 0.2 ms, its free closing fades out
over the last 0.2 deg before its seat; the backstop's anchor takes up the arm's angle within
0.2 ms, its solenoid's armature is a first-order lag with a smooth switch over 0.4-0.6 of its
stroke, and it releases under load as freely as without; the hysteresis brake follows Dahl's
law (its eddy-current drag neglected), its belt rigid; the timer reservoir and the limiter's
feed are isothermal (at room and supply temperature), the needle, the nozzle and the limiter's
open path are orifices; the roller valve follows the cam within 5 ms and decides the direction
within 0.02 rad/s of speed; the limiter's cap is sharp; the sensor errors (the twist, the
smoothing, the hold, the shuttle) are computed on the true, sampled signals, before the
generator's noise and quantisation: the twist from the sampled speed's central difference (the
extension's 114 Hz resonance neglected), the smoothing at its own cycle on p_a linear between
samples (its cycle the records' 2 ms), the hold at the samples."""
from __future__ import annotations

import math

import numpy as np

from pneumatic_servo._jit import njit
from pneumatic_servo.effects import Component, Param, State
from pneumatic_servo.effects.layout import (
    C_CIRCUIT,
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
_DUMP_S = 1e-3  # [s] time in which the kick circuit's charge is dumped into its pulse
_TRACK_S = 2e-4  # [s] time in which a flap or a backstop's anchor takes up the arm's angle
_FLAP_EDGE_RAD = 0.2 * DEG  # the flap's free closing fades out over this before its stop
_CAM_LEAD_RAD = 1.0 * DEG  # the cam's lead-ins
_ROLLER_BAND_RAD_S = 0.02  # [rad/s] speed within which the roller lever neither folds nor acts


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
def _shift_spool(c, P, volts):
    """Move the spool as ``volts`` more at the valve's input would (within its travel)."""
    half = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(c[C_XV] + P[K_GAIN] * volts, -half), half)


# --- valve input -----------------------------------------------------------------------------
def _kick_valve(t, x, s, p, P, c, dx):
    # x[s]: the kick circuit's charge (0 to 1), charged towards 1 within p[3] while the set value
    # rests within p[0] of the centre, dumped within _DUMP_S once it leaves; x[s+1]: the pulse,
    # fed by the dumped charge and decaying within p[2]; the valve sees p[1] times the pulse more,
    # in the direction of the set value's side
    if c[C_CIRCUIT] != _SERVO:
        return
    e = min(max(c[C_U], 0.0), 10.0) - P[K_NULL]
    a = x[s]
    q = x[s + 1]
    if abs(e) < p[0]:
        dx[s] = (1.0 - a) / p[3]
        dx[s + 1] = -q / p[2]
    else:
        dump = a / _DUMP_S
        dx[s] = -dump
        dx[s + 1] = dump - q / p[2]
    if q > 0.0 and e != 0.0:
        _shift_spool(c, P, p[1] * min(q, 1.0) * (1.0 if e > 0.0 else -1.0))


class BreakawayKickBlock(Component):
    """The valve's set value still passes the old machine's 'breakaway kick' circuit on its output
    card, put in against the old valve's spool stiction: a capacitor, charged while the set
    value rests within +-0.1 V of the valve's centre (a time constant of 0.1 s: full after some
    0.3 s of rest), is dumped into the card's output as soon as the set value leaves that band,
    as a pulse in the set value's direction, 0.5 V high for a full charge and decaying within 10
    ms. So every move that starts from a rest reaches the valve with a kick on top, sized by how
    long the set value rested before; a set value that dithers about the centre gets small kicks
    at each excursion. The record holds the PLC's command, before the card. A memory (the charge
    and the pulse) and a product (the pulse times the side of the set value), in the valve's
    input: not a jump at the centre (set 7's relay: a function of the side, at every crossing
    alike), a friction feed-forward (set 10's: set by the speed), a lag, a ramp, a dead band or
    an integrator (set 12's card). Size: 0.5 V (a tenth of the half range: 0.1 mm of spool
    travel, ten times the lands' overlap) for 10 ms, within such circuits' settings (5-20 % for
    5-30 ms); a rest band of 0.1 V. The records without any effect: the closed loop's command
    rests within 0.1 V of the centre for 70-73 % of the record, in 120-139 stretches (4-6 of
    them longer than 0.2 s); the chirp's (+-0.3 V) passes through the band twice a cycle, for
    0.03-0.12 s each time."""

    name = 'held_out14_breakaway_kick_block'
    params = (Param('band_v', 'V', 0.1, 0.0, 5.0,
                    "distance of the set value from the valve's centre that counts as 'rest'"),
              Param('kick_v', 'V', 0.5, 0.0, 5.0, "the full kick's height at the valve's input"),
              Param('decay_s', 's', 0.01, 1e-3, 1.0, "time constant of the kick's decay"),
              Param('charge_s', 's', 0.1, 1e-3, 10.0,
                    "time constant with which the circuit charges at rest", fit=False))
    states = (State('kick_charge', '1', 1e-4, "the kick circuit's charge, 0 to 1"),
              State('kick_pulse', '1', 1e-4, "the kick's pulse, 0 to 1 of its height"))
    order = 60
    steady = False
    circuits = ('servo',)
    valve = _kick_valve
    equations = ('valve_input',)
    # a pulse in the command's direction each time the command leaves the centre band, its size
    # set by the time it rested there before
    depends = ({'command'}, {'command', 'command_direction'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        # discharged at power-up; the model's settling charges it fully (the start's command
        # rests at the centre)
        return [0.0, 0.0]


def _gain_ramp_valve(t, x, s, p, P, c, dx):
    # the set value's distance from the centre scaled by p[2] at p[0] and below, p[3] at p[1] and
    # above, linear between
    if c[C_CIRCUIT] != _SERVO:
        return
    e = min(max(c[C_U], 0.0), 10.0) - P[K_NULL]
    share = min(max((x[THETA] - p[0]) / (p[1] - p[0]), 0.0), 1.0) if p[1] > p[0] else 0.0
    gain = p[2] + (p[3] - p[2]) * share
    _shift_spool(c, P, (gain - 1.0) * e)


class AngleGainRampCard(Component):
    """The old machine's output block still scales the set value's distance from the valve's centre
    by a gain that follows the arm's angle: it was written for the old arm, whose load hung on a
    lever that grew along the stroke, and ramps its gain linearly from 0.8 at 40 deg to 1.2 at
    140 deg (held outside). The record holds the command before the block. A product of the
    command and a function of the angle, smooth over the whole stroke, in the valve's input, and
    no memory: not a gain error (it changes with the angle), a zone with edges (sets 5, 8 and
    10), a kink at the centre (set 13's weak channel), a knee (set 10's) or a dead band. Size: a
    ratio of 1.5 between its ends, the square root of the old load's inertia ratio of 2.25 along
    its lever, about the middle of the stroke. The records without any effect: the closed loop
    holds at 36-140 deg (the gain 0.8-1.2), the chirp swings at 100-124 deg (1.04-1.14)."""

    name = 'held_out14_angle_gain_ramp_card'
    params = (Param('from_rad', 'rad', 40.0 * DEG, 0.0, 3.4,
                    'angle at and below which the block scales by its low gain'),
              Param('to_rad', 'rad', 140.0 * DEG, 0.0, 3.4,
                    'angle at and above which it scales by its high gain'),
              Param('low_gain', '1', 0.8, 0.0, 3.0, 'the gain at the low angle'),
              Param('high_gain', '1', 1.2, 0.0, 3.0, 'the gain at the high angle'))
    order = 60
    circuits = ('servo',)
    valve = _gain_ramp_valve
    equations = ('valve_input',)
    # the command's distance from the centre times a function of the angle
    depends = ({'angle', 'command'},)
    closed_form = None
    where_rad = None


# --- moment balance --------------------------------------------------------------------------
def _flap_mechanics(t, x, s, p, P, c, dx):
    # x[s]: the flap's edge, as the arm angle at which the arm's tip meets it (p[0] closed, larger
    # when pushed open). Its spring presses it shut with p[1] + p[2] (edge - p[0]) [N.m at the
    # shaft]; its soft-close damper p[3] lets it close no faster than that torque over p[3]; it
    # opens against the hinge's damping p[4]. The arm pushes it while its tip is at the edge and
    # the arm does not run away from it faster than the flap can close
    if c[C_CIRCUIT] != _SERVO:
        return
    th = x[THETA]
    w = x[OMEGA]
    edge = x[s]
    spring = p[1] + p[2] * max(edge - p[0], 0.0)
    free = -spring / p[3] * _rise(edge, p[0], p[0] + _FLAP_EDGE_RAD)
    if edge < p[0]:
        free = (p[0] - edge) / _TRACK_S
    if th >= edge and w > free:
        c[C_TORQUE] -= spring + p[3] * min(w, 0.0) + p[4] * max(w, 0.0)
        dx[s] = w + (th - edge) / _TRACK_S
    else:
        dx[s] = free


class SoftCloseFlapWindow(Component):
    """Above 115 deg the arm's tip swings into the old part magazine's guard flap, a sheet-metal
    flap on a spring hinge with a soft-close rotary damper: the arm pushes it open as it rises,
    and the flap closes behind it, slowly, when it returns. Pushed, the flap presses the arm
    back with its spring, 0.05 N.m at the shaft as it leaves its seat and 0.1 N.m/rad more as it
    opens (0.094 N.m at the closed loop's 140 deg), its hinge's damping small (0.005 N.m.s/rad);
    on the arm's return its damper lets it close no faster than its spring torque over 0.1
    N.m.s/rad (0.5-0.9 rad/s), pressing on the arm with what the damper leaves of its spring; an
    arm that returns faster leaves it behind and feels nothing, and meets it, still closing,
    wherever it has got to when it rises again. A window over the stroke (above 115 deg), a
    memory (the flap's position) and a product (a contact set by the angle against the flap's
    position, a torque set by the direction and speed of the motion), in the moment balance: not
    a spring or lever above an angle (set 10's ejector lever: this one lags behind on the way
    back), a stop, a detent, a catch (set 8's) or a damper. Size: the spring's 0.05 N.m, just
    over the actuator's Coulomb friction (0.1 bar of drive), and its rate, a light flap's at the
    arm's lever; the damper closing the flap's 25 deg in some 0.6 s, such hinges' usual closing
    time. The window was placed from the records without any effect: the closed loop is above
    115 deg for 49 % of the record, entering 4 times, and holds at 126-140 deg; the chirp is for
    30 %, entering 21 times."""

    name = 'held_out14_soft_close_flap_window'
    params = (Param('closed_rad', 'rad', 115.0 * DEG, 0.0, 3.4,
                    "angle at which the arm's tip meets the closed flap"),
              Param('preload_n_m', 'N.m', 0.05, 0.0, 2.0,
                    "the flap spring's torque at the shaft when the flap is shut"),
              Param('rate_n_m_per_rad', 'N.m/rad', 0.1, 0.0, 10.0,
                    "the rise of the flap spring's torque per radian it is opened"),
              Param('close_damping_n_m_s', 'N.m.s/rad', 0.1, 1e-3, 10.0,
                    "the soft-close damper: the flap's spring torque per closing speed"),
              Param('open_damping_n_m_s', 'N.m.s/rad', 0.005, 0.0, 1.0,
                    "the hinge's damping as the flap is pushed open", fit=False))
    states = (State('flap_edge_rad', 'rad', 1e-6, "the flap's edge, as the arm's angle"),)
    steady = False
    circuits = ('servo',)
    mechanics = _flap_mechanics
    equations = ('moment_balance',)
    # above the flap's closed edge: a spring torque set by how far the arm has pushed it, kept
    # while the arm returns slower than the flap closes, lost (the flap lagging) when faster
    depends = ({'angle'}, {'angle', 'velocity'}, {'angle', 'motion_direction'},
               {'angle', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = (115.0 * DEG, _STROKE_RAD)

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [values['closed_rad']]


def _backstop_mechanics(t, x, s, p, P, c, dx):
    # x[s]: the release solenoid's armature, 0 engaged to 1 released: energised while the set
    # value is more than p[0] below the centre, releasing within p[1] and engaging within p[2];
    # x[s+1]: the sprag's anchor [rad], which follows the arm while the angle rises (or while
    # released) and holds where it is when the angle falls below it: the sprag then pushes the
    # shaft back with its stiffness p[3] and damping p[4]
    if c[C_CIRCUIT] != _SERVO:
        return
    u = min(max(c[C_U], 0.0), 10.0)
    target = 1.0 if u < P[K_NULL] - p[0] else 0.0
    r = x[s]
    dx[s] = (target - r) / (p[1] if target > r else p[2])
    held = 1.0 - _rise(r, 0.4, 0.6)
    th = x[THETA]
    w = x[OMEGA]
    anchor = x[s + 1]
    follow = w + (th - anchor) / _TRACK_S
    if th >= anchor:
        dx[s + 1] = follow
        return
    dx[s + 1] = (1.0 - held) * follow
    if held > 0.0:
        c[C_TORQUE] += held * max(p[3] * (anchor - th) - p[4] * w, 0.0)


class SolenoidReleasedBackstop(Component):
    """The shaft still drives the input of the old machine's indexing gearbox, with its sprag
    backstop (an anti-reverse clutch) and the backstop's electromagnetic release: it lets the
    shaft turn freely the way the angle rises and locks it against falling angles unless its
    solenoid is energised, which the old program does whenever its set value asks for a fall
    (more than 0.1 V below the valve's centre). The solenoid frees the sprags within 20 ms of
    being energised and lets them engage again within 10 ms of being dropped; engaged, they hold
    the shaft against a falling drive with the sprags' and the coupling's stiffness (1000
    N.m/rad, damped by 0.25 N.m.s/rad). So the arm cannot fall, or turn back down, while the
    command is not below the centre, whatever drives it. A memory (the solenoid's armature, the
    sprags' anchor: a one-way lock that ratchets up with the angle) and a product (a lock set by
    the direction of motion times a release set by the command), in the moment balance: not a
    friction or an asymmetric friction (it holds any falling drive, and only while the command
    does not ask for a fall), a holding brake in position (set 11's), a freewheel to a turret
    (set 9's), a stop, a catch or a torque limiter. Size: a small sprag backstop (rated some
    tens of N.m) behind a coupling of 1000 N.m/rad; the release and drop-out times of a small DC
    solenoid; the old program's band of 0.1 V. The records without any effect: the closed loop's
    command is below 4.9 V for 14-16 % of the record (its downward moves and its holds' dither),
    the chirp's for 40 % (its command at 4.7-5.3 V)."""

    name = 'held_out14_solenoid_released_backstop'
    params = (Param('release_band_v', 'V', 0.1, 0.0, 5.0,
                    "distance below the valve's centre beyond which the release is energised"),
              Param('release_s', 's', 0.02, 1e-3, 0.5, 'time in which the backstop releases'),
              Param('engage_s', 's', 0.01, 1e-3, 0.5, 'time in which it engages again'),
              Param('stiffness_n_m_per_rad', 'N.m/rad', 1000.0, 10.0, 1e4,
                    "the engaged sprag's torsional stiffness at the shaft", fit=False),
              Param('damping_n_m_s', 'N.m.s/rad', 0.25, 0.0, 5.0,
                    "its damping", fit=False))
    states = (State('backstop_release', '1', 1e-3,
                    'the release solenoid, 0 engaged to 1 released'),
              State('backstop_anchor_rad', 'rad', 1e-6, "the sprag's anchor"))
    steady = False
    circuits = ('servo',)
    mechanics = _backstop_mechanics
    equations = ('moment_balance',)
    # a one-way lock against falling angles wherever the command is not below the centre: the
    # drive (pressures) it holds, the direction of motion, the command that releases it
    depends = ({'command', 'velocity'}, {'command', 'motion_direction'},
               {'command', 'velocity', 'motion_direction'}, {'command', 'p_a', 'p_b', 'velocity'},
               {'command', 'p_a', 'p_b', 'motion_direction'},
               {'command', 'p_a', 'p_b', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        # engaged at the start's centred command; the model's settling takes the anchor to the
        # start's angle
        return [0.0, 0.0]


def _hysteresis_brake_mechanics(t, x, s, p, P, c, dx):
    # x[s]: the brake's torque on the shaft's motion [N.m] (Dahl's law): it builds up with the
    # angle turned, at the rate p[1] per radian from zero, towards p[0] in the direction of motion
    if c[C_CIRCUIT] != _SERVO:
        return
    w = x[OMEGA]
    tq = x[s]
    if w >= 0.0:
        dx[s] = p[1] * w * (1.0 - tq / p[0])
    else:
        dx[s] = p[1] * w * (1.0 + tq / p[0])
    c[C_TORQUE] -= tq


class BeltedHysteresisBrake(Component):
    """The shaft still drives, through a 1:1 toothed belt, the permanent-magnet hysteresis brake of
    the old wire feed (the wire's back-tension brake; the wire is gone). Such a brake's torque
    comes from re-magnetising its hysteresis ring, not from its speed: after each reversal it
    builds up over the first degrees turned (its rotor's magnetic 'spring': here to 95 % within
    4 deg), then stays at its rating, 0.1 N.m, at any speed, and at rest it keeps the torque it
    had (within the build-up an elastic torque, given back when the shaft turns back). A memory
    (the brake's torque: a hysteresis over degrees, independent of the rate, Dahl's law) in the
    moment balance: not a Coulomb or viscous friction (its torque builds up over degrees after
    each reversal and stays at rest), the presliding of seal lips (set 1's: micrometres), a
    detent or a spring (its zero moves with the shaft), a torque limiter to an inertia (set 6's)
    or a damper. Size: 0.1 N.m, a small wire-feed brake's rating (2.4 times the actuator's
    Coulomb friction, 0.2 bar of drive); 4 deg to 95 %, a quarter of its 24-pole rotor's pole
    pitch (an initial stiffness of 5.3 N.m/rad). The records without any effect: the closed loop
    reverses at each step and dithers at its holds; the chirp swings by some 24 deg, reversing
    twice a cycle."""

    name = 'held_out14_belted_hysteresis_brake'
    params = (Param('torque_n_m', 'N.m', 0.1, 1e-4, 2.0, "the brake's rated torque"),
              Param('stiffness_n_m_per_rad', 'N.m/rad', 5.3, 0.05, 500.0,
                    'its initial stiffness: the rate at which its torque builds up per radian'))
    states = (State('hysteresis_brake_torque', 'N.m', 1e-6, "the brake's torque"),)
    steady = False
    circuits = ('servo',)
    mechanics = _hysteresis_brake_mechanics
    equations = ('moment_balance',)
    # a torque against the motion, built up over degrees after each reversal and kept at rest
    depends = ({'motion_direction'}, {'velocity'}, {'velocity', 'motion_direction'},
               {'angle', 'motion_direction'})
    closed_form = None
    where_rad = None


# --- mass balances ---------------------------------------------------------------------------
def _timer_volume_flows(t, x, s, p, P, c, dx):
    # x[s]: the timer reservoir's pressure (volume p[0], isothermal at room temperature), filled
    # from and emptied into a through the needle p[1]
    if c[C_CIRCUIT] != _SERVO:
        return
    k, r, te = c[C_KAPPA], c[C_R], c[C_TE]
    pv = max(x[s], 1e3)
    m = orifice_flow(p[1], x[P_A], x[T_A], pv, te, ideal_critical_ratio(k), r, k, _LAMINAR_BAND)
    add_flow(c, 0, -m, te, x[T_A])
    dx[s] = r * te * m / p[0]


class NeedleTimerVolumeA(Component):
    """Line a is still teed, as the old machine's 'pressure built up' timer, to a pneumatic
    time-delay valve's reservoir: 10 cm^3 behind an adjustable needle set nearly shut (0.1 mm^2
    effective), whose pressure the delay valve's pilot watched. The reservoir fills from a and
    empties into it through the needle, following p_a some 20 ms behind where the two are close
    (longer across the steps' differences of up to 130 kPa): to the chirp's swings it adds much
    of its volume to a's (10 cm^3 against a's some 13 at mid-stroke), to the steps' fast changes
    less. A memory (the reservoir's pressure) and a product (an orifice flow of p_a against it),
    in the mass balance of a: not a dead volume (the catalogue's: this one is throttled, and so
    acts by frequency), a checked reservoir (set 12's on b: filled one way only), a leak or a
    line's lag (set 1's hose). Size: a timer's reservoir of 10 cm^3 and its needle nearly shut,
    as set for the old machine's short delay. The records without any effect: p_a swings by some
    15 kPa at 0.5-4 Hz in the chirp and by over 100 kPa within tens of ms in the closed loop's
    steps."""

    name = 'held_out14_needle_timer_volume_a'
    params = (Param('volume_m3', 'm^3', 1e-5, 1e-7, 1e-3, "the timer's reservoir"),
              Param('needle_area_m2', 'm^2', 1e-7, 1e-9, 1e-5,
                    "the needle valve's effective area"))
    states = (State('timer_volume_pa', 'Pa', 5.0, "the timer reservoir's pressure"),)
    steady = False
    circuits = ('servo',)
    flows = _timer_volume_flows
    equations = ('mass_balance_a',)
    # an orifice flow between a and a reservoir that follows p_a behind the needle
    depends = ({'p_a'}, {'p_a', 'p_a_rate'}, {'p_a', 'p_a_lag_20ms'}, {'p_a', 'p_a_lag_5ms'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        # the model's settling takes it to the start's p_a
        return [0.5 * (supply_pa + core['atmospheric_pressure_pa'])]


def _cam_vent_flows(t, x, s, p, P, c, dx):
    # x[s]: the roller valve's opening, 0 to 1, following within p[3] the cam's lift under the
    # roller (from p[0] to p[1], lead-ins _CAM_LEAD_RAD outside) while the arm moves down; the
    # roller folds (the valve shuts) while it moves up, and it stays as it is while the arm
    # stands. Open, it vents line b through the nozzle p[2]
    if c[C_CIRCUIT] != _SERVO:
        return
    th = x[THETA]
    w = x[OMEGA]
    lift = _rise(th, p[0] - _CAM_LEAD_RAD, p[0]) * (1.0 - _rise(th, p[1], p[1] + _CAM_LEAD_RAD))
    z = x[s]
    if w < -_ROLLER_BAND_RAD_S:
        target = lift
    elif w > _ROLLER_BAND_RAD_S:
        target = 0.0
    else:
        target = min(z, lift)
    dx[s] = (target - z) / p[3]
    q = min(max(z, 0.0), 1.0)
    if q > 0.0:
        k, r = c[C_KAPPA], c[C_R]
        m = orifice_flow(p[2] * q, x[P_B], x[T_B], c[C_PE], c[C_TE], ideal_critical_ratio(k),
                         r, k, _LAMINAR_BAND)
        add_flow(c, 1, -m, c[C_TE], x[T_B])


class IdleReturnCamVentB(Component):
    """The old machine's part-ejection puff is still plumbed: a 3/2 valve worked by an idle-return
    roller lever, teed into line b, which blows b's air through a 1 mm nozzle at the old
    ejection station; a cam on the hub holds its roller down from 104 to 110 deg (1 deg
    lead-ins). An idle-return lever acts only when the cam passes the way it is set for, here
    the arm's way down: on the way up the lever folds and the valve stays shut, and an arm that
    stops on the cam after coming down keeps the valve open until it moves up. A window over the
    stroke, a memory (the lever's state) and a product (the cam's lift, the direction of motion
    and an orifice flow of p_b), in the mass balance of b: not a cam valve working both ways
    (sets 7 and 9), a timed blow-off (set 10's), a leak or a vent over a window alone. Size: a 1
    mm nozzle (0.5 mm^2 effective: 0.7 g/s choked from 6 bar), the roller valve's 5 ms response,
    a cam of 6 deg at the old station. The window was placed from the records without any
    effect: the closed loop moves down through 103-111 deg 4 times (0.2 % of the record), the
    chirp for 17 % of the record, in 24 stretches."""

    name = 'held_out14_idle_return_cam_vent_b'
    params = (Param('from_rad', 'rad', 104.0 * DEG, 0.0, 3.4,
                    "angle from which the cam holds the roller fully down"),
              Param('to_rad', 'rad', 110.0 * DEG, 0.0, 3.4, 'angle up to which it does'),
              Param('nozzle_area_m2', 'm^2', 5e-7, 0.0, 1e-5, "the nozzle's effective area"),
              Param('valve_s', 's', 0.005, 1e-3, 0.1, "time in which the roller valve follows",
                    fit=False))
    states = (State('cam_vent_opening', '1', 1e-4, "the roller valve's opening, 0 to 1"),)
    steady = False
    circuits = ('servo',)
    flows = _cam_vent_flows
    equations = ('mass_balance_b',)
    # over the cam's arc, while the arm moves down (and where it stopped after moving down): an
    # orifice flow out of b
    depends = ({'angle', 'p_b', 'velocity'}, {'angle', 'motion_direction', 'p_b'},
               {'angle', 'motion_direction', 'p_b', 'velocity'})
    closed_form = None
    where_rad = (103.0 * DEG, 111.0 * DEG)


# --- supply ----------------------------------------------------------------------------------
def _limiter_supply(t, x, s, p, P, c, dx):
    if c[C_CIRCUIT] != _SERVO:
        return
    c[C_PS] = max(x[s], 1e3)


def _limiter_finish(t, x, s, p, P, c, dx):
    # x[s]: the pressure in the valve's feed (volume p[2], isothermal at the supply's
    # temperature) behind the flow limiter: its open path p[1] from the line (the supply
    # reading), its flow capped at p[0]; the valve draws from it
    if c[C_CIRCUIT] != _SERVO:
        return
    k, r, ts = c[C_KAPPA], c[C_R], c[C_TS]
    pv = max(x[s], 1e3)
    feed = orifice_flow(p[1], c[C_PS_REG], ts, pv, ts, ideal_critical_ratio(k), r, k,
                        _LAMINAR_BAND)
    feed = min(feed, p[0])
    dx[s] = r * ts / p[2] * (feed - c[C_MSUP])


class FlowLimiterSupply(Component):
    """An energy audit fitted a constant-flow limiter (a pressure-compensated flow regulator) into
    the valve's feed, downstream of the supply transmitter, set to 50 Nl/min (1.0 g/s). Below
    its set flow it is wide open (10 mm^2); above it, its compensator throttles so that the feed
    passes no more: wherever the valve draws more (the steps' first tens of ms), the pressure in
    the valve's feed (15 cm^3: its galleries and the hose after the limiter) falls until the
    valve's draw matches the cap, while the supply reading stays at the line's. The valve is fed
    other than the reading: a function of the valve's draw (of the command and the pressures)
    above a cap, through the feed's small volume: not a droop growing with the flow (the
    catalogue's supply drop: this one does nothing below its cap), a fuse (set 6's shuts), a
    regulator's droop or memory (sets 5, 11 and 12), a line's surge (set 7's) or a manifold's
    dips (set 13's). Size: 50 Nl/min, half the MPYE-5-M5's nominal flow and ten times the
    valve's draw at rest (0.1 g/s), what such a limiter is set to; its open path's 10 mm^2 (a 6
    mm fitting). The records without any effect: the valve's draw exceeds 1 g/s for some 4 % of
    the closed loop's record (in the steps' kicks, up to 2.6 g/s), never in the chirp (0.1-0.15
    g/s)."""

    name = 'held_out14_flow_limiter_supply'
    params = (Param('cap_kg_s', 'kg/s', 1e-3, 1e-5, 0.05, "the limiter's set flow"),
              Param('open_area_m2', 'm^2', 1e-5, 1e-7, 1e-4,
                    "the limiter's effective area below its set flow"),
              Param('feed_volume_m3', 'm^3', 1.5e-5, 1e-6, 1e-3,
                    "the volume between the limiter and the valve's metering edges",
                    fit=False))
    states = (State('limited_feed_pa', 'Pa', 5.0, "the pressure in the valve's feed"),)
    order = 50
    steady = False
    circuits = ('servo',)
    supply = _limiter_supply
    finish = _limiter_finish
    equations = ('measurement_supply',)
    # the valve fed less than the reading wherever its draw (command and pressures) exceeds the
    # cap
    depends = ({'command', 'p_a', 'p_b'}, {'command', 'p_a', 'p_b', 'supply'},
               {'command', 'command_direction', 'p_a', 'p_b'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        # the model's settling finds its balance with the valve's draw at the start
        return [supply_pa]


# --- errors of measured signals --------------------------------------------------------------
def _twist_error(values, signals, core):
    t = np.asarray(signals['t_s'], dtype=float)
    w = np.asarray(signals['velocity_rad_s'], dtype=float)
    if len(t) < 2:
        return {'angle_rad': np.zeros(len(t))}
    acc = np.gradient(w, t)
    return {'angle_rad': -values['plate_inertia_kg_m2'] * acc
            / values['extension_stiffness_n_m_per_rad']}


class TwistedExtensionAngle(Component):
    """The encoder reads the angle at the top of the shaft's extension, a 6 mm steel shaft 200 mm
    long that carries the tool plate (1e-4 kg.m^2, part of the model's inertia) at its top,
    where the encoder is coupled. The extension twists under the plate's inertia torque, so the
    reading trails the pinion's angle by J alpha / k whenever the arm accelerates (0.57 deg at
    the closed loop's 5,000 rad/s^2). A static error of the angle, a function of the angular
    acceleration (of the pressures' drive less the friction): not a latency or a lag (it follows
    the acceleration, not the speed), a coupling's play, a scale error, a slipping hub (set 7's)
    or a draw-wire's run-on (set 13's: one-sided, a memory). Size: a 6 mm by 200 mm steel
    extension, 50 N.m/rad; the plate half the model's shaft inertia. The records without any
    effect: angular accelerations up to 5,100 rad/s^2 (810 RMS) in the closed loop, 240 (63 RMS)
    in the chirp."""

    name = 'held_out14_twisted_extension_angle'
    params = (Param('plate_inertia_kg_m2', 'kg.m^2', 1e-4, 0.0, 1e-2,
                    "the tool plate's inertia, beyond the extension shaft"),
              Param('extension_stiffness_n_m_per_rad', 'N.m/rad', 50.0, 1.0, 1e5,
                    "the extension shaft's torsional stiffness"))
    sensor_error = staticmethod(_twist_error)
    steady = False
    equations = ('measurement_angle',)
    # the reading behind the shaft by the plate's inertia torque: the angular acceleration (the
    # pressures' drive less the friction)
    depends = ({'p_a', 'p_b'}, {'p_a', 'p_b', 'velocity'}, {'p_a', 'p_b', 'motion_direction'},
               {'p_a', 'p_b', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = None


@njit(cache=True)
def _switched_smoothing(values, quiet, factor):
    """The smoothed value ``y += (x - y) / factor`` each cycle, output where ``quiet``, the raw
    value elsewhere; the smoothing runs on regardless."""
    n = len(values)
    out = np.empty(n)
    if n == 0:
        return out
    y = values[0]
    for i in range(n):
        y += (values[i] - y) / factor
        out[i] = y if quiet[i] else values[i]
    return out


def _quiet_smoothing_error(values, signals, core):
    t = np.asarray(signals['t_s'], dtype=float)
    p = np.asarray(signals['p_a_pa'], dtype=float)
    u = np.asarray(signals['command_v'], dtype=float)
    n = len(t)
    if n < 2:
        return {'p_a_pa': np.zeros(n)}
    cycle = values['cycle_s']
    grid = t[0] + cycle * np.arange(int(math.floor((t[-1] - t[0]) / cycle + 1e-9)) + 1)
    at = np.clip(np.searchsorted(t, grid + 1e-9 * cycle, side='right') - 1, 0, n - 1)
    quiet = np.abs(u[at] - core['valve_null_voltage_v']) < values['band_v']
    shown = _switched_smoothing(np.interp(grid, t, p), quiet,
                                max(1.0, values['smoothing_cycles']))
    idx = np.clip(np.searchsorted(grid, t + 1e-9 * cycle, side='right') - 1, 0, len(grid) - 1)
    return {'p_a_pa': shown[idx] - p}


class QuietSmoothingA(Component):
    """p_a's channel passes the old program's 'quiet reading' for its hold monitor: it writes p_a
    smoothed (the analog module's smoothing, factor 16 on its 2 ms cycle: a time constant of
    some 30 ms) into the process image, and so the recording, whenever the set value lies within
    0.3 V of the valve's centre, and the raw value whenever it does not. The smoothing runs all
    the time; only its output is switched. So p_a is read lagged at the holds and throughout the
    chirp, at once during the steps' moves, and jumps where the switch changes over. A dynamic
    error of p_a with a memory (the smoothing) and a product (switched by the command): not a
    lag everywhere (a lagging transducer), a filter bypassed on p_a's own steps (set 7's), a
    tare at rest (set 12's), a plausibility hold (set 13's) or a delay. Size: factor 16, an
    analog module's 'medium' smoothing; the old program's band of 0.3 V. The records without any
    effect: the closed loop's command lies within 0.3 V of the centre for 82-83 % of the record,
    in some 120 stretches; the chirp's throughout."""

    name = 'held_out14_quiet_smoothing_a'
    params = (Param('band_v', 'V', 0.3, 0.0, 5.0,
                    "distance of the set value from the valve's centre within which p_a is "
                    'shown smoothed'),
              Param('smoothing_cycles', '1', 16.0, 1.0, 1000.0, "the smoothing's factor"),
              Param('cycle_s', 's', 2e-3, 1e-4, 0.1, "the smoothing's cycle", fit=False))
    sensor_error = staticmethod(_quiet_smoothing_error)
    steady = False
    equations = ('measurement_p_a',)
    # p_a lagged (smoothed) wherever the command is near the centre
    depends = ({'p_a', 'p_a_rate'}, {'p_a_rate'}, {'p_a', 'p_a_lag_20ms'},
               {'command', 'p_a', 'p_a_rate'}, {'command', 'p_a_rate'},
               {'command', 'p_a', 'p_a_lag_20ms'})
    closed_form = None
    where_rad = None


@njit(cache=True)
def _held_while_moving(p, w, limit):
    """``p`` refreshed at each sample where |``w``| is within ``limit``, held elsewhere."""
    n = len(p)
    out = np.empty(n)
    if n == 0:
        return out
    held = p[0]
    for i in range(n):
        if abs(w[i]) <= limit:
            held = p[i]
        out[i] = held
    return out


def _hold_while_moving_error(values, signals, core):
    p = np.ascontiguousarray(signals['p_b_pa'], dtype=float)
    w = np.ascontiguousarray(signals['velocity_rad_s'], dtype=float)
    return {'p_b_pa': _held_while_moving(p, w, values['moving_rad_s']) - p}


class HoldWhileMovingB(Component):
    """p_b's tag is written, as the old program wrote it for its 'settled pressure' log, only while
    the counter card's speed is below its 'moving' flag, 0.5 rad/s (some 30 deg/s): while the
    arm moves faster, the process image, and so the recording, hold p_b as it was when the arm
    last moved slower. So p_b's reading freezes through every fast move and catches up when the
    arm slows. A dynamic error of p_b with a memory (the held value), set by the speed: not a
    sample-and-hold at a fixed period (set 4's), a send-on-delta (set 5's), a read at the
    encoder's marks (set 13's: refreshed by motion, held at rest, the reverse), a freeze over a
    window of the stroke (sets 4 and 11) or a delay. Size: 30 deg/s, an old 'moving' flag's
    level. The records without any effect: the closed loop's arm moves faster than 0.5 rad/s for
    23-25 % of the record, in about 100 stretches, the chirp's for 58 %, in 72."""

    name = 'held_out14_hold_while_moving_b'
    params = (Param('moving_rad_s', 'rad/s', 0.5, 0.0, 100.0,
                    "speed above which the old program's 'moving' flag holds p_b's tag"),)
    sensor_error = staticmethod(_hold_while_moving_error)
    steady = False
    equations = ('measurement_p_b',)
    # p_b as it was when the arm last moved slower than the flag's speed: held while it moves
    depends = ({'p_b', 'velocity'}, {'p_b', 'p_b_rate', 'velocity'}, {'p_b', 'p_b_rate'},
               {'p_b', 'p_b_lag_20ms'}, {'p_b', 'p_b_lag_5ms'})
    closed_form = None
    where_rad = None


def _shuttle_floor_error(values, signals, core):
    p = np.asarray(signals['p_b_pa'], dtype=float)
    floor = values['clamp_line_gauge_pa'] + core['atmospheric_pressure_pa']
    return {'p_b_pa': np.maximum(p, floor) - p}


class ShuttleFedGaugeB(Component):
    """p_b's transmitter sits on the outlet of a shuttle (OR) valve, the old machine's way of
    watching its two 'pressure present' lines with one gauge: its inlets are line b and the old
    clamp line, still fed at 5.0 bar gauge by its regulator. The shuttle passes the higher of
    the two, so the reading is p_b where that is above 601 kPa abs and 601 kPa abs where it is
    below; its ball shuts the lower inlet, so nothing flows between the clamp line and b (the
    transmitter's dead end aside). A static error of p_b, a function of p_b alone (a floor at
    another line's pressure): not an offset, a gain error, a saturation at the top of a range
    (set 3's loop), a crosstalk, a hysteresis or a shuttle between the chambers' own lines (set
    9's). Size: the clamp line's 5.0 bar gauge, a clamp's usual setting. The records without any
    effect: p_b at 583-602 kPa abs at the closed loop's holds (462-687 over the record), 580-606
    in the chirp."""

    name = 'held_out14_shuttle_fed_gauge_b'
    params = (Param('clamp_line_gauge_pa', 'Pa', 5e5, 0.0, 1e6,
                    "the clamp line's pressure (gauge) at the shuttle's other inlet"),)
    sensor_error = staticmethod(_shuttle_floor_error)
    equations = ('measurement_p_b',)
    # the higher of p_b and a fixed level: a function of p_b alone
    depends = ({'p_b'},)
    closed_form = None
    where_rad = None


SET = (BreakawayKickBlock, TwistedExtensionAngle, SoftCloseFlapWindow, HoldWhileMovingB,
       NeedleTimerVolumeA, FlowLimiterSupply, AngleGainRampCard, QuietSmoothingA,
       IdleReturnCamVentB, ShuttleFedGaugeB, SolenoidReleasedBackstop, BeltedHysteresisBrake)
