"""Reproduce the paper's qualitative results as PNG figures and a checked summary.

What is reproduced (Zhang et al., Energies 2019):

* charge/discharge with the pistons held, 0.6 MPa gauge, 5 V -> 5.5 V
  (Figs 22-23): p_a rises but stays below supply, p_b falls but stays above
  atmosphere, T_a jumps and recovers, T_b dips and recovers. Each claim is a
  boolean computed from the simulation;
* the open-loop servo response to a 2 Hz, 5 +/- 0.35 V sine (Figs 24-26);
* the static tests: closed-port p_a (Table 5), M4 and M5 (Figs 19-20);
* the flow coefficient C1 as printed and as settled (Eq. 40, MODEL_NOTES 2);
* what each switchable part contributes: with and without clearance flow,
  heat transfer versus adiabatic versus isothermal, Stribeck versus
  Coulomb + viscous friction.

Figures are drawn with matplotlib's Agg canvas directly, so no global
backend is touched.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..model import Model, ModelConfig, circuits
from ..model.simulate import SimResult
from ..physics.friction import coulomb_viscous_force, stribeck_force
from ..physics.valve import flow_coefficient, spool_displacement

MPA = 1e-6  # [MPa/Pa]
_COLORS = {'a': 'tab:red', 'b': 'tab:blue', 'ref': '0.45'}
_DPI = 110
#: a temperature excursion smaller than this is not a 'jump' or 'dip' [K]
MIN_EXCURSION_K = 1.0
#: 'does not reach' supply or atmosphere = stays this far from it [Pa]; the paper's
#: transmitters resolve 0.6 kPa (0.1 % of 0.6 MPa)
PRESSURE_MARGIN_PA = 1e3
#: 'recovers' = the final deviation from room temperature is below this share of the peak one
RECOVERY_FRACTION = 0.1


# ------------------------------------------------------------------------- summaries
def check_charge_discharge(res: SimResult, config: ModelConfig, step_time_s: float
                           ) -> dict:
    """The paper's charge/discharge claims, each evaluated on the simulation.

    Parameters
    ----------
    res : SimResult
        Output of :func:`pneumatic_servo.model.circuits.charge_discharge`.
    config : ModelConfig
        The model's configuration (atmospheric pressure, room temperature).
    step_time_s : float [s]
        Time of the valve step.

    Returns
    -------
    dict
        Booleans ``p_a_rises``, ``p_a_stays_below_supply``, ``p_b_falls``,
        ``p_b_stays_above_atmosphere``, ``t_a_jumps``, ``t_a_recovers``,
        ``t_b_dips``, ``t_b_recovers``, ``all_hold``, and the values they rest
        on (SI: Pa, K).
    """
    core = config.core
    pe, te = core['atmospheric_pressure_pa'], core['room_temperature_k']
    ps = float(np.max(res.inputs['supply_pa']))
    k = int(np.searchsorted(res.t, step_time_s))
    pa, pb, ta, tb = res.p_a_pa, res.p_b_pa, res.t_a_k, res.t_b_k
    ta_peak, tb_low = float(np.max(ta[k:])), float(np.min(tb[k:]))
    out = {
        'supply_pa': ps, 'atmospheric_pa': pe, 'room_temperature_k': te,
        'p_a_at_step_pa': float(pa[k]), 'p_a_final_pa': float(pa[-1]),
        'p_a_max_pa': float(np.max(pa)),
        'p_b_at_step_pa': float(pb[k]), 'p_b_final_pa': float(pb[-1]),
        'p_b_min_pa': float(np.min(pb)),
        't_a_peak_k': ta_peak, 't_a_final_k': float(ta[-1]),
        't_b_lowest_k': tb_low, 't_b_final_k': float(tb[-1]),
    }
    out['p_a_rises'] = bool(pa[-1] > pa[k] + PRESSURE_MARGIN_PA)
    out['p_a_stays_below_supply'] = bool(np.max(pa) < ps - PRESSURE_MARGIN_PA)
    out['p_b_falls'] = bool(pb[-1] < pb[k] - PRESSURE_MARGIN_PA)
    out['p_b_stays_above_atmosphere'] = bool(np.min(pb) > pe + PRESSURE_MARGIN_PA)
    out['t_a_jumps'] = bool(ta_peak - te > MIN_EXCURSION_K and ta_peak > ta[k])
    out['t_a_recovers'] = bool(abs(ta[-1] - te) < RECOVERY_FRACTION * (ta_peak - te))
    out['t_b_dips'] = bool(te - tb_low > MIN_EXCURSION_K and tb_low < tb[k])
    out['t_b_recovers'] = bool(abs(tb[-1] - te) < RECOVERY_FRACTION * (te - tb_low))
    claims = [key for key, v in out.items() if isinstance(v, bool)]
    out['all_hold'] = all(out[key] for key in claims)
    return out


def sine_summary(res: SimResult, settle_s: float = 5.0) -> dict:
    """Ranges of angle [rad], p_a and p_b [Pa] after ``settle_s`` [s] of the sine response."""
    keep = res.t >= min(settle_s, res.t[-1] / 2)
    ang = res.angle_rad[keep]
    out = {'window_start_s': float(res.t[keep][0])}
    for name, sig in (('angle_rad', ang), ('p_a_pa', res.p_a_pa[keep]),
                      ('p_b_pa', res.p_b_pa[keep])):
        out[f'{name}_min'] = float(np.min(sig))
        out[f'{name}_max'] = float(np.max(sig))
    out['angle_peak_to_peak_deg'] = float(np.degrees(np.ptp(ang)))
    out['finite'] = bool(np.all(np.isfinite(res.states)))
    return out


# ---------------------------------------------------------------------------- drawing
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


def static_curves(model: Model, config: ModelConfig,
                  voltages_v=None) -> dict[str, dict[str, list[float]]]:
    """Closed-port p_a and M5, flow-test M4, at the paper's three verification supplies."""
    volts = np.linspace(5.0, 10.0, 26) if voltages_v is None else np.asarray(voltages_v)
    out = {}
    for gauge in circuits.PAPER_FLOW_SUPPLIES_GAUGE_PA:
        ps = circuits.gauge_supply_pa(gauge, config)
        closed = [circuits.steady_outputs(model, 'closed_port', v, ps, config) for v in volts]
        flow = [circuits.steady_outputs(model, 'flow', v, ps, config) for v in volts]
        out[f'{gauge * MPA:g} MPa'] = {
            'voltage_v': [float(v) for v in volts],
            'closed_port_p_a_pa': [c['p_a_pa'] for c in closed],
            'closed_port_m5_kg_s': [c['m5_kg_s'] for c in closed],
            'flow_m4_kg_s': [f['m4_kg_s'] for f in flow],
            'flow_m5_kg_s': [f['m5_kg_s'] for f in flow],
        }
    return out


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
def run_paper_figures(out_dir, config: ModelConfig | None = None,
                      log: Callable[[str], None] = print, sine_duration_s: float = 10.0,
                      charge_duration_s: float = 6.0) -> dict:
    """Simulate the paper's experiments, write the figures to ``out_dir`` and summarise.

    Parameters
    ----------
    out_dir : path
        Directory for the PNG files (created).
    config : ModelConfig, optional
        Base model (default: the paper's). Variants swap one slot of it.
    log : callable
        Receives one progress line per stage.
    sine_duration_s, charge_duration_s : float [s]
        Lengths of the sine and charge/discharge records.

    Returns
    -------
    dict
        JSON-serialisable: ``charge_discharge`` (claims and values),
        ``sine`` (ranges), ``variants`` (per slot and variant), ``static``
        (curves) and ``figures`` (name -> path).
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cfg = config or ModelConfig.paper()
    model = Model(cfg)
    step_s = 0.1
    figures = {}

    def cd(c):
        return circuits.charge_discharge(Model(c), step_time_s=step_s,
                                         duration_s=charge_duration_s, config=c)

    def sine(c, duration=sine_duration_s):
        return circuits.sine_response(Model(c), duration_s=duration, config=c)

    log('charge/discharge at 0.6 MPa gauge, 5 V -> 5.5 V (blocked circuit)')
    base_cd = cd(cfg)
    checks = check_charge_discharge(base_cd, cfg, step_s)
    figures['charge_discharge'] = plot_charge_discharge(base_cd, cfg, step_s,
                                                        out / 'charge_discharge.png')
    log('2 Hz sine response at 5 +/- 0.35 V (servo circuit)')
    base_sine = sine(cfg)
    figures['sine_response'] = plot_sine(base_sine, out / 'sine_response.png')

    log('switchable parts: clearance, thermal, friction')
    slots = {n: cfg.with_slot(n) for n in ('no_clearance_flow', 'adiabatic', 'isothermal',
                                           'coulomb_viscous_friction')}
    clear = {'with clearance flow (paper)': base_cd, 'no clearance flow':
             cd(slots['no_clearance_flow'])}
    figures['variant_clearance'] = plot_pressure_variants(
        clear, cfg, step_s, 'Clearance part: with vs without clearance flow, charge/discharge',
        out / 'variant_clearance.png')
    thermal = {'heat transfer (paper)': base_cd, 'adiabatic': cd(slots['adiabatic']),
               'isothermal': cd(slots['isothermal'])}
    figures['variant_thermal'] = plot_thermal_variants(thermal, cfg, step_s,
                                                       out / 'variant_thermal.png')
    fric = {'Stribeck (paper)': base_sine,
            'Coulomb + viscous': sine(slots['coulomb_viscous_friction'])}
    figures['variant_friction'] = plot_friction_variants(fric, cfg, out / 'variant_friction.png')

    log('static tests: closed port (Table 5) and flow rates (Figs 19-20)')
    curves = static_curves(model, cfg)
    figures['static_tests'] = plot_static(curves, out / 'static_tests.png')
    figures['flow_coefficient'] = plot_flow_coefficient(cfg, out / 'flow_coefficient.png')

    variants = {
        'clearance': {k: check_charge_discharge(r, cfg, step_s) for k, r in clear.items()},
        'thermal': {k: check_charge_discharge(r, cfg, step_s) for k, r in thermal.items()},
        'friction': {k: sine_summary(r) for k, r in fric.items()},
    }
    return {'charge_discharge': checks, 'sine': sine_summary(base_sine), 'variants': variants,
            'static': curves, 'figures': figures,
            'finite': bool(all(np.all(np.isfinite(r.states)) for r in
                               list(clear.values()) + list(thermal.values())
                               + list(fric.values())))}

