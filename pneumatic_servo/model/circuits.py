"""The paper's four test circuits, and the steady states of the static ones.

=============  ======================================================  ===========
circuit        what is connected                                       paper
=============  ======================================================  ===========
``servo``      valve and actuator, shaft free between its end stops    Fig. 1
``blocked``    valve and actuator, pistons held at ``blocked_angle``   Figs 12, 21
``closed_port`` valve chamber a alone, ports 2, 3 and 4 closed          Table 5
``flow``       valve chamber a alone, port 4 vented through the        Fig. 10
               flow meter (``core.flow_outlet_area_m2``)
=============  ======================================================  ===========

In the two static circuits only chamber a (the valve chamber, volume
``core.valve_chamber_volume_m3``) has dynamics; its steady state is where
the net mass inflow is zero: supply -> a through the metering orifice
(Eq. 8) or the clearance (Eq. 24), a -> port 5 through the clearance
(Eq. 17) or the orifice (Eq. 22), and in the flow circuit a -> port 4
through the flow meter. :func:`steady_closed_port` and :func:`steady_flow`
find it with ``scipy.optimize.brentq`` on p_a; the gas temperature, and the
states of any added effect, are then settled as described in
:func:`steady_state`. The core holds chamber b still; the set-ups put it at
supply pressure and temperature, where a valve chamber with ports 2 and 3
closed ends up, so that it draws no supply air (this matters for the
supply mass flow and for ``supply_pressure_drop``).

Any circuit is simulated in time by ``simulate(..., circuit=...)``; the paper's experiments
in time (charge/discharge, the 2 Hz sine, a static circuit settling) are runs of
:mod:`pneumatic_servo.synth.runs`. All pressures are absolute [Pa]; the paper's supply
pressures are gauge readings (docs/model.md, section 1), see :func:`gauge_supply_pa`.
"""
from __future__ import annotations

import math

import numpy as np

from ..effects.layout import (
    C_ISOTHERMAL,
    C_M4,
    C_M5,
    C_MA,
    C_MSUP,
    CIRCUITS,
    N_CORE_STATES,
    P_A,
    P_B,
    T_A,
    T_B,
)
from ..errors import EffectError, SimulationError
from .assembly import Model
from .config import ModelConfig
from .simulate import as_model, initial_state

#: supply pressure of the paper's charge/discharge and servo tests [Pa, gauge]
PAPER_SUPPLY_GAUGE_PA = 0.6e6
#: supply pressures of the paper's flow-rate verification (Figs 19-20, Table 5) [Pa, gauge]
PAPER_FLOW_SUPPLIES_GAUGE_PA = (0.5e6, 0.7e6, 0.83e6)
#: drive voltages of Table 5 [V]
PAPER_TABLE5_VOLTAGES_V = (5.0, 5.1, 5.3, 5.5, 5.75, 6.0, 6.5, 7.0, 8.0, 9.0, 10.0)
STATIC_CIRCUITS = ('closed_port', 'flow', 'blocked')

_MAX_OUTER = 40  # p_a / T_a alternations when T_s differs from T_e


# ----------------------------------------------------------------------------- helpers
def gauge_supply_pa(gauge_pa: float, config: ModelConfig | None = None) -> float:
    """Absolute supply pressure [Pa] for a gauge reading ``gauge_pa`` [Pa, gauge]."""
    cfg = config or ModelConfig.paper()
    return float(gauge_pa) + cfg.core['atmospheric_pressure_pa']


def _net_inflow(model, P, x, voltage_v, supply_pa, circuit, p, chamber=0):
    """Net mass inflow [kg/s] into a chamber (0 = a, 1 = b) with its pressure set to ``p``."""
    x = x.copy()
    x[P_A + chamber] = p
    return model.evaluate(x, voltage_v, supply_pa, circuit, params=P)[0][C_MA + chamber]


def _solve_pressure(model, P, x, voltage_v, supply_pa, circuit, pe, chamber=0) -> float:
    """A chamber's pressure [Pa] where its net inflow is zero, by brentq between p_e and p_s.

    Every source in the static circuits is at supply or atmospheric
    pressure, so the root lies between them; the bracket is widened only
    for user effects that break this.
    """
    f = (lambda p: _net_inflow(model, P, x, voltage_v, supply_pa, circuit, p, chamber))
    lo, hi = min(pe, supply_pa), max(pe, supply_pa)
    f_lo, f_hi = f(lo), f(hi)
    for _ in range(8):
        if f_lo * f_hi <= 0.0:
            break
        lo, hi = 0.5 * lo, 2.0 * hi
        f_lo, f_hi = f(lo), f(hi)
    else:
        raise SimulationError(f'no steady chamber-a pressure between {lo:.6g} and {hi:.6g} Pa '
                              f'at {voltage_v:g} V; check the model parameters')
    # converged to rounding: near pressure ratio 1 the flow is steep in p_a
    from scipy.optimize import brentq  # 0.16 s of import: only static circuits need it
    return brentq(f, lo, hi, xtol=1e-9, rtol=4 * np.finfo(float).eps, maxiter=500)


def _solve_temperature(model, P, x, voltage_v, supply_pa, circuit, temps) -> float:
    """T_a [K] where dT_a/dt = 0 at the current p_a, or the current T_a if none is bracketed."""
    def g(temp):
        xt = x.copy()
        xt[T_A] = temp
        return model.evaluate(xt, voltage_v, supply_pa, circuit, params=P)[1][T_A]
    lo, hi = min(temps) - 1.0, max(temps) + 1.0
    g_lo, g_hi = g(lo), g(hi)
    if g_lo * g_hi > 0.0:
        return x[T_A]
    from scipy.optimize import brentq
    return brentq(g, lo, hi, xtol=1e-10, maxiter=200)


def _settle_chamber(model, P, x, voltage_v, supply_pa, circuit, pe, temps, fixed_t) -> None:
    """Set p_a (and, unless ``fixed_t``, T_a) of ``x`` in place to zero net flow and heat."""
    for _ in range(_MAX_OUTER):
        x[P_A] = _solve_pressure(model, P, x, voltage_v, supply_pa, circuit, pe)
        if fixed_t:
            return
        t_new = _solve_temperature(model, P, x, voltage_v, supply_pa, circuit, temps)
        if abs(t_new - x[T_A]) < 1e-9:
            return
        x[T_A] = t_new


def _settle_both(model, P, x, voltage_v, supply_pa, circuit, pe, rounds: int = 4) -> None:
    """Pistons held: each chamber's pressure to zero net inflow in turn (they couple only
    through effects such as a seal leak, so a few alternations settle them)."""
    for _ in range(rounds):
        for chamber in (0, 1):
            x[P_A + chamber] = _solve_pressure(model, P, x, voltage_v, supply_pa, circuit, pe,
                                               chamber)


def _free_states(model: Model, isothermal: bool, chambers: int = 1) -> list[int]:
    """Indices of the states that evolve in a static circuit: the chambers' pressures and
    temperatures (chamber a; both in the blocked circuit) and effect states."""
    core = [P_A, P_B][:chambers] + ([] if isothermal else [T_A, T_B][:chambers])
    return core + list(range(N_CORE_STATES, model.n_states))


def _polish(model, P, x, voltage_v, supply_pa, circuit, free) -> np.ndarray:
    """Newton-type solve of dx/dt = 0 over ``free`` states, started from ``x``."""
    scale = np.maximum(np.abs(x[free]), model.abs_tol[free] * 1e3)

    def resid(z):
        xt = x.copy()
        xt[free] = z * scale
        return model.evaluate(xt, voltage_v, supply_pa, circuit, params=P)[1][free] / scale

    from scipy.optimize import root
    sol = root(resid, x[free] / scale, method='hybr', options={'xtol': 1e-12})
    out = x.copy()
    out[free] = sol.x * scale
    return out


def _is_steady(dx: np.ndarray, x: np.ndarray, free: list[int]) -> bool:
    """True if every free state changes by less than 1e-9 of its size per second."""
    return bool(np.all(np.abs(dx[free]) <= 1e-9 * np.maximum(np.abs(x[free]), 1e-6) + 1e-12))


# ----------------------------------------------------------------------- steady states
def steady_state(model=None, circuit: str = 'closed_port', voltage_v: float = 5.0,
                 supply_pa: float | None = None, config: ModelConfig | None = None
                 ) -> np.ndarray:
    """Full steady state vector of a static circuit at a held valve voltage.

    Parameters
    ----------
    model : Model, ModelConfig or None
        The model (None: the paper's).
    circuit : str
        'closed_port', 'flow', or 'blocked' (pistons held: both chambers settle).
    voltage_v : float [V]
        Valve command, held.
    supply_pa : float [Pa, absolute]
        Supply pressure (default: the config's).
    config : ModelConfig, optional
        Parameter values for the same composition (no recompilation).

    Returns
    -------
    numpy.ndarray
        State vector with chamber a at its steady pressure [Pa] and temperature [K].

    Notes
    -----
    p_a is found by ``brentq`` on the net inflow between p_e and p_s. When
    T_s = T_e (the paper's case) the steady temperature is exactly T_s in
    every thermal variant: inflow brings T_s, outflow takes T_a, the wall is
    at T_e, and at zero net flow the energy balance
    c_p (T_s - T_a) m_in + h S (T_e - T_a) = 0 holds only at T_a = T_s. Otherwise
    p_a and T_a are settled alternately, each by ``brentq``. States of
    added effects (spool position, valve supply pressure, ...) and any
    remaining coupling are then settled together by ``scipy.optimize.root``.
    """
    model = as_model(model)
    cfg = config or model.config
    if circuit not in STATIC_CIRCUITS:
        raise SimulationError(f'no steady-state solver for circuit {circuit!r}; use '
                              f'{" or ".join(STATIC_CIRCUITS)} (simulate the others in time)')
    core = cfg.core
    ps = core['supply_pressure_pa'] if supply_pa is None else float(supply_pa)
    if not (math.isfinite(ps) and ps > 0.0 and math.isfinite(voltage_v)):
        raise SimulationError('supply pressure must be a finite absolute pressure [Pa] > 0 and '
                              'the voltage finite')
    cid = CIRCUITS[circuit]
    P = model.param_vector(cfg)
    pe, ts, te = (core['atmospheric_pressure_pa'], core['supply_temperature_k'],
                  core['room_temperature_k'])
    blocked = circuit == 'blocked'
    x = initial_state(model, p_b_pa=None if blocked else ps, t_b_k=ts, command_v=voltage_v,
                      supply_pa=ps, config=cfg, circuit=circuit)
    x[T_A] = ts
    isothermal = model.evaluate(x, voltage_v, ps, cid, params=P)[0][C_ISOTHERMAL] > 0.5
    if isothermal:
        x[T_A] = x[T_B] = te  # an isothermal chamber keeps the room temperature it starts at
    free = _free_states(model, isothermal, 2 if blocked else 1)
    if blocked:
        _settle_both(model, P, x, voltage_v, ps, cid, pe)
        x = _polish(model, P, x, voltage_v, ps, cid, free)
    else:
        _settle_chamber(model, P, x, voltage_v, ps, cid, pe, (ts, te),
                        fixed_t=isothermal or ts == te)
    if model.n_states == N_CORE_STATES and not blocked:
        # brentq's root is final: where Eq. 8 jumps at p_d/p_u = b the net flow can change
        # sign without passing zero, and the chamber then rests at the jump
        return x
    dx = model.evaluate(x, voltage_v, ps, cid, params=P)[1]
    if not _is_steady(dx, x, free):
        x = _polish(model, P, x, voltage_v, ps, cid, free)
        dx = model.evaluate(x, voltage_v, ps, cid, params=P)[1]
        if not (np.all(np.isfinite(x)) and _is_steady(dx * 1e-3, x, free)):
            raise SimulationError(f'no steady state found for the {circuit} circuit at '
                                  f'{voltage_v:g} V, {ps:.6g} Pa; simulate it in time instead')
    return x


def steady_closed_port(model=None, voltage_v: float = 5.0, supply_pa: float | None = None,
                       config: ModelConfig | None = None) -> float:
    """Steady valve-chamber pressure p_a [Pa, absolute] with ports 2, 3, 4 closed (Table 5).

    Parameters
    ----------
    model : Model, ModelConfig or None
        The model (None: the paper's).
    voltage_v : float [V]
        Valve command.
    supply_pa : float [Pa, absolute]
        Supply pressure (default: the config's).
    config : ModelConfig, optional
        Parameter values for the same composition.

    Returns
    -------
    float
        p_a [Pa, absolute] where supply inflow equals exhaust outflow.
    """
    return float(steady_state(model, 'closed_port', voltage_v, supply_pa, config)[P_A])


def steady_flow(model=None, voltage_v: float = 5.0, supply_pa: float | None = None,
                config: ModelConfig | None = None) -> tuple[float, float, float]:
    """Steady flow-rate test of Fig. 10: port 4 vented through the flow meter.

    Parameters are those of :func:`steady_closed_port`.

    Returns
    -------
    (p_a, m4, m5) : tuple of float
        Valve chamber pressure [Pa, absolute], mass flow out of port 4 [kg/s]
        and out of exhaust port 5 [kg/s]. At steady state the supply inflow
        equals m4 + m5 (the basis of Eq. 38).
    """
    model = as_model(model)
    cfg = config or model.config
    x = steady_state(model, 'flow', voltage_v, supply_pa, cfg)
    ps = cfg.core['supply_pressure_pa'] if supply_pa is None else supply_pa
    c, _ = model.evaluate(x, voltage_v, ps, 'flow', params=model.param_vector(cfg))
    return float(x[P_A]), float(c[C_M4]), float(c[C_M5])


def steady_outputs(model=None, circuit: str = 'closed_port', voltage_v: float = 5.0,
                   supply_pa: float | None = None, config: ModelConfig | None = None
                   ) -> dict[str, float]:
    """Steady p_a, p_b [Pa], T_a, T_b [K], m4 and m5 and the supply mass flow [kg/s] of a
    static circuit (p_b and T_b: the blocked circuit's chamber b; the valve's dead end in the
    others)."""
    model = as_model(model)
    cfg = config or model.config
    ps = cfg.core['supply_pressure_pa'] if supply_pa is None else supply_pa
    x = steady_state(model, circuit, voltage_v, ps, cfg)
    c, _ = model.evaluate(x, voltage_v, ps, circuit, params=model.param_vector(cfg))
    return {'p_a_pa': float(x[P_A]), 't_a_k': float(x[T_A]), 'p_b_pa': float(x[P_B]),
            't_b_k': float(x[T_B]), 'm4_kg_s': float(c[C_M4]), 'm5_kg_s': float(c[C_M5]),
            'supply_mass_flow_kg_s': float(c[C_MSUP])}


def predict_static(model, exp, config: ModelConfig | None = None) -> dict[str, np.ndarray]:
    """Steady outputs for each row of a static experiment (closed_port, flow or blocked CSV
    table).

    Each row's ``command_v`` [V] and ``supply_pa`` [Pa abs] set the operating
    point; a measured supply temperature ``t_s_k`` [K] replaces the config's.
    Returns signal -> array over the rows: ``p_a_pa``, ``t_a_k``, ``m4_kg_s``,
    ``m5_kg_s``, and ``p_b_pa``, ``t_b_k`` for the blocked circuit (both
    chambers). A row without a steady state gets NaN.
    """
    model = as_model(model)
    cfg = config or model.config
    if exp.circuit not in STATIC_CIRCUITS:
        raise SimulationError(f'{exp.name}: a static table must be a closed_port, flow or '
                              f'blocked test, not {exp.circuit!r}')
    n = len(exp.t)
    volts = exp['command_v']
    supplies = exp.signals.get('supply_pa', np.full(n, cfg.core['supply_pressure_pa']))
    temps = exp.signals.get('t_s_k')
    names = ('p_a_pa', 't_a_k', 'm4_kg_s', 'm5_kg_s')
    if exp.circuit == 'blocked':
        names += ('p_b_pa', 't_b_k')
    out = {k: np.full(n, np.nan) for k in names}
    for i in range(n):
        row_cfg = cfg
        if temps is not None and np.isfinite(temps[i]):
            row_cfg = cfg.copy()
            row_cfg.core['supply_temperature_k'] = float(temps[i])
        try:
            vals = steady_outputs(model, exp.circuit, float(volts[i]), float(supplies[i]),
                                  row_cfg)
        except EffectError:
            raise  # a component's own code failed: no row would do better
        except (SimulationError, ValueError, RuntimeError):
            continue  # a row the model cannot reach reads as a failed prediction
        for k in names:
            out[k][i] = vals[k]
    return out


__all__ = ['PAPER_SUPPLY_GAUGE_PA', 'PAPER_FLOW_SUPPLIES_GAUGE_PA', 'PAPER_TABLE5_VOLTAGES_V',
           'STATIC_CIRCUITS', 'gauge_supply_pa', 'steady_state',
           'steady_closed_port', 'steady_flow', 'steady_outputs', 'predict_static']
