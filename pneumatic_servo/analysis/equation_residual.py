"""The residual of one equation along a record, in the equation's own units: what the model
lacks there, computed from the measured signals.

* ``moment_balance`` [N.m]: J (measured angular acceleration - the model's), where the
  shaft slides and is away from the end stops;
* ``mass_balance_a``/``_b`` [kg/s]: V / (R T) (measured dp/dt - the model's), the mass flow
  the chamber's pressure rise asks for beyond the modelled flows;
* ``valve_input``, ``measurement_supply``: shown as the mass balance of chamber a (the
  valve's flow into it);
* ``measurement_*`` [rad, Pa]: the reading minus the k-step prediction.

Derivatives come from Savitzky-Golay fits of the measured signals; the gas temperature from
the prediction where it has one, else the room's. A view for the report, not a fit.
"""
from __future__ import annotations

import numpy as np

from ..effects.corrections import BY_EQUATION
from ..effects.terms import term_values
from ..effects.layout import C_INERTIA, C_R, C_VA, C_VB, N_CONTEXT, OMEGA, P_A, P_B
from ..experiment import Experiment
from ..model.assembly import Model
from ..model.config import ModelConfig
from ..model.simulate import initial_state
from ..prediction.inputs import smoothed_signals
from ..smoothing import savgol_filter

#: [s] window of the derivatives
DERIVATIVE_WINDOW_S = 0.031
#: [rad/s] the shaft slides (friction is the kinetic one) above this speed
SLIDING_RAD_S = 0.05


def _model_rates(model: Model, config: ModelConfig, exp: Experiment, sig: dict, pred: dict):
    """(angular acceleration, dp_a/dt, dp_b/dt, inertia, volume a, volume b, R) of the model
    at every measured state."""
    n = len(exp.t)
    x0 = initial_state(model, config=config, circuit=exp.circuit)
    P = model.param_vector(config)
    buffers = np.zeros(N_CONTEXT), np.zeros(model.n_states)
    out = np.zeros((n, 7))
    room = config.core['room_temperature_k']
    for k in range(n):
        x = x0.copy()
        for i, name in enumerate(('angle_rad', 'velocity_rad_s', 'p_a_pa', 'p_b_pa')):
            if name in sig:
                x[i] = sig[name][k]
        for i, name in ((4, 't_a_k'), (5, 't_b_k')):
            temp = pred.get(name, [np.nan] * n)[k]
            x[i] = temp if np.isfinite(temp) else room
        c, dx = model.evaluate(x, sig['command_v'][k], sig['supply_pa'][k], exp.circuit,
                               params=P, out=buffers)
        out[k] = (dx[OMEGA], dx[P_A], dx[P_B], c[C_INERTIA], c[C_VA], c[C_VB], c[C_R])
    return out.T


def equation_residual(config: ModelConfig, exp: Experiment, pred: dict, equation: str
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(residual [SI], samples where it is defined, the equation's terms (n, k) in the order
    of ``Equation.terms``) of ``equation`` along time series ``exp``, with ``pred`` the model's k-step prediction of
    it; None where the record cannot show it."""
    if exp.static or 'command_v' not in exp.signals:
        return None
    sig = smoothed_signals(exp)
    sig.setdefault('supply_pa', np.full(len(exp.t), config.core['supply_pressure_pa']))
    eq = BY_EQUATION[equation].equation
    regs = term_values(eq.terms, {**sig, 't_s': exp.t,
                                  **{k: v for k, v in pred.items()
                                     if k not in sig and k.endswith('_pa')}}, config.core)
    if eq.signal is not None:
        if eq.signal not in exp.signals or eq.signal not in pred:
            return None
        res = exp[eq.signal] - np.asarray(pred[eq.signal])
        return res, np.isfinite(res), regs
    equation = eq.shown_as or equation
    win = max(5, int(round(DERIVATIVE_WINDOW_S / exp.dt)) | 1)
    if len(exp.t) <= win:
        return None
    acc, dpa, dpb, inertia, va, vb, r = _model_rates(Model(config), config, exp, sig, pred)
    if equation == 'moment_balance':
        if exp.circuit != 'servo' or 'angle_rad' not in sig:
            return None
        measured = savgol_filter(exp['angle_rad'], win, 3, deriv=2, delta=exp.dt)
        stroke = config.core['stroke_rad']
        ok = (np.abs(sig['velocity_rad_s']) > SLIDING_RAD_S) \
            & (sig['angle_rad'] > 0.05 * stroke) & (sig['angle_rad'] < 0.95 * stroke)
        return inertia * (measured - acc), ok, regs
    chamber = equation[-1]
    name = f'p_{chamber}_pa'
    if name not in exp.signals:
        return None
    rate = savgol_filter(exp[name], win, 2, deriv=1, delta=exp.dt)
    temp = np.asarray(pred.get(f't_{chamber}_k', np.full(len(exp.t), np.nan)))
    temp = np.where(np.isfinite(temp), temp, config.core['room_temperature_k'])
    volume = va if chamber == 'a' else vb
    modelled = dpa if chamber == 'a' else dpb
    return volume / (r * temp) * (rate - modelled), np.ones(len(exp.t), bool), regs
