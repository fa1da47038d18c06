"""An eleventh set of held-out effects (twelve): a rig's physics that the project's model
does not contain, kept apart to measure ONCE, without tuning, how well the discovery finds
effects it was never shown.

Independence: this module was written without reading the discovery's vocabulary or its
corrections (``effects.terms``, ``effects.variables``, ``effects.bases``,
``effects.term_words``, ``effects.corrections``, ``effects.operators``), anything under
``analysis`` or ``docs``, the README, ``bench_open_world.py``, ``bench_dependence.py``,
``open_world_set.py``, ``synth.unlisted`` or any test, without importing any of them itself
and without running any diagnosis, benchmark, test or git command. What was read:
``held_out_set_10.py`` whole and of ``held_out_set_9.py`` its docstring, its helpers and
five of its classes; of ``held_out_set_6.py`` to ``held_out_set_8.py`` the first 6,000
characters of their module docstrings (a display cut the middle of set 7's), a text search
of those three files for their records and imports, their classes' names, the first 200
characters of their classes' docstrings and the statements that assign their ``name``,
``equations``, ``depends`` and ``where_rad``; of ``held_out_set.py`` to
``held_out_set_5.py`` and of ``held_out_set_7.py`` and ``held_out_set_9.py`` their classes'
names and the statements that assign their ``equations``, ``depends`` and ``where_rad`` (a
parse that printed those and nothing else); ``effects.base``, ``layout`` and
``effects/__init__`` whole, ``paper`` from its line 140 on (its thermal and friction parts)
and a text search of it for its classes and names; of ``catalogue`` its classes' names and
the first lines of their docstrings (a parse); ``model/core.py``; of ``model/simulate.py``
``sensor_errors`` and ``measured_states``; ``physics/gas.py``'s ``orifice_flow``;
``synth.varied`` whole and ``synth.hidden``'s ``hidden_config`` and ``truth``; of
``model/simulate.py`` also its lines 140-175; of ``model/config.py`` its lines 30-62
(``_check_values``) and 170-200 (``copy``, ``with_effect``, ``with_slot``); of
``experiment.py`` the ``Experiment`` class's checks of its signals; of ``control/pid.py`` a
text search for its gains. The paper was not opened (the rig's parts as the earlier sets
state them). No web search. Slips, none of a forbidden file's content: a listing of
``pneumatic_servo/`` and of ``effects/`` was filtered (without ``analysis`` and the five
forbidden modules), one of ``benchmarks/`` to the held-out sets; ``effects/__init__`` names
``CORRECTIONS`` from ``.corrections``, and the package's registry loads those modules
whenever it is used (as every record's generation here did). Nothing here was chosen or
sized with any of that in mind. The check runs kept their scratch files, compiled kernels
and numba's caches in a folder of their own, ``/tmp/ho11``.

Its physics differs from the effects of ``held_out_set.py`` to ``held_out_set_10.py``
(their docstrings and classes, as above, were read for this), from the earlier open-world
and unlisted effects those sets name (solenoid hysteresis, shaft-encoder coupling play, a
lagging transducer, a part-stroke vane leak, a track detent, friction growing with mean
pressure or with |p_a - p_b|, a supply offset, a p_b gain error, an encoder scale error, an
eccentric code wheel, a gravity arm, a spring-balanced arm, a pilot line into chamber a, a
larger bore of b, a valve dead band, a transmitter offset), from the examples the earlier
sets left aside and from the named effects of the catalogue and of the paper's parts. Some
candidates were dropped before any record was made with them: a quadratic air drag of a
guard plate on the arm (a plate light enough not to be a payload drags 0.03 N.m at the
steps' top speed, below the friction), a bulging plastic end cover (0.01 cm^3 at 5 bar), a
zero-order hold of the set value at a fieldbus's cycle (the adaptive integrator could step
over its sampling), a 16-bit counter's wrap (20,000 counts per turn never wrap within the
stroke), an acceleration-free ZOH or median filter of a reading (a delay, as the lagging
transducer), a transmitter's temperature coefficient (near set 3's thermal transient) and a
supply ripple of a piston compressor (no state of the rig sets it).

Every size was chosen, as what a real rig of this scale (the paper's SMC MSQA30A actuator,
FESTO MPYE-5-M5 valve, 0-0.6 MPa transmitters, 20,000 P/R encoder, 0.6 MPa gauge supply)
would have, before any record with the effect was generated (each docstring says why its
size is realistic); none was changed after. The angles, levels and times were placed, before
any record with an effect was generated, from the benchmark's two records made without any
effect (``closed_steps`` at 500 Hz, seed 7, and ``chirp`` at 500 Hz, seed 8, both 10 s after
a 1 s run-in, with both integrators, looked at for this): the closed loop holds at about
140, 126, 64, 72, 137, 38, 131, 129, 91 and 72 deg within 36-140 deg, at up to 48 rad/s and
5,100 rad/s^2, its shaft below 0.05 rad/s for 71-73 % of the record in stretches of up to
0.83 s (four to six over 0.3 s), its command within +-0.3 V of the centre at rest (99th
percentile; about half its holds hunt within 4.7-5.3 V, the others stay within 4.98-5.02 V)
and beyond +-0.5 V for 15 % of the time in some 117 stretches, 2.3-7.7 V (1st-99th
percentile) overall, its chambers at 454-690 kPa abs, p_a - p_b within -213..+205 kPa, p_a
and p_b changing at up to 273 and 228 bar/s; the open-loop chirp stays at 100-124 deg
(its discarded run-in swings over 95-130), below 2.9 rad/s and 240 rad/s^2, never below
0.05 rad/s for more than 0.09 s, p_a at 571-603 and p_b at 580-606 kPa abs, changing at up
to 4 and 5 bar/s, its command at 4.7-5.3 V.

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

* memory: :class:`InPositionHoldingBrake` (a standstill timer and the brake's switching),
  :class:`ViscoelasticCableCarrier` (a relaxing element's deflection),
  :class:`LeftoverNotchFilterBlock` (a second-order filter's states of the command),
  :class:`CamPilotVolumeB` (a pilot line's pressure), :class:`AirKnifeOnUpKickA` (a timer
  started by the command), :class:`StickyLocalRegulatorSupply` (a regulator's friction
  band: a play), :class:`CaptureRegisterAngle` (the edge of entry into a window),
  :class:`PulseDirectionCounter` (a count of the speed's magnitude with the command's side);
* windows over the stroke: :class:`CamPilotVolumeB` (from 120 deg up),
  :class:`CaptureRegisterAngle` (103-111 deg), and, over the whole stroke about a neutral,
  :class:`PressurisedHoseLoopA` (90 deg) and :class:`ViscoelasticCableCarrier` (100 deg);
* products of states: :class:`PressurisedHoseLoopA` (the angle x a function of p_a),
  :class:`InPositionHoldingBrake` (a friction x a latch of the speed and the command),
  :class:`CamPilotVolumeB` (a function of the angle x an orifice flow of p_b),
  :class:`AirKnifeOnUpKickA` (a latch of the command x an orifice flow of p_a),
  :class:`PulseDirectionCounter` (|speed| x the command's side),
  :class:`TransmitterAtValveEndB` (the square of b's flow: p_b's rate, the speed and the
  angle), :class:`ArmMountedTransmitterA` (the acceleration: the pressures and the friction);
* errors of measured signals: angle: :class:`CaptureRegisterAngle` (dynamic, a memory,
  over a window), :class:`PulseDirectionCounter` (dynamic, a memory); p_a:
  :class:`ArmMountedTransmitterA` (static in the states: the acceleration); p_b:
  :class:`TransmitterAtValveEndB` (dynamic: the flow, from rates); supply:
  :class:`StickyLocalRegulatorSupply` (dynamic, a memory: the valve is fed other than the
  reading). The valve's static staircase (:class:`EightBitOutputModule`) is the static
  counterpart in the balances.

Balance equations: valve input (:class:`EightBitOutputModule`,
:class:`LeftoverNotchFilterBlock`), moment balance (:class:`PressurisedHoseLoopA`,
:class:`InPositionHoldingBrake`, :class:`ViscoelasticCableCarrier`), mass balance of a
(:class:`AirKnifeOnUpKickA`), mass balance of b (:class:`CamPilotVolumeB`); the others are
sensor faults (the supply one a fault of what the valve is fed).

Notes written after the check runs. Every class generated both of its records to the end
with finite signals (the physical states and the recorded signals), with ``rk4`` for the
closed loop and ``predictor`` for the chirp for the classes at even positions of
:data:`SET`, the reverse for those at odd ones, each parameter given explicitly at its
default (every default within its bounds: asserted, and checked by the records'
configurations); figures are RMS (max) differences of the recorded signals (after the
generator's noise and quantisation, the same seed) from the same record, same integrator,
made without the effect: angle in deg, pressures in kPa. As sets 7 to 10 noted, the closed
loop, whose holds are driven by the measurement noise, takes another path after any change
at all: a hose loop of 1e-13 N.m/(rad.Pa) changed it by 0.10 deg and 1.7-1.8 kPa RMS with
``rk4``, an air knife of 1e-13 m^2 by 0.18 deg and 4.4-4.5 kPa with ``predictor``, and an
output module of 0.1 mV steps by 0.19 deg and 4.3-4.6 kPa with ``rk4``: the floor; the
open-loop chirp is deterministic (within 0.001 deg and 0.001 kPa of its own record). The
sensor errors leave the physics, and so the noise, as it was: their figures are the errors
themselves (against the encoder's 0.018 deg and the transmitters' 0.6 kPa).

Both records: :class:`PressurisedHoseLoopA` (closed: angle 0.32 (2.0), p_a 7.2 (48), p_b 7.1
(25); chirp: angle 6.13 (9.3), p_a 1.2, p_b 1.3, the arm at 98-123 deg),
:class:`InPositionHoldingBrake` (closed: applied three times, for 18 % of the record: angle
0.71 (5.8), p_a 11.5 (74), p_b 13.8 (86); chirp: applied in the discarded run-in only, from
0.16 to 0.36 s, while the arm stands at its start, which shifts the record by angle 1.84
(2.1), p_a 0.08, p_b 0.08), :class:`ViscoelasticCableCarrier` (closed: angle 0.45 (2.8), p_a
8.8 (60), p_b 8.9 (47), the relaxing element at -1.25..+1.16 rad; chirp: angle 2.15 (3.3),
p_a 0.7, p_b 0.8), :class:`EightBitOutputModule` (closed: angle 0.24 (1.1), p_a 4.9 (16), p_b
5.7 (18), barely above the floor: WEAK in the closed loop; chirp: angle 0.19 (0.7), p_a 0.25
(2.6), p_b 0.30 (3.1)), :class:`LeftoverNotchFilterBlock` (closed: angle 1.11 (8.4), p_a 17.4
(113), p_b 17.3 (95); chirp: angle 0.69 (1.9), p_a 1.7 (4.8), p_b 2.1 (6.0)),
:class:`CamPilotVolumeB` (closed: the arm above 120 deg for 49 % of the record, entering
three times, the pilot line at 101-677 kPa abs: angle 0.62 (5.7), p_a 13.6 (108), p_b 16.7
(136); chirp: the discarded run-in swings up to 147 deg and the line's charge, taken from b,
lets the arm ride higher, at 119-144 deg, with the line connected throughout the record
(540-605 kPa abs): angle 19.7 (21.6), p_a 4.9 (28), p_b 5.3 (46)),
:class:`StickyLocalRegulatorSupply` (closed: the valve fed 680-691 kPa abs, mean 684, against
the reading's 701: angle 0.50 (3.2), p_a 19.6 (104), p_b 18.2 (77); chirp: fed 691 kPa abs
throughout (the chirp's draws never leave the band): angle 0.71 (0.9), p_a 9.1 (9.4), p_b
9.1 (9.8): there it acts as a supply offset, its memory shows in the closed loop only),
:class:`CaptureRegisterAngle` (angle reading 0.24 (7.5) closed, 2.11 (8.0) chirp),
:class:`PulseDirectionCounter` (angle reading 48.5 (77) closed: the holds' noise-driven
dither and the steps' overshoots count the wrong way and the reading drifts by tens of
degrees over the record, a gross error, as such a miswired counter makes; 0.26 (0.37) chirp,
whose arm moves against the command's side by little between reversals),
:class:`ArmMountedTransmitterA` (p_a reading 0.49 (3.1) closed; 0.04 (0.15) chirp: WEAK, a
quarter of the noise), :class:`TransmitterAtValveEndB` (p_b reading 2.75 (34.6) closed, in
the steps; 0.009 (0.02) chirp: WEAK, nothing to see in the chirp's slow flows). The closed
loop only: :class:`AirKnifeOnUpKickA` (closed: the knife open for 14.5 % of the record, six
times, p_a down to 323 kPa abs (454 without): angle 2.05 (8.7), p_a 97 (290), p_b 100 (265);
chirp: never switched on, unchanged).

Changes after the first runs: none (no code changed, no size changed, no bound narrowed).

Robustness: each class was also run with each parameter at its lower and at its upper bound
(the others at their defaults), both records, with its integrators (144 records): none
raised and every signal stayed finite. Some bounds make rigs that hardly work, finite all
the same: a hose loop or a cable carrier of 10 N.m/rad, or a hose loop of 1e-5
N.m/(rad.Pa), pins both records' arms near their neutral (closed 62-113 deg, chirp 86-102);
an air knife switched at 0 V empties a and sends the chirp's arm onto the lower stop, one of
1e-5 m^2 or held 5 s moves the closed loop's p_a by 330-420 kPa RMS; a brake of 5 N.m holds
the chirp's arm at its start (95 deg); an output module of 1 V steps sends the chirp onto
the upper stop; a local regulator set at 0 Pa gauge starves the valve (both arms stay
where they start), one drooping 1e9 Pa.s/kg moves the closed loop's pressures by 135 kPa RMS;
a cam pilot line of 1e-3 m^3 sends the chirp onto the upper stop; a notch of quality 0.05 or
at 200 Hz moves the closed loop by 7-9 deg RMS; a pulse-and-direction counter whose
direction bit never changes (0 or 10 V) reads 500-900 deg off; a valve-end transmitter on a
0.1 mm hose reads absurdly (its loss grows with the inverse fourth power of the bore). Start-
up: the model's settling of the effects' own states (a Newton step on each alone) leaves
the notch's states at the initial command's steady state, the brake's timer and the knife's
timer where their initial states put them (the knife's run out, the brake's at zero: the
brake then applies 0.16 s into the run-in of a record that starts at rest, as the chirp's
does), the cam's pilot line at atmospheric pressure (the records start below the cam) and
the regulator's output at its set. Approximations in the code, not of size: the timers are
cleared within 0.05 ms, the brake and the knife's valve are first-order lags behind their
latches, the brake a friction added to the breakaway and the sliding friction alike; the
output module rounds the clipped command, with no settling of its own; the notch is the
continuous filter (the block's discrete one at the PLC's cycle is near it below 50 Hz); the
hose loop's and the cable carrier's rates are linear in the angle; the cam's pilot line is
isothermal at room temperature and its valve an orifice (pressed, to b; released, to
atmosphere, through the same area, shared over the cam's ramp); the knife an orifice from a
to atmosphere; the regulator's output a play operator (the friction band) on its drooping
set, closed within a first-order time; the sensor errors (the capture register, the counter,
the arm-mounted transmitter, the valve-end transmitter) are computed on the true, sampled
signals, before the generator's noise and quantisation: the capture register and the
counter from the sampled angle (an entry or a count between two samples is resolved at the
next sample), the acceleration and the flow into b as central differences of the sampled
speed and of b's mass (b's gas temperature taken from the states where the signals carry
it, else the room's).
"""
from __future__ import annotations

import math

import numpy as np

from pneumatic_servo._jit import njit
from pneumatic_servo.effects import Component, Param, State
from pneumatic_servo.effects.layout import (
    C_CIRCUIT,
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
_CLEAR_S = 5e-5  # [s] time constant with which a timer is cleared


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
def _eight_bit_valve(t, x, s, p, P, c, dx):
    # the output module's code: the set value (0-10 V) rounded to the nearest of its steps
    # p[0]; it sets the spool afresh (it runs first among the valve hooks)
    u = min(max(c[C_U], 0.0), 10.0)
    q = math.floor(u / p[0] + 0.5) * p[0]
    lim = P[K_HALF_W] + P[K_HOLE_R]
    c[C_XV] = min(max(P[K_GAIN] * (q - P[K_NULL]), -lim), lim)


class EightBitOutputModule(Component):
    """The valve's set value comes from the old machine's analog output module, which is
    still in the rack: an 8-bit module (0-10 V in 255 steps of 39.2 mV), where a 12- or
    16-bit one would be expected. The PLC's command is computed in floating point and the
    module rounds it to its nearest step: the valve sees a staircase of the command. The
    record holds the PLC's command, before the module. A static function of the command in
    the valve's input, a staircase of equal steps over the whole range: not a dead band (it
    passes every change larger than a step, at any distance from the centre), a clip, a knee
    or a gain error (its mean gain is one), and no memory. Size: 8 bits over 10 V, as the
    analog output modules of compact PLCs of the 1990s had; 39.2 mV is 7.8 um of spool, close
    to the lands' 10 um overlap, and the valve's centre (5 V) falls between two steps (4.980
    and 5.020 V). The records without any effect: the chirp's whole command lies within
    4.7-5.3 V (some 15 steps), the closed loop's holds dither within +-0.3 V of the centre
    and its steps kick across the range."""

    name = 'held_out11_eight_bit_output_module'
    params = (Param('step_v', 'V', 10.0 / 255.0, 1e-4, 1.0,
                    "the module's output step (its full range over its codes)"),)
    order = 20
    valve = _eight_bit_valve
    equations = ('valve_input',)
    depends = ({'command'},)
    closed_form = None
    where_rad = None


def _notch_valve(t, x, s, p, P, c, dx):
    # x[s], x[s+1]: the filter's states; with e the set value's distance from the centre, the
    # block passes e - a x[s+1], a = w0 / q: the notch (s^2 + w0^2) / (s^2 + a s + w0^2)
    if c[C_CIRCUIT] != _SERVO:
        return
    w0 = 2.0 * math.pi * p[0]
    a = w0 / p[1]
    e = min(max(c[C_U], 0.0), 10.0) - P[K_NULL]
    z1, z2 = x[s], x[s + 1]
    dx[s] = z2
    dx[s + 1] = e - w0 * w0 * z1 - a * z2
    lim = P[K_HALF_W] + P[K_HOLE_R]
    out = min(max(e - a * z2, -P[K_NULL]), 10.0 - P[K_NULL])
    c[C_XV] = min(max(c[C_XV] + P[K_GAIN] * (out - e), -lim), lim)


class LeftoverNotchFilterBlock(Component):
    """The PLC's output block for the axis still holds the notch filter the old machine
    needed: its arm, a 600 mm aluminium beam with a heavy gripper, rang at 15 Hz, and the
    block removes that frequency from the set value before it reaches the valve. The rig's
    short arm has no such mode; the notch is still on and delays and dents the command's
    changes near 15 Hz (the loop's steps, its hunting at the holds), and passes slow ones
    (the chirp's 0.5-4 Hz) nearly unchanged. A memory of the command (a second-order filter's
    states), in the valve's input: not a lag or a delay (it passes steady commands and slow
    ones unchanged, and fast ones too), a ramp limit, a lead or a dead time. Size: the old
    arm's first bending mode at 15 Hz; a notch of quality factor 1 (a -3 dB width of 15 Hz),
    the broad setting used against a mode that shifts with the payload. The records without
    any effect: the chirp's command changes at 0.5-4 Hz (the notch passes 93-100 % of it,
    shifted by up to 15 deg of phase at 4 Hz), the closed loop's steps change the command
    within a few milliseconds."""

    name = 'held_out11_leftover_notch_filter_block'
    params = (Param('centre_hz', 'Hz', 15.0, 0.1, 200.0, "the notch's centre frequency"),
              Param('quality', '1', 1.0, 0.05, 50.0, "the notch's quality factor (centre over "
                    'width)', fit=False))
    states = (State('notch_z1', 'V.s^2', 1e-9, "the filter's first state"),
              State('notch_z2', 'V.s', 1e-7, "the filter's second state"))
    order = 60
    steady = False
    circuits = ('servo',)
    valve = _notch_valve
    equations = ('valve_input',)
    # the command less its band near 15 Hz: a filter's memory of the command
    depends = ({'command'}, {'command', 'command_direction'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        w0 = 2.0 * math.pi * values['centre_hz']
        e = min(max(command_v, 0.0), 10.0) - core['valve_null_voltage_v']
        return [e / (w0 * w0), 0.0]


# --- moment balance --------------------------------------------------------------------------
def _hose_loop_mechanics(t, x, s, p, P, c, dx):
    # a spring about the angle p[2] whose rate grows with a's gauge pressure
    if c[C_CIRCUIT] != _SERVO:
        return
    rate = p[0] + p[1] * max(x[P_A] - c[C_PE], 0.0)
    c[C_TORQUE] -= rate * (x[THETA] - p[2])


class PressurisedHoseLoopA(Component):
    """The old machine's gripper clamp was fed from line a through a hose that loops from
    the frame to the arm, and the hose is still teed into a and still clamped to the arm
    (its end plugged at the arm). Turning the arm bends the loop; a reinforced hose under
    pressure is much stiffer in bending than at rest (the pressure pre-tensions its braid and
    resists the loop's ovalising), so the loop pushes the arm back towards its straight
    position, at 90 deg, with a rate that grows with p_a. A product of states (the angle,
    from the loop's neutral, times a function of p_a), in the moment balance, over the whole
    stroke: not a spring (its rate changes by a factor of four with a's pressure), a
    gravity arm, a harness over part of the stroke or a cylinder pushing over a window. Size:
    an 8 x 6 mm braided PU hose in a 150 mm loop: 0.01 N.m/rad at rest, 0.04 N.m/rad at
    5 bar gauge (6e-8 N.m/(rad.Pa)): 0.035 N.m at 50 deg from the neutral at the holds'
    pressures, near the actuator's Coulomb friction (0.042 N.m); its volume (28 cm^3 of a
    1 m loop, plugged) is not part of the class (a fixed dead volume, of the catalogue's
    kind). The neutral was placed from the records without any effect: the closed loop holds
    at 38-140 deg, the chirp swings about 112 deg."""

    name = 'held_out11_pressurised_hose_loop_a'
    params = (Param('rate_n_m_per_rad', 'N.m/rad', 0.01, 0.0, 10.0,
                    "the loop's bending rate at rest, at the shaft"),
              Param('pressure_rate_n_m_per_rad_pa', 'N.m/(rad.Pa)', 6e-8, 0.0, 1e-5,
                    'its growth per pascal of p_a (gauge)'),
              Param('neutral_rad', 'rad', 90.0 * DEG, 0.0, 3.4,
                    'angle at which the loop pushes neither way'))
    circuits = ('servo',)
    mechanics = _hose_loop_mechanics
    equations = ('moment_balance',)
    # (k0 + k1 p_a) (angle - neutral)
    depends = ({'angle', 'p_a'},)
    closed_form = None
    where_rad = None


def _brake_mechanics(t, x, s, p, P, c, dx):
    # x[s]: the time the arm has stood still (|speed| below p[1]) with the set value within
    # p[2] of the centre, counting up to p[0] + 5 ms and no further, cleared within _CLEAR_S
    # otherwise; x[s+1]: the brake, 0 released to 1 applied, following its command (applied
    # once that time exceeds p[0]) within p[4] applying and p[5] releasing; applied, it adds
    # p[3] of friction
    if c[C_CIRCUIT] != _SERVO:
        return
    q = x[s]
    u = min(max(c[C_U], 0.0), 10.0)
    if abs(x[OMEGA]) < p[1] and abs(u - P[K_NULL]) < p[2]:
        dx[s] = 1.0 - _rise(q, p[0] + 4e-3, p[0] + 5e-3)
    else:
        dx[s] = -q / _CLEAR_S
    want = _rise(q, p[0], p[0] + 1e-3)
    z = x[s + 1]
    dx[s + 1] = (want - z) / (p[4] if want > z else p[5])
    _add_friction(c, p[3] * min(max(z, 0.0), 1.0), x[OMEGA])


class InPositionHoldingBrake(Component):
    """The shaft's lower end carries the old machine's spring-applied holding brake (a small
    electromagnetic disc brake, released while its coil is powered), and the PLC still
    drives it with the old machine's in-position logic: once the arm has stood still for a
    while with the set value near the valve's centre, the PLC drops the coil and the brake
    holds the arm; as soon as the set value leaves that band, it powers the coil again and
    the brake lifts after its release time. A memory (a standstill timer, and the brake's
    own switching) set by the speed and the command, times a friction torque, in the moment
    balance: not a stiction (it needs a dwell and is lifted by the command, not by the
    torque), a friction set by a pressure or a dead time of the valve (the valve opens at
    once; the arm cannot follow until the brake lifts). Size: a brake of 0.3 N.m (the
    smallest size of such brakes, 0.4 N.m nominal, worn), half the drive's torque at 0.6 bar
    of difference; standstill below 0.05 rad/s (one count in 6 ms) for 0.15 s, the set value
    within +-0.5 V; the brake applies within 15 ms and lifts within 30 ms (its armature's
    times). The thresholds were placed from the records without any effect: the closed loop
    stands still for 71 % of the time, in stretches of up to 0.8 s, its command dithering
    within +-0.3 V at the holds (the 99th percentile) and beyond +-0.5 V in 116 stretches of
    the steps; the chirp never stands still for more than 0.09 s."""

    name = 'held_out11_in_position_holding_brake'
    params = (Param('standstill_s', 's', 0.15, 0.0, 10.0,
                    'time at standstill after which the brake is applied'),
              Param('still_speed_rad_s', 'rad/s', 0.05, 0.0, 10.0,
                    'speed below which the arm counts as standing still', fit=False),
              Param('band_v', 'V', 0.5, 0.0, 5.0,
                    'distance of the set value from the centre that lifts the brake'),
              Param('brake_torque_n_m', 'N.m', 0.3, 0.0, 5.0, "the brake's holding torque"),
              Param('apply_s', 's', 0.015, 1e-4, 0.5, 'time in which it applies', fit=False),
              Param('release_s', 's', 0.03, 1e-4, 0.5, 'time in which it lifts', fit=False))
    states = (State('standstill_time_s', 's', 1e-5, 'time the arm has stood still'),
              State('brake_applied', '1', 1e-3, 'the brake, 0 lifted to 1 applied'))
    steady = False
    circuits = ('servo',)
    mechanics = _brake_mechanics
    equations = ('moment_balance',)
    # a friction applied after a dwell at rest (speed), lifted by the command
    depends = ({'velocity'}, {'velocity', 'motion_direction'}, {'command', 'velocity'},
               {'command', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = None


def _cable_mechanics(t, x, s, p, P, c, dx):
    # x[s]: the relaxing element's deflection [rad]; the bundle's torque is its long-term
    # rate p[0] about the neutral p[3] plus the relaxing rate p[1] on x[s], which follows the
    # angle's changes and relaxes within p[2]
    if c[C_CIRCUIT] != _SERVO:
        return
    d = x[s]
    dx[s] = x[OMEGA] - d / p[2]
    c[C_TORQUE] -= p[0] * (x[THETA] - p[3]) + p[1] * d


class ViscoelasticCableCarrier(Component):
    """The sensors' and the old gripper's cables run to the arm in a short plastic cable
    carrier packed with PVC-sheathed cables. Bent by the arm, the bundle pushes back like a
    spring, but its PVC is viscoelastic: right after a move it pushes back more, then relaxes
    towards its long-term stiffness over a fraction of a second (a standard linear solid:
    a spring in parallel with a spring and a dashpot in series). A memory of the angle's
    changes (the relaxing element's deflection), in the moment balance: not a spring alone
    (its torque after a step decays), a damper (it stores the deflection), a Coulomb-type
    presliding or a harness over part of the stroke. Size: 0.02 N.m/rad long-term and 0.06
    N.m/rad more just after a move, relaxing within 0.3 s (PVC's relaxation at room
    temperature), about the neutral at 100 deg: 0.07 N.m long-term at the 38 deg hold, a
    further 0.06 N.m right after a 60 deg step. The neutral was placed from the records without
    any effect: the closed loop holds at 38-140 deg, the chirp swings about 112 deg."""

    name = 'held_out11_viscoelastic_cable_carrier'
    params = (Param('rate_n_m_per_rad', 'N.m/rad', 0.02, 0.0, 10.0,
                    "the bundle's long-term rate, at the shaft"),
              Param('relaxing_rate_n_m_per_rad', 'N.m/rad', 0.06, 0.0, 10.0,
                    'the further rate just after a move'),
              Param('relax_s', 's', 0.3, 1e-3, 100.0, 'time in which that part relaxes'),
              Param('neutral_rad', 'rad', 100.0 * DEG, 0.0, 3.4,
                    'angle at which the bundle pushes neither way', fit=False))
    states = (State('relaxing_deflection_rad', 'rad', 1e-7,
                    "the relaxing element's deflection"),)
    steady = False
    circuits = ('servo',)
    mechanics = _cable_mechanics
    equations = ('moment_balance',)
    depends = ({'angle'}, {'angle', 'velocity'}, {'angle', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = None


# --- mass balances ---------------------------------------------------------------------------
def _cam_pilot_flows(t, x, s, p, P, c, dx):
    # x[s]: the pilot volume's pressure (isothermal at room temperature). The roller valve
    # is pressed from p[0] up (its ramp p[1] below): pressed, it connects line b to the pilot
    # volume p[3] through p[2]; released, it vents the volume to atmosphere through p[2]
    if c[C_CIRCUIT] != _SERVO:
        return
    k, r, te = c[C_KAPPA], c[C_R], c[C_TE]
    crit = ideal_critical_ratio(k)
    w = _rise(x[THETA], p[0] - p[1], p[0])
    pv = max(x[s], 1e3)
    m_in = 0.0
    if w > 0.0:
        m_in = orifice_flow(p[2] * w, x[P_B], x[T_B], pv, te, crit, r, k, _LAMINAR_BAND)
        add_flow(c, 1, -m_in, te, x[T_B])
    m_out = 0.0
    if w < 1.0:
        m_out = orifice_flow(p[2] * (1.0 - w), pv, te, c[C_PE], te, crit, r, k, _LAMINAR_BAND)
    dx[s] = r * te / p[3] * (m_in - m_out)


class CamPilotVolumeB(Component):
    """The old gripper's closing was piloted from line b by a roller-lever 3/2 valve on the
    frame, which a cam on the arm presses from 120 deg up: pressed, it passes b's air into
    the pilot port of the gripper's valve (the valve is gone; its pilot line, plugged, is
    still there); released, it vents that line to atmosphere. So every time the arm goes
    above 120 deg, b fills the empty pilot line from its own air, and every time it comes
    back below, that air is thrown away. A window over the stroke (the cam) with a memory (the
    pilot line's pressure), through an orifice flow between p_b and that pressure, in the
    mass balance of b: not a leak over a window (it takes a fixed charge, then nothing while
    the arm stays up), a dead volume (it is emptied each time), a cam-throttled exhaust or a
    relief. Size: 0.6 m of 4 x 2.5 mm tube and the plugged port, 3 cm^3; the roller valve's
    1 mm^2 effective area (an M5 mechanical valve); the cam's ramp 2 deg of the arm. The cam
    was placed from the records without any effect: the closed loop holds at 126-140 deg
    above it and at 38-91 deg below it, the chirp reaches 122-124 deg at the top of some of
    its swings."""

    name = 'held_out11_cam_pilot_volume_b'
    params = (Param('from_rad', 'rad', 120.0 * DEG, 0.0, 3.4,
                    'angle from which the roller valve is fully pressed'),
              Param('ramp_rad', 'rad', 2.0 * DEG, 1e-4, 0.2, "the cam's ramp below it",
                    fit=False),
              Param('valve_area_m2', 'm^2', 1e-6, 0.0, 1e-5,
                    "the roller valve's effective area"),
              Param('pilot_volume_m3', 'm^3', 3e-6, 1e-8, 1e-3, 'the pilot line\'s volume'))
    states = (State('pilot_pressure_pa', 'Pa', 5.0, "the pilot line's pressure"),)
    steady = False
    circuits = ('servo',)
    flows = _cam_pilot_flows
    equations = ('mass_balance_b',)
    # an orifice flow between p_b and a volume that the angle connects (from 120 deg up)
    depends = ({'angle', 'p_b'}, {'angle', 'p_b', 'p_b_rate'}, {'angle', 'p_b', 'velocity'})
    closed_form = None
    where_rad = (118.0 * DEG, _STROKE_RAD)

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [core['atmospheric_pressure_pa']]


def _air_knife_flows(t, x, s, p, P, c, dx):
    # x[s]: time since the set value was last above p[0] (cleared while above, counting up to
    # p[1] + 5 ms and no further); x[s+1]: the knife's solenoid valve, 0 shut to 1 open,
    # following within p[3] its command: open while that time is below p[1]. Open, a blows
    # to atmosphere through the knife's slot p[2]
    if c[C_CIRCUIT] != _SERVO:
        return
    q = x[s]
    if c[C_U] > p[0]:
        dx[s] = -q / _CLEAR_S
    else:
        dx[s] = 1.0 - _rise(q, p[1] + 4e-3, p[1] + 5e-3)
    want = 1.0 - _rise(q, p[1], p[1] + 1e-3)
    dx[s + 1] = (want - x[s + 1]) / p[3]
    v = min(max(x[s + 1], 0.0), 1.0)
    if v > 0.0:
        k = c[C_KAPPA]
        m = orifice_flow(p[2] * v, x[P_A], x[T_A], c[C_PE], c[C_TE], ideal_critical_ratio(k),
                         c[C_R], k, _LAMINAR_BAND)
        add_flow(c, 0, -m, c[C_TE], x[T_A])


class AirKnifeOnUpKickA(Component):
    """The old machine blew its parts clean with an air knife while the arm swung them up
    fast: its PLC switched a 2/2 solenoid valve whenever the set value was above 7 V (its
    'fast up' signal, an analog comparator in the output block) and kept it on for at least
    0.1 s after (the old program's minimum on-time). The knife's air was taken, by a tee,
    from line a (the chamber that drives the arm up, pressurised just then). The knife is
    still there and still blows from a, while the command is above 7 V and for 0.1 s after.
    A memory (a timer started by the command, and the solenoid valve's switching) times an
    orifice flow of p_a to atmosphere, in the mass balance of a: not a leak (it blows only
    after the command has been high), an exhaust throttle or a quick exhaust (it does not
    depend on which way the valve meters, only on a level of the command). Size: a 25 mm
    air knife with a 0.05 mm slot, 5e-7 m^2 effective (some 0.7 g/s, 36 l/min ANR, at 5 bar
    gauge), a direct-acting solenoid valve switching in 10 ms; the 7 V level (2 V above the
    centre) and the 0.1 s of the old program. The level was placed from the records without
    any effect: the closed loop's command is above 7 V in the upward steps' kicks (its 99th
    percentile is 7.7 V), the chirp's stays within 4.7-5.3 V."""

    name = 'held_out11_air_knife_on_up_kick_a'
    params = (Param('level_v', 'V', 7.0, 0.0, 10.0,
                    'set value above which the knife is switched on'),
              Param('hold_s', 's', 0.1, 0.0, 5.0, 'time it stays on after the set value falls'),
              Param('slot_area_m2', 'm^2', 5e-7, 0.0, 1e-5, "the knife's effective area"),
              Param('valve_time_s', 's', 0.01, 1e-4, 0.1, "the solenoid valve's switching time",
                    fit=False))
    states = (State('time_since_high_s', 's', 1e-5, 'time since the set value was last high'),
              State('knife_valve', '1', 1e-3, "the knife's valve, 0 shut to 1 open"))
    steady = False
    circuits = ('servo',)
    flows = _air_knife_flows
    equations = ('mass_balance_a',)
    # a's orifice flow to atmosphere, while and after the command is above a level
    depends = ({'command', 'p_a'}, {'command', 'p_a', 'supply'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [values['hold_s'] + 5e-3, 0.0]


# --- supply ----------------------------------------------------------------------------------
def _regulator_supply(t, x, s, p, P, c, dx):
    c[C_PS] = max(x[s], 1e3)


def _regulator_finish(t, x, s, p, P, c, dx):
    # x[s]: the pressure the local regulator delivers to the valve. Without friction it would
    # sit at its set p[0] (gauge, no higher than its inlet) less its droop p[1] per kg/s drawn;
    # its valve moves only once that differs from x[s] by more than its friction band p[2],
    # and then closes the gap (less the band) within p[3]
    target = min(c[C_PE] + p[0], c[C_PS_REG]) - p[1] * c[C_MSUP]
    gap = target - x[s]
    if gap > p[2]:
        dx[s] = (gap - p[2]) / p[3]
    elif gap < -p[2]:
        dx[s] = (gap + p[2]) / p[3]


class StickyLocalRegulatorSupply(Component):
    """The valve is fed through a small local regulator on the frame, downstream of the
    service unit and its supply transmitter, set just below the line (5.9 bar gauge) to
    steady the valve's supply; it is an old diaphragm regulator whose valve stem and O-ring
    have dried out. Its valve moves only once the force on the diaphragm has changed by more
    than the stem's friction: its outlet droops with the valve's draw only after a first
    band, lags the draw, and after each draw stays where it stopped, anywhere within the
    band below (or above) its set, until the next draw moves it. The supply transmitter,
    before it, reads the line's 6 bar throughout. The valve is thus fed other than the
    reading: a memory (a play of the regulator's output, set by its friction) of the valve's
    draw (set by the command and the pressures): not a droop with the flow alone (it remembers
    the last draw), an offset (it changes with every draw), a tank's sawtooth or a timer.
    Size: set 10 kPa below the line's 701 kPa abs; a droop of 10 kPa per g/s (an M5 precision
    regulator's flow characteristic); a friction band of +-8 kPa (the sensitivity of a dry
    miniature regulator, 1-1.5 % of its 6 bar); the valve stem closes the gap within 20 ms.
    The records without any effect: the closed loop draws 0.1 g/s at its holds and up to
    2.6 g/s in its steps, the chirp 0.10-0.15 g/s throughout."""

    name = 'held_out11_sticky_local_regulator_supply'
    params = (Param('set_gauge_pa', 'Pa', 5.9e5, 0.0, 1e6, "the regulator's set (gauge)"),
              Param('droop_pa_s_per_kg', 'Pa.s/kg', 1e7, 0.0, 1e9,
                    'its droop per kg/s drawn'),
              Param('band_pa', 'Pa', 8e3, 0.0, 1e5, 'its friction band either side'),
              Param('response_s', 's', 0.02, 1e-4, 1.0, 'time in which it closes the gap',
                    fit=False))
    states = (State('valve_supply_pa', 'Pa', 5.0, 'pressure the regulator delivers'),)
    order = 5
    steady = False
    supply = _regulator_supply
    finish = _regulator_finish
    equations = ('measurement_supply',)
    # the valve fed less than the reading, by an amount set by the last draws
    depends = ({'command', 'p_a', 'p_b'}, {'command', 'p_a', 'p_b', 'supply'}, {'supply'})
    closed_form = None
    where_rad = None

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        return [min(core['atmospheric_pressure_pa'] + values['set_gauge_pa'], supply_pa)]


# --- errors of measured signals --------------------------------------------------------------
@njit(cache=True)
def _captured(angle, lo, hi):
    """The reading of a counter read from its capture register while the angle is within
    [lo, hi]: the edge by which it entered, held (the live angle outside)."""
    n = len(angle)
    out = np.empty(n)
    held = angle[0] if n else 0.0
    for i in range(n):
        a = angle[i]
        if lo <= a <= hi:
            if i == 0:
                held = a
            else:
                b = angle[i - 1]
                if b < lo:
                    held = lo
                elif b > hi:
                    held = hi
            out[i] = held
        else:
            out[i] = a
    return out


def _capture_error(values, signals, core):
    angle = np.ascontiguousarray(signals['angle_rad'], dtype=float)
    return {'angle_rad': _captured(angle, values['from_rad'], values['to_rad']) - angle}


class CaptureRegisterAngle(Component):
    """The encoder's counter card has a capture input, wired to the old machine's part-in-nest
    proximity switch, whose target on the arm covers 103-111 deg: when the switch is made the
    card copies the count into its capture register, and the old program, still running,
    reads the capture register instead of the live count for as long as the switch is made
    (it wanted the angle at which the part was detected). So while the arm is within the
    switch's target, the angle reading holds the edge by which it came in (103 deg coming
    up, 111 deg coming down), and it is live again outside. A window over the stroke with a
    memory (the edge of entry) in the angle's reading: not a resync or an offset (nothing is
    changed outside the window), a dwell or a quantisation (it holds what it read at the
    entry, whatever the arm does inside), and not a function of the angle alone. Size: the
    old switch's 8 deg target (an 18 mm sensor's operating distance on a 60 mm radius); its
    edges read exactly (the switch's own hysteresis, 0.1 deg, is neglected). The window was
    placed from the records without any effect: the closed loop passes it in its steps and
    holds at 91 and 126 deg either side of it, the chirp swings through it in every cycle."""

    name = 'held_out11_capture_register_angle'
    params = (Param('from_rad', 'rad', 103.0 * DEG, 0.0, 3.4,
                    "the lower edge of the switch's target"),
              Param('to_rad', 'rad', 111.0 * DEG, 0.0, 3.4, 'its upper edge'))
    sensor_error = staticmethod(_capture_error)
    steady = False
    equations = ('measurement_angle',)
    depends = ({'angle'}, {'angle', 'motion_direction'}, {'angle', 'velocity'})
    closed_form = None
    where_rad = (103.0 * DEG, 111.0 * DEG)


@njit(cache=True)
def _pulse_direction(angle, command, step, null):
    """The count of a counter in pulse-and-direction mode: it counts the encoder's count
    changes of ``angle`` (of width ``step``) up while ``command`` is at or above ``null``,
    down otherwise; returned as an angle, from ``angle[0]``."""
    n = len(angle)
    out = np.empty(n)
    if n == 0:
        return out
    prev = math.floor(angle[0] / step)
    count = prev
    out[0] = angle[0]
    for i in range(1, n):
        now = math.floor(angle[i] / step)
        pulses = abs(now - prev)
        count += pulses if command[i - 1] >= null else -pulses
        prev = now
        out[i] = angle[0] + (count - math.floor(angle[0] / step)) * step
    return out


def _pulse_direction_error(values, signals, core):
    angle = np.ascontiguousarray(signals['angle_rad'], dtype=float)
    command = np.ascontiguousarray(signals['command_v'], dtype=float)
    step = 2.0 * math.pi / values['counts_per_rev']
    read = _pulse_direction(angle, command, step, values['direction_null_v'])
    return {'angle_rad': read - angle}


class PulseDirectionCounter(Component):
    """The old machine's axis was a stepper drive, and the counter card that now counts the
    encoder is still configured for it: in pulse-and-direction mode, counting the pulses of
    its count input (now the encoder's, decoded to one pulse per count) up or down as its
    direction input says, and that input is still wired to the PLC's 'direction' output,
    which the output block sets whenever the set value is above the valve's centre. So the
    reading follows the arm while the arm turns the way the command points, and counts the
    wrong way while it does not: when the arm overshoots, coasts or is pushed back, and in
    the holds' dither. A memory (the count so far) of the speed's magnitude times the
    command's side, in the angle's reading: not a delay, a count loss above a speed, a play
    or a resync (it drifts, never comes back by itself, and only while the arm moves against
    the command's side). Size: the encoder's 20,000 counts per turn; the direction bit set at
    the valve's centre, 5 V. The records without any effect: the closed loop's arm overshoots
    and dithers at its holds, the chirp's arm lags its command by a quarter of a cycle and
    more."""

    name = 'held_out11_pulse_direction_counter'
    params = (Param('direction_null_v', 'V', 5.0, 0.0, 10.0,
                    'set value above which the direction output says up'),
              Param('counts_per_rev', '1', 20000.0, 100.0, 1e6,
                    "the encoder's counts per turn", fit=False))
    sensor_error = staticmethod(_pulse_direction_error)
    steady = False
    equations = ('measurement_angle',)
    # the reading's rate is |speed| with the command's sign
    depends = ({'command', 'velocity'}, {'command', 'velocity', 'motion_direction'},
               {'angle', 'command', 'velocity'}, {'command', 'motion_direction'})
    closed_form = None
    where_rad = None


def _acceleration_error(values, signals, core):
    speed = np.asarray(signals['velocity_rad_s'], dtype=float)
    t = np.asarray(signals['t_s'], dtype=float)
    if len(t) < 3:
        return {'p_a_pa': np.zeros(len(t))}
    acc = np.gradient(speed, t)
    return {'p_a_pa': values['sensitivity_pa_per_m_s2'] * values['radius_m'] * acc}


class ArmMountedTransmitterA(Component):
    """Chamber a's transmitter sits on the arm: the old machine had its gripper's valve
    manifold on the arm's hub, fed from line a through the hollow shaft, and the new
    transmitter was screwed into that manifold's spare port, 40 mm from the axis, its
    diaphragm facing along the arm's path. The diaphragm and its oil fill have mass: when
    the arm accelerates, they press on the sensing element as a pressure would, and the
    reading of p_a moves with the arm's tangential acceleration (the centripetal part,
    across the diaphragm's axis, does not show). A static error of p_a, a function of the
    arm's acceleration (set by the pressures, the friction and the speed): not a delay or a
    lag of p_a, a crosstalk from p_b or a function of the angle or the speed. Size: an
    acceleration sensitivity of 0.025 % of its 6 bar span per g (150 Pa per g, 15.3 Pa per
    m/s^2: a thin-film transmitter's datasheet figure); at 40 mm, the closed loop's steps'
    5,100 rad/s^2 give some 3 kPa, the chirp's 240 rad/s^2 0.15 kPa (a quarter of the
    noise). The records without any effect: the closed loop accelerates at up to 5,100
    rad/s^2, the chirp at up to 240."""

    name = 'held_out11_arm_mounted_transmitter_a'
    params = (Param('sensitivity_pa_per_m_s2', 'Pa.s^2/m', 15.3, 0.0, 1e4,
                    "the transmitter's reading per m/s^2 along its diaphragm's axis"),
              Param('radius_m', 'm', 0.04, 0.0, 1.0, "its distance from the axis",
                    fit=False))
    sensor_error = staticmethod(_acceleration_error)
    steady = False
    equations = ('measurement_p_a',)
    # the arm's acceleration: the drive (p_a - p_b) less the friction
    depends = ({'p_a', 'p_b'}, {'p_a', 'p_b', 'velocity'},
               {'p_a', 'p_b', 'velocity', 'motion_direction'})
    closed_form = None
    where_rad = None


def _valve_end_error(values, signals, core):
    p = np.asarray(signals['p_b_pa'], dtype=float)
    angle = np.asarray(signals['angle_rad'], dtype=float)
    t = np.asarray(signals['t_s'], dtype=float)
    if len(t) < 3:
        return {'p_b_pa': np.zeros(len(t))}
    r = core['gas_constant_j_per_kg_k']
    temp = np.asarray(signals.get('t_b_k', np.full(len(t), core['room_temperature_k'])),
                      dtype=float)
    swept = core['piston_area_m2'] * core['pinion_pitch_diameter_m']
    th = np.clip(angle, 0.0, core['stroke_rad'])
    vol = core['dead_volume_b_m3'] + swept * (core['stroke_rad'] - th)
    mass = p * vol / (r * temp)
    flow = np.gradient(mass, t)  # into b, through the hose
    area = 0.25 * math.pi * values['bore_m'] ** 2
    rho = p / (r * temp)
    return {'p_b_pa': values['loss_coefficient'] * flow * np.abs(flow) / (2.0 * rho * area ** 2)}


class TransmitterAtValveEndB(Component):
    """Chamber b's transmitter was moved from the actuator's port to the valve's manifold
    (to keep its cable off the moving parts), so it reads line b at the valve's end of the
    hose, 1.5 m from the chamber. The flow through the hose costs pressure: the reading is
    above the chamber's pressure while the valve fills b, below it while b empties, by the
    hose's and the fittings' loss, a square of the flow. A dynamic error of p_b (the flow
    into b is the rate of b's mass: p_b's rate and the piston's speed, at the angle): not a
    lag or a delay of p_b (it leads the chamber's pressure in every change), a resonance or
    a function of p_b alone, and the physics (the chamber's own pressure) is not changed:
    the hose's volume and resistance in the flow are the model's own. Size: 1.5 m of 6 x 4
    mm tube (a friction factor of 0.03 in turbulent flow, 11 velocity heads) and two push-in
    fittings (1.8): 12.8 velocity heads at 4 mm bore: some 39 kPa at the steps' largest
    draws (2.6 g/s at 5 bar), 0.1 kPa at the holds' 0.1 g/s. The records without any effect:
    the closed loop's p_b changes at up to 228 bar/s with the arm at up to 48 rad/s, the
    chirp's at up to 5 bar/s and 2.9 rad/s."""

    name = 'held_out11_transmitter_at_valve_end_b'
    params = (Param('loss_coefficient', '1', 12.8, 0.0, 1e4,
                    "the hose's and fittings' loss, in velocity heads"),
              Param('bore_m', 'm', 4e-3, 1e-4, 0.05, "the hose's bore", fit=False))
    sensor_error = staticmethod(_valve_end_error)
    steady = False
    equations = ('measurement_p_b',)
    # the square of the flow into b: of p_b, its rate, the angle and the speed
    depends = ({'p_b', 'p_b_rate', 'velocity'}, {'p_b_rate', 'velocity'},
               {'angle', 'p_b', 'p_b_rate', 'velocity'}, {'p_b', 'p_b_rate'}, {'p_b_rate'})
    closed_form = None
    where_rad = None


SET = (PressurisedHoseLoopA, CaptureRegisterAngle, InPositionHoldingBrake,
       ArmMountedTransmitterA, EightBitOutputModule, StickyLocalRegulatorSupply,
       CamPilotVolumeB, PulseDirectionCounter, LeftoverNotchFilterBlock,
       TransmitterAtValveEndB, ViscoelasticCableCarrier, AirKnifeOnUpKickA)
