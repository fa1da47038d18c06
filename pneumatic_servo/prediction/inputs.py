"""What drives a prediction: the recorded inputs as the model sees them, and the measured
signals a prediction starts from.

Units: s, V, Pa absolute, rad, K.
"""
from __future__ import annotations

import numpy as np

from ..experiment import Experiment
from ..model.config import ModelConfig
from ..model.simulate import delayed
from ..smoothing import savgol_filter

#: [s] width of the Savitzky-Golay window that smooths the signals a segment starts from
START_WINDOW_S = 0.021


def config_for(exp: Experiment, config: ModelConfig) -> ModelConfig:
    """``config`` adjusted to the record's set-up: where a blocked record held the pistons
    (``blocked_angle_rad`` in the bag's custom data)."""
    angle = exp.metadata.get('blocked_angle_rad')
    if exp.circuit == 'blocked' and angle is not None:
        config = config.copy()
        config.core['blocked_angle_rad'] = float(angle)
    return config



def supply_input(ps: np.ndarray, win: int) -> np.ndarray:
    """The measured supply as the model's input: its median if it only shows sensor noise,
    else lightly smoothed.

    Sensor noise fed into the valve flows would perturb the stick-slip events
    of the prediction and so the residual, differently for every candidate.
    """
    noise = float(np.std(np.diff(ps))) / np.sqrt(2.0)
    slow = savgol_filter(ps, 5 * win | 1, 2) if len(ps) > 5 * win else ps
    if np.percentile(slow, 99) - np.percentile(slow, 1) < 5.0 * noise:
        return np.full(len(ps), float(np.median(ps)))
    return savgol_filter(ps, max(5, (win // 2) | 1), 2)


def smoothed_signals(exp: Experiment, window_s: float = START_WINDOW_S
                     ) -> dict[str, np.ndarray]:
    """Measured signals smoothed (Savitzky-Golay, no delay) for starting predictions and
    for the measured supply input.

    A segment starts from one sample of the measurements, and sensor noise in
    that sample would persist through the whole segment; noise on the measured
    supply would be fed into the valve flows. The velocity is always the
    centred estimate from the angle: a recorded encoder velocity is usually a
    causal difference that lags.
    """
    out = dict(exp.signals)
    if exp.static:
        return out
    win = max(5, int(round(window_s / exp.dt)) | 1)
    if len(exp.t) <= win:
        return out
    for name in ('angle_rad', 'p_a_pa', 'p_b_pa'):
        if name in out:
            out[name] = savgol_filter(out[name], win, 2)
    if 'supply_pa' in out:
        out['supply_pa'] = supply_input(out['supply_pa'], win)
    if 'angle_rad' in exp.signals:
        out['velocity_rad_s'] = savgol_filter(exp['angle_rad'], win, 2, deriv=1, delta=exp.dt)
    return out


def valve_inputs(exp: Experiment, signals: dict, cfg: ModelConfig, d_in: float, d_out: float,
                 open_loop: bool) -> tuple[np.ndarray, np.ndarray]:
    """(command at the valve [V], supply at the valve [Pa]) over the record for one config.

    Open loop, the command reaches the valve ``d_in`` late and the measurement
    delay ``d_out`` is applied to the outputs. A k-step segment starts from the
    *measured* state, which is the physical state ``d_out`` ago: the measurement
    then evolves as the plant under inputs that much older, so ``d_out`` is
    added to the inputs instead (delaying the outputs again would drop the
    first ``d_out`` of motion of every segment).
    """
    u = exp['command_v']
    ps = signals.get('supply_pa')
    if ps is None:
        ps = np.full(len(exp.t), cfg.core['supply_pressure_pa'])
    if open_loop:
        return delayed(exp.t, u, d_in), ps
    return delayed(exp.t, u, d_in + d_out), delayed(exp.t, ps, d_out)
