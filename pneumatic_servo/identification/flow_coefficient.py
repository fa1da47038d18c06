"""Orifice flow coefficient C1 from flow-rate tests (paper Section 5.1, Eqs 38-40).

At a held voltage the supply inflow through the metering orifice equals
M4 + M5 (Eq. 1 at steady state), so with the orifice law of Eq. 8

    C1 = (M4 + M5) sqrt(R T_s) / (p_s (2 S_V + C0 S_H) psi(p_a / p_s))        (Eq. 38)

The paper takes the flow as choked, psi = psi* (the constant of Eq. 8's
second branch); that holds only while p_a / p_s < b. Where the table
measures p_a, the subsonic branch psi(p_a/p_s) of Eq. 8 is used instead,
which equals Eq. 38 when choked and stays right when the flow meter's
back pressure un-chokes the orifice (at high voltages it reads ~20 % low
otherwise). C0 is taken as known (0.43 in the paper).

The C1 values are then fitted with the symmetric 4th-order polynomial of
Eq. 40 in |x_v|, with the positive sign of docs/model.md (settlement 1):
C1 = p4 x^4 + p3 x^3 + p2 x^2 + p1 x + p0, x = |x_v| [m].
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .. import effects as registry
from ..errors import ExperimentError
from ..experiment import Experiment
from ..model.config import ModelConfig
from ..physics.gas import flow_function
from ..physics.valve import annulus_area, hole_open_area

POLY_KEYS = ('orifice_flow.flow_coefficient_p0', 'orifice_flow.flow_coefficient_p1_per_m',
             'orifice_flow.flow_coefficient_p2_per_m2', 'orifice_flow.flow_coefficient_p3_per_m3',
             'orifice_flow.flow_coefficient_p4_per_m4')


@dataclass
class FlowCoefficients:
    """C1 per operating point (Eq. 38) and the fitted polynomial (Eq. 40)."""

    voltage_v: np.ndarray          # [V]
    spool_m: np.ndarray            # |x_v| [m]
    supply_pa: np.ndarray          # [Pa abs]
    c1: np.ndarray                 # [-] per point
    c1_choked: np.ndarray          # [-] the paper's Eq. 38 (flow taken as choked)
    pressure_ratio: np.ndarray     # p_a / p_s (NaN where p_a is not measured)
    coefficients: np.ndarray = field(default_factory=lambda: np.zeros(5))  # p0..p4 [SI]
    stderr: np.ndarray = field(default_factory=lambda: np.zeros(5))
    rms: float = float('nan')      # RMS misfit of the polynomial [-]

    def polynomial(self, x_abs) -> np.ndarray:
        """C1 of the fitted Eq. 40 at |x_v| = ``x_abs`` [m]."""
        x = np.abs(np.asarray(x_abs, float))
        return np.polyval(self.coefficients[::-1], x)

    def values(self) -> dict[str, float]:
        """'owner.name' -> value of the polynomial coefficients, for ``ModelConfig.set``."""
        return dict(zip(POLY_KEYS, map(float, self.coefficients)))

    def per_voltage(self) -> dict[float, float]:
        """Mean C1 [-] at each tested voltage [V] (over all supplies)."""
        out = {}
        for v in np.unique(np.round(self.voltage_v, 6)):
            out[float(v)] = float(np.mean(self.c1[np.isclose(self.voltage_v, v)]))
        return out


def _orifice(config: ModelConfig) -> dict:
    return config.components.get('orifice_flow') or registry.get('orifice_flow').defaults()


def flow_coefficients(experiments, config: ModelConfig, choked_only: bool = False
                      ) -> FlowCoefficients:
    """C1 at every row of flow-test tables (Eq. 38), before any polynomial fit.

    Parameters
    ----------
    experiments : Experiment or list of Experiment
        Static ``flow`` tables with ``command_v``, ``supply_pa``, ``m4_kg_s``,
        ``m5_kg_s`` and optionally ``p_a_pa`` and ``t_s_k``.
    config : ModelConfig
        Valve geometry (Table 2), C0, b, and T_s where it is not measured.
    choked_only : bool
        Use the paper's choked form of Eq. 38 even where p_a is measured.
    """
    if isinstance(experiments, Experiment):
        experiments = [experiments]
    core = config.core
    orf = _orifice(config)
    kappa, r = core['heat_capacity_ratio'], core['gas_constant_j_per_kg_k']
    psi_choked = math.sqrt(2 * kappa / (kappa + 1) * (2 / (kappa + 1)) ** (2 / (kappa - 1)))
    s_h = annulus_area(core['sleeve_bore_diameter_m'], core['spool_diameter_m'])
    cols = {k: [] for k in ('v', 'x', 'ps', 'c1', 'c1c', 'ratio')}
    for exp in experiments:
        if exp.circuit != 'flow' or not exp.static:
            raise ExperimentError(f'{exp.name}: C1 needs a static flow-test table (circuit '
                                  f'flow), not a {exp.circuit} {"table" if exp.static else "bag"}')
        for sig in ('command_v', 'supply_pa', 'm4_kg_s', 'm5_kg_s'):
            if sig not in exp.signals:
                raise ExperimentError(f'{exp.name}: C1 needs {sig} (column '
                                      f'{"voltage_v" if sig == "command_v" else sig})')
        n = len(exp.t)
        ts = exp.signals.get('t_s_k', np.full(n, core['supply_temperature_k']))
        pa = exp.signals.get('p_a_pa')
        for i in range(n):
            u = float(exp['command_v'][i])
            xv = core['spool_gain_m_per_v'] * (min(max(u, 0.0), 10.0)
                                               - core['valve_null_voltage_v'])
            geom = 2.0 * hole_open_area(abs(xv), core['spool_shoulder_half_width_m'],
                                        core['hole_radius_m']) \
                + orf['area_conversion_coefficient'] * s_h
            ps = float(exp['supply_pa'][i])
            flux = ps * geom / math.sqrt(r * float(ts[i]))
            m_in = float(exp['m4_kg_s'][i] + exp['m5_kg_s'][i])
            ratio = float(pa[i]) / ps if pa is not None else float('nan')
            psi = psi_choked
            if pa is not None and not choked_only:
                psi = flow_function(ratio, orf['critical_pressure_ratio'], kappa,
                                    orf['laminar_ratio_band'])
            if psi <= 0:
                raise ExperimentError(f'{exp.name} row {i + 1}: p_a >= p_s, no flow through '
                                      'the orifice; check the pressures')
            cols['v'].append(u)
            cols['x'].append(abs(xv))
            cols['ps'].append(ps)
            cols['c1'].append(m_in / (flux * psi))
            cols['c1c'].append(m_in / (flux * psi_choked))
            cols['ratio'].append(ratio)
    arr = {k: np.array(v) for k, v in cols.items()}
    if len(arr['c1']) == 0:
        raise ExperimentError('no flow-test rows to compute C1 from')
    return FlowCoefficients(arr['v'], arr['x'], arr['ps'], arr['c1'], arr['c1c'], arr['ratio'])


def fit_polynomial(result: FlowCoefficients, degree: int = 4) -> FlowCoefficients:
    """Fit Eq. 40, C1 = sum p_k |x_v|^k (k = 0..4), by least squares; fills ``result``."""
    x, c1 = result.spool_m, result.c1
    if len(np.unique(np.round(x, 9))) < degree + 1:
        raise ExperimentError(f'C1 polynomial of degree {degree} needs at least {degree + 1} '
                              'different voltages')
    # scale x to mm so the normal equations are well conditioned
    scale = 1e-3
    V = np.vander(x / scale, degree + 1, increasing=True)
    coef, *_ = np.linalg.lstsq(V, c1, rcond=None)
    res = c1 - V @ coef
    dof = max(1, len(c1) - degree - 1)
    cov = float(res @ res) / dof * np.linalg.pinv(V.T @ V)
    powers = scale ** np.arange(degree + 1)
    coefficients = np.zeros(5)
    stderr = np.zeros(5)
    coefficients[:degree + 1] = coef / powers
    stderr[:degree + 1] = np.sqrt(np.clip(np.diag(cov), 0, None)) / powers
    result.coefficients, result.stderr = coefficients, stderr
    result.rms = float(np.sqrt(np.mean(res ** 2)))
    return result


def identify_flow_coefficient(experiments, config: ModelConfig, choked_only: bool = False
                              ) -> FlowCoefficients:
    """C1 per operating point (Eq. 38) and its Eq. 40 polynomial."""
    return fit_polynomial(flow_coefficients(experiments, config, choked_only))


def plot_flow_coefficient(result: FlowCoefficients, path) -> None:
    """C1 against voltage (Fig. 11) with the fitted polynomial."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.5, 4))
    ax.plot(result.voltage_v, result.c1, 'o', ms=4, label='Eq. 38 with psi(p_a/p_s)')
    ax.plot(result.voltage_v, result.c1_choked, 'x', ms=4, alpha=0.6,
            label='Eq. 38 as printed (choked)')
    # the spool gain [m/V] the points were computed with (Eq. 39)
    open_ = np.abs(result.voltage_v - 5.0) > 1e-6
    gain = float(np.median(result.spool_m[open_] / np.abs(result.voltage_v[open_] - 5.0))) \
        if open_.any() else 2e-4
    uu = np.linspace(5.0, 10.0, 200)
    ax.plot(uu, result.polynomial(gain * (uu - 5.0)), '-', label='Eq. 40 fit')
    ax.set_xlabel('valve voltage [V]')
    ax.set_ylabel('flow coefficient C1 [-]')
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
