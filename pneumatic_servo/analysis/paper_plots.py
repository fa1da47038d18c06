"""The paper's figures drawn (Figs 16-26 analogues and the switchable parts), as PNG files.

Figures are drawn with matplotlib's Agg canvas directly, so no global
backend is touched. :mod:`.paper_figures` runs the simulations they show.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..model import ModelConfig
from ..model.simulate import SimResult
from ..physics.friction import coulomb_viscous_force, stribeck_force
from ..physics.valve import flow_coefficient, spool_displacement

MPA = 1e-6  # [MPa/Pa]
_COLORS = {'a': 'tab:red', 'b': 'tab:blue', 'ref': '0.45'}
_DPI = 110


def _figure(nrows: int, ncols: int, width: float, height: float, title: str):
    fig = Figure(figsize=(width, height), dpi=_DPI, layout='constrained')
    FigureCanvasAgg(fig)
    axes = fig.subplots(nrows, ncols, squeeze=False)
    fig.suptitle(title, fontsize=12)
    for ax in axes.flat:
        ax.grid(True, alpha=0.3)
    return fig, axes


def _save(fig: Figure, path: Path) -> str:
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path)
    return str(path)


_REF_STYLE = {'supply': ('0.25', '--'), 'atmosphere': ('0.45', ':'), 'room': ('0.45', '--')}


def _hline(ax, y, label):
    color, ls = _REF_STYLE[label.split()[0]]
    ax.axhline(y, color=color, ls=ls, lw=1.1, label=label)


def _figure_legend(fig: Figure, ax) -> None:
    """One legend for the whole figure, below the panels, from ``ax``'s lines."""
    handles, labels = ax.get_legend_handles_labels()
    fig.legend(handles, labels, loc='outside lower center', ncol=min(len(labels), 5),
               fontsize=9)


def _step_line(ax, step_time_s, text=False):
    ax.axvline(step_time_s, color='0.6', ls='-.', lw=0.9)
    if text:
        ax.annotate('valve step', xy=(step_time_s, 0.5), xycoords=('data', 'axes fraction'),
                    xytext=(4, 0), textcoords='offset points', fontsize=8, color='0.4',
                    rotation=90, va='center')


def plot_charge_discharge(res: SimResult, config: ModelConfig, step_time_s: float,
                          path: Path) -> str:
    """Figs 22-23 analogue: p_a, p_b, T_a, T_b of the charge/discharge test."""
    core = config.core
    pe, te = core['atmospheric_pressure_pa'], core['room_temperature_k']
    ps = float(np.max(res.inputs['supply_pa']))
    u = res.inputs['command_v']
    fig, ax = _figure(2, 2, 10.0, 6.6, 'Charge/discharge, pistons held: supply 0.6 MPa gauge, '
                      f'valve {u[0]:g} V → {u[-1]:g} V at t = {step_time_s:g} s')
    for col, (ch, p, temp) in enumerate((('a', res.p_a_pa, res.t_a_k),
                                          ('b', res.p_b_pa, res.t_b_k))):
        top, bottom = ax[0, col], ax[1, col]
        top.plot(res.t, p * MPA, color=_COLORS[ch], lw=1.6, label=f'$p_{ch}$')
        _hline(top, ps * MPA, 'supply $p_s$')
        _hline(top, pe * MPA, 'atmosphere $p_e$')
        top.set_ylabel(f'$p_{ch}$ [MPa, absolute]')
        top.set_title(f'chamber {ch} ' + ('charging' if ch == 'a' else 'discharging'))
        top.set_ylim(0.0, ps * MPA * 1.08)
        bottom.plot(res.t, temp, color=_COLORS[ch], lw=1.6, label=f'$T_{ch}$')
        _hline(bottom, te, 'room $T_e$')
        bottom.set_ylabel(f'$T_{ch}$ [K]')
        bottom.set_xlabel('time [s]')
        for a in (top, bottom):
            _step_line(a, step_time_s, text=(ch == 'b'))  # room for the label only there
            a.legend(loc='best', fontsize=8)
            a.set_xlim(res.t[0], res.t[-1])
    return _save(fig, path)


def plot_sine(res: SimResult, path: Path, window_s: float = 4.0) -> str:
    """Figs 24-26 analogue: command, angle and chamber pressures of the sine response."""
    keep = res.t <= window_s
    t = res.t[keep]
    fig, ax = _figure(3, 1, 10.0, 7.4, 'Open-loop servo response: supply 0.6 MPa gauge, '
                      'valve 5 ± 0.35 V sine at 2 Hz')
    ax[0, 0].plot(t, res.inputs['command_v'][keep], color='k', lw=1.2, label='command $U$')
    ax[0, 0].set_ylabel('$U$ [V]')
    ax[1, 0].plot(t, np.degrees(res.angle_rad[keep]), color='tab:green', lw=1.6,
                  label=r'angle $\theta$')
    ax[1, 0].set_ylabel(r'$\theta$ [deg]')
    ax[2, 0].plot(t, res.p_a_pa[keep] * MPA, color=_COLORS['a'], lw=1.4, label='$p_a$')
    ax[2, 0].plot(t, res.p_b_pa[keep] * MPA, color=_COLORS['b'], lw=1.4, label='$p_b$')
    ax[2, 0].set_ylabel('pressure [MPa, absolute]')
    ax[2, 0].set_xlabel('time [s]')
    for a in ax[:, 0]:
        a.legend(loc='upper left', bbox_to_anchor=(1.0, 1.0), fontsize=8)
        a.set_xlim(t[0], t[-1])
    return _save(fig, path)


def _overlay(ax, results: dict[str, SimResult], getter: Callable, scale: float = 1.0):
    styles = ('-', '--', '-.', ':')
    for i, (label, res) in enumerate(results.items()):
        ax.plot(res.t, getter(res) * scale, ls=styles[i % 4], lw=1.6, label=label)


def plot_pressure_variants(results: dict[str, SimResult], config: ModelConfig,
                           step_time_s: float, title: str, path: Path) -> str:
    """Charge/discharge p_a and p_b of several model variants side by side.

    An inset magnifies the approach to supply in chamber a, where the
    clearance makes the difference.
    """
    pe = config.core['atmospheric_pressure_pa']
    ps = float(np.max(next(iter(results.values())).inputs['supply_pa']))
    fig, ax = _figure(1, 2, 10.0, 4.3, title)
    for col, ch in enumerate('ab'):
        a = ax[0, col]
        _overlay(a, results, (lambda r, ch=ch: r[f'p_{ch}_pa']), MPA)
        _hline(a, ps * MPA, 'supply')
        _hline(a, pe * MPA, 'atmosphere')
        _step_line(a, step_time_s)
        a.set_ylabel(f'$p_{ch}$ [MPa, absolute]')
        a.set_xlabel('time [s]')
        a.set_ylim(0.0, ps * MPA * 1.08)
        a.set_title(f'chamber {ch}')
    inset = ax[0, 0].inset_axes([0.4, 0.2, 0.55, 0.45])
    _overlay(inset, results, (lambda r: r.p_a_pa), MPA)
    _hline(inset, ps * MPA, 'supply')
    t_end = next(iter(results.values())).t[-1]
    inset.set_xlim(0.2 * t_end, t_end)
    inset.set_ylim((ps - 15e3) * MPA, (ps + 3e3) * MPA)
    inset.set_title('near supply', fontsize=8)
    inset.tick_params(labelsize=7)
    inset.grid(True, alpha=0.3)
    _figure_legend(fig, ax[0, 0])
    return _save(fig, path)


def plot_thermal_variants(results: dict[str, SimResult], config: ModelConfig,
                          step_time_s: float, path: Path) -> str:
    """Charge/discharge temperatures and pressures: heat transfer, adiabatic, isothermal."""
    te = config.core['room_temperature_k']
    fig, ax = _figure(2, 2, 10.0, 7.0, 'Thermal part: heat transfer (paper) vs adiabatic vs '
                      'isothermal, charge/discharge test')
    for col, ch in enumerate('ab'):
        _overlay(ax[0, col], results, (lambda r, ch=ch: r[f't_{ch}_k']))
        _hline(ax[0, col], te, 'room $T_e$')
        ax[0, col].set_ylabel(f'$T_{ch}$ [K]')
        ax[0, col].set_title(f'chamber {ch}')
        _overlay(ax[1, col], results, (lambda r, ch=ch: r[f'p_{ch}_pa']), MPA)
        ax[1, col].set_ylabel(f'$p_{ch}$ [MPa, absolute]')
        ax[1, col].set_xlabel('time [s]')
        for a in ax[:, col]:
            _step_line(a, step_time_s)
    _figure_legend(fig, ax[0, 0])
    return _save(fig, path)


def plot_friction_variants(results: dict[str, SimResult], config: ModelConfig,
                           path: Path, window_s: float = 2.0) -> str:
    """Friction laws and the sine response angle with each."""
    fig, ax = _figure(1, 3, 13.0, 3.9, 'Friction part: Stribeck (paper) vs Coulomb + viscous')
    st = config.values_of('stribeck_friction') or ModelConfig.paper().values_of(
        'stribeck_friction')
    w = np.linspace(-0.6, 0.6, 1201)
    fs = [stribeck_force(v, st['static_friction_n'], st['coulomb_friction_n'],
                         st['stribeck_velocity_rad_s'], st['viscous_friction_n_s_per_rad'])
          for v in w]
    fc = [coulomb_viscous_force(v, st['coulomb_friction_n'],
                                st['viscous_friction_n_s_per_rad']) for v in w]
    ax[0, 0].plot(w, fs, lw=1.6, label='Stribeck, Eq. 36')
    ax[0, 0].plot(w, fc, ls='--', lw=1.6, label='Coulomb + viscous')
    ax[0, 0].set_xlabel(r'$\dot\theta$ [rad/s]')
    ax[0, 0].set_ylabel('friction force $F_f$ [N]')
    ax[0, 0].set_title('sliding friction law')
    keep = {k: r.t <= window_s for k, r in results.items()}
    styles = ('-', '--')
    for i, (label, res) in enumerate(results.items()):
        m = keep[label]
        ax[0, 1].plot(res.t[m], np.degrees(res.angle_rad[m]), ls=styles[i % 2], lw=1.6,
                      label=label)
    ax[0, 1].set_xlabel('time [s]')
    ax[0, 1].set_ylabel(r'$\theta$ [deg]')
    ax[0, 1].set_title('sine response (5 ± 0.35 V, 2 Hz)')
    labels = list(results)
    if len(labels) >= 2:
        r0, r1 = results[labels[0]], results[labels[1]]
        m = keep[labels[0]]
        ax[0, 2].plot(r0.t[m], np.degrees(r1.angle_rad[m] - r0.angle_rad[m]), color='k', lw=1.4,
                      label=f'{labels[1]} − {labels[0]}')
    ax[0, 2].set_xlabel('time [s]')
    ax[0, 2].set_ylabel(r'angle difference [deg]')
    ax[0, 2].set_title('difference')
    for a in ax[0]:
        a.legend(loc='best', fontsize=8)
    return _save(fig, path)


def plot_static(curves: dict, path: Path) -> str:
    """Table 5 and Figs 19-20 analogues: closed-port p_a, M5, and flow-test M4."""
    fig, ax = _figure(1, 3, 13.0, 3.9, 'Static tests (Table 5, Figs 19-20): supplies 0.5, 0.7, '
                      '0.83 MPa gauge')
    for label, c in curves.items():
        v = c['voltage_v']
        ax[0, 0].plot(v, np.array(c['closed_port_p_a_pa']) * MPA, marker='.', label=label)
        ax[0, 1].plot(v, np.array(c['closed_port_m5_kg_s']) * 1e6, marker='.', label=label)
        ax[0, 2].plot(v, np.array(c['flow_m4_kg_s']) * 1e3, marker='.', label=label)
    ax[0, 0].set_ylabel('closed-port $p_a$ [MPa, absolute]')
    ax[0, 0].set_title('valve chamber, ports 2-4 closed')
    ax[0, 1].set_ylabel(r'closed-port $\dot M_5$ [mg/s]')
    ax[0, 1].set_title('clearance flow out of port 5')
    ax[0, 2].set_ylabel(r'flow-test $\dot M_4$ [g/s]')
    ax[0, 2].set_title('port 4 vented through flow meter')
    for a in ax[0]:
        a.set_xlabel('drive voltage $U$ [V]')
        a.legend(title='supply (gauge)', fontsize=8, title_fontsize=8)
    return _save(fig, path)


def plot_flow_coefficient(config: ModelConfig, path: Path) -> str:
    """C1 over the drive voltage: the polynomial as printed (Eq. 40) and as settled."""
    o = config.values_of('orifice_flow') or ModelConfig.paper().values_of('orifice_flow')
    p = [o['flow_coefficient_p0'], o['flow_coefficient_p1_per_m'],
         o['flow_coefficient_p2_per_m2'], o['flow_coefficient_p3_per_m3'],
         o['flow_coefficient_p4_per_m4']]
    core = config.core
    volts = np.linspace(0.0, 10.0, 401)
    xv = np.array([spool_displacement(u, core['valve_null_voltage_v'],
                                      core['spool_gain_m_per_v'], 1.0) for u in volts])
    settled = np.array([flow_coefficient(abs(x), *p) for x in xv])
    # Eq. 40 as printed: the x_v >= 0 branch has the odd terms negated
    printed = np.where(xv < 0.0, p[0] + p[1] * xv + p[2] * xv ** 2 + p[3] * xv ** 3
                       + p[4] * xv ** 4,
                       p[0] - p[1] * xv + p[2] * xv ** 2 - p[3] * xv ** 3 + p[4] * xv ** 4)
    fig, ax = _figure(1, 2, 11.0, 4.0, 'Flow coefficient $C_1$ (Eq. 40): sign settlement')
    for a in ax[0]:
        a.plot(volts, settled, lw=1.8, label='settled: $P(|x_v|)$ (used)')
        a.plot(volts, printed, ls='--', lw=1.6, label='as printed')
        a.axhline(0.0, color='k', lw=0.8)
        a.set_xlabel('drive voltage $U$ [V]')
        a.set_ylabel('$C_1$ [-]')
    checks = [(5.0, 0.4517), (7.0, 0.75), (10.0, 0.544)]
    ax[0, 1].plot(*zip(*checks), 'ko', ms=4,
                  label='0.4517 at null, ≈0.75 at 0.4 mm, 0.544 at 1 mm')
    ax[0, 1].set_ylim(-0.2, 0.9)
    ax[0, 0].set_title('whole range')
    ax[0, 1].set_title('zoom: the settled curve')
    ax[0, 0].legend(loc='lower center', fontsize=9)
    ax[0, 1].legend(loc='lower center', fontsize=8)
    return _save(fig, path)


# ------------------------------------------------------------------------------ driver
