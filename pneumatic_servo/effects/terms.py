"""The vocabulary of generic corrections, declared once, built from blocks.

A :class:`Term` is one candidate function of the state and inputs. It is one
expression over named variables (:data:`VARIABLES`); the same text is
compiled into the correction hooks (:mod:`.corrections`), evaluated over a
record's arrays, and written into an emitted effect file, so a term is never
declared twice. The blocks:

* **variables**: angle, speed, chamber pressures, valve command, supply;
* **functions** of them: sign (a smooth ``tanh``), absolute value, sine and
  cosine, the signed square root of a pressure drop (an orifice), and smooth
  **windows over the stroke** (Gaussian bumps at four places), a pressure above atmosphere
  (a gauge transmitter's span, offered to its own reading), the knots of a **free
  shape** over it (piecewise linear, fitted together where no closed form fits), and of a
  **free function of each variable** (fitted beside a correction to test whether it also
  depends on that variable: :attr:`Term.probes`); the functions are in :mod:`.bases`;
* **memory**: the direction in which the valve command last moved (a play
  operator of width :data:`COMMAND_PLAY_V`: magnetic hysteresis of a
  proportional solenoid), and the direction in which the shaft last moved (a
  play of :data:`MOTION_PLAY_RAD`: backlash between shaft and encoder);
* **products** of the above where a physical effect is one: friction that
  grows with chamber pressure, a leak across the vane over part of the stroke;
* **dynamics of a sensor**: the rate of change of a chamber pressure (a transmitter that
  lags by tau reads, to first order, -tau times it).

The command's memory is a state of the correction (an ODE that follows the
command outside its play band, declared on its variable: :attr:`Variable.memory`); the
shaft's is evaluated over the record, so
it is offered to the sensor equations only. The variables, and the constants of the
operators over them, are in :mod:`.variables`.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from . import term_words as w
from .bases import (  # noqa: F401 - the expressions call them; emitted files import them here
    COMMAND_MEMORY_S,
    N_KNOTS,
    N_PROBE_KNOTS,
    N_WINDOWS,
    hat,
    knot,
    memory_direction,
    memory_rate,
    signed_sqrt,
    window,
)
from .operators import direction, lag, rate  # noqa: F401 - the expressions call them
from .variables import (  # noqa: F401 - emitted files and the package read them here
    BY_VARIABLE,
    COMMAND_PLAY_V,
    LAGS_S,
    MOTION_PLAY_RAD,
    PROBE_SPANS,
    PROBED,
    READINGS,
    VARIABLES,
    Variable,
    array_namespace,
    probe_spans,
)

#: [rad/s] and [V]: widths over which the direction of motion and the side of the valve
#: centre change sign (tanh), so that a correction never makes the equations discontinuous
SIGN_VELOCITY_WIDTH = 0.01
SIGN_COMMAND_WIDTH = 0.02


@dataclass(frozen=True)
class Term:
    """A candidate term: its name, SI unit, a typical magnitude on a rig, its words, its
    expression over :data:`VARIABLES` and the functions of :mod:`.bases`, and the equations
    it is offered in (None: every equation that can evaluate it)."""

    name: str
    unit: str
    typical: float
    words: str
    expression: str
    equations: tuple[str, ...] | None = None
    #: parameters it counts as in a selection: a window's place, a product's pairing or an
    #: operator's memory is a choice made on the data, so such a term counts as two and a
    #: plain function of one variable is preferred where it fits as well
    cost: int = 1
    #: whether the linear screen selects it; a free shape's knots are fitted together, by
    #: the shape stage, never picked one by one
    screened: bool = True
    #: its words where it leads a correction, per kind of equation
    #: (:data:`.term_words.KINDS`): a function of a :class:`.term_words.Context` giving a
    #: sentence, or None where it says nothing particular (the equation's general words)
    says: dict = field(default_factory=dict, hash=False, compare=False)
    #: for a modulation (:func:`modulations`), the term whose size it makes vary (it is
    #: screened only where that term leads an equation's correction), and the name of the
    #: modulator it is multiplied by (:data:`BY_MODULATOR`)
    modulates: str = ''
    modulator: str = ''
    #: for a knot of the free function of one variable fitted beside a correction (never
    #: screened, never an answer): that variable, whose dependence it probes
    probes: str = ''

    @cached_property
    def variables(self) -> list[str]:
        """The names of :data:`VARIABLES` its expression uses."""
        used = set(re.findall(r'[A-Za-z_]\w*', self.expression))
        return [v.name for v in VARIABLES if v.name in used]

    @property
    def depends_on(self) -> list[str]:
        """The variables it is a function of along a record: those read from a signal (the
        stroke and the atmosphere are constants of the rig)."""
        return [v for v in self.variables if BY_VARIABLE[v].signal]

    @property
    def compiled(self) -> bool:
        """Whether a compiled hook can evaluate it (memory of the shaft cannot)."""
        return all(BY_VARIABLE[v].compiled is not None for v in self.variables)

    @property
    def memories(self) -> list[Variable]:
        """The variables it uses that are memories of the command (states)."""
        return [BY_VARIABLE[v] for v in self.variables if BY_VARIABLE[v].memory is not None]

    @property
    def lag_s(self) -> float | None:
        """[s] The time constant of the first-order lag of a reading it holds, if any."""
        return next((BY_VARIABLE[v].lag_s for v in self.variables if BY_VARIABLE[v].lag_s),
                    None)

    def dynamics_of(self, reading: str) -> bool:
        """Whether it writes the dynamics of variable ``reading``: another variable read from
        the same signal (its rate, a lag or a play of it)."""
        signal = BY_VARIABLE[reading].signal
        return any(v != reading and BY_VARIABLE[v].signal == signal for v in self.variables)

    def explain(self, kind: str, context: 'w.Context') -> str | None:
        """Its sentence as the leading term of a correction in an equation of ``kind``, or
        None (see :attr:`says`)."""
        words = self.says.get(kind)
        return words(context) if words is not None else None


def windowed(base: str, unit: str, typical: float, expression: str, words: str,
             meaning: str, equations: tuple[str, ...], kind: str, says) -> tuple[Term, ...]:
    """The products of a function (``base``, its ``expression``, ``unit``, ``typical``
    size and ``words``) with each window over the stroke: what ``meaning`` describes, only
    over part of it. ``says(k, windows)`` gives their words in equations of ``kind``. A
    product's pairing is a choice made on the data, so each costs two parameters."""
    return tuple(Term(f'{base}_in_window_{k}', unit, typical,
                      f'{words} over part {k + 1} of {N_WINDOWS} of the stroke ({meaning})',
                      f'{expression} * window(angle, stroke, {k})', equations, 2,
                      says={kind: says(k, N_WINDOWS)}) for k in range(N_WINDOWS))


def modulations(carriers, modulators, equations: tuple[str, ...],
                exclude=frozenset()) -> tuple[Term, ...]:
    """Each carrier (a plain term carrying an effect's mean: a valve gain's command, a
    friction's direction of motion) times each modulator of other variables (the angle, a
    pressure, a window over the stroke ...): the same effect, its size varying with that
    variable (a flow force on the spool grows with the pressure drop). Pairs in ``exclude``
    are declared elsewhere, with words. A pairing is chosen on the data: it costs two."""
    out = []
    for c in carriers:
        for name, expression, unit, typical, words in modulators:
            mod = Term(name, unit, typical, words, expression)
            if (c.name, name) in exclude or set(mod.depends_on) & set(c.depends_on):
                continue
            joined = f'_in_{name}' if name.startswith('window_') else f'_times_{name}'
            both = unit if c.unit == '1' else c.unit if unit == '1' else f'{c.unit}*{unit}'
            out.append(Term(f'{c.name}{joined}', both,
                            c.typical * typical, f'{c.words}, varying with {words}',
                            f'{c.expression} * {expression}', equations, 2, modulates=c.name,
                            modulator=name))
    return tuple(out)


#: what a carrier's size may vary with: each variable read from a signal, about a typical
#: value (mid-stroke, atmosphere: so that the product is not the carrier itself again), and
#: the windows over the stroke. (name, expression, SI unit, typical size, words)
MODULATORS = (
    ('angle', '(angle - 0.5 * stroke)', 'rad', 0.8, 'the angle from mid-stroke [rad]'),
    ('velocity', 'velocity', 'rad/s', 2.0, 'the shaft speed [rad/s]'),
    ('gauge_p_a', '(p_a - p_atm)', 'Pa', 3e5, 'the chamber a pressure above atmosphere [Pa]'),
    ('gauge_p_b', '(p_b - p_atm)', 'Pa', 3e5, 'the chamber b pressure above atmosphere [Pa]'),
    ('pressure_difference', '(p_a - p_b)', 'Pa', 3e5, 'p_a - p_b [Pa]'),
    ('command', 'command', 'V', 1.0, 'the valve command [V]'),
    ('gauge_supply', '(supply - p_atm)', 'Pa', 6e5, 'the supply above atmosphere [Pa]'),
    *((f'window_{k}', f'window(angle, stroke, {k})', '1', 1.0,
       f'a window over part {k + 1} of {N_WINDOWS} of the stroke') for k in range(N_WINDOWS)),
)
#: modulator name -> (expression, SI unit, typical size, words)
BY_MODULATOR = {m[0]: m[1:] for m in MODULATORS}
_FLOWS = ('mass_balance_a', 'mass_balance_b')
#: the equations a carrier is modulated in and a dependence is probed in (not the energy
#: balances or the temperatures)
_MODULATED = ('moment_balance', *_FLOWS, 'valve_input', 'measurement_supply',
              'measurement_angle', 'measurement_p_a', 'measurement_p_b')
TERMS = (
    Term('constant', '1', 1.0, 'one (a constant term)', '1.0',
         says={'torque': w.constant_torque, 'flow': w.constant_flow, 'valve': w.constant_valve,
               'heat': w.constant_heat, 'reading': w.constant_reading}),
    Term('angle', 'rad', 1.6, 'shaft angle', 'angle',
         says={'torque': w.angle_torque, 'flow': w.angle_flow, 'reading': w.angle_reading}),
    *(Term(f'{f}_angle', '1', 1.0, f'{trig} of the shaft angle', f'np.{f}(angle)',
           says={'torque': w.trig_torque(trig), 'flow': w.angle_flow})
      for f, trig in (('sin', 'sine'), ('cos', 'cosine'))),
    Term('velocity', 'rad/s', 2.0, 'shaft speed', 'velocity',
         says={'torque': w.velocity_torque, 'flow': w.velocity_flow,
               'reading': w.velocity_reading}),
    Term('sign_velocity', '1', 1.0, 'direction of motion',
         f'np.tanh(velocity / {SIGN_VELOCITY_WIDTH})', says={'torque': w.coulomb_torque}),
    # a gauge transmitter's gain error: proportional to the pressure above atmosphere (before
    # the absolute pressures: where both fit alike, a reading's gain is over a gauge span)
    *(Term(f'gauge_{v}', 'Pa', span, f'{words} pressure above atmosphere (what a gauge '
           'transmitter reads)', f'({v} - p_atm)', (f'measurement_{v}',),
           says={'reading': w.gauge_reading(v, words)})
      for v, words, span in (('p_a', 'chamber a', 3e5), ('p_b', 'chamber b', 3e5),
                             ('supply', 'supply', 6e5))),
    *(Term(f'p_{k}', 'Pa', 4e5, f'chamber {k} pressure (absolute)', f'p_{k}',
           says={'torque': w.chamber_torque(k), 'flow': w.chamber_flow(k),
                 'valve': w.pressure_driven_valve, 'reading': w.chamber_reading(k)})
      for k in 'ab'),
    Term('pressure_difference', 'Pa', 3e5, 'p_a - p_b', '(p_a - p_b)',
         says={'torque': w.difference_torque, 'flow': w.difference_flow,
               'valve': w.pressure_driven_valve}),
    Term('command', 'V', 1.0, 'valve command minus its centre (5 V)', 'command',
         says={'flow': w.command_flow, 'valve': w.command_valve}),
    Term('sign_command', '1', 1.0, 'side of the valve centre the command is on',
         f'np.tanh(command / {SIGN_COMMAND_WIDTH})',
         says={'flow': w.command_flow, 'valve': w.sign_command_valve}),
    Term('abs_command', 'V', 1.0, 'distance of the command from the valve centre',
         'np.abs(command)', says={'flow': w.command_flow, 'valve': w.abs_command_valve}),
    Term('supply', 'Pa', 7e5, 'supply pressure (absolute)', 'supply',
         says={'flow': w.supply_flow, 'valve': w.pressure_driven_valve,
               'reading': w.supply_reading}),
    *(Term(f'sqrt_drop_{k}', 'Pa^0.5', 600.0,
           f'signed square root of p_{k} - p_atm (an orifice from chamber {k} to atmosphere)',
           f'signed_sqrt(p_{k} - p_atm)', says={'flow': w.chamber_flow(k)}) for k in 'ab'),
    Term('sqrt_pressure_difference', 'Pa^0.5', 550.0,
         'signed square root of p_a - p_b (an orifice between the chambers)',
         'signed_sqrt(p_a - p_b)', says={'flow': w.difference_flow}),
    # windows over the stroke: where along it the correction acts
    *(Term(f'window_{k}', '1', 1.0, f'a window over part {k + 1} of {N_WINDOWS} of the '
           'stroke', f'window(angle, stroke, {k})',
           ('moment_balance', 'measurement_angle'), 2,
           says={'torque': w.window_torque(k, N_WINDOWS),
                 'reading': w.window_reading(k, N_WINDOWS)}) for k in range(N_WINDOWS)),
    # products with a window: what acts only over part of the stroke
    *windowed('sqrt_pressure_difference', 'Pa^0.5', 550.0, 'signed_sqrt(p_a - p_b)',
              'signed square root of p_a - p_b', 'an orifice between the chambers', _FLOWS,
              'flow', w.windowed_orifice_flow),
    *(t for k in 'ab' for t in windowed(
        f'sqrt_drop_{k}', 'Pa^0.5', 600.0, f'signed_sqrt(p_{k} - p_atm)',
        f'signed square root of p_{k} - p_atm', f'an orifice from chamber {k} to atmosphere',
        (f'mass_balance_{k}',), 'flow', w.windowed_vent_flow(k))),
    *windowed('velocity', 'rad/s', 2.0, 'velocity', 'shaft speed', 'damping there',
              ('moment_balance',), 'torque', w.windowed_damping_torque),
    *windowed('sign_velocity', '1', 1.0, f'np.tanh(velocity / {SIGN_VELOCITY_WIDTH})',
              'direction of motion', 'friction there', ('moment_balance',), 'torque',
              w.windowed_friction_torque),
    # products: friction that grows with the chambers' pressure
    Term('sign_velocity_times_mean_pressure', 'Pa', 3e5,
         'direction of motion times the mean chamber pressure above atmosphere (seal '
         'friction that grows with pressure)',
         f'np.tanh(velocity / {SIGN_VELOCITY_WIDTH}) * (0.5 * (p_a + p_b) - p_atm)',
         ('moment_balance',), 2, says={'torque': w.pressure_friction_torque}),
    Term('sign_velocity_times_pressure_difference', 'Pa', 3e5,
         'direction of motion times p_a - p_b (friction that grows with the load)',
         f'np.tanh(velocity / {SIGN_VELOCITY_WIDTH}) * (p_a - p_b)', ('moment_balance',), 2,
         says={'torque': w.load_friction_torque}),
    Term('sign_velocity_times_abs_pressure_difference', 'Pa', 3e5,
         'direction of motion times |p_a - p_b| (friction that grows with the load, whichever '
         'way it pushes)',
         f'np.tanh(velocity / {SIGN_VELOCITY_WIDTH}) * np.abs(p_a - p_b)', ('moment_balance',),
         2, says={'torque': w.abs_load_friction_torque}),
    # memory
    Term('command_direction', '1', 1.0, 'direction in which the command last moved '
         '(hysteresis)', 'command_direction', ('valve_input',) + _FLOWS, 2,
         says={'flow': w.hysteresis_flow, 'valve': w.hysteresis_valve}),
    Term('motion_direction', '1', 1.0, 'direction in which the shaft last moved (play)',
         'motion_direction', ('measurement_angle',), 2, says={'reading': w.play_reading}),
    # a free shape over the stroke: where no closed form fits (the shape stage)
    *(Term(f'angle_shape_{k}', '1', 1.0, f'knot {k + 1} of {N_KNOTS} of a free shape over '
           'the stroke', f'hat(angle, stroke, {k})', ('moment_balance', 'measurement_angle'),
           screened=False) for k in range(N_KNOTS)),
    # free functions of one variable: whether a correction also depends on it (probes)
    *(Term(f'{v}_probe_{k}', '1', 1.0, f'knot {k + 1} of {N_PROBE_KNOTS} of a free function '
           f'of {words}', f'knot({v}, {low.name}, {high.name}, {k})', _MODULATED,
           screened=False, probes=v)
      for v, words, *_ in PROBED for low, high in [PROBE_SPANS[v]] for k in range(N_PROBE_KNOTS)),
    # dynamics of a sensor: a lag of tau reads, to first order, -tau times the rate
    *(Term(f'rate_p_{k}', 'Pa/s', 2e6, f'rate of change of p_{k} (a lagging transmitter)',
           f'p_{k}_rate', (f'measurement_p_{k}',), says={'reading': w.pressure_rate_reading})
      for k in 'ab'),
    # the energy balances and temperature readings (records that hold the temperatures)
    *(Term(f'wall_minus_t_{k}', 'K', 20.0, f'wall temperature minus the chamber {k} gas '
           'temperature (heat through its wall)', f'(t_wall - t_{k})', (f'energy_balance_{k}',),
           says={'heat': w.wall_heat}) for k in 'ab'),
    *(Term(f't_{k}', 'K', 300.0, f'chamber {k} gas temperature', f't_{k}',
           (f'measurement_t_{k}',), says={'reading': w.temperature_reading}) for k in 'ab'),
    *(Term(f'rate_t_{k}', 'K/s', 50.0, f'rate of change of T_{k} (a lagging temperature '
           'sensor)', f't_{k}_rate', (f'measurement_t_{k}',),
           says={'reading': w.temperature_rate_reading}) for k in 'ab'),
    # a reading through a first-order lag at fixed time constants (a memory of the reading;
    # the rates above are its first order)
    *(Term(f'lag_{1e3 * tau:.0f}ms_{v}', READINGS[v][2], tau * READINGS[v][1],
           f'{v} through a first-order lag of {1e3 * tau:.0f} ms, minus {v} (a sensor that '
           'reads late)', f'({v}_lag_{1e3 * tau:.0f}ms - {v})', (f'measurement_{v}',), 2,
           says={'reading': w.lag_reading})
      for v, taus in LAGS_S.items() for tau in taus),
)
TERMS += modulations(
    [t for t in TERMS if t.cost == 1 and t.equations is None and t.depends_on],
    MODULATORS, _MODULATED, exclude={('sign_velocity', 'pressure_difference')} | {
        (c, f'window_{k}') for k in range(N_WINDOWS) for c in (
            'velocity', 'sign_velocity', 'sqrt_drop_a', 'sqrt_drop_b',
            'sqrt_pressure_difference')})
BY_NAME = {t.name: t for t in TERMS}


def offered(equation: str, sensor: bool, generic: bool = True,
            blind_to: tuple[str, ...] = ()) -> tuple[Term, ...]:
    """The terms offered in ``equation`` (a sensor equation is evaluated over arrays, so a
    term without a compiled form is offered there only); without ``generic``, of the terms
    offered everywhere only the constant; none that depends on a variable of ``blind_to``."""
    return tuple(t for t in TERMS
                 if (equation in (t.equations or ()) or t.equations is None
                     and (generic or not t.variables))
                 and (sensor or t.compiled) and not set(t.depends_on) & set(blind_to))


def variables_of(terms) -> list[Variable]:
    """The variables ``terms`` use, in the order of :data:`VARIABLES`."""
    names = {name for t in terms for name in t.variables}
    return [v for v in VARIABLES if v.name in names]



def term_values(terms, signals: dict, core: dict, params: dict | None = None) -> np.ndarray:
    """(n, len(terms)) values of ``terms`` over a record's ``signals`` [SI] (``params``: the
    correction's values, for its fixed parameters); only the variables they use are
    evaluated (a memory or a rate is a pass over the record)."""
    ns = array_namespace(signals, core, variables_of(terms), params)
    n = len(next(iter(signals.values())))
    return np.column_stack([np.broadcast_to(eval(t.expression, ns), (n,))  # noqa: S307
                            for t in terms]) if terms else np.zeros((n, 0))

