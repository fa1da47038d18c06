"""Compare an experiment with the model, in two views, and check it against limits.

* **open loop**: the recorded valve command and supply pressure drive the
  model over the whole record from the first measured state;
* **k-step ahead**: the model is re-initialised from the measured state
  every ``horizon_s`` and predicts only that far. The actuator integrates
  flow into angle, so a small bias makes the open-loop angle error grow
  without bound; the k-step view shows whether the model is locally right.

:func:`compare` returns a plain dict, ready for the ``compare --json`` file
of the interface contract (docs/interfaces.md): ``{"channels": {"angle": {...}, "p_a": {...}, "p_b": {...}},
"k_step": {...}, ...}``; every channel has ``rmse``, ``max_abs`` and
``fit_percent`` in SI units. Other tools add sections to the same dict.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import ConfigError, ExperimentError
from ..experiment import CHANNELS, Experiment
from ..model.assembly import Model
from ..model.config import ModelConfig
from ..prediction import COMPARE_HORIZON_S, config_for, open_loop, predict_checked, windows
from ..text import comma_list
from .metrics import channel_metrics

MODES = ('open_loop', 'k_step')
#: the paper's verification limits (Section 6.3): 1.25 deg and 4e-3 MPa
PAPER_MAX_ANGLE_ERROR_DEG = 1.25
PAPER_MAX_PRESSURE_ERROR_PA = 4.0e3
DEFAULT_HORIZON_S = COMPARE_HORIZON_S

def resolve_config(config=None, effects=None) -> ModelConfig:
    """A ModelConfig from a config, a YAML path or None (the paper's), plus named effects.

    ``effects`` is a list of catalogue names or a comma-separated string;
    each is added with its default values unless the config already has it.
    """
    if config is None:
        cfg = ModelConfig.paper()
    elif isinstance(config, ModelConfig):
        cfg = config.copy()
    else:
        cfg = ModelConfig.load(config)
    if isinstance(effects, str):
        effects = comma_list(effects)
    for name in effects or ():
        if name not in cfg.effects:
            cfg = cfg.with_effect(name)
    return cfg


def predict_views(exp: Experiment, config: ModelConfig, modes=MODES,
                  horizon_s: float = DEFAULT_HORIZON_S, model: Model | None = None
                  ) -> dict[str, dict[str, np.ndarray]]:
    """Predicted signals of ``exp`` per mode ('open_loop', 'k_step'); a static table has one."""
    for mode in modes:
        if mode not in MODES:
            raise ConfigError(f"unknown comparison mode {mode!r}; use 'open_loop' or 'k_step'")
    cfg = config_for(exp, config)
    model = model or Model(cfg)  # its kernels are compiled once per composition
    if exp.static:
        return {'open_loop': predict_checked(model, exp, cfg)}
    plans = {'open_loop': lambda: open_loop(exp), 'k_step': lambda: windows(exp, horizon_s)}
    return {mode: predict_checked(model, exp, cfg, plans[mode]()) for mode in modes}


def channel_table(exp: Experiment, pred: dict[str, np.ndarray], skip_s: float = 0.0) -> dict:
    """Metrics of every channel measured in ``exp`` and predicted in ``pred``."""
    keep = slice(None) if exp.static else exp.t >= exp.t[0] + skip_s
    if not exp.static and np.count_nonzero(keep) < 2:
        raise ExperimentError(f'{exp.name}: skipping the first {skip_s:g} s leaves nothing to '
                              f'compare (the record lasts {exp.duration:g} s); skip less')
    out = {}
    for ch, channel in CHANNELS.items():
        if channel.signal in exp.signals and channel.signal in pred:
            out[ch] = channel_metrics(exp[channel.signal][keep], pred[channel.signal][keep])
    return out


def compare(exp: Experiment, config=None, *, effects=None, mode: str = 'open_loop',
            modes=MODES, horizon_s: float = DEFAULT_HORIZON_S, skip_s: float = 0.0,
            model: Model | None = None, preds: dict | None = None) -> dict:
    """Compare ``exp`` with the model in both views.

    Parameters
    ----------
    exp : Experiment
        A time series or a static table.
    config : ModelConfig, path or None
        The model (default the paper's); ``effects`` adds catalogue effects.
    mode : {'open_loop', 'k_step'}
        The view reported under ``channels``; the other goes under its name.
    horizon_s : float [s]
        k-step prediction horizon.
    skip_s : float [s]
        Leave the first ``skip_s`` out of the metrics (start-up transient).
    preds : dict, optional
        Predictions already made (:func:`predict_views`), to avoid simulating twice.

    Returns
    -------
    dict
        ``channels`` (per channel ``rmse``, ``max_abs``, ``fit_percent``, SI),
        ``k_step`` or ``open_loop`` (the other view, same layout, with its
        ``horizon_s``), ``mode``, ``units`` and a description of the record
        and the model.
    """
    cfg = resolve_config(config, effects)
    if mode not in MODES:
        raise ConfigError(f"unknown comparison mode {mode!r}; use 'open_loop' or 'k_step'")
    modes = tuple(dict.fromkeys((mode,) + tuple(modes)))
    if preds is None:
        preds = predict_views(exp, cfg, modes, horizon_s, model)
    primary = mode if mode in preds else 'open_loop'
    result = {
        'experiment': exp.name, 'source': exp.metadata.get('source', ''),
        'circuit': exp.circuit, 'static': exp.static,
        'synthetic': bool(exp.metadata.get('synthetic', False)),
        'n_samples': int(len(exp.t)), 'duration_s': float(exp.duration),
        'mode': primary, 'channels': channel_table(exp, preds[primary], skip_s),
        'units': {ch: channel.unit for ch, channel in CHANNELS.items()},
        'model': {'components': list(cfg.components), 'effects': list(cfg.effects)},
    }
    for other in MODES:
        if other == primary:
            continue
        if other in preds:
            result[other] = {'channels': channel_table(exp, preds[other], skip_s)}
            if other == 'k_step':
                result[other]['horizon_s'] = horizon_s
        elif exp.static:
            result[other] = {'channels': {}, 'note': 'a static table has no time series'}
    if primary == 'k_step':
        result['horizon_s'] = horizon_s
    return result


# ---------------------------------------------------------------------- limits
def limits_for(max_angle_error_deg: float | None = PAPER_MAX_ANGLE_ERROR_DEG,
               max_pressure_error_pa: float | None = PAPER_MAX_PRESSURE_ERROR_PA,
               max_flow_error_kg_s: float | None = None,
               max_temperature_error_k: float | None = None) -> dict[str, float]:
    """Channel -> largest accepted absolute error [SI] (None: not checked)."""
    out = {}
    if max_angle_error_deg is not None:
        out['angle'] = math.radians(max_angle_error_deg)
    if max_pressure_error_pa is not None:
        out['p_a'] = out['p_b'] = float(max_pressure_error_pa)
    if max_flow_error_kg_s is not None:
        out['m4'] = out['m5'] = float(max_flow_error_kg_s)
    if max_temperature_error_k is not None:
        out['t_a'] = out['t_b'] = float(max_temperature_error_k)
    return out


def check_limits(result: dict, limits: dict[str, float]) -> list[dict]:
    """One row per compared channel: its max |error| against its limit [SI].

    A channel without a limit is listed (``passed`` None) but not checked;
    a channel whose error could not be computed fails.
    """
    rows = []
    for ch, m in result['channels'].items():
        limit = limits.get(ch)
        err = m.get('max_abs')
        passed = None if limit is None else (err is not None and err <= limit)
        rows.append({'channel': ch, 'max_abs': err, 'limit': limit, 'rmse': m.get('rmse'),
                     'fit_percent': m.get('fit_percent'), 'passed': passed,
                     'unit': CHANNELS[ch].unit})
    if not any(r['passed'] is not None for r in rows):
        raise ExperimentError(f'{result["experiment"]}: none of the measured channels '
                              f'({", ".join(result["channels"]) or "none"}) has a limit')
    return rows


def format_table(rows: list[dict]) -> str:
    """Plain-text table of :func:`check_limits` rows (angles shown in degrees)."""
    def show(ch, v):
        if v is None:
            return '-'
        if ch == 'angle':
            return f'{math.degrees(v):.4g} deg'
        return f'{v:.4g} {CHANNELS[ch].unit}'
    head = f'{"channel":<8} {"max |error|":>16} {"limit":>16} {"rmse":>16} {"fit %":>8}  result'
    lines = [head, '-' * len(head)]
    for r in rows:
        fit = '-' if r['fit_percent'] is None else f'{r["fit_percent"]:.1f}'
        verdict = {True: 'pass', False: 'FAIL', None: '(not checked)'}[r['passed']]
        lines.append(f'{r["channel"]:<8} {show(r["channel"], r["max_abs"]):>16} '
                     f'{show(r["channel"], r["limit"]):>16} {show(r["channel"], r["rmse"]):>16} '
                     f'{fit:>8}  {verdict}')
    return '\n'.join(lines)


def verify(exp: Experiment, config=None, *, effects=None, limits: dict | None = None,
           mode: str = 'open_loop', horizon_s: float = DEFAULT_HORIZON_S, skip_s: float = 0.0,
           model: Model | None = None) -> tuple[bool, list[dict], dict]:
    """Compare ``exp`` with the model and check the errors: (all passed, rows, compare dict)."""
    result = compare(exp, config, effects=effects, mode=mode, modes=(mode,),
                     horizon_s=horizon_s, skip_s=skip_s, model=model)
    rows = check_limits(result, limits if limits is not None else limits_for())
    return all(r['passed'] is not False for r in rows), rows, result
