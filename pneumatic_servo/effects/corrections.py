"""Generic corrections: what diagnosis can add where no named effect fits.

A correction adds, to one balance equation, one input or one measurement, a
linear combination of the terms of :mod:`.terms`:

    correction = sum_k  coefficient_k * term_k(state, inputs, memory)

Equations (each a component, named ``correction_<equation>``):

* ``moment_balance``: an extra torque on the shaft [N.m];
* ``mass_balance_a``, ``mass_balance_b``: an extra mass flow into a chamber [kg/s];
* ``valve_input``: an extra effective valve command [V];
* ``measurement_supply`` [Pa]: an error of the supply sensor. The model is fed that
  reading, so the error acts through the physics: the true supply is the reading less it;
* ``measurement_angle`` [rad], ``measurement_p_a``, ``measurement_p_b`` [Pa]: a sensor
  error, added to what the sensor reads; it does not feed back into the physics.

Every coefficient is in SI units of the equation per unit of its term, is zero by
default (the correction then adds exactly nothing) and is bounded by ten times the size
a plausible correction has. A correction whose terms include a memory of the command
(the direction it last moved in) owns that memory as a state.

The hooks are generated from the terms' expressions (:func:`hook_source`, also what
``diagnose --emit-effect`` writes) and compiled once per machine. The classes are
``generic``: diagnosis never tries them as named effects; its discovery step fits them
(``analysis.diagnosis.discovery``).
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import _jit
from . import bases, layout, terms
from .base import Component, Param
from .terms import Term, offered, term_values


@dataclass(frozen=True)
class Equation:
    """Where a correction acts: its unit, the size [SI] of a plausible correction, what it
    adds, the measured signal a sensor error shows in (None where it acts through the
    physics), and for those the hook stage, the statement that adds ``term`` and the
    order within the stage."""

    name: str
    unit: str
    size: float
    description: str
    signal: str | None = None
    stage: str = ''
    statement: str = ''
    order: int = 50
    acts_on: str = 'both'
    circuits: tuple[str, ...] = ('servo', 'blocked', 'closed_port', 'flow')
    #: the equation whose residual a report shows for this one, where it has no measurable
    #: residual of its own (a valve or supply error shows in chamber a's mass balance)
    shown_as: str = ''
    #: signals a record must hold for the equation to be told apart from the others: a heat
    #: flow and a mass flow into a chamber move its pressure alike, and only its
    #: temperature separates them
    needs: tuple[str, ...] = ()
    #: whether the terms offered in every equation are offered here; a temperature
    #: sensor sees no pressure or command, so its errors are its own terms and a constant
    generic: bool = True
    #: variables that cannot act here, so no term of them is offered: a torque on the shaft
    #: comes from the pressures, not from the valve's command, and a sensor of the angle or
    #: of a chamber's pressure does not see the command (where such a term was offered, the
    #: closed loop, in which the command follows every error, let it stand in for the
    #: effect's own variables and take the equation of a valve or chamber flow error)
    blind_to: tuple[str, ...] = ()
    #: the measured signal whose sensor it corrects, where that is not ``signal`` (the
    #: supply's reading feeds the model instead of being compared)
    reads: str = ''

    @property
    def terms(self) -> tuple[Term, ...]:
        """The terms offered in this equation, in the order of its parameters."""
        return offered(self.name, self.signal is not None, self.generic, self.blind_to)

    @property
    def own(self) -> tuple[Term, ...]:
        """The terms of a sensor's own reading alone (its value, its memory, lag or rate,
        constants), empty where the equation corrects no sensor: a transmitter's error
        follows what it measures (gain, offset, lag, a stuck bit), and a crosstalk from
        another signal needs a wiring fault, so discovery takes one only where it explains
        clearly more (in closed loop the command follows every error: a crosstalk of it into
        the supply reading stood in for a valve's flow error into chamber a)."""
        signal = self.reads or self.signal
        if not signal:
            return ()
        return tuple(t for t in self.terms
                     if all(terms.BY_VARIABLE[v].signal in ('', signal) for v in t.depends_on))

    @property
    def memories(self) -> list:
        """The memories of the command its terms use (:func:`memories`)."""
        return memories(self.terms)


def memories(used) -> list:
    """The memory variables ``used`` terms need, in the order of their states."""
    return [v for v in terms.VARIABLES if any(v in t.memories for t in used)]


#: the variables of the valve's command
COMMAND = ('command', 'command_direction')

EQUATIONS = (
    Equation('moment_balance', 'N.m', 1.0, 'an extra torque on the shaft',
             stage='mechanics', statement='c[C_TORQUE] += term', acts_on='angle',
             circuits=('servo',), blind_to=COMMAND),
    Equation('mass_balance_a', 'kg/s', 5e-5, 'an extra mass flow into chamber a',
             stage='flows', statement='add_flow(c, 0, term, c[C_TE], x[T_A])',
             acts_on='pressure'),
    Equation('mass_balance_b', 'kg/s', 5e-5, 'an extra mass flow into chamber b',
             stage='flows', statement='add_flow(c, 1, term, c[C_TE], x[T_B])',
             acts_on='pressure', circuits=('servo', 'blocked')),
    Equation('valve_input', 'V', 0.5, 'an extra effective valve command', stage='valve',
             statement='lim = P[K_HALF_W] + P[K_HOLE_R]\n'
                       '    c[C_XV] = min(max(c[C_XV] + P[K_GAIN] * term, -lim), lim)',
             order=15, shown_as='mass_balance_a'),
    Equation('measurement_supply', 'Pa', 2e4, 'an error of the supply pressure sensor '
             '(the model is fed its reading)', stage='supply',
             statement='c[C_PS] -= term\n    c[C_PS_REG] -= term', order=10,
             shown_as='mass_balance_a', reads='supply_pa'),
    Equation('measurement_angle', 'rad', 0.05, 'an error of the angle sensor', 'angle_rad',
             blind_to=COMMAND),
    Equation('measurement_p_a', 'Pa', 2e4, 'an error of the chamber a pressure sensor',
             'p_a_pa', blind_to=COMMAND),
    Equation('measurement_p_b', 'Pa', 2e4, 'an error of the chamber b pressure sensor',
             'p_b_pa', blind_to=COMMAND),
    Equation('energy_balance_a', 'W', 5.0, 'an extra heat flow into chamber a', stage='heat',
             statement='c[C_QA] += term', acts_on='pressure', shown_as='mass_balance_a',
             needs=('t_a_k',)),
    Equation('energy_balance_b', 'W', 5.0, 'an extra heat flow into chamber b', stage='heat',
             statement='c[C_QB] += term', acts_on='pressure', circuits=('servo', 'blocked'),
             shown_as='mass_balance_b', needs=('t_b_k',)),
    Equation('measurement_t_a', 'K', 2.0, 'an error of the chamber a temperature sensor',
             't_a_k', generic=False),
    Equation('measurement_t_b', 'K', 2.0, 'an error of the chamber b temperature sensor',
             't_b_k', generic=False),
)


def coefficient_name(term: str) -> str:
    return f'{term}_coefficient'


def _params(eq: Equation) -> tuple[Param, ...]:
    out = []
    for t in eq.terms:
        size = eq.size / t.typical
        unit = (eq.unit if t.unit == '1' else '1' if t.unit == eq.unit else
                's' if t.unit == f'{eq.unit}/s' else f'{eq.unit}/({t.unit})' if '*' in t.unit
                else f'{eq.unit}/{t.unit}')
        out.append(Param(coefficient_name(t.name), unit, 0.0, -10.0 * size, 10.0 * size,
                         f'{eq.description} per unit of {t.words}', fit=False,
                         plausible=(-size, size)))
    return tuple(out) + fixed_params(eq.terms)


def fixed_params(used) -> tuple[Param, ...]:
    """The fixed parameters ``used`` terms read (the spans of free functions), after the
    coefficients in a correction's parameters and in the order of :data:`.terms.VARIABLES`."""
    return tuple(v.param for v in terms.variables_of(used) if v.param is not None)


# --- the generated source: one function per equation, from the terms' expressions -------
#: names a generated hook may use, and where they are imported from
_LAYOUT_NAMES = ('THETA', 'OMEGA', 'P_A', 'P_B', 'T_A', 'T_B', 'C_PE', 'C_U', 'C_PS',
                 'C_PS_REG', 'C_TE', 'C_TORQUE', 'C_XV', 'C_QA', 'C_QB', 'K_NULL', 'K_STROKE',
                 'K_GAIN', 'K_HALF_W', 'K_HOLE_R', 'add_flow')
_TERM_NAMES = ('signed_sqrt', 'window', 'hat', 'knot', 'memory_direction', 'memory_rate',
               'COMMAND_PLAY_V', 'direction', 'MOTION_PLAY_RAD', 'rate', 'lag')


def _used(text: str, names) -> list[str]:
    return [n for n in names if re.search(rf'\b{n}\b', text)]


def hook_source(eq: Equation, used: list[Term], name: str = '_correction',
                skip_zero: bool = False) -> str:
    """Source of the compiled hook adding ``sum_i p[i] * used[i]`` to ``eq``.

    ``skip_zero``: evaluate a term only where its coefficient is not zero (the sum is the
    same), and none while the switch after the coefficients is off. The package's hooks
    carry every term of the vocabulary, and a screening simulation sets one of them;
    emitted files carry only the terms in use.
    """
    states = {v.name: f's + {i}' for i, v in enumerate(memories(used))}
    fixed = fixed_params(used)  # after the coefficients, before the switch
    index = {**{v: f'x[{i}]' for v, i in states.items()},
             **{q.name: f'p[{len(used) + i}]' for i, q in enumerate(fixed)}}
    lines = [f'def {name}(t, x, s, p, P, c, dx):',
             f'    """Add the correction: {eq.description} [{eq.unit}]."""',
             *(f'    {v.name} = ' + (v.compiled_at(index[v.name]) if v.name in index
                                      else v.compiled) for v in terms.variables_of(used))]
    if skip_zero:
        # p[len(used) + len(fixed)] is the hook's switch (1.0 while a coefficient is not
        # zero: ``.base.switched``); a hook with a memory runs always, to move its memory
        plain = [(i, t) for i, t in enumerate(used) if not t.modulates]
        lines += ['    term = 0.0', f'    if p[{len(used) + len(fixed)}] != 0.0:',
                  *_plain_sums(plain),
                  *('    ' + line.replace('\n', '\n    ') for line in _modulations(used))]
    else:
        lines.append('    term = ' + (' + '.join(f'p[{i}] * {t.expression}'
                                                for i, t in enumerate(used)) or '0.0'))
    lines += [f'    dx[{i}] = {terms.BY_VARIABLE[v].follows.format(m=f"x[{i}]")}'
              for v, i in states.items()]
    lines.append(f'    {eq.statement}')
    return '\n'.join(lines) + '\n'


#: an expression whose last argument is a whole number: a function's knot, a window
_INDEXED = re.compile(r'^(.*), (\d+)\)$')


def _plain_sums(plain: list[tuple[int, Term]]) -> list[str]:
    """Lines adding the plain terms ``plain`` (index, term), each where its coefficient is
    not zero. A run of terms at consecutive indices whose expressions differ only in a last
    argument counting 0, 1, 2, ... (a free function's knots, a term's windows) is one loop,
    which numba compiles once, not once per term: the seven hooks compile in 13.5 s on a
    fresh machine, against 19.3 s unrolled."""
    runs = []  # [expression before the count or None, first index, terms]
    for i, t in plain:
        m = _INDEXED.match(t.expression)
        last = runs[-1] if runs else None
        if (m and last and last[0] == m.group(1) and last[1] + len(last[2]) == i
                and int(m.group(2)) == len(last[2])):
            last[2].append(t)
        else:
            runs.append([m.group(1) if m and m.group(2) == '0' else None, i, [t]])
    lines = []
    for head, first, run in runs:
        if head is None or len(run) == 1:
            lines += [f'        if p[{i}] != 0.0:\n            term += p[{i}] * {t.expression}'
                      for i, t in enumerate(run, first)]
        else:
            lines += [f'        for k in range({len(run)}):\n'
                      f'            if p[{first} + k] != 0.0:\n'
                      f'                term += p[{first} + k] * {head}, k)']
    return lines


def _modulations(used: list[Term]) -> list[str]:
    """Lines adding the modulations among ``used`` (they follow the plain terms): each
    carrier and modulator is evaluated once, and only where a coefficient of theirs is not
    zero, so that a hundred products compile as one loop, not as a hundred expressions."""
    first = next((i for i, t in enumerate(used) if t.modulates), None)
    if first is None:
        return []
    products = used[first:]
    assert all(t.modulates for t in products), 'modulations follow the plain terms'
    carriers = list(dict.fromkeys(t.modulates for t in products))
    modulators = list(dict.fromkeys(t.modulator for t in products))
    ci = tuple(carriers.index(t.modulates) for t in products)
    mi = tuple(modulators.index(t.modulator) for t in products)
    return [f'    on = False\n    for k in range({first}, {len(used)}):\n'
            '        on = on or p[k] != 0.0',
            '    if on:',
            '        carriers = (' + ', '.join(terms.BY_NAME[c].expression for c in carriers)
            + ',)',
            '        modulators = (' + ', '.join(terms.BY_MODULATOR[m][0] for m in modulators)
            + ',)',
            f'        for k in range({len(products)}):',
            f'            if p[{first} + k] != 0.0:',
            f'                term += p[{first} + k] * carriers[{ci}[k]] * modulators[{mi}[k]]']


def sensor_source(eq: Equation, used: list[Term], name: str = '_sensor_error') -> str:
    """Source of the sensor error ``sum_k values[<term>_coefficient] * term_k`` of ``eq``
    over a record's arrays (the form ``Component.sensor_error`` takes)."""
    variables = terms.variables_of(used)
    total = ' + '.join(f"values['{coefficient_name(t.name)}'] * {t.expression}" for t in used)
    return (f'def {name}(values, signals, core):\n'
            f'    """What the sensor adds to its reading of {eq.signal} [SI]."""\n'
            + ''.join(f'    {v.name} = {v.array}\n' for v in variables)
            + "    n = len(next(iter(signals.values())))\n"
            f"    return {{'{eq.signal}': np.zeros(n) + ({total or '0.0'})}}\n")


def imports(source: str) -> str:
    """The import lines a generated function needs."""
    out = 'import numpy as np\n\n' if 'np.' in source else ''
    lay, fun = _used(source, _LAYOUT_NAMES), _used(source, _TERM_NAMES)
    if lay:
        out += f'from pneumatic_servo.effects.layout import {", ".join(lay)}\n'
    if fun:
        out += f'from pneumatic_servo.effects.terms import {", ".join(fun)}\n'
    return out


def _compiled_hooks() -> dict:
    """The hooks of every equation that acts through the physics, compiled from one
    generated module (cached on disk like the kernels)."""
    body = ''.join('\n\n@njit(cache=True, allocates=False)\n'
                   + hook_source(eq, list(eq.terms), f'hook_{eq.name}', skip_zero=True)
                   for eq in EQUATIONS if eq.signal is None)
    source = ('"""Generated by pneumatic_servo.effects.corrections: do not edit."""\n'
              + imports(body) + 'from pneumatic_servo._jit import njit\n' + body)
    # the layout's indices and the terms' functions are compiled in as constants: their
    # source is part of the key, so that an edit never loads stale machine code
    key = _jit.source_key(source, Path(layout.__file__).read_text(),
                          Path(terms.__file__).read_text(), Path(bases.__file__).read_text())
    module = _jit.load_generated(f'pneumatic_servo_corrections_{key}', source)
    return {eq.name: getattr(module, f'hook_{eq.name}') for eq in EQUATIONS
            if eq.signal is None}


def _sensor(eq: Equation):
    used = [(t, coefficient_name(t.name)) for t in eq.terms]
    keys = [k for _, k in used]

    def sensor_error(values: dict, signals: dict, core: dict) -> dict:
        # the terms in use only: a zero coefficient adds nothing, not even a missing sample
        # (checked first without building anything: this runs for every predicted segment)
        if not any(map(values.__getitem__, keys)):
            return {}
        on = [(t, values[k]) for t, k in used if values[k] != 0.0]
        return {eq.signal: term_values([t for t, _ in on], signals, core, values)
                @ np.array([c for _, c in on])}
    return sensor_error


class Correction(Component):
    """Base of the generic corrections: never tried as a named effect."""

    generic = True
    #: every term at zero in most simulations (a correction with the command's memory has
    #: a state, and is called always: see ``Component.skipped_at_neutral``)
    skipped_at_neutral = True
    summary = 'a generic correction term found by diagnosis'
    reference = 'analysis.diagnosis.discovery'

    @classmethod
    def refit_keys(cls, values: dict) -> list[str]:
        """Only the terms in use are refitted when the model is diagnosed again."""
        return [k for k, v in values.items() if k in cls.neutral and v != 0.0]

    @classmethod
    def initial_state(cls, values, command_v, supply_pa, core):
        # the command's memories start at the command: no direction yet
        return [float(command_v)] * len(cls.states)


def _correction_class(eq: Equation, hooks: dict) -> type[Component]:
    params = _params(eq)
    attrs = {'name': f'correction_{eq.name}', 'equation': eq, 'params': params,
             # the coefficients: a span of a free function adds nothing alone
             'neutral': {coefficient_name(t.name): 0.0 for t in eq.terms},
             'acts_on': eq.acts_on, 'circuits': eq.circuits, 'order': eq.order,
             'states': tuple(v.memory for v in eq.memories),
             '__doc__': f'Generic correction: {eq.description} [{eq.unit}], a linear '
                        'combination of the terms.'}
    if eq.signal is None:
        attrs[eq.stage] = hooks[eq.name]
    else:
        attrs['sensor_error'] = staticmethod(_sensor(eq))
    return type(f'Correction_{eq.name}', (Correction,), attrs)


_HOOKS = _compiled_hooks()
CORRECTIONS = tuple(_correction_class(eq, _HOOKS) for eq in EQUATIONS)
#: equation name -> its correction component
BY_EQUATION = {cls.equation.name: cls for cls in CORRECTIONS}
