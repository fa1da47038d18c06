"""Heat transfer coefficient h from a blocked-chamber discharge (paper Section 5.2, Eqs 41-42).

With the pistons held, the chamber volume V is constant and the pressure
and energy equations reduce to (m_dot: net mass inflow)

    R T m_dot = V dp/dt - (p V / T) dT/dt                                 (Eq. 41)
    h S (T_e - T) = c_v p V / (R T) dT/dt - R T m_dot - c_p (T_s - T) m_in  (Eq. 42)

so h(t) follows from the measured p, T and their derivatives. The last
term is not in the paper: gas that enters from the supply brings T_s, not
the chamber's T, and the spool clearance keeps feeding the chamber while
it discharges (Eq. 24). Left out, that enthalpy reads as heat transfer and
h comes out too large (by about a quarter on this rig); ``h_paper`` keeps
the paper's version for comparison. The inflow m_in is the clearance flow
(Eqs 17-18, 24-25) or, where the orifice feeds the chamber, the net flow
plus the clearance outflow.

A thermocouple lags the gas; with its time constant tau known, the gas
temperature is estimated as T_m + tau dT_m/dt. Derivatives come from a
Savitzky-Golay fit. Units: SI, pressures absolute.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import effects as registry
from ..errors import ExperimentError
from ..experiment import Experiment
from ..model.config import ModelConfig
from ..physics.gas import clearance_flow
from ..smoothing import savgol_filter

H_KEY = 'wall_heat_transfer.heat_transfer_coefficient_w_per_m2_k'


@dataclass
class HeatTransferResult:
    """The time-varying h of Eqs 41-42 and its averages [W/(m^2.K)]."""

    t: np.ndarray                 # [s]
    h_curve: np.ndarray           # [W/(m^2.K)], NaN where not evaluated
    valid: np.ndarray             # samples used for the averages
    h_mean: float                 # time average of the curve (the paper's "average")
    h_lsq: float                  # least squares: sum(num*den) / sum(den^2), robust near T = T_e
    h_paper: float                # as h_lsq but without the supply-enthalpy term
    chamber: str
    thermocouple_time_constant_s: float

    @property
    def h(self) -> float:
        """Recommended estimate: the least-squares average."""
        return self.h_lsq


def _wall_area(config: ModelConfig, chamber: str) -> float:
    values = config.components.get('wall_heat_transfer') or \
        registry.get('wall_heat_transfer').defaults()
    return values[f'wall_area_{chamber}_m2']


def _tc_constant(exp: Experiment, given: float | None) -> float:
    if given is not None:
        return float(given)
    sensors = exp.metadata.get('sensors') or {}
    return float(sensors.get('thermocouple_time_constant_s', 0.0))


def _supply_inflow(config: ModelConfig, chamber: str, xv, ps, p, T, mdot) -> np.ndarray:
    """Mass flow [kg/s] that enters the chamber from the supply (>= 0)."""
    core = config.core
    ds = core['spool_diameter_m']
    gap = 0.5 * (core['sleeve_bore_diameter_m'] - ds)
    clear = config.components.get('clearance_flow')
    if clear is None:  # no clearance in this model: only the orifice feeds the chamber
        l0 = None
    else:
        l0 = clear['clearance_initial_length_m']
    mu, r = core['gas_viscosity_pa_s'], core['gas_constant_j_per_kg_k']
    ts, te, pe = (core['supply_temperature_k'], core['room_temperature_k'],
                  core['atmospheric_pressure_pa'])
    metered = xv >= 0.0 if chamber == 'a' else xv < 0.0  # orifice from the supply
    out = np.zeros_like(p)
    for k in range(len(p)):
        length = None if l0 is None else l0 + abs(xv[k])
        if metered[k]:
            leak = 0.0 if length is None else clearance_flow(ds, gap, length, p[k], T[k], pe,
                                                              te, mu, r)
            out[k] = max(mdot[k] + max(leak, 0.0), 0.0)
        elif length is not None:
            out[k] = max(clearance_flow(ds, gap, length, ps[k], ts, p[k], T[k], mu, r), 0.0)
    return out


def heat_transfer_curve(exp: Experiment, config: ModelConfig, chamber: str = 'a',
                        tc_time_constant_s: float | None = None, window_s: float = 0.051,
                        min_delta_k: float = 2.0, settle_s: float = 0.05,
                        discharge_only: bool = True) -> HeatTransferResult:
    """h(t) of a blocked-chamber record (Eqs 41-42) and its averages.

    Parameters
    ----------
    exp : Experiment
        Blocked circuit, with the chamber's pressure and temperature.
    config : ModelConfig
        Geometry: volumes, wall areas, clearance; ``core.blocked_angle_rad``
        unless ``exp.metadata['blocked_angle_rad']`` says where the pistons were.
    chamber : {'a', 'b'}
    tc_time_constant_s : float, optional [s]
        Thermocouple time constant (default: the record's sensor metadata, else 0).
    window_s : float [s]
        Savitzky-Golay window for the derivatives.
    min_delta_k : float [K]
        Samples with |T_e - T| below this are left out (h is 0/0 there).
    settle_s : float [s]
        Samples this close to a valve command change are left out.
    discharge_only : bool
        Use only samples where the chamber loses mass, as the paper's test
        does: while it charges, the inflow's enthalpy dominates the balance
        and a small error in it swamps the heat transfer.
    """
    if exp.circuit != 'blocked' or exp.static:
        raise ExperimentError(f'{exp.name}: h needs a blocked-circuit record (pistons held), '
                              f'not {exp.circuit}')
    p_sig, t_sig = f'p_{chamber}_pa', f't_{chamber}_k'
    for sig in (p_sig, t_sig, 'command_v'):
        if sig not in exp.signals:
            raise ExperimentError(f'{exp.name}: h needs {sig}; record the chamber '
                                  'temperature too')
    core = config.core
    theta = float(exp.metadata.get('blocked_angle_rad', core['blocked_angle_rad']))
    swept = core['piston_area_m2'] * core['pinion_pitch_diameter_m']
    vol = (core['dead_volume_a_m3'] + swept * theta if chamber == 'a'
           else core['dead_volume_b_m3'] + swept * (core['stroke_rad'] - theta))
    area = _wall_area(config, chamber)
    kappa, r = core['heat_capacity_ratio'], core['gas_constant_j_per_kg_k']
    cp = kappa * r / (kappa - 1.0)
    te = core['room_temperature_k']
    dt = exp.dt
    w = max(5, int(round(window_s / dt)) | 1)
    tau = _tc_constant(exp, tc_time_constant_s)

    def sg(x, d=0):
        return savgol_filter(x, w, 2 if d < 2 else 3, deriv=d, delta=dt)

    p, dp = sg(exp[p_sig]), sg(exp[p_sig], 1)
    T, dT = sg(exp[t_sig]), sg(exp[t_sig], 1)
    if tau > 0:  # undo the thermocouple lag: T_gas = T_m + tau dT_m/dt
        T, dT = T + tau * dT, dT + tau * sg(exp[t_sig], 2)
    mdot = (vol * dp - p * vol / T * dT) / (r * T)                        # Eq. 41
    stored = (r / (kappa - 1.0)) * p * vol / (r * T) * dT                   # c_v m dT/dt
    u = exp['command_v']
    xv = core['spool_gain_m_per_v'] * (np.clip(u, 0.0, 10.0) - core['valve_null_voltage_v'])
    ps = exp.signals.get('supply_pa', np.full_like(p, core['supply_pressure_pa']))
    m_in = _supply_inflow(config, chamber, xv, ps, p, T, mdot)
    ts = core['supply_temperature_k']
    num_paper = stored - r * T * mdot
    num = num_paper - cp * (ts - T) * m_in                                # Eq. 42 + enthalpy
    den = area * (te - T)
    valid = np.abs(te - T) > min_delta_k
    if discharge_only:
        valid &= mdot < 0.0
    changes = np.flatnonzero(np.abs(np.diff(u)) > 1e-6)
    near = int(round(settle_s / dt)) + w
    for i in changes:
        valid[max(0, i - near):i + near + 1] = False
    valid[:w] = valid[-w:] = False
    if valid.sum() < 10:
        raise ExperimentError(f'{exp.name}: chamber {chamber} has no discharge that takes the '
                              f'gas more than {min_delta_k:g} K from room temperature; h needs '
                              'one: discharge the charged chamber faster')
    with np.errstate(divide='ignore', invalid='ignore'):
        curve = np.where(valid, num / den, np.nan)
    h_lsq = float(np.sum(num[valid] * den[valid]) / np.sum(den[valid] ** 2))
    h_paper = float(np.sum(num_paper[valid] * den[valid]) / np.sum(den[valid] ** 2))
    return HeatTransferResult(exp.t, curve, valid, float(np.nanmean(curve)), h_lsq, h_paper,
                              chamber, tau)


def identify_heat_transfer(experiments, config: ModelConfig, chamber: str = 'a',
                           tc_time_constant_s: float | None = None) -> HeatTransferResult:
    """h from one or more blocked discharge records; several are pooled by least squares."""
    if isinstance(experiments, Experiment):
        experiments = [experiments]
    results = [heat_transfer_curve(e, config, chamber, tc_time_constant_s)
               for e in experiments]
    if len(results) == 1:
        return results[0]
    weights = np.array([r.valid.sum() for r in results], float)
    h_lsq = float(np.average([r.h_lsq for r in results], weights=weights))
    h_mean = float(np.average([r.h_mean for r in results], weights=weights))
    h_paper = float(np.average([r.h_paper for r in results], weights=weights))
    first = results[0]
    return HeatTransferResult(first.t, first.h_curve, first.valid, h_mean, h_lsq, h_paper,
                              chamber, first.thermocouple_time_constant_s)


def plot_heat_transfer(exp: Experiment, result: HeatTransferResult, path) -> None:
    """Pressure, temperature and h(t) (the paper's Figs 13-15)."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    ch = result.chamber
    fig, ax = plt.subplots(3, 1, figsize=(7, 7), sharex=True)
    ax[0].plot(exp.t, exp[f'p_{ch}_pa'] * 1e-6)
    ax[0].set_ylabel(f'p_{ch} [MPa abs]')
    ax[1].plot(exp.t, exp[f't_{ch}_k'])
    ax[1].set_ylabel(f'T_{ch} [K]')
    ax[2].plot(result.t, result.h_curve, lw=0.8)
    ax[2].axhline(result.h_lsq, color='k', ls='--', label=f'average {result.h_lsq:.2f}')
    ax[2].axhline(result.h_paper, color='r', ls=':', label=f'paper Eq. 42 {result.h_paper:.2f}')
    ax[2].set_ylabel('h [W/(m^2 K)]')
    ax[2].set_xlabel('t [s]')
    ax[2].legend(fontsize=8)
    for a in ax:
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
