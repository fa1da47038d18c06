"""Predict a recorded experiment with the model: open-loop over the whole record, or
k-step-ahead from the measured state.

The actuator integrates flow into angle, so a small bias makes the open-loop
angle error grow without bound; the k-step view re-initialises the model
from the measured state every ``horizon_s`` and shows the local error. Both
are needed to tell a wrong model from an integrating bias.
"""
from __future__ import annotations

import numpy as np

from ..effects.layout import OMEGA, P_A, P_B, T_A, T_B, THETA
from ..errors import ExperimentError, SimulationError
from ..experiment import Experiment
from ..model.assembly import Model
from ..model.config import ModelConfig
from ..model.simulate import DEFAULT_RTOL, _delayed, initial_state, simulate_batch

#: predicted signal -> index in the state vector
STATE_SIGNALS = {'angle_rad': THETA, 'velocity_rad_s': OMEGA, 'p_a_pa': P_A, 'p_b_pa': P_B,
                 't_a_k': T_A, 't_b_k': T_B}


#: [s] half-width of the window over which an unmeasured velocity is estimated from the angle
VELOCITY_HALF_WINDOW_S = 5e-3


def _angle_slope(t: np.ndarray, angle: np.ndarray, k: int) -> float:
    """Least-squares slope [rad/s] of the angle over +/- VELOCITY_HALF_WINDOW_S around sample k.

    A two-point difference of a quantised encoder angle jumps by whole
    counts per sample; a centred line over ~10 ms averages that out.
    """
    half = max(1, int(round(VELOCITY_HALF_WINDOW_S / (t[1] - t[0]))))
    lo, hi = max(0, k - half), min(len(t), k + half + 1)
    if hi - lo < 2:
        return 0.0
    tt = t[lo:hi] - t[lo:hi].mean()
    return float(np.dot(tt, angle[lo:hi] - angle[lo:hi].mean()) / np.dot(tt, tt))


def _measured_state(model: Model, cfg: ModelConfig, exp: Experiment, k: int,
                    command_v: float) -> np.ndarray:
    """State vector from the measurements at sample ``k``; unmeasured parts from defaults.

    Velocity: measured, else the angle's local slope. Gas temperatures:
    measured, else room temperature.
    """
    sig = exp.signals
    if 'velocity_rad_s' in sig:
        vel = sig['velocity_rad_s'][k]
    elif 'angle_rad' in sig and len(exp.t) > 1:
        vel = _angle_slope(exp.t, sig['angle_rad'], k)
    else:
        vel = 0.0

    def get(name):
        return sig[name][k] if name in sig else None

    return initial_state(model, angle_rad=get('angle_rad'), p_a_pa=get('p_a_pa'),
                         p_b_pa=get('p_b_pa'), t_a_k=get('t_a_k'), t_b_k=get('t_b_k'),
                         velocity_rad_s=vel, command_v=command_v,
                         supply_pa=sig['supply_pa'][k] if 'supply_pa' in sig else None,
                         config=cfg, circuit=exp.circuit)


def _inputs(exp: Experiment, cfg: ModelConfig):
    if exp.static:
        raise ExperimentError(f'{exp.name}: a static table has no time series to simulate')
    if 'command_v' not in exp.signals:
        raise ExperimentError(f'{exp.name}: no valve command recorded; record valve/command')
    u = exp['command_v']
    ps = exp.signals.get('supply_pa')
    if ps is None:
        ps = np.full_like(u, cfg.core['supply_pressure_pa'])
    return u, ps


def predict_many(model: Model, exp: Experiment, configs: list[ModelConfig],
                 mode: str = 'open_loop', horizon_s: float = 0.2,
                 rtol: float = DEFAULT_RTOL) -> list[dict[str, np.ndarray]]:
    """Predicted signals of ``exp`` for each config (same composition as ``model``), in parallel.

    Returns, per config, a dict signal -> array on ``exp.t`` (states in
    STATE_SIGNALS, measurement delays applied). ``mode`` is 'open_loop' or
    'k_step' (re-initialised from the measured state every ``horizon_s`` [s]).
    A config whose simulation fails gets arrays of NaN.
    """
    if exp.static:
        from ..model import circuits  # steady-state solvers, imported only when needed
        return [circuits.predict_static(model, exp, cfg) for cfg in configs]
    if mode not in ('open_loop', 'k_step'):
        raise ExperimentError(f"unknown prediction mode {mode!r}; use 'open_loop' or 'k_step'")
    t = exp.t
    u, ps = _inputs(exp, configs[0])
    n = len(t)
    win = n if mode == 'open_loop' else max(2, int(round(horizon_s / exp.dt)) + 1)
    starts = list(range(0, n - 1, win - 1)) if win < n else [0]
    rows_p, rows_u, rows_ps, rows_x0, delays = [], [], [], [], []
    for cfg in configs:
        d_in, d_out = model.delays(cfg)
        d_ps = 0.0
        if mode == 'k_step':
            # a window starts from the *measured* state, which is the physical state d_out
            # ago; the measurement then evolves as the plant under inputs that much older
            d_in, d_ps, d_out = d_in + d_out, d_out, 0.0
        u_valve = _delayed(t, u, d_in)
        ps_valve = _delayed(t, ps, d_ps)
        P = model.param_vector(cfg)
        delays.append(d_out)
        for k0 in starts:
            k1 = min(k0 + win, n)
            seg_u = np.full(win, u_valve[k1 - 1])
            seg_ps = np.full(win, ps_valve[k1 - 1])
            seg_u[:k1 - k0], seg_ps[:k1 - k0] = u_valve[k0:k1], ps_valve[k0:k1]
            rows_p.append(P)
            rows_u.append(seg_u)
            rows_ps.append(seg_ps)
            rows_x0.append(_measured_state(model, cfg, exp, k0, u_valve[k0]))
    tw = t[0] + np.arange(win) * exp.dt if win < n else t
    XB, _, status = simulate_batch(model, tw, np.array(rows_u), np.array(rows_ps),
                                   np.array(rows_x0), np.array(rows_p), exp.circuit, rtol=rtol)
    out = []
    per = len(starts)
    for j, cfg in enumerate(configs):
        X = np.full((n, model.n_states), np.nan)
        ok = True
        for i, k0 in enumerate(starts):
            r = j * per + i
            k1 = min(k0 + win, n)
            if status[r] != 0:
                ok = False
                break
            seg = XB[r, :k1 - k0]
            if delays[j] > 0:
                seg = _delayed(tw[:k1 - k0], seg, delays[j])
            X[k0:k1] = seg
        if not ok:
            X[:] = np.nan
        out.append({name: X[:, idx] for name, idx in STATE_SIGNALS.items()})
    return out


def predict(model, exp: Experiment, config: ModelConfig | None = None, mode: str = 'open_loop',
            horizon_s: float = 0.2, rtol: float = DEFAULT_RTOL) -> dict[str, np.ndarray]:
    """Predicted signals of one experiment (see :func:`predict_many`); raises on failure."""
    model = model if isinstance(model, Model) else Model(model)
    cfg = config or model.config
    pred = predict_many(model, exp, [cfg], mode, horizon_s, rtol)[0]
    if any(np.isnan(v).all() for v in pred.values()):
        raise SimulationError(f'{exp.name}: the model could not be simulated over this record')
    return pred
