"""Predict a recorded experiment for many parameter sets of one composition, in one batch."""
from __future__ import annotations

import numpy as np

from ..effects.layout import CIRCUITS, OMEGA, P_A, P_B, T_A, T_B, THETA
from ..errors import ExperimentError, SimulationError
from ..experiment import Experiment
from ..model import culprit
from ..model.assembly import Model
from ..model.circuits import predict_static
from ..model.config import ModelConfig
from ..model.simulate import (
    DEFAULT_RTOL,
    delayed,
    measured_states,
    sensing,
    simulate_batch,
)
from .inputs import config_for, smoothed_signals, valve_inputs
from .plans import Plan, open_loop
from .start import stack_windows, start_states

#: predicted signal -> index in the state vector
STATE_SIGNALS = {'angle_rad': THETA, 'velocity_rad_s': OMEGA, 'p_a_pa': P_A, 'p_b_pa': P_B,
                 't_a_k': T_A, 't_b_k': T_B}


def _check(exp: Experiment) -> None:
    if 'command_v' not in exp.signals:
        raise ExperimentError(f'{exp.name or "experiment"}: no valve command recorded; record '
                              'valve/command')


def predict(model: Model, exp: Experiment, configs: list[ModelConfig], plan: Plan | None = None,
            rtol: float = DEFAULT_RTOL) -> list[dict[str, np.ndarray]]:
    """Predicted signals of ``exp`` for each config (one composition, ``model``'s), in parallel.

    Parameters
    ----------
    model : Model
        The compiled composition every config belongs to.
    exp : Experiment
        A time series (any circuit) or a static table.
    configs : list of ModelConfig
        Parameter sets; each is first adjusted to the record (:func:`config_for`).
    plan : Plan, optional
        Which samples to predict from where (default :func:`~.plans.open_loop`);
        ignored for a static table, which is solved row by row for steady states.
    rtol : float
        Relative tolerance of the integrator.

    Returns
    -------
    list of dict
        Per config, signal -> array on ``exp.t`` (the states of
        :data:`STATE_SIGNALS`; NaN outside the plan's segments). A config whose
        simulation fails gets NaN throughout.
    """
    return _predict(model, exp, configs, plan, rtol)[0]


def _predict(model, exp, configs, plan, rtol):
    """:func:`predict`, and a function that says why a config's simulation failed."""
    cfgs = [config_for(exp, cfg) for cfg in configs]
    if exp.static:
        return [predict_static(model, exp, cfg) for cfg in cfgs], (lambda j: '')
    _check(exp)
    plan = plan or open_loop(exp)
    signals = smoothed_signals(exp) if plan.smooth_start else exp.signals
    us, pss, params, d_outs = map(list, zip(*(_inputs(model, exp, signals, cfg, plan)
                                              for cfg in cfgs)))
    segs = plan.segments
    X0 = start_states(model, exp, signals, cfgs, us, pss, params, segs, plan.lead_s)
    win = max(b - a for a, b in segs)
    P = np.repeat(np.array(params), len(segs), axis=0)
    tw = exp.t[:win] - exp.t[0]
    XB, _, status = simulate_batch(model, tw, stack_windows(win, segs, us),
                                   stack_windows(win, segs, pss), X0, P, exp.circuit, rtol=rtol,
                                   lengths=[b - a for a, b in segs] * len(cfgs))
    out = []
    for j in range(len(cfgs)):
        rows = range(j * len(segs), (j + 1) * len(segs))
        X = np.full((len(exp.t), model.n_states), np.nan)
        if np.all(status[rows.start:rows.stop] == 0):
            live = sensing(model, cfgs[j])
            for r, (a, b) in zip(rows, segs):
                # the sensors read each segment's prediction on its own: a sensor's dynamics
                # (a lag) never see the step from one segment's end to the next one's start
                X[a:b] = measured_states(model, cfgs[j], exp.t[a:b],
                                         delayed(tw[:b - a], XB[r, :b - a], d_outs[j]),
                                         us[j][a:b], pss[j][a:b], live)
        out.append({name: X[:, idx] for name, idx in STATE_SIGNALS.items()})

    def why(j: int) -> str:
        """'' or ': ' + the component whose hook made config ``j``'s first failed segment
        fail (replayed in plain Python: the error path only)."""
        for i, (a, _) in enumerate(segs):
            r = j * len(segs) + i
            if status[r] != 0:
                return culprit.explain_status(
                    model.layout, X0[r], tw, stack_windows(win, segs, us)[r],
                    stack_windows(win, segs, pss)[r], P[r], CIRCUITS[exp.circuit], True, rtol,
                    model.abs_tol, 10, XB[r], t_offset=exp.t[a] - exp.t[0])
        return ''
    return out, why


def _inputs(model, exp, signals, cfg, plan) -> tuple:
    """(valve command, supply pressure, parameter vector, output delay) of ``cfg`` on
    ``exp``: what a prediction of it is driven by."""
    d_in, d_out = model.delays(cfg)
    u, ps = valve_inputs(exp, signals, cfg, d_in, d_out, plan.open_loop)
    return u, ps, model.param_vector(cfg), d_out if plan.open_loop else 0.0


def predict_checked(model: Model, exp: Experiment, config: ModelConfig | None = None,
                    plan: Plan | None = None, rtol: float = DEFAULT_RTOL
                    ) -> dict[str, np.ndarray]:
    """Predicted signals of one experiment (see :func:`predict`); raises if the model could
    not be simulated over it."""
    preds, why = _predict(model, exp, [config or model.config], plan, rtol)
    pred = preds[0]
    if any(np.isnan(v).all() for v in pred.values()):
        raise SimulationError(f'{exp.name}: the model could not be simulated over this '
                              f'record{why(0)}')
    return pred
