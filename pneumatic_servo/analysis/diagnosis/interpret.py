"""A discovered correction in the words an engineer would write: what it is, and the physics
that usually causes it."""
from __future__ import annotations

import math

from ...effects.corrections import BY_EQUATION
from ...effects.term_words import Context
from ...effects.terms import BY_MODULATOR, BY_NAME, N_KNOTS, VARIABLES
from ...model.config import ModelConfig

#: the vocabulary's order: simplest first
ORDER = {name: i for i, name in enumerate(BY_NAME)}
#: shares of a correction's variation closer than this are one shape over the record
SAME_SHAPE = 0.01


def leading(terms: dict[str, float], shares: dict[str, float] | None = None) -> str:
    """The regressor a correction mostly depends on.

    With ``shares`` (the share of the correction's variation along the record each term
    follows alone, ``readings.term_spread``): the term with the largest. A constant level
    depends on nothing, so the constant leads only where nothing else varies: a gravity arm
    seen over a narrow range is a level plus a slope, and it depends on the angle. Without
    shares (a correction read back without its record): the term largest at its typical
    size. Terms whose shares differ by less than :data:`SAME_SHAPE` are the same function
    over the record (the angle and its cosine over a short arc); the simplest, first in the
    vocabulary, leads."""
    varying = [r for r in terms if (shares or {}).get(r, 0.0) > 0.0]
    if varying:
        top = max(shares[r] for r in varying)
        return min((r for r in varying if shares[r] > top - SAME_SHAPE), key=ORDER.get)
    return max(terms, key=lambda r: abs(terms[r]) * BY_NAME[r].typical)


def varies_with(terms, lead: str) -> list[str]:
    """The terms of a correction that make its leading term ``lead``'s size vary: those
    that are ``lead`` times another factor (its modulations, :func:`.terms.modulations`, and
    the products declared with words of their own: a friction over part of the stroke)."""
    mine = BY_NAME[lead].expression
    return [r for r in terms if r != lead and (BY_NAME[r].expression.startswith(f'{mine} * ')
                                               or BY_NAME[r].expression.endswith(f' * {mine}'))]


def depends_on(terms, lead: str) -> list[str]:
    """The variables a correction with ``terms`` led by ``lead`` depends on: those of its
    leading term and of the terms that make that term's size vary (:func:`varies_with`);
    another term beside them adds to the correction, and says nothing of what its main
    part depends on."""
    used = {v for r in (lead, *varies_with(terms, lead)) for v in BY_NAME[r].depends_on}
    return [v.name for v in VARIABLES if v.name in used]


def _general(equation: str, x: Context) -> str:
    """The words of an equation for a leading term that says nothing particular there."""
    if equation == 'moment_balance':
        return f'a torque that follows the {x.words}, {x.c:+.3g} per unit'
    if equation.startswith('mass_balance_'):
        return f'a flow {x.into} chamber {x.chamber} that follows the {x.words}'
    if equation == 'valve_input':
        return f'an extra valve command that follows the {x.words}'
    if equation.startswith('energy_balance_'):
        return f'a heat flow {x.into} chamber {x.chamber} that follows the {x.words}'
    if x.signal == 'angle':
        return f'an error of the angle reading that follows the {x.words}'
    if x.signal == 'supply':
        return f'an error of the supply reading that follows the {x.words}'
    if x.signal.startswith('t_'):
        return (f'an error of the chamber {x.chamber} temperature reading that follows the '
                f'{x.words}')
    return (f'an error of the chamber {x.chamber} pressure reading that follows the '
            f'{x.words}: crosstalk or a wiring fault')


def _kind(equation: str) -> str:
    """The kind of ``equation`` its terms speak in (:data:`.term_words.KINDS`)."""
    for prefix, kind in (('moment_', 'torque'), ('mass_', 'flow'), ('valve_', 'valve'),
                         ('energy_', 'heat')):
        if equation.startswith(prefix):
            return kind
    return 'reading'


def interpret(equation: str, terms: dict[str, float], config: ModelConfig,
              shares: dict[str, float] | None = None, lag_ms: float | None = None,
              angles_deg: tuple[float, float] | None = None) -> str:
    """One sentence on a correction of ``equation`` with ``terms`` (regressor -> coefficient,
    SI): what it is, after its leading term (:func:`leading`, with the terms' ``shares`` of
    its variation along the record where known), and the physics that usually causes it;
    a sensor error is called one, never a change of the physics. ``lag_ms``: the time
    constant of a reading's lag terms over the record (``readings.equivalent_lag_ms``);
    ``angles_deg``: the angles the record visits (``readings.angle_span_deg``)."""
    if not terms:
        return 'no term'
    reg = leading(terms, shares)
    kind = _kind(equation)
    signal = equation.removeprefix('measurement_') if kind == 'reading' else ''
    chamber = equation[-1] if kind in ('flow', 'heat') or signal[:2] in ('p_', 't_') else ''
    x = Context(terms[reg], terms, config.core, BY_NAME[reg].words, chamber, signal, lag_ms,
                angles_deg)
    text = BY_NAME[reg].explain(kind, x) or _general(equation, x)
    if kind == 'reading':
        text = 'a sensor error, not missing physics: ' + text
    mods = [BY_NAME[r] for r in varies_with(terms, reg) if BY_NAME[r].modulates]
    if mods:
        # c (1 + (c_k / c) m_k): the share of its size each unit of a modulator adds
        text += '; its size varies with ' + ' and '.join(
            f'{BY_MODULATOR[t.modulator][3]} ({terms[t.name] / terms[reg]:+.3g} of it per '
            'unit)' if terms[reg] else BY_MODULATOR[t.modulator][3] for t in mods)
    others = [r for r in terms if r != reg]
    if others:
        text += ' (with ' + ', '.join(f'{r} {terms[r]:+.3g}' for r in others) + ')'
    return text


def describe_shape(equation: str, terms: dict[str, float], config: ModelConfig,
                   undetermined=()) -> str:
    """One sentence on a free shape over the stroke (knot -> value, SI): its span and where it
    is largest over the knots the record determines (``undetermined``: those it does not
    reach), and what it is in this equation."""
    stroke = config.core['stroke_rad']
    knots = {int(r.rsplit('_', 1)[1]): v for r, v in terms.items() if r not in undetermined}
    if not knots:
        return 'a shape over the stroke that these records do not determine'
    angle = {k: math.degrees(k / (N_KNOTS - 1) * stroke) for k in knots}
    top = max(knots, key=lambda k: abs(knots[k]))
    unit = BY_EQUATION[equation].equation.unit
    what = ('a torque' if equation == 'moment_balance' else
            'a sensor error, not missing physics: an error of the angle reading'
            if equation == 'measurement_angle' else 'a correction')
    seen = (f' between {min(angle.values()):.0f} and {max(angle.values()):.0f} deg'
            if len(knots) < N_KNOTS else '')
    return (f'{what} that follows a free shape over the stroke: from '
            f'{min(knots.values()):+.3g} to {max(knots.values()):+.3g} {unit}'
            f'{seen}, largest ({knots[top]:+.3g}) near {angle[top]:.0f} deg ({N_KNOTS} knots, '
            'piecewise linear)')
