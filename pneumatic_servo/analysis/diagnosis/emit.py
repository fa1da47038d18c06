"""A discovered correction written out as a user effect: a documented Python file with one
``Component`` class, its fitted coefficients as ``Param`` defaults and bounds.

The user renames the class and its ``name`` to the physics they recognise
(``ReturnSpring``) and names it in a config or on the command line as
``path/to/file.py:Class``; it then takes part in simulation, fitting and
diagnosis like a built-in effect.
"""
from __future__ import annotations

import re

from ...effects.corrections import BY_EQUATION, REGRESSORS, SIGN_COMMAND_WIDTH, SIGN_VELOCITY_WIDTH
from .discovery import Discovered

#: regressor -> (expression in a compiled hook of state ``x``, context ``c``, parameters ``P``;
#: expression over the arrays of ``signals`` in a sensor error)
EXPRESSIONS = {
    'constant': ('1.0', '1.0'),
    'angle': ('x[THETA]', 'angle'),
    'sin_angle': ('math.sin(x[THETA])', 'np.sin(angle)'),
    'cos_angle': ('math.cos(x[THETA])', 'np.cos(angle)'),
    'velocity': ('x[OMEGA]', 'velocity'),
    'sign_velocity': (f'math.tanh(x[OMEGA] / {SIGN_VELOCITY_WIDTH})',
                      f'np.tanh(velocity / {SIGN_VELOCITY_WIDTH})'),
    'p_a': ('x[P_A]', 'p_a'),
    'p_b': ('x[P_B]', 'p_b'),
    'pressure_difference': ('(x[P_A] - x[P_B])', '(p_a - p_b)'),
    'command': ('(c[C_U] - P[K_NULL])', 'command'),
    'sign_command': (f'math.tanh((c[C_U] - P[K_NULL]) / {SIGN_COMMAND_WIDTH})',
                     f'np.tanh(command / {SIGN_COMMAND_WIDTH})'),
    'abs_command': ('abs(c[C_U] - P[K_NULL])', 'np.abs(command)'),
    'supply': ('c[C_PS]', 'supply'),
    'sqrt_drop_a': ('math.copysign(math.sqrt(abs(x[P_A] - c[C_PE])), x[P_A] - c[C_PE])',
                    'np.sign(p_a - p_atm) * np.sqrt(np.abs(p_a - p_atm))'),
    'sqrt_drop_b': ('math.copysign(math.sqrt(abs(x[P_B] - c[C_PE])), x[P_B] - c[C_PE])',
                    'np.sign(p_b - p_atm) * np.sqrt(np.abs(p_b - p_atm))'),
    'sqrt_pressure_difference': ('math.copysign(math.sqrt(abs(x[P_A] - x[P_B])), '
                                 'x[P_A] - x[P_B])',
                                 'np.sign(p_a - p_b) * np.sqrt(np.abs(p_a - p_b))'),
}
assert set(EXPRESSIONS) == {r.name for r in REGRESSORS}

#: equation -> (hook stage, statement adding the correction ``term``, layout names it uses)
STATEMENTS = {
    'moment_balance': ('mechanics', 'c[C_TORQUE] += term', ['C_TORQUE']),
    'mass_balance_a': ('flows', 'add_flow(c, 0, term, c[C_TE], x[T_A])',
                       ['C_TE', 'T_A', 'add_flow']),
    'mass_balance_b': ('flows', 'add_flow(c, 1, term, c[C_TE], x[T_B])',
                       ['C_TE', 'T_B', 'add_flow']),
    'valve_input': ('valve', 'lim = P[K_HALF_W] + P[K_HOLE_R]\n    '
                    'c[C_XV] = min(max(c[C_XV] + P[K_GAIN] * term, -lim), lim)',
                    ['C_XV', 'K_GAIN', 'K_HALF_W', 'K_HOLE_R']),
}
_HOOK_NAMES = ('THETA', 'OMEGA', 'P_A', 'P_B', 'C_U', 'C_PS', 'C_PE', 'K_NULL')
_DESCRIPTIONS = {r.name: r.description for r in REGRESSORS}


def _sentence(text: str) -> str:
    return text[:1].upper() + text[1:] + '.'


def class_name(equation: str) -> str:
    return 'Discovered' + ''.join(w.capitalize() for w in equation.split('_'))


def _params(term: Discovered) -> str:
    """``Param`` declarations of the terms: the fitted value as the default, the generic
    correction's bounds and plausible range."""
    cls_ = BY_EQUATION[term.equation]
    decl = {p.name: p for p in cls_.params}
    stderr = term.to_json()['stderr']
    lines = []
    for reg, value in term.terms.items():
        p = decl[f'{reg}_coefficient']
        what = f'{cls_.equation.description} per unit of {_DESCRIPTIONS[reg]}'
        if stderr.get(reg) is not None and stderr[reg] == stderr[reg]:
            what += f' (fitted +/- {stderr[reg]:.2g})'
        lines.append(f"        Param({p.name!r}, {p.unit!r}, {value!r}, {p.lower!r}, "
                     f"{p.upper!r},\n              {what!r},\n"
                     f"              plausible={p.plausible!r}),")
    return '\n'.join(lines)


def _hook_source(term: Discovered) -> tuple[str, list[str]]:
    stage, statement, names = STATEMENTS[term.equation]
    expr = ' + '.join(f'p[{i}] * {EXPRESSIONS[reg][0]}' for i, reg in enumerate(term.terms))
    used = [n for n in _HOOK_NAMES if any(n in EXPRESSIONS[r][0] for r in term.terms)]
    body = (f'def _correction(t, x, s, p, P, c, dx):\n'
            f'    """Add the correction: {BY_EQUATION[term.equation].equation.description} '
            f'[{BY_EQUATION[term.equation].equation.unit}]."""\n'
            f'    term = {expr}\n'
            f'    {statement}\n')
    return body, sorted(set(names + used)), stage


#: variables of the array expressions, as read from a sensor error's arguments
ARRAY_VARIABLES = {
    'angle': "signals['angle_rad']",
    'velocity': "signals['velocity_rad_s']",
    'p_a': "signals['p_a_pa']",
    'p_b': "signals['p_b_pa']",
    'command': "signals['command_v'] - core['valve_null_voltage_v']",
    'supply': "signals['supply_pa']",
    'p_atm': "core['atmospheric_pressure_pa']",
}


def _sensor_source(term: Discovered) -> str:
    signal = BY_EQUATION[term.equation].equation.signal
    exprs = [EXPRESSIONS[reg][1] for reg in term.terms]
    total = ' + '.join(f"values['{reg}_coefficient'] * {e}" for reg, e in zip(term.terms, exprs))
    used = [v for v in ARRAY_VARIABLES if any(re.search(rf'\b{v}\b', e) for e in exprs)]
    lines = ''.join(f'    {v} = {ARRAY_VARIABLES[v]}\n' for v in used)
    return (f'def _sensor_error(values, signals, core):\n'
            f'    """What the sensor adds to its reading of {signal} [SI]."""\n{lines}'
            f'    return {{{signal!r}: {total}}}\n')


def effect_source(term: Discovered, found_on: list[str]) -> str:
    """The source of a Python module holding ``term`` as a user effect class."""
    cls_ = BY_EQUATION[term.equation]
    eq = cls_.equation
    name = class_name(term.equation)
    header = (f'"""A correction found by ``pneumatic-servo diagnose``:\n{term.interpretation}.\n\n'
              f'Equation: {eq.name} ({eq.description}, [{eq.unit}]).\n'
              f'Found on: {", ".join(found_on)}; it cut the held-out error by '
              f'{100 * term.error_reduction:.0f} %.\n\n'
              f'Rename the class and its ``name`` to the physics you recognise (for example\n'
              f'``ReturnSpring`` and ``\'return_spring\'``), then use it as\n'
              f'``effects: {{\'path/to/this_file.py:{name}\': {{}}}}`` in a model config, or\n'
              f'``pneumatic-servo compare BAG --effects path/to/this_file.py:{name}``.\n'
              f'The coefficients below are the fitted values, in SI units.\n"""\n')
    neutral = ', '.join(f"'{reg}_coefficient': 0.0" for reg in term.terms)
    example = ', '.join(f"'{reg}_coefficient': {v!r}" for reg, v in term.terms.items())
    common = (f"    name = 'discovered_{term.equation}'\n"
              f"    summary = '{eq.description}, found by diagnosis'\n"
              f"    reference = 'pneumatic-servo diagnose --emit-effect'\n"
              f"    acts_on = '{cls_.acts_on}'\n"
              f'    params = (\n{_params(term)}\n    )\n'
              f'    neutral = {{{neutral}}}\n'
              f'    example = {{{example}}}\n')
    if eq.signal is not None:
        numpy = 'import numpy as np\n\n' if 'np.' in _sensor_source(term) else ''
        return (header + f'\n{numpy}from pneumatic_servo.effects import '
                'Component, Param\n\n\n' + _sensor_source(term) + f'\n\nclass {name}(Component):\n'
                f'    """{_sentence(term.interpretation)}"""\n\n' + common
                + '    sensor_error = staticmethod(_sensor_error)\n')
    hook, names, stage = _hook_source(term)
    return (header + '\nimport math\n\nfrom pneumatic_servo.effects import Component, Param\n'
            f'from pneumatic_servo.effects.layout import {", ".join(names)}\n\n\n' + hook
            + f'\n\nclass {name}(Component):\n    """{_sentence(term.interpretation)}"""\n\n'
            + common
            + f'    {stage} = _correction\n')
