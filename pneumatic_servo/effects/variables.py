"""The variables the vocabulary's expressions use (:mod:`.terms`): how a compiled hook reads
each, how a record's arrays give it, and the constants of the operators over them (the
plays of the command and of the shaft, the lags of a reading, the spans of the free
functions that probe a dependence).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .base import Param, State
from .bases import hat, knot, signed_sqrt, window
from .operators import direction, lag, rate

#: [V] width of the play whose output gives the direction the command last moved in
COMMAND_PLAY_V = 0.05
#: [rad] width of the play whose output gives the direction the shaft last moved in
MOTION_PLAY_RAD = 0.004
#: [rad/s] the shaft speeds a free function of the speed spans where no record sets its span
#: (:data:`PROBE_SPANS`' default; a record's steps can reach +-38 rad/s)
PROBE_SPEED_RAD_S = 4.0
#: [s] time constants of the first-order lags a reading is offered through: a pressure
#: transmitter on a short line and on a long thin one. A coefficient c on a lag of tau is,
#: to first order, a lag of c tau; a lag as fast as the record's steps is far from its
#: first-order rate there, and such a term writes it. (Not the gas temperatures: a
#: thermocouple's 60 ms lag on a blocked record fitted as 114 ms, each window starting
#: from the lagged reading; their rate reads it right, if it explains less)
LAGS_S = {'p_a': (0.005, 0.02), 'p_b': (0.005, 0.02)}
#: the signal each lagged reading is of, a typical rate of change [unit/s] and the unit
READINGS = {'p_a': ('p_a_pa', 2e6, 'Pa'), 'p_b': ('p_b_pa', 2e6, 'Pa')}

#: the variables a correction's dependence is probed on: (variable, words, SI unit, the span
#: a free function of it covers where no record gives one [low, high]). The dependence test
#: sets the span from the record (:data:`PROBE_SPANS`): five knots over the 600 kPa from
#: atmosphere to the supply are a straight line over a chirp's 35 kPa
PROBED = (('angle', 'the shaft angle', 'rad', (0.0, 3.3)),
          ('velocity', 'the shaft speed', 'rad/s', (-PROBE_SPEED_RAD_S, PROBE_SPEED_RAD_S)),
          ('p_a', 'the chamber a pressure', 'Pa', (101325.0, 701325.0)),
          ('p_b', 'the chamber b pressure', 'Pa', (101325.0, 701325.0)),
          ('command', 'the valve command', 'V', (-5.0, 5.0)))


def _atmosphere_to_supply(core: dict) -> tuple[float, float]:
    """[Pa] the range a chamber pressure can take on a rig with ``core``."""
    return core['atmospheric_pressure_pa'], core['supply_pressure_pa']


#: the range [SI] (low, high) over which a rig can move each probed variable, from its core
#: parameters: the stroke, atmosphere to the supply, and the valve's 0-10 V input (the
#: output gate's clamp) about its null; the speed has none (the valve's flow limits it, not
#: a parameter). A dependence test over a small share of it tested little (``dependence``)
RIG_RANGES = {
    'angle': lambda core: (0.0, core['stroke_rad']),
    'p_a': _atmosphere_to_supply, 'p_b': _atmosphere_to_supply,
    'command': lambda core: (-core['valve_null_voltage_v'], 10.0 - core['valve_null_voltage_v'])}
#: the span of each probed variable's free function, (low, high): fixed parameters of a
#: correction that offers its knots (:attr:`Variable.param`), named with their unit
#: (``p_a_probe_low_pa``), set per record by the dependence test
PROBE_SPANS = {v: tuple(Param(f'{v}_probe_{end}_{unit.lower().replace("/", "_")}', unit,
                              default, -1e7, 1e7, f'{end} end of the span of the free '
                              f'function of {words} [{unit}]', fit=False)
                        for end, default in zip(('low', 'high'), span))
               for v, words, unit, span in PROBED}


@dataclass(frozen=True)
class Variable:
    """A name the expressions use: how a compiled hook reads it (None: not available
    there), and how an emitted sensor error reads it from ``signals`` and ``core``."""

    name: str
    compiled: str | None
    array: str
    #: the signal it comes from; where a record lacks it, the atmosphere (a pressure), the
    #: room (a temperature) or 0
    signal: str = ''
    atmospheric: bool = False
    room: bool = False
    #: [s] the time constant of the first-order lag its signal is read through (None: none)
    lag_s: float | None = None
    #: a memory of the valve command, a state of the correction that uses it: what the
    #: state is (:class:`.base.State`) and the rate [V/s] at which it follows the command,
    #: an expression of ``{m}`` (the state's value) like :attr:`compiled`; the state starts
    #: at the command
    memory: 'State | None' = None
    follows: str = ''
    #: a fixed parameter of the correction that uses it (the span of a free function): a
    #: compiled hook reads it from its parameters (``{m}``: ``p[i]``), an array from the
    #: correction's values, else its default
    param: 'Param | None' = None

    def compiled_at(self, state: str) -> str | None:
        """Its compiled expression with its memory held in ``state`` (``x[s + i]``)."""
        return None if self.compiled is None else self.compiled.format(m=state)


VARIABLES = (
    Variable('angle', 'x[THETA]', "signals['angle_rad']", 'angle_rad'),
    Variable('velocity', 'x[OMEGA]', "signals['velocity_rad_s']", 'velocity_rad_s'),
    Variable('p_a', 'x[P_A]', "signals['p_a_pa']", 'p_a_pa', True),
    Variable('p_b', 'x[P_B]', "signals['p_b_pa']", 'p_b_pa', True),
    Variable('p_atm', 'c[C_PE]', "core['atmospheric_pressure_pa']"),
    Variable('command', '(c[C_U] - P[K_NULL])',
             "signals['command_v'] - core['valve_null_voltage_v']", 'command_v'),
    Variable('supply', 'c[C_PS]', "signals['supply_pa']", 'supply_pa', True),
    Variable('stroke', 'P[K_STROKE]', "core['stroke_rad']"),
    Variable('command_direction', 'memory_direction(c[C_U] - {m}, COMMAND_PLAY_V)',
             "direction(signals['command_v'], COMMAND_PLAY_V)", 'command_v',
             memory=State('command_memory_v', 'V', 1e-3, 'the command as last left by its '
                          'play (the memory of the direction it moved in)'),
             follows='memory_rate(c[C_U] - {m}, COMMAND_PLAY_V)'),
    Variable('motion_direction', None, "direction(signals['angle_rad'], MOTION_PLAY_RAD)",
             'angle_rad'),
    Variable('p_a_rate', None, "rate(signals['p_a_pa'], signals.get('t_s'))", 'p_a_pa'),
    Variable('p_b_rate', None, "rate(signals['p_b_pa'], signals.get('t_s'))", 'p_b_pa'),
    *(Variable(f'{v}_lag_{1e3 * tau:.0f}ms', None,
               f"lag(signals['{READINGS[v][0]}'], signals.get('t_s'), {tau})",
               READINGS[v][0], True, lag_s=tau)
      for v, taus in LAGS_S.items() for tau in taus),
    # the gas temperatures, where a record holds them (the energy balances)
    Variable('t_a', 'x[T_A]', "signals['t_a_k']", 't_a_k', room=True),
    Variable('t_b', 'x[T_B]', "signals['t_b_k']", 't_b_k', room=True),
    Variable('t_wall', 'c[C_TE]', "core['room_temperature_k']"),
    Variable('t_a_rate', None, "rate(signals['t_a_k'], signals.get('t_s'))", 't_a_k'),
    Variable('t_b_rate', None, "rate(signals['t_b_k'], signals.get('t_s'))", 't_b_k'),
    *(Variable(p.name, '{m}', f"params.get('{p.name}', {p.default!r})", param=p)
      for span in PROBE_SPANS.values() for p in span),
)
BY_VARIABLE = {v.name: v for v in VARIABLES}


def array_namespace(signals: dict, core: dict, variables, params: dict | None = None
                     ) -> dict:
    """``variables`` as arrays over a record (``signals`` [SI]; a missing one at its
    default; a fixed parameter from the correction's ``params``), with the functions the
    expressions call."""
    n = len(next(iter(signals.values())))
    ns = {'np': np, 'signed_sqrt': signed_sqrt, 'window': window, 'direction': direction,
          'rate': rate, 'lag': lag, 'hat': hat, 'knot': knot,
          'COMMAND_PLAY_V': COMMAND_PLAY_V, 'MOTION_PLAY_RAD': MOTION_PLAY_RAD,
          'signals': signals, 'core': core, 'params': params or {}}
    ns['p_atm'] = float(core['atmospheric_pressure_pa'])
    for v in variables:
        if v.signal and v.signal not in signals:
            ns[v.name] = np.full(n, ns['p_atm'] if v.atmospheric else
                                 float(core['room_temperature_k']) if v.room else 0.0)
        elif v.name != 'p_atm':
            ns[v.name] = np.asarray(eval(v.array, ns), dtype=float)  # noqa: S307 - our text
    return ns


#: [1] the share of a record's samples a probed variable's span leaves out at each end:
#: none, as beyond its ends a free function holds, and a speed proxy with its extremes held
#: needed another variable to make up for them (the signals are smoothed; no outliers)
PROBE_SPAN_TAIL = 0.0


def apart_span(records: list[dict], core: dict, variable: str, given: list[str]
               ) -> float | None:
    """[SI] How far ``records`` (as :func:`probe_spans` takes them) moved probed ``variable``
    apart from the probed variables ``given``: the span of what is left of it after its
    least-squares fit on a cubic in each of them, over the records together; without
    ``given``, its span. None where no record holds it.

    Why: with a four-way valve p_a mirrors p_b through a sine, and records that move p_a
    only with p_b cannot tell a correction of one from a correction of the other, however
    far both moved."""
    names = [variable, *(g for g in given if g in PROBE_SPANS and g != variable)]
    used = [BY_VARIABLE[n] for n in names]
    held = [r for r in records if used[0].signal in r]
    if not held:
        return None
    spaces = [array_namespace(r, core, used) for r in held]
    columns = [np.concatenate([ns[n] for ns in spaces]) for n in names]
    rows = np.all(np.isfinite(columns), axis=0)
    values = columns[0][rows]
    if not len(values):
        return None
    left = values
    if len(names) > 1:
        # standardised before the powers, so that the fit is conditioned alike in Pa and rad
        z = [(c[rows] - c[rows].mean()) / (c[rows].std() or 1.0) for c in columns[1:]]
        basis = np.column_stack([np.ones(len(left)), *(zi ** k for zi in z for k in (1, 2, 3))])
        left = values - basis @ np.linalg.lstsq(basis, values, rcond=None)[0]
    # at most its own span: what a fit leaves can reach further than the values did
    return float(min(np.ptp(np.quantile(v, (PROBE_SPAN_TAIL, 1.0 - PROBE_SPAN_TAIL)))
                     for v in (values, left)))


def probe_spans(records: list[dict], core: dict) -> dict[str, float]:
    """The span parameters (:data:`PROBE_SPANS`) of each probed variable over ``records``
    (each a record's ``signals`` [SI], as :func:`.terms.term_values` takes them): from its
    :data:`PROBE_SPAN_TAIL` to its 1 - :data:`PROBE_SPAN_TAIL` quantile, where the records
    hold it."""
    out = {}
    for v, (low, high) in PROBE_SPANS.items():
        variable = BY_VARIABLE[v]
        held = [r for r in records if variable.signal in r]
        if not held:
            continue
        values = np.concatenate([array_namespace(r, core, [variable])[v] for r in held])
        values = values[np.isfinite(values)]
        if len(values):
            out[low.name], out[high.name] = np.quantile(
                values, (PROBE_SPAN_TAIL, 1.0 - PROBE_SPAN_TAIL)).tolist()
    return out
