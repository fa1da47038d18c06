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

The figures themselves are drawn by :mod:`.paper_plots`.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np

from ..model import Model, ModelConfig, circuits
from ..model.simulate import SimResult
from .paper_plots import (
    MPA,
    plot_charge_discharge,
    plot_flow_coefficient,
    plot_friction_variants,
    plot_pressure_variants,
    plot_sine,
    plot_static,
    plot_thermal_variants,
)

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

