"""The state a prediction starts from: measured where the record measures it, the rest from
defaults or from a short lead-in simulation."""
from __future__ import annotations

import numpy as np

from ..effects.layout import CORE_STATE_NAMES, OMEGA, P_A, P_B, THETA
from ..experiment import Experiment
from ..model.assembly import Model
from ..model.config import ModelConfig
from ..model.simulate import initial_state, sensing, sensor_errors, simulate_batch

#: [s] half-width of the window over which an unmeasured velocity is estimated from the angle
VELOCITY_HALF_WINDOW_S = 5e-3
#: states reset to the measurements after a lead-in, by circuit, with their signals
MEASURED_STATES = {'servo': ((THETA, 'angle_rad'), (OMEGA, 'angle_rad'), (P_A, 'p_a_pa'),
                             (P_B, 'p_b_pa')),
                   'blocked': ((P_A, 'p_a_pa'), (P_B, 'p_b_pa'))}


def angle_slope(t: np.ndarray, angle: np.ndarray, k: int) -> float:
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


def measured_values(exp: Experiment, cfg: ModelConfig, signals: dict, k: int) -> dict:
    """The core states at sample ``k`` that ``signals`` measure, as :func:`initial_state`'s
    keywords (None: not measured).

    Velocity: the signals' own, else the angle's local slope, else 0. Outside the servo
    circuit the pistons stand at the config's blocked angle.
    """
    def get(name):
        return float(signals[name][k]) if name in signals else None

    if 'velocity_rad_s' in signals:
        vel = get('velocity_rad_s')
    elif 'angle_rad' in signals and len(exp.t) > 1:
        vel = angle_slope(exp.t, signals['angle_rad'], k)
    else:
        vel = 0.0
    angle = get('angle_rad') if exp.circuit == 'servo' else cfg.core['blocked_angle_rad']
    return {'angle_rad': angle, 'p_a_pa': get('p_a_pa'), 'p_b_pa': get('p_b_pa'),
            't_a_k': get('t_a_k'), 't_b_k': get('t_b_k'), 'velocity_rad_s': vel}


def measured_state(model: Model, cfg: ModelConfig, exp: Experiment, signals: dict, k: int,
                   command_v: float, supply_pa: float, params: np.ndarray | None = None
                   ) -> np.ndarray:
    """State vector from the measured ``signals`` at sample ``k`` (:func:`measured_values`);
    the rest from defaults: gas temperatures at room temperature, effect states settled.
    ``params``: ``cfg``'s parameter vector, where the caller has it."""
    return initial_state(model, **measured_values(exp, cfg, signals, k), command_v=command_v,
                         supply_pa=supply_pa, config=cfg, circuit=exp.circuit, params=params)


def physical_signals(model: Model, cfg: ModelConfig, signals: dict, command_v: np.ndarray,
                     supply_pa: np.ndarray, t: np.ndarray) -> dict:
    """``signals`` with the model's sensor errors taken out (to first order: each error is
    evaluated at the reading), so a segment starts from the physical state; ``t`` [s] the
    sample times (a sensor's dynamics need them)."""
    live = sensing(model, cfg)
    if not live:
        return signals
    errors = sensor_errors(model, cfg, {**signals, 'command_v': command_v,
                                        'supply_pa': supply_pa, 't_s': t}, live)
    return {**signals, **{sig: signals[sig] - err for sig, err in errors.items()
                          if sig in signals}}


def stack_windows(win: int, segments, arrays) -> np.ndarray:
    """Stack per-config input arrays into (rows, win) windows starting at each segment,
    padded with the segment's last value."""
    starts = np.array([a for a, _ in segments])
    last = np.array([b - 1 for _, b in segments])
    index = np.minimum(starts[:, None] + np.arange(win), last[:, None])
    return np.concatenate([np.asarray(arr)[index] for arr in arrays])


def start_states(model: Model, exp: Experiment, signals: dict, cfgs, us, pss, params,
                 segments, lead_s: float) -> np.ndarray:
    """Start states of every (config, segment), config-major: measured, with the unmeasured
    ones (gas temperatures, effect states) from a lead-in simulation of ``lead_s`` [s] where
    the record leaves room for one; the measured states are then reset to the measurements.
    """
    physical = [physical_signals(model, cfg, signals, u, ps, exp.t)
                for cfg, u, ps in zip(cfgs, us, pss)]
    rows = list(zip(cfgs, physical, us, pss, params))

    def at(starts):
        """measured_state of every (config, start sample), config-major."""
        return np.array([measured_state(model, cfg, exp, sig, a, u[a], ps[a], p)
                         for cfg, sig, u, ps, p in rows for a in starts])

    lead = int(round(lead_s / exp.dt))
    pre = [(max(a - lead, 0), a + 1) for a, _ in segments]
    if (lead < 2 or exp.circuit not in MEASURED_STATES
            or all(b - a < 3 for a, b in pre)):
        return at([a for a, _ in segments])
    P = np.repeat(np.array(params), len(segments), axis=0)
    XB, _, status = simulate_batch(model, exp.t[:lead + 1] - exp.t[0],
                                   stack_windows(lead + 1, pre, us),
                                   stack_windows(lead + 1, pre, pss),
                                   at([a for a, _ in pre]), P, exp.circuit,
                                   lengths=[b - a for a, b in pre] * len(rows))
    keep = [i for i, sig in MEASURED_STATES[exp.circuit] if sig in exp.signals]
    X0 = np.empty((len(pre) * len(rows), model.n_states))
    for r, (a, b) in enumerate(pre * len(rows)):
        cfg, sig, u, ps, p = rows[r // len(pre)]
        if b - a >= 3 and status[r] == 0:
            # after the lead-in only the measured states are reset: no settling needed
            X0[r] = XB[r, b - a - 1]
            X0[r, keep] = _core_vector(measured_values(exp, cfg, sig, b - 1))[keep]
        else:
            X0[r] = measured_state(model, cfg, exp, sig, b - 1, u[b - 1], ps[b - 1], p)
    return X0


def _core_vector(values: dict) -> np.ndarray:
    """The core states of :func:`measured_values`, NaN where unmeasured."""
    return np.array([np.nan if values[k] is None else values[k] for k in CORE_STATE_NAMES])
