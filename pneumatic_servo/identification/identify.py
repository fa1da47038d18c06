"""The paper's identification procedures in one pass, from a set of experiments to a config.

Each experiment is used by the procedure it suits (:func:`classify`):

* static ``flow`` tables -> C1 per voltage (Eq. 38) -> Eq. 40 polynomial;
* ``blocked`` records with a chamber temperature -> h (Eqs 41-42);
* ``servo`` runs at a held valve voltage -> Stribeck friction (Eq. 43, Fig. 16);

then, optionally, chosen parameters are refined by output error over
chosen experiments together (:func:`~.output_error.fit_output_error`), with
standard errors and the correlation matrix. The result is a
:class:`~pneumatic_servo.model.ModelConfig` that ``ModelConfig.save``
writes as the YAML the nodes and the CLI take as it is.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ConfigError, ExperimentError
from ..experiment import Experiment
from ..model.config import ModelConfig
from .flow_coefficient import FlowCoefficients, identify_flow_coefficient
from .friction import FrictionResult, identify_friction
from .heat_transfer import H_KEY, HeatTransferResult, heat_transfer_curve
from .output_error import FitResult, fit_output_error

STEPS = ('flow', 'heat', 'friction')


def classify(exp: Experiment) -> str | None:
    """The procedure an experiment serves: 'flow', 'heat', 'friction' or None."""
    if exp.static:
        ok = exp.circuit == 'flow' and 'm4_kg_s' in exp and 'm5_kg_s' in exp
        return 'flow' if ok else None
    if exp.circuit == 'blocked' and ('t_a_k' in exp or 't_b_k' in exp):
        return 'heat'
    if exp.circuit == 'servo' and all(s in exp for s in ('angle_rad', 'p_a_pa', 'p_b_pa',
                                                          'command_v')):
        u = exp['command_v']
        tail = u[len(u) // 4:]
        # a friction run holds the valve at one voltage for most of the record
        if len(tail) > 10 and np.ptp(tail) < 1e-6:
            return 'friction'
    return None


@dataclass
class Identification:
    """What each procedure found, and the config with all of it applied."""

    config: ModelConfig
    flow: FlowCoefficients | None = None
    heat: list[HeatTransferResult] = field(default_factory=list)
    heat_h: float | None = None
    friction: FrictionResult | None = None
    friction_method: str = 'least_squares'
    refinement: FitResult | None = None
    used: dict[str, list[str]] = field(default_factory=dict)
    skipped: dict[str, str] = field(default_factory=dict)

    def summary(self) -> str:
        """Human-readable report: values, uncertainties, what was used."""
        out = []
        if self.flow is not None:
            f = self.flow
            out.append(f'flow coefficient C1 (Eq. 38) from {len(f.c1)} points of '
                       f'{", ".join(self.used.get("flow", []))}:')
            out.append('  voltage [V]   C1 [-]')
            for v, c in f.per_voltage().items():
                out.append(f'  {v:10.3f}   {c:.4f}')
            out.append('  Eq. 40 polynomial, C1 = p0 + p1|x| + ... + p4|x|^4 (x in m), '
                       f'RMS misfit {f.rms:.2g}:')
            for name, v, s in zip(('p0', 'p1', 'p2', 'p3', 'p4'), f.coefficients, f.stderr):
                out.append(f'    {name} = {v:.6g} +/- {s:.2g}')
        if self.heat_h is not None:
            out.append(f'heat transfer coefficient h (Eqs 41-42) = {self.heat_h:.3f} W/(m^2 K)')
            for r in self.heat:
                out.append(f'  chamber {r.chamber}: least squares {r.h_lsq:.3f}, time average '
                           f'{r.h_mean:.3f}, paper Eq. 42 without supply enthalpy '
                           f'{r.h_paper:.3f}; thermocouple tau '
                           f'{r.thermocouple_time_constant_s:g} s')
        if self.friction is not None:
            out.append(f'friction (Eq. 43, Fig. 16) from {len(self.friction.points)} points '
                       f'({", ".join(self.used.get("friction", []))}); '
                       f'config uses {self.friction_method}:')
            if self.friction.geometric is None:
                out.append(f'  geometric: not possible ({self.friction.geometric_error})')
            for fit in (self.friction.geometric, self.friction.least_squares):
                if fit is None:
                    continue
                se = fit.stderr
                out.append(f'  {fit.method:<13} F_s {fit.static_friction_n:.3f} N '
                           f'(+/- {se.get("static_friction_n", float("nan")):.2g}), '
                           f'F_c {fit.coulomb_friction_n:.3f} N '
                           f'(+/- {se.get("coulomb_friction_n", float("nan")):.2g}), '
                           f"theta'_s {fit.stribeck_velocity_rad_s:.4f} rad/s "
                           f'(+/- {se.get("stribeck_velocity_rad_s", float("nan")):.2g}), '
                           f'B {fit.viscous_friction_n_s_per_rad:.3f} N.s/rad '
                           f'(+/- {se.get("viscous_friction_n_s_per_rad", float("nan")):.2g})')
            geo = self.friction.geometric
            raw = geo.notes.get('raw_stribeck_velocity') if geo is not None else None
            if raw is not None:
                out.append(f"  (geometric theta'_s before calibration to Eq. 36: {raw:.4f})")
        if self.refinement is not None:
            out.append(refinement_report(self.refinement))
        for name, why in self.skipped.items():
            out.append(f'not used: {name}: {why}')
        return '\n'.join(out)

    def to_dict(self) -> dict:
        """Machine-readable results (for ``identify --json``)."""
        d: dict = {'used': self.used, 'skipped': self.skipped}
        if self.flow is not None:
            d['flow_coefficient'] = {
                'per_voltage': {f'{v:g}': c for v, c in self.flow.per_voltage().items()},
                'polynomial': self.flow.values(),
                'stderr': dict(zip(self.flow.values(), map(float, self.flow.stderr))),
                'rms': self.flow.rms}
        if self.heat_h is not None:
            d['heat_transfer'] = {'h': self.heat_h, 'chambers': [
                {'chamber': r.chamber, 'h_lsq': r.h_lsq, 'h_mean': r.h_mean,
                 'h_paper': r.h_paper} for r in self.heat]}
        if self.friction is not None:
            d['friction'] = {'method': self.friction_method}
            for fit in (self.friction.geometric, self.friction.least_squares):
                if fit is not None:
                    d['friction'][fit.method] = {**fit.values(), 'stderr': fit.stderr}
        if self.refinement is not None:
            r = self.refinement
            d['refinement'] = {'values': r.values, 'stderr': r.stderr,
                               'correlation': np.asarray(r.correlation).tolist(),
                               'free': r.keys, 'rms': r.rms, 'success': r.converged,
                               'at_bound': r.at_bound}
        return d

    def header(self) -> str:
        """Comment lines for the saved YAML: where the values came from."""
        lines = ['identified by pneumatic_servo.identification.identify']
        for step, names in self.used.items():
            lines.append(f'{step}: {", ".join(names)}')
        return '\n'.join(lines)


def refinement_report(fit: FitResult) -> str:
    """Values, standard errors and the correlation matrix of an output-error fit."""
    out = [f'output-error refinement ({"converged" if fit.converged else "NOT converged"}: '
           f'{fit.message}), {fit.n_data} residuals:']
    for k in fit.keys:
        se = fit.stderr[k]
        if se is None:
            out.append(f'  {k} = {fit.values[k]:.6g} (not determined: '
                       f'{fit.identifiability.reason(k)})')
            continue
        rel = abs(se / fit.values[k]) if fit.values[k] else float('inf')
        flag = '  at bound' if k in fit.at_bound else ''
        flag += '  (poorly determined)' if rel > 0.5 else ''
        out.append(f'  {k} = {fit.values[k]:.6g} +/- {se:.2g}{flag}')
    out.append('  correlation:')
    short = [k.split('.')[-1][:14] for k in fit.keys]
    out.append('    ' + ' '.join(f'{s:>14}' for s in short))
    for s, row in zip(short, np.asarray(fit.correlation)):
        out.append(f'    {s:<14}' + ''.join(f'{v:15.2f}' for v in row)[1:])
    strong = [(fit.keys[i], fit.keys[j], fit.correlation[i][j])
              for i in range(len(fit.keys)) for j in range(i)
              if abs(fit.correlation[i][j]) > 0.9]
    for a, b, c in strong:
        out.append(f'  {a} and {b} are {c:+.2f} correlated: these data cannot separate them')
    out.append('  normalised RMS residual per channel: '
               + ', '.join(f'{k} {v:.3g}' for k, v in fit.rms.items()))
    return '\n'.join(out)


def _apply(cfg: ModelConfig, values: dict[str, float], step: str) -> None:
    """Write identified ``values`` into ``cfg``; a value outside its parameter's bounds is
    refused, never written."""
    for key, value in values.items():
        try:
            cfg.set(key, value)
        except ConfigError as exc:
            raise ExperimentError(f'{step}: the identified {exc}; the records do not support '
                                  'this identification') from None


def identify(experiments: list[Experiment], base: ModelConfig | None = None,
             steps=STEPS, friction_method: str = 'least_squares',
             tc_time_constant_s: float | None = None, refine=None,
             refine_experiments: list[Experiment] | None = None,
             refine_mode: str = 'open_loop', refine_bounds: dict | None = None,
             refine_channels=None, max_nfev: int = 30) -> Identification:
    """Run the paper's procedures on ``experiments`` and apply the results to ``base``.

    Parameters
    ----------
    experiments : list of Experiment
        Any mix; each is used by the step it suits (see :func:`classify`).
    base : ModelConfig, optional
        Geometry and everything not identified (default the paper's).
    steps : iterable of {'flow', 'heat', 'friction'}
        Procedures to run; a step without data is reported, not an error,
        unless it was asked for explicitly (``steps`` given) and has none.
    friction_method : {'least_squares', 'geometric'}
        Which Stribeck estimate goes into the config.
    tc_time_constant_s : float, optional [s]
        Thermocouple time constant (default: from the records' metadata).
    refine : list of str, optional
        Parameter keys to refine by output error afterwards.
    refine_experiments : list of Experiment, optional
        Experiments for the refinement (default: the time series given).
    refine_mode, refine_bounds, refine_channels, max_nfev
        Passed to :func:`fit_output_error`.
    """
    steps = tuple(steps)
    unknown = set(steps) - set(STEPS)
    if unknown:
        raise ConfigError(f'unknown identification step(s) {sorted(unknown)}; use '
                          f'{", ".join(STEPS)}')
    if friction_method not in ('least_squares', 'geometric'):
        raise ConfigError("friction_method must be 'least_squares' or 'geometric'")
    cfg = (base or ModelConfig.paper()).copy()
    groups: dict[str, list[Experiment]] = {s: [] for s in STEPS}
    skipped = {}
    for exp in experiments:
        kind = classify(exp)
        if kind is None:
            skipped[exp.name] = 'not a flow table, blocked record with temperature or ' \
                                'held-voltage servo run'
        else:
            groups[kind].append(exp)
    result = Identification(cfg, skipped=skipped, friction_method=friction_method)
    if tc_time_constant_s is not None and not (math.isfinite(tc_time_constant_s)
                                                and tc_time_constant_s > 0):
        raise ConfigError(f'thermocouple time constant {tc_time_constant_s!r} s: give a '
                          'positive number of seconds')
    if 'flow' in steps and groups['flow']:
        result.flow = identify_flow_coefficient(groups['flow'], cfg)
        bad = {v: c for v, c in result.flow.per_voltage().items() if not c > 0.0}
        if bad:
            raise ExperimentError(f'flow: the flow coefficient C1 comes out '
                                  f'{min(bad.values()):.3g} at {min(bad):g} V; C1 is positive: '
                                  'check the flow tables (m4, m5, supply) of those voltages')
        _apply(cfg, result.flow.values(), 'flow')
        result.used['flow'] = [e.name for e in groups['flow']]
    if 'heat' in steps and groups['heat']:
        _heat(result, groups['heat'], cfg, tc_time_constant_s)
    if 'friction' in steps and groups['friction']:
        result.friction = identify_friction(groups['friction'], cfg)
        fit = getattr(result.friction, friction_method)
        if fit is None:
            raise ExperimentError(f'friction: no geometric construction: '
                                  f'{result.friction.geometric_error}; or use least squares')
        if fit.static_friction_n < fit.coulomb_friction_n:
            raise ExperimentError(f'friction: the {friction_method} estimate has F_s < F_c; '
                                  'the runs do not show the Stribeck dip')
        _apply(cfg, fit.values(), 'friction')
        result.used['friction'] = [e.name for e in groups['friction']]
    for step in steps:
        if not groups[step] and step in steps and len(steps) < len(STEPS):
            raise ExperimentError(f'no experiment for the {step} step among '
                                  f'{", ".join(e.name for e in experiments)}')
    if not result.used and not refine:
        raise ExperimentError(
            'none of the experiments serves an identification step (flow tables, blocked '
            'records with temperatures, servo runs at a held voltage): '
            + '; '.join(f'{k}: {v}' for k, v in skipped.items()))
    if refine:
        exps = refine_experiments or [e for e in experiments if not e.static]
        if not exps:
            raise ExperimentError('nothing to refine on: give time-series experiments')
        fit = fit_output_error(cfg, exps, list(refine), channels=refine_channels,
                               mode=refine_mode, bounds=refine_bounds, max_nfev=max_nfev)
        result.refinement = fit
        cfg = fit.config
        result.used['refinement'] = [e.name for e in exps]
    cfg.validate()
    result.config = cfg
    return result


def _heat(result: Identification, exps, cfg: ModelConfig, tau) -> None:
    num = den = 0.0
    for exp in exps:
        for ch in ('a', 'b'):
            if f't_{ch}_k' not in exp or f'p_{ch}_pa' not in exp:
                continue
            try:
                r = heat_transfer_curve(exp, cfg, ch, tau)
            except ExperimentError as exc:
                result.skipped[f'{exp.name} (chamber {ch})'] = str(exc)
                continue
            result.heat.append(r)
            weight = float(r.valid.sum())
            num += weight * r.h_lsq
            den += weight
    if den == 0:
        raise ExperimentError('no blocked record with a usable temperature transient for h')
    result.heat_h = num / den
    if 'wall_heat_transfer' not in cfg.components:
        raise ConfigError('the base model has no wall_heat_transfer component to take h; '
                          'use the paper thermal model')
    _apply(cfg, {H_KEY: result.heat_h}, 'heat')
    result.used['heat'] = [e.name for e in exps]
