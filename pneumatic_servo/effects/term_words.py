"""The words of the vocabulary's terms: what a correction led by a term is, in each kind of
equation, and the physics that usually causes it.

Each function takes a :class:`Context` and returns a sentence, or None where the term says
nothing particular there (the equation's general words are used:
:mod:`pneumatic_servo.analysis.diagnosis.interpret`). A term names its words where it is
declared (``Term.says`` in :mod:`.terms`), so that everything about a term is in one place;
the kinds are :data:`KINDS`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

#: the kinds of equation a term can speak in: the moment balance, a chamber's mass balance,
#: the valve input, a chamber's energy balance, a sensor's reading
KINDS = ('torque', 'flow', 'valve', 'heat', 'reading')


@dataclass(frozen=True)
class Context:
    """What a term's words may use: its coefficient ``c`` [SI], the correction's ``terms``
    (name -> coefficient), the rig's ``core`` parameters, the ``chamber`` of a mass or
    energy balance or a chamber's reading ('a', 'b'; '' elsewhere), the ``signal`` a
    reading is of ('angle', 'supply', 'p_a', 't_b', ...; '' in a balance), a reading's
    ``lag_ms``, the one first-order lag closest to its lag terms over the record, the
    term's own ``words`` (what it is a function of) and ``angles_deg``, the angles the
    record visits [deg]."""

    c: float
    terms: dict
    core: dict
    words: str = ''
    chamber: str = ''
    signal: str = ''
    lag_ms: float | None = None
    angles_deg: tuple[float, float] | None = None

    @property
    def into(self) -> str:
        return 'into' if self.c > 0 else 'out of'

    @property
    def pressure(self) -> bool:
        """Whether this is a chamber pressure's reading."""
        return self.signal in ('p_a', 'p_b')


def part(k: int, windows: int, x: Context) -> str:
    """Where along the stroke window ``k`` of ``windows`` acts, in degrees; where the
    record never enters it (``x.angles_deg``), that it meets only the window's tail, so
    that being confined to it is the fit's form, not something the record shows."""
    stroke = math.degrees(x.core['stroke_rad'])
    lo, hi = k * stroke / windows, (k + 1) * stroke / windows
    where = f'between about {lo:.0f} and {hi:.0f} deg'
    if x.angles_deg is None or (x.angles_deg[1] >= lo and x.angles_deg[0] <= hi):
        return where
    a, b = x.angles_deg
    return (f'{where} by the form fitted, though the record stays within {a:.0f}-{b:.0f} deg '
            'and meets only its tail (there it grows towards that part; whether it ends '
            'there the record cannot say)')


# --- the constant ---------------------------------------------------------------------------
def constant_torque(x: Context) -> str:
    return (f'a constant torque of {x.c:+.3g} N.m on the shaft: a load, a preload, or '
            'gravity on an arm held near one angle')


def constant_flow(x: Context) -> str:
    return (f'a steady flow of {abs(x.c) * 1e3:.3g} g/s {x.into} chamber {x.chamber}: a leak '
            + ('from the supply' if x.c > 0 else 'to atmosphere') + ' at a steady rate')


def constant_valve(x: Context) -> str:
    return f'the valve acts as if the command were {x.c:+.3g} V off: its null is offset'


def constant_heat(x: Context) -> str:
    return (f'a steady heat flow of {abs(x.c):.3g} W {x.into} chamber {x.chamber}: a heat '
            'source or sink on its wall (a warm valve or motor, a cold mounting plate)')


def constant_reading(x: Context) -> str | None:
    if x.signal == 'angle':
        return f'the angle sensor reads {math.degrees(x.c):+.3g} deg off: an encoder zero offset'
    if x.signal == 'supply':
        return (f'the supply transmitter reads {x.c / 1e3:+.3g} kPa off, and the model is fed '
                'that reading: a transmitter offset')
    if x.pressure:
        return (f'chamber {x.chamber} pressure reads {x.c / 1e3:+.3g} kPa off: a transmitter '
                'offset (a gauge reading would be about -101 kPa)')
    if x.signal.startswith('t_'):
        return f'the chamber {x.chamber} temperature reads {x.c:+.3g} K off: a sensor offset'
    return None


# --- the angle and its functions --------------------------------------------------------------
def angle_torque(x: Context) -> str:
    rest = -x.terms.get('constant', 0.0) / x.c
    where = f' about {rest:.2f} rad' if 'constant' in x.terms else ''
    return (f'an extra torque that {"rises" if x.c > 0 else "falls"} with angle, about '
            f'{x.c:+.3g} N.m/rad{where}: a return spring, or a gravity load on an arm')


def angle_flow(x: Context) -> str:
    return (f'a flow {x.into} chamber {x.chamber} that changes with angle: a leak that opens '
            'over part of the stroke')


def angle_reading(x: Context) -> str | None:
    return f'the angle sensor\'s scale is off by {100 * x.c:+.2f} %' \
        if x.signal == 'angle' else None


def trig_torque(trig: str):
    def words(x: Context) -> str:
        return (f'a torque that varies with the {trig} of the angle, {abs(x.c):.3g} N.m at '
                'most: gravity on an offset mass that turns with the shaft, or a spring')
    return words


def window_torque(k: int, windows: int):
    def words(x: Context) -> str:
        return (f'a torque of {x.c:+.3g} N.m only over part of the stroke, '
                f'{part(k, windows, x)}: a local load, a rough or worn stretch of the '
                'track, or a soft stop')
    return words


def window_reading(k: int, windows: int):
    def words(x: Context) -> str | None:
        return (f'the angle reads {math.degrees(x.c):+.2g} deg off {part(k, windows, x)} '
                'only: a nonlinearity of the angle sensor') if x.signal == 'angle' else None
    return words


# --- the speed ---------------------------------------------------------------------------------
def velocity_torque(x: Context) -> str:
    return (f'a torque proportional to speed, {x.c:+.3g} N.m.s/rad: '
            + ('more viscous damping than the model has' if x.c < 0 else
               'less viscous damping than the model has'))


def velocity_flow(x: Context) -> str:
    return (f'a flow that follows the shaft speed: the swept volume of chamber {x.chamber} '
            'differs from the model\'s (piston area or pinion)')


def velocity_reading(x: Context) -> str | None:
    return (f'the angle reading is {1e3 * abs(x.c):.3g} ms '
            f'{"early" if x.c > 0 else "late"}: a timing error of the angle sensor') \
        if x.signal == 'angle' else None


def coulomb_torque(x: Context) -> str:
    more = 'more' if x.c < 0 else 'less'
    return (f'a torque of {abs(x.c):.3g} N.m that {"opposes" if x.c < 0 else "aids"} the '
            f'motion: {more} Coulomb friction than the model has')


def play_reading(x: Context) -> str | None:
    if x.signal != 'angle':
        return None
    return (f'the angle reading {"lags" if x.c < 0 else "leads"} the shaft by '
            f'{math.degrees(abs(x.c)):.2g} deg in the direction it last moved: play '
            f'(backlash) of about {math.degrees(2 * abs(x.c)):.2g} deg between shaft and '
            'encoder')


# --- the pressures -----------------------------------------------------------------------------
def difference_torque(x: Context) -> str:
    share = x.c / (x.core['piston_area_m2'] * x.core['pinion_pitch_diameter_m'])
    return (f'a torque that grows with p_a - p_b, {100 * share:+.1f} % of the piston '
            'torque: the effective piston area or pinion diameter is off by that share')


def difference_flow(x: Context) -> str:
    sign = x.c if x.chamber == 'b' else -x.c
    return ('a flow between the chambers that grows with their pressure difference: a leak '
            'across the pistons' if sign > 0 else
            f'a flow {x.into} chamber {x.chamber} against the pressure difference')


def pressure_driven_valve(x: Context) -> str:
    return (f'the valve\'s effective opening follows the {x.words}: flow forces on the '
            'spool, or a pressure-dependent driver')


def chamber_torque(chamber: str):
    def words(x: Context) -> str:
        return (f'a torque that grows with p_{chamber}, {x.c:+.3g} N.m/Pa: the two pistons '
                '(or chambers) do not push with the same effective area')
    return words


def chamber_flow(chamber: str):
    """A flow out of ``chamber`` that grows with its own pressure (its pressure, or the
    orifice from it to atmosphere)."""
    def words(x: Context) -> str | None:
        if x.chamber != chamber or x.c >= 0:
            return None
        return (f'a flow out of chamber {chamber} that grows with its pressure: a leak from '
                f'chamber {chamber} to atmosphere (a fitting, a rod seal)')
    return words


def chamber_reading(chamber: str):
    def words(x: Context) -> str | None:
        return (f'the chamber {chamber} transmitter\'s gain is off by {100 * x.c:+.2f} %'
                if x.signal == f'p_{chamber}' else None)
    return words


def gauge_reading(signal: str, name: str):
    """A gain error over a gauge transmitter's span: proportional to the pressure above
    atmosphere, zero at atmosphere."""
    def words(x: Context) -> str | None:
        return (f'the {name} transmitter\'s gain over its gauge span is off by '
                f'{100 * x.c:+.2f} %' if x.signal == signal else None)
    return words


def supply_flow(x: Context) -> str | None:
    if x.c <= 0:
        return None
    return (f'a flow from the supply into chamber {x.chamber}: the valve leaks from its '
            f'supply port into the {x.chamber} side (a worn land or seal)')


def supply_reading(x: Context) -> str | None:
    return f'the supply transmitter\'s gain is off by {100 * x.c:+.2f} %' \
        if x.signal == 'supply' else None


def windowed_orifice_flow(k: int, windows: int):
    def words(x: Context) -> str:
        return ('a leak between the chambers that exists only ' + part(k, windows, x)
                + ': wear of the housing or vane seal over part of the stroke')
    return words


def windowed_vent_flow(chamber: str):
    """A leak from ``chamber`` to atmosphere over part of the stroke (per window)."""
    def by_window(k: int, windows: int):
        def words(x: Context) -> str:
            return (f'a leak {"into" if x.c > 0 else "out of"} chamber {chamber} '
                    f'{"from" if x.c > 0 else "to"} atmosphere that exists only '
                    + part(k, windows, x) + ': a scored bore or end cover, or a port '
                    'the vane uncovers there')
        return words
    return by_window


def windowed_damping_torque(k: int, windows: int):
    def words(x: Context) -> str:
        return (f'a torque proportional to speed, {x.c:+.3g} N.m.s/rad, only '
                + part(k, windows, x) + ': '
                + ('a damper, drag or linkage that acts there' if x.c < 0 else
                   'less damping there than the model has'))
    return words


def windowed_friction_torque(k: int, windows: int):
    def words(x: Context) -> str:
        return (f'a torque of {abs(x.c):.3g} N.m that {"opposes" if x.c < 0 else "aids"} '
                'the motion only ' + part(k, windows, x) + ': '
                + ('a rough, dented or tight stretch of the bore or track' if x.c < 0 else
                   'less friction there than the model has'))
    return words


# --- the valve command -------------------------------------------------------------------------
def command_flow(x: Context) -> str:
    return (f'a flow {x.into} chamber {x.chamber} that follows the valve command: the '
            f'valve\'s flow gain on the {x.chamber} side differs from the model\'s')


def command_valve(x: Context) -> str:
    return f'the valve\'s gain around its null differs by {100 * x.c:+.1f} %'


def sign_command_valve(x: Context) -> str:
    return (f'a step of {abs(x.c):.3g} V at the valve centre: a nonlinearity of the valve '
            'around its null (' + ('a dead band: spool overlap' if x.c < 0 else
                                   'a jump: spool underlap') + ')')


def abs_command_valve(x: Context) -> str:
    return ('the valve opens differently to either side of its null: an asymmetry of the '
            'valve around its centre')


def hysteresis_flow(x: Context) -> str:
    return (f'a flow {x.into} chamber {x.chamber} that depends on the direction the command '
            'last moved in: hysteresis of the valve')


def hysteresis_valve(x: Context) -> str:
    return (f'the valve acts as if the command were {abs(x.c):.3g} V '
            + ('behind' if x.c < 0 else 'ahead of') + ' it in the direction it last moved: '
            f'hysteresis of the proportional solenoid, a band of about {2 * abs(x.c):.3g} V')


# --- friction that grows with pressure ------------------------------------------------------
def pressure_friction_torque(x: Context) -> str:
    return (f'a friction that grows with the chambers\' pressure, {1e5 * abs(x.c):.3g} N.m '
            'per bar above atmosphere, ' + ('opposing' if x.c < 0 else 'aiding')
            + ' the motion: seals pressed harder as the pressure rises')


def load_friction_torque(x: Context) -> str:
    return (f'a friction that grows with the load p_a - p_b, {1e5 * abs(x.c):.3g} N.m per '
            'bar: gear or bearing friction under load')


def abs_load_friction_torque(x: Context) -> str:
    return (f'a friction that grows with the load |p_a - p_b| whichever way it pushes, '
            f'{1e5 * abs(x.c):.3g} N.m per bar, ' + ('opposing' if x.c < 0 else 'aiding')
            + ' the motion: gears or bearings loaded by the pressure difference')


# --- a sensor's dynamics --------------------------------------------------------------------
def pressure_rate_reading(x: Context) -> str:
    return (f'the chamber {x.chamber} pressure reads {1e3 * abs(x.c):.3g} ms '
            + ('late: a lag of the transmitter or of the line to it' if x.c < 0 else
               'early: a timing error of the transmitter'))


def lag_reading(x: Context) -> str:
    """'the <reading> reads through a lag of about N ms: <cause>', the time constant the
    one lag closest to the correction over the record (without it, no number)."""
    what, cause = (f'chamber {x.chamber} pressure',
                   'a lag of the transmitter or of the line to it')
    if x.lag_ms is None:
        return f'the {what} reads through a lag: {cause}'
    return (f'the {what} reads through a lag of about {abs(x.lag_ms):.2g} ms'
            + (f' (the one lag closest to its lag terms): {cause}' if x.lag_ms > 0 else
               ' ahead: a timing error of the sensor'))


# --- the gas temperatures ---------------------------------------------------------------------
def wall_heat(x: Context) -> str:
    more, larger = ('more', 'larger') if x.c > 0 else ('less', 'smaller')
    return (f'{more} heat through the wall of chamber {x.chamber} than the model has, '
            f'{x.c:+.3g} W/K: its heat transfer coefficient or wall area is {larger}')


def temperature_reading(x: Context) -> str:
    return f'the chamber {x.chamber} temperature sensor\'s gain is off by {100 * x.c:+.2f} %'


def temperature_rate_reading(x: Context) -> str:
    return (f'the chamber {x.chamber} temperature reads {1e3 * abs(x.c):.3g} ms '
            + ('late: the sensor\'s own time constant (a thermocouple in its sheath)'
               if x.c < 0 else 'early: a timing error of the sensor'))
