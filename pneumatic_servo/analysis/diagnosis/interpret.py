"""A discovered correction in the words an engineer would write: what it is, and the physics
that usually causes it."""
from __future__ import annotations

import math

from ...effects.corrections import BY_EQUATION
from ...effects.terms import BY_NAME, N_KNOTS, N_WINDOWS
from ...model.config import ModelConfig

TYPICAL = {t.name: t.typical for t in BY_NAME.values()}
DESCRIPTION = {t.name: t.words for t in BY_NAME.values()}
#: the vocabulary's order: simplest first
ORDER = {name: i for i, name in enumerate(BY_NAME)}
#: shares of a correction's variation closer than this are one shape over the record
SAME_SHAPE = 0.01


def _part(reg: str, core: dict) -> str:
    """Where along the stroke window term ``reg`` acts, in degrees."""
    k = int(reg.rsplit('_', 1)[1])
    stroke = math.degrees(core['stroke_rad'])
    return f'between about {k * stroke / N_WINDOWS:.0f} and {(k + 1) * stroke / N_WINDOWS:.0f} deg'


def leading(terms: dict[str, float], shares: dict[str, float] | None = None) -> str:
    """The regressor a correction mostly depends on.

    With ``shares`` (the share of the correction's variation along the record each term
    follows alone, ``discovery.term_spread``): the term with the largest. A constant level
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
    return max(terms, key=lambda r: abs(terms[r]) * TYPICAL[r])


def _moment(reg: str, c: float, terms: dict, core: dict) -> str:
    if reg == 'constant':
        return (f'a constant torque of {c:+.3g} N.m on the shaft: a load, a preload, or '
                'gravity on an arm held near one angle')
    if reg == 'angle':
        rest = -terms.get('constant', 0.0) / c
        where = f' about {rest:.2f} rad' if 'constant' in terms else ''
        return (f'an extra torque that {"rises" if c > 0 else "falls"} with angle, about '
                f'{c:+.3g} N.m/rad{where}: a return spring, or a gravity load on an arm')
    if reg in ('sin_angle', 'cos_angle'):
        trig = 'sine' if reg == 'sin_angle' else 'cosine'
        return (f'a torque that varies with the {trig} of the angle, {abs(c):.3g} N.m at '
                'most: gravity on an offset mass that turns with the shaft, or a spring')
    if reg == 'velocity':
        return (f'a torque proportional to speed, {c:+.3g} N.m.s/rad: '
                + ('more viscous damping than the model has' if c < 0 else
                   'less viscous damping than the model has'))
    if reg == 'sign_velocity':
        return (f'a torque of {abs(c):.3g} N.m that {"opposes" if c < 0 else "aids"} the '
                'motion: ' + ('more Coulomb friction than the model has' if c < 0 else
                              'less Coulomb friction than the model has'))
    if reg == 'pressure_difference':
        share = c / (core['piston_area_m2'] * core['pinion_pitch_diameter_m'])
        return (f'a torque that grows with p_a - p_b, {100 * share:+.1f} % of the piston '
                'torque: the effective piston area or pinion diameter is off by that share')
    if reg in ('p_a', 'p_b'):
        return (f'a torque that grows with {reg}, {c:+.3g} N.m/Pa: the two pistons (or '
                'chambers) do not push with the same effective area')
    if reg.startswith('window_'):
        return (f'a torque of {c:+.3g} N.m only over part of the stroke, {_part(reg, core)}: '
                'a local load, a rough or worn stretch of the track, or a soft stop')
    if reg == 'sign_velocity_times_mean_pressure':
        return (f'a friction that grows with the chambers\' pressure, {1e5 * abs(c):.3g} N.m '
                'per bar above atmosphere, ' + ('opposing' if c < 0 else 'aiding')
                + ' the motion: seals pressed harder as the pressure rises')
    if reg == 'sign_velocity_times_pressure_difference':
        return (f'a friction that grows with the load p_a - p_b, {1e5 * abs(c):.3g} N.m per '
                'bar: gear or bearing friction under load')
    if reg == 'sign_velocity_times_abs_pressure_difference':
        return (f'a friction that grows with the load |p_a - p_b| whichever way it pushes, '
                f'{1e5 * abs(c):.3g} N.m per bar, ' + ('opposing' if c < 0 else 'aiding')
                + ' the motion: gears or bearings loaded by the pressure difference')
    return f'a torque that follows the {DESCRIPTION[reg]}, {c:+.3g} per unit'


def _mass(chamber: str, reg: str, c: float, terms: dict, core: dict) -> str:
    into = 'into' if c > 0 else 'out of'
    if reg == 'constant':
        return (f'a steady flow of {abs(c) * 1e3:.3g} g/s {into} chamber {chamber}: a leak '
                + ('from the supply' if c > 0 else 'to atmosphere') + ' at a steady rate')
    if reg in (f'p_{chamber}', f'sqrt_drop_{chamber}') and c < 0:
        return (f'a flow out of chamber {chamber} that grows with its pressure: a leak from '
                f'chamber {chamber} to atmosphere (a fitting, a rod seal)')
    if reg == 'supply' and c > 0:
        return (f'a flow from the supply into chamber {chamber}: the valve leaks from its '
                f'supply port into the {chamber} side (a worn land or seal)')
    if reg in ('pressure_difference', 'sqrt_pressure_difference'):
        sign = c if chamber == 'b' else -c
        return ('a flow between the chambers that grows with their pressure difference: a '
                'leak across the pistons' if sign > 0 else
                f'a flow {into} chamber {chamber} against the pressure difference')
    if reg in ('command', 'abs_command', 'sign_command'):
        return (f'a flow {into} chamber {chamber} that follows the valve command: the '
                f'valve\'s flow gain on the {chamber} side differs from the model\'s')
    if reg == 'velocity':
        return (f'a flow that follows the shaft speed: the swept volume of chamber {chamber} '
                'differs from the model\'s (piston area or pinion)')
    if reg in ('angle', 'sin_angle', 'cos_angle'):
        return (f'a flow {into} chamber {chamber} that changes with angle: a leak that opens '
                'over part of the stroke')
    if reg.startswith('sqrt_pressure_difference_in_window_'):
        return ('a leak between the chambers that exists only ' + _part(reg, core)
                + ': wear of the housing or vane seal over part of the stroke')
    if reg == 'command_direction':
        return (f'a flow {into} chamber {chamber} that depends on the direction the command '
                'last moved in: hysteresis of the valve')
    return f'a flow {into} chamber {chamber} that follows the {DESCRIPTION[reg]}'


def _valve(reg: str, c: float, terms: dict, core: dict) -> str:
    if reg == 'constant':
        return (f'the valve acts as if the command were {c:+.3g} V off: its null is offset')
    if reg == 'command':
        return f'the valve\'s gain around its null differs by {100 * c:+.1f} %'
    if reg == 'sign_command':
        return (f'a step of {abs(c):.3g} V at the valve centre: a nonlinearity of the valve '
                'around its null (' + ('a dead band: spool overlap' if c < 0 else
                                      'a jump: spool underlap') + ')')
    if reg == 'abs_command':
        return ('the valve opens differently to either side of its null: an asymmetry of '
                'the valve around its centre')
    if reg == 'command_direction':
        return (f'the valve acts as if the command were {abs(c):.3g} V '
                + ('behind' if c < 0 else 'ahead of') + ' it in the direction it last moved: '
                f'hysteresis of the proportional solenoid, a band of about {2 * abs(c):.3g} V')
    if reg in ('p_a', 'p_b', 'supply', 'pressure_difference'):
        return (f'the valve\'s effective opening follows the {DESCRIPTION[reg]}: flow forces '
                'on the spool, or a pressure-dependent driver')
    return f'an extra valve command that follows the {DESCRIPTION[reg]}'


def _heat(chamber: str, reg: str, c: float) -> str:
    into = 'into' if c > 0 else 'out of'
    if reg == 'constant':
        return (f'a steady heat flow of {abs(c):.3g} W {into} chamber {chamber}: a heat source '
                'or sink on its wall (a warm valve or motor, a cold mounting plate)')
    if reg == f'wall_minus_t_{chamber}':
        more, larger = ('more', 'larger') if c > 0 else ('less', 'smaller')
        return (f'{more} heat through the wall of chamber {chamber} than the model has, '
                f'{c:+.3g} W/K: its heat transfer coefficient or wall area is {larger}')
    return f'a heat flow {into} chamber {chamber} that follows the {DESCRIPTION[reg]}'


def _temperature(chamber: str, reg: str, c: float) -> str:
    if reg == 'constant':
        return f'the chamber {chamber} temperature reads {c:+.3g} K off: a sensor offset'
    if reg == f't_{chamber}':
        return f'the chamber {chamber} temperature sensor\'s gain is off by {100 * c:+.2f} %'
    if reg == f'rate_t_{chamber}':
        return (f'the chamber {chamber} temperature reads {1e3 * abs(c):.3g} ms '
                + ('late: the sensor\'s own time constant (a thermocouple in its sheath)'
                   if c < 0 else 'early: a timing error of the sensor'))
    return f'an error of the chamber {chamber} temperature reading that follows the ' \
        f'{DESCRIPTION[reg]}'


def _lagging(what: str, cause: str, lag_ms: float | None) -> str:
    """'the <what> reads through a lag of about N ms: <cause>', with ``lag_ms`` the one
    first-order lag closest to the correction over the record (without it, no number)."""
    if lag_ms is None:
        return f'the {what} reads through a lag: {cause}'
    return (f'the {what} reads through a lag of about {abs(lag_ms):.2g} ms'
            + (f' (the one lag closest to its lag terms): {cause}' if lag_ms > 0 else
               ' ahead: a timing error of the sensor'))


def _measurement(signal: str, reg: str, c: float, terms: dict, core: dict,
                 lag_ms: float | None = None) -> str:
    if signal == 'angle':
        if reg == 'constant':
            return f'the angle sensor reads {math.degrees(c):+.3g} deg off: an encoder zero offset'
        if reg == 'angle':
            return f'the angle sensor\'s scale is off by {100 * c:+.2f} %'
        if reg == 'velocity':
            return (f'the angle reading is {1e3 * abs(c):.3g} ms '
                    f'{"early" if c > 0 else "late"}: a timing error of the angle sensor')
        if reg == 'motion_direction':
            return (f'the angle reading {"lags" if c < 0 else "leads"} the shaft by '
                    f'{math.degrees(abs(c)):.2g} deg in the direction it last moved: play '
                    f'(backlash) of about {math.degrees(2 * abs(c)):.2g} deg between shaft '
                    'and encoder')
        if reg.startswith('window_'):
            return (f'the angle reads {math.degrees(c):+.2g} deg off {_part(reg, core)} only: '
                    'a nonlinearity of the angle sensor')
        return f'an error of the angle reading that follows the {DESCRIPTION[reg]}'
    if signal == 'supply':
        if reg == 'constant':
            return (f'the supply transmitter reads {c / 1e3:+.3g} kPa off, and the model is '
                    'fed that reading: a transmitter offset')
        if reg == 'supply':
            return f'the supply transmitter\'s gain is off by {100 * c:+.2f} %'
        return (f'an error of the supply reading that follows the {DESCRIPTION[reg]}')
    chamber = signal[-1]
    if signal.startswith('t_'):
        return _temperature(chamber, reg, c)
    if reg == 'constant':
        return (f'chamber {chamber} pressure reads {c / 1e3:+.3g} kPa off: a transmitter '
                'offset (a gauge reading would be about -101 kPa)')
    if reg == f'p_{chamber}':
        return f'the chamber {chamber} transmitter\'s gain is off by {100 * c:+.2f} %'
    if reg.startswith('lag_'):
        return _lagging(f'chamber {chamber} pressure',
                        'a lag of the transmitter or of the line to it', lag_ms)
    if reg == f'rate_p_{chamber}':
        return (f'the chamber {chamber} pressure reads {1e3 * abs(c):.3g} ms '
                + ('late: a lag of the transmitter or of the line to it' if c < 0 else
                   'early: a timing error of the transmitter'))
    return (f'an error of the chamber {chamber} pressure reading that follows the '
            f'{DESCRIPTION[reg]}: crosstalk or a wiring fault')


def interpret(equation: str, terms: dict[str, float], config: ModelConfig,
              shares: dict[str, float] | None = None, lag_ms: float | None = None) -> str:
    """One sentence on a correction of ``equation`` with ``terms`` (regressor -> coefficient,
    SI): what it is, after its leading term (:func:`leading`, with the terms' ``shares`` of
    its variation along the record where known), and the physics that usually causes it;
    a sensor error is called one, never a change of the physics. ``lag_ms``: the time
    constant of a reading's lag terms over the record (``discovery.equivalent_lag_ms``)."""
    if not terms:
        return 'no term'
    reg = leading(terms, shares)
    c, core = terms[reg], config.core
    if equation == 'moment_balance':
        text = _moment(reg, c, terms, core)
    elif equation.startswith('mass_balance_'):
        text = _mass(equation[-1], reg, c, terms, core)
    elif equation == 'valve_input':
        text = _valve(reg, c, terms, core)
    elif equation.startswith('energy_balance_'):
        text = _heat(equation[-1], reg, c)
    else:
        text = 'a sensor error, not missing physics: ' + _measurement(
            equation.removeprefix('measurement_'), reg, c, terms, core, lag_ms)
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
