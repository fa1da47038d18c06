"""A discovered correction written out as a user effect: a documented Python file with one
``Component`` class, its fitted coefficients as ``Param`` defaults and bounds.

The user renames the class and its ``name`` to the physics they recognise
(``ReturnSpring``) and names it in a config or on the command line as
``path/to/file.py:Class``; it then takes part in simulation, fitting and
diagnosis like a built-in effect.
"""
from __future__ import annotations

from ...effects.corrections import (
    BY_EQUATION,
    hook_source,
    imports,
    memories,
    sensor_source,
)
from ...effects.terms import BY_NAME
from .discovery import Discovered, terms_of


def _sentence(text: str) -> str:
    return text[:1].upper() + text[1:] + '.'


def class_name(equation: str) -> str:
    return 'Discovered' + ''.join(w.capitalize() for w in equation.split('_'))


def _params(term: Discovered) -> str:
    """``Param`` declarations of the terms: the fitted value as the default, the generic
    correction's bounds and plausible range."""
    cls_ = BY_EQUATION[term.equation]
    decl = {p.name: p for p in cls_.params}
    stderr = terms_of(term.stderr)
    lines = []
    for reg, value in term.terms.items():
        p = decl[f'{reg}_coefficient']
        what = f'{cls_.equation.description} per unit of {BY_NAME[reg].words}'
        if stderr.get(reg) is not None and stderr[reg] == stderr[reg]:
            what += f' (fitted +/- {stderr[reg]:.2g})'
        lines.append(f"        Param({p.name!r}, {p.unit!r}, {value!r}, {p.lower!r}, "
                     f"{p.upper!r},\n              {what!r},\n"
                     f"              plausible={p.plausible!r}),")
    return '\n'.join(lines)


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
    used = [BY_NAME[reg] for reg in term.terms]
    states = [v.memory for v in memories(used)]
    code = sensor_source(eq, used) if eq.signal is not None else hook_source(eq, used)
    body = common + (f'    {eq.stage} = _correction\n' if eq.signal is None else
                     '    sensor_error = staticmethod(_sensor_error)\n')
    if states:  # the command's memories are states of the effect, starting at the command
        body += (f'    states = ({", ".join(map(repr, states))},)\n\n'
                 '    @classmethod\n'
                 '    def initial_state(cls, values, command_v, supply_pa, core):\n'
                 f'        return [float(command_v)] * {len(states)}\n')
    base = 'Component, Param, State' if states else 'Component, Param'
    return (header + '\n' + imports(code) + f'from pneumatic_servo.effects import {base}\n\n\n'
            + code + f'\n\nclass {name}(Component):\n'
            f'    """{_sentence(term.interpretation)}"""\n\n' + body)
